#!/usr/bin/env python3
"""Checks that no function of the selfcalib module is longer than 120 lines (doc/architecture.md): the lines of its body, from the line of the opening brace to the line of the
closing one, both counted. Lambdas inside a function are part of it; namespaces, classes, structs,
unions, enums and initializer lists are not functions (a member function defined inside a class is).

    cmake/check-functions.py [MODULE_DIR] [--allow FILE] [--limit N]

MODULE_DIR defaults to modules/selfcalib beside this script; its src/ and include/ are read
(.h, .hpp, .cpp). FILE (optional: long-functions.txt beside this script when it exists) lists
functions known to be longer while they are being split, one a line, `PATH NAME LENGTH` (PATH relative to MODULE_DIR, NAME as printed by this
script); such a function passes while it is no longer than its LENGTH. Prints every function over
the limit; the exit status is 1 when one is neither allowed nor within its allowed length, 2 on a
malformed allow list.
"""
import os
import re
import sys

SCOPE_WORDS = re.compile(r'\b(namespace|class|struct|union|enum)\b')
QUALIFIERS = re.compile(r'^(\s|const\b|volatile\b|noexcept\b(\s*\([^()]*\))?|override\b|final\b|mutable\b|&&?'
                        r'|->\s*[\w:<>,\s*&]+)*$')


def strip(text):
    """The text with comments, string and character literals blanked (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i))
            i = j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = ')' + m.group(1) + '"'
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + re.sub(r'[^\n]', ' ', text[i + 2:j]))
            i = j
        elif c in '"\'':
            # a digit separator (1'000'000) is not a character literal
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(' ')
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            j = min(j + 1, n)
            out.append(c + ' ' * (j - i - 2) + c if j - i >= 2 else c)
            i = j
        elif c == '#' and (i == 0 or text[i - 1] == '\n' or text[:i].rstrip(' \t').endswith('\n')):
            # a preprocessor line (with its continuations)
            j = i
            while True:
                k = text.find('\n', j)
                if k < 0:
                    k = n
                    break
                if text[k - 1] != '\\':
                    break
                j = k + 1
            out.append(re.sub(r'[^\n]', ' ', text[i:k]))
            i = k
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def top_level_parens(head):
    """(balanced, index of the '(' matching the last top-level ')', or -1)."""
    depth, last_close, open_of = 0, -1, {}
    stack = []
    for k, c in enumerate(head):
        if c == '(':
            stack.append(k)
        elif c == ')':
            if not stack:
                return False, -1
            o = stack.pop()
            if not stack:
                open_of[k] = o
                last_close = k
    if stack:
        return False, -1
    return True, open_of.get(last_close, -1), last_close


def signature_name(h):
    """The function's name in a head that ends with its parameter list and qualifiers, or None."""
    res = top_level_parens(h)
    if not res[0] or res[1] < 0:
        return None
    _, open_paren, close_paren = res
    if not QUALIFIERS.match(h[close_paren + 1:]):
        return None
    before = h[:open_paren].rstrip()
    m = re.search(r'(operator\s*(\(\)|[^\s(]+)|[~\w:<>]+)\s*$', before)
    name = re.sub(r'\s+', '', m.group(1)) if m else ''
    return name if re.search(r'\w', name) else 'lambda'


def init_colon(h):
    """The index of a constructor's initializer-list colon (the first top-level ':' after a ')',
    not '::'), or -1."""
    depth, seen_paren = 0, False
    for k, c in enumerate(h):
        if c in '([{':
            depth += 1
        elif c in ')]}':
            depth -= 1
            if depth == 0 and c == ')':
                seen_paren = True
        elif c == ':' and depth == 0 and seen_paren:
            if h[k + 1:k + 2] == ':' or h[k - 1:k] == ':':
                continue
            return k
    return -1


