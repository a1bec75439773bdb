//! What every pair kernel of the forces layer shares: the lane batch ([`PairBatch`], up to
//! [`BATCH`] pairs in structure-of-arrays form), the instruction sets of the lane loops
//! ([`Isa`]), the keyed pair noise of a batch's lanes (`docs/models.md` P-4, P-4a, P-4b) and the
//! pair geometry's small helpers. The styles' batch kernels (DPD's `pair_forces_batch`, sDPD's
//! `sdpd_forces_batch`) read the lanes the pair loops fill and write `fpair` and `energy`.

/// Pairs closer than this are skipped (their direction e_ij is undefined), as LAMMPS's DPD does.
pub(crate) const MIN_PAIR_DISTANCE: f64 = 1.0e-10;

pub use crate::rng::NoiseDist;

#[inline(always)]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// True when a pair at squared distance `rsq` interacts: `MIN_PAIR_DISTANCE² ≤ rsq < rc²`.
#[inline(always)]
pub fn in_range(rsq: f64, rc: f64) -> bool {
    rsq < rc * rc && rsq >= MIN_PAIR_DISTANCE * MIN_PAIR_DISTANCE
}

/// Pairs per [`PairBatch`].
pub const BATCH: usize = 64;

/// Up to [`BATCH`] pairs in structure-of-arrays form, for [`pair_forces_batch`](crate::forces::dpd::kernel::pair_forces_batch): the inputs of
/// [`pair_force`](crate::forces::dpd::kernel::pair_force) for each pair, with the pair's tags in place of its Gaussian (the batch draws
/// ξ_ij itself, [`crate::rng::pair_gaussian`]) and an index into the caller's coefficient table.
#[derive(Clone, Debug)]
pub struct PairBatch {
    /// Number of pairs filled (≤ [`BATCH`]).
    pub len: usize,
    /// r_ij by component: `dr[k][l]` is component k of pair l.
    pub dr: [[f64; BATCH]; 3],
    /// v_ij by component (with any Lees–Edwards velocity offset already added).
    pub dv: [[f64; BATCH]; 3],
    /// 1/m_i + 1/m_j.
    pub inv_mass_sum: [f64; BATCH],
    /// Index of the pair's coefficients in the table passed to [`pair_forces_batch`](crate::forces::dpd::kernel::pair_forces_batch).
    pub coeff: [u32; BATCH],
    /// Tag of i.
    pub tag_i: [u32; BATCH],
    /// Tag of j.
    pub tag_j: [u32; BATCH],
    /// Result: the total pair force divided by r, so the force on i is `fpair · r_ij`
    /// (0 for a pair out of range). Entries from `len` on are unspecified.
    pub fpair: [f64; BATCH],
    /// Result: the conservative pair energy (0 for a pair out of range). Entries from `len` on
    /// are unspecified.
    pub energy: [f64; BATCH],
    /// Result of a kernel with a non-central part (`dpd/nonlinear/ext`'s perpendicular friction
    /// and noise, docs/models.md §4.11): that part of the force on i by component, `ft[k][l]`,
    /// added to `fpair · r_ij` when [`PairBatch::transverse`] is set (−it on j).
    pub ft: [[f64; BATCH]; 3],
    /// Set by a kernel that wrote [`PairBatch::ft`]; central kernels leave it false.
    pub transverse: bool,
    /// Working arrays of [`pair_forces_batch`](crate::forces::dpd::kernel::pair_forces_batch) (kept here so that no call zeroes them).
    pub(crate) scratch: BatchScratch,
    /// (Last, after the lane arrays, so that their alignment is that of the struct.) The box's lattice when it is shorter than 2 r_c along a periodic axis: each lane's
    /// noise is then keyed by the periodic image of its pair too
    /// ([`crate::rng::ImageFrame::pair_stream`], `docs/models.md` P-4b). None: the plain key
    /// (every image code would be 0).
    pub images: Option<crate::rng::ImageFrame>,
}

/// Lane arrays of per-pair coefficients a batch kernel gathers from its table (a kernel names
/// its own rows; DPD's are listed in its `batch.rs`).
pub(crate) type CoeffLanes = [[f64; BATCH]; COEFF_LANES];

/// Rows of [`CoeffLanes`].
pub(crate) const COEFF_LANES: usize = 7;

