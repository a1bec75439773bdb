#!/usr/bin/env python3
"""Writes a polymer-solution data file (atom_style bond) for the examples in this folder.

    python3 gen_solution.py [--L 8] [--density 3] [--chains 16] [--beads 10] [--bond 0.7]
                            [--seed 1] [--temp T] > solution.data

Chains (type 2, molecule ids 1..chains) are random walks of step --bond from a uniformly random
first bead; they cross the periodic boundaries (coordinates wrapped, image flags written).
Solvent beads (type 1, molecule 0) fill the box at uniformly random positions up to the number
density. The generator is SplitMix64, fixed and documented, so a seed gives the same file on
every machine. DPD's soft repulsion lets the engines start from these overlapping positions.
With --temp T the file has a Velocities section: Maxwell-Boltzmann at kT = T (unit masses, Box-
Muller on the same generator), total momentum removed, so both engines start from the same
state (`velocity create` draws different numbers in LAMMPS and in the standalone engine).
"""
import argparse
import math


class SplitMix64:
    def __init__(self, seed):
        self.state = (0x9E3779B97F4A7C15 ^ seed) & (2**64 - 1)

    def uniform(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & (2**64 - 1)
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & (2**64 - 1)
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & (2**64 - 1)
        return ((z ^ (z >> 31)) >> 11) / 2**53


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--L", type=float, default=8.0, help="cubic box edge")
    p.add_argument("--density", type=float, default=3.0, help="beads per unit volume")
    p.add_argument("--chains", type=int, default=16)
    p.add_argument("--beads", type=int, default=10, help="beads per chain")
    p.add_argument("--bond", type=float, default=0.7, help="random-walk step")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--temp", type=float, default=None, help="write Velocities at this kT")
    a = p.parse_args()
    rng = SplitMix64(a.seed)
    L = a.L
    total = round(a.density * L**3)
    nsolvent = total - a.chains * a.beads
    if nsolvent < 0:
        p.error("more chain beads than the density allows")
    atoms, bonds = [], []
    for c in range(a.chains):
        x = [rng.uniform() * L for _ in range(3)]
        for k in range(a.beads):
            if k:
                u = 2 * rng.uniform() - 1
                phi = 2 * math.pi * rng.uniform()
                s = math.sqrt(1 - u * u)
                x = [x[0] + a.bond * s * math.cos(phi), x[1] + a.bond * s * math.sin(phi),
                     x[2] + a.bond * u]
                bonds.append((len(atoms), len(atoms) + 1))
            atoms.append((c + 1, 2, x))
    for _ in range(nsolvent):
        atoms.append((0, 1, [rng.uniform() * L for _ in range(3)]))
    out = [f"polymer solution: {a.chains} chains of {a.beads} beads, {nsolvent} solvent beads, "
           f"L = {L:g}, seed {a.seed} (gen_solution.py)", "",
           f"{len(atoms)} atoms", "2 atom types", f"{len(bonds)} bonds", "1 bond types", "",
           f"0 {L:g} xlo xhi", f"0 {L:g} ylo yhi", f"0 {L:g} zlo zhi", "",
           "Masses", "", "1 1.0", "2 1.0", "", "Atoms # bond", ""]
    for i, (mol, typ, x) in enumerate(atoms):
        im = [math.floor(c / L) for c in x]
        w = [c - L * k for c, k in zip(x, im)]
        out.append(f"{i + 1} {mol} {typ} {w[0]:.10f} {w[1]:.10f} {w[2]:.10f} {im[0]} {im[1]} {im[2]}")
    if a.temp is not None:
        vel = []
        for _ in atoms:
            g = []
            for _ in range(3):
                u1, u2 = 1.0 - rng.uniform(), rng.uniform()
                g.append(math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2))
            vel.append([math.sqrt(a.temp) * x for x in g])
        mean = [sum(v[k] for v in vel) / len(vel) for k in range(3)]
        out += ["", "Velocities", ""]
        out += [f"{i + 1} {v[0] - mean[0]:.17g} {v[1] - mean[1]:.17g} {v[2] - mean[2]:.17g}"
                for i, v in enumerate(vel)]
    out += ["", "Bonds", ""]
    out += [f"{k + 1} 1 {i} {j}" for k, (i, j) in enumerate(bonds)]
    print("\n".join(out))


if __name__ == "__main__":
    main()
