#!/usr/bin/env python3
"""Speed of pair_style dpd/nonlinear (build/dpdnlplugin.so) beside LAMMPS's own pair_style dpd
and dpd/omp in the same LAMMPS binary, on the same inputs (in.ideal, in.gw). Stdlib only.

    python3 lammps-plugin/bench/bench.py [--lmp .venv-lammps/bin/lmp] [--reps 5] [--ranks 1,2]

Runs are interleaved (every repetition runs every style of every system, in a rotating order)
so that a change of machine load hits all styles alike; the table gives medians over the
repetitions. Atom-steps/s = N × steps / loop time of the timed run (the second `run`, after a
warm-up run); the pair time per step comes from LAMMPS's timing breakdown. Each run uses one
core (one MPI rank, OMP_NUM_THREADS=1) but dpd/omp and plugin-omp (the plugin on LAMMPS's
OpenMP threads, -pk omp N), which run on --threads threads per rank. Results go to
stdout as a Markdown table, with the load average before each repetition.
"""
import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import peers  # noqa: E402  (LAMMPS's log, read once for every benchmark here)

SYSTEMS = {"ideal": "ideal DPD, n = 16, N = 20000, δt = 1e-3",
           "gw": "Groot–Warren, n = 3, a = 25, N = 20000, δt = 0.04",
           "gw03": "Groot–Warren as gw, LAMMPS's default `neighbor 0.3 bin`"}
# The input of each system and its extra variables.
INPUT = {"ideal": ("in.ideal", {}), "gw": ("in.gw", {}), "gw03": ("in.gw", {"skin": "0.3"})}
LABELS = {"plugin": "dpd/nonlinear (plugin)", "plugin2": "dpd/nonlinear (--plugin2-dir build)",
          "plugin-omp": "dpd/nonlinear (plugin), --threads threads",
          "plugin2-omp": "dpd/nonlinear (--plugin2-dir build), --threads threads", "dpd": "dpd",
          "omp": "dpd/omp",
          "plugin-lammps": "dpd/nonlinear (plugin) walking LAMMPS's list (DPDNL_PAIR_LIST=lammps)",
          "plugin-lammps-omp": "dpd/nonlinear (plugin) walking LAMMPS's list, --threads threads"}
# Styles that run on --threads OpenMP threads per rank (-pk omp N): dpd/omp, and the plugin,
# which takes LAMMPS's thread count.
THREADED = ("omp", "plugin-omp", "plugin2-omp", "plugin-lammps-omp")


