#!/usr/bin/env python3
"""Every style of build/dpdnlplugin.so beside its LAMMPS peer in the same LAMMPS binary (issue 58,
item 2): one rank, one thread, whole run. Stdlib only.

    python3 lammps-plugin/bench/peers.py [--lmp .venv-lammps/bin/lmp] [--reps 3]
        [--cases ideal,gw,mdpd,sdpd,ext,tstat,ext-tstat,schemes] [--steps-scale 1.0]

Cases (inputs beside this script; each says what it is and where its physics comes from):

- ideal, gw: in.ideal / in.gw, `dpd/nonlinear` (friction none) against `pair dpd`; gw runs at
  LAMMPS's default skin 0.3 (in.gw's own default is 1.0: here -var skin 0.3).
- mdpd: in.mdpd, `mdpd/nonlinear` (friction none, and friction cross with gamma1 = 1) against
  `hybrid/overlay mdpd/rhosum mdpd`.
- sdpd: in.sdpd, `sdpd` (the migration recipe) against `sdpd/taitwater/isothermal`.
- ext: in.ext, `dpd/nonlinear/ext` against `dpd/ext`.
- tstat, ext-tstat: in.cgwater, `dpd/nonlinear/tstat` against `dpd/tstat` and
  `dpd/nonlinear/ext/tstat` against `dpd/ext/tstat`, each overlaid on the example's table; the
  table alone is timed too (its Pair time is subtracted in the "thermostat alone" ratio).
- schemes, schemes-gw: `dpd/nonlinear`'s non-linear friction and noise schemes (gamma1 = 1) on
  in.ideal / in.gw, against friction none.

Runs are interleaved: every repetition runs every run of every case, the order rotated by one
each repetition. Each run: OMP_NUM_THREADS=1, one rank, the loop time of the second `run` (after
a warm-up `run`). M atom-steps/s = N × steps / loop time; "per CPU-s" divides by LAMMPS's
"% CPU use" (less sensitive to other load); Pair, Neigh and Comm come from LAMMPS's timing
breakdown (ms per step); list builds = "Neighbor list builds" of the timed run (the plugin's
styles build their own pair list: their Neigh is LAMMPS's list, which they do not walk).
Output: a Markdown table on stdout (medians over repetitions, min–max of the rate), one line per
run on stderr as it goes.
"""
import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))

SCHEMES = [("cross", "plain"), ("dot", "plain"), ("cross", "corrected"), ("dot", "corrected"),
           ("cross", "twostep"), ("dot", "twostep")]


def scheme_runs(system_vars):
    runs = []
    for friction, noise in SCHEMES:
        runs.append((f"{friction}/{noise}", f"dpd/nonlinear friction {friction} noise {noise}",
                     dict(system_vars, style="scheme", friction=friction, noise=noise, g1="1.0"),
                     "scheme"))
    return runs


