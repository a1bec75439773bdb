#!/usr/bin/env python3
"""Summary of validation/le_flip/run.sh: per run kT and eta* with `dpdnl analyze couette`'s
errors, the atoms put through y at flips and the momentum they changed; per mode the seed mean,
its error (seed s.d./sqrt(n)) and the seed s.d. beside the mean per-run error estimate.

usage: summary.py WORK RESULTS DPDNL [NPROD]"""
import json
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from flip_record import flip_records  # noqa: E402

work, res, dpdnl = sys.argv[1:4]
nprod = int(sys.argv[4]) if len(sys.argv) > 4 else 20000
N = 1600
runs = {}
for f in sorted(os.listdir(work)):
    m = re.fullmatch(r"log\.(check|jump)_s(\d+)", f)
    if not m:
        continue
    mode, seed = m.group(1), int(m.group(2))
    tag = f"{mode}_s{seed}"
    log = open(os.path.join(work, f)).read()
    first = (flip_records(log) or [{}])[0]
    atoms = first.get("atoms", 0)
    leak = first.get("momentum", 0.0)
    out = {}
    for what, fname, extra in (("eta", f"pxy.{tag}.ave", ["--rate", "3"]),
                               ("kT", f"temp.{tag}.ave", ["--rate=-1", "--col", "c_tdef",
                                                          "--from", str(nprod // 2)])):
        prefix = os.path.join(work, f"an.{what}.{tag}")
        subprocess.run([dpdnl, "analyze", "couette", os.path.join(work, fname)] + extra +
                       ["--out", prefix, "--no-plot"], check=True, capture_output=True)
        j = json.load(open(prefix + ".json"))
        out[what] = (j["viscosity"], j["viscosity_err"])
    runs.setdefault(mode, []).append((seed, out["kT"], out["eta"], atoms, leak))


def stats(xs):
    n = len(xs)
    m = sum(xs) / n
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1)) if n > 1 else float("nan")
    return m, sd, sd / math.sqrt(n)


cpath = os.path.join(work, "commit.txt")
commit = open(cpath).read().strip() if os.path.exists(cpath) else "unknown"
lines = ["# The momentum leak at box flips and fix flip/momentum (issue 41)", "",
         f"Binary: {os.path.basename(dpdnl)} of commit {commit}. The tutorial's 2-D Couette flow, N = {N}, rate 3, delta t = 0.005, "
         "10 + 100 time units, friction none; kT over the second half of the production run. "
         "`check`: the flipped atoms keep their velocities (plain fix deform, LAMMPS's "
         "behaviour); `jump`: fix flip/momentum gives them remap v's velocity jump. V = the "
         "momentum the flips changed / N (mass 1).", ""]
csv = ["mode,seed,kT,kT_err,eta,eta_err,atoms_through_y,momentum_changed,V"]
for mode in ("check", "jump"):
    rs = sorted(runs.get(mode, []))
    if not rs:
        continue
    lines += [f"## mode {mode}", "",
              "| seed | kT | eta* | atoms through y at flips | momentum changed | V |",
              "|---|---|---|---|---|---|"]
    for seed, kt, eta, atoms, leak in rs:
        v = leak / N if mode == "check" else 0.0
        lines.append(f"| {seed} | {kt[0]:.4f} ± {kt[1]:.4f} | {eta[0]:.4f} ± {eta[1]:.4f} | "
                     f"{atoms} | {leak:.4g} | {v:.4g} |")
        csv.append(f"{mode},{seed},{kt[0]:.6g},{kt[1]:.3g},{eta[0]:.6g},{eta[1]:.3g},{atoms},"
                   f"{leak:.6g},{v:.6g}")
    for name, k in (("kT", 1), ("eta*", 2)):
        m, sd, se = stats([r[k][0] for r in rs])
        est = sum(r[k][1] for r in rs) / len(rs)
        lines.append(f"\n{name}: seed mean {m:.4f} ± {se:.4f} (n = {len(rs)}); seed s.d. "
                     f"{sd:.4f} against the mean per-run error estimate {est:.4f} "
                     f"(ratio {sd / est:.2f})")
    lines.append("")
open(os.path.join(res, "summary.md"), "w").write("\n".join(lines) + "\n")
open(os.path.join(res, "summary.csv"), "w").write("\n".join(csv) + "\n")
print("\n".join(lines))
