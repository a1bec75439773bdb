#!/usr/bin/env python3
"""Copy the Python reference's docstrings from the stub into the Rust sources of the extension.

The functions and the class that Rust implements (python/src/) are documented in the stub
python/python/dpdnl/_dpdnl.pyi, which scripts/pyref.py renders into the manual. Python's
``help()`` shows the extension's own ``__doc__``, which PyO3 takes from the ``///`` comments
(and, for the exceptions, from the text of ``create_exception!``). This script writes the
stub's docstring into each of those places, so that the two are the same text;
python/tests/test_docs.py fails when they differ.

Usage:
    python3 scripts/pydoc-rust.py            # rewrites the doc comments under python/src
    python3 scripts/pydoc-rust.py --check    # exit 1 if one differs (no rewrite)
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
STUB = ROOT / "python/python/dpdnl/_dpdnl.pyi"
SRC = ROOT / "python/src"

#: Rust function names that differ from the Python name (getters named get_*).
RUST_NAME = {"box": "get_box", "positions": "get_positions", "velocities": "get_velocities",
             "__init__": "new"}


def targets() -> list[tuple[str, str, str]]:
    """(kind, Rust name, docstring) for every documented item of the stub: kind is
    ``fn``, ``method`` (in a ``#[pymethods]`` block), ``struct`` or ``exception``."""
    tree = ast.parse(STUB.read_text(), str(STUB))
    out = []
    for node in tree.body:
        if not isinstance(node, (ast.FunctionDef, ast.ClassDef)) or node.name.startswith("_"):
            continue
        doc = ast.get_docstring(node, clean=True)
        if doc is None:
            continue
        if isinstance(node, ast.FunctionDef):
            out.append(("fn", node.name, doc))
            continue
        is_exc = any(ast.unparse(b).endswith("Error") for b in node.bases)
        out.append(("exception" if is_exc else "struct", node.name, doc))
        for m in node.body:
            if not isinstance(m, ast.FunctionDef):
                continue
            mdoc = ast.get_docstring(m, clean=True)
            if mdoc is None or (m.name.startswith("_") and m.name != "__init__"):
                continue
            out.append(("method", RUST_NAME.get(m.name, m.name), mdoc))
    return out


def doc_comment(doc: str, indent: str) -> list[str]:
    return [f"{indent}///" + (f" {line}" if line else "") for line in doc.splitlines()]


def replace_item(text: str, kind: str, name: str, doc: str) -> tuple[str, bool]:
    """`text` with the doc comment of item `name` replaced; False when it is not found."""
    lines = text.split("\n")
    if kind == "exception":
        pat = re.compile(r"create_exception!\(\s*dpdnl,\s*" + name + r",\s*\w+,\s*\"", re.S)
        m = pat.search(text)
        if not m:
            return text, False
        start = m.end()
        i = start
        while text[i] != '"':
            i += 2 if text[i] == "\\" else 1
        lit = doc.replace("\\", "\\\\").replace('"', '\\"')
        return text[:start] + lit + text[i:], True
    if kind == "struct":
        pat = re.compile(r"^\s*pub struct " + name + r"\b")
    else:
        pat = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?fn " + re.escape(name) + r"\b")
    first = 0
    if kind == "method":
        first = next((k for k, line in enumerate(lines) if "#[pymethods]" in line), len(lines))
    for k, line in enumerate(lines):
        if k < first or not pat.match(line):
            continue
        j = k - 1
        while j >= 0 and lines[j].lstrip().startswith("#["):
            j -= 1
        end = j + 1
        while j >= 0 and lines[j].lstrip().startswith("///"):
            j -= 1
        start = j + 1
        indent = re.match(r"\s*", line).group(0)
        new = lines[:start] + doc_comment(doc, indent) + lines[end:]
        return "\n".join(new), True
    return text, False


def main() -> int:
    check = "--check" in sys.argv[1:]
    files = sorted(SRC.rglob("*.rs"))
    texts = {f: f.read_text() for f in files}
    missing = []
    for kind, name, doc in targets():
        for f in files:
            new, found = replace_item(texts[f], kind, name, doc)
            if found:
                texts[f] = new
                break
        else:
            missing.append(name)
    if missing:
        print(f"pydoc-rust: not found under python/src: {missing}", file=sys.stderr)
        return 1
    changed = [f for f in files if texts[f] != f.read_text()]
    if check:
        for f in changed:
            print(f"pydoc-rust: {f.relative_to(ROOT)} differs from the stub's docstrings",
                  file=sys.stderr)
        return 1 if changed else 0
    for f in changed:
        f.write_text(texts[f])
        print(f"pydoc-rust: wrote {f.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