def run(lmp, plugin_dirs, system, style, steps, threads, workdir, ranks=1, mpirun=None):
    log = os.path.join(workdir, f"log.{system}.{style}.{ranks}")
    env = dict(os.environ, OMP_NUM_THREADS=str(threads if style in THREADED else 1),
               LAMMPS_PLUGIN_PATH=plugin_dirs[style.startswith("plugin2")])
    # The plugin's former path (issue 44's A/B switch): it walks the list LAMMPS builds.
    env["DPDNL_PAIR_LIST"] = "lammps" if style.startswith("plugin-lammps") else "own"
    input_style = "plugin" if style.startswith("plugin") else style
    script, extra = INPUT[system]
    cmd = [lmp, "-in", script, "-var", "style", input_style, "-var", "steps", str(steps),
           "-log", log, "-screen", "none", "-nocite"]
    for k, v in extra.items():
        cmd += ["-var", k, v]
    if style in THREADED:
        cmd += ["-pk", "omp", str(threads)]
    if ranks > 1:
        cmd = [mpirun, "-np", str(ranks)] + cmd
    p = subprocess.run(cmd, cwd=HERE, env=env, capture_output=True, text=True)
    text = open(log).read() if os.path.exists(log) else ""
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{p.stdout[-1500:]}{p.stderr[-1500:]}")
    r = peers.parse_log(text)
    if r is None:
        sys.exit(f"{' '.join(cmd)}: no timed run in its log:\n{text[-1500:]}")
    return {"atom_steps": r["atom_steps"],
            # per CPU-second of the loop (LAMMPS's "% CPU use"): less sensitive to other load
            "atom_steps_cpu": r["atom_steps_cpu"],
            "pair_per_step": r["pair"], "neigh_per_step": r["neigh"], "builds": r["builds"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lmp", default=os.path.join(ROOT, ".venv-lammps", "bin", "lmp"))
    ap.add_argument("--plugin-dir", default=os.path.join(ROOT, "build"),
                    help="directory holding dpdnlplugin.so (LAMMPS_PLUGIN_PATH)")
    ap.add_argument("--plugin2-dir", help="a second plugin build to time beside the first "
                    "(style plugin2)")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--steps-ideal", type=int, default=500)
    ap.add_argument("--steps-gw", type=int, default=500)
    ap.add_argument("--styles", default="plugin,dpd,omp",
                    help="comma-separated: plugin, plugin-omp (the plugin on --threads threads), "
                    "plugin2, plugin2-omp, plugin-lammps, plugin-lammps-omp (the plugin walking "
                    "LAMMPS's list), dpd, omp")
    ap.add_argument("--systems", default="ideal,gw", help="comma-separated: ideal, gw, gw03")
    ap.add_argument("--threads", type=int, default=1,
                    help="OpenMP threads per rank of dpd/omp and plugin-omp")
    ap.add_argument("--ranks", default="1",
                    help="MPI rank counts, comma-separated (e.g. 1,2): every style runs at each "
                    "(one OpenMP thread per rank), through --mpirun")
    ap.add_argument("--mpirun", default=None,
                    help="the MPI launcher of --lmp's MPI (default: mpirun beside --lmp)")
    args = ap.parse_args()
    styles = args.styles.split(",")
    systems = args.systems.split(",")
    try:
        rank_counts = [int(r) for r in args.ranks.split(",")]
    except ValueError:
        sys.exit(f"--ranks {args.ranks}: expected rank counts such as 1,2")
    if any(r < 1 for r in rank_counts):
        sys.exit(f"--ranks {args.ranks}: rank counts must be at least 1")
    mpirun = args.mpirun or os.path.join(os.path.dirname(os.path.abspath(args.lmp)), "mpirun")
    if max(rank_counts) > 1 and not os.path.exists(mpirun):
        sys.exit(f"--ranks {args.ranks}: no MPI launcher at {mpirun} (give --mpirun)")
    configs = [(st, r) for r in rank_counts for st in styles]
    steps = {"ideal": args.steps_ideal, "gw": args.steps_gw, "gw03": args.steps_gw}
    results = {(s, c): [] for s in systems for c in configs}
    loads = []
    with tempfile.TemporaryDirectory(prefix="dpdnl-bench-") as tmp:
        for rep in range(args.reps):
            loads.append(os.getloadavg()[0])
            order = configs[rep % len(configs):] + configs[:rep % len(configs)]
            for system in systems:
                for (style, ranks) in order:
                    r = run(args.lmp, (args.plugin_dir, args.plugin2_dir), system, style,
                            steps[system], args.threads, tmp, ranks, mpirun)
                    results[(system, (style, ranks))].append(r)
                    print(f"# rep {rep} {system:5} {style:6} x{ranks} "
                          f"{r['atom_steps'] / 1e6:8.3f} "
                          f"M atom-steps/s ({r['atom_steps_cpu'] / 1e6:.3f} per CPU-s)  "
                          f"pair {r['pair_per_step'] * 1e3:8.3f} ms/step "
                          f"neigh {r['neigh_per_step'] * 1e3:8.3f} ms/step "
                          f"({r['builds']} LAMMPS builds)",
                          file=sys.stderr, flush=True)
        loads.append(os.getloadavg()[0])

    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), platform.processor())
    print(f"Machine: {cpu}, {os.cpu_count()} logical CPUs; {platform.platform()}")
    print(f"1-minute load average before each repetition and at the end: "
          f"{', '.join(f'{x:.1f}' for x in loads)}")
    print(f"{args.reps} interleaved repetitions; medians (min–max); one core per rank "
          f"(dpd/omp and plugin-omp: {args.threads} OpenMP thread(s)); MPI ranks: {args.ranks}\n")
    print("| system | pair style | ranks | M atom-steps/s (wall) | M atom-steps per CPU-s | "
          "Pair + Neigh ms/step (wall) | plugin ÷ this, same ranks (wall) | plugin ÷ this (per CPU-s) "
          f"| plugin on {args.threads} threads ÷ this (wall) | speed-up over 1 rank (wall) |")
    print("|---|---|---:|---|---|---|---|---|---|---|")

    def span(xs, fmt):
        return f"{statistics.median(xs):{fmt}} ({min(xs):{fmt}}–{max(xs):{fmt}})"

    def med(system, style, ranks, key):
        rs = results.get((system, (style, ranks)))
        return statistics.median(r[key] for r in rs) if rs else None

    for system in systems:
        for (style, ranks) in configs:
            rs = results[(system, (style, ranks))]
            wall = [r["atom_steps"] / 1e6 for r in rs]
            cpu = [r["atom_steps_cpu"] / 1e6 for r in rs]
            pair = [r["pair_per_step"] * 1e3 for r in rs]
            neigh = statistics.median(r["neigh_per_step"] * 1e3 for r in rs)
            ratios = []
            for base_style, key in (("plugin", "atom_steps"), ("plugin", "atom_steps_cpu"),
                                    ("plugin-omp", "atom_steps")):
                base = med(system, base_style, ranks, key)
                this = med(system, style, ranks, key)
                ratios.append(f"{base / this:.2f}" if base and style != base_style else "—")
            one = med(system, style, 1, "atom_steps")
            speedup = f"{med(system, style, ranks, 'atom_steps') / one:.2f}" \
                if one and ranks > 1 else "—"
            label = LABELS[style].replace("--threads", str(args.threads))
            print(f"| {SYSTEMS[system]} | {label} | {ranks} | {span(wall, '.3f')} | "
                  f"{span(cpu, '.3f')} | {statistics.median(pair):.2f} + {neigh:.2f} | {ratios[0]} | {ratios[1]} | "
                  f"{ratios[2]} | {speedup} |")


if __name__ == "__main__":
    main()