/// The results of a batch kernel's stages for each lane, between its loops: `g` seven values
/// of the pair's geometry, `gs` three of its friction (what each row holds is the kernel's).
#[derive(Clone, Debug)]
pub(crate) struct StageArrays {
    pub(crate) g: [[f64; BATCH]; 7],
    pub(crate) gs: [[f64; BATCH]; 3],
}

/// The per-lane coefficients, random bits, Gaussians and stage results of one batch
/// evaluation: plain lane arrays that any style's batch kernel may use, so that none of them
/// is allocated or zeroed per call.
#[derive(Clone, Debug)]
pub(crate) struct BatchScratch {
    pub(crate) co: CoeffLanes,
    pub(crate) bits: [[u32; BATCH]; 4],
    pub(crate) xi: [f64; BATCH],
    pub(crate) st: StageArrays,
    /// The transverse noise vector ξ⃗_ij of each lane (`dpd/nonlinear/ext`), by component.
    pub(crate) xt: [[f64; BATCH]; 3],
}

impl Default for PairBatch {
    fn default() -> Self {
        PairBatch {
            len: 0,
            dr: [[0.0; BATCH]; 3],
            dv: [[0.0; BATCH]; 3],
            inv_mass_sum: [0.0; BATCH],
            coeff: [0; BATCH],
            tag_i: [0; BATCH],
            tag_j: [0; BATCH],
            images: None,
            fpair: [0.0; BATCH],
            energy: [0.0; BATCH],
            ft: [[0.0; BATCH]; 3],
            transverse: false,
            scratch: BatchScratch {
                co: [[0.0; BATCH]; COEFF_LANES],
                bits: [[0; BATCH]; 4],
                xi: [0.0; BATCH],
                st: StageArrays {
                    g: [[0.0; BATCH]; 7],
                    gs: [[0.0; BATCH]; 3],
                },
                xt: [[0.0; BATCH]; 3],
            },
        }
    }
}

/// Instruction sets [`pair_forces_batch`](crate::forces::dpd::kernel::pair_forces_batch) can use (chosen at run time; the results are the same
/// bits with each, since the arithmetic is IEEE and never fused).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Isa {
    /// Baseline x86-64 / any target: SSE2 vectors (2 lanes) or scalar code.
    Baseline,
    /// AVX2 + FMA (4 lanes; FMA instructions are available but never used for a·b + c).
    Avx2,
    /// AVX-512 F/DQ/VL/BW (8 lanes).
    Avx512,
}

impl Isa {
    /// The best instruction set this CPU has, capped by the environment variable `DPDNL_SIMD`
    /// (`baseline`, `avx2` or `avx512`; for benchmarks and tests), read once.
    pub fn detect() -> Isa {
        static ISA: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *ISA.get_or_init(|| {
            let best = Isa::best_supported();
            let cap = match std::env::var("DPDNL_SIMD").as_deref() {
                Ok("baseline") => Isa::Baseline,
                Ok("avx2") => Isa::Avx2,
                _ => Isa::Avx512,
            };
            if (cap as u8) < (best as u8) {
                cap
            } else {
                best
            }
        })
    }

    /// The best instruction set the CPU supports, probed once (the hot loops ask per batch
    /// and per list row; ten feature tests each time were 1 % of the LAMMPS path's profile).
    pub fn best_supported() -> Isa {
        static BEST: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *BEST.get_or_init(Isa::probe)
    }

    /// The CPU's feature tests behind [`Isa::best_supported`].
    fn probe() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512dq")
                && std::arch::is_x86_feature_detected!("avx512vl")
                && std::arch::is_x86_feature_detected!("avx512bw")
                && std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
                && std::arch::is_x86_feature_detected!("popcnt")
                && std::arch::is_x86_feature_detected!("bmi1")
                && std::arch::is_x86_feature_detected!("bmi2")
                && std::arch::is_x86_feature_detected!("lzcnt")
            {
                return Isa::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
                && std::arch::is_x86_feature_detected!("popcnt")
                && std::arch::is_x86_feature_detected!("bmi1")
                && std::arch::is_x86_feature_detected!("bmi2")
                && std::arch::is_x86_feature_detected!("lzcnt")
            {
                return Isa::Avx2;
            }
        }
        Isa::Baseline
    }
}

