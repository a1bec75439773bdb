#!/usr/bin/env python3
"""The shape of the house, measured: layers, circles, long files and long functions.

    python3 tools/house.py            # the table (upward imports, circles, sizes)
    python3 tools/house.py --check    # exit 1 on an upward import or a circle in src/
    python3 tools/house.py --edges    # every module-level arrow, for a drawing

An *arrow* is a reference from one file of the core crate (src/, the CLI under src/bin/
included) to another: a `use crate::…`/`use super::…` item or an inline `crate::a::b` path,
outside comments and outside a trailing `#[cfg(test)]` module. Its target is the file of the
deepest module the path names. The layers are ARCHITECTURE.md's, bottom first (LAYERS below);
an arrow from a lower layer to a higher one is *upward*. A *circle* is a set of two or more
files that reach each other, not counting the arrows from a file to the `mod.rs` of a module
that contains it (a module's own facade, which its parts may read).
"""

import argparse
import os
import re
import sys
from collections import defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# ARCHITECTURE.md's layers, bottom first; a module reads only its own layer and those below.
LAYERS = [
    ["fmtnum", "rng", "grammar", "stats"],
    ["units", "theory"],
    ["forces", "init"],
    ["engine"],
    ["io", "analysis", "report", "plot"],
    ["input"],
    ["host", "lib"],
    ["bin"],
]
LAYER = {m: i for i, ms in enumerate(LAYERS) for m in ms}

FILE_LIMIT = 800
FN_LIMIT = 150


def rust_files(top):
    out = []
    for d, _, fs in os.walk(os.path.join(ROOT, top)):
        out += [os.path.join(d, f) for f in fs if f.endswith(".rs")]
    return sorted(out)


def module_of(path):
    """The module path (list of names) of a file under src/; src/bin/X/… → ['bin', X, …]."""
    rel = os.path.relpath(path, os.path.join(ROOT, "src")).replace(os.sep, "/")
    parts = rel[:-3].split("/")
    if parts[-1] in ("mod", "main") or rel == "lib.rs":
        parts = parts[:-1]
    return parts or ["lib"]


def code_lines(text):
    """The lines outside comments, and outside a trailing `#[cfg(test)]` module."""
    lines = text.split("\n")
    for i, ln in enumerate(lines):
        if ln.strip() == "#[cfg(test)]" and i + 1 < len(lines) and re.match(
            r"\s*(pub(\(\w+\))? )?mod \w+ \{", lines[i + 1]
        ):
            lines = lines[:i]
            break
    out = []
    for ln in lines:
        s = ln.split("//")[0] if "//" in ln and '"' not in ln.split("//")[0] else ln
        if ln.lstrip().startswith("//"):
            s = ""
        out.append(s)
    return out


PATH_RE = re.compile(r"\b(crate|super)((?:::(?:super|[A-Za-z_]\w*))+)(::\{([^}]*)\})?")


def references(path, mod, files_by_mod):
    """The files this file's code names."""
    with open(path, encoding="utf-8") as f:
        text = "\n".join(code_lines(f.read()))
    # A `use` with a group: join it onto one line so that the regex sees it.
    text = re.sub(r"\{\s*\n", "{", text)
    text = re.sub(r",\s*\n\s*", ", ", text)
    targets = set()
    for m in PATH_RE.finditer(text):
        head, rest, _, group = m.groups()
        names = [p for p in rest.split("::") if p]
        if head == "crate":
            cur = ["bin", mod[1]] if mod[0] == "bin" else []
        else:
            cur = list(mod[:-1])
        for p in names:
            if p == "super":
                cur = cur[:-1]
            else:
                cur.append(p)
        cands = [cur]
        if group:
            for g in group.split(","):
                g = g.strip().split("::")[0].split(" ")[0]
                if g and g not in ("self", "*"):
                    cands.append(cur + [g])
        for c in cands:
            # The deepest prefix of c that is a file's module.
            for k in range(len(c), 0, -1):
                t = files_by_mod.get(tuple(c[:k]))
                if t:
                    if t != path:
                        targets.add(t)
                    break
    return targets


