//! Speed histograms against the Maxwell–Boltzmann distribution in d dimensions (non-linear
//! paper §3.2 and eq. 53; `docs/models.md` §1.5).
//!
//! The expected content of a bin is the exact integral of the density over the bin,
//! N [F(v_hi) − F(v_lo)], with the cumulative distribution F(v) = P(d/2, m v² / 2kT) (the
//! regularized incomplete gamma function), so the comparison does not depend on the bin width.
//! Counts outside the histogram range (LAMMPS's `Missing-counts`, or the end bins of
//! `beyond extra`) form one more category whose expectation is N [1 − F(hi) + F(lo)].

use super::is_pos;

use super::formats::AveHisto;
use super::special::{chi2_sf, gamma_p, kolmogorov_sf, ln_gamma};
use crate::stats::block_average;

/// Maxwell–Boltzmann density of the speed in `d` dimensions,
/// P(v) = 2 (m / 2kT)^{d/2} / Γ(d/2) · v^{d−1} exp(−m v² / 2kT)
/// (eq. 53 of the non-linear paper for d = 3; (m/kT) v exp(−m v²/2kT) for d = 2).
pub fn mb_pdf(v: f64, kt: f64, mass: f64, d: usize) -> f64 {
    if v < 0.0 {
        return 0.0;
    }
    let a = mass / (2.0 * kt);
    let h = 0.5 * d as f64;
    (2f64.ln() + h * a.ln() - ln_gamma(h) + (d as f64 - 1.0) * v.ln() - a * v * v).exp()
}

/// Cumulative Maxwell–Boltzmann speed distribution, F(v) = P(d/2, m v² / 2kT).
pub(crate) fn mb_cdf(v: f64, kt: f64, mass: f64, d: usize) -> f64 {
    if v <= 0.0 {
        return 0.0;
    }
    gamma_p(0.5 * d as f64, mass * v * v / (2.0 * kt))
}

/// A speed histogram: pooled counts and, when available, the counts of independent outputs
/// (LAMMPS outputs of `ave one`, increments of `ave running`, or dump frames).
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedHistogram {
    /// Bin edges (n + 1 values, increasing).
    pub edges: Vec<f64>,
    pub counts: Vec<f64>,
    /// Counts outside `[edges[0], edges[n]]`.
    pub outside: f64,
    /// Per-output `(counts, outside)`; empty when unknown.
    pub blocks: Vec<(Vec<f64>, f64)>,
    /// How the blocks were obtained (for the report).
    pub note: String,
}

/// Uniform bin edges over `[lo, hi]`.
pub fn uniform_edges(lo: f64, hi: f64, bins: usize) -> Vec<f64> {
    (0..=bins)
        .map(|i| lo + (hi - lo) * i as f64 / bins as f64)
        .collect()
}

impl SpeedHistogram {
    /// Bins speed samples; each slice of `frames` is one block (e.g. one dump frame).
    pub fn from_samples(frames: &[Vec<f64>], edges: Vec<f64>) -> Result<Self, String> {
        let n = edges.len().saturating_sub(1);
        if n == 0 || edges.windows(2).any(|w| !is_pos(w[1] - w[0])) {
            return Err("speed histogram: edges must increase (at least one bin)".into());
        }
        let (lo, hi) = (edges[0], edges[n]);
        let width = (hi - lo) / n as f64;
        let mut blocks = Vec::with_capacity(frames.len());
        for f in frames {
            let mut c = vec![0.0; n];
            let mut out = 0.0;
            for &v in f {
                if !(v >= lo && v < hi) {
                    out += 1.0;
                    continue;
                }
                // Uniform edges: direct index, corrected against the stored edges.
                let mut i = (((v - lo) / width) as usize).min(n - 1);
                while i > 0 && v < edges[i] {
                    i -= 1;
                }
                while i + 1 < n && v >= edges[i + 1] {
                    i += 1;
                }
                c[i] += 1.0;
            }
            blocks.push((c, out));
        }
        let mut counts = vec![0.0; n];
        let mut outside = 0.0;
        for (c, o) in &blocks {
            for (a, b) in counts.iter_mut().zip(c) {
                *a += b;
            }
            outside += o;
        }
        Ok(SpeedHistogram {
            edges,
            counts,
            outside,
            note: format!("{} frames", blocks.len()),
            blocks,
        })
    }

