//! The near pass of one row and the cell scan of a list build with AVX2: four entries at a time,
//! the in-range ones moved to the front of the vectors by a permutation table (AVX2 has no
//! compress instruction) and stored whole. Same pairs, same order, same bits as the portable
//! `near_row` and scan: the arithmetic is the same IEEE operations in the same order (no FMA),
//! and only which entries are kept depends on it. The building blocks (loads, tables) are in
//! `engine::simd::avx2`, shared with the C ABI's list walk.
use super::slab::{PassConst, Pending, RowArgs, Sink};
use crate::engine::simd::avx2::{front_epi32, front_pd, load4, separation};
use crate::forces::BATCH;
use std::arch::x86_64::*;

// Whole 4-lane chunks fit in the batch arrays.
const _: () = assert!(BATCH.is_multiple_of(4));

/// |v| ≥ q per lane (`v` and `q` finite or not: the same comparison as `f64::abs() >= q`).
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
#[inline]
fn abs_ge(v: __m256d, q: __m256d) -> __m256d {
    let abs = _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
    _mm256_cmp_pd::<_CMP_GE_OQ>(abs, q)
}

/// The near pass of one row ([`super::slab::near_row`]'s contract): the in-range near pairs
/// appended to the batch in row order, the row positions of the entries through a periodic
/// boundary pushed to `far_list`.
///
/// # Safety
/// The CPU has AVX2, and every index in `r.row` is < `pc.x.len()` = `pc.v.len()` =
/// `pc.tag.len()` (and, with more than one type, `r.row_t + typ[j] < pc.rcsq.len()` and
/// `typ[j] < pc.inv_mass.len()`).
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) unsafe fn near_row<const ONE_TYPE: bool>(
    r: &RowArgs,
    pc: &PassConst,
    p: &mut Pending,
    len: &mut usize,
    far_list: &mut Vec<u32>,
    sink: &mut Sink,
) {
    let xi = r.xi.map(|c| _mm256_set1_pd(c));
    let vi = r.vi.map(|c| _mm256_set1_pd(c));
    let q = pc.quarter.map(|c| _mm256_set1_pd(c));
    let min_sq = _mm256_set1_pd(pc.min_sq);
    let ivec = _mm_set1_epi32(r.i as i32);
    let tagi = _mm_set1_epi32(r.tag_i as i32);
    let xp = pc.x.as_ptr() as *const f64;
    let vp = pc.v.as_ptr() as *const f64;
    let m = r.row.len();
    if m == 0 {
        return;
    }
    let mut k0 = 0;
    while k0 < m {
        if *len > BATCH - 4 {
            sink.evaluate::<ONE_TYPE>(p, len);
        }
        let lanes = (m - k0).min(4);
        // Entries past the row's end repeat its last atom; their lanes are masked off.
        let jt: [u32; 4] = std::array::from_fn(|t| r.row[(k0 + t).min(m - 1)]);
        let j = jt.map(|v| v as usize);
        let live = (1usize << lanes) - 1;
        // SAFETY (all pointer reads and writes below): indices are valid by the caller's
        // contract; `*len + 4 <= BATCH`, so every 4-lane store stays inside the batch arrays
        // (lanes past the kept ones are overwritten by later appends or never read).
        unsafe {
            let ([dx, dy, dz], rsq) = separation(xi, load4(xp, j));
            let (rcsq, coeff, ims) = if ONE_TYPE {
                (
                    _mm256_set1_pd(pc.one_rcsq),
                    _mm_set1_epi32(pc.one_coeff as i32),
                    _mm256_set1_pd(pc.ims_one),
                )
            } else {
                let tj = j.map(|j| pc.typ[j] as usize);
                let ci = tj.map(|t| r.row_t + t);
                (
                    _mm256_set_pd(
                        pc.rcsq[ci[3]],
                        pc.rcsq[ci[2]],
                        pc.rcsq[ci[1]],
                        pc.rcsq[ci[0]],
                    ),
                    _mm_set_epi32(ci[3] as i32, ci[2] as i32, ci[1] as i32, ci[0] as i32),
                    _mm256_set_pd(
                        r.inv_mi + pc.inv_mass[tj[3]],
                        r.inv_mi + pc.inv_mass[tj[2]],
                        r.inv_mi + pc.inv_mass[tj[1]],
                        r.inv_mi + pc.inv_mass[tj[0]],
                    ),
                )
            };
            let inside = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_LT_OQ>(rsq, rcsq),
                _mm256_cmp_pd::<_CMP_GE_OQ>(rsq, min_sq),
            );
            let far = _mm256_or_pd(
                _mm256_or_pd(abs_ge(dx, q[0]), abs_ge(dy, q[1])),
                abs_ge(dz, q[2]),
            );
            let far_bits = _mm256_movemask_pd(far) as usize & live;
            let ok = _mm256_movemask_pd(inside) as usize & live & !far_bits;
            let at = *len;
            let b = &mut p.batch;
            _mm256_storeu_pd(b.dr[0].as_mut_ptr().add(at), front_pd(dx, ok));
            _mm256_storeu_pd(b.dr[1].as_mut_ptr().add(at), front_pd(dy, ok));
            _mm256_storeu_pd(b.dr[2].as_mut_ptr().add(at), front_pd(dz, ok));
            let [wx, wy, wz] = load4(vp, j);
            _mm256_storeu_pd(
                b.dv[0].as_mut_ptr().add(at),
                front_pd(_mm256_sub_pd(vi[0], wx), ok),
            );
            _mm256_storeu_pd(
                b.dv[1].as_mut_ptr().add(at),
                front_pd(_mm256_sub_pd(vi[1], wy), ok),
            );
            _mm256_storeu_pd(
                b.dv[2].as_mut_ptr().add(at),
                front_pd(_mm256_sub_pd(vi[2], wz), ok),
            );
            let jv = _mm_loadu_si128(jt.as_ptr() as *const __m128i);
            let tj = _mm_set_epi32(
                pc.tag[j[3]] as i32,
                pc.tag[j[2]] as i32,
                pc.tag[j[1]] as i32,
                pc.tag[j[0]] as i32,
            );
            let store = |dst: *mut u32, v: __m128i| _mm_storeu_si128(dst as *mut __m128i, v);
            store(p.j.as_mut_ptr().add(at), front_epi32(jv, ok));
            store(p.i.as_mut_ptr().add(at), ivec);
            store(b.tag_j.as_mut_ptr().add(at), front_epi32(tj, ok));
            store(b.tag_i.as_mut_ptr().add(at), tagi);
            if ONE_TYPE {
                store(b.coeff.as_mut_ptr().add(at), coeff);
                _mm256_storeu_pd(b.inv_mass_sum.as_mut_ptr().add(at), ims);
            } else {
                store(b.coeff.as_mut_ptr().add(at), front_epi32(coeff, ok));
                _mm256_storeu_pd(b.inv_mass_sum.as_mut_ptr().add(at), front_pd(ims, ok));
            }
            *len = at + ok.count_ones() as usize;
            let mut f = far_bits;
            while f != 0 {
                far_list.push(k0 as u32 + f.trailing_zeros());
                f &= f - 1;
            }
        }
        k0 += 4;
    }
    if *len == BATCH {
        sink.evaluate::<ONE_TYPE>(p, len);
    }
}

