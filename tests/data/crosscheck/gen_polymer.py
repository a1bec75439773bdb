#!/usr/bin/env python3
"""Write the polymer-solution data files of the bonded golden cases (deterministic, stdlib only).

Run from anywhere: python3 tests/data/crosscheck/gen_polymer.py  (rewrites polymer*.data beside it)

A DPD solvent (type 1, molecule 0) with bead-spring chains (type 2, molecules 1..M): each chain
a random walk of fixed step b from a uniform start, so chains cross the periodic boundaries;
positions are written wrapped into the box with the image flags that unwrap every chain, so no
bond is longer than b. Angles join every three consecutive beads. Velocities are uniform in
[-1, 1) with the mean removed. atom_style angle columns: id mol type x y z ix iy iz.

polymer3d_wrapped.data is the same system as a structure generator writes it: wrapped
coordinates and no image flags (columns id mol type x y z, so every flag is 0), the chains
crossing the boundaries; LAMMPS warns "Inconsistent image flags" and bonds by the minimum image.
"""
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, title, lo, hi, dim, n_total, n_chains, chain_len, bond, seed, flags=True):
    rng = random.Random(seed)
    L = [hi[d] - lo[d] for d in range(3)]
    atoms = []  # (tag, mol, type, unwrapped x)
    bonds, angles = [], []
    tag = 0
    for c in range(n_chains):
        x = [rng.uniform(lo[d], hi[d]) for d in range(3)]
        if dim == 2:
            x[2] = 0.0
        first = tag + 1
        for k in range(chain_len):
            if k > 0:
                if dim == 3:
                    z = rng.uniform(-1.0, 1.0)
                    phi = rng.uniform(0.0, 2.0 * math.pi)
                    s = math.sqrt(1.0 - z * z)
                    step = [s * math.cos(phi), s * math.sin(phi), z]
                else:
                    phi = rng.uniform(0.0, 2.0 * math.pi)
                    step = [math.cos(phi), math.sin(phi), 0.0]
                x = [x[d] + bond * step[d] for d in range(3)]
            tag += 1
            atoms.append((tag, c + 1, 2, list(x)))
            if k > 0:
                bonds.append((1, tag - 1, tag))
            if k > 1:
                angles.append((1, tag - 2, tag - 1, tag))
        assert tag == first + chain_len - 1
    while tag < n_total:
        tag += 1
        x = [rng.uniform(lo[d], hi[d]) for d in range(3)]
        if dim == 2:
            x[2] = 0.0
        atoms.append((tag, 0, 1, x))
    vels = []
    for _ in atoms:
        v = [rng.uniform(-1.0, 1.0) for _ in range(3)]
        if dim == 2:
            v[2] = 0.0
        vels.append(v)
    mean = [sum(v[d] for v in vels) / len(vels) for d in range(3)]
    vels = [[v[d] - mean[d] for d in range(3)] for v in vels]
    with open(os.path.join(HERE, name), "w") as f:
        f.write(f"{title}\n\n{len(atoms)} atoms\n2 atom types\n{len(bonds)} bonds\n1 bond types\n")
        f.write(f"{len(angles)} angles\n1 angle types\n\n")
        for d, ax in enumerate("xyz"):
            f.write(f"{lo[d]:.17g} {hi[d]:.17g} {ax}lo {ax}hi\n")
        f.write("\nAtoms # angle\n\n")
        for t, mol, typ, x in atoms:
            im = [0, 0, 0]
            w = list(x)
            for d in range(dim):
                im[d] = math.floor((x[d] - lo[d]) / L[d])
                w[d] = x[d] - im[d] * L[d]
                if w[d] >= hi[d]:
                    w[d] = lo[d]
                    im[d] += 1
            if flags:
                f.write(f"{t} {mol} {typ} {w[0]:.17g} {w[1]:.17g} {w[2]:.17g} {im[0]} {im[1]} {im[2]}\n")
            else:
                f.write(f"{t} {mol} {typ} {w[0]:.17g} {w[1]:.17g} {w[2]:.17g}\n")
        f.write("\nVelocities\n\n")
        for (t, _, _, _), v in zip(atoms, vels):
            f.write(f"{t} {v[0]:.17g} {v[1]:.17g} {v[2]:.17g}\n")
        f.write("\nBonds\n\n")
        for k, (bt, a, b) in enumerate(bonds):
            f.write(f"{k + 1} {bt} {a} {b}\n")
        f.write("\nAngles\n\n")
        for k, (at, a, b, c) in enumerate(angles):
            f.write(f"{k + 1} {at} {a} {b} {c}\n")


# 3-D, 8^3 box at density 3: 1536 atoms, 24 chains of 10 beads (bond 0.9).
write("polymer3d.data", "dpdnl golden: 3-D polymer solution, 24 chains x 10 beads in solvent",
      [-4.0] * 3, [4.0] * 3, 3, 1536, 24, 10, 0.9, 21)
# 2-D, 10 x 10 box at density 4: 400 atoms, 8 chains of 8 beads.
write("polymer2d.data", "dpdnl golden: 2-D polymer solution, 8 chains x 8 beads in solvent",
      [-5.0, -5.0, -0.5], [5.0, 5.0, 0.5], 2, 400, 8, 8, 0.9, 22)
# The 3-D system again as a generator writes it: wrapped, no image flags.
write("polymer3d_wrapped.data",
      "dpdnl golden: 3-D polymer solution as a generator writes it (wrapped, no image flags)",
      [-4.0] * 3, [4.0] * 3, 3, 1536, 24, 10, 0.9, 21, flags=False)
