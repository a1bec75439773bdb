//! Reverse non-equilibrium MD with the modified PeX push (non-linear paper §3.3, eqs. 55–58;
//! `docs/models.md` §1.5 and P-6; `fix pex/push` in docs/fixes.md).
//!
//! Geometry: box `[xlo, xlo + Lx)` periodic in x, slab centres c1 = xlo + Lx/4 (receives +Δp_z
//! on its slowest particle) and c2 = xlo + 3Lx/4 (receives −Δp_z). The two halves between the
//! slabs are the *central* half (c1, c2), centred on xlo + Lx/2, and the *outer* half (c2,
//! c1 + Lx) across the periodic boundary, centred on xlo. With Δp_z > 0 the v_z profile falls
//! across the central half and rises across the outer one.
//!
//! Fit window: the bins whose centres lie within `fit_fraction · Lx/4` of a half's centre,
//! i.e. the middle `fit_fraction` of each half (default 0.5: with 40 bins, 10 bins per half,
//! at least Lx/8 away from either slab centre). Coordinates in the outer half are unwrapped
//! around xlo so the fit is continuous.
//!
//! Per output of `fix ave/chunk` (one profile), the slopes s_c and s_o of v_z(x) in the
//! central and outer windows give the shear rate g = (s_o − s_c)/2 (eq. 56 averaged over both
//! halves). The viscosity is μ = Π_xz / g with Π_xz from eq. 55; its error comes from the
//! block-averaged standard error of g over outputs (Flyvbjerg–Petersen, `stats::block_average`)
//! combined with the error of Π_xz. Since least squares is linear in the data, the mean of the
//! per-output slopes equals the slope of the mean profile.

use super::is_pos;

use super::formats::AveChunk;
use crate::stats::{BlockEstimate, LinFit, block_average, linear_fit};

/// Π_xz imposed by pushes of `dp` every `every` steps of length `dt` (eq. 55):
/// Π_xz = Δp_z / (2 L_y L_z N δt).
pub fn pex_stress_nominal(dp: f64, every: u64, dt: f64, ly: f64, lz: f64) -> f64 {
    dp / (2.0 * ly * lz * every as f64 * dt)
}

/// Π_xz from the momentum actually moved (eq. 55 with ΣΔp_z over Δt): the least-squares slope
/// of the cumulative total (`f_ID` of `fix pex/push`) against time, divided by 2 L_y L_z.
/// Returns (Π_xz, standard error of the slope / 2 L_y L_z).
pub fn pex_stress_from_total(
    steps: &[f64],
    total: &[f64],
    dt: f64,
    ly: f64,
    lz: f64,
) -> Result<(f64, f64), String> {
    let t: Vec<f64> = steps.iter().map(|s| s * dt).collect();
    let fit = linear_fit(&t, total).map_err(|e| format!("PeX momentum series: {e}"))?;
    let a = 2.0 * ly * lz;
    let err = if fit.slope_err.is_finite() {
        fit.slope_err / a
    } else {
        0.0
    };
    Ok((fit.slope / a, err))
}

/// Which columns of the `fix ave/chunk` file hold what.
#[derive(Debug, Clone, PartialEq)]
pub struct NemdColumns {
    /// Bin centre (default `Coord1`).
    pub x: String,
    /// Mean v_z per bin (default `vz`).
    pub vz: String,
    /// Number density per bin (default `density/number`); if absent, `Ncount / (Δx L_y L_z)`.
    pub density: String,
    /// Mean of (p_x² + p_y²)/(2m) per particle, i.e. k_B T_d of eq. 58 (default `v_td`, from
    /// `variable td atom mass*(vx*vx+vy*vy)/2`); optional.
    pub td: String,
}

impl Default for NemdColumns {
    fn default() -> Self {
        NemdColumns {
            x: "Coord1".into(),
            vz: "vz".into(),
            density: "density/number".into(),
            td: "v_td".into(),
        }
    }
}

/// Profiles of several outputs on common bins.
#[derive(Debug, Clone, PartialEq)]
pub struct Profiles {
    pub steps: Vec<u64>,
    /// Bin centres.
    pub x: Vec<f64>,
    /// `[output][bin]`.
    pub vz: Vec<Vec<f64>>,
    pub density: Vec<Vec<f64>>,
    /// k_B T_d per bin (eq. 58), if the file has the column.
    pub td: Option<Vec<Vec<f64>>>,
    pub count: Vec<Vec<f64>>,
    /// How the density was obtained (column name or `Ncount/(dx*Ly*Lz)`).
    pub density_source: String,
    pub td_source: Option<String>,
}