def graph():
    files = rust_files("src")
    by_mod = {tuple(module_of(p)): p for p in files}
    if ("lib",) not in by_mod:
        by_mod[("lib",)] = os.path.join(ROOT, "src", "lib.rs")
    edges = {p: references(p, module_of(p), by_mod) for p in files}
    return files, edges


def top(path):
    return module_of(path)[0]


def rel(p):
    return os.path.relpath(p, ROOT)


def is_facade_of(a, b):
    """True when b is the mod.rs/lib.rs of a module that contains file a."""
    mb = module_of(b)
    if not b.endswith(("mod.rs", "lib.rs")):
        return False
    ma = module_of(a)
    return mb == ["lib"] or (len(mb) <= len(ma) and ma[: len(mb)] == mb and a != b)


def circles(files, edges):
    g = {a: {b for b in edges[a] if not is_facade_of(a, b)} for a in files}
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in files:
        if v not in index:
            visit(v)
    return out


def upward(files, edges):
    out = []
    for a in files:
        for b in sorted(edges[a]):
            la, lb = LAYER.get(top(a)), LAYER.get(top(b))
            if la is None or lb is None:
                continue
            if lb > la:
                out.append((a, b))
    return out


def long_functions(paths, limit):
    out = []
    fn_re = re.compile(r"^(\s*)(pub(\([\w:]+\))? )?(const )?(async )?(unsafe )?(extern \"C\" )?fn (\w+)")
    for p in paths:
        with open(p, encoding="utf-8") as f:
            lines = f.read().split("\n")
        for i, ln in enumerate(lines):
            m = fn_re.match(ln)
            if not m or ln.rstrip().endswith(";"):
                continue
            indent = m.group(1)
            for j in range(i + 1, len(lines)):
                if lines[j] == indent + "}":
                    if j - i + 1 > limit:
                        out.append((p, m.group(8), j - i + 1))
                    break
    return out


def long_files(limit):
    out = []
    for top_dir in ("src", "capi/src", "python/src", "python/python", "tests", "lammps-plugin", "validation", "tools", "scripts"):
        for d, _, fs in os.walk(os.path.join(ROOT, top_dir)):
            if "/target" in d or "__pycache__" in d:
                continue
            for f in fs:
                if f.endswith((".rs", ".py", ".cpp", ".h")):
                    p = os.path.join(d, f)
                    with open(p, encoding="utf-8", errors="replace") as fh:
                        n = sum(1 for _ in fh)
                    if n > limit:
                        out.append((p, n))
    return sorted(out, key=lambda x: -x[1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 on an upward arrow or a circle")
    ap.add_argument("--edges", action="store_true", help="print the module-level arrows")
    a = ap.parse_args()
    files, edges = graph()
    if a.edges:
        mods = defaultdict(set)
        for x in files:
            for y in edges[x]:
                if top(x) != top(y):
                    mods[top(x)].add(top(y))
        for x in sorted(mods):
            print(f"{x} -> {', '.join(sorted(mods[x]))}")
        return 0
    up = upward(files, edges)
    circ = circles(files, edges)
    rust = rust_files("src") + rust_files("capi/src") + rust_files("python/src") + rust_files("tests")
    lfn = long_functions(rust, FN_LIMIT)
    lfile = long_files(FILE_LIMIT)
    print(f"upward arrows: {len(up)}")
    for x, y in up:
        print(f"  {rel(x)} ({top(x)}) -> {rel(y)} ({top(y)})")
    print(f"circles: {len(circ)}")
    for c in circ:
        print("  " + " <-> ".join(rel(x) for x in c))
    print(f"files over {FILE_LIMIT} lines: {len(lfile)}")
    for p, n in lfile:
        print(f"  {rel(p)}: {n}")
    print(f"functions over {FN_LIMIT} lines: {len(lfn)}")
    for p, name, n in sorted(lfn, key=lambda x: -x[2]):
        print(f"  {rel(p)}: {name} {n}")
    if a.check and (up or circ):
        print("FAIL: an import points up the layers, or files form a circle (ARCHITECTURE.md)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
