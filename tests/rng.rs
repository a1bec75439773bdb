//! Keyed pair noise: known-answer vectors, symmetry, key sensitivity, distribution.

use dpdnl::rng::{
    STREAM_PAIR_NOISE, gaussian_from_bits, keyed_bits, ordered_tags, pair_gaussian, philox4x32_10,
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
/// documented algorithm): (seed, step, tag_i, tag_j, ξ). libm and Python may differ in the last
/// bit of ln/cos, hence the 1e-14 relative tolerance.
const PAIR_VECTORS: &[(u32, u64, u32, u32, f64)] = &[
    (1, 0, 1, 2, 0.6425453671682086),
    (34387, 1, 7, 3, 0.22684022566269213),
    (34387, 123456789012, 1000, 999, -0.0658115417305718),
    (2147483647, 5, 4294967295, 1, 1.125538931103521),
    (42, 4294967303, 12, 13, -1.0568111274416334),
];

#[test]
fn pair_gaussian_vectors() {
    for &(seed, step, ti, tj, want) in PAIR_VECTORS {
        let got = pair_gaussian(seed, step, ti, tj);
        assert!(
            (got - want).abs() <= 1e-14 * want.abs().max(1.0),
            "ξ({seed},{step},{ti},{tj}) = {got}, reference {want}"
        );
    }
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
