#!/usr/bin/env python3
"""Function and file sizes of a Rust source tree: every `fn` longer than a limit, every file
longer than a limit (lines, test modules included; comments and blank lines count).

    tools/sizes.py src [--fn 150] [--file 700]

A function runs from its `fn` line to the line of the brace that closes its body (braces in
strings, chars and comments are skipped). Exits 0; prints the tables, longest first."""
import os, re, sys

def strip(line, state):
    """The line without strings, char literals and comments; state carries a block comment."""
    out, i, n = [], 0, len(line)
    while i < n:
        if state['block']:
            j = line.find('*/', i)
            if j < 0:
                return ''.join(out)
            state['block'] = False
            i = j + 2
            continue
        c = line[i]
        if line.startswith('//', i):
            break
        if line.startswith('/*', i):
            state['block'] = True
            i += 2
            continue
        if c == '"' or (c == 'r' and re.match(r'r#*"', line[i:]) and (i == 0 or not (line[i-1].isalnum() or line[i-1] == '_'))):
            if c == 'r':
                m = re.match(r'r(#*)"', line[i:])
                end = '"' + m.group(1)
                j = line.find(end, i + len(m.group(0)))
                if j < 0:
                    state['raw'] = end
                    return ''.join(out)
                i = j + len(end)
                continue
            j = i + 1
            while j < n and line[j] != '"':
                j += 2 if line[j] == '\\' else 1
            if j >= n:
                state['str'] = True
                return ''.join(out)
            i = j + 1
            continue
        if c == "'":
            m = re.match(r"'(\\.[^']*|[^\\'])'", line[i:])
            if m:
                i += len(m.group(0))
                continue
        out.append(c)
        i += 1
    return ''.join(out)

def scan(path):
    fns, stack, depth = [], [], 0
    state = {'block': False, 'str': False, 'raw': None}
    pending = None
    lines = open(path, encoding='utf-8').read().split('\n')
    for no, raw in enumerate(lines, 1):
        line = raw
        if state['raw']:
            j = line.find(state['raw'])
            if j < 0:
                continue
            line = line[j + len(state['raw']):]
            state['raw'] = None
        if state['str']:
            j = 0
            while j < len(line) and line[j] != '"':
                j += 2 if line[j] == '\\' else 1
            if j >= len(line):
                continue
            line = line[j + 1:]
            state['str'] = False
        code = strip(line, state)
        m = re.search(r'\bfn\s+([A-Za-z_][A-Za-z0-9_]*)', code)
        if m and pending is None:
            pending = (m.group(1), no)
        for c in code:
            if c == '{':
                depth += 1
                if pending is not None:
                    stack.append((pending[0], pending[1], depth))
                    pending = None
            elif c == '}':
                if stack and stack[-1][2] == depth:
                    name, start, _ = stack.pop()
                    fns.append((no - start + 1, name, start))
                depth -= 1
            elif c == ';' and pending is not None and not stack or (c == ';' and pending is not None and stack and depth == stack[-1][2]):
                pending = None
    return fns, len(lines) - (1 if lines and lines[-1] == '' else 0)

def main():
    args = [a for a in sys.argv[1:] if not a.startswith('--')]
    opt = dict(zip(sys.argv[1::2], sys.argv[2::2]))
    fn_limit, file_limit = int(opt.get('--fn', 150)), int(opt.get('--file', 700))
    fns, files = [], []
    for root in args or ['src']:
        for d, _, fs in os.walk(root):
            for f in sorted(fs):
                if f.endswith('.rs'):
                    p = os.path.join(d, f)
                    fl, n = scan(p)
                    fns += [(l, name, p, s) for l, name, s in fl]
                    files.append((n, p))
    long_fns = sorted([x for x in fns if x[0] > fn_limit], reverse=True)
    long_files = sorted([x for x in files if x[0] > file_limit], reverse=True)
    print(f"{len(files)} files, {len(fns)} functions; {len(long_fns)} functions over {fn_limit} lines, {len(long_files)} files over {file_limit} lines")
    for l, name, p, s in long_fns:
        print(f"  fn {l:5d}  {name}  {p}:{s}")
    for n, p in long_files:
        print(f"  file {n:5d}  {p}")

main()
