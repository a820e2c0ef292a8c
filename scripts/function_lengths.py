#!/usr/bin/env python3
"""Lists functions longer than a limit (default 80 lines) and source files longer than 800 lines.

A rough scanner for the house rules (README "House style"): a function starts at a line that opens a
brace after a parenthesised parameter list at brace depth 0 or 1 (namespace or class level) and ends at
its matching brace. Usage: scripts/function_lengths.py [--limit N] [--file-limit N] [paths...]
"""
import argparse, pathlib, re, subprocess, sys

HEAD = re.compile(r'^\s*(?:template\s*<.*>\s*)?[\w:<>,*&~\s\[\]]*?\b([~\w:]+)\s*\((?:[^;{}]|\n)*\)\s*(?:const\s*)?(?:noexcept\s*)?(?:override\s*)?(?:->\s*[\w:<>,\s*&]+)?\s*(?::[^;{]*)?\{\s*$')
CONTROL = {'if', 'for', 'while', 'switch', 'catch', 'return', 'else', 'do', 'sizeof'}

def scan(path):
    lines = path.read_text(errors='replace').split('\n')
    depth, out, i = 0, [], 0
    stack = []  # (name, start line, depth before)
    head = ''
    for n, line in enumerate(lines, 1):
        code = re.sub(r'//.*', '', line)
        code = re.sub(r'"(?:\\.|[^"\\])*"', '""', code)
        code = re.sub(r"'(?:\\.|[^'\\])*'", "''", code)
        head = (head + ' ' + code.strip())[-400:] if code.strip() else head
        opens, closes = code.count('{'), code.count('}')
        if opens > closes and depth <= 2 and not stack:
            m = HEAD.match(head.strip()) or HEAD.match(code)
            if m and m.group(1).split('::')[-1] not in CONTROL and '=' not in code.split('(')[0]:
                stack.append((m.group(1), n, depth))
        depth += opens - closes
        if stack and depth <= stack[-1][2]:
            name, start, _ = stack.pop()
            out.append((n - start + 1, name, start))
        if code.strip().endswith((';', '{', '}')):
            head = ''
    return len(lines), out

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--limit', type=int, default=80)
    ap.add_argument('--file-limit', type=int, default=800)
    ap.add_argument('paths', nargs='*')
    a = ap.parse_args()
    files = a.paths or subprocess.check_output(['git', 'ls-files', '*.cpp', '*.hpp']).decode().split()
    bad = 0
    for f in files:
        if f.startswith(('tests/', 'bench/', 'fuzz/')) and not a.paths:
            continue
        count, funcs = scan(pathlib.Path(f))
        if count > a.file_limit:
            print(f'{f}: {count} lines (file)'); bad += 1
        for length, name, start in funcs:
            if length > a.limit:
                print(f'{f}:{start}: {name} {length} lines'); bad += 1
    return 1 if bad else 0

sys.exit(main())
