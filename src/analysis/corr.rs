//! Mean-squared displacement of a series over all time origins, by FFT.
//!
//! For a series x_0 … x_{N−1} and lag m,
//! MSD(m) = 1/(N−m) Σ_{k=0}^{N−m−1} (x_{k+m} − x_k)²
//!        = 1/(N−m) [Σ_{k<N−m} x_k² + Σ_{k≥m} x_k²] − 2 S(m),   S(m) = 1/(N−m) Σ_k x_k x_{k+m},
//! with the autocorrelation S from a zero-padded FFT (O(N log N) instead of O(N · lags)).
//! The mean of x is removed first (the MSD does not depend on it) to limit cancellation.

/// In-place iterative radix-2 FFT of (re, im) pairs; `inverse` applies the conjugate transform
/// without the 1/n factor. The length must be a power of two.
fn fft(re: &mut [f64], im: &mut [f64], inverse: bool) {
    let n = re.len();
    debug_assert!(n.is_power_of_two() && im.len() == n);
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let sign = if inverse { 1.0 } else { -1.0 };
    let mut len = 2;
    while len <= n {
        let ang = sign * 2.0 * std::f64::consts::PI / len as f64;
        let half = len / 2;
        // Twiddles computed directly per index (no accumulated rounding).
        let tw: Vec<(f64, f64)> = (0..half)
            .map(|k| {
                let a = ang * k as f64;
                (a.cos(), a.sin())
            })
            .collect();
        for start in (0..n).step_by(len) {
            for k in 0..half {
                let (wr, wi) = tw[k];
                let (a, b) = (start + k, start + k + half);
                let xr = re[b] * wr - im[b] * wi;
                let xi = re[b] * wi + im[b] * wr;
                re[b] = re[a] - xr;
                im[b] = im[a] - xi;
                re[a] += xr;
                im[a] += xi;
            }
        }
        len <<= 1;
    }
}

/// Σ_k x_k x_{k+m} for m = 0 ..= max_lag (unnormalised autocorrelation).
pub(crate) fn autocorrelation_sums(x: &[f64], max_lag: usize) -> Vec<f64> {
    let n = x.len();
    let size = (2 * n).next_power_of_two().max(2);
    let mut re = vec![0.0; size];
    let mut im = vec![0.0; size];
    re[..n].copy_from_slice(x);
    fft(&mut re, &mut im, false);
    for k in 0..size {
        re[k] = re[k] * re[k] + im[k] * im[k];
        im[k] = 0.0;
    }
    fft(&mut re, &mut im, true);
    (0..=max_lag.min(n.saturating_sub(1)))
        .map(|m| re[m] / size as f64)
        .collect()
}

/// MSD(m) of `x` over all origins for m = 0 ..= max_lag (capped at N − 1).
pub(crate) fn msd_all_origins(x: &[f64], max_lag: usize) -> Vec<f64> {
    let n = x.len();
    if n == 0 {
        return Vec::new();
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let y: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let max_lag = max_lag.min(n - 1);
    let s = autocorrelation_sums(&y, max_lag);
    // prefix[k] = Σ_{j<k} y_j²
    let mut prefix = vec![0.0; n + 1];
    for k in 0..n {
        prefix[k + 1] = prefix[k] + y[k] * y[k];
    }
    (0..=max_lag)
        .map(|m| {
            let cnt = (n - m) as f64;
            let sq = prefix[n - m] + (prefix[n] - prefix[m]);
            ((sq - 2.0 * s[m]) / cnt).max(0.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fft_msd_matches_direct_sum() {
        let x: Vec<f64> = (0..37)
            .map(|i| ((i * 7919) % 101) as f64 * 0.13 + (i as f64).sin())
            .collect();
        let fast = msd_all_origins(&x, 36);
        for m in 0..=36 {
            let direct: f64 = (0..x.len() - m)
                .map(|k| (x[k + m] - x[k]).powi(2))
                .sum::<f64>()
                / (x.len() - m) as f64;
            assert!(
                (fast[m] - direct).abs() <= 1e-10 * direct.max(1.0),
                "lag {m}: {} vs {direct}",
                fast[m]
            );
        }
    }
}
