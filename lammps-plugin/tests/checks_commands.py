"""Restart, bad arguments, `clear`."""
import os

from harness import (DATA, INPUTS, PLUGIN_MODE, TOL, check, read_dump, rel_diff_dumps,
                     rel_diff_rows, run_lammps, thermo_blocks)


def restart(tmp):
    print("restart: run 50 + write_restart + run 50  vs  read_restart + run 50")
    wd = os.path.join(tmp, "restart")
    rfile = os.path.join(wd, "restart.dpd3d")
    data = os.path.join(DATA, "dpd3d.data")
    out = {}
    for np in [1, 2]:
        rc, logw, o = run_lammps(wd, f"write{np}", os.path.join(INPUTS, "restart_write.in"), np,
                                 True, {"data": data, "dump": os.path.join(wd, f"dw{np}"),
                                        "restart": rfile})
        check(rc == 0, f"restart_write np{np} runs" + ("" if rc == 0 else ": " + o[-2000:]))
        rc, logr, o = run_lammps(wd, f"read{np}", os.path.join(INPUTS, "restart_read.in"), np,
                                 True, {"dump": os.path.join(wd, f"dr{np}"), "restart": rfile})
        check(rc == 0, f"restart_read np{np} runs" + ("" if rc == 0 else ": " + o[-2000:]))
        if rc != 0:
            continue
        tw, tr = thermo_blocks(logw)[-1][1], thermo_blocks(logr)[-1][1]
        rt, _ = rel_diff_rows(tw, tr)
        rd = rel_diff_dumps(read_dump(os.path.join(wd, f"dw{np}")),
                            read_dump(os.path.join(wd, f"dr{np}")))
        out[np] = (rt, rd)
        check(tw[0][0] == 50 and tr[-1][0] == 100 and rt <= TOL and rd <= TOL,
              f"restart np{np}: continued run vs uninterrupted: thermo {rt:.2e}, dump {rd:.2e}")
    return out


ERROR_CASES = [
    # (label, commands after the common header, expected text in the ERROR line)
    ("no ghost velocities", "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 1 1 0\nrun 0",
     "comm_modify vel yes", False),
    ("too few pair_style args", "pair_style dpd/nonlinear 1.0 1.0", "pair_style dpd/nonlinear T rc seed", True),
    ("bad friction", "pair_style dpd/nonlinear 1.0 1.0 5 friction bogus", "friction 'bogus' must be none, cross or dot", True),
    ("bad noise", "pair_style dpd/nonlinear 1.0 1.0 5 noise twostage", "noise 'twostage' must be plain, corrected or twostep", True),
    ("bad weight", "pair_style dpd/nonlinear 1.0 1.0 5 weight -1", "weight exponent -1 must be > 0", True),
    ("unknown keyword", "pair_style dpd/nonlinear 1.0 1.0 5 frcition dot", "unknown pair_style dpd/nonlinear keyword 'frcition'", True),
    ("seed 0", "pair_style dpd/nonlinear 1.0 1.0 0", "seed = 0", True),
    ("negative T", "pair_style dpd/nonlinear -1.0 1.0 5", "T = -1 must be >= 0", True),
    ("zero rc", "pair_style dpd/nonlinear 1.0 0.0 5", "rc = 0 must be > 0", True),
    ("non-numeric T", "pair_style dpd/nonlinear hot 1.0 5", "expected a number for T, found 'hot'", True),
    ("negative gamma0", "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 25 -4.5 0", "gamma0 = -4.5 must be >= 0", True),
    ("negative gamma1", "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 25 4.5 -1", "gamma1 = -1 must be >= 0", True),
    ("pair_coeff arg count", "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 25 4.5", "pair_coeff I J a gamma0 gamma1 [rc]", True),
    ("missing pair", "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 25 4.5 0\npair_coeff 2 2 25 4.5 0\nrun 0",
     "types 1 2 are not set", True),
    ("nve/euler args", "fix 1 all nve/euler 1.0", "fix ID group-ID nve/euler", True),
    ("pex/push dp", "fix 1 all pex/push -0.1", "dp = -0.1 must be a finite number > 0", True),
    ("pex/push width", "fix 1 all pex/push 0.1 width 0", "width = 0 must be", True),
    ("pex/push every", "fix 1 all pex/push 0.1 every 0", "every = 0 must be in 1..=2147483647", True),
    ("pex/push keyword", "fix 1 all pex/push 0.1 slab 2", "unknown fix pex/push keyword 'slab'", True),
    ("pex/push wide", "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 1 1 0\nfix 1 all pex/push 0.1 width 3\nrun 0",
     "width 3 must be at most Lx/2 = 2.5", True),
]


def errors(tmp):
    print("bad arguments give LAMMPS ERROR lines")
    data = os.path.join(DATA, "dpd3d.data")
    for k, (label, cmds, want, vel) in enumerate(ERROR_CASES):
        head = "units lj\natom_style atomic\n" + ("comm_modify vel yes\n" if vel else "")
        head += f"read_data {data}\nmass * 1.0\n"
        wd = os.path.join(tmp, "errors")
        script = os.path.join(wd, f"case{k}.src")
        os.makedirs(wd, exist_ok=True)
        with open(script, "w") as f:
            f.write(head + cmds + "\n")
        rc, log, out = run_lammps(wd, f"case{k}", script)
        lines = [l for l in (out + log).splitlines() if l.startswith("ERROR")]
        ok = rc != 0 and any(want in l for l in lines)
        check(ok, f"{label}: {lines[0] if lines else '(no ERROR line) ' + out[-500:]}")
    # 2-D rejects pex/push.
    wd = os.path.join(tmp, "errors")
    script = os.path.join(wd, "pex2d.src")
    with open(script, "w") as f:
        f.write(f"units lj\ndimension 2\natom_style atomic\ncomm_modify vel yes\n"
                f"read_data {os.path.join(DATA, 'dpd2d.data')}\nmass * 1.0\n"
                "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 1 1 0\n"
                "fix 1 all pex/push 0.1\nrun 0\n")
    rc, log, out = run_lammps(wd, "pex2d", script)
    lines = [l for l in out.splitlines() if l.startswith("ERROR")]
    check(rc != 0 and any("it needs dimension 3" in l for l in lines),
          f"pex/push in 2-D: {lines[0] if lines else out[-300:]}")


def survives_clear(tmp):
    print("styles survive 'clear'")
    wd = os.path.join(tmp, "clear")
    os.makedirs(wd, exist_ok=True)
    data = os.path.join(DATA, "dpd3d.data")
    block = (f"units lj\natom_style atomic\ncomm_modify vel yes\nread_data {data}\nmass * 1.0\n"
             "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 5 4.5 0\n"
             "fix 1 all nve/euler\nfix 2 all pex/push 0.1\nrun 5\n")
    script = os.path.join(wd, "clear.src")
    with open(script, "w") as f:
        f.write(block + "clear\n" + block + "clear\n" + block)
    rc, log, out = run_lammps(wd, "clear", script)
    check(rc == 0 and len(thermo_blocks(log)) == 3,
          "three runs separated by 'clear'" + ("" if rc == 0 else ": " + out[-500:]))
    if PLUGIN_MODE:
        check(log.count("Restoring plugin: pair_style dpd/nonlinear (") == 2,
              "LAMMPS re-registers the plugin's styles after each 'clear'")
    else:
        check("WARNING: could not hook" not in out, "LAMMPS::create() interposition active")
