#!/usr/bin/env python3
"""Writes the generated tables of doc/findings.md from the code, or checks that they are current.

    python3 doc/tools/findings-table.py [--check]

Findings: every place in modules/selfcalib/src that raises a vpSelfCalibDataCheck::Finding (the
calls add(out, SEVERITY, "code", message), addDoubt(r, "code", message), Finding{SEVERITY, "code",
message} and push_back({SEVERITY, "code", message})): its code, severity and message, the parts
computed at run time shown as "...". Refusals of the command-line tool: the bad-input catalogue
(test/catalogue/cases.cmake, through test/catalogue/readme-table.py). Each table sits between
<!-- BEGIN generated NAME --> and <!-- END generated NAME --> in doc/findings.md; the rest of the
page is written by hand. --check exits 1 when a table differs from the code (ctest docs-findings).
"""
import difflib
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAGE = os.path.join(ROOT, "doc", "findings.md")
SRC = os.path.join(ROOT, "modules", "selfcalib", "src")
CODE = re.compile(r'"([a-z][a-z0-9]*(?:-[a-z0-9]+)+)"')
CALL = re.compile(r'\b(add|addDoubt|Finding|push_back)\s*[({]')
SEVERITY = re.compile(r'vpSelfCalibDataCheck::(WARNING|DEGENERATE|DOUBT)')


