#!/usr/bin/env python3
"""Velocity-Verlet tables of the finite-step report, written from the sweep CSVs.

    validation/finite_step/vv_tables.py [RESULTS_DIR]      (default: results/ beside this file)

Reads vv_sweep_300tau.csv, vv_sweep_fine.csv (2-D ideal fluid), vv_nonlinear.csv (the non-linear
paper's 3-D fluid) and vv_weighting.csv (the weighting paper's Table 3 fluid) and writes
RESULTS_DIR/vv_tables.md; the README's tables are copies of it (validation/sync_tables.py).
Where a 2-D point was run twice the more precise run (smaller block error) is kept, as the Euler
plot does. The "1 %" table interpolates T/T0 linearly between neighbouring points of a density
and gives the first δt/δt_c where it reaches 1.01, and x = δt √(kT/m)/r_c there (kT = 0.5,
m = r_c = 1 in these runs).
"""
import csv
import math
import sys
from pathlib import Path

KT_2D = 0.5  # kT0 = σ²/2γ of the 2-D sweeps (γ = σ = 1)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def cell(t, e):
    return f"{float(t):.4f} ± {float(e):.4f}"


def ideal_2d(res):
    """(table lines, 1 % lines) for the 2-D ideal fluid."""
    best = {}  # (n, frac) -> row with the smallest error
    for name in ("vv_sweep_300tau.csv", "vv_sweep_fine.csv"):
        for r in rows(res / name):
            key = (int(r["n"]), float(r["dt_over_dtc"]))
            if key not in best or float(r["err"]) < float(best[key]["err"]):
                best[key] = r
    dens = sorted({n for n, _ in best})
    fracs = sorted({f for _, f in best})
    neigh = {n: next(r["neighbours"] for (m, _), r in best.items() if m == n) for n in dens}
    head = " | ".join(f"n = {n} ({round(float(neigh[n]))})" for n in dens)
    out = [f"| δt/δt_c | {head} | Euler, eq. 22 |", "|---" * (len(dens) + 2) + "|"]
    for f in fracs:
        cells = [cell(best[(n, f)]["T_over_T0"], best[(n, f)]["err"]) if (n, f) in best else "" for n in dens]
        eq22 = next(r["eq22"] for (_, g), r in best.items() if g == f)
        out.append(f"| {f:g} | {' | '.join(cells)} | {float(eq22):.4f} |")
    cross = ["| n | δt/δt_c at T/T0 = 1.01 | x = δt √(kT/m)/r_c there |", "|---|---|---|"]
    for n in dens:
        pts = sorted((f, float(r["T_over_T0"]), float(r["dt"])) for (m, f), r in best.items() if m == n)
        hit = None
        for (f0, t0, d0), (f1, t1, d1) in zip([(0.0, 1.0, 0.0)] + pts, pts):
            if t0 < 1.01 <= t1:
                w = (1.01 - t0) / (t1 - t0)
                hit = (f0 + w * (f1 - f0), (d0 + w * (d1 - d0)) * math.sqrt(KT_2D))
                break
        cross.append(f"| {n} | {hit[0]:.3f} | {hit[1]:.3f} |" if hit else f"| {n} | not reached | — |")
    return out, cross


def nonlinear_3d(res):
    data = rows(res / "vv_nonlinear.csv")
    dts = sorted({float(r["dt"]) for r in data})
    frac = {float(r["dt"]): float(r["dt_over_dtc"]) for r in data}
    label = {
        "ref": "Ref (`friction none`, plain noise)",
        "dot_plain": "Dot, plain noise",
        "dot_corrected": "Dot, corrected noise (eq. 32)",
        "twostep_dot": "Dot, two-step noise",
    }
    heads = [f"δt = {d:g} ({frac[d]:.3f} δt_c)" for d in dts]
    out = [f"| model | {' | '.join(heads)} |", "|---" * (len(dts) + 1) + "|"]
    models = list(dict.fromkeys(r["model"] for r in data))
    for m in models:
        by = {float(r["dt"]): r for r in data if r["model"] == m}
        cells = [cell(by[d]["T_over_T0"], by[d]["err"]) if d in by else "" for d in dts]
        out.append(f"| {label.get(m, m)} | {' | '.join(cells)} |")
    eq22 = {float(r["dt"]): float(r["eq22_euler"]) for r in data}
    out.append(f"| Euler, eq. 22 (for scale) | {' | '.join(f'{eq22[d]:.4f}' for d in dts)} |")
    return out


def weighting_2d(res):
    out = ["| δt | δt/δt_c | x = δt √(kT/m)/r_c | T/T0 | Euler, eq. 22 |", "|---|---|---|---|---|"]
    for r in rows(res / "vv_weighting.csv"):
        dt = float(r["dt"])  # kT = m = r_c = 1: x = δt
        out.append(
            f"| {dt:g} | {float(r['dt_over_dtc']):.3f} | {dt:g} | {cell(r['T_over_T0'], r['err'])} "
            f"| {float(r['eq22_euler']):.3f} |"
        )
    return out


def main():
    res = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent / "results"
    try:
        table, cross = ideal_2d(res)
        sections = [
            ("Velocity-Verlet: 2-D ideal fluid, T/T0", table),
            ("Velocity-Verlet: 2-D ideal fluid, where the heating reaches 1 %", cross),
            ("Velocity-Verlet: the non-linear paper's 3-D fluid, T/T0", nonlinear_3d(res)),
            ("Velocity-Verlet: the weighting paper's Table 3 fluid, T/T0", weighting_2d(res)),
        ]
    except (OSError, KeyError, ValueError) as e:
        print(f"vv_tables.py: {e}", file=sys.stderr)
        return 1
    text = "\n".join(f"## {h}\n\n" + "\n".join(t) + "\n" for h, t in sections)
    (res / "vv_tables.md").write_text(text)
    print(text, end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
