#!/usr/bin/env python3
"""Runs the command blocks a Markdown page marks runnable, as a user would type them.

    python3 doc/tools/run-doc-blocks.py --build BUILD --source SRC --data DATA [--slow] PAGE

A block is runnable when the line before its ```sh fence (blank lines aside) is
<!-- runnable: TAGS -->, TAGS among `sim` (the simulated robot: always run), `real-data` (reads
../shared/data: run when DATA exists, else left out with a message) and `slow` (run only with
--slow). With --slow, the slow blocks run with the blocks before the last of them (they prepare its
files); the blocks after it are left out, the run without --slow runs them. The blocks of a page
run in order, in one fresh directory laid out like a checkout:
build/ is BUILD, modules/, tutorial/, test/ and doc/ are SRC's, and ../shared/data is DATA, so the
commands run verbatim. Each block runs under bash -e -o pipefail. Exit 0 when every block ran and
succeeded, 1 at the first failure (the page, the line, the output), 77 when no block could run
(ctest SKIP_RETURN_CODE).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

MARK = re.compile(r"^<!--\s*runnable:\s*([\w\s-]+?)\s*-->\s*$")
KNOWN = {"sim", "real-data", "slow"}


def blocks(path):
    lines = open(path, encoding="utf-8").read().splitlines()
    out, i = [], 0
    while i < len(lines):
        m = MARK.match(lines[i].strip())
        if m:
            tags = set(m.group(1).split())
            if not tags <= KNOWN or not tags & {"sim", "real-data"}:
                sys.exit(f"{path}:{i + 1}: runnable tags must be sim or real-data, optionally slow: {m.group(1)}")
            j = i + 1
            while j < len(lines) and not lines[j].strip():
                j += 1
            if j >= len(lines) or lines[j].strip() != "```sh":
                sys.exit(f"{path}:{i + 1}: a runnable mark must be followed by a ```sh block")
            k = j + 1
            while k < len(lines) and lines[k].strip() != "```":
                k += 1
            out.append((j + 2, tags, "\n".join(lines[j + 1:k])))
            i = k
        i += 1
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--slow", action="store_true")
    ap.add_argument("--keep", action="store_true", help="keep the working directory")
    ap.add_argument("page")
    a = ap.parse_args()
    todo = blocks(a.page)
    if not todo:
        sys.exit(f"{a.page}: no runnable block")
    have_data = os.path.isdir(a.data)
    top = tempfile.mkdtemp(prefix="selfcalib-doc-")
    work = os.path.join(top, "checkout")
    os.makedirs(os.path.join(top, "shared"))
    os.makedirs(work)
    os.symlink(os.path.abspath(a.build), os.path.join(work, "build"))
    for d in ("modules", "tutorial", "test", "doc", "apps", "cmake"):
        os.symlink(os.path.join(os.path.abspath(a.source), d), os.path.join(work, d))
    if have_data:
        os.symlink(os.path.abspath(a.data), os.path.join(top, "shared", "data"))
    slow_at = [i for i, (_, tags, _) in enumerate(todo) if "slow" in tags]
    last_slow = slow_at[-1] if slow_at else -1
    ran = 0
    try:
        for i, (line, tags, text) in enumerate(todo):
            where = f"{os.path.relpath(a.page, a.source)}:{line}"
            if "slow" in tags and not a.slow:
                print(f"-- {where}: slow, not run (ctest -L slow runs it)")
                continue
            if a.slow and i > last_slow:
                print(f"-- {where}: after the last slow block, not run with --slow (the run without it runs it)")
                continue
            if "real-data" in tags and not have_data:
                print(f"-- {where}: needs {a.data} (../shared/data), which is absent: not run")
                continue
            print(f"-- {where} [{' '.join(sorted(tags))}]\n{text}", flush=True)
            res = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", text], cwd=work,
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            print(res.stdout, end="", flush=True)
            if res.returncode != 0:
                print(f"FAILED: the block at {where} exited with {res.returncode}")
                return 1
            ran += 1
    finally:
        if a.keep:
            print(f"working directory kept: {work}")
        else:
            shutil.rmtree(top, ignore_errors=True)
    if ran == 0:
        print(f"SKIPPED: no block of {a.page} could run here (see above)")
        return 77
    print(f"{ran} block(s) of {os.path.relpath(a.page, a.source)} ran and succeeded")
    return 0


if __name__ == "__main__":
    sys.exit(main())
