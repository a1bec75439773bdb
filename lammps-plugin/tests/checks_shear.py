"""Sheared boxes: flips of fix deform, and fix flip/momentum."""
import os
import re
import sys

from harness import (LAST_TOL, LAUNCHER, PLUGIN_MODE, ROOT, check, rel_diff_rows, run_lammps,
                     thermo_blocks)


def sheared_flip(tmp):
    """The golden cross-engine case tests/data/crosscheck/in.shear_flip_3d (fix deform every 2
    steps at erate 2 on a triclinic box of L_x = 5, flipping twice in 100 steps) on 1, 2 and 4
    ranks: the tilt follows fix deform (xy = 0.1 m, m the last even step, less whole L_x after a
    flip, |xy| <= L_x/2 but for the one step before a flip), and 2 and 4 ranks give the thermo
    of 1 rank. In plugin mode the 1-rank thermo is also compared with build/lmp_dpdnl (Debian's
    LAMMPS), which `dpdnl crosscheck` compares with the standalone engine (tests/crosscheck.rs).
    """
    print("sheared box with flips (in.shear_flip_3d) on 1, 2, 4 ranks")
    cases = os.path.join(ROOT, "tests", "data", "crosscheck")
    script = os.path.join(cases, "in.shear_flip_3d")
    runs = {}
    for np in (1, 2, 4):
        wd = os.path.join(tmp, "shear_flip", f"np{np}")
        rc, log, out = run_lammps(wd, "shear_flip", script, np, cwd=cases,
                                  variables={"engine": f"runtests_np{np}"})
        for f in os.listdir(cases):
            if f.startswith("dump.shear_flip_3d.runtests_"):
                os.remove(os.path.join(cases, f))
        check(rc == 0, f"shear_flip np{np} runs" + ("" if rc == 0 else ": " + out[-2000:]))
        if rc == 0:
            runs[np] = thermo_blocks(log)[-1]
    if 1 not in runs:
        return
    header, rows = runs[1]
    ixy = header.index("Xy")
    bad = []
    flips = 0
    for k, r in enumerate(rows):
        step, xy = int(r[0]), r[ixy]
        m = step - step % 2
        n = (0.1 * m - xy) / 5.0
        if abs(n - round(n)) > 1e-9 or abs(xy) > 2.5 + 0.2 + 1e-12:
            bad.append((step, xy))
        if k and abs(xy - rows[k - 1][ixy]) > 2.5:
            flips += 1
    check(not bad and flips == 2, f"shear_flip: tilt follows fix deform with 2 flips "
          f"(flips {flips}, off {bad[:3]})")
    for np in (2, 4):
        if np in runs:
            rt, rv = rel_diff_rows(rows, runs[np][1])
            check(rt <= LAST_TOL, f"shear_flip: np1 vs np{np}: thermo {rt:.2e} (per value {rv:.2e})")
    if PLUGIN_MODE and os.access(LAUNCHER, os.X_OK):
        wd = os.path.join(tmp, "shear_flip", "launcher")
        rc, log, out = run_lammps(wd, "shear_flip", script, 1, lmp=LAUNCHER, env={}, cwd=cases,
                                  variables={"engine": "runtests_launcher"})
        for f in os.listdir(cases):
            if f.startswith("dump.shear_flip_3d.runtests_"):
                os.remove(os.path.join(cases, f))
        if rc == 0:
            rt, rv = rel_diff_rows(rows, thermo_blocks(log)[-1][1])
            check(rt <= LAST_TOL, f"shear_flip: plugin vs build/lmp_dpdnl: thermo {rt:.2e}")
        else:
            check(False, "shear_flip build/lmp_dpdnl runs: " + out[-2000:])


FLIP_SCRIPT = """units           lj
dimension       2
atom_style      atomic
comm_modify     vel yes
read_data       {data}
change_box      all triclinic
mass            * 1.0
pair_style      dpd/nonlinear 1.0 1.0 34387 friction none
pair_coeff      * * 0.0 4.5 0.0
neighbor        1.0 bin
neigh_modify    delay 0 every 1 check yes
timestep        0.005
fix             1 all nve
fix             2 all enforce2d
fix             3 all deform 1 xy erate 3.0 remap v
{fix}
velocity        all ramp vx 0.0 30.0 y -5.0 5.0 sum yes units box
compute         tdef all temp/deform
thermo          100
thermo_style    custom step temp c_tdef pxy xy
thermo_modify   format float %20.15g
dump            1 all custom 1000 dump.fm id mass x y vx vy
dump_modify     1 sort id format float %20.15g
run             1000
"""


