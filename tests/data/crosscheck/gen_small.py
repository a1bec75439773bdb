#!/usr/bin/env python3
"""Write the data files of the small-box golden cases (issue 42: boxes shorter than 2 rc,
where a pair meets several periodic images of its partner; deterministic, stdlib only).

Run from anywhere: python3 tests/data/crosscheck/gen_small.py  (rewrites small3d.data,
tiny3d.data and small2d.data beside it)

- small3d.data: 3-D box 6 x 6 x 1.5 (z shorter than 2 rc for rc = 1), 162 atoms (n = 3),
  types 1 and 2 (masses 1 and 1.5), kT = 1 Maxwell velocities with zero total momentum.
- tiny3d.data: 3-D box 1.5 x 1.5 x 1.5 (every axis short), 10 atoms of type 1.
- small2d.data: 2-D box 6 x 1.5 (y, the shear gradient, short), 27 atoms of type 1.
Positions keep 0.3 apart at least (a pair closer than that starts with a stiff kick).
"""
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))


def state(seed, n, lo, hi, dim, masses, ntypes):
    rng = random.Random(seed)
    xs = []
    while len(xs) < n:
        x = [rng.uniform(lo[k], hi[k]) if k < dim else 0.0 for k in range(3)]
        ok = True
        for y in xs:
            d2 = 0.0
            for k in range(dim):
                L = hi[k] - lo[k]
                d = x[k] - y[k]
                d -= L * round(d / L)
                d2 += d * d
            if d2 < 0.09:
                ok = False
                break
        if ok:
            xs.append(x)
    types = [1 + (i % ntypes) for i in range(n)]
    vs = []
    for t in types:
        s = math.sqrt(1.0 / masses[t - 1])
        vs.append([rng.gauss(0.0, s) if k < dim else 0.0 for k in range(3)])
    ptot = [sum(masses[t - 1] * v[k] for t, v in zip(types, vs)) for k in range(3)]
    mtot = sum(masses[t - 1] for t in types)
    vs = [[v[k] - ptot[k] / mtot for k in range(3)] for v in vs]
    return xs, types, vs


def write(name, seed, n, lo, hi, dim, masses, ntypes):
    xs, types, vs = state(seed, n, lo, hi, dim, masses, ntypes)
    f = lambda v: "%.16e" % v
    lines = [f"LAMMPS data file: gen_small.py ({name})", "", f"{n} atoms", f"{ntypes} atom types", ""]
    for k, ax in enumerate("xyz"):
        lines.append(f"{f(lo[k])} {f(hi[k])} {ax}lo {ax}hi")
    lines += ["", "Masses", ""]
    lines += [f"{t + 1} {f(masses[t])}" for t in range(ntypes)]
    lines += ["", "Atoms # atomic", ""]
    lines += [f"{i + 1} {t} {f(x[0])} {f(x[1])} {f(x[2])} 0 0 0" for i, (x, t) in enumerate(zip(xs, types))]
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {f(v[0])} {f(v[1])} {f(v[2])}" for i, v in enumerate(vs)]
    with open(os.path.join(HERE, name), "w") as out:
        out.write("\n".join(lines) + "\n")


write("small3d.data", 42, 162, [0.0, 0.0, 0.0], [6.0, 6.0, 1.5], 3, [1.0, 1.5], 2)
write("tiny3d.data", 7, 10, [0.0, 0.0, 0.0], [1.5, 1.5, 1.5], 3, [1.0], 1)
write("small2d.data", 11, 27, [0.0, 0.0, -0.5], [6.0, 1.5, 0.5], 2, [1.0], 1)
