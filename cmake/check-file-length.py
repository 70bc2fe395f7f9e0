#!/usr/bin/env python3
"""Checks that no source file of the command-line tool is longer than 300 lines (doc/architecture.md:
one file per command, the shared options apart, so that a command reads in one sitting): every .cpp,
.h and .hpp under DIR, counted as `wc -l` does (a last line without its newline counted too).

    cmake/check-file-length.py [DIR] [--limit N]

DIR defaults to apps/ beside this script's folder. Prints every file over the limit with its length;
the exit status is 1 when one is, 2 when DIR is not a folder.
"""
import os
import sys


def length(path):
    """The number of lines of the file at `path`."""
    with open(path, 'rb') as f:
        data = f.read()
    return data.count(b'\n') + (1 if data and not data.endswith(b'\n') else 0)


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    folder = os.path.join(here, '..', 'apps')
    limit = 300
    args = list(argv[1:])
    while args:
        a = args.pop(0)
        if a == '--limit':
            if not args or not args[0].isdigit():
                print('--limit: expected a number of lines')
                return 2
            limit = int(args.pop(0))
        else:
            folder = a
    if not os.path.isdir(folder):
        print(f'{folder}: not a folder (expected the apps/ folder of the repository)')
        return 2
    long_ones, count = [], 0
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        for fn in sorted(files):
            if not fn.endswith(('.cpp', '.h', '.hpp')):
                continue
            count += 1
            path = os.path.join(root, fn)
            n = length(path)
            if n > limit:
                long_ones.append((os.path.relpath(path, os.path.join(folder, '..')), n))
    for rel, n in long_ones:
        print(f'{rel}: {n} lines, more than {limit}')
    if long_ones:
        print(f'{len(long_ones)} file(s) of {count} longer than {limit} lines: split them (one file per command, '
              'shared code in its own file)')
        return 1
    print(f'no file of {count} is longer than {limit} lines')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
