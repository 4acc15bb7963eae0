#!/usr/bin/env python3
"""Every float threshold in the tests names the figure it was set from: a CHECK or REQUIRE that
compares with a decimal literal (other than zero) carries a comment on its line or the line
above (what was measured, the goal it holds, or why the value is what it is), so a reader can
tell a tight bound from a loose one and see what a failure moved from.

Usage: check_thresholds.py TESTS_DIR
"""
import pathlib
import re
import sys

ASSERT = re.compile(r'\b(CHECK|REQUIRE)(_MESSAGE|_FALSE)?\(')
# A comparison with a decimal literal: < 0.05, >= 1.5f, <= 2.99e-8f.
LITERAL = re.compile(r'[<>]=?\s*-?(\d+\.\d*(e-?\d+)?f?)\b')


def nonzero(literal):
    return float(literal.rstrip('f')) != 0.0


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    unnamed = []
    for path in sorted(pathlib.Path(sys.argv[1]).rglob('*.cpp')):
        lines = path.read_text(encoding='utf-8').split('\n')
        for i, line in enumerate(lines):
            found = ASSERT.search(line)
            if not found or '//' in line:
                continue
            if not any(nonzero(m.group(1)) for m in LITERAL.finditer(line[found.end():])):
                continue
            if i > 0 and lines[i - 1].strip().startswith('//'):
                continue
            unnamed.append(f'{path}:{i + 1}: {line.strip()}')
    if unnamed:
        print('thresholds without the figure they were set from (a comment on the line or above):')
        print('\n'.join(unnamed))
        sys.exit(1)
    print('every float threshold names its figure')


if __name__ == '__main__':
    main()