def profile_momentum(frame, t):
    """Sum of m (v_x - 3 y) over a dump frame (id mass x y vx vy) at time t, plus 3 t P_y: the
    momentum relative to the shear profile of FLIP_SCRIPT, which the drift of the atoms along y
    changes by -3 P_y per unit time (P_y, conserved, is not 0 in the data file)."""
    return sum(r[1] * (r[4] - 3.0 * r[3] + 3.0 * t * r[5]) for r in frame)


def dump_frames(path):
    """The frames of a dump of FLIP_SCRIPT: lists of rows of floats."""
    frames, rows = [], None
    with open(path) as f:
        for line in f:
            if line.startswith("ITEM: ATOMS"):
                rows = []
                frames.append(rows)
            elif line.startswith("ITEM:"):
                rows = None
            elif rows is not None:
                rows.append([float(w) for w in line.split()])
    return frames


def flip_momentum(tmp):
    """fix flip/momentum (issue 41) on the manual's 2-D Couette flow at rate 3 (skin 1.0, so
    that atoms are often outside the box at a flip), 1000 steps with 15 flips: with the fix, the momentum relative to the profile is conserved to round-off
    on 1, 2 and 4 ranks, every rank count gives the thermo of 1 rank, and the end-of-run line
    counts the atoms given the jump; without it, LAMMPS's fix deform leaks exactly the momentum
    that the end-of-run warning reports (the pair style adds fix flip/momentum mode check)."""
    print("fix flip/momentum: momentum through box flips on 1, 2, 4 ranks")
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    from flip_record import flip_records
    data = os.path.join(ROOT, "docs", "examples", "fluid2d.data")
    runs = {}
    for fix, nps in (("fix 4 all flip/momentum", (1, 2, 4)), ("", (1,))):
        for np in nps:
            wd = os.path.join(tmp, "flip_momentum", f"{'fix' if fix else 'plain'}{np}")
            os.makedirs(wd, exist_ok=True)
            script = os.path.join(wd, "in.fm")
            with open(script, "w") as f:
                f.write(FLIP_SCRIPT.format(data=data, fix=fix))
            rc, log, out = run_lammps(wd, "fm", script, np)
            check(rc == 0, f"flip/momentum {'fix' if fix else 'plain'} np{np} runs" +
                  ("" if rc == 0 else ": " + out[-2000:]))
            if rc != 0:
                continue
            frames = dump_frames(os.path.join(wd, "dump.fm"))
            p0, p1 = profile_momentum(frames[0], 0.0), profile_momentum(frames[-1], 5.0)
            first = (flip_records(log) or [{}])[0]
            crossed = first.get("atoms", 0)
            if fix:
                runs[np] = thermo_blocks(log)[-1][1]
                check(crossed >= 1 and "WARNING: fix deform" not in log,
                      f"flip/momentum np{np}: {crossed} atoms given the jump, no warning")
                check(abs(p1 - p0) < 1e-9,
                      f"flip/momentum np{np}: momentum relative to the profile kept "
                      f"({p0:.3e} -> {p1:.3e})")
            else:
                leak = first.get("momentum", float("nan"))
                check(crossed >= 3 and abs((p1 - p0) - leak) <= 1e-5 * abs(leak),
                      f"plain fix deform: {crossed} atoms leak {p1 - p0:.6g}, "
                      f"the warning says {leak}")
    if 1 in runs:
        for np in (2, 4):
            if np in runs:
                # The first 300 steps (4 flips): later the ranks' summation orders have grown
                # apart chaotically.
                early = lambda rows: [r for r in rows if r[0] <= 300]
                rt, rv = rel_diff_rows(early(runs[1]), early(runs[np]))
                check(rt <= LAST_TOL, f"flip/momentum: np1 vs np{np}: thermo {rt:.2e}")
