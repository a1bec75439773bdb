#!/usr/bin/env python3
"""Render the Python package's reference page of the manual from its source.

The reference is generated from the two files that state the package's interface: the type stubs
of the extension module (python/python/dpdnl/_dpdnl.pyi, whose docstrings are the documentation
of the Rust-implemented functions and classes) and the pure-Python part
(python/python/dpdnl/__init__.py). Both are read with the standard library's ``ast``, so nothing
is imported: the page can be built without compiling the extension (pdoc or pydoc would import
``dpdnl`` and so need the maturin build, minutes of compiling, in the docs job).

Docstrings follow the Google layout: a summary, then the sections ``Args:`` (one ``name:
meaning, unit`` entry per parameter; the type and the default are taken from the signature),
``Returns:``, ``Raises:`` and ``Example:`` (doctest lines, ``>>>``, which
python/tests/test_docs.py runs). The page is refused (exit 1, naming the place) when a public
function or method lacks an example, or when its ``Args:`` and its signature do not name the
same parameters, so the reference cannot fall behind the signatures.

Usage:
    python3 scripts/pyref.py            # writes docs/manual/python-api.md
    python3 scripts/pyref.py --check    # exit 1 if that file is not what the sources give
"""

from __future__ import annotations

import ast
import re
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PKG = ROOT / "python/python/dpdnl"
OUT = ROOT / "docs/manual/python-api.md"


def rst_to_md(text: str) -> str:
    """The few reST constructs the docstrings use, as Markdown."""
    text = re.sub(r":(?:class|func|meth|attr|mod):`~?([^`]+)`", r"`\1`", text)
    text = text.replace("``", "`")
    return text


def dedent_doc(node: ast.AST) -> str:
    doc = ast.get_docstring(node, clean=True)
    return rst_to_md(doc) if doc else ""


SECTIONS = ("Args", "Returns", "Raises", "Example")
#: Problems found while rendering (a missing example, Args that do not match the signature).
PROBLEMS: list[str] = []


def split_doc(doc: str) -> tuple[str, dict[str, str]]:
    """A cleaned docstring as its text before the first section and each section's body,
    dedented."""
    intro: list[str] = []
    sections: dict[str, list[str]] = {}
    current: list[str] = intro
    for line in doc.splitlines():
        m = re.fullmatch(r"(" + "|".join(SECTIONS) + r"):\s*", line)
        if m:
            current = sections.setdefault(m.group(1), [])
            continue
        current.append(line)
    body = {k: textwrap.dedent("\n".join(v)).strip("\n") for k, v in sections.items()}
    return "\n".join(intro).strip("\n"), body


def parse_args(body: str) -> dict[str, str]:
    """``name: text`` entries of an ``Args:`` section (continuation lines indented)."""
    out: dict[str, str] = {}
    name = None
    for line in body.splitlines():
        m = re.match(r"^(\*{0,2}\w+):\s*(.*)$", line)
        if m and not line.startswith(" "):
            name = m.group(1).lstrip("*")
            out[name] = m.group(2).strip()
        elif name is not None and line.strip():
            out[name] += " " + line.strip()
    return out


def params(fn: ast.FunctionDef, drop_self: bool) -> list[tuple[str, str, str]]:
    """(name, type, default) of each parameter, in order; default "required" when none."""
    a = fn.args
    pos = a.posonlyargs + a.args
    defaults = [None] * (len(pos) - len(a.defaults)) + list(a.defaults)
    rows = []
    for arg, d in zip(pos, defaults):
        rows.append((arg, d))
    rows += list(zip(a.kwonlyargs, a.kw_defaults))
    if drop_self and rows and rows[0][0].arg in ("self", "cls"):
        rows = rows[1:]
    out = []
    for arg, d in rows:
        ann = ast.unparse(arg.annotation) if arg.annotation is not None else ""
        out.append((arg.arg, ann, "required" if d is None else ast.unparse(d)))
    return out


