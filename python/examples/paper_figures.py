"""A short run that makes two of the papers' figures: the speed distribution against
Maxwell-Boltzmann (non-linear paper, eq. 53) and the Einstein-Helfand running viscosity against
the kinetic theory of the design (weighting-function paper, eq. 59).

    python paper_figures.py [OUTDIR] [--steps N]

Designs (gamma, s) for a target viscosity and Schmidt number, runs the ideal fluid (a = 0) in
the standalone engine with a speed histogram and the off-diagonal pressure written by the
engine's own fix ave/histo and fix ave/time, analyses both files, prints the numbers and, if
matplotlib is installed, writes OUTDIR/paper_figures.png. Every number comes from the Rust crate;
this script only passes them around. A run of 20 000 steps (the default, 500 atoms) takes about
10 s on two cores; the papers' error bars need 10-100 times more. The kinetic theory is the
ideal-fluid approximation (Marsh, Backx and Ernst), not an exact result: the measured viscosity
need not equal it.
"""

import argparse
import os
import sys
import time

import numpy as np

import dpdnl


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outdir", nargs="?", default="paper_figures_out")
    ap.add_argument("--steps", type=int, default=20000)
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    os.chdir(a.outdir)

    # 1. Design: gamma and s for eta = 1.5, Sc = 3 at n = 4, rc = 1, kT = 1 (exact inversion).
    n, lbox, kt, dt = 4.0, 5.0, 1.0, 0.005
    d = dpdnl.design(eta=1.5, sc=3.0, density=n, rc=1.0, kt=kt, seed=4242)
    print(f"design: gamma = {d.gamma:.6g}, s = {d.s:.6g} -> kinetic theory eta = "
          f"{d.predicted.eta:.6g}, Sc = {d.predicted.schmidt:.6g}")
    e = dpdnl.euler_temperature(d.gamma, d.s, n, 1.0, dt, kt=kt)
    print(f"Euler at dt = {dt} would heat to T/T0 = {e.t_ratio:.5f}; velocity-Verlet is used")

    # 2. Run: the design's own input lines, speed histogram and pressure tensor to files.
    sim = dpdnl.Simulation()
    half = lbox / 2
    sim.commands([
        "units lj",
        "atom_style atomic",
        f"region box block -{half} {half} -{half} {half} -{half} {half}",
        "create_box 1 box",
        f"create_atoms 1 random {int(n * lbox ** 3)} 8675 box",
        "mass 1 1.0",
        f"velocity all create {kt} 4928 mom yes dist gaussian",
        d.pair_style,
        d.pair_coeff,
        "neighbor 0.3 bin",
        f"timestep {dt}",
        "fix 1 all nve",
        "thermo 1000",
        "thermo_style custom step temp press pxy pxz pyz",
    ])
    sim.run(1000)
    sim.commands([
        "reset_timestep 0",
        "variable speed atom sqrt(vx*vx+vy*vy+vz*vz)",
        "fix hist all ave/histo 10 100 1000 0.0 5.0 100 v_speed mode vector ave one "
        "file speed.histo",
        "fix press all ave/time 1 1 1 c_thermo_press[4] c_thermo_press[5] "
        'c_thermo_press[6] file press.ave format " %.10g"',
    ])
    t0 = time.time()
    sim.run(a.steps)
    secs = time.time() - t0
    print(f"ran {sim.natoms} atoms for {a.steps} steps in {secs:.1f} s "
          f"({a.steps / secs:.0f} steps/s, {sim.threads} threads)")
    temp = sim.thermo[-1]["Temp"]
    print(f"thermo: {len(temp)} rows, mean T = {temp.mean():.4f}")

    # 3. Analyse the engine's files, as `dpdnl analyze mb/eh` would.
    m = dpdnl.mb("speed.histo", temp=kt)
    kt_err = m["kt_fit_err_blocks"] or m["kt_fit_err_iid"]
    print(f"Maxwell-Boltzmann: kT fitted {m['kt_fit']:.4f} +- {kt_err:.4f} (set {kt}); "
          f"chi2 = {m['chi2']:.1f} for {m['dof']} dof, p = {m['p_value']:.3g}")
    v = dpdnl.eh("press.ave", dt=dt, box=[lbox] * 3, temp=kt, density=n)
    print(f"Einstein-Helfand: eta = {v['viscosity']:.3f} +- {v['viscosity_err']:.3f} "
          f"(window [{v['t_min']:.3f}, {v['t_max']:.3f}]); kinetic theory (approximation) "
          f"{d.predicted.eta:.3f}")

    # 4. The figure (matplotlib is optional).
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no figure (pip install matplotlib)")
        return 0
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    t = m["table"]
    ax1.errorbar(t["v_mid"], t["pdf"], yerr=t["pdf_err"], fmt="o", ms=3, label="measured")
    vs = np.linspace(0, t["v_hi"][-1], 300)
    ax1.plot(vs, dpdnl.mb_pdf(vs, kt), "--", label=f"Maxwell-Boltzmann, kT = {kt}")
    ax1.set(xlabel="speed v", ylabel="P(v)", title="Speed distribution (eq. 53)")
    ax1.legend()
    c = v["table"]
    show = c["t"] <= 3 * v["t_max"]
    ax2.plot(c["t"][show][1:], c["mu_running"][show][1:], label="running EH viscosity")
    ax2.axhline(d.predicted.eta, color="k", ls="--", label="kinetic theory of the design")
    ax2.axhline(v["viscosity"], color="C1", label=f"fit: {v['viscosity']:.2f}")
    ax2.axvspan(v["t_min"], v["t_max"], color="C1", alpha=0.15, label="fit window")
    ax2.set(xlabel="t", ylabel="eta(t)", title="Einstein-Helfand viscosity (eq. 59)")
    ax2.legend()
    fig.tight_layout()
    fig.savefig("paper_figures.png", dpi=120)
    print(f"wrote {os.path.join(os.getcwd(), 'paper_figures.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
