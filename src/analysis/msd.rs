//! Self-diffusion from the mean-squared displacement, D = MSD / (2 d t) (`docs/models.md` P-10),
//! fitted as D = slope / (2d) of MSD(t) over a window that leaves out the ballistic start, and the
//! Schmidt number Sc = ν / D = μ / (ρ D) (weighting-function paper §4; `docs/models.md` P-11).
//!
//! Two sources:
//! - a single-origin MSD series, as LAMMPS's `compute msd` (column 4 = total) writes through
//!   `fix ave/time` or thermo output. Default window: the last 80 % of the series. Its error is
//!   the Brownian estimate for N independent walkers, D √((4 t₁/(t₂ − t₁) + 2) / (N d)) for a
//!   window [t₁, t₂] (the variance of the two-point estimator [MSD(t₂) − MSD(t₁)] / (2d (t₂ − t₁))),
//!   which needs N; without N only the regression error is given (an underestimate: the
//!   points are strongly correlated).
//! - unwrapped trajectories (dumps with `xu yu zu`, or `x y z ix iy iz`): the MSD averaged over
//!   all time origins (FFT) and atoms, lags up to half the trajectory; default window: lags
//!   from 20 % to 100 % of that. The atoms are split into 8 groups (by position in id order,
//!   i mod 8); the error is the standard error of the 8 group values of D.

use super::is_pos;

use super::corr::msd_all_origins;
use crate::io::dump_read::DumpFrame;
use crate::stats::{LinFit, linear_fit, variance};

/// Parameters of the MSD fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MsdOptions {
    pub dim: usize,
    /// Fit window; `None` uses the defaults of the module documentation.
    pub t_min: Option<f64>,
    pub t_max: Option<f64>,
    /// Default window start as a fraction of the largest lag (0.2).
    pub fit_from: f64,
    /// Largest lag for all-origin MSDs, as a fraction of the trajectory length (0.5).
    pub max_lag_fraction: f64,
    /// Atom groups for the error of all-origin MSDs (8).
    pub groups: usize,
}

impl MsdOptions {
    pub fn new(dim: usize) -> Self {
        MsdOptions {
            dim,
            t_min: None,
            t_max: None,
            fit_from: 0.2,
            max_lag_fraction: 0.5,
            groups: 8,
        }
    }
}

/// Results of an MSD analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct MsdReport {
    pub method: String,
    pub t: Vec<f64>,
    pub msd: Vec<f64>,
    /// Standard error per lag (between groups), for all-origin MSDs.
    pub msd_err: Option<Vec<f64>>,
    pub t_min: f64,
    pub t_max: f64,
    pub fit: LinFit,
    pub d: f64,
    pub d_err: f64,
    pub d_err_method: String,
    /// D of each atom group (all-origin MSDs).
    pub d_groups: Vec<f64>,
}

fn window_fit(t: &[f64], y: &[f64], t_min: f64, t_max: f64) -> Result<LinFit, String> {
    let (tw, yw): (Vec<f64>, Vec<f64>) = t
        .iter()
        .zip(y)
        .filter(|(t, _)| **t >= t_min && **t <= t_max)
        .map(|(a, b)| (*a, *b))
        .unzip();
    if tw.len() < 3 {
        return Err(format!(
            "MSD: the fit window [{t_min}, {t_max}] holds {} points (need 3)",
            tw.len()
        ));
    }
    linear_fit(&tw, &yw)
}

fn check_dim(dim: usize) -> Result<(), String> {
    if dim == 2 || dim == 3 {
        Ok(())
    } else {
        Err(format!("MSD: dimension must be 2 or 3, got {dim}"))
    }
}

