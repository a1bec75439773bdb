"""pair_style hybrid and hybrid/overlay."""
import math
import os

from harness import (DATA, PLUGIN_MODE, TOL, check, error_lines, read_dump, rel_diff_rows,
                     run_lammps, thermo_blocks)
from checks_bonds import chains_data


def dump_forces(path):
    """{id: [fx, fy, fz]} of the one frame of a `run 0` dump (id fx fy fz)."""
    frames = read_dump(path)
    cols, rows, _ = frames[min(frames)]
    k = cols.index("fx")
    return {i: r[k:k + 3] for i, r in rows.items()}


def force_diff(a, b):
    """max |a - b| / max |b| over atoms and components of two force dumps (inf if the atoms
    differ)."""
    if sorted(a) != sorted(b):
        return math.inf
    scale = max(abs(x) for v in b.values() for x in v) or 1.0
    return max(abs(x - y) for i in a for x, y in zip(a[i], b[i])) / scale


def hybrid(tmp):
    """pair_style hybrid and hybrid/overlay (issue 42):
    - hybrid/overlay: dpd/nonlinear beside another style (soft with A = 0) gives the numbers of
      dpd/nonlinear alone (the sub-style's list holds the same pairs);
    - hybrid: dpd/nonlinear on type pairs 1 1 and 2 2, soft on 1 2 (LAMMPS's skip list) gives,
      over 100 steps, the thermo of hybrid/overlay with dpd/nonlinear on every pair, 1 2 given
      zero coefficients, plus soft on 1 2;
    - as the top-level style a missing type pair is still refused, the error naming hybrid;
    - with the plugin (LAMMPS's DPD-BASIC): step-0 forces of dpd/nonlinear (friction none,
      weight 2, T ~ 0, moving atoms: conservative + dissipative) against LAMMPS's own pair dpd
      under the same hybrid, also with special_bonds lj on bead-spring chains."""
    print("pair_style hybrid/overlay and hybrid")
    d = os.path.join(tmp, "hybrid")
    os.makedirs(d, exist_ok=True)
    head = ("units lj\natom_style atomic\ncomm_modify vel yes\nread_data " +
            os.path.join(DATA, "dpd3d.data") + "\nmass * 1.0\n")
    tail = ("neighbor 1.0 bin\nneigh_modify delay 0 every 1 check yes\ntimestep 0.01\n"
            "fix 1 all nve\nthermo 50\nthermo_style custom step temp press pe pxy\n"
            "thermo_modify format float %.15g\nrun 100\n")
    style = "dpd/nonlinear 1.0 1.0 34387 friction dot noise twostep"
    pairs = {
        "alone": f"pair_style {style}\npair_coeff * * 5.0 4.5 1.0\n",
        "overlay": f"pair_style hybrid/overlay {style} soft 1.0\n"
                   "pair_coeff * * dpd/nonlinear 5.0 4.5 1.0\npair_coeff * * soft 0.0\n",
        "subset": f"pair_style hybrid {style} soft 1.0\npair_coeff 1 1 dpd/nonlinear 5.0 4.5 1.0\n"
                  "pair_coeff 2 2 dpd/nonlinear 6.0 3.0 0.5 0.9\npair_coeff 1 2 soft 2.0\n",
        "zero12": f"pair_style hybrid/overlay {style} soft 1.0\n"
                  "pair_coeff 1 1 dpd/nonlinear 5.0 4.5 1.0\n"
                  "pair_coeff 2 2 dpd/nonlinear 6.0 3.0 0.5 0.9\n"
                  "pair_coeff 1 2 dpd/nonlinear 0.0 0.0 0.0\npair_coeff 1 2 soft 2.0\n",
        "top": f"pair_style {style}\npair_coeff 1 1 5.0 4.5 1.0\npair_coeff 2 2 5.0 4.5 1.0\n",
    }
    got = {}
    for name, pair in pairs.items():
        path = os.path.join(d, f"in.{name}")
        with open(path, "w") as f:
            f.write(head + pair + tail)
        rc, log, out = run_lammps(d, name, path, cwd=d)
        got[name] = (rc, log, out)
    rc, log, out = got["top"]
    errs = error_lines(log + out)
    check(rc != 0 and any("types 1 2 are not set" in e and "as the top-level pair style" in e
                          and "hybrid" in e for e in errs),
          "the top-level dpd/nonlinear without pair_coeff 1 2 is refused, naming hybrid: "
          + (errs[0] if errs else out[-300:]))
    for a, b, what in [("alone", "overlay", "hybrid/overlay dpd/nonlinear + soft (A = 0) equals "
                        "dpd/nonlinear alone"),
                       ("zero12", "subset", "hybrid dpd/nonlinear on 1 1 and 2 2 + soft on 1 2 "
                        "equals hybrid/overlay with dpd/nonlinear 1 2 zero")]:
        if got[a][0] != 0 or got[b][0] != 0:
            check(False, f"{what}: runs: " + (got[a][2] + got[b][2])[-600:])
            continue
        rt, rv = rel_diff_rows(thermo_blocks(got[a][1])[-1][1], thermo_blocks(got[b][1])[-1][1])
        check(rt <= TOL, f"{what}: thermo {rt:.2e} over 100 steps")
    # Type pair 1 2 left to hybrid's mixing, which gives it to the style of 1 1 and 2 2: these
    # styles do not mix (as pair dpd).
    path = os.path.join(d, "in.mixed")
    with open(path, "w") as f:
        f.write(head + f"pair_style hybrid {style}\npair_coeff 1 1 dpd/nonlinear 5.0 4.5 1.0\n"
                "pair_coeff 2 2 dpd/nonlinear 5.0 4.5 1.0\nrun 0\n")
    rc, log, out = run_lammps(d, "mixed", path, cwd=d)
    errs = error_lines(log + out)
    check(rc != 0 and any("types 1 2 are not set (this style does not mix)" in e for e in errs),
          "hybrid's mixing of type pair 1 2 into dpd/nonlinear is refused: "
          + (errs[0] if errs else out[-300:]))
    hybrid_restart(d, head)
    hybrid_pair_modify_special(d)
    if PLUGIN_MODE:
        hybrid_vs_pair_dpd(d)


