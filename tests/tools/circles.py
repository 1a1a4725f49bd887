#!/usr/bin/env python3
"""Circles between C files: file A calls a function defined in file B, and B (through
any chain) calls one defined in A. Prints each circle with its edges and the functions
behind them; exit 1 if there is one. Usage: circles.py DIR [DIR...] (each folder on its
own: libhalo/, examples/, validate/). Static functions, prototypes, comments and string
literals are not counted.

circles.py --folders DIR [DIR...]: the same between the folders: a file of folder A
calls a function defined in a file of folder B, and B, through any chain, calls into A."""
import glob
import re
import sys

DEFINITION = re.compile(r'^(?!static)[a-zA-Z_][\w \*]*?\b(halo_\w+)\s*\([^;{]*\)\s*\{', re.M)


def code(path):
    text = open(path, encoding='utf-8', errors='replace').read()
    text = re.sub(r'/\*.*?\*/', '', text, flags=re.S)
    text = re.sub(r'//[^\n]*', '', text)
    return re.sub(r'"(\\.|[^"\\\n])*"', '""', text)


def sources(folders):
    return sorted(f for folder in folders for f in glob.glob(folder + '/**/*.c', recursive=True)
                  if 'embedded' not in f)


def call_graph(files):
    """{calling file: {defining file: [function names]}} over the given files."""
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
    return calls


def components(nodes, calls):
    """The strongly connected components of more than one node (Tarjan)."""
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
    for f in nodes:
        if f not in index:
            visit(f)
    return found


def report(found, calls):
    for component in found:
        print('circle: ' + ', '.join(component))
        for a in component:
            for b, names in sorted(calls.get(a, {}).items()):
                if b in component:
                    print('  %s -> %s (%s)' % (a, b, ', '.join(names)))
    return len(found)


def circles(folder):
    files = sources([folder])
    calls = call_graph(files)
    for targets in calls.values():
        for b in targets:
            targets[b].sort()
    return report(components(files, calls), calls)


def folder_circles(folders):
    """Circles between the folders: the file graph over all of them, contracted."""
    files = sources(folders)
    top = {f: f.split('/')[0] for f in files}
    calls = {}
    for a, targets in call_graph(files).items():
        for b, names in targets.items():
            if top[a] != top[b]:
                calls.setdefault(top[a], {}).setdefault(top[b], []).extend(
                    '%s: %s' % (a, n) for n in names)
    for targets in calls.values():
        for b in targets:
            names = sorted(set(targets[b]))
            targets[b] = names[:4] + (['%d more' % (len(names) - 4)] if len(names) > 4 else [])
    return report(components(sorted(set(top.values())), calls), calls)


args = sys.argv[1:]
if args and args[0] == '--folders':
    total = folder_circles([a.rstrip('/') for a in args[1:]])
    print('%d circle(s) between the folders %s' % (total, ' '.join(args[1:])))
else:
    total = sum(circles(folder) for folder in args)
    print('%d circle(s) in %s' % (total, ' '.join(args)))
sys.exit(1 if total else 0)