/// D from a single-origin MSD series (times `t`, any origin; only differences matter).
pub fn from_series(
    t: &[f64],
    msd: &[f64],
    o: &MsdOptions,
    n_atoms: Option<usize>,
) -> Result<MsdReport, String> {
    check_dim(o.dim)?;
    if t.len() != msd.len() || t.len() < 3 {
        return Err(format!(
            "MSD: need at least 3 (t, MSD) points of equal count (got {} and {})",
            t.len(),
            msd.len()
        ));
    }
    let t0 = t[0];
    let tr: Vec<f64> = t.iter().map(|v| v - t0).collect();
    let t_end = tr[tr.len() - 1];
    let t_max = o.t_max.unwrap_or(t_end);
    let t_min = o.t_min.unwrap_or(o.fit_from * t_max);
    let fit = window_fit(&tr, msd, t_min, t_max)?;
    let d = fit.slope / (2.0 * o.dim as f64);
    let (d_err, d_err_method) = match n_atoms {
        Some(n) if n > 0 && t_max > t_min => {
            let ratio = 4.0 * t_min / (t_max - t_min) + 2.0;
            (
                d.abs() * (ratio / (n as f64 * o.dim as f64)).sqrt(),
                format!("Brownian estimate for {n} independent walkers"),
            )
        }
        _ => (
            fit.slope_err / (2.0 * o.dim as f64),
            "regression only (underestimate; give the atom count for a realistic error)".into(),
        ),
    };
    Ok(MsdReport {
        method: "single origin (compute msd)".into(),
        t: tr,
        msd: msd.to_vec(),
        msd_err: None,
        t_min,
        t_max,
        fit,
        d,
        d_err,
        d_err_method,
        d_groups: Vec::new(),
    })
}

/// D from unwrapped trajectories: `series[i * dim + k]` is coordinate k of atom i over equally
/// spaced frames `dt_frame` apart.
pub fn from_trajectories(
    series: &[Vec<f64>],
    dim: usize,
    dt_frame: f64,
    o: &MsdOptions,
) -> Result<MsdReport, String> {
    check_dim(dim)?;
    if series.is_empty() || !series.len().is_multiple_of(dim) {
        return Err("MSD: no trajectories".into());
    }
    let n_atoms = series.len() / dim;
    let frames = series[0].len();
    if frames < 4 || series.iter().any(|s| s.len() != frames) {
        return Err(format!(
            "MSD: need at least 4 frames for every atom (got {frames})"
        ));
    }
    if !is_pos(dt_frame) {
        return Err(format!(
            "MSD: the time between frames must be positive (got {dt_frame})"
        ));
    }
    let max_lag = (((frames - 1) as f64 * o.max_lag_fraction) as usize).max(3);
    let groups = o.groups.clamp(1, n_atoms);
    let mut sums = vec![vec![0.0; max_lag + 1]; groups];
    let mut counts = vec![0usize; groups];
    for i in 0..n_atoms {
        let g = i % groups;
        counts[g] += 1;
        for k in 0..dim {
            let m = msd_all_origins(&series[i * dim + k], max_lag);
            for (s, v) in sums[g].iter_mut().zip(&m) {
                *s += v;
            }
        }
    }
    let t: Vec<f64> = (0..=max_lag).map(|m| m as f64 * dt_frame).collect();
    let msd: Vec<f64> = (0..=max_lag)
        .map(|m| sums.iter().map(|s| s[m]).sum::<f64>() / n_atoms as f64)
        .collect();
    let group_curves: Vec<Vec<f64>> = sums
        .iter()
        .zip(&counts)
        .map(|(s, &c)| s.iter().map(|v| v / c as f64).collect())
        .collect();
    let t_max = o.t_max.unwrap_or(t[max_lag]);
    let t_min = o.t_min.unwrap_or(o.fit_from * t_max);
    let fit = window_fit(&t, &msd, t_min, t_max)?;
    let two_d = 2.0 * dim as f64;
    let d = fit.slope / two_d;
    let d_groups = group_curves
        .iter()
        .map(|c| window_fit(&t, c, t_min, t_max).map(|f| f.slope / two_d))
        .collect::<Result<Vec<_>, _>>()?;
    let (d_err, d_err_method) = if groups >= 2 {
        (
            (variance(&d_groups) / groups as f64).sqrt(),
            format!("standard error over {groups} atom groups"),
        )
    } else {
        (fit.slope_err / two_d, "regression only (one atom)".into())
    };
    let msd_err = (groups >= 2).then(|| {
        (0..=max_lag)
            .map(|m| {
                let xs: Vec<f64> = group_curves.iter().map(|c| c[m]).collect();
                (variance(&xs) / groups as f64).sqrt()
            })
            .collect()
    });
    Ok(MsdReport {
        method: format!("all time origins, {n_atoms} atoms"),
        t,
        msd,
        msd_err,
        t_min,
        t_max,
        fit,
        d,
        d_err,
        d_err_method,
        d_groups,
    })
}