def render_doc(node: ast.AST, where: str, fn: ast.FunctionDef | None, drop_self: bool,
               out: list[str], need_example: bool = True) -> None:
    """The docstring of `node` with its sections: a parameter table (types and defaults from
    `fn`'s signature), returns, raises, and the example as a code block."""
    doc = ast.get_docstring(node, clean=True) or ""
    intro, sec = split_doc(doc)
    if intro:
        out.append(rst_to_md(intro) + "\n")
    if fn is not None:
        ps = params(fn, drop_self)
        documented = parse_args(sec.get("Args", ""))
        names = [p[0] for p in ps]
        if set(names) != set(documented):
            missing = [n for n in names if n not in documented]
            extra = [n for n in documented if n not in names]
            PROBLEMS.append(
                f"{where}: Args and signature differ (undocumented: {missing}, not in the "
                f"signature: {extra})"
            )
        if ps:
            out.append("**Parameters**\n")
            out.append("| name | type | default | meaning |\n|---|---|---|---|")
            for name, ann, default in ps:
                text = rst_to_md(documented.get(name, "")).replace("|", "\\|")
                shown = default if default == "required" else f"`{default}`"
                out.append(f"| `{name}` | `{ann}` | {shown} | {text} |")
            out.append("")
    elif "Args" in sec:
        PROBLEMS.append(f"{where}: Args without a signature")
    if "Returns" in sec:
        out.append("**Returns**\n")
        out.append(rst_to_md(sec["Returns"]) + "\n")
    if "Raises" in sec:
        out.append("**Raises**\n")
        for name, text in parse_args(sec["Raises"]).items():
            out.append(f"- `{name}`: {rst_to_md(text)}")
        out.append("")
    if "Example" in sec:
        out.append("**Example**\n")
        out.append("```python\n" + sec["Example"] + "\n```\n")
    elif need_example:
        PROBLEMS.append(f"{where}: no Example section")


def signature(fn: ast.FunctionDef, drop_self: bool = False) -> str:
    args = fn.args
    if drop_self and args.args and args.args[0].arg in ("self", "cls"):
        args = ast.arguments(
            posonlyargs=args.posonlyargs,
            args=args.args[1:],
            vararg=args.vararg,
            kwonlyargs=args.kwonlyargs,
            kw_defaults=args.kw_defaults,
            kwarg=args.kwarg,
            defaults=args.defaults[-len(args.args) + 1 :] if len(args.args) > 1 else [],
        )
        # Defaults belong to the last parameters; recompute from the original list.
        n_def = len(fn.args.defaults)
        kept = fn.args.args[1:]
        args.defaults = fn.args.defaults[max(0, n_def - len(kept)) :] if n_def else []
    ret = f" -> {ast.unparse(fn.returns)}" if fn.returns is not None else ""
    return f"{fn.name}({ast.unparse(args)}){ret}"


def decorators(fn: ast.FunctionDef) -> set[str]:
    return {ast.unparse(d) for d in fn.decorator_list}


def render_class(cls: ast.ClassDef, out: list[str]) -> None:
    bases = ", ".join(ast.unparse(b) for b in cls.bases)
    out.append(f"### `dpdnl.{cls.name}`\n")
    if bases:
        out.append(f"`class {cls.name}({bases})`\n")
    # The class's text, its fields, then its example (the methods follow).
    intro, sections = split_doc(ast.get_docstring(cls, clean=True) or "")
    if intro:
        out.append(rst_to_md(intro) + "\n")
    fields = []
    members = []
    for item in cls.body:
        if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
            fields.append(item)
        elif isinstance(item, ast.FunctionDef) and (
            not item.name.startswith("_") or item.name == "__init__"
        ):
            members.append(item)
    # Attribute docstrings (a string literal right after an annotated field).
    field_docs: dict[str, str] = {}
    for a, b in zip(cls.body, cls.body[1:]):
        if (
            isinstance(a, ast.AnnAssign)
            and isinstance(a.target, ast.Name)
            and isinstance(b, ast.Expr)
            and isinstance(b.value, ast.Constant)
            and isinstance(b.value.value, str)
        ):
            text = " ".join(line.strip() for line in b.value.value.strip().splitlines())
            field_docs[a.target.id] = rst_to_md(text).replace("|", "\\|")
    if fields and field_docs:
        out.append("| field | type | meaning |\n|---|---|---|")
        for f in fields:
            name = f.target.id
            out.append(
                f"| `{name}` | `{ast.unparse(f.annotation)}` | {field_docs.get(name, '')} |"
            )
        out.append("")
    elif fields:
        out.append("| field | type |\n|---|---|")
        for f in fields:
            out.append(f"| `{f.target.id}` | `{ast.unparse(f.annotation)}` |")
        out.append("")
    if "Example" in sections:
        out.append("**Example**\n")
        out.append("```python\n" + sections["Example"] + "\n```\n")
    else:
        PROBLEMS.append(f"dpdnl.{cls.name}: no Example section")
    if set(sections) - {"Example"}:
        PROBLEMS.append(f"dpdnl.{cls.name}: a class docstring has only text and an Example")
    seen_props: set[str] = set()
    for m in members:
        decs = decorators(m)
        if any(d.endswith(".setter") for d in decs):
            if m.name in seen_props:
                out[-1] = out[-1].replace("(read-only)", "(settable)")
            continue
        doc = dedent_doc(m)
        if "property" in decs:
            seen_props.add(m.name)
            ret = ast.unparse(m.returns) if m.returns is not None else ""
            line = f"- `{m.name}: {ret}` (read-only)" + (f": {doc}" if doc else "")
            out.append(line.replace("\n", " "))
            continue
        if out and out[-1].startswith("- `"):
            out.append("")
        kind = "staticmethod " if "staticmethod" in decs else ""
        name = f"{cls.name}" if m.name == "__init__" else f"{cls.name}.{m.name}"
        sig = signature(m, drop_self="staticmethod" not in decs)
        sig = name + sig[len(m.name) :]
        out.append(f"#### `{kind}{sig}`\n".replace("`staticmethod ", "`"))
        # The class's example constructs it; every other method has its own.
        render_doc(
            m, f"dpdnl.{name}", m, "staticmethod" not in decs, out, m.name != "__init__"
        )
    if out and out[-1].startswith("- `"):
        out.append("")


