#!/usr/bin/env python3
"""Write the start of examples/droplet: a spherical drop of liquid 1 (type 1) of radius R in
liquid 2 (type 2), both at number density RHO, in an L x L x L box centred on 0, atoms at
random positions and Gaussian velocities of kT = 1 (mass 1) with zero total momentum (a fixed
seed: the same file every time; the engines' `velocity create` generators differ, so the start
comes from the file and both engines begin from the same state).

usage: gen_drop.py [OUT] [L] [R] [RHO] [SEED] [drop|layer]
(defaults: drop.data 10 2.5 6.5 2024 drop). `layer`: instead of the drop, a flat layer of
liquid 1, |z| < R, across the box (two flat interfaces: the interfacial tension).
The drop's (layer's) atoms are type 1, the others type 2; one mass (1) for both, as pair_style
mdpd/nonlinear needs.
"""
import math
import random
import sys


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "drop.data"
    box = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    radius = float(sys.argv[3]) if len(sys.argv) > 3 else 2.5
    rho = float(sys.argv[4]) if len(sys.argv) > 4 else 6.5
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 2024
    shape = sys.argv[6] if len(sys.argv) > 6 else "drop"
    if shape not in ("drop", "layer"):
        sys.exit(f"gen_drop.py: shape '{shape}' must be drop or layer")
    if not (0 < 2 * radius < box and rho > 0):
        sys.exit(f"gen_drop.py: need 0 < 2R < L and RHO > 0 (R = {radius}, L = {box}, RHO = {rho})")
    rng = random.Random(seed)
    n = int(round(rho * box**3))
    half = box / 2
    atoms = []
    for k in range(n):
        x = [rng.uniform(-half, half) for _ in range(3)]
        if shape == "drop":
            inside = math.sqrt(sum(c * c for c in x)) < radius
        else:
            inside = abs(x[2]) < radius
        atoms.append((k + 1, 1 if inside else 2, x))
    with open(out, "w") as f:
        f.write(f"{shape} of radius {radius} in a {box} box, number density {rho}, seed {seed} (gen_drop.py)\n\n")
        f.write(f"{n} atoms\n2 atom types\n\n")
        for ax in "xyz":
            f.write(f"{-half} {half} {ax}lo {ax}hi\n")
        f.write("\nMasses\n\n1 1.0\n2 1.0\n\nAtoms # atomic\n\n")
        for i, t, x in atoms:
            f.write(f"{i} {t} {x[0]:.12f} {x[1]:.12f} {x[2]:.12f}\n")
        vel = [[rng.gauss(0.0, 1.0) for _ in range(3)] for _ in atoms]
        mean = [sum(v[k] for v in vel) / n for k in range(3)]
        f.write("\nVelocities\n\n")
        for (i, _, _), v in zip(atoms, vel):
            f.write(f"{i} {v[0] - mean[0]:.12f} {v[1] - mean[1]:.12f} {v[2] - mean[2]:.12f}\n")
    ndrop = sum(1 for a in atoms if a[1] == 1)
    print(f"{out}: {n} atoms, {ndrop} in the drop (R = {radius}), box {box}")


if __name__ == "__main__":
    main()
