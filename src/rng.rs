//! Keyed, counter-based random numbers for pair noise.
//!
//! Every random number the physics uses is a pure function of a *key*, never the state of a
//! stream. That is what lets the standalone engine and LAMMPS (any MPI decomposition, newton on
//! or off, any thread count) draw the same ξ_ij for the same pair at the same step.
//!
//! # Algorithm and bit layout (generator version 1, Gaussian mapping version 2)
//! The generator is Philox4x32-10 (Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as easy
//! as 1, 2, 3", SC'11), 10 rounds, multipliers `0xD2511F53`, `0xCD9E8D57`, Weyl key increments
//! `0x9E3779B9`, `0xBB67AE85`. One call maps a 128-bit counter and a 64-bit key to 128 bits:
//!
//! | word | content |
//! |------|---------|
//! | key k0 | `seed` (u32, the `pair_style` seed) |
//! | key k1 | `stream` (u32, the purpose: [`STREAM_PAIR_NOISE`], [`STREAM_VELOCITY`], …; for the pair noise in a box shorter than 2 r_c, the image bytes of [`image_stream`]) |
//! | counter c0 | `step` bits 0–31 |
//! | counter c1 | `step` bits 32–63 |
//! | counter c2 | `min(tag_i, tag_j)` (u32) |
//! | counter c3 | `max(tag_i, tag_j)` (u32) |
//!
//! The four output words o0..o3 become one standard Gaussian by Box–Muller (version 2 of the
//! mapping; version 1 used 53-bit uniforms and libm's `ln`/`cos`):
//! `a = ((o0 << 32) | o1) >> 12`, `b = ((o2 << 32) | o3) >> 12` (52-bit integers),
//! `u1 = 1 − a · 2⁻⁵² ∈ [2⁻⁵², 1]`, `ξ = sqrt(−2 ln u1) · cos(2π b · 2⁻⁵²)`.
//! The tag order is applied inside [`pair_gaussian`], so ξ_ij = ξ_ji by construction.
//!
//! Both functions are evaluated here, in plain IEEE arithmetic, not by the platform's libm: `ln`
//! is fdlibm's `__ieee754_log` (error < 1 ulp) written without branches, and the cosine reduces
//! the angle exactly in integers (the octant is `round(b / 2⁵⁰)`, the remainder `d = b − 2⁵⁰ ·
//! octant` is converted exactly) before fdlibm's `__kernel_sin`/`__kernel_cos` on
//! [−π/4, π/4]. So ξ has the same bits on every machine and in every engine, and a batch of
//! pairs vectorises (no calls, no branches): see [`crate::forces::PairBatch`]. Largest |ξ|:
//! sqrt(−2 ln 2⁻⁵²) = 8.49 (P(|ξ| > 8.49) = 2·10⁻¹⁷).
//!
//! **Uniform pair noise** (`pair_style dpd/nonlinear … noise_dist uniform`, [`uniform_noise_from_bits`]):
//! the same key and counter; `a = ((o0 << 32) | o1) >> 12` (52 bits), `u = (a + ½) 2⁻⁵² ∈ (0, 1)`,
//! `ξ = √3 (2u − 1)`: zero mean, unit variance, symmetric (a ↦ 2⁵² − 1 − a maps ξ to −ξ exactly),
//! |ξ| < √3. No logarithm, no cosine, half the output words.
//!
//! [`keyed_uniform`] (used by `create_atoms … random` and `velocity … dist uniform`) is unchanged
//! from version 1: `b' = ((o2 << 32) | o3) >> 11`, `u = b' · 2⁻⁵³ ∈ [0, 1)`.
//! Known-answer vectors (Random123's) and the Gaussian's test vectors live in `tests/rng.rs`.

/// Stream id of the pair random force ξ_ij (`docs/models.md` §4.2, P-4).
pub const STREAM_PAIR_NOISE: u32 = 0x0000_0001;
/// Stream id used by `velocity … create` (keyed by atom tag and component).
pub const STREAM_VELOCITY: u32 = 0x0000_0002;
/// Stream id used by `create_atoms … random` (keyed by atom tag and component).
pub const STREAM_CREATE_ATOMS: u32 = 0x0000_0003;