    /// The histogram of a `fix ave/histo` file.
    ///
    /// Bin edges are rebuilt from the bin centres (`Coord`, uniform spacing Δ, edges at
    /// centre ± Δ/2); `beyond extra` is recognised by its end bins sitting at `lo` and `hi`
    /// (half a bin from their neighbours), and their counts are treated as outside. Outputs
    /// with `ave one` are independent blocks and are summed; `ave running` (recognised by
    /// counts that never decrease from one output to the next) is cumulative, so the last
    /// output is the pooled histogram and the differences between outputs are the blocks.
    /// `beyond end` cannot be recognised from the file and must not be used. Blocks of outputs
    /// before `from_step` are left out (for `ave running`, after taking the differences).
    pub fn from_ave_histo(h: &AveHisto, from_step: u64) -> Result<Self, String> {
        let (extra, inner, edges) = histo_bins(h)?;
        let n = h.blocks[0].coord.len();
        let split = |b: &super::formats::HistoBlock| -> (Vec<f64>, f64) {
            let counts: Vec<f64> = b.count[inner.clone()].to_vec();
            let ends = if extra {
                b.count[0] + b.count[n - 1]
            } else {
                0.0
            };
            (counts, b.missing + ends)
        };
        let outputs: Vec<(Vec<f64>, f64)> = h.blocks.iter().map(split).collect();
        let running = outputs.len() >= 2
            && outputs.windows(2).all(|w| {
                w[1].1 >= w[0].1
                    && w[1].0.iter().zip(&w[0].0).all(|(a, b)| a >= b)
                    && w[1].0.iter().sum::<f64>() + w[1].1 > w[0].0.iter().sum::<f64>() + w[0].1
            });
        let (blocks, note) = output_blocks(outputs, running);
        let steps: Vec<u64> = h.blocks.iter().map(|b| b.step).collect();
        let blocks: Vec<(Vec<f64>, f64)> = blocks
            .into_iter()
            .zip(&steps)
            .filter(|(_, s)| **s >= from_step)
            .map(|(b, _)| b)
            .collect();
        if blocks.is_empty() {
            return Err(format!("fix ave/histo: no output at step >= {from_step}"));
        }
        let nb = edges.len() - 1;
        let mut counts = vec![0.0; nb];
        let mut outside = 0.0;
        for (c, o) in &blocks {
            for (a, b) in counts.iter_mut().zip(c) {
                *a += b;
            }
            outside += o;
        }
        Ok(SpeedHistogram {
            edges,
            counts,
            outside,
            blocks,
            note: if extra {
                format!("{note}; beyond extra")
            } else {
                note
            },
        })
    }

    /// Total number of samples (inside and outside).
    pub fn total(&self) -> f64 {
        self.counts.iter().sum::<f64>() + self.outside
    }
}

/// Rounds a histogram limit rebuilt from bin centres that LAMMPS prints with six significant
/// digits (`%g`) to six significant digits of the histogram's scale, so the limits given in
/// the script (0 and 2, not -1e-8 and 1.9999966) come back.
fn round_printed(v: f64, scale: f64) -> f64 {
    if !is_pos(scale) || !scale.is_finite() {
        return v;
    }
    let q = 10f64.powi(scale.log10().floor() as i32 - 5);
    (v / q).round() * q
}

/// Parameters of the comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MbOptions {
    /// The set temperature kT (energy units).
    pub kt: f64,
    pub mass: f64,
    /// Dimension d (2 or 3).
    pub dim: usize,
    /// Neighbouring bins are merged for the χ² test until each category expects at least this
    /// many counts (5 is the usual rule).
    pub min_expected: f64,
}