# name -> (description, input, steps, runs, base): runs are (key, label, vars, role), role one of
# ours (ratio against the case's peer), peer, scheme (ratio against `base`, a (case, key) of
# friction none), shared (the table alone: its Pair is subtracted from ours and the peer).
CASES = {
    "ideal": ("ideal DPD, n = 16, N = 20000, kT = 0.1, γ = 5, rc = 1, δt = 1e-3, skin 0.3 "
              "(in.ideal sets LAMMPS's default)", "in.ideal", 500,
              [("ours", "dpd/nonlinear (friction none)", {"style": "plugin"}, "ours"),
               ("peer", "dpd", {"style": "dpd"}, "peer")], None),
    "gw": ("Groot–Warren, n = 3, a = 25, γ = 4.5, kT = 1, N = 20000, δt = 0.04, skin 0.3 "
           "(LAMMPS's default)", "in.gw", 500,
           [("ours", "dpd/nonlinear (friction none)", {"style": "plugin", "skin": "0.3"}, "ours"),
            ("peer", "dpd", {"style": "dpd", "skin": "0.3"}, "peer")], None),
    "mdpd": ("many-body DPD liquid, ρ = 6.05, A = −40, B = 25, γ = 18, rc = 1, rd = 0.75, kT = 1, "
             "N = 20000, δt = 0.01, fix mvv/dpd, skin 0.3 (the example's line)", "in.mdpd", 200,
             [("ours", "mdpd/nonlinear (friction none)", {"side": "ours"}, "ours"),
              ("cross", "mdpd/nonlinear friction cross, gamma1 = 1",
               {"side": "ours", "friction": "cross", "g1": "1.0"}, "ours"),
              ("peer", "hybrid/overlay mdpd/rhosum mdpd", {"side": "peer"}, "peer")], None),
    "sdpd": ("sDPD water, units micro, 300 K, ρ0 = 1, c0 = 10, μ = 1, Lucy kernel h = 4a, "
             "8000 atoms (sc lattice), δt = 5e-4, skin 0.1 h (the example's line)", "in.sdpd", 40,
             [("ours", "sdpd (kernel lucy, density summed, fix nve)", {"side": "ours"}, "ours"),
              ("peer", "sdpd/taitwater/isothermal (density integrated, fix sph)",
               {"side": "peer"}, "peer")], None),
    "ext": ("dpd/ext example grown to N = 20000, ρ = 1.6, two types (m = 1, 2), kT = 1, "
            "rc 1.2–1.22, δt = 0.01, skin 0.3 (LAMMPS's default)", "in.ext", 500,
            [("ours", "dpd/nonlinear/ext", {"style": "dpd/nonlinear/ext"}, "ours"),
             ("peer", "dpd/ext", {"style": "dpd/ext"}, "peer")], None),
    "tstat": ("CG SPC/E water (dpd/ext/tstat example) × 8 = 17440 beads, units real, 300 K, "
              "table rc 9 Å + thermostat γ = 20, rc 10 Å, δt = 1 fs, skin 2 Å (LAMMPS's default)",
              "in.cgwater", 50,
              [("ours", "table + dpd/nonlinear/tstat",
                {"style": "dpd/nonlinear/tstat", "form": "tstat"}, "ours"),
               ("peer", "table + dpd/tstat", {"style": "dpd/tstat", "form": "tstat"}, "peer"),
               ("table", "table alone", {"form": "none"}, "shared")], None),
    "ext-tstat": ("as tstat, γ∥ = 20, γ⊥ = 10, ws = ws⊥ = 0.5 (the example's)", "in.cgwater", 50,
                  [("ours", "table + dpd/nonlinear/ext/tstat",
                    {"style": "dpd/nonlinear/ext/tstat", "form": "ext"}, "ours"),
                   ("peer", "table + dpd/ext/tstat", {"style": "dpd/ext/tstat", "form": "ext"},
                    "peer")], None),
    "schemes": ("non-linear schemes on the ideal system, gamma1 = 1", "in.ideal", 500,
                scheme_runs({}), ("ideal", "ours")),
    "schemes-gw": ("non-linear schemes on Groot–Warren (skin 0.3), gamma1 = 1", "in.gw", 500,
                   scheme_runs({"skin": "0.3"}), ("gw", "ours")),
}


def parse_log(text):
    """The timed (last) run of a LAMMPS log: loop time, steps, atoms, % CPU, breakdown."""
    loops = re.findall(r"Loop time of ([\d.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms",
                       text)
    if not loops:
        return None
    loop, _, nsteps, natoms = loops[-1]
    loop, nsteps, natoms = float(loop), int(nsteps), int(natoms)
    cpu = re.findall(r"([\d.]+)% CPU use with", text)
    out = {"loop": loop, "steps": nsteps, "atoms": natoms,
           "cpu_frac": float(cpu[-1]) / 100.0 if cpu else 1.0}
    for part in ("Pair", "Neigh", "Comm", "Modify", "Other"):
        rows = re.findall(rf"^{part}\s+\|\s+([\d.eE+-]+)", text, re.M)
        out[part.lower()] = float(rows[-1]) / nsteps if rows else 0.0
    builds = re.findall(r"^Neighbor list builds = (\d+)", text, re.M)
    out["builds"] = int(builds[-1]) if builds else 0
    work = natoms * nsteps
    out["atom_steps"] = work / loop
    out["atom_steps_cpu"] = work / (loop * out["cpu_frac"])
    return out


