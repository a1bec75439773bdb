//! Keyed pair noise: known-answer vectors, symmetry, key sensitivity, distribution.

use dpdnl::rng::{
    STREAM_PAIR_NOISE, gaussian_from_bits, keyed_bits, ln_normal, ordered_tags, pair_gaussian,
    pair_uniform_noise, philox4x32_10, uniform_noise_from_bits,
};

/// Random123's published known-answer vectors for Philox4x32-10 (kat_vectors).
#[test]
fn philox_known_answers() {
    assert_eq!(
        philox4x32_10([0, 0, 0, 0], [0, 0]),
        [0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8]
    );
    assert_eq!(
        philox4x32_10([u32::MAX; 4], [u32::MAX; 2]),
        [0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd]
    );
    assert_eq!(
        philox4x32_10(
            [0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344],
            [0xa4093822, 0x299f31d0]
        ),
        [0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1]
    );
}

/// ξ_ij from the independent Python reference (tools/philox_vectors.py, written from the
/// documented algorithm with Python's math.log/math.cos): (seed, step, tag_i, tag_j, ξ). The
/// engine evaluates ln and cos itself (fdlibm-based, < 1 ulp each); Python's libm differs in
/// the last bits, and the angle 2π b 2⁻⁵² rounds differently there, hence the tolerance
/// 1e-14 · max(|ξ|, 1) (about 50 ulp at |ξ| = 1; a wrong mapping is off by O(1)).
const PAIR_VECTORS: &[(u32, u64, u32, u32, f64)] = &[
    (1, 0, 1, 2, 0.16919724474822506),
    (34387, 1, 7, 3, 2.185482334919234),
    (34387, 123456789012, 1000, 999, -0.025233714199438064),
    (2147483647, 5, 4294967295, 1, 0.5851811056914731),
    (42, 4294967303, 12, 13, -1.3028841500048969),
    (7, 99, 3, 4, 0.156083354553673),
    (123, 0, 1, 5, 0.29164457571314695),
    (123, 1, 1, 5, -0.2662753842572842),
    (9, 1099511627776, 17, 2147483648, -1.1802444399758163),
    (65535, 3, 8, 9, 0.8904105038091169),
];

/// Crafted output words (same Python reference): every octant of the angle, both branches of
/// fdlibm's cosine kernel and of its log, and both ends of u1 (1 and 2⁻⁵²). Same tolerance.
const WORD_VECTORS: &[([u32; 4], f64)] = &[
    ([0x0, 0xfff, 0x0, 0xfff], -0.0),
    ([0xffffffff, 0xffffffff, 0x0, 0x3fff], 8.490424416849509),
    (
        [0x80000000, 0xfff, 0xaaaaaaa, 0xaaaaafff],
        1.1372907488792907,
    ),
    ([0x0, 0x3039fff, 0x20000000, 0xfff], 1.6556390451433757e-06),
    (
        [0x40000000, 0xfff, 0x60000000, 0x11fff],
        -0.5363600213026642,
    ),
    (
        [0x3ad, 0xe68b1fff, 0x9fffffff, 0xffffffff],
        -0.00046829834246548525,
    ),
    ([0xfffffc00, 0xfff, 0xe0000000, 0xfff], 3.905027269087732),
    (
        [0x100000, 0xfff, 0xffffffff, 0xffffbfff],
        0.022098435789617076,
    ),
    ([0xc0000000, 0xfff, 0x50000000, 0xfff], -0.6372097124584207),
    ([0x1, 0xfff, 0xb5555555, 0x55556fff], -5.585104428188214e-06),
    (
        [0x11f71f, 0xb04cbfff, 0x80000000, 0x63fff],
        -0.023416520650006163,
    ),
];

fn close(got: f64, want: f64) -> bool {
    (got - want).abs() <= 1e-14 * want.abs().max(1.0)
}

