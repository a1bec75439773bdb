#!/usr/bin/env python3
"""Is the many-body repulsion of pair_style mdpd/nonlinear a conservative force?

docs/models.md §4.10, point 2 of "Where this departs from Warren (2003)". The B part of P-28,

    F_ij = B (rho_i + rho_j) (1 - r/rd) e_ij,   rho_i = sum_{j != i} w(r_ij),

is minus the gradient of a potential only if its Jacobian dF_k/dr_n is a symmetric matrix
(over all atoms and components). This script builds that Jacobian by central differences for
a few atoms in a small cluster, with two density weights:

- Warren's (Phys. Rev. E 68, 066702 (2003)): w = 15/(2 pi rd^3) (1 - r/rd)^2;
- the 3-D Lucy kernel of LAMMPS's mdpd/rhosum and of this project (P-27):
  w = 105/(16 pi rd^3) (1 + 3 r/rd) (1 - r/rd)^3.

It prints the largest asymmetry |J_ab - J_ba| against the largest |J_ab|: round-off for
Warren's weight, of the order of the entries themselves for Lucy's. For Warren's weight it also
checks that -grad U equals the force, U = sum_i pi rd^4 B rho_i^2 / 30, and that LAMMPS's pair
tally sum_{i<j} B rd (rho_i + rho_j) (1 - r/rd)^2 / 2 (the B term of P-29) is 2 U.

Standard library only; runs in a second:  python3 validation/mdpd/curl_check.py
"""
import math
import random

RD = 0.75
B = 1.0


def w_warren(r):
    return 15.0 / (2.0 * math.pi * RD**3) * (1.0 - r / RD) ** 2 if r < RD else 0.0


def w_lucy(r):
    if r >= RD:
        return 0.0
    u = r / RD
    return 105.0 / (16.0 * math.pi * RD**3) * (1.0 + 3.0 * u) * (1.0 - u) ** 3


def densities(x, w):
    n = len(x)
    return [sum(w(math.dist(x[i], x[j])) for j in range(n) if j != i) for i in range(n)]


def forces(x, w):
    """The B part of P-28 on every atom (3 components each)."""
    n = len(x)
    rho = densities(x, w)
    f = [[0.0, 0.0, 0.0] for _ in range(n)]
    for i in range(n):
        for j in range(n):
            if i == j:
                continue
            d = [x[i][c] - x[j][c] for c in range(3)]
            r = math.sqrt(sum(c * c for c in d))
            if r < RD:
                s = B * (rho[i] + rho[j]) * (1.0 - r / RD) / r
                for c in range(3):
                    f[i][c] += s * d[c]
    return f


def shifted(x, atom, comp, h):
    y = [p[:] for p in x]
    y[atom][comp] += h
    return y


def jacobian(x, w, h=1e-6):
    n = len(x)
    jac = {}
    for m in range(n):
        for b in range(3):
            fp = forces(shifted(x, m, b, h), w)
            fm = forces(shifted(x, m, b, -h), w)
            for k in range(n):
                for a in range(3):
                    jac[(k, a, m, b)] = (fp[k][a] - fm[k][a]) / (2.0 * h)
    return jac


def asymmetry(x, w):
    jac = jacobian(x, w)
    worst = max(abs(v - jac[(m, b, k, a)]) for (k, a, m, b), v in jac.items())
    scale = max(abs(v) for v in jac.values())
    return worst, scale


def warren_energy(x):
    return sum(math.pi * RD**4 * B * r * r / 30.0 for r in densities(x, w_warren))


def lammps_tally(x, w):
    n = len(x)
    rho = densities(x, w)
    e = 0.0
    for i in range(n):
        for j in range(i + 1, n):
            r = math.dist(x[i], x[j])
            if r < RD:
                e += 0.5 * B * RD * (rho[i] + rho[j]) * (1.0 - r / RD) ** 2
    return e


def main():
    rng = random.Random(1)
    x = [[rng.uniform(0.0, 0.9) for _ in range(3)] for _ in range(6)]
    for name, w in (("Warren", w_warren), ("Lucy", w_lucy)):
        worst, scale = asymmetry(x, w)
        print(f"{name:7s} weight: max |J_ab - J_ba| = {worst:.3e}, max |J_ab| = {scale:.3e}")
    f = forces(x, w_warren)
    h = 1e-6
    err = max(
        abs(-(warren_energy(shifted(x, m, b, h)) - warren_energy(shifted(x, m, b, -h))) / (2 * h)
            - f[m][b])
        for m in range(len(x))
        for b in range(3)
    )
    print(f"Warren  weight: max |-grad U - F| = {err:.3e}; "
          f"LAMMPS tally / U = {lammps_tally(x, w_warren) / warren_energy(x):.12f}")


if __name__ == "__main__":
    main()