def render_function(fn: ast.FunctionDef, out: list[str]) -> None:
    out.append(f"### `dpdnl.{fn.name}`\n")
    out.append(f"```python\n{signature(fn)}\n```\n")
    render_doc(fn, f"dpdnl.{fn.name}", fn, False, out)


def main() -> int:
    init = ast.parse((PKG / "__init__.py").read_text(), "__init__.py")
    stub = ast.parse((PKG / "_dpdnl.pyi").read_text(), "_dpdnl.pyi")
    all_names: list[str] = []
    for node in init.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            all_names = [ast.literal_eval(e) for e in node.value.elts]
    defs: dict[str, ast.AST] = {}
    for tree in (stub, init):  # the Python wrapper wins over the stub of the same name
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                defs[node.name] = node
    out = [
        "# Python API",
        "",
        "<!-- Generated by scripts/pyref.py from python/python/dpdnl/__init__.py and",
        "     _dpdnl.pyi: edit the docstrings there, then run `python3 scripts/pyref.py`. -->",
        "",
        "Install with `python3 -m venv .venv && .venv/bin/pip install ./python`, then",
        "`import dpdnl`. Every number comes from the Rust crate, the same code as the `dpdnl`",
        "program; the package's own guide, with an example and its output, is `python/README.md`.",
        "",
        rst_to_md(ast.get_docstring(init) or ""),
        "",
    ]
    classes = [n for n in all_names if isinstance(defs.get(n), ast.ClassDef)]
    functions = [n for n in all_names if isinstance(defs.get(n), ast.FunctionDef)]
    missing = [n for n in all_names if n not in defs]
    if missing:
        print(f"pyref: names in __all__ without a definition: {missing}", file=sys.stderr)
        return 1
    out.append("## Classes and exceptions\n")
    for n in classes:
        render_class(defs[n], out)
    out.append("## Functions\n")
    for n in functions:
        render_function(defs[n], out)
    if PROBLEMS:
        for problem in PROBLEMS:
            print(f"pyref: {problem}", file=sys.stderr)
        print(
            "pyref: fix the docstrings (python/python/dpdnl/_dpdnl.pyi, __init__.py; see this "
            "script's docstring for their layout)",
            file=sys.stderr,
        )
        return 1
    text = "\n".join(out).rstrip() + "\n"
    text = re.sub(r"\n{3,}", "\n\n", text)
    if "--check" in sys.argv[1:]:
        if not OUT.is_file() or OUT.read_text() != text:
            print(
                f"pyref: {OUT.relative_to(ROOT)} is not up to date with the package's "
                "docstrings; run `python3 scripts/pyref.py` and commit it",
                file=sys.stderr,
            )
            return 1
        print(f"pyref: {OUT.relative_to(ROOT)} is up to date")
        return 0
    OUT.write_text(text)
    print(f"pyref: wrote {OUT.relative_to(ROOT)} ({len(classes)} classes, {len(functions)} functions)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
