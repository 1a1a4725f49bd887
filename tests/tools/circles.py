#!/usr/bin/env python3
"""Circles between C files: file A calls a function defined in file B, and B (through
any chain) calls one defined in A. Prints each circle with its edges and the functions
behind them; exit 1 if there is one. Usage: circles.py DIR [DIR...] (each folder on its
own: libhalo/, examples/, validate/). Static functions, prototypes, comments and string
literals are not counted."""
import glob
import re
import sys

DEFINITION = re.compile(r'^(?!static)[a-zA-Z_][\w \*]*?\b(halo_\w+)\s*\([^;{]*\)\s*\{', re.M)


def code(path):
    text = open(path, encoding='utf-8', errors='replace').read()
    text = re.sub(r'/\*.*?\*/', '', text, flags=re.S)
    text = re.sub(r'//[^\n]*', '', text)
    return re.sub(r'"(\\.|[^"\\\n])*"', '""', text)


def circles(folder):
    files = sorted(f for f in glob.glob(folder + '/**/*.c', recursive=True) if 'embedded' not in f)
    defined = {}
    for f in files:
        for m in DEFINITION.finditer(open(f, encoding='utf-8', errors='replace').read()):
            defined.setdefault(m.group(1), f)
    calls = {}
    for f in files:
        body = code(f)
        for name, where in defined.items():
            if where != f and re.search(r'\b' + name + r'\s*\(', body):
                calls.setdefault(f, {}).setdefault(where, []).append(name)
    # strongly connected components (Tarjan)
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in calls.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    sys.setrecursionlimit(10000)
    for f in files:
        if f not in index:
            visit(f)
    for component in found:
        print('circle: ' + ', '.join(component))
        for a in component:
            for b, names in sorted(calls.get(a, {}).items()):
                if b in component:
                    print('  %s -> %s (%s)' % (a, b, ', '.join(sorted(names))))
    return len(found)


total = sum(circles(folder) for folder in sys.argv[1:])
print('%d circle(s) in %s' % (total, ' '.join(sys.argv[1:])))
sys.exit(1 if total else 0)