/// Stream ids of the three components of the transverse pair noise ξ⃗_ij of
/// `pair_style dpd/nonlinear/ext` (`docs/models.md` P-31): independent of ξ_ij and of each
/// other. Like [`STREAM_PAIR_NOISE`] they are the low byte of the stream word; in a box shorter
/// than 2 r_c the image bytes go above it ([`with_purpose`]).
pub const STREAM_TRANSVERSE: [u32; 3] = [0x0000_0004, 0x0000_0005, 0x0000_0006];

/// A pair-noise stream word (`image_stream`'s, low byte [`STREAM_PAIR_NOISE`]) with its low
/// byte replaced by `purpose`: the same image key for another of the pair's variates. The
/// identity for `purpose` = [`STREAM_PAIR_NOISE`].
#[inline(always)]
pub fn with_purpose(stream: u32, purpose: u32) -> u32 {
    (stream & !0xFF) | (purpose & 0xFF)
}

const PHILOX_M0: u32 = 0xD251_1F53;
const PHILOX_M1: u32 = 0xCD9E_8D57;
const PHILOX_W0: u32 = 0x9E37_79B9;
const PHILOX_W1: u32 = 0xBB67_AE85;

/// Philox4x32 with 10 rounds: the bijection of counter `ctr` under key `key`.
///
/// Written on 64-bit words holding 32-bit values, so that a loop over many counters vectorises
/// into 32×32→64-bit multiplies (`pmuludq`) without packing and unpacking 32-bit lanes: the
/// words c1 and c3 carry the high half of the product above bit 31 between rounds, which only
/// ever reaches a multiply (that reads the low 32 bits) or the final mask. Same function as the
/// textbook 32-bit form (Random123's known answers are in `tests/rng.rs`).
#[inline(always)]
pub fn philox4x32_10(ctr: [u32; 4], key: [u32; 2]) -> [u32; 4] {
    const LOW: u64 = 0xffff_ffff;
    let [mut c0, mut c1, mut c2, mut c3] = ctr.map(u64::from);
    let (mut k0, mut k1) = (key[0], key[1]);
    for round in 0..10 {
        if round > 0 {
            k0 = k0.wrapping_add(PHILOX_W0);
            k1 = k1.wrapping_add(PHILOX_W1);
        }
        let p0 = u64::from(PHILOX_M0) * (c0 & LOW);
        let p1 = u64::from(PHILOX_M1) * (c2 & LOW);
        // New c0 = hi(p1) ^ c1 ^ k0 and c2 = hi(p0) ^ c3 ^ k1 (low 32 bits are what count;
        // the upper bits of c1, c3 are cleared by the `& LOW` before the next use).
        c0 = ((p1 >> 32) ^ c1 ^ u64::from(k0)) & LOW;
        c2 = ((p0 >> 32) ^ c3 ^ u64::from(k1)) & LOW;
        c1 = p1;
        c3 = p0;
    }
    [c0 as u32, c1 as u32, c2 as u32, c3 as u32]
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

/// Two uniforms from 128 bits: `u1 ∈ (0, 1)`, `u2 ∈ [0, 1)`, 53 bits each (the version-1
/// mapping; [`keyed_uniform`] returns `u2`).
#[inline(always)]
pub(crate) fn uniforms_from_bits(o: [u32; 4]) -> (f64, f64) {
    let a = ((u64::from(o[0]) << 32) | u64::from(o[1])) >> 11;
    let b = ((u64::from(o[2]) << 32) | u64::from(o[3])) >> 11;
    ((a as f64 + 0.5) * TWO_POW_M53, b as f64 * TWO_POW_M53)
}

/// One standard Gaussian from 128 bits (Box–Muller, cosine branch; mapping version 2 in the
/// module documentation).
#[inline(always)]
pub fn gaussian_from_bits(o: [u32; 4]) -> f64 {
    let a = ((u64::from(o[0]) << 32) | u64::from(o[1])) >> 12;
    let b = ((u64::from(o[2]) << 32) | u64::from(o[3])) >> 12;
    // u1 = 1 − a 2⁻⁵² ∈ [2⁻⁵², 1], exactly: (1 + a 2⁻⁵²) − 1 is exact, and so is 1 − that.
    let u1 = 1.0 - (f64::from_bits(0x3FF0_0000_0000_0000 | a) - 1.0);
    let radius = (-2.0 * ln_normal(u1)).sqrt();
    radius * cos_turns52(b)
}

/// One zero-mean, unit-variance uniform variate from 128 bits: √3 (2u − 1) with the 52-bit
/// midpoint uniform u = (a + ½) 2⁻⁵² of o0, o1 (module documentation). The variance-matched
/// alternative to [`gaussian_from_bits`] for the pair noise (Groot & Warren 1997; only the first
/// two moments enter the Fokker–Planck limit).
#[inline(always)]
pub fn uniform_noise_from_bits(o: [u32; 4]) -> f64 {
    let a = ((u64::from(o[0]) << 32) | u64::from(o[1])) >> 12;
    // x = 1 + a 2⁻⁵² ∈ [1, 2) exactly (the bits of a as the mantissa, as in
    // `gaussian_from_bits`); 2x − 3 = 2a 2⁻⁵² − 1 and the half step 2⁻⁵² are exact (multiples of
    // 2⁻⁵² below 1 in size), so 2u − 1 = (2a + 1) 2⁻⁵² − 1 has no rounding at all. Bit
    // operations and adds only: vectorises on AVX2 too (no 64-bit integer conversion).
    let x = f64::from_bits(0x3FF0_0000_0000_0000 | a);
    SQRT_3 * ((2.0 * x - 3.0) + TWO_POW_M52)
}

const TWO_POW_M52: f64 = 1.0 / 4_503_599_627_370_496.0;

#[allow(clippy::excessive_precision)]
const SQRT_3: f64 = 1.732_050_807_568_877_293_527_446_341_505_872_367;

// fdlibm's constants, digit for digit (here and in the kernels below).
#[allow(clippy::excessive_precision)]
const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
#[allow(clippy::excessive_precision)]
const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;

/// ln x for a normal, finite x > 0 (fdlibm `__ieee754_log`, both of its branches evaluated and
/// selected, so the function is straight-line code; error < 1 ulp). Zero, subnormal, negative,
/// infinite and NaN arguments are outside its domain (the Box–Muller u1 ≥ 2⁻⁵² never is).
#[allow(clippy::excessive_precision)]
#[inline(always)]
pub fn ln_normal(x: f64) -> f64 {
    const LG1: f64 = 6.666_666_666_666_735_130e-1;
    const LG2: f64 = 3.999_999_999_940_941_908e-1;
    const LG3: f64 = 2.857_142_874_366_239_149e-1;
    const LG4: f64 = 2.222_219_843_214_978_396e-1;
    const LG5: f64 = 1.818_357_216_161_805_012e-1;
    const LG6: f64 = 1.531_383_769_920_937_332e-1;
    const LG7: f64 = 1.479_819_860_511_658_591e-1;
    let bits = x.to_bits();
    let hx = (bits >> 32) as i64;
    // Exponent, and the mantissa scaled into [sqrt(2)/2, sqrt(2)).
    let mut k = (hx >> 20) - 1023;
    let m = hx & 0x000f_ffff;
    let i = (m + 0x95f64) & 0x0010_0000;
    let hi = (m | (i ^ 0x3ff0_0000)) as u64;
    k += i >> 20;
    let f = f64::from_bits((hi << 32) | (bits & 0xffff_ffff)) - 1.0;
    let s = f / (2.0 + f);
    let dk = k as f64;
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    let hfsq = 0.5 * f * f;
    // fdlibm's `i > 0` test: the mantissa is far enough from 1 that the hfsq form is the
    // accurate one. Both forms reduce exactly to fdlibm's k = 0 expressions when k = 0.
    let far = ((m - 0x6147a) | (0x6b851 - m)) > 0;
    let with_hfsq = dk * LN2_HI - ((hfsq - (s * (hfsq + r) + dk * LN2_LO)) - f);
    let without = dk * LN2_HI - ((s * (f - r) - dk * LN2_LO) - f);
    if far { with_hfsq } else { without }
}

/// fdlibm `__kernel_sin(x, 0, 0)` for |x| ≤ π/4.
#[allow(clippy::excessive_precision)]
#[inline(always)]
fn kernel_sin(x: f64) -> f64 {
    const S1: f64 = -1.666_666_666_666_663_243_48e-1;
    const S2: f64 = 8.333_333_333_322_489_461_24e-3;
    const S3: f64 = -1.984_126_982_985_794_931_34e-4;
    const S4: f64 = 2.755_731_370_707_006_767_89e-6;
    const S5: f64 = -2.505_076_025_340_686_341_95e-8;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    let z = x * x;
    let v = z * x;
    let r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    x + v * (S1 + z * r)
}

/// fdlibm `__kernel_cos(x, 0)` for |x| ≤ π/4, both branches evaluated and selected.
#[allow(clippy::excessive_precision)]
#[inline(always)]
fn kernel_cos(x: f64) -> f64 {
    const C1: f64 = 4.166_666_666_666_660_190_37e-2;
    const C2: f64 = -1.388_888_888_887_410_957_49e-3;
    const C3: f64 = 2.480_158_728_947_672_941_78e-5;
    const C4: f64 = -2.755_731_435_139_066_330_35e-7;
    const C5: f64 = 2.087_572_321_298_174_827_90e-9;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    let z = x * x;
    let r = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let small = 1.0 - (0.5 * z - z * r);
    // |x| ≥ 0.3: subtract qx = x/4 rounded down to 21 mantissa bits (fdlibm), or 0.28125 when
    // |x| > 0.78125 (never reached for |x| ≤ π/4 but kept for fidelity).
    let ax = x.abs();
    let qx = if ax > 0.78125 {
        0.28125
    } else {
        f64::from_bits(ax.to_bits().wrapping_sub(0x0020_0000_0000_0000) & 0xffff_ffff_0000_0000)
    };
    let hz = 0.5 * z - qx;
    let large = (1.0 - qx) - (hz - z * r);
    if ax < 0.3 { small } else { large }
}

/// cos(2π b 2⁻⁵²) for a 52-bit integer b, with the angle reduced exactly in integers.
#[inline(always)]
fn cos_turns52(b: u64) -> f64 {
    // 2π · 2⁻⁵², rounded to nearest.
    const TWO_PI_2M52: f64 = std::f64::consts::TAU / 4_503_599_627_370_496.0;
    // Octant boundaries: q = round(4 b 2⁻⁵²) mod 4, d = b − q 2⁵⁰ ∈ [−2⁴⁹, 2⁴⁹].
    let qr = (b + (1 << 49)) >> 50;
    let d = b as i64 - (qr << 50) as i64;
    let q = qr & 3;
    // d → f64 exactly (|d| < 2⁵¹) through the 1.5·2⁵² bias, then φ = 2π d 2⁻⁵² ∈ [−π/4, π/4].
    const BIAS: f64 = 6_755_399_441_055_744.0;
    let df = f64::from_bits(BIAS.to_bits().wrapping_add(d as u64)) - BIAS;
    let phi = df * TWO_PI_2M52;
    let (s, c) = (kernel_sin(phi), kernel_cos(phi));
    // cos(q π/2 + φ) = cos φ, −sin φ, −cos φ, sin φ.
    let v = if q & 1 == 0 { c } else { s };
    if q == 1 || q == 2 { -v } else { v }
}

/// The periodic lattice of a box, for the image part of the pair-noise key (`docs/models.md`
/// P-4b): in a box shorter than 2 r_c along a periodic axis, atom i can interact with several
/// periodic images of atom j at once, and each image pair must draw its own ξ. The image is
/// named by integer coordinates n = (n_x, n_y, n_z) of the separation r_lo − r_hi (lower tag
/// minus higher tag) in the lattice a = (L_x, 0, 0), b = (xy, L_y, 0), c = (xz, yz, L_z)
/// (LAMMPS's box; the standalone engine's Lees–Edwards offset is its xy):
/// n_z = round(d_z / L_z), d ← d − n_z c, n_y = round(d_y / L_y), d ← d − n_y b,
/// n_x = round(d_x / L_x), rounding half away from zero, a non-periodic axis giving 0. The tilts
/// are first reduced into [0, L) (xy and xz by L_x, yz by L_y, with xz following the change of
/// c by b), so a box and its flipped twin (the same lattice) name every image alike. Properties
/// (tests/small_box.rs): n(−d) = −n(d); images differing by a lattice vector m get codes
/// differing by m; and when every periodic length is ≥ 2 r_c, |d| < r_c gives n = 0, the
/// stream of [`STREAM_PAIR_NOISE`] unchanged, so every existing key keeps its numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageFrame {
    len: [f64; 3],
    inv_len: [f64; 3],
    /// xy, xz, yz, reduced.
    tilt: [f64; 3],
    /// Which axes are periodic (false past the dimension).
    periodic: [bool; 3],
}

