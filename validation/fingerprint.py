#!/usr/bin/env python3
"""Fingerprints of the code behind every published result (issue 41).

A *family* is a set of code paths that a group of published results depends on (periodic
NEMD, sheared Couette, bonded Couette, sDPD, the Euler integrator, the analyses, ...). Its
fingerprint is a short deterministic run of those paths, hashed at full precision: each of the
family's runs (validation/fingerprints/families.txt) is the very script its results come from,
shrunk by `-var`s to seconds, followed by a `run 0` that dumps every atom's position, velocity
and force with %.17g; the hash (SHA-256, first 16 hex digits) covers the thermo rows of every
run and that dump. The analysis family runs `dpdnl analyze` on committed inputs and hashes its
JSON and CSV outputs. A change of code that moves any bit of those paths changes the
fingerprint; the project's runs give the same bits on every x86-64 instruction set (baseline,
AVX2, AVX-512) and any thread count, and `check --isa` tests that the fingerprints do too.

Every published result (validation/fingerprints/results.txt: a path or glob, the families it
depends on, the fingerprint of each when it was made, and the one command that regenerates it)
carries its families' fingerprints. `check` recomputes the current fingerprints and fails,
naming each stale result and its command, when a result's recorded fingerprint is not the
current one, unless

- validation/fingerprints/exceptions.txt, a reviewed list, says why a change of fingerprint
  cannot move that family's results, backed by a measurement (FAMILY OLD NEW REASON), or
- validation/fingerprints/pending.txt lists the result as stale and waiting for regeneration
  (RESULT-GLOB REASON); such results are printed as STALE on every check and listed in
  validation/README.md, and the list must shrink, never hide: a pending entry whose result is
  current again fails the check too, so that it is removed.

Usage:
  validation/fingerprint.py compute [FAMILY ...]       print the current fingerprints
  validation/fingerprint.py check [--isa]              the CI check (--isa: also under
                                                        DPDNL_SIMD=baseline, avx2, avx512)
  validation/fingerprint.py record RESULT-GLOB ...     after regenerating those results
                                                        (results.txt entries, fnmatch): they
                                                        carry the current fingerprints
Options: --dpdnl BIN [target/release/dpdnl or $DPDNL], --lmp BIN [build/lmp_dpdnl or $LMP],
--root CHECKOUT (the scripts of another commit, to fingerprint that commit's binaries)
(families of LAMMPS runs are skipped with a note when it is missing, unless --require-lmp).
"""

import argparse
import concurrent.futures
import fnmatch
import glob
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Where the families' scripts are read (--root: another checkout, to fingerprint an older
# commit's code with the scripts it ran).
SCRIPTS_ROOT = ROOT
FP = os.path.join(ROOT, "validation", "fingerprints")


def read_table(name):
    """Rows of a whitespace-separated table file (comments and blank lines skipped); the last
    column of lines with more words than `ncols` keeps its spaces when `ncols` is given."""
    rows = []
    path = os.path.join(FP, name)
    with open(path) as f:
        for k, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            rows.append((k, s))
    return rows


def families():
    """family -> list of runs (engine, script, vars) in file order."""
    out = {}
    for k, s in read_table("families.txt"):
        w = s.split()
        if len(w) < 3 or w[1] not in ("dpdnl", "lmp", "analyze"):
            sys.exit(f"validation/fingerprints/families.txt:{k}: want FAMILY dpdnl|lmp|analyze "
                     f"SCRIPT [VAR=VALUE ...], got: {s}")
        out.setdefault(w[0], []).append((w[1], w[2], w[3:]))
    return out


def thermo_rows(log):
    """The rows of every thermo table of a LAMMPS or dpdnl log (the header line included)."""
    rows, inside = [], False
    for line in log.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            inside = True
            rows.append(" ".join(words))
        elif inside:
            if line.startswith("Loop time") or line.startswith("WARNING") or not words:
                inside = not line.startswith("Loop time")
                continue
            try:
                [float(x) for x in words]
            except ValueError:
                continue
            rows.append(" ".join(words))
    return rows


WRAPPER = """include         {script}
dump            dpdnl_fp all custom 1 dump.fp id type x y z vx vy vz fx fy fz
dump_modify     dpdnl_fp sort id format float %.17g
run             0
"""


