#!/usr/bin/env python3
"""The temperature of the many-body DPD liquid under shear-thinning friction (issue 46).

    validation/mdpd/thinning.py [--quick]

Runs validation/mdpd/in.liquid (pair_style mdpd/nonlinear, the A = -40, B = 25 liquid at its
coexistence density 6.48) and validation/mdpd/in.ideal (dpd/nonlinear, a = 0, the same box and
atoms) in the standalone engine, for the cases of CASES below, and writes
validation/mdpd/results/thinning.csv and thinning.md (the table the manual page
docs/manual/styles/pair_mdpd_nonlinear.md copies).

What it measures. With LAMMPS's Lucy density weight the many-body force is not the gradient
of a potential (docs/models.md section 4.10): it does net work on the atoms, which the
thermostat must remove, so the liquid settles at T > kT even with `friction none`. If the
heat input W does not depend on the friction, the balance W = Gamma (T - kT) makes the excess
T - kT inversely proportional to the friction gamma0 (first group of cases). A thinning
friction removes less heat as the liquid gets hotter (gamma = gamma0 exp(-gamma1 S) falls with
the pair velocities), so the excess grows with gamma1, and where the friction's loss outruns
the heat balance the temperature runs away (second and third groups). Without the many-body
force (in.ideal) the same schemes keep kT, to an error that shrinks with the time step
(fourth group): the excess is the many-body force's, not a fault of the noise schemes.

Each run starts from the same liquid equilibrated for 20 time units with friction none and
gamma0 = 18 (T within 1 % of kT), so that no run starts hot: with a friction that thins as the
liquid heats, a hot start can itself decide where the run ends up, which the last group (no
equilibration: the random start heats the liquid far above kT in its first steps) shows.

Statistics: thermo every 0.05 time units over 100 time units; the first 10 are discarded; the
mean's error is that of 20 block means (blocks of 4.5 time units, much longer than the kinetic
temperature's correlation time, about 1 / (gamma0 n [w_D]) < 0.1 here). Runs whose
temperature bursts (dot at gamma1 >= 1) are not stationary: their error bar is indicative
only, and the table also gives the largest block mean.

Environment: DPDNL [target/release/dpdnl], PAR [2] runs at a time.
"""

import csv
import os
import re
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RES = os.path.join(HERE, "results")
DPDNL = os.environ.get("DPDNL", os.path.join(ROOT, "target", "release", "dpdnl"))

EQ, TIME, SKIP, SAMPLE, NBLOCKS = 20.0, 100.0, 10.0, 0.05, 20

# (group, script, friction, noise, gamma0, gamma1, dt[, equilibration time])
CASES = []
for g0 in (2.25, 4.5, 9.0, 18.0):
    CASES.append(("heat balance", "liquid", "none", "plain", g0, 0.0, 0.005))
    CASES.append(("heat balance", "liquid", "cross", "plain", g0, 2.0, 0.005))
for g1 in (0.5, 1.0, 2.0):
    for fr, no in (("cross", "plain"), ("dot", "corrected"), ("dot", "twostep")):
        if not (g1 == 2.0 and fr == "cross"):
            CASES.append(("thinning", "liquid", fr, no, 4.5, g1, 0.005))
CASES.append(("time step", "liquid", "cross", "plain", 4.5, 2.0, 0.0025))
CASES.append(("time step", "liquid", "dot", "corrected", 4.5, 2.0, 0.0025))
CASES.append(("no many-body force", "ideal", "none", "plain", 4.5, 0.0, 0.004))
for dt in (0.004, 0.002, 0.001):
    for fr, no in (("cross", "plain"), ("dot", "corrected"), ("dot", "twostep")):
        CASES.append(("no many-body force", "ideal", fr, no, 4.5, 2.0, dt))
# No equilibration: the measured run starts from the random positions, whose first steps heat
# the liquid far above kT.
for fr, no, g0 in (("none", "plain", 4.5), ("cross", "plain", 2.25), ("cross", "plain", 4.5),
                   ("dot", "corrected", 4.5), ("dot", "twostep", 4.5)):
    CASES.append(("hot start", "liquid", fr, no, g0, 0.0 if fr == "none" else 2.0, 0.005, 0.0))


def run(case):
    group, script, fr, no, g0, g1, dt = case[:7]
    eq_time = case[7] if len(case) > 7 else EQ
    steps = int(round(TIME / dt))
    eq = int(round(eq_time / dt))
    every = int(round(SAMPLE / dt))
    cmd = [DPDNL, "run", os.path.join(HERE, f"in.{script}"), "--threads", "1",
           "-var", "friction", fr, "-var", "noise", no, "-var", "gamma0", str(g0),
           "-var", "gamma1", str(g1), "-var", "dt", str(dt), "-var", "every", str(every),
           "-var", "steps", str(steps), "-var", "eq", str(eq), "--log", "none"]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=RES)
    if p.returncode != 0:
        sys.exit(f"thinning.py: {' '.join(cmd)} failed:\n{p.stderr}")
    temps = []
    for line in p.stdout.splitlines():
        m = re.match(r"\s*(\d+)\s+(\S+)\s*$", line)
        if m and int(m.group(1)) * dt > eq_time + SKIP + 1e-9:
            temps.append(float(m.group(2)))
    if len(temps) < NBLOCKS:
        sys.exit(f"thinning.py: {len(temps)} samples from {' '.join(cmd)}")
    b = len(temps) // NBLOCKS
    means = [statistics.fmean(temps[k * b:(k + 1) * b]) for k in range(NBLOCKS)]
    mean = statistics.fmean(temps[:b * NBLOCKS])
    err = statistics.stdev(means) / NBLOCKS ** 0.5
    return dict(group=group, style="mdpd/nonlinear" if script == "liquid" else "dpd/nonlinear a=0",
                friction=fr, noise=no, gamma0=g0, gamma1=g1, dt=dt, samples=len(temps),
                T=f"{mean:.4f}", err=f"{err:.4f}", max_block=f"{max(means):.3f}",
                excess_x_gamma0=f"{(mean - 1.0) * g0:.3f}")


def main():
    cases = CASES
    if "--quick" in sys.argv[1:]:
        global EQ, TIME, SKIP
        EQ, TIME, SKIP = 2.0, 6.0, 1.0
        cases = CASES[:2]
    os.makedirs(RES, exist_ok=True)
    with ThreadPoolExecutor(int(os.environ.get("PAR", "2"))) as ex:
        rows = list(ex.map(run, cases))
    name = "thinning_quick" if cases is not CASES else "thinning"
    with open(os.path.join(RES, f"{name}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    lines = [
        "| case | style | friction / noise | γ0 | γ1 | δt | ⟨T⟩ (kT = 1) | largest block mean | (⟨T⟩ − 1) γ0 |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['group']} | {r['style']} | {r['friction']} / {r['noise']} | {r['gamma0']:g} "
                     f"| {r['gamma1']:g} | {r['dt']:g} | {r['T']} ± {r['err']} | {r['max_block']} "
                     f"| {r['excess_x_gamma0']} |")
    with open(os.path.join(RES, f"{name}.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