impl ImageFrame {
    /// The frame of a box with side lengths `len`, tilts `[xy, xz, yz]` (0 for an orthogonal
    /// box) and periodic flags for the first `dim` axes.
    pub fn new(dim: usize, len: [f64; 3], tilt: [f64; 3], periodic: [bool; 3]) -> ImageFrame {
        let reduce = |t: f64, l: f64| -> (f64, f64) {
            let k = (t / l).floor();
            let r = t - k * l;
            if r >= l || r < 0.0 { (0.0, k) } else { (r, k) }
        };
        let (xy, _) = reduce(tilt[0], len[0]);
        // c ← c − k b with k = ⌊yz / L_y⌋: yz into [0, L_y), xz follows by −k xy.
        let (yz, k) = reduce(tilt[2], len[1]);
        let (xz, _) = reduce(tilt[1] - k * xy, len[0]);
        let mut p = [false; 3];
        p[..dim.min(3)].copy_from_slice(&periodic[..dim.min(3)]);
        ImageFrame {
            len,
            inv_len: len.map(|l| 1.0 / l),
            tilt: [xy, xz, yz],
            periodic: p,
        }
    }

    /// The image coordinates n of a separation `d` (see the type).
    #[inline]
    pub fn image_of(&self, mut d: [f64; 3]) -> [i32; 3] {
        let round = |y: f64| (y + 0.5f64.copysign(y)) as i64 as f64;
        let mut n = [0.0; 3];
        if self.periodic[2] {
            n[2] = round(d[2] * self.inv_len[2]);
            d[0] -= n[2] * self.tilt[1];
            d[1] -= n[2] * self.tilt[2];
        }
        if self.periodic[1] {
            n[1] = round(d[1] * self.inv_len[1]);
            d[0] -= n[1] * self.tilt[0];
        }
        if self.periodic[0] {
            n[0] = round(d[0] * self.inv_len[0]);
        }
        n.map(|v| v.clamp(-127.0, 127.0) as i32)
    }