def run_family(name, runs, exe, env):
    """The fingerprint of one family (None when its engine is missing), and a note."""
    h = hashlib.sha256()
    for engine, script, variables in runs:
        tmp = tempfile.mkdtemp(prefix=f"dpdnl-fp-{name.replace('/', '_')}-")
        try:
            if engine == "analyze":
                src = os.path.join(ROOT, script)
                # SCRIPT is a directory of inputs; VARS are `analyze` arguments, ';'-separated
                # commands, with {dir} the input directory and {out} an output prefix.
                # The inputs are copied and named relative to the run's folder: the outputs
                # name their inputs, and must not name the checkout's path.
                cmds = " ".join(variables).split(";")
                for f in os.listdir(src):
                    shutil.copy(os.path.join(src, f), tmp)
                for i, c in enumerate(cmds):
                    args = c.replace("{dir}", ".").replace("{out}", f"o{i}")
                    p = subprocess.run([exe["dpdnl"], "analyze"] + args.split() + ["--no-plot"],
                                       capture_output=True, text=True, env=env, cwd=tmp)
                    if p.returncode != 0:
                        raise RuntimeError(f"{name}: dpdnl analyze {args}: {p.stderr[-2000:]}")
                for f in sorted(os.listdir(tmp)):
                    if f.startswith("o") and f.endswith((".json", ".csv")):
                        h.update(f.encode())
                        h.update(open(os.path.join(tmp, f), "rb").read())
                continue
            # SCRIPT may be A+B+…: run in order in one folder (B reads what A wrote). Each
            # script's folder travels with it (data files, included scripts).
            for part in script.split("+"):
                page, _, block = part.partition("#")
                src = os.path.join(SCRIPTS_ROOT, page)
                if not os.path.exists(src):
                    return None, f"{page} is not in {SCRIPTS_ROOT}: skipped"
                if block:
                    # PAGE#NAME: the script a page of the manual writes with `cat > NAME <<'EOF'`.
                    text = open(src).read()
                    start = text.find(f"cat > {block} <<'EOF'\n")
                    if start < 0:
                        raise RuntimeError(f"{name}: {page} writes no {block} (cat > {block} <<'EOF')")
                    start = text.index("\n", start) + 1
                    with open(os.path.join(tmp, block), "w") as f:
                        f.write(text[start:text.index("\nEOF\n", start) + 1])
                    src = os.path.join(tmp, block)
                else:
                    for f in os.listdir(os.path.dirname(src)):
                        p = os.path.join(os.path.dirname(src), f)
                        if os.path.isfile(p) and not os.path.exists(os.path.join(tmp, f)):
                            shutil.copy(p, tmp)
                with open(os.path.join(tmp, "in.fingerprint"), "w") as f:
                    f.write(WRAPPER.format(script=os.path.basename(src)))
                argv = []
                for v in variables:
                    k, _, val = v.partition("=")
                    argv += ["-var", k, val]
                if engine == "dpdnl":
                    cmd = [exe["dpdnl"], "run", "in.fingerprint", "--log", "log.fp"] + argv
                else:
                    if not exe.get("lmp"):
                        return None, "no LAMMPS (build/lmp_dpdnl): skipped"
                    cmd = [exe["lmp"], "-in", "in.fingerprint", "-log", "log.fp", "-screen",
                           "none"] + argv
                p = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=tmp)
                logpath = os.path.join(tmp, "log.fp")
                if p.returncode != 0:
                    log = open(logpath).read() if os.path.exists(logpath) else ""
                    raise RuntimeError(f"{name}: {' '.join(cmd)} failed:\n"
                                       f"{(p.stdout + p.stderr + log)[-3000:]}")
                rows = thermo_rows(open(logpath).read())
                if not rows:
                    raise RuntimeError(f"{name}: no thermo rows in the log of {part}")
                h.update("\n".join(rows).encode())
                # The dump of the wrapper's `run 0`, every atom's x, v and f at %.17g.
                h.update(open(os.path.join(tmp, "dump.fp"), "rb").read())
                os.remove(os.path.join(tmp, "dump.fp"))
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return h.hexdigest()[:16], ""


