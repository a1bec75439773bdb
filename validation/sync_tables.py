#!/usr/bin/env python3
"""Keeps the result tables of the validation READMEs equal to the summaries they are copied from.

    validation/sync_tables.py [--check] README.md ...

A README table that is a copy of a table in a generated summary (results/summary.md,
results/repulsion.md, ...) carries a marker on the line just above it:

    <!-- copy: results/summary.md | Heading text of the summary's section -->
    <!-- copy: results/summary.md | Heading text #2 -->      (the section's second table)

The path is relative to the README; the heading is the summary's heading line without its
leading '#'s; a section runs to the next heading of any level; a table is a run of lines that
start with '|'. Without --check the marked tables are rewritten in place from their summaries
(summary.sh runs this after writing the summary); with --check nothing is written and the exit
status is 1 if any marked table differs from its source (the test suite's staleness check). A
marker whose file, heading or table is missing, or that is not followed by a table, is an error
(exit 2) in both modes.
"""
import re
import sys
from pathlib import Path

MARK = re.compile(r"^<!-- copy: (?P<path>[^|]+?) \| (?P<head>.+?)(?: #(?P<k>\d+))? -->\s*$")


def tables_of_section(lines, head):
    """The tables (lists of lines) of the section whose heading text is `head`, or None."""
    for i, line in enumerate(lines):
        if line.startswith("#") and line.lstrip("#").strip() == head:
            tables, cur = [], None
            for line2 in lines[i + 1 :]:
                if line2.startswith("#"):
                    break
                if line2.startswith("|"):
                    cur = cur if cur is not None else []
                    cur.append(line2)
                elif cur is not None:
                    tables.append(cur)
                    cur = None
            if cur is not None:
                tables.append(cur)
            return tables
    return None


def sync(readme: Path, check: bool):
    """Returns (changed table count, errors) for one README; writes it unless check."""
    lines = readme.read_text(encoding="utf-8").split("\n")
    out, errors, changed, i = [], [], 0, 0
    cache = {}
    while i < len(lines):
        line = lines[i]
        out.append(line)
        i += 1
        m = MARK.match(line)
        if not m:
            continue
        where = f"{readme}:{i}"
        src = (readme.parent / m["path"].strip()).resolve()
        if src not in cache:
            try:
                cache[src] = src.read_text(encoding="utf-8").split("\n")
            except OSError as e:
                errors.append(f"{where}: cannot read {m['path']}: {e.strerror}")
                cache[src] = None
        if cache[src] is None:
            continue
        tables = tables_of_section(cache[src], m["head"].strip())
        k = int(m["k"] or 1)
        if tables is None:
            errors.append(f"{where}: no heading '{m['head']}' in {m['path']}")
            continue
        if not 1 <= k <= len(tables):
            errors.append(f"{where}: section '{m['head']}' of {m['path']} has {len(tables)} table(s), not #{k}")
            continue
        j = i
        while j < len(lines) and lines[j].startswith("|"):
            j += 1
        if j == i:
            errors.append(f"{where}: the marker is not followed by a table")
            continue
        if lines[i:j] != tables[k - 1]:
            changed += 1
            print(f"{where}: table differs from {m['path']} § {m['head']}" + (f" #{k}" if k > 1 else ""))
        out.extend(tables[k - 1])
        i = j
    if not check and changed and not errors:
        readme.write_text("\n".join(out), encoding="utf-8")
    return changed, errors


def main(argv):
    check = "--check" in argv
    files = [a for a in argv if a != "--check"]
    if not files or any(a.startswith("-") for a in files):
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    total, errors = 0, []
    for f in files:
        try:
            n, e = sync(Path(f), check)
        except OSError as err:
            n, e = 0, [f"{f}: cannot read: {err.strerror}"]
        total += n
        errors += e
    for e in errors:
        print(f"sync_tables.py: {e}", file=sys.stderr)
    if errors:
        return 2
    if check and total:
        print(f"sync_tables.py: {total} table(s) stale; run validation/sync_tables.py {' '.join(files)}", file=sys.stderr)
        return 1
    if not check and total:
        print(f"sync_tables.py: {total} table(s) rewritten")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
