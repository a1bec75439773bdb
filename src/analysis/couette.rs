//! Couette flow under Lees–Edwards boundaries (weighting-function paper §5; `docs/models.md` §3.5,
//! P-12): η* = −⟨P_xy⟩ / γ̇, with ⟨P_xy⟩ and its error from block averaging
//! (Flyvbjerg–Petersen, `stats::block_average`) of the P_xy series, the shear rate either the
//! imposed one (`fix deform … erate`) or measured as the slope of the streaming-velocity
//! profile v_x(y) over the whole box (block-averaged over the outputs of `fix ave/chunk`).

use super::formats::AveChunk;
use crate::stats::{BlockEstimate, block_average, linear_fit};

/// The measured shear rate and the mean profile it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct RateProfile {
    pub y: Vec<f64>,
    pub v_mean: Vec<f64>,
    pub v_err: Vec<f64>,
    /// Slope dv_x/dy, block-averaged over outputs.
    pub rate: BlockEstimate,
    /// The fitted profile at coordinate 0 (y_lo in `units reduced`), averaged over outputs,
    /// and its block error: V, the mean velocity relative to the imposed profile γ̇ (y − y_lo)
    /// when the coordinate starts at y_lo.
    pub intercept: f64,
    pub intercept_err: f64,
    pub n_outputs: usize,
}

/// Shear rate from a `fix ave/chunk` profile (bin/1d along the gradient direction): the
/// least-squares slope of `vcol` against `ycol` over all non-empty bins, per output.
pub fn rate_from_profile(
    chunk: &AveChunk,
    ycol: &str,
    vcol: &str,
    from_step: u64,
) -> Result<RateProfile, String> {
    let need = |name: &str| {
        chunk.column_index(name).ok_or_else(|| {
            format!(
                "fix ave/chunk file has no column '{name}' (columns: {})",
                chunk.columns.join(" ")
            )
        })
    };
    let (jy, jv) = (need(ycol)?, need(vcol)?);
    let jn = chunk.column_index("Ncount");
    let blocks: Vec<_> = chunk
        .blocks
        .iter()
        .filter(|b| b.step >= from_step)
        .collect();
    let first = blocks.first().ok_or(format!(
        "fix ave/chunk file has no output at step >= {from_step}"
    ))?;
    let y: Vec<f64> = first.rows.iter().map(|r| r[jy]).collect();
    let mut slopes = Vec::new();
    let mut per_bin: Vec<Vec<f64>> = vec![Vec::new(); y.len()];
    let mut intercepts = Vec::new();
    for b in &blocks {
        if b.rows.len() != y.len() {
            return Err(format!(
                "fix ave/chunk: step {} (line {}) has {} bins, step {} has {}",
                b.step,
                b.line,
                b.rows.len(),
                first.step,
                y.len()
            ));
        }
        let (ys, vs): (Vec<f64>, Vec<f64>) = b
            .rows
            .iter()
            .filter(|r| jn.is_none_or(|j| r[j] > 0.0))
            .map(|r| (r[jy], r[jv]))
            .unzip();
        let fit =
            linear_fit(&ys, &vs).map_err(|e| format!("shear profile, step {}: {e}", b.step))?;
        slopes.push(fit.slope);
        intercepts.push(fit.intercept);
        for (i, r) in b.rows.iter().enumerate() {
            per_bin[i].push(r[jv]);
        }
    }
    let stats: Vec<BlockEstimate> = per_bin.iter().map(|v| block_average(v)).collect();
    Ok(RateProfile {
        y,
        v_mean: stats.iter().map(|s| s.mean).collect(),
        v_err: stats.iter().map(|s| s.stderr).collect(),
        rate: block_average(&slopes),
        intercept: crate::stats::mean(&intercepts),
        intercept_err: block_average(&intercepts).stderr,
        n_outputs: blocks.len(),
    })
}

/// Results of [`analyze`].
#[derive(Debug, Clone, PartialEq)]
pub struct CouetteReport {
    pub pxy: BlockEstimate,
    pub rate: f64,
    pub rate_err: f64,
    /// η* = −⟨P_xy⟩ / γ̇ and its error (relative errors of ⟨P_xy⟩ and γ̇ in quadrature).
    pub viscosity: f64,
    pub viscosity_err: f64,
    pub n_samples: usize,
}

/// η* = −⟨P_xy⟩ / γ̇ from a P_xy series and the shear rate (with its error, 0 if imposed).
pub fn analyze(pxy: &[f64], rate: f64, rate_err: f64) -> Result<CouetteReport, String> {
    if pxy.len() < 2 {
        return Err(format!(
            "Couette: need at least 2 P_xy samples (got {})",
            pxy.len()
        ));
    }
    if let Some(k) = pxy.iter().position(|v| !v.is_finite()) {
        return Err(format!("Couette: P_xy sample {k} is not finite"));
    }
    if !(rate != 0.0 && rate.is_finite()) {
        return Err(format!(
            "Couette: the shear rate must be non-zero (got {rate})"
        ));
    }
    let b = block_average(pxy);
    let viscosity = -b.mean / rate;
    let rel_p = if b.mean != 0.0 {
        b.stderr / b.mean
    } else {
        0.0
    };
    let rel_r = rate_err / rate;
    Ok(CouetteReport {
        pxy: b,
        rate,
        rate_err,
        viscosity,
        viscosity_err: viscosity.abs() * (rel_p * rel_p + rel_r * rel_r).sqrt(),
        n_samples: pxy.len(),
    })
}