def strip_comments(text):
    """Comments out, string literals kept (a scanner that knows literals)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif c == "'":
            j = i + 1
            while j < n and text[j] != "'":
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def call_end(text, start):
    """Index after the bracket that closes the one opened at start (literals skipped)."""
    depth, i = 0, start
    while i < len(text):
        c = text[i]
        if c == '"':
            i += 1
            while text[i] != '"':
                i += 2 if text[i] == "\\" else 1
        elif c in "({[":
            depth += 1
        elif c in ")}]":
            depth -= 1
            if depth == 0:
                return i + 1
        i += 1
    return len(text)


def message(args):
    """The literal parts of an argument list, the computed parts as '...'."""
    parts, i, last_literal = [], 0, False
    pieces = re.split(r'("(?:[^"\\]|\\.)*")', args)
    for p in pieces:
        if p.startswith('"'):
            s = p[1:-1].replace('\\"', '"').replace("\\n", " ")
            parts.append(s)
            last_literal = True
        else:
            bare = re.sub(r"\s|\+|,|\(|\)|<<", "", p.replace("::", ""))
            if re.search(r"[A-Za-z0-9_]", bare):
                if not parts or parts[-1] != "...":
                    parts.append("...")
            elif ":" in bare and parts:
                parts.append(" / ")
    text = "".join(p if p != "..." else " ... " for p in parts)
    return re.sub(r"\s+", " ", text).replace("( ", "(").replace(" )", ")").strip()


def streamed(text, at, args):
    """A message built before the call: the literals streamed into the ostringstream it names
    (NAME.str()), or, when it is a parameter of a small wrapper function, the literals its callers
    pass (each caller's message, joined by ' / ')."""
    m = re.search(r"(\w+)\.str\(\)", args)
    if m:
        name = m.group(1)
        decl = text.rfind("std::ostringstream " + name, 0, at)
        if decl >= 0:
            body = text[decl:at]
            pieces = []
            for sm in re.finditer(r"\b" + name + r"\s*<<", body):
                i = sm.end()
                while i < len(body) and body[i] != ";":
                    if body[i] == '"':
                        i += 1
                        while body[i] != '"':
                            i += 2 if body[i] == "\\" else 1
                    i += 1
                pieces.append(body[sm.end():i])
            return message(" + ".join(pieces))
    m = re.fullmatch(r"\s*,?\s*(\w+)\s*", args)
    if not m:
        return "..."
    param = m.group(1)
    fn = None
    for d in re.finditer(r"\n[\w:<>&* ]+?\b(\w+)\(([^)]*)\)\s*\{", text[:at]):
        fn = d if re.search(r"\b" + param + r"\b", d.group(2)) else fn
    if not fn:
        return "..."
    out = []
    for c in re.finditer(r"\b" + fn.group(1) + r"\s*\(", text[fn.end():]):
        start = fn.end() + c.end() - 1
        call = text[start + 1:call_end(text, start) - 1]
        first = re.search(r'"', call)
        if first:
            msg = message(call[first.start():])
            if msg and msg not in out:
                out.append(msg)
    return " / ".join(out) or "..."


def findings():
    rows = {}
    for path in sorted(glob.glob(os.path.join(SRC, "**", "*.cpp"), recursive=True)):
        text = strip_comments(open(path, encoding="utf-8").read())
        for m in CALL.finditer(text):
            open_at = m.end() - 1
            end = call_end(text, open_at)
            inner = text[open_at + 1:end - 1]
            if m.group(1) == "push_back" and not inner.lstrip().startswith("{"):
                continue
            if m.group(1) == "push_back":
                inner = inner.strip()[1:-1]
            code = CODE.search(inner)
            sev = SEVERITY.findall(inner[:code.start()]) if code else []
            if not code:
                continue
            if m.group(1) == "addDoubt":
                sev = ["DOUBT"]
            if not sev:
                continue
            head = inner[:code.start()]
            if not re.fullmatch(r"[\s\w.&*:?,()!<>=]*", head):
                continue
            rel = os.path.relpath(path, os.path.join(ROOT, "modules", "selfcalib"))
            sev_text = " or ".join(s.lower() for s in dict.fromkeys(sev))
            msg = message(inner[code.end():])
            if msg in ("", "..."):
                msg = streamed(text, open_at, inner[code.end():])
            key = code.group(1)
            if key in rows:
                prev = rows[key]
                prev[1] = " or ".join(dict.fromkeys(prev[1].split(" or ") + sev_text.split(" or ")))
                if msg not in prev[2]:
                    prev[2] += " / " + msg
                if rel not in prev[3]:
                    prev[3] += ", " + rel
            else:
                rows[key] = [key, sev_text, msg, rel]
    order = {"degenerate": 0, "doubt": 1, "warning": 2}
    out = ["| code | severity | what it says (the computed parts as ...) | raised in |", "|---|---|---|---|"]
    for key, sev, msg, rel in sorted(rows.values(), key=lambda r: (order.get(r[1].split(" or ")[0], 3), r[0])):
        msg = msg.replace("|", "\\|")
        out.append(f"| <a id=\"{key}\"></a>`{key}` | {sev} | {msg} | `{rel}` |")
    out.append("")
    out.append(f"{len(rows)} findings.")
    return "\n".join(out)


def catalogue():
    res = subprocess.run([sys.executable, os.path.join(ROOT, "test", "catalogue", "readme-table.py")],
                         capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit("test/catalogue/readme-table.py: " + res.stderr)
    return res.stdout.rstrip() + "\n\n" + res.stderr.strip()


def render(page, name, body):
    begin, end = f"<!-- BEGIN generated {name} -->", f"<!-- END generated {name} -->"
    if begin not in page or end not in page:
        sys.exit(f"doc/findings.md has no {begin} ... {end} block")
    a, rest = page.split(begin, 1)
    _, b = rest.split(end, 1)
    return a + begin + "\n" + body.rstrip() + "\n" + end + b


def main():
    check = "--check" in sys.argv[1:]
    old = open(PAGE, encoding="utf-8").read()
    new = render(render(old, "findings", findings()), "catalogue", catalogue())
    if check:
        if new != old:
            sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                                       "doc/findings.md (committed)", "from the code"))
            print("doc/findings.md is not what the code raises: run python3 doc/tools/findings-table.py and commit")
            return 1
        print("doc/findings.md matches the code's findings and the catalogue")
        return 0
    open(PAGE, "w", encoding="utf-8").write(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
