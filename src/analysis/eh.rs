//! Einstein–Helfand shear viscosity (non-linear paper eq. 59; `docs/models.md` §1.5 and P-13):
//!
//! μ = lim_{t→∞} V / (2 k_B T t) ⟨(∫_0^t Π_ab(t') dt')²⟩,
//!
//! from the off-diagonal pressure-tensor series (including random and correction forces, as
//! LAMMPS's and this engine's `pxy pxz pyz` do), averaged over all time origins and over the
//! components given (xy, xz, yz in 3-D; xy in 2-D).
//!
//! Discretisation: sample k holds Π over the interval [kΔ, (k+1)Δ) (an instantaneous value
//! when Δ is one step, or the mean over the interval from `fix ave/time 1 N N`), and the
//! integral is A_k = Δ Σ_{j<k} Π_j. Sampling instantaneous values every N > 1 steps is not
//! the same: the random stress is uncorrelated from step to step, so such sparse samples
//! overestimate its contribution by about N.
//!
//! ⟨(A(t0+t) − A(t0))²⟩ grows linearly once t exceeds the stress correlation time; μ comes from
//! the slope b of a least-squares line over the fit window [t_min, t_max], μ = V b / (2 k_B T).
//! The window must stay well below the decay time of the slowest transverse momentum mode,
//! τ_L = L² / (4π² ν) with ν = μ / ρ (the paper: t ≪ L²/4π²ν). By default t_max = 0.1 τ_L and
//! t_min = t_max / 4, found by iterating from a first fit (ν is not known in advance); the
//! window is reported. The error is the standard error over independent consecutive blocks of
//! the run (default 10, fewer if a block would be shorter than 4 t_max), each fitted on the
//! same window. The report also gives the difference between μ fitted on the two halves of the
//! window ([`EhReport::drift`]): when the stress correlation time is not short compared with
//! τ_L (small boxes, slow conservative stresses) the window is still in the transient and this
//! difference is significant; then widen the window (`window_factor`) or use a larger box.

use super::is_pos;

use super::corr::msd_all_origins;
use crate::stats::{LinFit, linear_fit, variance};
use std::f64::consts::PI;

/// Parameters of the Einstein–Helfand analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EhOptions {
    /// Time between samples Δ.
    pub dt_sample: f64,
    /// Volume (area in 2-D).
    pub volume: f64,
    /// k_B T.
    pub kt: f64,
    /// Box length L of the window criterion (the smallest box length).
    pub box_len: f64,
    /// Mass density ρ = n m (for ν = μ / ρ).
    pub mass_density: f64,
    /// t_max = window_factor · τ_L when not given (default 0.1).
    pub window_factor: f64,
    /// t_min = tmin_fraction · t_max when not given (default 0.25).
    pub tmin_fraction: f64,
    pub t_max: Option<f64>,
    pub t_min: Option<f64>,
    /// Number of blocks for the error (default 10).
    pub n_blocks: usize,
}

impl EhOptions {
    /// The defaults above for a given sampling, volume, temperature, box and density.
    pub fn new(dt_sample: f64, volume: f64, kt: f64, box_len: f64, mass_density: f64) -> Self {
        EhOptions {
            dt_sample,
            volume,
            kt,
            box_len,
            mass_density,
            window_factor: 0.1,
            tmin_fraction: 0.25,
            t_max: None,
            t_min: None,
            n_blocks: 10,
        }
    }
}

/// Results of [`analyze`].
#[derive(Debug, Clone, PartialEq)]
pub struct EhReport {
    /// Lag times t (0, Δ, 2Δ, …) up to the largest lag computed.
    pub t: Vec<f64>,
    /// ⟨(∫Π dt)²⟩ averaged over origins and components.
    pub msd: Vec<f64>,
    /// The running estimate μ(t) = V ⟨(∫Π dt)²⟩ / (2 k_B T t) (NaN at t = 0).
    pub running: Vec<f64>,
    /// Fit window.
    pub t_min: f64,
    pub t_max: f64,
    /// τ_L = L² / (4π² ν) at the final viscosity.
    pub tau_l: f64,
    /// How the window was set: `given` or `auto (N iterations)`.
    pub window_source: String,
    /// True when the automatic t_max was capped by the run length (the run is too short for
    /// the chosen window factor).
    pub capped: bool,
    pub fit: LinFit,
    pub viscosity: f64,
    pub viscosity_err: f64,
    /// μ per component on the same window.
    pub per_component: Vec<f64>,
    /// μ per block (the error is their standard error).
    pub blocks: Vec<f64>,
    /// Linearity check: μ fitted on the second half of the window minus μ on the first half,
    /// and its block error. Zero within errors when ⟨(∫Π)²⟩ is linear over the window; a
    /// significant positive drift means the window is still in the transient (the stress
    /// correlation time is not short compared with t_min).
    pub drift: f64,
    pub drift_err: f64,
    pub n_samples: usize,
}

