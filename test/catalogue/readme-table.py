#!/usr/bin/env python3
"""Prints the README's bad-input catalogue table from test/catalogue/cases.cmake:
case, what the tool says (the regular expression its output must match), exit code, test."""
import os
import re
import sys

path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cases.cmake")
pattern = re.compile(r'^catalogue_case\((\S+) (\d) "((?:[^"\\]|\\.)*)" "((?:[^"\\]|\\.)*)" \[=\[(.*)\]=\]\)$')
rows = []
for line in open(path, encoding="utf-8"):
    line = line.rstrip("\n")
    if not line.startswith("catalogue_case("):
        continue
    m = pattern.match(line)
    if not m:
        sys.exit("cannot read: " + line)
    name, code, regex, case, _ = m.groups()
    says = regex.replace("\\\\", "\\").replace("|", "\\|")
    rows.append(f"| {case} | `{says}` | {code} | `cat-{name}` |")
print("| case | what the tool says (a regular expression on its output) | exit | test |")
print("|---|---|---|---|")
print("\n".join(rows))
print(f"\n{len(rows)} cases.", file=sys.stderr)
