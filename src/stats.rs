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
    /// Lag-1 autocorrelation of the block means, `c1 / c0` with
    /// `c1 = (1/n) Σ (b_i − b̄)(b_{i+1} − b̄)`; 0 when the block means are all equal.
    pub autocorr: f64,
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
    /// `true` when the error can be trusted: the blocked means test uncorrelated from some
    /// level on, the chosen level lies [`EXTRA_LEVELS`] levels beyond it with at least
    /// [`MIN_TRUSTED_BLOCKS`] blocks of at least [`MIN_BLOCK_OVER_G`] times the statistical
    /// inefficiency (so `n_eff ≥ 32`). `false`: the series is too short for its correlation
    /// time, and `stderr` is a lower bound.
    pub converged: bool,
    /// Effective number of independent samples, `N s_0² / stderr²` (`s_0` the naive standard
    /// error of level 0): N divided by the statistical inefficiency `g = 2 τ_int` the blocking
    /// measured. `NaN` for fewer than two values.
    pub n_eff: f64,
}

/// Levels with fewer blocks than this are never chosen: the error of the error,
/// `1/sqrt(2 (n − 1))`, is 27 % at 8 blocks.
pub const MIN_BLOCKS: usize = 8;

/// An error from fewer blocks than this is flagged as a lower bound. A short correlated
/// series can look uncorrelated by chance, and then its error is small exactly when it looks
/// trustworthy; requiring 16 blocks at the chosen level (so a level beyond it, with 8, exists)
/// flags 99 % of AR(1) series with fewer than 15 effective samples, where 8 blocks and
/// `n_eff ≥ 10` alone let 8–25 % of them pass with errors 2–3 times too small.
pub const MIN_TRUSTED_BLOCKS: usize = 16;

/// Levels added beyond the first one where the blocked means test uncorrelated: the test
/// stops where the remaining correlation is too small to detect, not where it is gone, and
/// the deficit of the blocked variance falls as 1/(block length) beyond the correlation time,
/// so two more doublings cut the residual bias by four (`tests/stats.rs` measures it).
pub const EXTRA_LEVELS: usize = 2;

/// The chosen blocks must be at least this many times the statistical inefficiency
/// `g = (stderr / s_0)²` long, i.e. span at least 4 integrated correlation times
/// (`g = 2 τ_int` in samples), or the error is flagged as a lower bound.
pub const MIN_BLOCK_OVER_G: f64 = 2.0;

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
        let c1 = cur.windows(2).map(|w| (w[0] - m) * (w[1] - m)).sum::<f64>() / n as f64;
        let stderr = (c0 / (n - 1) as f64).sqrt();
        levels.push(BlockLevel {
            block_len,
            n_blocks: n,
            stderr,
            stderr_err: stderr / (2.0 * (n - 1) as f64).sqrt(),
            autocorr: if c0 > 0.0 { c1 / c0 } else { 0.0 },
        });
        cur = cur.chunks_exact(2).map(|p| 0.5 * (p[0] + p[1])).collect();
        block_len *= 2;
    }
    levels
}

/// Upper 1 % point of the χ² distribution with `k` degrees of freedom, by the
/// Wilson–Hilferty cube-root approximation (0.8 % low at k = 1, better above).
fn chi2_upper_1pct(k: usize) -> f64 {
    // The standard normal quantile of 0.99.
    const Z: f64 = 2.326_347_874_040_841;
    let k = k as f64;
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + Z * a.sqrt()).powi(3)
}

/// The first level `j` from which on the blocked means are uncorrelated, by the test of
/// Jonsson, Phys. Rev. E 98, 043304 (2018): `M_j = Σ_{k ≥ j} n_k (ρ_k + (n_k − 1)/n_k²)²`,
/// with `ρ_k` the lag-1 autocorrelation of level k and `(n_k − 1)/n_k²` its bias for
/// uncorrelated data, is χ² with (levels − j) degrees of freedom when levels j.. are
/// uncorrelated; `j` is the first level where `M_j` is below its upper 1 % point. `None` when
/// every level shows correlation.
fn first_uncorrelated_level(levels: &[BlockLevel]) -> Option<usize> {
    let terms: Vec<f64> = levels
        .iter()
        .map(|l| {
            let n = l.n_blocks as f64;
            let d = l.autocorr + (n - 1.0) / (n * n);
            if l.stderr > 0.0 { n * d * d } else { 0.0 }
        })
        .collect();
    let mut tail: f64 = terms.iter().sum();
    for (j, t) in terms.iter().enumerate() {
        if tail < chi2_upper_1pct(levels.len() - j) {
            return Some(j);
        }
        tail -= t;
    }
    None
}

/// Mean and standard error of a (possibly correlated) series by blocking (Flyvbjerg &
/// Petersen, J. Chem. Phys. 91, 461 (1989)), with the block length chosen from the data.
///
/// Each level halves the series by averaging neighbouring pairs; for correlated data the
/// per-level estimate `s_k` of the standard error grows with the block length until blocks are
/// much longer than the correlation time, then stays constant.
///
/// Choice of the level:
/// 1. `j`, the first level from which on the block means pass Jonsson's test for lag-1
///    correlation at the 1 % level (Jonsson, Phys. Rev. E 98, 043304 (2018));
/// 2. `k = j +` [`EXTRA_LEVELS`] (the test cannot see correlation below its noise, which still
///    biases `s_j` low by up to ~20 %; two doublings cut that by four), at most the last level
///    with [`MIN_BLOCKS`] blocks;
/// 3. further levels while the blocks are shorter than [`MIN_BLOCK_OVER_G`] `g_k`, with
///    `g_k = (s_k / s_0)²` the statistical inefficiency (the same cap).
///
/// The estimate is `converged` (trusted) when step 1 found a level, step 2 stayed below the
/// cap, the chosen level has at least [`MIN_TRUSTED_BLOCKS`] blocks and its blocks are long
/// enough (step 3), which together mean `n_eff = N / g ≥ 32`; otherwise `stderr` (of the level
/// reached) is a lower bound. `tests/stats.rs` checks the errors against the spread of independent
/// realisations of correlated series.
///
/// Empty input gives `NaN` mean and error; a single value gives its value and a `NaN` error; a
/// constant series its value with error 0.
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
            n_eff: f64::NAN,
        };
    };
    let n = xs.len() as f64;
    if first.stderr == 0.0 {
        return BlockEstimate {
            mean: m,
            stderr: 0.0,
            block_len: 1,
            n_blocks: xs.len(),
            converged: true,
            n_eff: n,
        };
    }
    let g = |l: &BlockLevel| (l.stderr / first.stderr).powi(2);
    let short = |l: &BlockLevel| (l.block_len as f64) < MIN_BLOCK_OVER_G * g(l);
    let cap = levels
        .iter()
        .take_while(|l| l.n_blocks >= MIN_BLOCKS)
        .count()
        .max(1)
        - 1;
    let test = first_uncorrelated_level(&levels);
    let mut k = test.map_or(cap, |j| (j + EXTRA_LEVELS).min(cap));
    while k < cap && short(&levels[k]) {
        k += 1;
    }
    let chosen = &levels[k];
    let n_eff = n / g(chosen);
    let converged = test.is_some_and(|j| j + EXTRA_LEVELS <= cap)
        && chosen.n_blocks >= MIN_TRUSTED_BLOCKS
        && !short(chosen);
    BlockEstimate {
        mean: m,
        stderr: chosen.stderr,
        block_len: chosen.block_len,
        n_blocks: chosen.n_blocks,
        converged,
        n_eff,
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
