#!/usr/bin/env python3
"""Write the data files of the unit-style golden cases (deterministic, stdlib only).

Run from anywhere: python3 tests/data/crosscheck/gen_units.py  (rewrites real3d.data,
metal3d.data, si3d.data and nano3d.data beside it)

Each is dpd3d.data (the 500-atom, 3-D state of the `lj` golden cases, kT = 1, masses 1 and 1.5)
carried into a LAMMPS unit style: lengths times L0, masses times M0 and velocities times
L0/tau0, with tau0 = L0 sqrt(M0 mvv2e / eps) the time unit of energy eps = k_B T (T = 300 K)
and mvv2e, boltz LAMMPS's constants of the style. The scripts (in.units_*) give parameters of
the same order, rounded, so the cases are fluids like the lj ones, not exact copies of them.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# LAMMPS's Update::set_units: (boltz, mvv2e).
STYLES = {
    "real": (0.0019872067, 48.88821291 * 48.88821291),
    "metal": (8.617343e-5, 1.0364269e-4),
    "si": (1.3806504e-23, 1.0),
    "nano": (0.013806504, 1.0),
}
T = 300.0
# Length per sigma: 6 Angstrom (real, metal), 1 micrometre (si), 1 nm (nano).
L0 = {"real": 6.0, "metal": 6.0, "si": 1e-6, "nano": 1.0}
# Mass per lj mass unit: g/mol (real, metal), kg (si: a cubic micrometre of water), ag (nano).
M0 = {"real": 18.0, "metal": 40.0, "si": 1e-15, "nano": 1e-4}


def scales(style):
    boltz, mvv2e = STYLES[style]
    eps = boltz * T
    tau = L0[style] * math.sqrt(M0[style] * mvv2e / eps)
    return L0[style], M0[style], L0[style] / tau, tau


def convert(style):
    length, mass, velocity, tau = scales(style)
    src = open(os.path.join(HERE, "dpd3d.data")).read().splitlines()
    out = [f"LAMMPS data file, units {style}: dpd3d.data with lengths x {length}, masses x "
           f"{mass}, velocities x L0/tau0 = {velocity!r} (tau0 = {tau!r}; gen_units.py)"]
    section = None
    for line in src[1:]:
        w = line.split()
        if not w:
            out.append(line)
            continue
        if w[0] in ("Masses", "Atoms", "Velocities"):
            section = w[0]
            out.append(line)
            continue
        if len(w) >= 4 and w[2] in ("xlo", "ylo", "zlo"):
            out.append(f"{float(w[0]) * length!r} {float(w[1]) * length!r} {w[2]} {w[3]}")
        elif section == "Masses":
            out.append(f"{w[0]} {float(w[1]) * mass!r}")
        elif section == "Atoms":
            x = [float(v) * length for v in w[2:5]]
            out.append(" ".join(w[:2] + [repr(v) for v in x] + w[5:]))
        elif section == "Velocities":
            v = [float(u) * velocity for u in w[1:4]]
            out.append(" ".join([w[0]] + [repr(u) for u in v]))
        else:
            out.append(line)
    with open(os.path.join(HERE, f"{style}3d.data"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    for s in STYLES:
        convert(s)
        length, mass, velocity, tau = scales(s)
        print(f"{s}: L0 = {length}, M0 = {mass}, tau0 = {tau!r}, eps = kT({T} K)")