def compute(names, exe, env=None):
    fams = families()
    out = {}
    for n in names or list(fams):
        if n not in fams:
            sys.exit(f"unknown family '{n}' (validation/fingerprints/families.txt)")
        fp, note = run_family(n, fams[n], exe, dict(os.environ, **(env or {})))
        out[n] = (fp, note)
    return out


def results():
    """(line, glob, {family: fingerprint}, command) of results.txt."""
    out = []
    for k, s in read_table("results.txt"):
        w = s.split(None, 2)
        if len(w) < 3:
            sys.exit(f"validation/fingerprints/results.txt:{k}: want GLOB FAMILY=FP[,FAMILY=FP...] "
                     f"COMMAND, got: {s}")
        fps = {}
        for item in w[1].split(","):
            f, _, v = item.partition("=")
            fps[f] = v
        out.append((k, w[0], fps, w[2]))
    return out


def exceptions():
    """{(family, old): (new, reason)} of the reviewed list."""
    out = {}
    for k, s in read_table("exceptions.txt"):
        w = s.split(None, 3)
        if len(w) < 4:
            sys.exit(f"validation/fingerprints/exceptions.txt:{k}: want FAMILY OLD NEW REASON")
        out[(w[0], w[1])] = (w[2], w[3])
    return out


def pending():
    """{glob: reason} of the results waiting for regeneration."""
    out = {}
    for k, s in read_table("pending.txt"):
        w = s.split(None, 1)
        if len(w) < 2:
            sys.exit(f"validation/fingerprints/pending.txt:{k}: want RESULT-GLOB REASON")
        out[w[0]] = w[1]
    return out


def current_by_exception(family, recorded, now, exc):
    """True when a chain of reviewed exceptions leads from the recorded fingerprint to now."""
    seen = set()
    fp = recorded
    while fp != now:
        if (family, fp) not in exc or fp in seen:
            return False
        seen.add(fp)
        fp = exc[(family, fp)][0]
    return True


def check(args, exe):
    now = compute(None, exe)
    for n, (fp, note) in now.items():
        print(f"fingerprint {n:24s} {fp or '-':16s} {note}")
    missing_lmp = {n for n, (fp, _) in now.items() if fp is None}
    if missing_lmp and args.require_lmp:
        sys.exit(f"FAIL: no LAMMPS for the families {sorted(missing_lmp)} (--require-lmp)")
    if args.isa:
        # The three instruction sets' runs are independent and wait more than they compute
        # (LAMMPS's MPI start-up, short runs): they go side by side, verdicts in this order.
        isas = ("baseline", "avx2", "avx512")
        with concurrent.futures.ThreadPoolExecutor(len(isas)) as pool:
            others = list(pool.map(lambda isa: compute(None, exe, {"DPDNL_SIMD": isa}), isas))
        for isa, other in zip(isas, others):
            bad = [n for n in now if other[n][0] != now[n][0]]
            if bad:
                sys.exit(f"FAIL: DPDNL_SIMD={isa} changes the fingerprints of {bad}: they must "
                         "be the same on every host")
            print(f"DPDNL_SIMD={isa}: the same fingerprints")
    exc, pend = exceptions(), pending()
    stale, stale_pending, fresh_pending, unknown = [], [], set(), []
    still_waiting = set()
    for k, pattern, fps, cmd in results():
        matched = glob.glob(os.path.join(ROOT, pattern))
        if not matched and not os.path.exists(os.path.join(ROOT, pattern.split("#")[0])):
            unknown.append(f"results.txt:{k}: '{pattern}' matches no file")
        bad = []
        for fam, rec in fps.items():
            if fam not in now:
                unknown.append(f"results.txt:{k}: unknown family '{fam}'")
                continue
            cur = now[fam][0]
            if cur is None:
                continue
            if rec != cur and not current_by_exception(fam, rec, cur, exc):
                bad.append(f"{fam} {rec} -> {cur}")
        waiting = [g for g in pend if fnmatch.fnmatch(pattern, g) or g == pattern]
        if bad and waiting:
            stale_pending.append((pattern, bad, cmd, pend[waiting[0]]))
            still_waiting.update(waiting)
        elif bad:
            stale.append((pattern, bad, cmd))
        elif waiting:
            fresh_pending.update(waiting)
    # A pending glob is done only when every result it covers is current (a regeneration in
    # parts makes some of them current first: `couette_*` covers `couette_*ext*`).
    fresh_pending -= still_waiting
    for p, bad, cmd, why in stale_pending:
        print(f"STALE (pending regeneration: {why}): {p} [{'; '.join(bad)}]\n    regenerate: {cmd}")
    ok = True
    if unknown:
        ok = False
        print("FAIL: " + "\n      ".join(unknown))
    if stale:
        ok = False
        print(f"FAIL: {len(stale)} published result(s) not made by the current code:")
        for p, bad, cmd in stale:
            print(f"  {p}: {'; '.join(bad)}\n    regenerate: {cmd}\n"
                  f"    (then: validation/fingerprint.py record '{p}')")
    if fresh_pending:
        ok = False
        print("FAIL: listed as pending in validation/fingerprints/pending.txt but current: "
              f"{sorted(fresh_pending)} (remove them from the list)")
    if not ok:
        sys.exit(1)
    print(f"fingerprints: every published result is the current code's"
          f" ({len(stale_pending)} listed as pending regeneration)")