def hybrid_pair_modify_special(d):
    """pair_modify pair dpd/nonlinear special lj 0.5 0.1 0.9 under pair_style hybrid (LAMMPS
    sets the sub-style's factors only around its compute, after its set-up: dpdnl_pair_special)
    gives the step-0 forces of the same hybrid with special_bonds lj 0.5 0.1 0.9 (the other
    sub-style, zero, has no force), on bead-spring chains of two types; both LAMMPS versions."""
    chains_data(os.path.join(d, "chains.data"))
    forces = {}
    for name, special, modify in [
            ("own", "0.25 0.5 0.75", "pair_modify pair dpd/nonlinear special lj 0.5 0.1 0.9\n"),
            ("global", "0.5 0.1 0.9", ""),
            ("plain", "0.25 0.5 0.75", "")]:
        path = os.path.join(d, f"in.special_{name}")
        with open(path, "w") as f:
            f.write("units lj\natom_style bond\ncomm_modify vel yes\nread_data chains.data\n"
                    "mass * 1.0\nbond_style harmonic\nbond_coeff 1 50.0 0.9\n"
                    f"special_bonds lj {special}\n"
                    "velocity all create 1.0 4928 mom yes dist gaussian\n"
                    "pair_style hybrid dpd/nonlinear 1.0e-30 1.0 34387 zero 1.0\n"
                    "pair_coeff 1 1 dpd/nonlinear 25.0 4.5 0.0\n"
                    "pair_coeff 2 2 dpd/nonlinear 18.0 3.0 0.0\npair_coeff 1 2 zero\n" + modify +
                    f"dump 1 all custom 1 dump.special_{name} id fx fy fz\n"
                    "dump_modify 1 sort id format float %.17g\nrun 0\n")
        rc, log, out = run_lammps(d, f"special_{name}", path, cwd=d)
        check(rc == 0, f"hybrid with special factors ({name}) runs"
              + ("" if rc == 0 else ": " + out[-600:]))
        if rc == 0:
            forces[name] = dump_forces(os.path.join(d, f"dump.special_{name}"))
    if len(forces) == 3:
        same = force_diff(forces["own"], forces["global"])
        changed = force_diff(forces["plain"], forces["global"])
        check(same <= TOL and changed > 1e-2,
              f"pair_modify pair dpd/nonlinear special lj under hybrid equals special_bonds with "
              f"those factors: step-0 forces {same:.2e} (the factors change them by {changed:.2e})")