/// Append to `nbr` (from position `len`) the atoms j in `lo..hi` with |xs − x_j|² < `cutsq`
/// (raw separations), in increasing order; returns the new length. Four candidates at a time
/// from contiguous positions (six 128-bit loads, unpacked), the kept indices moved to the
/// front; the last 1–3 candidates by the portable test.
///
/// # Safety
/// The CPU has AVX2; `lo <= hi <= x.len()`; `nbr.len() >= len + (hi − lo) + 4`.
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) unsafe fn scan_cell(
    xs: [f64; 3],
    x: &[[f64; 3]],
    lo: usize,
    hi: usize,
    cutsq: f64,
    nbr: &mut [u32],
    mut len: usize,
) -> usize {
    let base = x.as_ptr() as *const f64;
    let xv = xs.map(|c| _mm256_set1_pd(c));
    let cut = _mm256_set1_pd(cutsq);
    let iota = _mm_setr_epi32(0, 1, 2, 3);
    let mut j0 = lo;
    while j0 + 4 <= hi {
        // SAFETY: atoms j0..j0 + 4 exist (j0 + 4 <= hi <= x.len()): the six loads read their 12
        // doubles; the store writes 4 entries from `len`, and len + 4 <= nbr.len() since at most
        // j0 − lo entries were appended so far.
        unsafe {
            let l = |k: usize| _mm_loadu_pd(base.add(3 * j0 + 2 * k));
            // (x0 y0) (z0 x1) (y1 z1) (x2 y2) (z2 x3) (y3 z3)
            let (l0, l1, l2, l3, l4, l5) = (l(0), l(1), l(2), l(3), l(4), l(5));
            let gx = _mm256_set_m128d(
                _mm_shuffle_pd::<0b10>(l3, l4),
                _mm_shuffle_pd::<0b10>(l0, l1),
            );
            let gy = _mm256_set_m128d(
                _mm_shuffle_pd::<0b01>(l3, l5),
                _mm_shuffle_pd::<0b01>(l0, l2),
            );
            let gz = _mm256_set_m128d(
                _mm_shuffle_pd::<0b10>(l4, l5),
                _mm_shuffle_pd::<0b10>(l1, l2),
            );
            let (_, rsq) = separation(xv, [gx, gy, gz]);
            let keep = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(rsq, cut)) as usize;
            let jv = _mm_add_epi32(_mm_set1_epi32(j0 as i32), iota);
            _mm_storeu_si128(
                nbr.as_mut_ptr().add(len) as *mut __m128i,
                front_epi32(jv, keep),
            );
            len += keep.count_ones() as usize;
        }
        j0 += 4;
    }
    for (j, xj) in x.iter().enumerate().take(hi).skip(j0) {
        let d = [xs[0] - xj[0], xs[1] - xj[1], xs[2] - xj[2]];
        nbr[len] = j as u32;
        len += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutsq);
    }
    len
}