/// Takes the NEMD profiles out of a `fix ave/chunk` file (bin/1d along x), keeping outputs
/// with step ≥ `from_step`. `ly_lz` is L_y L_z, used only when there is no density column.
pub fn profiles_from_chunk(
    chunk: &AveChunk,
    cols: &NemdColumns,
    from_step: u64,
    ly_lz: f64,
) -> Result<Profiles, String> {
    let need = |name: &str| {
        chunk.column_index(name).ok_or_else(|| {
            format!(
                "fix ave/chunk file has no column '{name}' (columns: {})",
                chunk.columns.join(" ")
            )
        })
    };
    let jx = need(&cols.x)?;
    let jv = need(&cols.vz)?;
    let jn = chunk.column_index("Ncount");
    let jd = chunk.column_index(&cols.density);
    let jt = chunk.column_index(&cols.td);
    let blocks: Vec<_> = chunk
        .blocks
        .iter()
        .filter(|b| b.step >= from_step)
        .collect();
    let first = blocks.first().ok_or(format!(
        "fix ave/chunk file has no output at step >= {from_step}"
    ))?;
    let x: Vec<f64> = first.rows.iter().map(|r| r[jx]).collect();
    if x.len() < 8 {
        return Err(format!(
            "fix ave/chunk: {} bins; the NEMD analysis needs at least 8",
            x.len()
        ));
    }
    let dx = (x[x.len() - 1] - x[0]) / (x.len() - 1) as f64;
    let mut p = Profiles {
        steps: Vec::new(),
        x: x.clone(),
        vz: Vec::new(),
        density: Vec::new(),
        td: jt.map(|_| Vec::new()),
        count: Vec::new(),
        density_source: match jd {
            Some(_) => cols.density.clone(),
            None => "Ncount/(dx*Ly*Lz)".into(),
        },
        td_source: jt.map(|_| cols.td.clone()),
    };
    if jd.is_none() && (jn.is_none() || !is_pos(ly_lz)) {
        return Err(format!(
            "fix ave/chunk file has neither '{}' nor 'Ncount' (with the box) for the density",
            cols.density
        ));
    }
    let density_of = |r: &Vec<f64>| match (jd, jn) {
        (Some(j), _) => r[j],
        (None, Some(j)) => r[j] / (dx * ly_lz),
        (None, None) => f64::NAN, // excluded by the check above
    };
    for b in &blocks {
        let bx: Vec<f64> = b.rows.iter().map(|r| r[jx]).collect();
        if bx != x {
            return Err(format!(
                "fix ave/chunk: the bins of step {} (line {}) differ from those of step {}",
                b.step, b.line, first.step
            ));
        }
        p.steps.push(b.step);
        p.vz.push(b.rows.iter().map(|r| r[jv]).collect());
        let counts: Vec<f64> = match jn {
            Some(j) => b.rows.iter().map(|r| r[j]).collect(),
            None => vec![1.0; x.len()],
        };
        p.density.push(b.rows.iter().map(density_of).collect());
        if let (Some(j), Some(td)) = (jt, p.td.as_mut()) {
            td.push(b.rows.iter().map(|r| r[j]).collect());
        }
        p.count.push(counts);
    }
    Ok(p)
}

/// Parameters of the NEMD analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NemdOptions {
    pub xlo: f64,
    pub lx: f64,
    /// Π_xz (eq. 55) and its error.
    pub stress: f64,
    pub stress_err: f64,
    /// Fraction of each half (between slab centres) used for the fit; default 0.5.
    pub fit_fraction: f64,
}

/// The fit in one half.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfFit {
    /// `central` or `outer`.
    pub name: &'static str,
    /// Window in unwrapped coordinates, `[lo, hi]`.
    pub window: (f64, f64),
    /// Indices of the bins in the window, and their unwrapped coordinates.
    pub bins: Vec<usize>,
    pub x: Vec<f64>,
    /// Fit of the mean profile in the window (slope error from the regression alone).
    pub fit: LinFit,
    /// Block-averaged slope over outputs.
    pub slope: BlockEstimate,
}

/// Mean and block error of a quantity per bin.
#[derive(Debug, Clone, PartialEq)]
pub struct BinStat {
    pub mean: Vec<f64>,
    pub err: Vec<f64>,
}

fn bin_stat(rows: &[Vec<f64>]) -> BinStat {
    let nb = rows.first().map_or(0, Vec::len);
    let mut mean = Vec::with_capacity(nb);
    let mut err = Vec::with_capacity(nb);
    for i in 0..nb {
        let xs: Vec<f64> = rows.iter().map(|r| r[i]).collect();
        let b = block_average(&xs);
        mean.push(b.mean);
        err.push(b.stderr);
    }
    BinStat { mean, err }
}

/// Results of [`analyze`].
#[derive(Debug, Clone, PartialEq)]
pub struct NemdReport {
    pub n_outputs: usize,
    pub first_step: u64,
    pub last_step: u64,
    pub x: Vec<f64>,
    pub vz: BinStat,
    pub density: BinStat,
    /// k_B T_d per bin (eq. 58), if available.
    pub td: Option<BinStat>,
    pub halves: [HalfFit; 2],
    /// g = (s_outer − s_central)/2, block-averaged over outputs.
    pub shear_rate: BlockEstimate,
    pub stress: f64,
    pub stress_err: f64,
    /// μ = Π_xz / g (eqs. 55–56) and its error.
    pub viscosity: f64,
    pub viscosity_err: f64,
    /// Means over both fit windows (block-averaged over outputs).
    pub density_centre: BlockEstimate,
    pub td_centre: Option<BlockEstimate>,
    pub fit_fraction: f64,
}