/// ξ_ij of every lane into `b.scratch.xi` (all [`BATCH`] lanes: those past `b.len` get
/// garbage from stale tags that nobody reads): [`crate::rng::pair_gaussian`] of the lane's tags,
/// in two loops (random bits, then Gaussians) that run in SIMD lanes.
#[inline(always)]
pub(crate) fn pair_gaussians(b: &mut PairBatch, seed: u32, step: u64) {
    lane_bits(b, seed, step, crate::rng::STREAM_PAIR_NOISE);
    let bits = &b.scratch.bits;
    let xi = &mut b.scratch.xi;
    for l in 0..BATCH {
        xi[l] = crate::rng::gaussian_from_bits([bits[0][l], bits[1][l], bits[2][l], bits[3][l]]);
    }
}

/// The keyed bits of every lane into `b.scratch.bits` (P-4; with [`PairBatch::images`], each
/// lane's stream names its pair's periodic image, P-4b), for the stream `purpose` (its low
/// byte; [`crate::rng::STREAM_PAIR_NOISE`] for ξ_ij, [`crate::rng::STREAM_TRANSVERSE`] for
/// the components of ξ⃗_ij).
#[inline(always)]
fn lane_bits(b: &mut PairBatch, seed: u32, step: u64, purpose: u32) {
    let bits = &mut b.scratch.bits;
    match &b.images {
        None => {
            for l in 0..BATCH {
                let (lo, hi) = crate::rng::ordered_tags(b.tag_i[l], b.tag_j[l]);
                let o = crate::rng::keyed_bits(seed, purpose, step, lo, hi);
                bits[0][l] = o[0];
                bits[1][l] = o[1];
                bits[2][l] = o[2];
                bits[3][l] = o[3];
            }
        }
        Some(frame) => {
            for l in 0..BATCH {
                let (ti, tj) = (b.tag_i[l], b.tag_j[l]);
                let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
                let stream = crate::rng::with_purpose(frame.pair_stream(ti, tj, dr), purpose);
                let (lo, hi) = crate::rng::ordered_tags(ti, tj);
                let o = crate::rng::keyed_bits(seed, stream, step, lo, hi);
                bits[0][l] = o[0];
                bits[1][l] = o[1];
                bits[2][l] = o[2];
                bits[3][l] = o[3];
            }
        }
    }
}

/// ξ_ij of every lane from `dist` (as [`pair_gaussians`]; the uniform variate needs only the
/// first two words of the keyed bits and no ln or cos, [`crate::rng::uniform_noise_from_bits`]).
#[inline(always)]
pub(crate) fn pair_noise(b: &mut PairBatch, seed: u32, step: u64, dist: NoiseDist) {
    if dist == NoiseDist::Gaussian {
        return pair_gaussians(b, seed, step);
    }
    lane_bits(b, seed, step, crate::rng::STREAM_PAIR_NOISE);
    let bits = &b.scratch.bits;
    let xi = &mut b.scratch.xi;
    for l in 0..BATCH {
        xi[l] = crate::rng::uniform_noise_from_bits([bits[0][l], bits[1][l], 0, 0]);
    }
}

/// The transverse noise vector ξ⃗_ij of every lane into `b.scratch.xt` (docs/models.md P-31):
/// component k from the stream [`crate::rng::STREAM_TRANSVERSE`]`[k]`, drawn for the ordered
/// tags (min, max) as ξ_ij is, then negated when tag_i > tag_j, so ξ⃗_ji = −ξ⃗_ij
/// ([`crate::rng::pair_transverse`], the same bits). `dim` 2: the z component is 0.
#[inline(always)]
pub(crate) fn pair_transverse_noise(
    b: &mut PairBatch,
    seed: u32,
    step: u64,
    dist: NoiseDist,
    dim: u32,
) {
    for k in 0..3 {
        if k == 2 && dim == 2 {
            b.scratch.xt[2] = [0.0; BATCH];
            continue;
        }
        lane_bits(b, seed, step, crate::rng::STREAM_TRANSVERSE[k]);
        let bits = &b.scratch.bits;
        let out = &mut b.scratch.xt[k];
        for l in 0..BATCH {
            let o = [bits[0][l], bits[1][l], bits[2][l], bits[3][l]];
            let x = match dist {
                NoiseDist::Gaussian => crate::rng::gaussian_from_bits(o),
                NoiseDist::Uniform => crate::rng::uniform_noise_from_bits([o[0], o[1], 0, 0]),
            };
            out[l] = if b.tag_i[l] > b.tag_j[l] { -x } else { x };
        }
    }
}

/// The lane Gaussians left by the last [`pair_gaussians`].
#[inline(always)]
pub(crate) fn lane_gaussians(b: &PairBatch) -> &[f64; BATCH] {
    &b.scratch.xi
}