def run_one(lmp, plugin_dir, case, key, steps, workdir, perf_stat=False):
    _, script, _, runs, _ = CASES[case]
    _, _, vars_, _ = next(r for r in runs if r[0] == key)
    log = os.path.join(workdir, f"log.{case}.{key.replace('/', '-')}")
    env = dict(os.environ, OMP_NUM_THREADS="1", LAMMPS_PLUGIN_PATH=plugin_dir)
    cmd = [lmp, "-in", script, "-var", "steps", str(steps), "-log", log, "-screen", "none",
           "-nocite"]
    for k, v in vars_.items():
        cmd += ["-var", k, v]
    p = subprocess.run(cmd, cwd=HERE, env=env, capture_output=True, text=True)
    text = open(log).read() if os.path.exists(log) else ""
    r = parse_log(text)
    if p.returncode != 0 or r is None:
        sys.exit(f"{' '.join(cmd)} failed:\n{text[-1500:]}{p.stdout[-1500:]}{p.stderr[-1500:]}")
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lmp", default=os.path.join(ROOT, ".venv-lammps", "bin", "lmp"))
    ap.add_argument("--plugin-dir", default=os.path.join(ROOT, "build"),
                    help="directory holding dpdnlplugin.so (LAMMPS_PLUGIN_PATH)")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--cases", default="ideal,gw,mdpd,sdpd,ext,tstat,ext-tstat,schemes",
                    help=f"comma-separated, of: {', '.join(CASES)}")
    ap.add_argument("--steps-scale", type=float, default=1.0,
                    help="multiply every case's timed steps (e.g. 0.25 for a quick look)")
    ap.add_argument("--json", help="also write the raw per-run results to this file")
    ap.add_argument("--report-from", help="no runs: rebuild the table from the '# rep' lines "
                    "of an earlier invocation's stderr (or from its --json file)")
    args = ap.parse_args()
    cases = args.cases.split(",")
    bad = [c for c in cases if c not in CASES]
    if bad:
        sys.exit(f"--cases: unknown {', '.join(bad)} (known: {', '.join(CASES)})")
    if not os.path.exists(os.path.join(args.plugin_dir, "dpdnlplugin.so")):
        sys.exit(f"no dpdnlplugin.so in {args.plugin_dir}: bash lammps-plugin/build-plugin.sh")
    # A scheme case ratios against its base run: time that run too.
    for c in list(cases):
        base = CASES[c][4]
        if base and base[0] not in cases:
            cases.insert(0, base[0])
    configs = [(c, r[0]) for c in cases for r in CASES[c][3]]
    if "ext-tstat" in cases and "tstat" not in cases:
        configs.append(("tstat", "table"))
    results = {cfg: [] for cfg in configs}
    loads = []
    if args.report_from:
        loads = read_back(args.report_from, results)
        report(args, cases, configs, results, loads)
        return
    with tempfile.TemporaryDirectory(prefix="dpdnl-peers-") as tmp:
        for rep in range(args.reps):
            loads.append(os.getloadavg()[0])
            k = rep % len(configs)
            for (case, key) in configs[k:] + configs[:k]:
                steps = max(1, round(CASES[case][2] * args.steps_scale))
                r = run_one(args.lmp, args.plugin_dir, case, key, steps, tmp)
                results[(case, key)].append(r)
                print(f"# rep {rep} {case:10} {key:16} {r['atom_steps'] / 1e6:8.3f} M atom-steps/s "
                      f"({r['atom_steps_cpu'] / 1e6:.3f} per CPU-s, CPU {r['cpu_frac']:.0%}) "
                      f"pair {r['pair'] * 1e3:.3f} neigh {r['neigh'] * 1e3:.3f} "
                      f"comm {r['comm'] * 1e3:.3f} ms/step, {r['builds']} builds",
                      file=sys.stderr, flush=True)
        loads.append(os.getloadavg()[0])
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"loads": loads, "runs": [{"case": c, "key": k, "results": rs}
                                               for (c, k), rs in results.items()]}, fh, indent=1)
    report(args, cases, configs, results, loads)


REP_LINE = re.compile(r"^# rep (\d+) (\S+)\s+(\S+)\s+([\d.]+) M atom-steps/s \(([\d.]+) per CPU-s, "
                      r"CPU (\d+)%\) pair ([\d.]+) neigh ([\d.]+) comm ([\d.]+) ms/step, (\d+) builds")


