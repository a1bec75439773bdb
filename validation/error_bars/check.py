#!/usr/bin/env python3
"""The errors `dpdnl analyze couette` reports against the spread of independent seeds.

Usage: check.py DPDNL RATE DIR LABEL   (DIR holds pxy.SEED.ave, one per seed)

For each seed's `fix ave/time` file (columns c_pdef[4] and c_tdef, every 10 steps):
  eta*: `dpdnl analyze couette FILE --rate RATE`, its viscosity and viscosity_err;
  kT:   `dpdnl analyze couette FILE --col c_tdef --rate=-1`, which reports
        -<c_tdef>/(-1) = <kT> and its block error through the same estimator.
The seeds' standard deviation (divisor n - 1) is the error a single run should report; it is
compared with the root mean square of the reported errors. Its own relative uncertainty is
1/sqrt(2 (n - 1)) (Gaussian means), the band the ratio should fall in.

For comparison, the errors of the estimator before issue 41 (src/stats.rs at 57426af: the first
blocking level with at least 16 blocks where s_(k+1) <= s_k + s_k/sqrt(2(n_k - 1)), else the
last such level) are computed here from the same series.

Prints one Markdown table row per quantity. Standard library only.
"""
import glob
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile


def old_block_error(xs):
    """Standard error by the pre-issue-41 rule of src/stats.rs (see the module doc)."""
    levels = []
    cur = list(xs)
    while len(cur) >= 2:
        n = len(cur)
        m = sum(cur) / n
        c0 = sum((x - m) ** 2 for x in cur) / n
        s = math.sqrt(c0 / (n - 1))
        levels.append((n, s, s / math.sqrt(2 * (n - 1))))
        cur = [0.5 * (cur[2 * i] + cur[2 * i + 1]) for i in range(n // 2)]
    usable = [lv for lv in levels if lv[0] >= 16]
    for a, b in zip(usable, usable[1:]):
        if b[1] <= a[1] + a[2]:
            return a[1], True
    return (usable[-1] if usable else levels[0])[1], False


def column(path, name):
    cols, vals = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                toks = line[1:].split()
                if toks and toks[0] == "TimeStep":
                    cols = toks
                continue
            toks = line.split()
            if toks:
                vals.append(float(toks[cols.index(name)]))
    return vals


def analyze(dpdnl, path, args, out):
    subprocess.run(
        [dpdnl, "analyze", "couette", path, *args, "--out", out, "--no-plot"],
        check=True,
        capture_output=True,
    )
    with open(out + ".json") as f:
        return json.load(f)


def main():
    dpdnl, rate, d, label = sys.argv[1:5]
    files = sorted(
        glob.glob(os.path.join(d, "pxy.*.ave")),
        key=lambda p: int(re.search(r"pxy\.(\d+)\.ave$", p).group(1)),
    )
    if len(files) < 3:
        sys.exit(f"{d}: need at least 3 seeds, found {len(files)}")
    tmp = tempfile.mkdtemp()
    cases = [
        ("eta*", ["--rate", rate], "c_pdef[4]", lambda v: -v / float(rate)),
        ("kT", ["--col", "c_tdef", "--rate=-1"], "c_tdef", lambda v: v),
    ]
    for name, args, col, to_value in cases:
        vals, errs, trusted, neff, old = [], [], 0, [], []
        for k, path in enumerate(files):
            j = analyze(dpdnl, path, args, os.path.join(tmp, f"{k}"))
            vals.append(j["viscosity"])
            errs.append(j["viscosity_err"])
            trusted += bool(j["pxy_converged"])
            neff.append(j["pxy_n_eff"])
            xs = column(path, col)
            e, _ = old_block_error(xs)
            # The same propagation as analyze couette: the relative error of the mean.
            m = sum(xs) / len(xs)
            old.append(abs(to_value(m)) * e / abs(m))
        n = len(vals)
        samples = len(column(files[0], col))
        sd = statistics.stdev(vals)
        rel = 1 / math.sqrt(2 * (n - 1))
        rms = math.sqrt(sum(e * e for e in errs) / n)
        rms_old = math.sqrt(sum(e * e for e in old) / n)
        print(
            f"| {label} | {name} | {n} | {samples} | {statistics.mean(vals):.4f} "
            f"| {sd:.4f} ± {sd * rel:.4f} | {rms:.4f} | {sd / rms:.2f} ± {sd / rms * rel:.2f} "
            f"| {trusted}/{n} | {statistics.median(neff):.0f} "
            f"| {rms_old:.4f} | {sd / rms_old:.2f} |"
        )


if __name__ == "__main__":
    main()
