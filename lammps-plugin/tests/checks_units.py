"""Unit styles: T is a temperature in `units real`, every unit style sets up."""
import math
import os
import re

from harness import check, run_lammps, thermo_blocks


def blocked_mean(xs):
    """Mean and standard error by Flyvbjerg-Petersen blocking: the error of the block means,
    halving the series until 32 blocks are left, the largest over the levels (a correlated
    series' error grows with the block length up to a plateau; taking the largest never
    underestimates it by stopping early)."""
    mean = sum(xs) / len(xs)
    worst, x = 0.0, list(xs)
    while len(x) >= 32:
        n = len(x)
        var = sum((v - mean) ** 2 for v in x) / (n - 1)
        worst = max(worst, math.sqrt(var / n))
        x = [0.5 * (x[2 * k] + x[2 * k + 1]) for k in range(n // 2)]
    return mean, worst


def units(tmp):
    """units real (issue 42): T of pair_style dpd/nonlinear is a temperature, as for pair dpd
    (kT = k_B T), and the two-step kick and the correction take LAMMPS's ftm2v through the C ABI.
    The fluid of tests/thermostat.rs carried into units real (T0 = 300 K, m = 18 g/mol, r_c = 10
    A, gamma0 = 5 eps tau/r_c^2, gamma1 = tau^2/r_c^4, dt = 0.005 tau with eps = 10 k_B T0 and
    tau = r_c sqrt(m mvv2e/eps)), 1029 atoms, 1000 steps then 10000 sampled every 10: <T> within
    4 sigma + 1.5 % of 300 K (the tolerance of tests/thermostat.rs, for its reasons) for friction
    none, and dot with noise corrected and twostep; dot with plain noise is > 5 % hot. Then every
    other LAMMPS unit style sets up (run 0) and logs kT = boltz T with LAMMPS's boltz."""
    print("units: <T> in units real for every noise scheme; every unit style sets up")
    d = os.path.join(tmp, "units")
    os.makedirs(d, exist_ok=True)
    boltz, mvv2e = 0.0019872067, 48.88821291 * 48.88821291    # the test's own numbers
    t0, m, rc = 300.0, 18.0, 10.0
    eps = 10.0 * boltz * t0
    tau = rc * math.sqrt(m * mvv2e / eps)
    gamma0, g1, dt, box = 5.0 * eps * tau / rc ** 2, tau ** 2 / rc ** 4, 0.005 * tau, 7 * rc
    for friction, noise in [("none", "plain"), ("dot", "corrected"), ("dot", "twostep"),
                            ("dot", "plain")]:
        gamma1 = 0.0 if friction == "none" else g1
        name = f"real_{friction}_{noise}"
        path = os.path.join(d, "in." + name)
        with open(path, "w") as f:
            f.write(f"units real\natom_style atomic\ncomm_modify vel yes\n"
                    f"region box block 0 {box} 0 {box} 0 {box}\ncreate_box 1 box\n"
                    f"create_atoms 1 random 1029 777 box\nmass 1 {m}\n"
                    f"velocity all create {t0} 4928 mom yes\n"
                    f"pair_style dpd/nonlinear {t0} {rc} 34387 friction {friction} noise {noise}\n"
                    f"pair_coeff 1 1 0.0 {gamma0!r} {gamma1!r}\nneighbor 3.0 bin\n"
                    f"neigh_modify delay 0 every 1 check yes\ntimestep {dt!r}\nfix 1 all nve\n"
                    f"thermo 1000\nrun 1000\nthermo 10\nthermo_style custom step temp\n"
                    f"thermo_modify format float %.12g\nrun 10000\n")
        rc_, log, out = run_lammps(d, name, path, cwd=d)
        if rc_ != 0:
            check(False, f"units real {friction}/{noise} runs: " + out[-500:])
            continue
        header, rows = thermo_blocks(log)[-1]
        mean, err = blocked_mean([r[header.index("Temp")] for r in rows[1:]])
        dev = mean / t0 - 1.0
        if (friction, noise) == ("dot", "plain"):
            check(mean - t0 > 0.05 * t0 + 4 * err,
                  f"units real dot/plain runs hot, as in lj: <T> = {mean:.2f} +- {err:.2f} K "
                  f"({100 * dev:+.1f} %)")
        else:
            check(abs(mean - t0) < 4 * err + 0.015 * t0,
                  f"units real {friction}/{noise}: <T> = {mean:.2f} +- {err:.2f} K "
                  f"({100 * dev:+.2f} %, T0 = 300 K)")
    # Every other unit style: LAMMPS's constants reach the set-up (run 0 of a box of 27 atoms;
    # the numbers need not be physical).
    for style in ["lj", "metal", "si", "cgs", "electron", "micro", "nano"]:
        path = os.path.join(d, "in." + style)
        with open(path, "w") as f:
            f.write(f"units {style}\natom_style atomic\ncomm_modify vel yes\n"
                    "region box block 0 3 0 3 0 3\ncreate_box 1 box\n"
                    "create_atoms 1 random 27 5 box\nmass 1 1.0\n"
                    "pair_style dpd/nonlinear 2.0 1.0 5 friction dot noise twostep\n"
                    "pair_coeff 1 1 1.0 1.0 1.0\nrun 0\n")
        rc_, log, out = run_lammps(d, style, path, cwd=d)
        note = re.search(r"units (\S+): T = 2 is a temperature .*kT = boltz T = (\S+) energy "
                         r"units \(boltz = (\S+),", log)
        if style == "lj":
            check(rc_ == 0 and note is None, "units lj sets up, kT = T (no note)")
            continue
        ok = (rc_ == 0 and note is not None and note.group(1) == style
              and float(note.group(2)) == 2.0 * float(note.group(3)))
        check(ok, f"units {style} sets up with LAMMPS's boltz: " +
              (note.group(0) if note else out[-300:]))
