"""The styles the LAMMPS side registers are the Rust library's list (issue 55): the names that
`info styles pair|fix|compute` shows with the dpdnl styles loaded and not without them are
exactly the pair styles (dpdnl_pair_style_*) and the fixes and computes (dpdnl_lammps_style*)
that the C ABI lists, read from build/cargo/release/libdpdnl_capi.so."""
import ctypes
import os
import re

from harness import ENV, LAUNCHER, LMP, PLUGIN_MODE, ROOT, check, run_lammps

CAPI_SO = os.path.join(ROOT, "build", "cargo", "release", "libdpdnl_capi.so")
DEBIAN_LMP = "/usr/bin/lmp"


class LammpsStyle(ctypes.Structure):
    _fields_ = [("command", ctypes.c_char_p), ("name", ctypes.c_char_p),
                ("info", ctypes.c_char_p)]


def rust_styles():
    """{(kind, name)} the C ABI lists."""
    lib = ctypes.CDLL(CAPI_SO)
    lib.dpdnl_pair_style_name.restype = ctypes.c_char_p
    lib.dpdnl_pair_style_name.argtypes = [ctypes.c_int32]
    lib.dpdnl_lammps_style.restype = LammpsStyle
    lib.dpdnl_lammps_style.argtypes = [ctypes.c_int32]
    out = {("pair", lib.dpdnl_pair_style_name(k).decode())
           for k in range(lib.dpdnl_pair_style_count())}
    for k in range(lib.dpdnl_lammps_style_count()):
        s = lib.dpdnl_lammps_style(k)
        out.add((s.command.decode(), s.name.decode()))
    return out


def info_styles(text):
    """{(kind, name)} of the `info styles pair|fix|compute` sections of a LAMMPS output."""
    out, kind = set(), None
    for line in text.splitlines():
        m = re.match(r"(Pair|Fix|Compute) styles:", line)
        if m:
            kind = m.group(1).lower()
        elif kind and re.match(r"[A-Z][a-z]* styles:|Info-Info", line):
            kind = None
        elif kind:
            out.update((kind, w) for w in line.split())
    return out


def registry(tmp):
    print("the styles registered are the Rust library's list (info styles, with and without)")
    if not os.path.exists(CAPI_SO):
        check(False, f"{CAPI_SO} not found (cargo build --release -p dpdnl-capi)")
        return
    wd = os.path.join(tmp, "registry")
    os.makedirs(wd, exist_ok=True)
    script = os.path.join(wd, "info.in")
    with open(script, "w") as f:
        f.write("info styles pair\ninfo styles fix\ninfo styles compute\n")
    if PLUGIN_MODE:
        plain = (LMP, dict(ENV, LAMMPS_PLUGIN_PATH=""))
    else:
        plain = (DEBIAN_LMP, {})
    got = {}
    for label, exe, env in [("with", LMP if PLUGIN_MODE else LAUNCHER, ENV),
                            ("without", plain[0], plain[1])]:
        rc, log, out = run_lammps(wd, label, script, lmp=exe, env=env)
        got[label] = info_styles(out)
        check(rc == 0 and got[label], f"info styles {label} the dpdnl styles" +
              ("" if rc == 0 else ": " + out[-500:]))
    want = rust_styles()
    added = got["with"] - got["without"]
    check(added == want and len(want) >= 7,
          f"registered: {len(added)} styles, the C ABI lists {len(want)}"
          + ("" if added == want else f" (only registered: {sorted(added - want)}, "
             f"only listed: {sorted(want - added)})"))