    /// The pair-noise stream of the pair (tag_i, tag_j) at separation `dr` = r_i − r_j:
    /// [`image_stream`] of the image coordinates of r_lo − r_hi.
    #[inline]
    pub fn pair_stream(&self, tag_i: u32, tag_j: u32, dr: [f64; 3]) -> u32 {
        let d = if tag_i <= tag_j { dr } else { dr.map(|c| -c) };
        image_stream(self.image_of(d))
    }
}

/// The stream word of the pair noise for image coordinates `n` (P-4b): [`STREAM_PAIR_NOISE`]
/// for n = 0, else with n_x, n_y, n_z as bytes (two's complement) in bits 8–15, 16–23, 24–31,
/// a word no other stream uses.
#[inline(always)]
pub fn image_stream(n: [i32; 3]) -> u32 {
    STREAM_PAIR_NOISE
        | (u32::from(n[0] as i8 as u8) << 8)
        | (u32::from(n[1] as i8 as u8) << 16)
        | (u32::from(n[2] as i8 as u8) << 24)
}

/// ξ_ij: the standard Gaussian of pair (i, j) at `step`, symmetric in the two tags.
#[inline(always)]
pub fn pair_gaussian(seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
    let (lo, hi) = ordered_tags(tag_i, tag_j);
    gaussian_from_bits(keyed_bits(seed, STREAM_PAIR_NOISE, step, lo, hi))
}

