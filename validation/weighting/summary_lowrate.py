#!/usr/bin/env python3
"""Issue 31, item 4: where the sDPD low-rate excess of Table 4 comes from (compressibility, run
length or the model). Fluid: Table 4, Sc0 = 400, eta0 = 49, s = 0.0700 (proposed kernel, r_c =
2.5), N = 1600, 2-D Couette (examples/sdpd/in.couette_sdpd2d in build/lmp_dpdnl), with pair
seeds 1-4 (run.sh sdpd-couette SEEDS=...). Run tags:

  t4s400e49c20   c0 = 20, dt = 0.01,   10 + 6 time units (1000 + 600 steps)
  t4s400e49c40   c0 = 40, dt = 0.005,  10 + 6 time units (2000 + 1200 steps; the Table 4 runs)
  t4s400e49c80   c0 = 80, dt = 0.0025, 10 + 6 time units (4000 + 2400 steps)
  t4s400e49long  c0 = 40, dt = 0.005,  10 + 30 time units (2000 + 6000 steps): 5x longer
  t4s400e49vlong c0 = 40, dt = 0.005,  10 + 60 time units (2000 + 12000 steps): 10x longer
  t4s400e49c20long, t4s400e49c80long: c0 = 20 and 80 (dt scaled), 10 + 30 time units

  summary_lowrate.py --collect   reads work/<run>/pxy.ave, writes results/lowrate.csv
  summary_lowrate.py             the markdown tables (from results/lowrate.csv), to stdout

eta* = -<P_xy>/rate over the production (P_xy of compute pressure with the temp/deform bias,
sampled every 10 steps). Errors: std over seeds / sqrt(n). Windows: the production cut into
successive 6-time-unit windows, to see whether eta* drifts with time (a start transient) or
stays (a property of the model). Standard library only."""
import csv
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
WORK = os.path.join(HERE, "work")
RES = os.path.join(HERE, "results")
CSV = os.path.join(RES, "lowrate.csv")
TAGS = {  # tag: (c0, dt)
    "t4s400e49c20": (20, 0.01),
    "t4s400e49c40": (40, 0.005),
    "t4s400e49c80": (80, 0.0025),
    "t4s400e49long": (40, 0.005),
    "t4s400e49vlong": (40, 0.005),
    "t4s400e49c20long": (20, 0.01),
    "t4s400e49c80long": (80, 0.0025),
}
PAPER = {"0.05": 47.74, "0.1": 48.44, "0.2": 48.85, "0.5": 49.34, "1": 49.73}
ETABAR = 49.06
WINDOW = 6.0  # time units per window
NAME = re.compile(r"^sdpd_(t4s400e49(?:c20|c40|c80|long|vlong|c20long|c80long))_r([0-9.]+)_s([0-9]+)_lmp$")