/// ⟨(A(t0 + mΔ) − A(t0))²⟩ over all origins for m = 0 ..= max_lag, where A_k = Δ Σ_{j<k} Π_j.
pub(crate) fn integral_msd(pi: &[f64], dt_sample: f64, max_lag: usize) -> Vec<f64> {
    let mut a = Vec::with_capacity(pi.len() + 1);
    let mut acc = 0.0;
    a.push(0.0);
    for p in pi {
        acc += dt_sample * p;
        a.push(acc);
    }
    msd_all_origins(&a, max_lag)
}

fn average_curves(curves: &[Vec<f64>]) -> Vec<f64> {
    let n = curves.iter().map(Vec::len).min().unwrap_or(0);
    (0..n)
        .map(|m| curves.iter().map(|c| c[m]).sum::<f64>() / curves.len() as f64)
        .collect()
}

/// Least-squares line of `msd` against t over the lags in [t_min, t_max].
fn fit_window(msd: &[f64], dt: f64, t_min: f64, t_max: f64) -> Result<LinFit, String> {
    let (t, y): (Vec<f64>, Vec<f64>) = msd
        .iter()
        .enumerate()
        .map(|(m, v)| (m as f64 * dt, *v))
        .filter(|(t, _)| *t >= t_min - 1e-12 * dt && *t <= t_max + 1e-12 * dt)
        .unzip();
    if t.len() < 3 {
        return Err(format!(
            "Einstein–Helfand: the fit window [{t_min}, {t_max}] holds {} lags (need 3); \
             sample more often or widen the window",
            t.len()
        ));
    }
    linear_fit(&t, &y)
}

/// Einstein–Helfand viscosity from off-diagonal stress series (see the module documentation).
pub fn analyze(components: &[&[f64]], o: &EhOptions) -> Result<EhReport, String> {
    let n = check_inputs(components, o)?;
    let dt = o.dt_sample;
    let scale = o.volume / (2.0 * o.kt);
    let lag_cap = n / 4;
    let curves: Vec<Vec<f64>> = components
        .iter()
        .map(|c| integral_msd(&c[..n], dt, lag_cap))
        .collect();
    let msd = average_curves(&curves);
    let t_cap = lag_cap as f64 * dt;

    let (t_min, t_max, window_source, capped) = choose_window(o, &msd, scale, t_cap)?;
    if !(t_max > t_min && t_min >= 0.0) {
        return Err(format!(
            "Einstein–Helfand: invalid fit window [{t_min}, {t_max}]"
        ));
    }
    let fit = fit_window(&msd, dt, t_min, t_max)?;
    let viscosity = scale * fit.slope;
    let per_component = curves
        .iter()
        .map(|c| fit_window(c, dt, t_min, t_max).map(|f| scale * f.slope))
        .collect::<Result<Vec<_>, _>>()?;

    // Independent blocks, each long enough for 4 t_max.
    let lag_max = (t_max / dt).ceil() as usize;
    let block_curves = block_curves(components, o, n, lag_max);
    let blocks: Vec<f64> = block_curves
        .iter()
        .map(|c| fit_window(c, dt, t_min, t_max).map(|f| scale * f.slope))
        .collect::<Result<_, _>>()?;
    let viscosity_err = if blocks.len() >= 2 {
        (variance(&blocks) / blocks.len() as f64).sqrt()
    } else {
        f64::NAN
    };
    // Linearity check: μ from the second half of the window minus μ from the first half.
    let t_mid = 0.5 * (t_min + t_max);
    let halves = |c: &[f64]| -> Option<f64> {
        let a = fit_window(c, dt, t_min, t_mid).ok()?;
        let b = fit_window(c, dt, t_mid, t_max).ok()?;
        Some(scale * (b.slope - a.slope))
    };
    let drift = halves(&msd).unwrap_or(f64::NAN);
    let drifts: Vec<f64> = block_curves.iter().filter_map(|c| halves(c)).collect();
    let drift_err = if drifts.len() >= 2 {
        (variance(&drifts) / drifts.len() as f64).sqrt()
    } else {
        f64::NAN
    };
    let t: Vec<f64> = (0..msd.len()).map(|m| m as f64 * dt).collect();
    let running = msd
        .iter()
        .zip(&t)
        .map(|(v, t)| if *t > 0.0 { scale * v / t } else { f64::NAN })
        .collect();
    Ok(EhReport {
        t,
        msd,
        running,
        t_min,
        t_max,
        tau_l: tau_l(o, viscosity),
        window_source,
        capped,
        fit,
        viscosity,
        viscosity_err,
        per_component,
        blocks,
        drift,
        drift_err,
        n_samples: n,
    })
}

