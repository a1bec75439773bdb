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
        // No correlation: the plateau starts at once (a level or two of noise at most).
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
    // Too short for a plateau: the naive estimate, flagged as not converged.
    let e = block_average(&[1.0, 2.0, 3.0, 4.0]);
    assert_eq!((e.mean, e.block_len, e.converged), (2.5, 1, false));
    // sqrt(c0 / (n − 1)) with c0 = 5/4, n = 4.
    assert!((e.stderr - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
    let e = block_average(&[7.0; 100]);
    assert_eq!((e.mean, e.stderr), (7.0, 0.0));
    assert!(e.converged);
}

#[test]
fn blocking_levels_halve() {
    let levels = blocking_levels(&gaussians(3, 100));
    let lens: Vec<(usize, usize)> = levels.iter().map(|l| (l.block_len, l.n_blocks)).collect();
    assert_eq!(
        lens,
        vec![(1, 100), (2, 50), (4, 25), (8, 12), (16, 6), (32, 3)]
    );
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
