#!/usr/bin/env python3
"""Summary of validation/polymer/run.sh: one row per run (friction, rate): eta* = -<P_xy>/rate
from `dpdnl analyze couette` (its block error), the temp/deform temperature, <R_g^2> per chain
and its xx part (flow direction), each with the standard error of 20 block means; a run that
stopped (the engine's blow-up check) is listed with the engine's message. Writes
results/summary.csv, results/summary.md and the flow curve (dpdnl analyze flowcurve).

    summary.py WORK RESULTS DPDNL
"""
import glob
import json
import math
import os
import subprocess
import sys

work, res, dpdnl = sys.argv[1:4]


def blocks(xs, nb=20):
    """Mean and standard error of nb block means."""
    bl = len(xs) // nb
    m = sum(xs) / len(xs)
    means = [sum(xs[b * bl:(b + 1) * bl]) / bl for b in range(nb)]
    var = sum((x - m) ** 2 for x in means) / (nb - 1)
    return m, math.sqrt(var / nb)


def columns(path):
    rows = [list(map(float, l.split())) for l in open(path) if l.strip() and not l.startswith("#")]
    return list(zip(*rows))


rows = []
for d in sorted(glob.glob(os.path.join(work, "*_r*"))):
    name = os.path.basename(d)
    friction, rate = name.split("_r")
    obs = os.path.join(d, "obs.ave")
    log = next((p for p in (os.path.join(d, "log.lammps"), os.path.join(d, "log.dpdnl"))
                if os.path.exists(p)), None)
    text = open(log).read() if log else ""
    if "ERROR" in text or not os.path.exists(obs) or "Total wall time" not in text:
        msg = next((l for l in text.splitlines() if "ERROR" in l), "no output")
        rows.append(dict(friction=friction, rate=float(rate), tag=rate,
                         status="stopped: " + msg.strip()))
        continue
    out = os.path.join(res, name + ".couette")
    subprocess.run([dpdnl, "analyze", "couette", obs, "--col", "c_pdef[4]", "--rate", rate,
                    "--label", friction, "--out", out, "--no-plot"], check=True,
                   stdout=subprocess.DEVNULL)
    eta = json.load(open(out + ".json"))
    cols = columns(obs)
    t, rg2, rgxx = blocks(cols[2]), blocks(cols[3]), blocks(cols[4])
    rows.append(dict(friction=friction, rate=float(rate), tag=rate, status="ok",
                     eta=eta["viscosity"], eta_err=eta["viscosity_err"], T=t[0], T_err=t[1],
                     rg2=rg2[0], rg2_err=rg2[1], rgxx=rgxx[0], rgxx_err=rgxx[1]))

rows.sort(key=lambda r: (r["friction"], r["rate"]))
keys = ["friction", "rate", "status", "eta", "eta_err", "T", "T_err", "rg2", "rg2_err", "rgxx",
        "rgxx_err"]
with open(os.path.join(res, "summary.csv"), "w") as f:
    f.write(",".join(keys) + "\n")
    for r in rows:
        f.write(",".join(str(r.get(k, "")) for k in keys) + "\n")
with open(os.path.join(res, "summary.md"), "w") as f:
    f.write("| friction | rate | η* | T (temp/deform) | ⟨R_g²⟩ | ⟨R_g²⟩_xx |\n|---|---:|---:|---:|---:|---:|\n")
    for r in rows:
        if r["status"] != "ok":
            f.write(f"| {r['friction']} | {r['rate']:g} | {r['status']} | | | |\n")
            continue
        f.write(f"| {r['friction']} | {r['rate']:g} | {r['eta']:.3f} ± {r['eta_err']:.3f} | "
                f"{r['T']:.4f} ± {r['T_err']:.4f} | {r['rg2']:.3f} ± {r['rg2_err']:.3f} | "
                f"{r['rgxx']:.3f} ± {r['rgxx_err']:.3f} |\n")
ok = [os.path.join(res, f"{r['friction']}_r{r['tag']}.couette.json") for r in rows
      if r["status"] == "ok"]
ok = [p for p in ok if os.path.exists(p)]
if ok:
    subprocess.run([dpdnl, "analyze", "flowcurve", *ok, "--out", os.path.join(res, "flowcurve")],
                   check=True, stdout=subprocess.DEVNULL)
print(open(os.path.join(res, "summary.md")).read())
