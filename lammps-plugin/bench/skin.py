#!/usr/bin/env python3
"""The measurements of docs/manual/tuning.md: the neighbour skin, `neigh_modify delay` and
`noise_dist uniform`, in the standalone engine (`dpdnl run --threads 1`) and in LAMMPS
(`build/lmp_dpdnl`, OMP_NUM_THREADS=1), on in.skin: the Groot-Warren fluid (n = 3, a = 25,
dt = 0.04) and an ideal fluid at n = 16 (a = 0, dt = 0.005), N = 20000, 200 + 300 steps.

    python3 lammps-plugin/bench/skin.py [--reps 3] [--out results.json]

from the repository's folder, after `cargo build --release` and `bash lammps-plugin/build.sh`
(DPDNL=path overrides target/release/dpdnl). Repetitions are interleaved; the summary gives,
per configuration, the median of the process CPU seconds (user + sys: less sensitive to other
jobs than wall time), LAMMPS's neighbour-list builds and dangerous builds of the 300-step run,
and the temperature at step 500.
"""
import argparse, json, os, re, resource, statistics, subprocess, sys
from collections import defaultdict

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
CASES = {"gw": dict(n=3, a=25, dt=0.04), "n16": dict(n=16, a=0, dt=0.005)}


def configs():
    out = []
    for case in CASES:
        for skin in (0.2, 0.3, 0.5, 0.8, 1.0, 1.5):
            for eng in ("lmp", "dpdnl"):
                out.append((case, eng, skin, 0, "gaussian"))
        for eng in ("lmp", "dpdnl"):
            out.append((case, eng, 0.3 if case == "n16" else 1.0, 0, "uniform"))
        out.append((case, "lmp", 0.3, 10, "gaussian"))
    return out


def run(cfg, dpdnl, lmp):
    case, eng, skin, delay, noise = cfg
    v = dict(CASES[case], skin=skin, delay=delay, noise=noise, steps=300)
    words = [w for k, x in v.items() for w in ("-var", k, str(x))]
    if eng == "lmp":
        cmd, env = [lmp, "-in", "in.skin", "-log", "none"] + words, dict(os.environ, OMP_NUM_THREADS="1")
    else:
        cmd, env = [dpdnl, "run", "in.skin", "--threads", "1", "--log", "none"] + words, dict(os.environ)
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=HERE)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        sys.exit(f"{' '.join(cmd)}:\n{out.stdout[-2000:]}{out.stderr[-2000:]}")
    last = lambda pat: (re.findall(pat, out.stdout, re.M) or [None])[-1]
    return dict(case=case, eng=eng, skin=skin, delay=delay, noise=noise,
                cpu=r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime,
                builds=last(r"Neighbor list builds = (\d+)"), danger=last(r"Dangerous builds = (\d+)"),
                temp500=last(r"^\s+500\s+([0-9.eE+-]+)"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    dpdnl = os.environ.get("DPDNL", os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "dpdnl"))
    lmp = os.path.join(ROOT, "build", "lmp_dpdnl")
    res = [run(c, dpdnl, lmp) for _ in range(a.reps) for c in configs()]
    if a.out:
        json.dump(res, open(a.out, "w"), indent=1)
    g = defaultdict(list)
    for r in res:
        g[(r["case"], r["eng"], r["skin"], r["delay"], r["noise"])].append(r)
    print("case  engine  skin  delay  noise     CPU s (median, min-max)  builds  dangerous  T(500)")
    for k, rs in g.items():
        cpu = [r["cpu"] for r in rs]
        print(f"{k[0]:5} {k[1]:7} {k[2]:4}  {k[3]:5}  {k[4]:8}  {statistics.median(cpu):6.2f} ({min(cpu):.2f}-{max(cpu):.2f})"
              f"  {rs[0]['builds'] or '-':>6}  {rs[0]['danger'] or '-':>9}  {rs[0]['temp500']}")


if __name__ == "__main__":
    main()