/// One bin of the comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct MbBin {
    pub lo: f64,
    pub hi: f64,
    pub count: f64,
    /// Observed density count / (N · width) and its standard error (from the spread between
    /// blocks when there are at least 8, else Poisson √count).
    pub pdf: f64,
    pub pdf_err: f64,
    /// Expected density at the set and at the fitted temperature, averaged over the bin.
    pub pdf_set: f64,
    pub pdf_fit: f64,
    /// Expected count at the set temperature.
    pub expected: f64,
}

/// The result of [`analyze`].
#[derive(Debug, Clone, PartialEq)]
pub struct MbReport {
    pub opts: MbOptions,
    pub n_total: f64,
    pub n_blocks: usize,
    pub bins: Vec<MbBin>,
    pub outside: f64,
    pub outside_expected: f64,
    /// Maximum-likelihood kT from the binned counts (outside category included).
    pub kt_fit: f64,
    /// Its error assuming independent samples (inverse Fisher information).
    pub kt_fit_err_iid: f64,
    /// Its error from the spread of per-block fits (block-averaged); `None` with < 2 blocks.
    pub kt_fit_err_blocks: Option<f64>,
    /// Statistical inefficiency g = (err_blocks / err_iid)² (≥ 1 when samples are
    /// correlated); `None` without blocks.
    pub inefficiency: Option<f64>,
    /// Pearson χ² against the set temperature, its degrees of freedom (categories − 1) and
    /// tail probability assuming independent samples.
    pub chi2: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The same p-value with χ² divided by the inefficiency g (correlated samples).
    pub p_value_corrected: Option<f64>,
    /// χ² against the fitted temperature (categories − 2 degrees of freedom).
    pub chi2_fit: f64,
    pub dof_fit: usize,
    pub p_value_fit: f64,
    /// Largest difference between the empirical and the MB cumulative distributions at the
    /// bin edges, and its Kolmogorov tail probability for N independent samples (N/g with
    /// correlation). `NaN` when the histogram does not start at v ≤ 0.
    pub ks_d: f64,
    pub ks_p: f64,
}

/// Category probabilities of the bins and the outside at temperature kt.
fn probabilities(edges: &[f64], kt: f64, o: &MbOptions) -> (Vec<f64>, f64) {
    let f: Vec<f64> = edges
        .iter()
        .map(|&e| mb_cdf(e, kt, o.mass, o.dim))
        .collect();
    let p: Vec<f64> = f.windows(2).map(|w| (w[1] - w[0]).max(0.0)).collect();
    let outside = (1.0 - f[f.len() - 1] + f[0]).max(0.0);
    (p, outside)
}

fn log_likelihood(counts: &[f64], outside: f64, edges: &[f64], kt: f64, o: &MbOptions) -> f64 {
    let (p, po) = probabilities(edges, kt, o);
    let mut l = 0.0;
    for (n, p) in counts.iter().zip(&p) {
        if *n > 0.0 {
            l += n * p.max(1e-300).ln();
        }
    }
    if outside > 0.0 {
        l += outside * po.max(1e-300).ln();
    }
    l
}

