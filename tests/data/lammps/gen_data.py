#!/usr/bin/env python3
"""Write the small LAMMPS data files used by lammps-plugin/tests (deterministic, stdlib only).

Run from anywhere: python3 tests/data/lammps/gen_data.py  (rewrites the *.data files beside it)
Positions are uniform in the box, velocities uniform in [-1, 1) with the mean removed, so total
momentum is zero for equal masses (tests compare momentum change, not its value).
"""
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, title, lo, hi, n, ntypes, dim, seed, type_of):
    rng = random.Random(seed)
    atoms, vels = [], []
    for i in range(n):
        x = [rng.uniform(lo[d], hi[d]) for d in range(3)]
        v = [rng.uniform(-1.0, 1.0) for _ in range(3)]
        if dim == 2:
            x[2], v[2] = 0.0, 0.0
        atoms.append((i + 1, type_of(i), x))
        vels.append(v)
    mean = [sum(v[d] for v in vels) / n for d in range(3)]
    vels = [[v[d] - mean[d] for d in range(3)] for v in vels]
    with open(os.path.join(HERE, name), "w") as f:
        f.write(f"{title}\n\n{n} atoms\n{ntypes} atom types\n\n")
        for d, ax in enumerate("xyz"):
            f.write(f"{lo[d]:.17g} {hi[d]:.17g} {ax}lo {ax}hi\n")
        f.write("\nAtoms # atomic\n\n")
        for tag, t, x in atoms:
            f.write(f"{tag} {t} {x[0]:.17g} {x[1]:.17g} {x[2]:.17g}\n")
        f.write("\nVelocities\n\n")
        for (tag, _, _), v in zip(atoms, vels):
            f.write(f"{tag} {v[0]:.17g} {v[1]:.17g} {v[2]:.17g}\n")


# 3-D, density 3, two types (every third atom is type 2).
write("dpd3d.data", "dpdnl test: 3-D, 375 atoms, 2 types", [-2.5] * 3, [2.5] * 3, 375, 2, 3,
      11, lambda i: 2 if i % 3 == 0 else 1)
# 2-D, density 4 per unit area, two types.
write("dpd2d.data", "dpdnl test: 2-D, 400 atoms, 2 types", [-5.0, -5.0, -0.5], [5.0, 5.0, 0.5],
      400, 2, 2, 12, lambda i: 2 if i % 4 == 0 else 1)
# PeX box 2L x L x L (L = 4) centred on 0, density 3, one type.
write("pex3d.data", "dpdnl test: PeX box 8 x 4 x 4, 384 atoms", [-4.0, -2.0, -2.0],
      [4.0, 2.0, 2.0], 384, 1, 3, 13, lambda i: 1)