/// The number of samples used (the shortest series), after checking the series and the
/// options.
fn check_inputs(components: &[&[f64]], o: &EhOptions) -> Result<usize, String> {
    let n = components.iter().map(|c| c.len()).min().unwrap_or(0);
    if components.is_empty() || n < 16 {
        return Err(format!(
            "Einstein–Helfand: need at least one stress series of 16 samples or more (got {} \
             series, shortest {n})",
            components.len()
        ));
    }
    for (name, v) in [
        ("sample interval", o.dt_sample),
        ("volume", o.volume),
        ("kT", o.kt),
        ("box length", o.box_len),
        ("mass density", o.mass_density),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(format!(
                "Einstein–Helfand: the {name} must be positive (got {v})"
            ));
        }
    }
    if let Some((k, j)) = components
        .iter()
        .enumerate()
        .find_map(|(k, c)| c.iter().position(|v| !v.is_finite()).map(|j| (k, j)))
    {
        return Err(format!(
            "Einstein–Helfand: stress series {} has a non-finite value at sample {j}",
            k + 1
        ));
    }
    Ok(n)
}

/// τ_L = L² ρ / (4 π² μ), the decay time of the box's slowest shear mode.
fn tau_l(o: &EhOptions, mu: f64) -> f64 {
    o.box_len * o.box_len * o.mass_density / (4.0 * PI * PI * mu)
}

/// The fit window (t_min, t_max), where it came from, and whether t_max was capped at `t_cap`:
/// given, or iterated to `window_factor` · τ_L(μ(window)) on the averaged `msd`.
fn choose_window(
    o: &EhOptions,
    msd: &[f64],
    scale: f64,
    t_cap: f64,
) -> Result<(f64, f64, String, bool), String> {
    let dt = o.dt_sample;
    Ok(match (o.t_min, o.t_max) {
        (Some(a), Some(b)) => (a, b.min(t_cap), "given".to_string(), b > t_cap),
        (a, Some(b)) => (
            a.unwrap_or(o.tmin_fraction * b),
            b.min(t_cap),
            "given".to_string(),
            b > t_cap,
        ),
        (a, None) => {
            // Iterate t_max = factor · τ_L(μ(window)).
            let floor = (12.0 * dt / o.tmin_fraction.max(1e-3)).min(t_cap);
            let mut t_max = t_cap;
            let mut iterations = 0;
            let mut capped = false;
            for it in 1..=50 {
                iterations = it;
                let t_min = a.unwrap_or(o.tmin_fraction * t_max);
                let mu = scale * fit_window(msd, dt, t_min, t_max)?.slope;
                if !is_pos(mu) {
                    return Err(format!(
                        "Einstein–Helfand: the fitted slope on [{t_min}, {t_max}] is not \
                         positive ({mu}); the series is too short or not a stress"
                    ));
                }
                let want = o.window_factor * tau_l(o, mu);
                capped = want > t_cap;
                let next = want.clamp(floor, t_cap);
                let done = (next - t_max).abs() <= 1e-3 * t_max;
                t_max = next;
                if done {
                    break;
                }
            }
            (
                a.unwrap_or(o.tmin_fraction * t_max),
                t_max,
                format!(
                    "auto: t_max = {} L^2/(4 pi^2 nu), t_min = {} t_max ({iterations} iterations)",
                    o.window_factor, o.tmin_fraction
                ),
                capped,
            )
        }
    })
}

/// The averaged integral MSD of each of `o.n_blocks` independent blocks (fewer, so that each is
/// long enough for 4 t_max = 4 `lag_max` samples; none when fewer than 2 fit).
fn block_curves(components: &[&[f64]], o: &EhOptions, n: usize, lag_max: usize) -> Vec<Vec<f64>> {
    let dt = o.dt_sample;
    let mut nb = o.n_blocks.max(1);
    while nb > 1 && n / nb < 4 * lag_max {
        nb -= 1;
    }
    if nb >= 2 {
        let len = n / nb;
        (0..nb)
            .map(|b| {
                let cs: Vec<Vec<f64>> = components
                    .iter()
                    .map(|c| integral_msd(&c[b * len..(b + 1) * len], dt, lag_max))
                    .collect();
                average_curves(&cs)
            })
            .collect()
    } else {
        Vec::new()
    }
}