/// Wraps `v` into [−L/2, L/2).
fn wrap(v: f64, l: f64) -> f64 {
    v - l * (v / l + 0.5).floor()
}

/// Fits the profiles (see the module documentation).
pub fn analyze(p: &Profiles, o: &NemdOptions) -> Result<NemdReport, String> {
    if !is_pos(o.lx) || !is_pos(o.fit_fraction) || o.fit_fraction > 1.0 {
        return Err(format!(
            "NEMD: need Lx > 0 and 0 < fit fraction <= 1 (got {}, {})",
            o.lx, o.fit_fraction
        ));
    }
    let n_out = p.vz.len();
    if n_out == 0 {
        return Err("NEMD: no profile to analyse".into());
    }
    let half_width = o.fit_fraction * o.lx / 4.0;
    let centres = [o.xlo + 0.5 * o.lx, o.xlo];
    let names = ["central", "outer"];
    let mut windows: Vec<(Vec<usize>, Vec<f64>)> = Vec::new();
    for c in centres {
        let mut bins = Vec::new();
        let mut xs = Vec::new();
        for (i, &x) in p.x.iter().enumerate() {
            let d = wrap(x - c, o.lx);
            if d.abs() < half_width {
                bins.push(i);
                xs.push(c + d);
            }
        }
        if bins.len() < 3 {
            return Err(format!(
                "NEMD: the fit window of a half holds {} bins (need 3); increase the number of \
                 bins or the fit fraction, or check the box (xlo = {}, Lx = {})",
                bins.len(),
                o.xlo,
                o.lx
            ));
        }
        windows.push((bins, xs));
    }

    // Per-output slopes in each window (bins with no atoms are left out of that output's fit).
    let mut slopes = [Vec::with_capacity(n_out), Vec::with_capacity(n_out)];
    let mut g = Vec::with_capacity(n_out);
    for k in 0..n_out {
        let mut s = [0.0; 2];
        for h in 0..2 {
            let (bins, xs) = &windows[h];
            let (xv, yv): (Vec<f64>, Vec<f64>) = bins
                .iter()
                .zip(xs)
                .filter(|(i, _)| p.count[k][**i] > 0.0)
                .map(|(i, x)| (*x, p.vz[k][*i]))
                .unzip();
            s[h] = linear_fit(&xv, &yv)
                .map_err(|e| format!("NEMD, step {}: {e}", p.steps[k]))?
                .slope;
            slopes[h].push(s[h]);
        }
        g.push(0.5 * (s[1] - s[0]));
    }
    let vz = bin_stat(&p.vz);
    let density = bin_stat(&p.density);
    let td = p.td.as_ref().map(|t| bin_stat(t));
    let halves = [0, 1].map(|h| {
        let (bins, xs) = &windows[h];
        let ys: Vec<f64> = bins.iter().map(|&i| vz.mean[i]).collect();
        let fit = linear_fit(xs, &ys).unwrap_or(LinFit {
            slope: f64::NAN,
            intercept: f64::NAN,
            slope_err: f64::NAN,
            intercept_err: f64::NAN,
            r2: f64::NAN,
        });
        HalfFit {
            name: names[h],
            window: (centres[h] - half_width, centres[h] + half_width),
            bins: bins.clone(),
            x: xs.clone(),
            fit,
            slope: block_average(&slopes[h]),
        }
    });
    let shear_rate = block_average(&g);
    let gm = shear_rate.mean;
    let viscosity = o.stress / gm;
    let rel = |v: f64, e: f64| if v != 0.0 { e / v } else { 0.0 };
    let viscosity_err = viscosity.abs()
        * (rel(gm, shear_rate.stderr).powi(2) + rel(o.stress, o.stress_err).powi(2)).sqrt();
    let window_mean = |rows: &[Vec<f64>]| -> BlockEstimate {
        let all: Vec<usize> = windows.iter().flat_map(|w| w.0.iter().copied()).collect();
        let per: Vec<f64> = rows
            .iter()
            .map(|r| all.iter().map(|&i| r[i]).sum::<f64>() / all.len() as f64)
            .collect();
        block_average(&per)
    };
    Ok(NemdReport {
        n_outputs: n_out,
        first_step: p.steps[0],
        last_step: p.steps[n_out - 1],
        x: p.x.clone(),
        density_centre: window_mean(&p.density),
        td_centre: p.td.as_ref().map(|t| window_mean(t)),
        vz,
        density,
        td,
        halves,
        shear_rate,
        stress: o.stress,
        stress_err: o.stress_err,
        viscosity,
        viscosity_err,
        fit_fraction: o.fit_fraction,
    })
}