def read_back(path, results):
    """Fill `results` from an earlier invocation (its --json file, or its stderr's '# rep' lines,
    whose rates are rounded to 1e-3 M atom-steps/s). Returns the load averages (none from stderr)."""
    text = open(path).read()
    if text.lstrip().startswith("{"):
        data = json.loads(text)
        for run in data["runs"]:
            if (run["case"], run["key"]) in results:
                results[(run["case"], run["key"])] = run["results"]
        return data["loads"]
    for line in text.splitlines():
        m = REP_LINE.match(line)
        if not m or (m.group(2), m.group(3)) not in results:
            continue
        wall, per_cpu = float(m.group(4)) * 1e6, float(m.group(5)) * 1e6
        results[(m.group(2), m.group(3))].append(
            {"atom_steps": wall, "atom_steps_cpu": per_cpu, "cpu_frac": wall / per_cpu,
             "pair": float(m.group(7)) / 1e3, "neigh": float(m.group(8)) / 1e3,
             "comm": float(m.group(9)) / 1e3, "builds": int(m.group(10))})
    return []


def med(results, cfg, key):
    rs = results.get(cfg)
    return statistics.median(r[key] for r in rs) if rs else None


def report(args, cases, configs, results, loads):
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), platform.processor())
    print(f"Machine: {cpu}, {os.cpu_count()} logical CPUs; {platform.platform()}")
    print("1-minute load average before each repetition and at the end: "
          f"{', '.join(f'{x:.1f}' for x in loads)}")
    print(f"{args.reps} interleaved repetitions, medians (min–max); one rank, "
          f"OMP_NUM_THREADS=1; steps × {args.steps_scale}\n")
    for case in cases:
        print(f"- **{case}**: {CASES[case][0]} (`{CASES[case][1]}`)")
    print()
    print("| case | pair style | M atom-steps/s (wall) | M atom-steps per CPU-s | "
          "Pair + Neigh + Comm ms/step (wall) | the same × % CPU (CPU ms/step) | list builds | "
          "÷ peer (wall) | ÷ peer (per CPU-s) |")
    print("|---|---|---|---|---|---|---:|---:|---:|")

    def span(xs):
        return f"{statistics.median(xs):.3f} ({min(xs):.3f}–{max(xs):.3f})"

    notes = []
    for case in cases:
        _, _, _, runs, base = CASES[case]
        peer = (case, "peer") if any(r[3] == "peer" for r in runs) else base
        for key, label, _, role in runs:
            rs = results[(case, key)]
            wall = [r["atom_steps"] / 1e6 for r in rs]
            per_cpu = [r["atom_steps_cpu"] / 1e6 for r in rs]
            pnc = " + ".join(f"{med(results, (case, key), p) * 1e3:.2f}"
                             for p in ("pair", "neigh", "comm"))
            pnc_cpu = " + ".join(
                f"{statistics.median(r[p] * r['cpu_frac'] for r in rs) * 1e3:.2f}"
                for p in ("pair", "neigh", "comm"))
            builds = statistics.median(r["builds"] for r in rs)
            if role in ("ours", "scheme") and peer in results:
                ratios = [f"{med(results, (case, key), q) / med(results, peer, q):.2f}"
                          for q in ("atom_steps", "atom_steps_cpu")]
            else:
                ratios = ["—", "—"]
            print(f"| {case} | {label} | {span(wall)} | {span(per_cpu)} | {pnc} | {pnc_cpu} | "
                  f"{builds:.0f} | {ratios[0]} | {ratios[1]} |")
        table = ("tstat", "table")
        if case in ("tstat", "ext-tstat") and table in results:
            def pair_cpu(cfg):
                return statistics.median(r["pair"] * r["cpu_frac"] for r in results[cfg])
            t = pair_cpu(table)
            ours, theirs = pair_cpu((case, "ours")), pair_cpu((case, "peer"))
            notes.append(f"- {case}: the thermostat alone (Pair × % CPU less the table's "
                         f"{t * 1e3:.2f} CPU ms/step): ours {(ours - t) * 1e3:.2f}, peer "
                         f"{(theirs - t) * 1e3:.2f} CPU ms/step, peer ÷ ours "
                         f"{(theirs - t) / (ours - t):.2f}")
    if notes:
        print("\n" + "\n".join(notes))


if __name__ == "__main__":
    main()