#[test]
fn pair_gaussian_vectors() {
    for &(seed, step, ti, tj, want) in PAIR_VECTORS {
        let got = pair_gaussian(seed, step, ti, tj);
        assert!(
            close(got, want),
            "ξ({seed},{step},{ti},{tj}) = {got}, reference {want}"
        );
    }
    for &(o, want) in WORD_VECTORS {
        let got = gaussian_from_bits(o);
        assert!(close(got, want), "ξ({o:x?}) = {got}, reference {want}");
    }
}

/// Units in the last place between two finite doubles of the same sign.
fn ulps(a: f64, b: f64) -> u64 {
    (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
}

/// The engine's ln against the platform's libm over [2⁻⁵², 1] (the Box–Muller range) and a
/// wider normal range. Both are fdlibm-grade (< 1 ulp from the exact value), so they can differ
/// by at most 1 ulp where the exact value lies between two doubles; measured: ≤ 1.
#[test]
fn ln_matches_libm() {
    let mut worst = 0;
    for k in 0..200_000u32 {
        let o = keyed_bits(3, 77, u64::from(k), 0, 0);
        let m = ((u64::from(o[0]) << 32) | u64::from(o[1])) >> 12;
        // Exponents from −1022 to +1023, and the Box–Muller interval [2⁻⁵², 1].
        let e = u64::from(o[2] % 2046) + 1;
        for x in [
            f64::from_bits((e << 52) | m),
            1.0 - m as f64 * 2f64.powi(-52),
        ] {
            if x == 1.0 {
                assert_eq!(ln_normal(x), 0.0);
                continue;
            }
            let (a, b) = (ln_normal(x), x.ln());
            assert!(a.signum() == b.signum() || a == 0.0, "ln({x}) = {a} vs {b}");
            worst = worst.max(ulps(a, b));
        }
    }
    eprintln!("ln vs libm: worst {worst} ulp");
    assert!(worst <= 1, "ln differs from libm by {worst} ulp");
}

/// The Gaussian mapping against the same formula evaluated with libm (`ln`, `cos` of the
/// rounded angle) on 10⁶ draws. The reference rounds θ = 2π b 2⁻⁵² (|Δθ| ≤ 2⁻⁵¹ ≈ 4.4e-16 for
/// θ < 2π) where the engine reduces exactly, and each side's cos/ln may be off by an ulp, so
/// |Δξ| ≤ r (4.4e-16 + 2.2e-16) + |ξ| 2.2e-16 with r ≤ 8.49: tolerance 6e-15 · max(|ξ|, 1).
#[test]
fn gaussian_matches_libm_formula() {
    let mut worst: f64 = 0.0;
    for k in 0..1_000_000u32 {
        let o = keyed_bits(5, 1, u64::from(k), 1, 2);
        let a = ((u64::from(o[0]) << 32) | u64::from(o[1])) >> 12;
        let b = ((u64::from(o[2]) << 32) | u64::from(o[3])) >> 12;
        let u1 = 1.0 - a as f64 * 2f64.powi(-52);
        let want =
            (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * (b as f64 * 2f64.powi(-52))).cos();
        let got = gaussian_from_bits(o);
        let rel = (got - want).abs() / want.abs().max(1.0);
        worst = worst.max(rel);
        assert!(rel <= 6e-15, "draw {k}: {got} vs {want}");
    }
    eprintln!("Gaussian vs libm formula: worst {worst:.2e} · max(|ξ|, 1)");
}

#[test]
fn pair_order_and_symmetry() {
    assert_eq!(ordered_tags(5, 3), (3, 5));
    assert_eq!(ordered_tags(3, 5), (3, 5));
    for k in 0..1000u32 {
        let (a, b) = (k * 7 + 1, k * 13 + 2);
        assert_eq!(
            pair_gaussian(9, u64::from(k), a, b).to_bits(),
            pair_gaussian(9, u64::from(k), b, a).to_bits()
        );
    }
}

/// Changing any single key field (seed, step low/high word, either tag, stream) changes the draw.
#[test]
fn every_key_field_matters() {
    let base = keyed_bits(11, STREAM_PAIR_NOISE, 100, 5, 6);
    let variants = [
        keyed_bits(12, STREAM_PAIR_NOISE, 100, 5, 6),
        keyed_bits(11, STREAM_PAIR_NOISE + 1, 100, 5, 6),
        keyed_bits(11, STREAM_PAIR_NOISE, 101, 5, 6),
        keyed_bits(11, STREAM_PAIR_NOISE, 100 + (1 << 32), 5, 6),
        keyed_bits(11, STREAM_PAIR_NOISE, 100, 4, 6),
        keyed_bits(11, STREAM_PAIR_NOISE, 100, 5, 7),
    ];
    for v in variants {
        assert_ne!(v, base);
        // A good mixer flips about half of the 128 bits.
        let flipped: u32 = v
            .iter()
            .zip(base.iter())
            .map(|(a, b)| (a ^ b).count_ones())
            .sum();
        assert!((32..=96).contains(&flipped), "only {flipped} bits changed");
    }
}

/// Moments of 10^6 draws over consecutive steps and pairs. Standard errors for N = 10^6:
/// mean 1e-3, variance sqrt(2/N) = 1.4e-3, kurtosis sqrt(96/N) ≈ 1e-2; tolerances are 5 σ.
#[test]
fn gaussian_moments() {
    let n = 1_000_000u32;
    let (mut s1, mut s2, mut s4) = (0.0, 0.0, 0.0);
    let mut tail = 0u32;
    for k in 0..n {
        let x = pair_gaussian(77, u64::from(k / 1000), k % 1000 + 1, 5000);
        s1 += x;
        s2 += x * x;
        s4 += x * x * x * x;
        if x.abs() > 3.0 {
            tail += 1;
        }
    }
    let nf = f64::from(n);
    let mean = s1 / nf;
    let var = s2 / nf - mean * mean;
    let kurt = s4 / nf / (var * var);
    assert!(mean.abs() < 5e-3, "mean {mean}");
    assert!((var - 1.0).abs() < 7e-3, "variance {var}");
    assert!((kurt - 3.0).abs() < 5e-2, "kurtosis {kurt}");
    // P(|x| > 3) = 0.0026998; binomial σ = sqrt(N p) ≈ 52 counts.
    let expect = 0.002_699_8 * nf;
    assert!(
        (f64::from(tail) - expect).abs() < 5.0 * expect.sqrt(),
        "tail {tail} vs {expect}"
    );
    let _ = gaussian_from_bits([0, 0, 0, 0]).is_finite();
}

/// `noise_dist uniform`: ξ = √3 (2u − 1) from the pair's keyed bits. Exact properties: symmetric
/// pair order; the bits a and 2⁵² − 1 − a give ξ and −ξ exactly; |ξ| < √3 with the extremes at
/// √3 (1 − 2⁻⁵²). Moments of 10⁶ draws (uniform: variance 1, kurtosis 9/5; standard errors for
/// N = 10⁶: mean 1e-3, variance sqrt((9/5 − 1)/N) = 9e-4, kurtosis about 2e-3; tolerances
/// 5 σ) and a χ² over 20 equal bins (19 degrees of freedom: χ² < 43.8 fails by chance with
/// probability 10⁻³).
#[test]
fn uniform_noise_is_symmetric_bounded_and_flat() {
    let sqrt3 = 3f64.sqrt();
    assert_eq!(
        pair_uniform_noise(77, 9, 4, 11).to_bits(),
        pair_uniform_noise(77, 9, 11, 4).to_bits()
    );
    for k in [0u64, 1, 12345, (1 << 51) - 1, 1 << 51, (1 << 52) - 1] {
        let bits = |k: u64| {
            let w = k << 12;
            [(w >> 32) as u32, w as u32, 0xDEAD, 0xBEEF]
        };
        let (a, b) = (
            uniform_noise_from_bits(bits(k)),
            uniform_noise_from_bits(bits((1 << 52) - 1 - k)),
        );
        assert_eq!(a.to_bits(), (-b).to_bits(), "k = {k}");
        assert!(a.abs() < sqrt3, "k = {k}: {a}");
    }
    let edge = uniform_noise_from_bits([0, 0, 0, 0]);
    assert_eq!(edge, -sqrt3 * (1.0 - 2f64.powi(-52)));
    let n = 1_000_000u32;
    let (mut s1, mut s2, mut s4) = (0.0, 0.0, 0.0);
    let mut bins = [0u32; 20];
    for k in 0..n {
        let x = pair_uniform_noise(77, u64::from(k / 1000), k % 1000 + 1, 5000);
        assert!(x.abs() < sqrt3);
        s1 += x;
        s2 += x * x;
        s4 += x * x * x * x;
        bins[((x / sqrt3 + 1.0) * 10.0) as usize] += 1;
    }
    let nf = f64::from(n);
    let mean = s1 / nf;
    let var = s2 / nf - mean * mean;
    let kurt = s4 / nf / (var * var);
    assert!(mean.abs() < 5e-3, "mean {mean}");
    assert!((var - 1.0).abs() < 4.5e-3, "variance {var}");
    assert!((kurt - 1.8).abs() < 1e-2, "kurtosis {kurt}");
    let expect = nf / 20.0;
    let chi2: f64 = bins
        .iter()
        .map(|&c| (f64::from(c) - expect).powi(2) / expect)
        .sum();
    assert!(chi2 < 43.8, "chi2 {chi2} over 19 dof: {bins:?}");
}

/// Φ(x) by composite Simpson integration of the density from 0 (error < 1e-13 at 2·10⁴ panels
/// per unit), so the test does not depend on an erf implementation.
fn normal_cdf(x: f64) -> f64 {
    let n = ((x.abs() * 20_000.0).ceil() as usize).max(2) & !1;
    let h = x / n as f64;
    let pdf = |t: f64| (-0.5 * t * t).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let mut s = pdf(0.0) + pdf(x);
    for k in 1..n {
        s += if k % 2 == 1 { 4.0 } else { 2.0 } * pdf(k as f64 * h);
    }
    0.5 + s * h / 3.0
}

/// The shape of the distribution: χ² of 10⁶ pair draws in 42 bins (width 0.25 on [−5, 5] and
/// the two tails) against the exact normal probabilities. With 41 degrees of freedom the
/// 1 − 10⁻⁶ quantile is 99.5 (Wilson–Hilferty), so a correct generator fails once in 10⁶ runs
/// (the draws are fixed by their keys, so the test is deterministic).
#[test]
fn gaussian_chi_square() {
    let n = 1_000_000u32;
    let edges: Vec<f64> = (0..=40).map(|k| -5.0 + 0.25 * f64::from(k)).collect();
    let mut counts = vec![0u64; edges.len() + 1];
    for k in 0..n {
        let x = pair_gaussian(2024, u64::from(k / 500), k % 500 + 1, 100_000 + k / 500);
        let bin = edges.partition_point(|&e| e <= x);
        counts[bin] += 1;
    }
    let cdf: Vec<f64> = edges.iter().map(|&e| normal_cdf(e)).collect();
    let mut chi2 = 0.0;
    for (b, &c) in counts.iter().enumerate() {
        let lo = if b == 0 { 0.0 } else { cdf[b - 1] };
        let hi = if b == edges.len() { 1.0 } else { cdf[b] };
        let expect = (hi - lo) * f64::from(n);
        chi2 += (c as f64 - expect).powi(2) / expect;
    }
    eprintln!("χ² = {chi2:.1} (41 degrees of freedom)");
    assert!(chi2 < 99.5, "χ² = {chi2} with 41 degrees of freedom");
}
