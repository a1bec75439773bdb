#!/usr/bin/env python3
"""results/repulsion.md: the weighting paper's proposed DPD with the soft repulsion a that the
Groot-Warren compressibility rule gives (validation/weighting/repulsion.sh), beside the a = 0
results and the paper's numbers (../reference/weighting_tables_2d.csv). Also writes
results/repulsion_eta_a.svg (eta* against a) and results/repulsion_t3.svg (eta* against the
shear rate). Standard library only.

Errors of eta*: the larger of `dpdnl analyze couette`'s block error and the standard error of 10
block means of the P_xy series (results/NAME.obs.txt, written by run.sh), since the analysis often
settles on one-sample blocks for these runs."""
import csv
import glob
import math
import os
import re

from summary_sdpd import eta as couette_eta, jload, temp

HERE = os.path.dirname(os.path.abspath(__file__))
RES = os.path.join(HERE, "results")
REF = os.path.join(HERE, "..", "reference", "weighting_tables_2d.csv")
RATES = ["0.05", "0.1", "0.2", "0.5", "1"]


def eta(name):
    """(eta*, err, T, T err) of a Couette run, or None (eta* and its error as summary_sdpd's)."""
    v = couette_eta(name)
    if v is None:
        return None
    e, err = v
    t = temp(name) or (math.nan, math.nan)
    return e, err, t[0], t[1]


def rate_mean(got):
    """Mean of eta* over the rates run and its standard error from the per-rate errors."""
    return (sum(v[0] for v in got) / len(got), math.sqrt(sum(v[1] ** 2 for v in got)) / len(got))


def fmt(v, nd=2):
    if v is None:
        return "–"
    return f"{v[0]:.{nd}f} ± {v[1]:.{nd}f}"


def runtime(name):
    p = os.path.join(RES, "runtimes.csv")
    s = None
    for row in csv.reader(open(p)):
        if row and row[0] == name:
            s = row[4]
    return s or "–"


def reference():
    rows = []
    for line in open(REF):
        if line.startswith("#") or line.startswith("table"):
            continue
        w = line.strip().split(",")
        if len(w) >= 13:
            rows.append(w)
    return rows


def printed_dpd_row(eta0):
    """Table 2's row printed as 'proposed DPD' where the sDPD copy flags a label swap, or None."""
    path = os.path.join(HERE, "..", "reference", "weighting_sdpd_tables_2d.csv")
    for line in open(path):
        w = line.strip().split(",")
        if len(w) >= 15 and w[0] == "2" and w[1] == "DPD(label as printed)" and float(w[5]) == eta0:
            return w
    return None


def ref_row(table, rc, eta0):
    for w in reference():
        if w[0] == str(table) and float(w[1]) == rc and float(w[3]) == eta0:
            return w
    return None


def eos_lines():
    out = []
    for p in sorted(glob.glob(os.path.join(RES, "eos_rc*_a*.txt"))):
        lines = open(p).read().splitlines()
        pts = [ln.split() for ln in lines if ln.startswith("n ")]
        m = re.search(r"rc (\S+) a (\S+): kappa\^-1 = \(1/kT\) dP/dn = (\S+) \+- (\S+); alpha = .* = (\S+) "
                      r"\(mean field pi rc\^3/24 = (\S+), ratio (\S+)\)", lines[-2] if len(lines) > 1 else "")
        a16 = lines[-1].split()[-1] if lines else "–"
        if m:
            out.append((m.groups(), pts, a16))
    return out


