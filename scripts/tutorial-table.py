#!/usr/bin/env python3
"""The table of the tutorial's step 5 (docs/manual/tutorial.md), from the files its commands make.

In the tutorial's folder, after step 5 (the page runs it so):

    python3 "$DPDNL_ROOT/scripts/tutorial-table.py"

reads flowcurve.csv (label,rate,eta,eta_err, from `dpdnl analyze flowcurve`) and the logs
log.none.RATE and log.cross.RATE of the Couette runs, prints the table in Markdown and writes it
to table.md. kT is the mean of the thermo column Temp (temp/deform) over the second half of the
last run of each log; the length of that run gives the scale the page was run at.

From the repository's folder, after a run of the whole page at SCALE=1 (the numbers the page
shows):

    python3 scripts/tutorial-table.py --update DIR

puts DIR/table.md between the page's markers `<!-- generated: tutorial-table ... -->` and
`<!-- end generated -->` and copies DIR/flowcurve.svg to docs/figures/tutorial-flowcurve.svg.
It refuses a run made at another scale (--any-scale overrides, for trying it out).
"""

import argparse
import csv
import glob
import os
import re
import shutil
import subprocess
import sys

PRODUCTION_STEPS = 20000  # the steps of the page's production run at scale 1
PAGE = "docs/manual/tutorial.md"
FIGURE = "docs/figures/tutorial-flowcurve.svg"
BEGIN = re.compile(r"^<!-- generated: tutorial-table\b.*-->$")
END = "<!-- end generated -->"


def last_run(log):
    """(steps, [(step, temp)]) of the last run in a dpdnl or LAMMPS log."""
    rows, steps, cols, cur = [], None, None, None
    with open(log) as f:
        for line in f:
            w = line.split()
            if w[:1] == ["Step"]:
                cols, cur = w, []
            elif line.startswith("Loop time") and cur is not None:
                m = re.search(r"for (\d+) steps", line)
                steps, rows, cols, cur = (int(m.group(1)) if m else None), cur, None, None
            elif cols and cur is not None and len(w) == len(cols):
                try:
                    cur.append((int(w[0]), float(w[cols.index("Temp")])))
                except ValueError:
                    pass
    if steps is None or not rows:
        sys.exit(f"{log}: no finished run with a Temp column")
    return steps, rows


def mean_temp(rows):
    """Mean Temp over the second half of a run's thermo lines (by step)."""
    first, last = rows[0][0], rows[-1][0]
    half = [t for s, t in rows if s >= first + (last - first) / 2]
    return sum(half) / len(half)


def table(folder):
    """The Markdown table and the scale it was run at."""
    eta = {}
    with open(os.path.join(folder, "flowcurve.csv")) as f:
        for r in csv.DictReader(f):
            eta[(r["label"], float(r["rate"]))] = (float(r["eta"]), float(r["eta_err"]))
    rates = sorted({rate for _, rate in eta})
    scales = set()
    lines = [
        "| γ̇ | η*, `friction none` | η*, `friction cross`, γ1 = 0.5 | ratio | kT, none / cross |",
        "|---|---|---|---|---|",
    ]
    for rate in rates:
        cells, kts = [], []
        for label in ("none", "cross"):
            if (label, rate) not in eta:
                sys.exit(f"flowcurve.csv: no {label} point at rate {rate:g}")
            e, err = eta[(label, rate)]
            cells.append(f"{e:.3f} ± {err:.3f}")
            logs = [p for p in glob.glob(os.path.join(folder, f"log.{label}.*"))
                    if abs(float(p.rsplit(f"log.{label}.", 1)[1]) - rate) < 1e-9]
            if len(logs) != 1:
                sys.exit(f"{folder}: expected one log.{label}.{rate:g}, found {logs}")
            steps, rows = last_run(logs[0])
            scales.add(steps / PRODUCTION_STEPS)
            kts.append(f"{mean_temp(rows):.2f}")
        ratio = eta[("cross", rate)][0] / eta[("none", rate)][0]
        lines.append(f"| {rate:g} | {cells[0]} | {cells[1]} | {ratio:.2f} | {kts[0]} / {kts[1]} |")
    if len(scales) != 1:
        sys.exit(f"the runs were made at different scales: {sorted(scales)}")
    return "\n".join(lines) + "\n", scales.pop()


def update(folder, any_scale):
    text, scale = table(folder)
    if abs(scale - 1) > 1e-12 and not any_scale:
        sys.exit(f"{folder} was run at SCALE={scale:g}; the page shows SCALE=1 (--any-scale to override)")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    page = os.path.join(root, PAGE)
    lines = open(page).read().split("\n")
    begin = [i for i, l in enumerate(lines) if BEGIN.match(l)]
    end = [i for i, l in enumerate(lines) if l == END]
    if len(begin) != 1 or len(end) != 1 or end[0] < begin[0]:
        sys.exit(f"{PAGE}: expected one '<!-- generated: tutorial-table ... -->' ... '{END}' region")
    try:
        commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    marker = (f"<!-- generated: tutorial-table by `python3 scripts/tutorial-table.py --update DIR` "
              f"from a run of this page at SCALE={scale:g}, commit {commit} -->")
    lines[begin[0]:end[0] + 1] = [marker] + text.rstrip("\n").split("\n") + [END]
    with open(page, "w") as f:
        f.write("\n".join(lines))
    os.makedirs(os.path.dirname(os.path.join(root, FIGURE)), exist_ok=True)
    shutil.copyfile(os.path.join(folder, "flowcurve.svg"), os.path.join(root, FIGURE))
    print(f"updated {PAGE} (table) and {FIGURE} from {folder} (SCALE={scale:g}, commit {commit})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--update", metavar="DIR",
                    help="put DIR's table and figure into the page (run from the repository)")
    ap.add_argument("--any-scale", action="store_true",
                    help="with --update: accept a run at SCALE other than 1")
    a = ap.parse_args()
    if a.update:
        update(a.update, a.any_scale)
        return
    text, scale = table(".")
    with open("table.md", "w") as f:
        f.write(text)
    print(f"η* and kT at SCALE={scale:g} (also in table.md):")
    print(text, end="")


if __name__ == "__main__":
    main()