def classify(head):
    """('function', name), ('scope', None), ('init', None) (a member's brace initializer in a
    constructor's list) or ('other', None) (a variable's braced initializer) for the text before a
    brace at class or namespace level."""
    h = head.strip()
    res = top_level_parens(h)
    if not res[0]:
        return 'other', None
    colon = init_colon(h)
    if colon >= 0:
        name = signature_name(h[:colon])
        if name:
            # `) : a(x), b{y}`: the brace after `b` initializes a member, the one after `)` or `}`
            # opens the body
            return ('init', None) if re.search(r'[\w>]\s*$', h[colon + 1:]) else ('function', name)
    if res[1] < 0:
        if SCOPE_WORDS.search(h) or h.startswith('extern') or h == '':
            return 'scope', None
        return 'other', None
    name = signature_name(h)
    if name:
        return 'function', name
    if SCOPE_WORDS.search(h[:res[1]]) and '=' not in h[:res[1]]:
        return 'scope', None
    return 'other', None


def functions(path):
    """(name, first line, length) of each function defined in the file."""
    with open(path, encoding='utf-8', errors='replace') as f:
        text = strip(f.read())
    found = []
    # stack of (kind, line of the brace); kind 'scope' or 'function' or 'other' or 'init'
    stack = []
    head_start = 0
    i, n = 0, len(text)
    line = 1
    in_function = 0
    while i < n:
        c = text[i]
        if c == '\n':
            line += 1
        elif c == '{':
            if in_function:
                stack.append(('inner', line, None))
            else:
                kind, name = classify(text[head_start:i])
                stack.append((kind, line, name))
                if kind == 'function':
                    in_function = 1
                elif kind == 'other':
                    in_function = 0
            if stack[-1][0] in ('scope',):
                head_start = i + 1
        elif c == '}':
            if stack:
                kind, first, name = stack.pop()
                if kind == 'function':
                    found.append((name, first, line - first + 1))
                    in_function = 0
                    head_start = i + 1
                elif kind == 'scope':
                    head_start = i + 1
                elif kind in ('other',) and not in_function:
                    pass  # a braced initializer: its statement ends at the ';'
                # 'init' and 'inner': the head goes on
        elif c == ';' and not in_function and (not stack or stack[-1][0] == 'scope'):
            head_start = i + 1
        elif c == ':' and not in_function and re.search(r'\b(public|private|protected)\s*$', text[head_start:i]):
            head_start = i + 1
        i += 1
    return found


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    module = os.path.join(here, '..', 'modules', 'selfcalib')
    allow_file = os.path.join(here, 'long-functions.txt')
    limit = 120
    args = list(argv[1:])
    while args:
        a = args.pop(0)
        if a == '--allow':
            allow_file = args.pop(0)
        elif a == '--limit':
            limit = int(args.pop(0))
        else:
            module = a
    allowed = {}
    if os.path.exists(allow_file):
        with open(allow_file, encoding='utf-8') as f:
            for k, raw in enumerate(f, 1):
                s = raw.split('#', 1)[0].strip()
                if not s:
                    continue
                parts = s.split()
                if len(parts) != 3 or not parts[2].isdigit():
                    print(f'{allow_file}:{k}: expected PATH NAME LENGTH, got: {raw.rstrip()}')
                    return 2
                allowed.setdefault((parts[0], parts[1]), []).append(int(parts[2]))
    long_ones, bad = [], []
    for sub in ('src', 'include'):
        for root, dirs, files in os.walk(os.path.join(module, sub)):
            dirs.sort()
            for fn in sorted(files):
                if not fn.endswith(('.h', '.hpp', '.cpp')):
                    continue
                path = os.path.join(root, fn)
                rel = os.path.relpath(path, module)
                for name, first, length in functions(path):
                    if length > limit:
                        ok = any(length <= a for a in allowed.get((rel, name), []))
                        long_ones.append((rel, name, first, length, ok))
                        if not ok:
                            bad.append((rel, name, first, length))
    for rel, name, first, length, ok in long_ones:
        print(f'{rel}:{first}: {name}: {length} lines' + (' (allowed by the list)' if ok else ''))
    present = {(r, nm) for r, nm, _, _, _ in long_ones}
    for key in sorted(allowed):
        if key not in present:
            print(f'{key[0]} {key[1]}: listed, no longer over {limit} lines: remove it from {allow_file}')
    if bad:
        print(f'{len(bad)} function(s) longer than {limit} lines and not in {allow_file} (or longer than '
              'listed): split them')
        return 1
    if long_ones:
        print(f'no function is longer than {limit} lines, except {len(long_ones)} listed in {allow_file}')
    else:
        print(f'no function is longer than {limit} lines')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