def collect():
    rows = []
    for d in sorted(os.listdir(WORK)):
        m = NAME.match(d)
        p = os.path.join(WORK, d, "pxy.ave")
        if not m or not os.path.exists(p):
            continue
        tag, rate, seed = m.group(1), m.group(2), int(m.group(3))
        c0, dt = TAGS[tag]
        data = [
            [float(w) for w in line.split()]
            for line in open(p)
            if line.strip() and not line.startswith("#")
        ]
        if not data:
            continue
        span = data[-1][0] * dt  # production time
        nwin = max(1, int(round(span / WINDOW)))
        for w in range(-1, nwin):  # -1: the whole production
            if w < 0:
                sel = data
            else:
                lo, hi = w * WINDOW / dt, (w + 1) * WINDOW / dt
                sel = [r for r in data if lo < r[0] <= hi]
            if not sel:
                continue
            pxy = sum(r[1] for r in sel) / len(sel)
            rows.append(
                {
                    "tag": tag,
                    "c0": c0,
                    "dt": dt,
                    "rate": rate,
                    "seed": seed,
                    "window": "all" if w < 0 else str(w),
                    "samples": len(sel),
                    "eta": -pxy / float(rate),
                    "T": sum(r[2] for r in sel) / len(sel),
                    "drel": sum(r[5] for r in sel) / len(sel),
                }
            )
    if not rows:
        sys.exit(f"summary_lowrate.py: no runs of the low-rate study in {WORK} (run.sh sdpd-couette first)")
    with open(CSV, "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    print(f"wrote {CSV} ({len(rows)} rows)")


def mean_err(xs):
    n = len(xs)
    m = sum(xs) / n
    if n < 2:
        return m, float("nan"), n
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
    return m, s / math.sqrt(n), n


def table():
    rows = list(csv.DictReader(open(CSV)))
    out = []
    p = out.append
    p("### sDPD low-rate excess (issue 31): sound speed and run length (Table 4, Sc0 = 400, η0 = 49, s = 0.0700)")
    p("")
    p(
        "N = 1600, 2-D Couette in build/lmp_dpdnl, 4 pair seeds per row; η* = −⟨P_xy⟩/γ̇ over the "
        "production, ± std over seeds/√n; η̄ (kinetic theory) = 49.06."
    )
    p("")
    p("| run | c0 | δt | production (time units) | γ̇ | η* per seed | η* mean | paper η* | (mean − η̄)/err | T | rms(d − ⟨d⟩)/⟨d⟩ |")
    p("|---|---|---|---|---|---|---|---|---|---|---|")
    for tag in TAGS:
        for rate in ("0.05", "0.2"):
            sel = [r for r in rows if r["tag"] == tag and r["rate"] == rate and r["window"] == "all"]
            if not sel:
                continue
            sel.sort(key=lambda r: int(r["seed"]))
            etas = [float(r["eta"]) for r in sel]
            m, e, n = mean_err(etas)
            c0, dt = TAGS[tag]
            span = int(sel[0]["samples"]) * 10 * dt
            tm = sum(float(r["T"]) for r in sel) / n
            dm = sum(float(r["drel"]) for r in sel) / n
            p(
                f"| {tag} | {c0} | {dt} | {span:g} | {rate} | {', '.join(f'{x:.1f}' for x in etas)} | "
                f"{m:.2f} ± {e:.2f} ({n}) | {PAPER[rate]} | {(m - ETABAR) / e:+.1f} | {tm:.4f} | {dm:.4f} |"
            )
    p("")
    p("### After the start transient: the longer runs from production time 12 on (22 time units after the random start)")
    p("")
    p("Per seed the mean of its windows from 12 on (equal lengths), then mean ± std over seeds/√n.")
    p("")
    p("| run | c0 | δt | γ̇ | time span | η* per seed | η* mean | (mean − η̄)/η̄ | paper η* | (mean − paper)/err |")
    p("|---|---|---|---|---|---|---|---|---|---|")
    for tag, rate in [(t, r) for t in TAGS if t.endswith("long") for r in ("0.05", "0.2")]:
        per = {}
        for r in rows:
            if r["tag"] == tag and r["rate"] == rate and r["window"] != "all" and int(r["window"]) >= 2:
                per.setdefault(int(r["seed"]), []).append(float(r["eta"]))
        if not per:
            continue
        nw = max(len(v) for v in per.values())
        etas = [sum(v) / len(v) for k, v in sorted(per.items()) if len(v) == nw]
        if len(etas) < 2:
            continue
        m, e, n = mean_err(etas)
        c0, dt = TAGS[tag]
        p(
            f"| {tag} | {c0} | {dt} | {rate} | {2 * WINDOW:g}–{(nw + 2) * WINDOW:g} | {', '.join(f'{x:.1f}' for x in etas)} | "
            f"{m:.2f} ± {e:.2f} ({n}) | {100 * (m - ETABAR) / ETABAR:+.1f} % | {PAPER[rate]} | {(m - PAPER[rate]) / e:+.1f} |"
        )
    p("")
    p("### The longer runs cut into 6-time-unit windows: η* against time")
    p("")
    p("| run | c0 | γ̇ | window (time units after the 10 of equilibration) | η* per seed | mean ± std/√n |")
    p("|---|---|---|---|---|---|")
    for tag, rate in [(t, r) for t in TAGS if t.endswith("long") for r in ("0.05", "0.2")]:
        wins = sorted({int(r["window"]) for r in rows if r["tag"] == tag and r["rate"] == rate and r["window"] != "all"})
        for w in wins:
            sel = [r for r in rows if r["tag"] == tag and r["rate"] == rate and r["window"] == str(w)]
            sel.sort(key=lambda r: int(r["seed"]))
            etas = [float(r["eta"]) for r in sel]
            m, e, n = mean_err(etas)
            p(
                f"| {tag} | {TAGS[tag][0]} | {rate} | {w * WINDOW:g}–{(w + 1) * WINDOW:g} | {', '.join(f'{x:.1f}' for x in etas)} | "
                f"{m:.2f} ± {e:.2f} ({n}) |"
            )
    p("")
    print("\n".join(out))


if __name__ == "__main__":
    if "--collect" in sys.argv[1:]:
        collect()
    else:
        if os.path.exists(CSV):
            table()
