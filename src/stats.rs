//! Statistics helpers: means, block-averaged standard errors of correlated series, and
//! ordinary least-squares line fits.
//!
//! Functions never panic; degenerate inputs give `NaN` estimates (documented per function) or
//! an `Err` naming what is wrong.

/// Arithmetic mean; `NaN` for an empty slice.
pub fn mean(xs: &[f64]) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    xs.iter().sum::<f64>() / xs.len() as f64
}

/// Unbiased sample variance (divisor N − 1); `NaN` for fewer than two values.
pub fn variance(xs: &[f64]) -> f64 {
    if xs.len() < 2 {
        return f64::NAN;
    }
    let m = mean(xs);
    xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (xs.len() - 1) as f64
}

/// One level of the blocking transformation: the series averaged over blocks of `block_len`
/// consecutive values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockLevel {
    /// Values per block (a power of two).
    pub block_len: usize,
    /// Number of blocks at this level (values left over at the end are dropped).
    pub n_blocks: usize,
    /// Standard error of the mean estimated from the spread of the block means,
    /// `sqrt(c0 / (n_blocks − 1))` with `c0` the (1/n) variance of the block means.
    pub stderr: f64,
    /// The standard error of `stderr` itself, `stderr / sqrt(2 (n_blocks − 1))`
    /// (Flyvbjerg & Petersen 1989, eq. 28, for Gaussian block means).
    pub stderr_err: f64,
}

/// The blocked estimate of a mean and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockEstimate {
    /// Mean of all values (not only of those in whole blocks).
    pub mean: f64,
    /// Standard error of the mean at the chosen block level.
    pub stderr: f64,
    /// Values per block at the chosen level (1 means the naive iid estimate).
    pub block_len: usize,
    /// Number of blocks at the chosen level.
    pub n_blocks: usize,
    /// `true` when a plateau was found; `false` when the series is too short to see one, in
    /// which case `stderr` is the last level with at least [`MIN_BLOCKS`] blocks and is likely an
    /// underestimate.
    pub converged: bool,
}

/// Levels with fewer blocks than this are not used to choose a plateau: their error bars are
/// too wide to tell growth from noise.
pub(crate) const MIN_BLOCKS: usize = 16;

/// All levels of the Flyvbjerg–Petersen blocking transformation of `xs`, from block length 1
/// while at least two blocks remain.
pub fn blocking_levels(xs: &[f64]) -> Vec<BlockLevel> {
    let mut levels = Vec::new();
    let mut cur: Vec<f64> = xs.to_vec();
    let mut block_len = 1;
    while cur.len() >= 2 {
        let n = cur.len();
        let m = mean(&cur);
        let c0 = cur.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n as f64;
        let stderr = (c0 / (n - 1) as f64).sqrt();
        levels.push(BlockLevel {
            block_len,
            n_blocks: n,
            stderr,
            stderr_err: stderr / (2.0 * (n - 1) as f64).sqrt(),
        });
        cur = cur.chunks_exact(2).map(|p| 0.5 * (p[0] + p[1])).collect();
        block_len *= 2;
    }
    levels
}

/// Mean and standard error of a (possibly correlated) series by the blocking method of
/// Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989).
///
/// Each level halves the series by averaging neighbouring pairs; for correlated data the
/// per-level estimate `s_k` of the standard error grows with the block length until blocks are
/// longer than the correlation time, then stays constant within its error
/// `δ_k = s_k / sqrt(2 (n_k − 1))`.
///
/// Plateau rule: the chosen level is the first `k` (with at least [`MIN_BLOCKS`] blocks at
/// levels `k` and `k + 1`) where the estimate stops growing within its own error,
/// `s_{k+1} ≤ s_k + δ_k`. If no such level exists, the last level with at least
/// [`MIN_BLOCKS`] blocks is returned with `converged = false` (for series shorter than
/// `2 · MIN_BLOCKS`, the naive estimate of level 0).
///
/// Empty input gives `NaN` mean and error; a single value gives its value and a `NaN` error.
pub fn block_average(xs: &[f64]) -> BlockEstimate {
    let m = mean(xs);
    let levels = blocking_levels(xs);
    let Some(first) = levels.first() else {
        return BlockEstimate {
            mean: m,
            stderr: f64::NAN,
            block_len: 1,
            n_blocks: xs.len(),
            converged: false,
        };
    };
    let usable: Vec<&BlockLevel> = levels.iter().filter(|l| l.n_blocks >= MIN_BLOCKS).collect();
    let plateau = usable
        .windows(2)
        .find(|w| w[1].stderr <= w[0].stderr + w[0].stderr_err)
        .map(|w| w[0]);
    let (chosen, converged) = match plateau {
        Some(l) => (l, true),
        None => (usable.last().copied().unwrap_or(first), false),
    };
    BlockEstimate {
        mean: m,
        stderr: chosen.stderr,
        block_len: chosen.block_len,
        n_blocks: chosen.n_blocks,
        converged,
    }
}

/// An ordinary least-squares line `y = slope · x + intercept`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinFit {
    /// The slope.
    pub slope: f64,
    /// The intercept at x = 0.
    pub intercept: f64,
    /// Standard error of the slope, `sqrt(s² / Sxx)` with `s² = SSR / (n − 2)`.
    pub slope_err: f64,
    /// Standard error of the intercept, `sqrt(s² (1/n + x̄² / Sxx))`.
    pub intercept_err: f64,
    /// Coefficient of determination `1 − SSR / SST` (1 when `y` is constant and fitted exactly).
    pub r2: f64,
}

/// Least-squares fit of `y` against `x`, assuming independent errors of equal variance.
///
/// With exactly two points the line is exact and the standard errors are `NaN` (no degrees of
/// freedom left). Errors: different lengths, fewer than two points, non-finite values, or all
/// `x` equal.
pub fn linear_fit(x: &[f64], y: &[f64]) -> Result<LinFit, String> {
    if x.len() != y.len() {
        return Err(format!(
            "linear fit: {} x values but {} y values",
            x.len(),
            y.len()
        ));
    }
    let n = x.len();
    if n < 2 {
        return Err(format!("linear fit: needs at least 2 points, got {n}"));
    }
    if let Some(i) = (0..n).find(|&i| !x[i].is_finite() || !y[i].is_finite()) {
        return Err(format!(
            "linear fit: non-finite point {i}: ({}, {})",
            x[i], y[i]
        ));
    }
    let (mx, my) = (mean(x), mean(y));
    let sxx: f64 = x.iter().map(|xi| (xi - mx) * (xi - mx)).sum();
    if sxx == 0.0 {
        return Err(format!("linear fit: all {n} x values are equal ({mx})"));
    }
    let sxy: f64 = x.iter().zip(y).map(|(xi, yi)| (xi - mx) * (yi - my)).sum();
    let syy: f64 = y.iter().map(|yi| (yi - my) * (yi - my)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ssr: f64 = x
        .iter()
        .zip(y)
        .map(|(xi, yi)| {
            let r = yi - (slope * xi + intercept);
            r * r
        })
        .sum();
    let s2 = if n > 2 {
        ssr / (n - 2) as f64
    } else {
        f64::NAN
    };
    let r2 = if syy > 0.0 { 1.0 - ssr / syy } else { 1.0 };
    Ok(LinFit {
        slope,
        intercept,
        slope_err: (s2 / sxx).sqrt(),
        intercept_err: (s2 * (1.0 / n as f64 + mx * mx / sxx)).sqrt(),
        r2,
    })
}
