//! Block averaging and line fits on synthetic data with known answers.
//!
//! The noise comes from `dpdnl::rng::keyed_gaussian`, a counter-based generator, so every run
//! sees the same numbers; the tolerances are still set from the statistics (stated in each
//! test), not tuned to these particular draws.

use dpdnl::rng::keyed_gaussian;
use dpdnl::stats::{BlockEstimate, block_average, blocking_levels, linear_fit, mean, variance};

/// Stream number for test noise (any value not used by the engine is fine).
const STREAM: u32 = 0x5747;

fn gaussians(seed: u32, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| keyed_gaussian(seed, STREAM, i as u64, 0, 1))
        .collect()
}

/// Relative standard deviation of a blocked standard-error estimate with `n` blocks.
fn rel_sigma(est: &BlockEstimate) -> f64 {
    1.0 / (2.0 * (est.n_blocks as f64 - 1.0)).sqrt()
}

#[test]
fn mean_and_variance_exact() {
    assert_eq!(mean(&[1.0, 2.0, 3.0, 6.0]), 3.0);
    assert_eq!(variance(&[1.0, 2.0, 3.0, 6.0]), 14.0 / 3.0);
    assert!(mean(&[]).is_nan());
    assert!(variance(&[1.0]).is_nan());
}

#[test]
fn iid_gaussian_stderr_is_sigma_over_sqrt_n() {
    // x = 3 + 2 ξ, N = 2^16: the true standard error is 2/256. The tolerance is 5 standard
    // deviations of the blocked estimate at the level it chose, 1/sqrt(2(n_blocks − 1)).
    let n = 1 << 16;
    let (mu, sigma) = (3.0, 2.0);
    for seed in 1..=10 {
        let xs: Vec<f64> = gaussians(seed, n).iter().map(|g| mu + sigma * g).collect();
        let est = block_average(&xs);
        let want = sigma / (n as f64).sqrt();
        assert!(est.converged, "seed {seed}: {est:?}");
        assert!(
            (est.stderr / want - 1.0).abs() < 5.0 * rel_sigma(&est),
            "seed {seed}: stderr {} vs {want} ({est:?})",
            est.stderr
        );
        // No correlation: the test passes at level 0 (at level 1 for 1 % of the series), and the
        // estimate is taken EXTRA_LEVELS = 2 levels further.
        assert!(est.block_len <= 8, "seed {seed}: {est:?}");
        assert!(
            (est.mean - mu).abs() < 5.0 * want,
            "seed {seed}: mean {}",
            est.mean
        );
    }
}

#[test]
fn ar1_stderr_matches_integrated_autocorrelation() {
    // x_t = φ x_{t−1} + sqrt(1 − φ²) ξ_t with x_0 = ξ_0 is stationary with unit variance and
    // Var(mean) → (1 + φ) / ((1 − φ) N). For φ = 0.9 that is 19/N.
    //
    // Tolerance: 5 standard deviations of the estimate at the chosen level, plus the
    // finite-block bias. For AR(1) the block-mean variance at block length b falls short of the
    // limit by the fraction 2φ(1 − φ^b) / (b (1 − φ)(1 + φ)) ≤ 9.5/b; the standard error by
    // half of that.
    let n = 1 << 18;
    let phi: f64 = 0.9;
    let want = ((1.0 + phi) / ((1.0 - phi) * n as f64)).sqrt();
    for seed in 1..=5 {
        let g = gaussians(seed, n);
        let mut xs = Vec::with_capacity(n);
        let mut x = g[0];
        xs.push(x);
        for gi in &g[1..] {
            x = phi * x + (1.0 - phi * phi).sqrt() * gi;
            xs.push(x);
        }
        let est = block_average(&xs);
        assert!(est.converged, "seed {seed}: {est:?}");
        let bias = 0.5 * 2.0 * phi / (est.block_len as f64 * (1.0 - phi) * (1.0 + phi));
        let tol = 5.0 * rel_sigma(&est) + bias;
        assert!(
            (est.stderr / want - 1.0).abs() < tol,
            "seed {seed}: stderr {} vs {want} (tol {tol}, {est:?})",
            est.stderr
        );
        // The naive (block length 1) estimate is low by about sqrt((1 − φ)/(1 + φ)) = 0.23.
        let naive = blocking_levels(&xs)[0].stderr;
        assert!(naive / want < 0.3, "seed {seed}: naive {naive} vs {want}");
        assert!(est.block_len >= 32, "seed {seed}: {est:?}");
    }
}