/// Maximum-likelihood kT of binned counts (golden-section search in ln kT) and its Fisher
/// error. `None` when there are no counts.
fn fit_kt(counts: &[f64], outside: f64, edges: &[f64], o: &MbOptions) -> Option<(f64, f64)> {
    let n: f64 = counts.iter().sum::<f64>();
    if !is_pos(n) {
        return None;
    }
    // Start from the second moment of the bin centres: <v²> = d kT / m.
    let v2: f64 = counts
        .iter()
        .zip(edges.windows(2))
        .map(|(c, w)| c * (0.5 * (w[0] + w[1])).powi(2))
        .sum::<f64>()
        / n;
    let k0 = if v2 > 0.0 {
        o.mass * v2 / o.dim as f64
    } else {
        o.kt
    };
    let l = |lk: f64| -log_likelihood(counts, outside, edges, lk.exp(), o);
    let (mut a, mut b) = (k0.ln() - 2.0, k0.ln() + 2.0);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (l(c), l(d));
    for _ in 0..200 {
        if (b - a).abs() < 1e-12 {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = l(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = l(d);
        }
    }
    let kt = (0.5 * (a + b)).exp();
    let h = 1e-3 * kt;
    let ll = |k: f64| log_likelihood(counts, outside, edges, k, o);
    let curv = (ll(kt + h) - 2.0 * ll(kt) + ll(kt - h)) / (h * h);
    let err = if curv < 0.0 {
        (-1.0 / curv).sqrt()
    } else {
        f64::NAN
    };
    Some((kt, err))
}

/// Pearson χ² over categories merged until each expects at least `min_expected`; returns
/// (χ², number of categories).
fn chi2_merged(
    counts: &[f64],
    outside: f64,
    p: &[f64],
    p_out: f64,
    n: f64,
    min_expected: f64,
) -> (f64, usize) {
    let mut cats: Vec<(f64, f64)> = Vec::new();
    let (mut o, mut e) = (0.0, 0.0);
    for (c, pi) in counts.iter().zip(p) {
        o += c;
        e += n * pi;
        if e >= min_expected {
            cats.push((o, e));
            o = 0.0;
            e = 0.0;
        }
    }
    let mut last = (o, e);
    let out = (outside, n * p_out);
    if out.1 >= min_expected {
        if last.1 > 0.0 || last.0 > 0.0 {
            match cats.last_mut() {
                Some(l) => {
                    l.0 += last.0;
                    l.1 += last.1;
                }
                None => cats.push(last),
            }
        }
        cats.push(out);
    } else {
        last.0 += out.0;
        last.1 += out.1;
        match cats.last_mut() {
            Some(l) if last.1 < min_expected => {
                l.0 += last.0;
                l.1 += last.1;
            }
            _ => cats.push(last),
        }
    }
    let chi2 = cats
        .iter()
        .map(|(o, e)| {
            if *e > 0.0 {
                (o - e) * (o - e) / e
            } else if *o > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        })
        .sum();
    (chi2, cats.len())
}

/// Compares a speed histogram with the Maxwell–Boltzmann distribution at the set temperature
/// and fits the temperature.
pub fn analyze(h: &SpeedHistogram, o: &MbOptions) -> Result<MbReport, String> {
    if !is_pos(o.kt) || !is_pos(o.mass) || !(o.dim == 2 || o.dim == 3) {
        return Err(format!(
            "Maxwell–Boltzmann: need kT > 0, m > 0 and d = 2 or 3 (got kT = {}, m = {}, d = {})",
            o.kt, o.mass, o.dim
        ));
    }
    let n = h.total();
    if !is_pos(n) {
        return Err("Maxwell–Boltzmann: the histogram is empty".into());
    }
    let (p, p_out) = probabilities(&h.edges, o.kt, o);
    let (kt_fit, kt_err_iid) = fit_kt(&h.counts, h.outside, &h.edges, o)
        .ok_or("Maxwell–Boltzmann: no counts inside the histogram range")?;
    let (pf, pf_out) = probabilities(&h.edges, kt_fit, o);

    // Per-block fits for a correlation-aware error.
    let block_fits: Vec<f64> = h
        .blocks
        .iter()
        .filter_map(|(c, out)| fit_kt(c, *out, &h.edges, o).map(|f| f.0))
        .collect();
    let kt_fit_err_blocks = (block_fits.len() >= 2).then(|| block_average(&block_fits).stderr);
    let inefficiency = kt_fit_err_blocks
        .filter(|e| e.is_finite() && kt_err_iid > 0.0)
        .map(|e| (e / kt_err_iid).powi(2));

    // Per-bin error of the density: spread over blocks (≥ 8 blocks), else Poisson.
    let nb = h.counts.len();
    let block_pdf_err: Option<Vec<f64>> = (h.blocks.len() >= 8).then(|| {
        (0..nb)
            .map(|i| {
                let w = h.edges[i + 1] - h.edges[i];
                let xs: Vec<f64> = h
                    .blocks
                    .iter()
                    .filter_map(|(c, out)| {
                        let t = c.iter().sum::<f64>() + out;
                        (t > 0.0).then(|| c[i] / (t * w))
                    })
                    .collect();
                crate::stats::variance(&xs).sqrt() / (xs.len() as f64).sqrt()
            })
            .collect()
    });
    let bins = (0..nb)
        .map(|i| {
            let (lo, hi) = (h.edges[i], h.edges[i + 1]);
            let w = hi - lo;
            let c = h.counts[i];
            MbBin {
                lo,
                hi,
                count: c,
                pdf: c / (n * w),
                pdf_err: block_pdf_err
                    .as_ref()
                    .map_or(c.max(1.0).sqrt() / (n * w), |e| e[i]),
                pdf_set: p[i] / w,
                pdf_fit: pf[i] / w,
                expected: n * p[i],
            }
        })
        .collect();

    let (chi2, k) = chi2_merged(&h.counts, h.outside, &p, p_out, n, o.min_expected);
    let dof = k.saturating_sub(1).max(1);
    let p_value = chi2_sf(chi2, dof as f64);
    let p_value_corrected = inefficiency.map(|g| chi2_sf(chi2 / g.max(1.0), dof as f64));
    let (chi2_fit, kf) = chi2_merged(&h.counts, h.outside, &pf, pf_out, n, o.min_expected);
    let dof_fit = kf.saturating_sub(2).max(1);
    let p_value_fit = chi2_sf(chi2_fit, dof_fit as f64);

    let (ks_d, ks_p) = if h.edges[0] <= 0.0 {
        let mut cum = 0.0;
        let mut dmax: f64 = 0.0;
        for (i, c) in h.counts.iter().enumerate() {
            cum += c;
            let f = mb_cdf(h.edges[i + 1], o.kt, o.mass, o.dim);
            dmax = dmax.max((cum / n - f).abs());
        }
        let n_eff = n / inefficiency.unwrap_or(1.0).max(1.0);
        let s = n_eff.sqrt();
        (dmax, kolmogorov_sf((s + 0.12 + 0.11 / s) * dmax))
    } else {
        (f64::NAN, f64::NAN)
    };

    Ok(MbReport {
        opts: *o,
        n_total: n,
        n_blocks: h.blocks.len(),
        bins,
        outside: h.outside,
        outside_expected: n * p_out,
        kt_fit,
        kt_fit_err_iid: kt_err_iid,
        kt_fit_err_blocks,
        inefficiency,
        chi2,
        dof,
        p_value,
        p_value_corrected,
        chi2_fit,
        dof_fit,
        p_value_fit,
        ks_d,
        ks_p,
    })
}

/// Speeds of one dump frame (columns vx vy [vz]), and the dimension (given, or 2 when vz is
/// absent or all 0): the samples of `dpdnl analyze mb` on dumps, for the CLI and Python.
pub(crate) fn frame_speeds(
    f: &crate::io::dump_read::DumpFrame,
    dim: Option<usize>,
) -> Result<(Vec<f64>, usize), String> {
    let col = |n: &str| f.columns.iter().position(|c| c == n);
    let (jx, jy) = match (col("vx"), col("vy")) {
        (Some(x), Some(y)) => (x, y),
        _ => {
            return Err(format!(
                "step {}: the dump needs vx vy [vz] columns (has {})",
                f.step,
                f.columns.join(" ")
            ));
        }
    };
    let jz = col("vz");
    let d = dim.unwrap_or(match jz {
        Some(j) if f.rows.iter().any(|r| r[j] != 0.0) => 3,
        _ => 2,
    });
    if d == 3 && jz.is_none() {
        return Err(format!("step {}: --dim 3 needs a vz column", f.step));
    }
    Ok((
        f.rows
            .iter()
            .map(|r| {
                let mut s = r[jx] * r[jx] + r[jy] * r[jy];
                if d == 3
                    && let Some(j) = jz
                {
                    s += r[j] * r[j];
                }
                s.sqrt()
            })
            .collect(),
        d,
    ))
}

/// The bins of a `fix ave/histo` file ([`SpeedHistogram::from_ave_histo`]): whether it has
/// `beyond extra` end bins, the range of its regular bins and their edges.
fn histo_bins(h: &AveHisto) -> Result<(bool, std::ops::Range<usize>, Vec<f64>), String> {
    let first = h.blocks.first().ok_or("fix ave/histo file has no output")?;
    let c = &first.coord;
    let n = c.len();
    if n < 2 {
        return Err("fix ave/histo: need at least two bins".into());
    }
    for b in &h.blocks {
        if b.coord != *c {
            return Err(format!(
                "fix ave/histo: the bins of step {} (line {}) differ from those of step {}",
                b.step, b.line, first.step
            ));
        }
    }
    let uniform = |lo: usize, hi: usize| -> Option<f64> {
        if hi <= lo {
            return None;
        }
        let d = (c[hi] - c[lo]) / (hi - lo) as f64;
        let scale = c[lo].abs().max(c[hi].abs());
        (d > 0.0 && (lo..=hi).all(|i| (c[i] - (c[lo] + (i - lo) as f64 * d)).abs() <= 1e-5 * scale))
            .then_some(d)
    };
    let close = |a: f64, b: f64, d: f64| (a - b).abs() <= 1e-4 * d;
    // `beyond extra`: n − 2 regular bins plus end bins at lo and hi.
    let extra = n >= 4
        && uniform(1, n - 2).is_some_and(|d| {
            close(c[1] - c[0], 0.5 * d, d) && close(c[n - 1] - c[n - 2], 0.5 * d, d)
        });
    let (inner, edges) = if extra {
        let scale = c[0].abs().max(c[n - 1].abs());
        (
            1..n - 1,
            uniform_edges(
                round_printed(c[0], scale),
                round_printed(c[n - 1], scale),
                n - 2,
            ),
        )
    } else {
        let d = uniform(0, n - 1).ok_or(
            "fix ave/histo: bin centres are not uniformly spaced (only linear bins are \
             supported)",
        )?;
        let (lo, hi) = (c[0] - 0.5 * d, c[n - 1] + 0.5 * d);
        let scale = lo.abs().max(hi.abs());
        (
            0..n,
            uniform_edges(round_printed(lo, scale), round_printed(hi, scale), n),
        )
    };
    Ok((extra, inner, edges))
}

/// The blocks of the outputs (counts, outside) of a `fix ave/histo` file: the outputs
/// themselves (`ave one`) or, when `running` (`ave running`), their differences; with the note
/// that says which.
fn output_blocks(outputs: Vec<(Vec<f64>, f64)>, running: bool) -> (Vec<(Vec<f64>, f64)>, String) {
    if running {
        let mut v = vec![outputs[0].clone()];
        for w in outputs.windows(2) {
            v.push((
                w[1].0.iter().zip(&w[0].0).map(|(a, b)| a - b).collect(),
                w[1].1 - w[0].1,
            ));
        }
        (
            v,
            format!(
                "{} outputs, cumulative (ave running): blocks are their differences",
                outputs.len()
            ),
        )
    } else {
        (
            outputs.clone(),
            format!("{} independent outputs (ave one)", outputs.len()),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pdf_integrates_to_cdf() {
        for d in [2, 3] {
            let (kt, m) = (0.1, 1.0);
            // Trapezoid integral of the density up to v = 1 against F(1).
            let n = 20_000;
            let h = 1.0 / n as f64;
            let mut s = 0.0;
            for i in 0..n {
                s += 0.5
                    * h
                    * (mb_pdf(i as f64 * h, kt, m, d) + mb_pdf((i + 1) as f64 * h, kt, m, d));
            }
            assert!((s - mb_cdf(1.0, kt, m, d)).abs() < 1e-7, "d = {d}");
        }
        // d = 3 closed form of eq. 53 at v = 0.5, kT = 0.1, m = 1.
        let v: f64 = 0.5;
        let eq53 = (2.0 / std::f64::consts::PI).sqrt()
            * (1.0f64 / 0.1).powf(1.5)
            * v
            * v
            * (-v * v / 0.2).exp();
        assert!((mb_pdf(v, 0.1, 1.0, 3) - eq53).abs() < 1e-12);
    }
}