def svg_xy(path, title, xlabel, ylabel, series, hlines=()):
    """A small line/point plot: series = [(label, colour, [(x, y, err)], connect)]."""
    W, H, L, R, T, B = 560, 380, 70, 170, 40, 50
    xs = [p[0] for _, _, pts, _ in series for p in pts]
    ys = [p[1] + p[2] for _, _, pts, _ in series for p in pts] + [p[1] - p[2] for _, _, pts, _ in series for p in pts]
    ys += [h for h, _, _ in hlines]
    x0, x1 = min(xs), max(xs)
    y0, y1 = min(ys), max(ys)
    pad = 0.08 * (y1 - y0 or 1)
    y0, y1 = y0 - pad, y1 + pad
    if x1 == x0:
        x1 = x0 + 1

    def X(x):
        return L + (x - x0) / (x1 - x0) * (W - L - R)

    def Y(y):
        return H - B - (y - y0) / (y1 - y0) * (H - T - B)

    s = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{W / 2 - R / 2}" y="20" text-anchor="middle" font-size="14">{title}</text>',
         f'<line x1="{L}" y1="{H - B}" x2="{W - R}" y2="{H - B}" stroke="black"/>',
         f'<line x1="{L}" y1="{T}" x2="{L}" y2="{H - B}" stroke="black"/>',
         f'<text x="{(L + W - R) / 2}" y="{H - 12}" text-anchor="middle">{xlabel}</text>',
         f'<text x="16" y="{(T + H - B) / 2}" text-anchor="middle" transform="rotate(-90 16 {(T + H - B) / 2})">{ylabel}</text>']
    for k in range(6):
        xv = x0 + k * (x1 - x0) / 5
        yv = y0 + k * (y1 - y0) / 5
        s.append(f'<text x="{X(xv):.1f}" y="{H - B + 16}" text-anchor="middle">{xv:.3g}</text>')
        s.append(f'<text x="{L - 6}" y="{Y(yv) + 4:.1f}" text-anchor="end">{yv:.3g}</text>')
        s.append(f'<line x1="{L}" y1="{Y(yv):.1f}" x2="{W - R}" y2="{Y(yv):.1f}" stroke="#eee"/>')
    ly = T + 10
    for h, colour, label in hlines:
        s.append(f'<line x1="{L}" y1="{Y(h):.1f}" x2="{W - R}" y2="{Y(h):.1f}" stroke="{colour}" stroke-dasharray="6 4"/>')
        s.append(f'<line x1="{W - R + 10}" y1="{ly}" x2="{W - R + 30}" y2="{ly}" stroke="{colour}" stroke-dasharray="6 4"/>')
        s.append(f'<text x="{W - R + 34}" y="{ly + 4}">{label}</text>')
        ly += 18
    for label, colour, pts, connect in series:
        pts = sorted(pts)
        if connect and len(pts) > 1:
            d = " ".join(f"{X(x):.1f},{Y(y):.1f}" for x, y, _ in pts)
            s.append(f'<polyline points="{d}" fill="none" stroke="{colour}"/>')
        for x, y, e in pts:
            s.append(f'<line x1="{X(x):.1f}" y1="{Y(y - e):.1f}" x2="{X(x):.1f}" y2="{Y(y + e):.1f}" stroke="{colour}"/>')
            s.append(f'<circle cx="{X(x):.1f}" cy="{Y(y):.1f}" r="3.5" fill="{colour}"/>')
        s.append(f'<circle cx="{W - R + 20}" cy="{ly}" r="3.5" fill="{colour}"/>')
        s.append(f'<text x="{W - R + 34}" y="{ly + 4}">{label}</text>')
        ly += 18
    s.append("</svg>")
    with open(os.path.join(RES, path), "w") as fh:
        fh.write("\n".join(s) + "\n")


