#!/usr/bin/env python3
"""Build the seed corpora of the fuzz targets from the repository's own files.

Usage: fuzz/seed.py OUT_DIR [SCRIPT_BIN]   (run from the repository root)

Writes OUT_DIR/<target>/ (script, readers, grammar, restart) and OUT_DIR/cwd/, the data files
the script seeds read (read_data dpd3d.data, ...): run the script fuzzer from a copy of cwd/.
Scripts are made small for the fuzzer's caps (Options::max_steps/max_atoms in
fuzz_targets/script.rs): includes are inlined, every `create_atoms … random N` makes 150 atoms
and every `run N` runs 20 steps.

With SCRIPT_BIN (the built `script` fuzz target), the scripts fuzz/gen/*.in are run in
OUT_DIR/gen/ (the fuzz binary runs the files it is given once each) and the dumps, logs, data
and restart files they write become seeds of the readers and restart targets.
"""
import hashlib
import pathlib
import re
import shutil
import subprocess
import sys

root = pathlib.Path(".")
out = pathlib.Path(sys.argv[1])
for t in ["script", "readers", "grammar", "restart", "cwd"]:
    (out / t).mkdir(parents=True, exist_ok=True)


def put(target, data):
    if isinstance(data, str):
        data = data.encode()
    name = hashlib.sha1(data).hexdigest()[:16]
    (out / target / name).write_bytes(data)


def inline(path, depth=0):
    lines = []
    for line in path.read_text(errors="replace").splitlines():
        m = re.match(r"\s*include\s+(\S+)", line)
        if m and depth < 4:
            inc = path.parent / m.group(1)
            if inc.exists():
                lines.extend(inline(inc, depth + 1))
                continue
        lines.append(line)
    return lines


def shrink(lines):
    res = []
    for line in lines:
        line = re.sub(r"^(\s*create_atoms\s+\S+\s+random\s+)\S+", r"\g<1>150", line)
        line = re.sub(r"^(\s*run\s+)\S+", r"\g<1>20", line)
        line = re.sub(r"^(\s*read_data\s+)\S*/", r"\1", line)
        line = re.sub(r"^(\s*variable\s+data\s+index\s+)\S*/", r"\1", line)
        res.append(line)
    return "\n".join(res) + "\n"


scripts = [p for p in root.glob("**/*") if p.is_file() and "target" not in p.parts
           and ".git" not in p.parts and "fuzz" not in p.parts
           and (p.name.startswith("in.") or p.suffix == ".in")]
for p in sorted(scripts):
    put("script", shrink(inline(p)))

# Bad-input cases: each case's lines after the prelude of tests/bad_input.rs.
prelude = "units lj\natom_style atomic\ncomm_modify vel yes\nread_data dpd3d.data\nmass * 1.0\n"
case = None
cases = []
for line in (root / "tests/data/bad_input/cases.txt").read_text().splitlines():
    if line.startswith("== "):
        case = []
        cases.append(case)
    elif case is not None and not line.startswith(("expect:", "lammps:", "class:", "cause:", "cure:")) and line.strip():
        case.append(line)
for c in cases:
    put("script", shrink(prelude.splitlines() + c))
    # The style lines of each case for the grammar target (selector: family, 2 types).
    for i, line in enumerate(c):
        w = line.split()
        if not w:
            continue
        rest = "\n".join(l.split(None, 1)[1] if len(l.split()) > 1 else "" for l in c[i + 1:]
                         if l.startswith("pair_coeff"))
        if w[0] == "pair_style" and len(w) > 1:
            fam = 1 if w[1] == "sdpd" else 0
            put("grammar", bytes([fam | (1 << 2)]) + (" ".join(w[2:]) + "\n" + rest).encode())
        elif w[0] == "fix" and len(w) > 3:
            put("grammar", bytes([2]) + " ".join(w[3:]).encode())

# A few hand-written grammar seeds: every keyword of each family.
for sel, text in [
    (0x04, "1.0 1.0 5 friction dot noise twostep weight 0.5\n1 2 25.0 eta 1.0 sc 2.0\n"
           "* * 25.0 4.5 1.0 0.9\n"),
    (0x05, "1.0 1.0 7 kernel proposed 1.5\n* * 1.0 10.0 eta 1.0 sc 2.0 0.9\n1 1 1.0 10.0 1.0 0.8\n"),
    (0x02, "pex/push 0.1 width 0.5 every 2"),
    (0x22, "nve/euler"),
    (0x08, "1.0 1.0 5 friction cross noise corrected\n1*2 2* 25.0 4.5 1.0\n"),
]:
    put("grammar", bytes([sel]) + text.encode())

for p in sorted(root.glob("tests/data/**/*.data")):
    shutil.copy(p, out / "cwd" / p.name)
    put("readers", b"\x00" + p.read_bytes())
logs = [p for p in root.glob("tests/data/**/*") if p.is_file()
        and ("log" in p.name or p.suffix == ".lammps")]
for p in sorted(logs) + [root / "log.dpdnl"]:
    if p.exists():
        put("readers", b"\x01" + p.read_bytes()[:200000])

for p in sorted(root.glob("fuzz/gen/*.in")):
    put("script", p.read_text())
if len(sys.argv) > 2:
    gen = out / "gen"
    gen.mkdir(exist_ok=True)
    for p in (out / "cwd").iterdir():
        shutil.copy(p, gen / p.name)
    scripts = []
    for p in sorted(root.glob("fuzz/gen/*.in")):
        shutil.copy(p, gen / p.name)
        scripts.append(p.name)
    subprocess.run([str(pathlib.Path(sys.argv[2]).resolve())] + scripts, cwd=gen,
                   env={"RAYON_NUM_THREADS": "1"}, check=True, capture_output=True)
    for p in sorted(gen.iterdir()):
        if p.name.startswith("dump"):
            put("readers", b"\x02" + p.read_bytes())
        elif p.name.startswith("log."):
            put("readers", b"\x01" + p.read_bytes())
        elif p.name.startswith("w") and p.suffix == ".data":
            put("readers", b"\x00" + p.read_bytes())
        elif p.suffix == ".restart" and p.stat().st_size < 20000:
            put("restart", p.read_bytes())