#[test]
fn block_average_degenerate_inputs() {
    let e = block_average(&[]);
    assert!(e.mean.is_nan() && e.stderr.is_nan() && !e.converged);
    let e = block_average(&[4.0]);
    assert_eq!(e.mean, 4.0);
    assert!(e.stderr.is_nan());
    // Too short for any test of correlation: the naive estimate, flagged as a lower bound.
    let e = block_average(&[1.0, 2.0, 3.0, 4.0]);
    assert_eq!((e.mean, e.block_len, e.converged), (2.5, 1, false));
    // sqrt(c0 / (n − 1)) with c0 = 5/4, n = 4.
    assert!((e.stderr - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
    let e = block_average(&[7.0; 100]);
    assert_eq!((e.mean, e.stderr), (7.0, 0.0));
    assert!(e.converged);
    assert_eq!(e.n_eff, 100.0);
}

#[test]
fn blocking_levels_halve() {
    let levels = blocking_levels(&gaussians(3, 100));
    let lens: Vec<(usize, usize)> = levels.iter().map(|l| (l.block_len, l.n_blocks)).collect();
    assert_eq!(
        lens,
        vec![(1, 100), (2, 50), (4, 25), (8, 12), (16, 6), (32, 3)]
    );
    // The lag-1 autocorrelation of level 0, from its definition.
    let xs = [1.0, 3.0, 2.0, 6.0];
    let (m, c0) = (3.0, (4.0 + 0.0 + 1.0 + 9.0) / 4.0);
    let c1 = ((1.0 - m) * (3.0 - m) + (3.0 - m) * (2.0 - m) + (2.0 - m) * (6.0 - m)) / 4.0;
    let l0 = blocking_levels(&xs)[0];
    assert!((l0.autocorr - c1 / c0).abs() < 1e-15, "{l0:?}");
}

/// An AR(1) series x_t = φ x_{t−1} + sqrt(1 − φ²) ξ_t started in its stationary state
/// (unit variance, autocorrelation φ^t), realisation `seed`, component `tag`.
fn ar1(seed: u32, tag: u32, n: usize, phi: f64) -> Vec<f64> {
    let c = (1.0 - phi * phi).sqrt();
    let mut x = keyed_gaussian(seed, STREAM, 0, tag, 7);
    (0..n)
        .map(|i| {
            let v = x;
            x = phi * x + c * keyed_gaussian(seed, STREAM, i as u64 + 1, tag, 7);
            v
        })
        .collect()
}

/// The exact variance of the mean of n consecutive values of a stationary series with
/// autocorrelation φ^t and variance `var`: (var/n) [1 + 2 Σ_{t=1}^{n−1} (1 − t/n) φ^t].
fn ar1_var_of_mean(n: usize, phi: f64, var: f64) -> f64 {
    let nf = n as f64;
    let sum: f64 = (1..n)
        .map(|t| (1.0 - t as f64 / nf) * phi.powi(t as i32))
        .sum();
    var / nf * (1.0 + 2.0 * sum)
}

/// What the realisations say about the estimator.
struct Spread {
    /// Standard deviation of the realisations' means (divisor R − 1).
    sd: f64,
    /// Root mean square of the estimated standard errors.
    rms_err: f64,
    /// Relative standard deviation of `sd / rms_err` from the realisations themselves:
    /// `1/sqrt(2(R − 1))` for the sample standard deviation, and the spread of the squared
    /// errors over R for the RMS, combined.
    rel_sigma: f64,
    /// Relative standard deviation of `rms_err` alone.
    rel_rms: f64,
    /// Realisations whose error was flagged as a lower bound.
    flagged: usize,
    /// Mean of the estimated statistical inefficiency g = N / n_eff.
    g: f64,
    r: usize,
}

fn spread(r: usize, series: impl Fn(u32) -> Vec<f64>) -> Spread {
    let mut gs = Vec::with_capacity(r);
    let ests: Vec<BlockEstimate> = (0..r as u32)
        .map(|k| {
            let xs = series(k);
            let e = block_average(&xs);
            gs.push(xs.len() as f64 / e.n_eff);
            e
        })
        .collect();
    let means: Vec<f64> = ests.iter().map(|e| e.mean).collect();
    let sq: Vec<f64> = ests.iter().map(|e| e.stderr * e.stderr).collect();
    let ms = mean(&sq);
    // RMS = sqrt(ms): relative error half that of ms, sd(err²)/(ms sqrt(R)).
    let rel_rms = 0.5 * variance(&sq).sqrt() / (ms * (r as f64).sqrt());
    let rel_sd = 1.0 / (2.0 * (r as f64 - 1.0)).sqrt();
    Spread {
        sd: variance(&means).sqrt(),
        rms_err: ms.sqrt(),
        rel_sigma: (rel_sd * rel_sd + rel_rms * rel_rms).sqrt(),
        rel_rms,
        flagged: ests.iter().filter(|e| !e.converged).count(),
        g: mean(&gs),
        r,
    }
}

/// The check of the estimator against independent realisations: the RMS of the estimated
/// errors equals the realisation-to-realisation standard deviation of the means within 3 of
/// the ratio's standard deviations (stated by `Spread::rel_sigma`, from R), and the spread
/// itself equals the exact one within 3 of its own (a check of the generator).
fn assert_honest(name: &str, s: &Spread, exact_sd: f64) {
    let rel_sd = 1.0 / (2.0 * (s.r as f64 - 1.0)).sqrt();
    assert!(
        (s.sd / exact_sd - 1.0).abs() < 3.0 * rel_sd,
        "{name}: realisations' sd {} vs exact {exact_sd} (tol {})",
        s.sd,
        3.0 * rel_sd
    );
    let ratio = s.rms_err / s.sd;
    eprintln!(
        "{name}: R = {}, sd of means {:.4e} (exact {exact_sd:.4e}), RMS error {:.4e}, ratio {ratio:.3} ± {:.3}, flagged {}, mean g {:.1}",
        s.r, s.sd, s.rms_err, s.rel_sigma, s.flagged, s.g
    );
    assert!(
        (ratio - 1.0).abs() < 3.0 * s.rel_sigma,
        "{name}: RMS error / spread = {ratio} (tolerance {})",
        3.0 * s.rel_sigma
    );
    // Against the exact value the only noise is the RMS's own (1–2 %), which shows the
    // estimator's residual bias: 3–4 % low in these cases (measured over four independent
    // noise streams). Tolerance: 3 of the RMS's σ plus 5 % for that bias.
    let to_exact = s.rms_err / exact_sd;
    assert!(
        (to_exact - 1.0).abs() < 3.0 * s.rel_rms + 0.05,
        "{name}: RMS error / exact = {to_exact} (tolerance {})",
        3.0 * s.rel_rms + 0.05
    );
}

/// AR(1) with φ = 0.9 (τ_int = (1 + φ)/(2(1 − φ)) = 9.5 samples, g = 19), N = 4096, so
/// n_eff ≈ 216: 300 realisations. Errors must match the spread (3σ of the ratio, σ ≈ 4.3 %
/// at R = 300), and no realisation may be flagged beyond the test's own false alarms (the 1 %
/// level of its χ² test: at most 4 % = 12 of 300, 5 binomial σ above 3).
#[test]
fn errors_match_the_spread_of_independent_ar1_series() {
    let (n, phi, r) = (4096, 0.9, 300);
    let s = spread(r, |k| ar1(k + 1, 0, n, phi));
    assert_honest("AR(1) φ = 0.9", &s, ar1_var_of_mean(n, phi, 1.0).sqrt());
    assert!(s.flagged <= r * 4 / 100, "flagged {}", s.flagged);
    // The statistical inefficiency g = N / n_eff it reports: exactly N Var(mean) = 19.0 here
    // (finite N). Its mean over the realisations within 10 %: g carries the noise of an error
    // squared, 2/sqrt(2(n_blocks − 1)) ≈ 25–35 % per realisation, ≈ 2 % over 300 (3σ = 6 %),
    // plus the residual bias of the blocks' length (a few per cent).
    let want = n as f64 * ar1_var_of_mean(n, phi, 1.0);
    assert!((s.g / want - 1.0).abs() < 0.10, "g {} vs {want}", s.g);
}

/// A slowly decorrelating series: a fast AR(1) (φ = 0.5, variance 1) plus a slow one
/// (φ = 0.995, variance 0.05, τ ≈ 200 samples). The slow part is 5 % of the variance but
/// 87 % of the variance of the mean (g = 3 + 0.05 · 399 ≈ 23), the case where a window on
/// the autocorrelation (Sokal) or the first level that stops growing stops too early.
/// N = 65536 (n_eff ≈ 2800; blocks of 4096 samples, 20 slow times, leave 16 of them), 200
/// realisations (σ of the ratio ≈ 5 %).
#[test]
fn errors_match_the_spread_of_a_slowly_decorrelating_series() {
    let (n, r) = (65536, 200);
    let amp = 0.05f64;
    let s = spread(r, |k| {
        let fast = ar1(k + 1, 1, n, 0.5);
        let slow = ar1(k + 1, 2, n, 0.995);
        fast.iter()
            .zip(&slow)
            .map(|(f, w)| f + amp.sqrt() * w)
            .collect()
    });
    let exact = (ar1_var_of_mean(n, 0.5, 1.0) + ar1_var_of_mean(n, 0.995, amp)).sqrt();
    assert_honest("fast + slow AR(1)", &s, exact);
    assert!(s.flagged <= r * 4 / 100, "flagged {}", s.flagged);
}

/// A series too short for its correlation time is flagged, and the flag is needed: AR(1)
/// φ = 0.9 over N = 128 samples has n_eff = 128/19 ≈ 7. At least 95 % of 300 realisations must
/// be flagged (a short correlated series can look uncorrelated by chance: 8 of 300 would be 2.7
/// %), and their errors are indeed small: RMS error / spread below 0.9 (the ratio's σ is about
/// 5 %; for the naive error it would be sqrt((1 − φ)/(1 + φ)) ≈ 0.23, for a trusted one 1).
#[test]
fn too_short_series_are_flagged_as_lower_bounds() {
    let (n, phi, r) = (128, 0.9, 300);
    let s = spread(r, |k| ar1(k + 1, 3, n, phi));
    eprintln!(
        "AR(1) φ = 0.9, N = {n}: flagged {} of {r}, RMS error / spread {:.3}",
        s.flagged,
        s.rms_err / s.sd
    );
    assert!(
        s.flagged >= r * 95 / 100,
        "flagged only {} of {r}",
        s.flagged
    );
    assert!(
        s.rms_err / s.sd < 0.9,
        "RMS error / spread {}",
        s.rms_err / s.sd
    );
    // Uncorrelated values are not flagged for being few: 64 white-noise values.
    let w = spread(r, |k| gaussians(k + 1000, 64));
    assert!(
        w.flagged <= r * 4 / 100,
        "white noise flagged {}",
        w.flagged
    );
    assert_honest("white noise, N = 64", &w, 1.0 / 8.0);
}

#[test]
fn exact_line() {
    // All values are small multiples of 1/4, so every sum and product is exact in binary.
    let x: Vec<f64> = (0..11).map(f64::from).collect();
    let y: Vec<f64> = x.iter().map(|x| 2.5 * x - 1.25).collect();
    let f = linear_fit(&x, &y).unwrap();
    assert_eq!((f.slope, f.intercept), (2.5, -1.25));
    assert_eq!((f.slope_err, f.intercept_err, f.r2), (0.0, 0.0, 1.0));
}

#[test]
fn textbook_line() {
    // x = 1..5, y = 2 4 5 4 5: Sxx = 10, Sxy = 6, slope 0.6, intercept 2.2, SSR = 2.4,
    // SST = 6, s² = 0.8, slope error sqrt(0.08), intercept error sqrt(0.8 (1/5 + 9/10)).
    let f = linear_fit(&[1.0, 2.0, 3.0, 4.0, 5.0], &[2.0, 4.0, 5.0, 4.0, 5.0]).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b.abs();
    assert!(close(f.slope, 0.6), "{f:?}");
    assert!(close(f.intercept, 2.2), "{f:?}");
    assert!(close(f.r2, 0.6), "{f:?}");
    assert!(close(f.slope_err, 0.08f64.sqrt()), "{f:?}");
    assert!(close(f.intercept_err, 0.88f64.sqrt()), "{f:?}");
}

#[test]
fn noisy_line_errors_are_honest() {
    // y = 1 − 0.3 x + 0.5 ξ on x = 0..n−1. The true slope error is 0.5/sqrt(Sxx); the estimate
    // uses s from n − 2 degrees of freedom, relative spread 1/sqrt(2(n − 2)): tolerance 5 of
    // those. The fitted slope must lie within 5 (true) standard errors of −0.3.
    let n = 1000;
    let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let g = gaussians(11, n);
    let y: Vec<f64> = x
        .iter()
        .zip(&g)
        .map(|(x, g)| 1.0 - 0.3 * x + 0.5 * g)
        .collect();
    let f = linear_fit(&x, &y).unwrap();
    let mx = mean(&x);
    let sxx: f64 = x.iter().map(|x| (x - mx) * (x - mx)).sum();
    let true_err = 0.5 / sxx.sqrt();
    assert!((f.slope_err / true_err - 1.0).abs() < 5.0 / (2.0 * (n as f64 - 2.0)).sqrt());
    assert!((f.slope + 0.3).abs() < 5.0 * true_err, "{f:?}");
    let true_ierr = 0.5 * (1.0 / n as f64 + mx * mx / sxx).sqrt();
    assert!((f.intercept - 1.0).abs() < 5.0 * true_ierr, "{f:?}");
    assert!(f.r2 > 0.99, "{f:?}");
}

#[test]
fn linear_fit_errors() {
    assert!(
        linear_fit(&[1.0], &[1.0])
            .unwrap_err()
            .contains("at least 2")
    );
    assert!(
        linear_fit(&[1.0, 2.0], &[1.0])
            .unwrap_err()
            .contains("1 y values")
    );
    assert!(
        linear_fit(&[2.0, 2.0, 2.0], &[1.0, 2.0, 3.0])
            .unwrap_err()
            .contains("equal")
    );
    assert!(
        linear_fit(&[1.0, f64::NAN], &[1.0, 2.0])
            .unwrap_err()
            .contains("non-finite")
    );
    // Two points: exact line, no degrees of freedom for the errors.
    let f = linear_fit(&[0.0, 2.0], &[1.0, 5.0]).unwrap();
    assert_eq!((f.slope, f.intercept), (2.0, 1.0));
    assert!(f.slope_err.is_nan() && f.intercept_err.is_nan());
}
