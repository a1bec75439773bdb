"""special_bonds lj factors on bead-spring chains."""
import math
import os
import random

from harness import PLUGIN_MODE, check, run_lammps, thermo_blocks


def chains_data(path, nchain=40, clen=8, box=6.0, seed=5):
    """Write a LAMMPS data file (atom_style bond) of `nchain` random-walk chains of `clen` beads,
    bond length 0.9, two alternating types, crossing the periodic boundaries."""
    rng = random.Random(seed)
    atoms, bonds, tag = [], [], 0
    for c in range(nchain):
        x = [rng.uniform(0, box) for _ in range(3)]
        for k in range(clen):
            tag += 1
            if k > 0:
                d = [rng.gauss(0, 1) for _ in range(3)]
                n = math.sqrt(sum(t * t for t in d))
                x = [x[i] + 0.9 * d[i] / n for i in range(3)]
                bonds.append((tag - 1, tag))
            img = [math.floor(x[i] / box) for i in range(3)]
            atoms.append((tag, c + 1, 1 + k % 2, [x[i] - img[i] * box for i in range(3)], img))
    with open(path, "w") as f:
        f.write(f"chains\n\n{len(atoms)} atoms\n2 atom types\n{len(bonds)} bonds\n1 bond types\n\n"
                f"0 {box} xlo xhi\n0 {box} ylo yhi\n0 {box} zlo zhi\n\nAtoms # bond\n\n")
        for t, m, ty, w, img in atoms:
            f.write(f"{t} {m} {ty} {w[0]:.10f} {w[1]:.10f} {w[2]:.10f} {img[0]} {img[1]} {img[2]}\n")
        f.write("\nBonds\n\n")
        for k, (i, j) in enumerate(bonds):
            f.write(f"{k + 1} 1 {i} {j}\n")


def special_bonds(tmp):
    """special_bonds lj factors scale a bonded neighbour's pair (issue 29): at rest and T ~ 0 only
    the conservative force acts, so pair dpd/nonlinear (friction none) gives LAMMPS's own pair
    dpd's energy and pressure at step 0 (needs DPD-BASIC: the plugin's LAMMPS), compute
    pair/local (single()) the same per-pair sums, and the factors change the energy."""
    print("special_bonds lj factors (bead-spring chains)")
    d = os.path.join(tmp, "special")
    os.makedirs(d, exist_ok=True)
    chains_data(os.path.join(d, "chains.data"))
    pairs = {
        "dpd": "pair_style dpd 1.0e-20 1.0 12345\npair_coeff * * 25.0 4.5\npair_coeff 1 2 18.0 3.0",
        "nl": "pair_style dpd/nonlinear 1.0e-20 1.0 12345\npair_coeff * * 25.0 4.5 0.0\n"
              "pair_coeff 1 2 18.0 3.0 0.0",
    }
    # compute reduce takes a local compute as it is in LAMMPS 2021 and with 'inputs local' since.
    local = " inputs local" if PLUGIN_MODE else ""
    for name, pair in pairs.items():
        with open(os.path.join(d, f"in.{name}"), "w") as f:
            f.write("units lj\natom_style bond\ncomm_modify vel yes\nread_data chains.data\n"
                    "mass * 1.0\nbond_style harmonic\nbond_coeff 1 50.0 0.9\n"
                    "special_bonds lj ${s1} ${s2} ${s3}\n" + pair + "\n"
                    "compute pl all pair/local eng force\n"
                    "compute sum all reduce sum c_pl[1] c_pl[2]" + local + "\n"
                    "thermo_style custom step pe evdwl press c_sum[1] c_sum[2]\n"
                    "thermo_modify format float %.15g\nrun 0\n")
    styles = ["nl", "dpd"] if PLUGIN_MODE else ["nl"]
    got = {}
    for factors in ["0.25 0.5 0.75", "1 1 1", "0 1 1"]:
        s1, s2, s3 = factors.split()
        for name in styles:
            rc, log, out = run_lammps(d, f"{name}_{s1}_{s2}_{s3}", os.path.join(d, f"in.{name}"),
                                      variables={"s1": s1, "s2": s2, "s3": s3}, cwd=d)
            blocks = thermo_blocks(log)
            if rc != 0 or not blocks:
                check(False, f"{name} with special_bonds lj {factors} runs: {out[-300:]}")
                continue
            got[(name, factors)] = blocks[0][1][0]
            if name == "nl":
                row = got[(name, factors)]
                check(abs(row[4] - row[2]) <= 1e-12 * abs(row[2]),
                      f"special_bonds lj {factors}: compute pair/local (single) energies sum to "
                      f"evdwl ({row[4]:.15g} vs {row[2]:.15g})")
        if ("nl", factors) in got and ("dpd", factors) in got:
            a, b = got[("nl", factors)], got[("dpd", factors)]
            check(abs(a[2] - b[2]) <= 1e-12 * abs(b[2]) and abs(a[3] - b[3]) <= 1e-9 * abs(b[3]),
                  f"special_bonds lj {factors}: evdwl {a[2]:.15g} vs pair dpd {b[2]:.15g}, "
                  f"press {a[3]:.12g} vs {b[3]:.12g}")
            # compute pair/local through single(): the conservative energy and force of every
            # pair, scaled by its factor, as pair dpd's single() gives them.
            check(all(abs(a[k] - b[k]) <= 1e-12 * abs(b[k]) for k in (4, 5)),
                  f"special_bonds lj {factors}: compute pair/local (single) sums eng "
                  f"{a[4]:.15g} vs {b[4]:.15g}, force {a[5]:.15g} vs {b[5]:.15g}")
    if ("nl", "0.25 0.5 0.75") in got and ("nl", "1 1 1") in got:
        check(got[("nl", "0.25 0.5 0.75")][2] < got[("nl", "1 1 1")][2],
              "the factors weaken the bonded neighbours' repulsion (evdwl "
              f"{got[('nl', '0.25 0.5 0.75')][2]:.6g} < {got[('nl', '1 1 1')][2]:.6g})")