def main():
    out = []
    p = out.append
    p("# The proposed DPD with the soft repulsion (Groot–Warren compressibility rule)")
    p("")
    p("Written by `validation/weighting/summary_repulsion.py` from the results of `validation/weighting/repulsion.sh`.")
    p("η* errors: the larger of the analysis's block error and the standard error of 10 block means.")
    p("")
    # 1. equation of state
    eos = eos_lines()
    a1 = a25 = None
    if eos:
        p("## Equation of state at rest (in.eos2d, N = 1600, 2·10⁴ steps, δt = 0.005)")
        p("")
        p("| r_c | a (mean field 180 kT/(π n r_c³)) | ⟨P⟩ at n = 3.6 / 4 / 4.4 | κ⁻¹ = (1/kT) ∂P/∂n | α = (P − n kT)/(a n²) | mean-field α = π r_c³/24 | ratio | a for κ⁻¹ = 16 |")
        p("|---|---|---|---|---|---|---|---|")
        for (rc, a, k, ke, al, mf, ratio), pts, a16 in eos:
            ps = " / ".join(f"{float(w[3]):.2f} ± {float(w[4]):.2f}" for w in pts)
            p(f"| {rc} | {a} | {ps} | {float(k):.2f} ± {float(ke):.2f} | {float(al):.4f} | {float(mf):.4f} | {float(ratio):.3f} | {float(a16):.4g} |")
            if float(rc) == 1.0:
                a1 = f"{float(a16):.4g}"
            else:
                a25 = f"{float(a16):.4g}"
        p("")
    # 2. Table 3
    if a1:
        w = ref_row(3, 1.0, 10)
        p(f"## Table 3 (r_c = 1, η0 = 10, s = ½), Couette η* with a = {a1} beside a = 0")
        p("")
        p("| γ̇ | η* standalone, a = " + a1 + " | η* LAMMPS, a = " + a1 + " | T (temp/deform) standalone / LAMMPS | η* standalone, a = 0 (committed) | paper η* | (ours − paper)/paper |")
        p("|---|---|---|---|---|---|---|")
        t3pts, t3zero, t3paper = [], [], []
        for i, r in enumerate(RATES):
            sa = eta(f"couette_t3_a{a1}_N1600_r{r}")
            la = eta(f"couette_t3_a{a1}_N1600_r{r}_lmp")
            z = eta(f"couette_t3_N1600_r{r}")
            pp = float(w[6 + i]) if w else math.nan
            dev = f"{(sa[0] - pp) / pp * 100:+.1f} %" if sa else "–"
            tt = f"{sa[2]:.4f} / {la[2]:.4f}" if sa and la else (f"{sa[2]:.4f} / –" if sa else "–")
            p(f"| {r} | {fmt(sa)} | {fmt(la)} | {tt} | {fmt(z)} | {pp:.4f} | {dev} |")
            if sa:
                t3pts.append((float(r), sa[0], sa[1]))
            if z:
                t3zero.append((float(r), z[0], z[1]))
            t3paper.append((float(r), pp, 0.0))
        p("")
        if t3pts:
            m = sum(x[1] for x in t3pts) / len(t3pts)
            sd = math.sqrt(sum((x[1] - m) ** 2 for x in t3pts) / max(1, len(t3pts) - 1))
            p(f"Mean over the rates, standalone: {m:.3f} (std {sd:.3f}); paper {float(w[11]):.4f} (std {float(w[12]):.4f}).")
            p("")
            svg_xy("repulsion_t3.svg", "Table 3 fluid (r_c = 1, η0 = 10, s = ½): Couette η*", "shear rate γ̇", "η*",
                   [(f"a = {a1}", "#d62728", t3pts, True), ("a = 0", "#1f77b4", t3zero, True),
                    ("paper", "black", t3paper, True)], [(10.0381, "#888", "η̄ (kinetic theory)")])
            p("![Table 3 with and without the repulsion](repulsion_t3.svg)")
            p("")
    # 3. Table 5
    if a25:
        p(f"## Table 5 (r_c = 2.5), Couette η* with a = {a25}")
        p("")
        p("| Sc0 | η0 | s | η* at γ̇ = 0.05 / 0.1 / 0.2 / 0.5 / 1 (standalone) | mean | LAMMPS at 0.2 | a = 0 mean (committed) | paper mean ± std | (ours − paper)/paper | at γ̇ = 1: ours / paper |")
        p("|---|---|---|---|---|---|---|---|---|---|")
        zs_all = []
        rows = [("t5a", 400, 49), ("t5s400e39", 400, 39), ("t5s400e31", 400, 31),
                ("t5s1000e79", 1000, 79), ("t5s1000e59", 1000, 59), ("t5s1000e49", 1000, 49)]
        for tag, sc, e0 in rows:
            w = None
            for x in reference():
                if x[0] == "5" and x[2] == str(sc) and float(x[3]) == e0:
                    w = x
            vals = [eta(f"couette_{tag}_a{a25}_N1600_r{r}") for r in RATES]
            if not any(vals):
                continue
            got = [v for v in vals if v]
            m, me = rate_mean(got)
            lm = eta(f"couette_{tag}_a{a25}_N1600_r0.2_lmp")
            zs = [eta(f"couette_{tag}_N1600_r{r}") for r in RATES] if tag == "t5a" else []
            zs = [z for z in zs if z]
            zm = f"{sum(z[0] for z in zs) / len(zs):.2f}" if zs else "–"
            pm = float(w[11]) if w else math.nan
            if w:
                zs_all += [(v[0] - float(w[6 + i])) / v[1] for i, v in enumerate(vals) if v]
            last = f"{vals[-1][0]:.2f} / {float(w[10]):.2f}" if w and vals[-1] else "–"
            p(f"| {sc} | {e0} | {w[4] if w else '?'} | " + " / ".join(f"{v[0]:.2f} ± {v[1]:.2f}" if v else "–" for v in vals)
              + f" | {m:.2f} ± {me:.2f} | {fmt(lm)} | {zm} | {pm:.2f} ± {float(w[12]) if w else math.nan:.2f} | {(m - pm) / pm * 100:+.1f} % | {last} |")
        p("")
        if zs_all:
            zm_ = sum(zs_all) / len(zs_all)
            chi = sum(z * z for z in zs_all) / len(zs_all)
            p(f"Over the {len(zs_all)} (row, rate) points: mean of (ours − paper)/σ_ours = {zm_:+.2f}, "
              f"mean of its square = {chi:.2f} (the paper's own scatter not included).")
            p("")
    # 3b. Table 2 (the proposed DPD rows: r_c = 2.5, s = 1/2, eta0 = 10 and 50)
    if a25 and any(eta(f"couette_t2e{e0}_a{a25}_N1600_r{r}") for e0 in (10, 50) for r in RATES):
        p(f"## Table 2 (proposed DPD, r_c = 2.5, s = ½), Couette η* with a = {a25}")
        p("")
        p("The paper's η0 = 50 row labelled 'proposed DPD' is the noisier of its two proposed rows; "
          "its caption calls DPD the more stable, so the labels look swapped "
          "(validation/reference/weighting_tables_2d.csv). Both are shown; the quiet row is "
          "the one this project reads as DPD. Run lengths: `repulsion.sh` step t2.")
        p("")
        p("| η0 | η* at γ̇ = 0.05 / 0.1 / 0.2 / 0.5 / 1 (standalone) | mean | LAMMPS at 0.2 | T standalone (mean over rates) | paper η* at the 5 rates | paper mean ± std | (ours − paper)/paper | η̄ (eq. 60) |")
        p("|---|---|---|---|---|---|---|---|---|")
        for e0 in (10, 50):
            vals = [eta(f"couette_t2e{e0}_a{a25}_N1600_r{r}") for r in RATES]
            got = [v for v in vals if v]
            if not got:
                continue
            m, me = rate_mean(got)
            ts = [v[2] for v in got if not math.isnan(v[2])]
            tm = f"{sum(ts) / len(ts):.3f}" if ts else "–"
            lm = eta(f"couette_t2e{e0}_a{a25}_N1600_r0.2_lmp")
            w = ref_row(2, 2.5, e0)
            pm = float(w[11])
            p(f"| {e0} | " + " / ".join(f"{v[0]:.2f} ± {v[1]:.2f}" if v else "–" for v in vals)
              + f" | {m:.2f} ± {me:.2f} | {fmt(lm)} | {tm} | " + " / ".join(w[6:11]) + f" | {pm:.2f} ± {float(w[12]):.2f}"
              + f" | {(m - pm) / pm * 100:+.1f} % | {float(w[5]):.2f} |")
            alt = printed_dpd_row(e0)
            if alt:
                am = float(alt[13])
                p(f"| {e0} (the row printed as 'DPD') | | | | | " + " / ".join(f"{float(x):.2f}" for x in alt[8:13])
                  + f" | {am:.2f} ± {float(alt[14]):.2f} | {(m - am) / am * 100:+.1f} % | |")
        p("")
    # 4. diffusion
    if a25:
        j = jload(f"diff_a{a25}_N1600.msd.json")
        z = jload("diff_N1600.msd.json")
        if j:
            p(f"## Fig. 4: self-diffusion, Sc0 = 400, η0 = 49, s = 0.0700, r_c = 2.5 (N = 1600, 3·10⁴ steps, δt = 10⁻³)")
            p("")
            p("| a | D (all origins) | paper DPD | kinetic theory |")
            p("|---|---|---|---|")
            if z:
                p(f"| 0 (committed) | {z['diffusion']:.4f} ± {z['diffusion_err']:.4f} | 0.0319 | 0.0306 |")
            p(f"| {a25} | {j['diffusion']:.4f} ± {j['diffusion_err']:.4f} | 0.0319 | 0.0306 |")
            p("")
    # 5. Schmidt number
    if a25:
        rows = []
        for sc in ["10", "30", "100", "300", "1000"]:
            c = eta(f"sc_dpd_a{a25}_{sc}_r0.2")
            d = jload(f"sc_dpdeq_a{a25}_{sc}.msd.json")
            if c and d:
                S = c[0] / (4.0 * d["diffusion"])
                Se = S * math.hypot(c[1] / c[0], d["diffusion_err"] / d["diffusion"])
                rows.append((sc, c, d, S, Se))
        if rows:
            p(f"## Fig. 5 (DPD, s = ½, r_c = 2.5, a = {a25}): Sc = η*/(m n D), η* at γ̇ = 0.2, D at rest")
            p("")
            p("| Sc0 | η0 (eq. 65) | η* | D | Sc | Sc/Sc0 | a = 0 (committed; η by EH at rest): η, D, Sc |")
            p("|---|---|---|---|---|---|---|")
            for sc, c, d, S, Se in rows:
                e0 = math.sqrt(3 * float(sc) * 100 / (4 * 3.5 * 4.5))
                zeh, zd = jload(f"sc_dpdeq_{sc}.eh.json"), jload(f"sc_dpdeq_{sc}.msd.json")
                zero = "–"
                if zeh and zd:
                    zero = (f"{zeh['viscosity']:.2f} ± {zeh.get('viscosity_err') or 0:.2f}, {zd['diffusion']:.5f}, "
                            f"{zeh['viscosity'] / (4 * zd['diffusion']):.1f}")
                p(f"| {sc} | {e0:.3f} | {c[0]:.2f} ± {c[1]:.2f} | {d['diffusion']:.5f} ± {d['diffusion_err']:.5f} | {S:.1f} ± {Se:.1f} | {S / float(sc):.2f} | {zero} |")
            p("")
    # 6. sensitivity
    pts = []
    for f in glob.glob(os.path.join(RES, "couette_t3_a*_N1600_r0.2.couette.json")):
        name = os.path.basename(f)[: -len(".couette.json")]
        a = float(re.search(r"_a([0-9.]+)_", name).group(1))
        v = eta(name)
        if v:
            pts.append((a, v))
    if pts:
        pts.sort()
        w = ref_row(3, 1.0, 10)
        p("## Sensitivity: η* of the Table 3 fluid at γ̇ = 0.2 against a (standalone, 6·10⁴ steps)")
        p("")
        p("| a | η* | T (temp/deform) | paper η* at 0.2 |")
        p("|---|---|---|---|")
        for a, v in pts:
            p(f"| {a:g} | {v[0]:.2f} ± {v[1]:.2f} | {v[2]:.4f} | {float(w[8]):.4f} |")
        p("")
        svg_xy("repulsion_eta_a.svg", "Table 3 fluid at γ̇ = 0.2: η* against the repulsion a", "a", "η*",
               [("this project", "#d62728", [(a, v[0], v[1]) for a, v in pts], True)],
               [(float(w[8]), "black", "paper η*"), (10.0381, "#888", "η̄ (kinetic theory)")])
        p("![η* against a](repulsion_eta_a.svg)")
        p("")
    with open(os.path.join(RES, "repulsion.md"), "w") as fh:
        fh.write("\n".join(out))
    print("\n".join(out))


if __name__ == "__main__":
    main()