/// Steps of the frames, unwrapped coordinates `series[i * dim + k]`, and how they were obtained.
pub type Unwrapped = (Vec<u64>, Vec<Vec<f64>>, String);

/// Unwrapped coordinates of every atom over the frames of a dump, as `series[i * dim + k]`,
/// with the frames' steps. Uses `xu yu zu` if present, else `x y z` with image flags
/// `ix iy iz`, else `x y z` unwrapped by the minimum image between consecutive frames (valid
/// only when no atom moves half a box between frames; reported in the returned note). Atoms
/// are matched by `id` (the dump reader sorts rows by id); every frame must hold the same ids.
pub fn unwrapped_series(frames: &[DumpFrame], dim: usize) -> Result<Unwrapped, String> {
    check_dim(dim)?;
    let first = frames.first().ok_or("MSD: the dump has no frame")?;
    let axes = ["x", "y", "z"];
    let col = |f: &DumpFrame, name: &str| f.columns.iter().position(|c| c == name);
    let id_col = col(first, "id");
    let mode = if (0..dim).all(|k| col(first, &format!("{}u", axes[k])).is_some()) {
        0
    } else if (0..dim)
        .all(|k| col(first, axes[k]).is_some() && col(first, &format!("i{}", axes[k])).is_some())
    {
        1
    } else if (0..dim).all(|k| col(first, axes[k]).is_some()) {
        2
    } else {
        return Err(format!(
            "MSD: the dump has no positions (need xu yu zu, or x y z [ix iy iz]); columns: {}",
            first.columns.join(" ")
        ));
    };
    let n = first.rows.len();
    let mut series = vec![Vec::with_capacity(frames.len()); n * dim];
    let mut steps = Vec::with_capacity(frames.len());
    for f in frames {
        if f.rows.len() != n {
            return Err(format!(
                "MSD: step {} has {} atoms, the first frame {n}",
                f.step,
                f.rows.len()
            ));
        }
        if let (Some(j), Some(j0)) = (col(f, "id"), id_col)
            && f.rows.iter().zip(&first.rows).any(|(a, b)| a[j] != b[j0])
        {
            return Err(format!(
                "MSD: step {} does not hold the same atom ids as step {}",
                f.step, first.step
            ));
        }
        steps.push(f.step);
        for k in 0..dim {
            let l: f64 = f.box_bounds[k][1] - f.box_bounds[k][0];
            let (jx, jimg) = match mode {
                0 => (col(f, &format!("{}u", axes[k])), None),
                1 => (col(f, axes[k]), col(f, &format!("i{}", axes[k]))),
                _ => (col(f, axes[k]), None),
            };
            let jx = jx.ok_or(format!("MSD: step {} lacks a position column", f.step))?;
            for (i, r) in f.rows.iter().enumerate() {
                let mut x = r[jx];
                if let Some(ji) = jimg {
                    x += r[ji] * l;
                }
                let s = &mut series[i * dim + k];
                if mode == 2
                    && let Some(&prev) = s.last()
                {
                    let d: f64 = x - prev;
                    x = prev + d - l * (d / l).round();
                }
                s.push(x);
            }
        }
    }
    let note = match mode {
        0 => "unwrapped columns xu yu zu",
        1 => "x y z with image flags",
        _ => "wrapped x y z unwrapped by minimum image between frames",
    }
    .to_string();
    Ok((steps, series, note))
}

/// Sc = ν / D = μ / (ρ D) with ρ the mass density, and its propagated error.
pub fn schmidt(mu: f64, mu_err: f64, rho: f64, d: f64, d_err: f64) -> (f64, f64) {
    let sc = mu / (rho * d);
    let rel = |v: f64, e: f64| {
        if v != 0.0 && e.is_finite() {
            e / v
        } else {
            0.0
        }
    };
    (
        sc,
        sc.abs() * (rel(mu, mu_err).powi(2) + rel(d, d_err).powi(2)).sqrt(),
    )
}
