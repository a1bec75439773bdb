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


def chain_rg2(dump):
    """Per-frame <R_g^2> and <R_g,xx^2> over the chains (molecule id > 0) of a LAMMPS dump with
    columns id mol x y z, sorted by id, chains' beads consecutive in id along the backbone.
    Each chain is unwrapped along its bonds by the minimum image of the frame's box (tilt xy
    from the triclinic header), so image flags are not used."""
    out = []
    with open(dump) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if not lines[i].startswith("ITEM: TIMESTEP"):
            i += 1
            continue
        step = int(lines[i + 1])
        n = int(lines[i + 3])
        header = lines[i + 4]
        b = [list(map(float, lines[i + 5 + k].split())) for k in range(3)]
        xy = b[0][2] if "xy" in header else 0.0
        lx = (b[0][1] - max(0.0, xy)) - (b[0][0] - min(0.0, xy))
        ly, lz = b[1][1] - b[1][0], b[2][1] - b[2][0]
        cols = lines[i + 8].split()[2:]
        ci = {c: k for k, c in enumerate(cols)}
        chains = {}
        for l in lines[i + 9:i + 9 + n]:
            t = l.split()
            mol = int(t[ci["mol"]])
            if mol > 0:
                chains.setdefault(mol, []).append([float(t[ci[c]]) for c in ("x", "y", "z")])
        rg2 = rgxx = 0.0
        for beads in chains.values():
            pos = [beads[0]]
            for p in beads[1:]:
                q = pos[-1]
                d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
                k = round(d[2] / lz); d[2] -= k * lz
                k = round(d[1] / ly); d[1] -= k * ly; d[0] -= k * xy
                k = round(d[0] / lx); d[0] -= k * lx
                pos.append([q[0] + d[0], q[1] + d[1], q[2] + d[2]])
            m = len(pos)
            c = [sum(p[a] for p in pos) / m for a in range(3)]
            rg2 += sum((p[a] - c[a]) ** 2 for p in pos for a in range(3)) / m
            rgxx += sum((p[0] - c[0]) ** 2 for p in pos) / m
        out.append((step, rg2 / len(chains), rgxx / len(chains)))
        i += 9 + n
    return out


rows = []
for d in sorted(glob.glob(os.path.join(work, "*_r*"))):
    if not os.path.isdir(d):
        continue
    name = os.path.basename(d)
    friction, rate = name.split("_r")
    obs = os.path.join(d, "obs.ave")
    text = ""
    for f in ("log.lammps", "log.dpdnl", "screen.txt"):
        if os.path.exists(os.path.join(d, f)):
            text += open(os.path.join(d, f)).read()
    finished = "Total wall time" in text or text.count("Loop time of") >= 2
    if ("ERROR" in text or not os.path.exists(obs) or not finished
            or not os.path.exists(os.path.join(d, "poly.dump"))):
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
    t = blocks(cols[2])
    frames = chain_rg2(os.path.join(d, "poly.dump"))
    rg2, rgxx = blocks([f[1] for f in frames]), blocks([f[2] for f in frames])
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