/// The pair's uniform noise variate (zero mean, unit variance; [`uniform_noise_from_bits`]),
/// keyed as [`pair_gaussian`]: `noise_dist uniform`.
#[inline(always)]
pub fn pair_uniform_noise(seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
    let (lo, hi) = ordered_tags(tag_i, tag_j);
    uniform_noise_from_bits(keyed_bits(seed, STREAM_PAIR_NOISE, step, lo, hi))
}

/// The distribution of the pair variate ξ_ij (`pair_style … noise_dist gaussian|uniform`;
/// docs/models.md §4.2, P-4a). Both have zero mean and unit variance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NoiseDist {
    /// Standard Gaussian (Box–Muller on the keyed bits): the papers' choice, the default.
    #[default]
    Gaussian,
    /// Uniform on [−√3, √3] from the same keyed bits (Groot & Warren 1997): no ln or cos.
    Uniform,
}

impl NoiseDist {
    /// The keyword used by `pair_style … noise_dist KEYWORD`.
    pub fn keyword(self) -> &'static str {
        match self {
            NoiseDist::Gaussian => "gaussian",
            NoiseDist::Uniform => "uniform",
        }
    }

    /// Parse a `noise_dist` keyword value.
    pub fn from_keyword(s: &str) -> Option<NoiseDist> {
        match s {
            "gaussian" => Some(NoiseDist::Gaussian),
            "uniform" => Some(NoiseDist::Uniform),
            _ => None,
        }
    }

    /// ξ_ij of the pair (tags in either order) at `step`.
    #[inline(always)]
    pub fn pair_xi(self, seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
        match self {
            NoiseDist::Gaussian => pair_gaussian(seed, step, tag_i, tag_j),
            NoiseDist::Uniform => pair_uniform_noise(seed, step, tag_i, tag_j),
        }
    }
}

/// ξ⃗_ij: the transverse noise vector of pair (i, j) at `step` (`docs/models.md` P-31), drawn
/// from `dist` for the ordered tags (component k from stream [`STREAM_TRANSVERSE`]`[k]`) and
/// negated when `tag_i > tag_j`, so ξ⃗_ji = −ξ⃗_ij exactly. `dim` 2: the z component is 0.
#[inline(always)]
pub fn pair_transverse(
    dist: NoiseDist,
    seed: u32,
    step: u64,
    tag_i: u32,
    tag_j: u32,
    dim: u32,
) -> [f64; 3] {
    let (lo, hi) = ordered_tags(tag_i, tag_j);
    let sign = if tag_i > tag_j { -1.0 } else { 1.0 };
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        if k == 2 && dim == 2 {
            break;
        }
        let o = keyed_bits(seed, STREAM_TRANSVERSE[k], step, lo, hi);
        let v = match dist {
            NoiseDist::Gaussian => gaussian_from_bits(o),
            NoiseDist::Uniform => uniform_noise_from_bits([o[0], o[1], 0, 0]),
        };
        *xk = if sign < 0.0 { -v } else { v };
    }
    x
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