def hybrid_restart(d, head):
    """write_restart under pair_style hybrid with sdpd (1 1) and dpd/nonlinear (2 2): LAMMPS's
    hybrid stores its sub-styles' settings (not their coefficients); read_restart and the
    pair_coeff lines again continue the run as the uninterrupted one (thermo <= 1e-12)."""
    coeffs = ("pair_coeff 1 1 sdpd 3.0 10.0 1.0\npair_coeff 2 2 dpd/nonlinear 25.0 4.5 1.0\n"
              "pair_coeff 1 2 soft 3.0\n")
    run = ("neighbor 1.0 bin\nneigh_modify delay 0 every 1 check yes\ntimestep 0.01\n"
           "fix 1 all nve\nthermo 10\nthermo_style custom step temp press pe pxy\n"
           "thermo_modify format float %.15g\n")
    scripts = {
        "hyb_write": head + "pair_style hybrid dpd/nonlinear 1.0 1.0 5 friction dot sdpd 1.0 1.0 "
                            "7 soft 1.0\n" + coeffs + run + "run 20\nwrite_restart hyb.restart\n"
                            "run 20\n",
        "hyb_read": "read_restart hyb.restart\ncomm_modify vel yes\n" + coeffs + run + "run 20\n",
    }
    got = {}
    for name, text in scripts.items():
        path = os.path.join(d, "in." + name)
        with open(path, "w") as f:
            f.write(text)
        rc, log, out = run_lammps(d, name, path, cwd=d)
        check(rc == 0, f"pair_style hybrid {name} runs" + ("" if rc == 0 else ": " + out[-600:]))
        got[name] = thermo_blocks(log) if rc == 0 else None
    if got.get("hyb_write") and got.get("hyb_read"):
        rt, rv = rel_diff_rows(got["hyb_write"][-1][1], got["hyb_read"][-1][1])
        check(rt <= TOL, f"pair_style hybrid (sdpd + dpd/nonlinear + soft): the restart continues "
              f"the run: thermo {rt:.2e}")


def hybrid_vs_pair_dpd(d):
    """Step 0 under the same pair_style hybrid: dpd/nonlinear (friction none, default weight 2:
    w_D = (1 - r/rc)^2, as pair dpd) against LAMMPS's pair dpd on type pairs 1 1 and 2 2, soft
    on 1 2, at T = 1e-30 (noise ~1e-15 of the forces) with atoms moving (velocity create 1.0),
    so the force is conservative + dissipative; a run with gamma = 0 shows the dissipative part
    is not negligible. Then the same on bead-spring chains with special_bonds lj 0.25 0.5 0.75
    (bonded 1-3 and 1-4 neighbours of dpd's pairs scaled as pair dpd scales them), and with the
    sub-style's own factors (pair_modify pair NAME special lj 0.5 0.1 0.9)."""
    chains_data(os.path.join(d, "chains.data"))
    chains = ("atom_style bond\nread_data chains.data\n",
              "bond_style harmonic\nbond_coeff 1 50.0 0.9\nspecial_bonds lj 0.25 0.5 0.75\n")
    systems = {
        "fluid": ("atom_style atomic\nread_data " + os.path.join(DATA, "dpd3d.data") + "\n", "",
                  ""),
        "chains": chains + ("",),
        # The sub-style's own factors (pair_modify pair NAME special), set by hybrid around its
        # compute only: dpdnl_pair_special.
        "chains_pair_modify": chains + ("pair_modify pair {sub} special lj 0.5 0.1 0.9\n",),
    }
    styles = {
        "nl": ("dpd/nonlinear 1.0e-30 1.0 34387 friction none", "{a} {g} 0.0"),
        "dpd": ("dpd 1.0e-30 1.0 34387", "{a} {g}"),
        "dpd_g0": ("dpd 1.0e-30 1.0 34387", "{a} 0.0"),
    }
    for system, (read, extra, post) in systems.items():
        forces = {}
        for name, (style, cf) in styles.items():
            sub = style.split()[0]
            c11 = cf.format(a=25.0, g=4.5)
            c22 = cf.format(a=18.0, g=3.0) + " 0.9"
            script = os.path.join(d, f"in.h2h_{system}_{name}")
            with open(script, "w") as f:
                f.write(f"units lj\ncomm_modify vel yes\n{read}mass * 1.0\n{extra}"
                        "velocity all create 1.0 4928 mom yes dist gaussian\n"
                        f"pair_style hybrid {style} soft 1.0\n"
                        f"pair_coeff 1 1 {sub} {c11}\npair_coeff 2 2 {sub} {c22}\n"
                        "pair_coeff 1 2 soft 3.0\n" + post.format(sub=sub) +
                        f"dump 1 all custom 1 dump.h2h_{system}_{name} id fx fy fz\n"
                        "dump_modify 1 sort id format float %.17g\nrun 0\n")
            rc, log, out = run_lammps(d, f"h2h_{system}_{name}", script, cwd=d)
            check(rc == 0, f"hybrid {system} with {name} ({sub}) runs"
                  + ("" if rc == 0 else ": " + out[-600:]))
            if rc == 0:
                forces[name] = dump_forces(os.path.join(d, f"dump.h2h_{system}_{name}"))
        if len(forces) < 3:
            continue
        diff = force_diff(forces["nl"], forces["dpd"])
        dissipative = force_diff(forces["dpd_g0"], forces["dpd"])
        check(diff <= TOL and dissipative > 1e-2,
              f"hybrid ({system}): dpd/nonlinear vs pair dpd on 1 1 and 2 2 (soft on 1 2), step-0 "
              f"forces {diff:.2e} relative (the dissipative part is {dissipative:.2e} of them)")