def record(patterns, exe):
    """The results.txt entries named by `patterns` get the current fingerprint of each of their
    families: run it after regenerating exactly those results. A pattern that is an entry's glob
    names that entry only (recording `couette_*` must not also record `couette_*ext*`, which its
    glob happens to match); any other pattern names every entry whose glob it matches (fnmatch)."""
    now = compute(None, exe)
    path = os.path.join(FP, "results.txt")
    lines = open(path).read().splitlines(keepends=True)
    globs = {g for _, g, _, _ in results()}
    out, done = [], set()
    for line in lines:
        s = line.strip()
        if s and not s.startswith("#"):
            w = s.split(None, 2)
            hit = [p for p in patterns if w[0] == p or (p not in globs and fnmatch.fnmatch(w[0], p))]
            if hit:
                done.update(hit)
                items = []
                for item in w[1].split(","):
                    f, _, v = item.partition("=")
                    if f in now and now[f][0]:
                        v = now[f][0]
                    items.append(f"{f}={v}")
                line = f"{w[0]} {','.join(items)} {w[2]}\n"
                print(f"recorded {line.strip()}")
        out.append(line)
    missing = [p for p in patterns if p not in done]
    if missing:
        sys.exit(f"record: no results.txt entry matches {missing}")
    open(path, "w").write("".join(out))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("action", choices=["compute", "check", "record"])
    ap.add_argument("families", nargs="*")
    ap.add_argument("--dpdnl", default=os.environ.get("DPDNL") or os.path.join(
        os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target"), "release", "dpdnl"))
    ap.add_argument("--lmp", default=os.environ.get("LMP") or os.path.join(ROOT, "build",
                                                                            "lmp_dpdnl"))
    ap.add_argument("--isa", action="store_true")
    ap.add_argument("--root", help="read the families' scripts from this checkout (an older "
                    "commit's worktree, with --dpdnl/--lmp its binaries)")
    ap.add_argument("--require-lmp", action="store_true")
    args = ap.parse_args()
    if args.root:
        global SCRIPTS_ROOT
        SCRIPTS_ROOT = os.path.abspath(args.root)
    exe = {"dpdnl": os.path.abspath(args.dpdnl),
           "lmp": os.path.abspath(args.lmp) if os.access(args.lmp, os.X_OK) else None}
    if not os.access(exe["dpdnl"], os.X_OK):
        sys.exit(f"{exe['dpdnl']} not found: cargo build --release (or --dpdnl BIN)")
    try:
        if args.action == "compute":
            for n, (fp, note) in compute(args.families, exe).items():
                print(f"{n} {fp or '-'} {note}".rstrip())
        elif args.action == "check":
            check(args, exe)
        else:
            if not args.families:
                sys.exit("record: name the results.txt globs of the regenerated results")
            record(args.families, exe)
    except RuntimeError as e:
        sys.exit(f"FAIL: {e}")


if __name__ == "__main__":
    main()
