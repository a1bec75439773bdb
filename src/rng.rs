//! Keyed, counter-based random numbers for pair noise.
//!
//! Every random number the physics uses is a pure function of a *key*, never the state of a
//! stream. That is what lets the standalone engine and LAMMPS (any MPI decomposition, newton on
//! or off, any thread count) draw the same ξ_ij for the same pair at the same step.
//!
//! # Algorithm and bit layout (version 1)
//! The generator is Philox4x32-10 (Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as easy
//! as 1, 2, 3", SC'11), 10 rounds, multipliers `0xD2511F53`, `0xCD9E8D57`, Weyl key increments
//! `0x9E3779B9`, `0xBB67AE85`. One call maps a 128-bit counter and a 64-bit key to 128 bits:
//!
//! | word | content |
//! |------|---------|
//! | key k0 | `seed` (u32, the `pair_style` seed) |
//! | key k1 | `stream` (u32, the purpose: [`STREAM_PAIR_NOISE`], [`STREAM_VELOCITY`], …) |
//! | counter c0 | `step` bits 0–31 |
//! | counter c1 | `step` bits 32–63 |
//! | counter c2 | `min(tag_i, tag_j)` (u32) |
//! | counter c3 | `max(tag_i, tag_j)` (u32) |
//!
//! The four output words o0..o3 become one standard Gaussian by Box–Muller:
//! `a = ((o0 << 32) | o1) >> 11`, `b = ((o2 << 32) | o3) >> 11` (53-bit integers),
//! `u1 = (a + 0.5) · 2⁻⁵³ ∈ (0, 1)`, `u2 = b · 2⁻⁵³ ∈ [0, 1)`,
//! `ξ = sqrt(−2 ln u1) · cos(2π u2)`.
//! The tag order is applied inside [`pair_gaussian`], so ξ_ij = ξ_ji by construction.
//! Known-answer vectors (Random123's) and the Gaussian's test vectors live in `tests/rng.rs`.

/// Stream id of the pair random force ξ_ij (MODELS §1).
pub const STREAM_PAIR_NOISE: u32 = 0x0000_0001;
/// Stream id used by `velocity … create` (keyed by atom tag and component).
pub const STREAM_VELOCITY: u32 = 0x0000_0002;
/// Stream id used by `create_atoms … random` (keyed by atom tag and component).
pub const STREAM_CREATE_ATOMS: u32 = 0x0000_0003;

const PHILOX_M0: u32 = 0xD251_1F53;
const PHILOX_M1: u32 = 0xCD9E_8D57;
const PHILOX_W0: u32 = 0x9E37_79B9;
const PHILOX_W1: u32 = 0xBB67_AE85;

#[inline(always)]
fn mulhilo(a: u32, b: u32) -> (u32, u32) {
    let p = u64::from(a) * u64::from(b);
    ((p >> 32) as u32, p as u32)
}

/// Philox4x32 with 10 rounds: the bijection of counter `ctr` under key `key`.
#[inline(always)]
pub fn philox4x32_10(ctr: [u32; 4], key: [u32; 2]) -> [u32; 4] {
    let mut c = ctr;
    let mut k = key;
    for round in 0..10 {
        if round > 0 {
            k[0] = k[0].wrapping_add(PHILOX_W0);
            k[1] = k[1].wrapping_add(PHILOX_W1);
        }
        let (hi0, lo0) = mulhilo(PHILOX_M0, c[0]);
        let (hi1, lo1) = mulhilo(PHILOX_M1, c[2]);
        c = [hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0];
    }
    c
}

/// The ordered tag pair `(min, max)`: the one place the pair order is decided.
#[inline(always)]
pub fn ordered_tags(tag_i: u32, tag_j: u32) -> (u32, u32) {
    if tag_i <= tag_j {
        (tag_i, tag_j)
    } else {
        (tag_j, tag_i)
    }
}

/// The raw 128 bits for key `(seed, stream)` and counter `(step, lo, hi)`, with no reordering.
#[inline(always)]
pub fn keyed_bits(seed: u32, stream: u32, step: u64, lo: u32, hi: u32) -> [u32; 4] {
    philox4x32_10([step as u32, (step >> 32) as u32, lo, hi], [seed, stream])
}

const TWO_POW_M53: f64 = 1.0 / 9_007_199_254_740_992.0;

/// Two uniforms from 128 bits: `u1 ∈ (0, 1)`, `u2 ∈ [0, 1)`, 53 bits each.
#[inline(always)]
pub fn uniforms_from_bits(o: [u32; 4]) -> (f64, f64) {
    let a = ((u64::from(o[0]) << 32) | u64::from(o[1])) >> 11;
    let b = ((u64::from(o[2]) << 32) | u64::from(o[3])) >> 11;
    ((a as f64 + 0.5) * TWO_POW_M53, b as f64 * TWO_POW_M53)
}

/// One standard Gaussian from 128 bits (Box–Muller, cosine branch).
#[inline(always)]
pub fn gaussian_from_bits(o: [u32; 4]) -> f64 {
    let (u1, u2) = uniforms_from_bits(o);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// ξ_ij: the standard Gaussian of pair (i, j) at `step`, symmetric in the two tags.
#[inline(always)]
pub fn pair_gaussian(seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
    let (lo, hi) = ordered_tags(tag_i, tag_j);
    gaussian_from_bits(keyed_bits(seed, STREAM_PAIR_NOISE, step, lo, hi))
}

/// A uniform in `[0, 1)` keyed by `(seed, stream, step, a, b)` (no reordering of `a`, `b`).
#[inline]
pub fn keyed_uniform(seed: u32, stream: u32, step: u64, a: u32, b: u32) -> f64 {
    uniforms_from_bits(keyed_bits(seed, stream, step, a, b)).1
}

/// A standard Gaussian keyed by `(seed, stream, step, a, b)` (no reordering of `a`, `b`).
#[inline]
pub fn keyed_gaussian(seed: u32, stream: u32, step: u64, a: u32, b: u32) -> f64 {
    gaussian_from_bits(keyed_bits(seed, stream, step, a, b))
}
