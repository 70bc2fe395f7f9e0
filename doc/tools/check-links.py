#!/usr/bin/env python3
"""Checks the relative links and anchors of README.md, CHANGELOG.md and doc/*.md (no network).

    python3 doc/tools/check-links.py [ROOT]

Every Markdown link [text](target) and image outside code blocks and inline code: a target with a
scheme (http:, https:, mailto:) is left alone; any other must name a file or folder that exists,
relative to the page, and an anchor (#name) must be a heading of the target page (GitHub's rule:
lower case, punctuation dropped, spaces to hyphens, -1, -2 for repeats) or an explicit
<a id="name">. Exit 1 listing every broken link (ctest docs-links).
"""
import glob
import os
import re
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def prose(text):
    """The page without fenced code blocks and inline code (their brackets are not links)."""
    out, fence = [], False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fence = not fence
            out.append("")
            continue
        out.append("" if fence else re.sub(r"`[^`]*`", "``", line))
    return out


def slug(heading):
    h = re.sub(r"<[^>]+>", "", heading).strip().lower()
    h = h.replace("`", "")
    h = re.sub(r"[^\w\- ]", "", h)
    return h.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen, found = {}, set()
        text = open(path, encoding="utf-8").read()
        for line in prose(text):
            m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(2))
                n = seen.get(s, 0)
                seen[s] = n + 1
                found.add(s if n == 0 else f"{s}-{n}")
        found.update(re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", text))
        cache[path] = found
    return cache[path]


def main():
    pages = [os.path.join(ROOT, "README.md"), os.path.join(ROOT, "CHANGELOG.md")]
    pages += sorted(glob.glob(os.path.join(ROOT, "doc", "**", "*.md"), recursive=True))
    broken, count = [], 0
    for page in pages:
        if not os.path.exists(page):
            continue
        for n, line in enumerate(prose(open(page, encoding="utf-8").read()), 1):
            for m in LINK.finditer(line):
                target = m.group(1)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):
                    continue
                count += 1
                path, _, anchor = target.partition("#")
                dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
                where = f"{os.path.relpath(page, ROOT)}:{n}: {target}"
                if not os.path.exists(dest):
                    broken.append(f"{where}: {os.path.relpath(dest, ROOT)} does not exist")
                elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                    broken.append(f"{where}: no heading or anchor '{anchor}' in {os.path.relpath(dest, ROOT)}")
    for b in broken:
        print(b)
    print(f"{count} relative links checked in {len(pages)} pages, {len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
