//! The distance filter of a row: the candidates of one run of bins within the row's reach
//! that the row keeps, branch-free, eight at a time with AVX-512 (the same pairs with every
//! instruction set).

use super::sorted::Sorted;

/// Which candidates in range a run keeps.
#[derive(Clone, Copy)]
pub(super) enum Keep {
    /// All of them (owned partners; ghosts with newton off).
    All,
    /// Ghosts with newton on, for a row of tag t: a larger tag, or tag t (an image of the row's
    /// own atom) when x_j − x_i is positive in z, then y, then x (module docs).
    AboveTag(i32),
}

impl Keep {
    #[inline(always)]
    fn keeps(self, tj: i32, d: [f64; 3]) -> bool {
        match self {
            Keep::All => true,
            Keep::AboveTag(ti) => {
                let up = (d[2] > 0.0)
                    | ((d[2] == 0.0) & ((d[1] > 0.0) | ((d[1] == 0.0) & (d[0] > 0.0))));
                (ti < tj) | ((ti == tj) & up)
            }
        }
    }
}

/// Appends to `nbr` the atoms `run` of `sorted` within `csq` of `xi` that `keep` keeps, in
/// bin order. Branch-free: every candidate is written, the count advances when it is kept
/// (about a third are in range: a branch would be mispredicted). With AVX-512, eight at a
/// time with the same arithmetic ((dx² + dy²) + dz², no FMA), so the same pairs are kept with
/// every instruction set.
#[inline(always)]
pub(super) fn push_run(
    nbr: &mut Vec<i32>,
    sorted: &Sorted,
    run: std::ops::Range<usize>,
    xi: [f64; 3],
    csq: f64,
    keep: Keep,
) {
    if run.is_empty() {
        return;
    }
    let at = nbr.len();
    #[cfg(target_arch = "x86_64")]
    if avx512() {
        // 16 entries of room past the run: the vector loop stores 16 lanes at a time, into
        // the spare capacity (not zeroed first: a memset per run cost 5 % of a Groot–Warren
        // step).
        nbr.reserve(run.len() + 16);
        let out = nbr.spare_capacity_mut().as_mut_ptr() as *mut i32;
        // SAFETY: the CPU has AVX-512F (checked); `run` is within `sorted`'s arrays (bin
        // starts); `out` has room for run.len() + 16 entries (reserved). The loop initialises
        // the first n of them, so the length may grow by n.
        unsafe {
            let n = run_avx512(out, sorted, run, xi, csq, keep);
            nbr.set_len(at + n);
        }
        return;
    }
    nbr.resize(at + run.len(), 0);
    let n = run_scalar(&mut nbr[at..], sorted, run, xi, csq, keep);
    nbr.truncate(at + n);
}

/// [`push_run`]'s portable loop: the kept candidates to the front of `out`; their count.
#[inline(always)]
fn run_scalar(
    out: &mut [i32],
    sorted: &Sorted,
    run: std::ops::Range<usize>,
    xi: [f64; 3],
    csq: f64,
    keep: Keep,
) -> usize {
    let mut n = 0usize;
    let (xs, ys, zs, order, tags) = sorted.run(run);
    for ((((&x, &y), &z), &j), &tj) in xs.iter().zip(ys).zip(zs).zip(order).zip(tags) {
        let d = [x - xi[0], y - xi[1], z - xi[2]];
        let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        out[n] = j as i32;
        n += ((rsq < csq) & keep.keeps(tj, d)) as usize;
    }
    n
}

/// Whether the CPU has AVX-512F (detected once; off under `cfg(test)` while
/// [`super::tests::SCALAR`] is set on the thread).
#[cfg(target_arch = "x86_64")]
fn avx512() -> bool {
    use std::sync::OnceLock;
    static HAS: OnceLock<bool> = OnceLock::new();
    #[cfg(test)]
    if super::tests::SCALAR.with(|s| s.get()) {
        return false;
    }
    *HAS.get_or_init(|| std::arch::is_x86_feature_detected!("avx512f"))
}

/// [`run_scalar`] eight candidates at a time: their distances, the tag test of
/// [`Keep::AboveTag`] in lanes (a tie, an image of the row's own atom, is settled lane by lane
/// as the scalar loop does), and the kept indices compressed to the front in a register and
/// stored 16 lanes wide.
///
/// # Safety
/// The CPU has AVX-512F; `run` is within `sorted`'s arrays; `out` is valid for writing
/// run.len() + 16 entries.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn run_avx512(
    out: *mut i32,
    sorted: &Sorted,
    run: std::ops::Range<usize>,
    xi: [f64; 3],
    csq: f64,
    keep: Keep,
) -> usize {
    use std::arch::x86_64::*;
    let (xs, ys, zs, order, tags) = sorted.run(run);
    let len = xs.len();
    let (x0, y0, z0) = (
        _mm512_set1_pd(xi[0]),
        _mm512_set1_pd(xi[1]),
        _mm512_set1_pd(xi[2]),
    );
    let cut = _mm512_set1_pd(csq);
    let mut n = 0usize;
    let mut k = 0usize;
    while k < len {
        let lanes = (len - k).min(8);
        let live: __mmask8 = if lanes == 8 { 0xFF } else { (1u8 << lanes) - 1 };
        // SAFETY: lanes past `len` are masked off in every load (no memory is read there);
        // the store writes 16 lanes from n <= k, and k + 16 <= len + 16 entries of `out`.
        unsafe {
            let dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(live, xs.as_ptr().add(k)), x0);
            let dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(live, ys.as_ptr().add(k)), y0);
            let dz = _mm512_sub_pd(_mm512_maskz_loadu_pd(live, zs.as_ptr().add(k)), z0);
            let rsq = _mm512_add_pd(
                _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                _mm512_mul_pd(dz, dz),
            );
            let mut m = _mm512_mask_cmp_pd_mask::<_CMP_LT_OQ>(live, rsq, cut);
            if let Keep::AboveTag(ti) = keep
                && m != 0
            {
                let t = _mm512_maskz_loadu_epi32(live as __mmask16, tags.as_ptr().add(k));
                let tiv = _mm512_set1_epi32(ti);
                let above = _mm512_cmpgt_epi32_mask(t, tiv) as __mmask8;
                let mut tie = _mm512_cmpeq_epi32_mask(t, tiv) as __mmask8 & m;
                let mut kept = m & above;
                while tie != 0 {
                    let l = tie.trailing_zeros() as usize;
                    let j = k + l;
                    let d = [xs[j] - xi[0], ys[j] - xi[1], zs[j] - xi[2]];
                    if keep.keeps(tags[j], d) {
                        kept |= 1 << l;
                    }
                    tie &= tie - 1;
                }
                m = kept;
            }
            let idx =
                _mm512_maskz_loadu_epi32(live as __mmask16, order.as_ptr().add(k) as *const i32);
            let packed = _mm512_maskz_compress_epi32(m as __mmask16, idx);
            _mm512_storeu_si512(out.add(n) as *mut _, packed);
            n += m.count_ones() as usize;
        }
        k += 8;
    }
    n
}
