//! The near pass of one row with AVX-512: 8 entries at a time, positions gathered, the
//! in-range near pairs compressed into the batch. Same pairs, same order, same bits as the
//! portable `near_row`.
use super::slab::{PassConst, Pending, RowArgs, Sink};
use crate::forces::BATCH;
use std::arch::x86_64::*;

// Whole 8-lane chunks fit in the batch arrays.
const _: () = assert!(BATCH.is_multiple_of(8));

/// Components of the positions of the atoms `row[k0..k0 + 8]` (entries past the row's end
/// repeat its last atom) as three vectors: eight masked 256-bit loads of (x, y, z) and a
/// transpose, cheaper than three 8-element gathers.
///
/// # Safety
/// The CPU has AVX-512 F/VL; `base` points to 3·n doubles and every index in `row` is < n;
/// `k0 < row.len()`.
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
#[inline]
unsafe fn load_xyz(base: *const f64, row: &[u32], k0: usize) -> [__m512d; 3] {
    let last = row.len() - 1;
    // SAFETY: each load reads the 3 doubles of an atom < n (mask 0b111: the fourth lane
    // is not read).
    let at = |t: usize| unsafe {
        _mm256_maskz_loadu_pd(0b0111, base.add(3 * row[(k0 + t).min(last)] as usize))
    };
    transpose8([at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7)])
}

/// Eight (x, y, z, ·) vectors to the three 8-lane vectors of x, y and z.
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
#[inline]
fn transpose8(a: [__m256d; 8]) -> [__m512d; 3] {
    let [a0, a1, a2, a3, a4, a5, a6, a7] = a;
    let u0 = _mm512_insertf64x4::<1>(
        _mm512_castpd256_pd512(_mm256_unpacklo_pd(a0, a1)),
        _mm256_unpacklo_pd(a4, a5),
    );
    let u1 = _mm512_insertf64x4::<1>(
        _mm512_castpd256_pd512(_mm256_unpacklo_pd(a2, a3)),
        _mm256_unpacklo_pd(a6, a7),
    );
    let v0 = _mm512_insertf64x4::<1>(
        _mm512_castpd256_pd512(_mm256_unpackhi_pd(a0, a1)),
        _mm256_unpackhi_pd(a4, a5),
    );
    let v1 = _mm512_insertf64x4::<1>(
        _mm512_castpd256_pd512(_mm256_unpackhi_pd(a2, a3)),
        _mm256_unpackhi_pd(a6, a7),
    );
    let even = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
    let odd = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
    [
        _mm512_permutex2var_pd(u0, even, u1),
        _mm512_permutex2var_pd(v0, even, v1),
        _mm512_permutex2var_pd(u0, odd, u1),
    ]
}

/// Append to `nbr` (from position `len`) the atoms j in `lo..hi` with |x_i − x_j|² <
/// `cutsq` (raw separations), in increasing order; returns the new length. Eight
/// candidates at a time: contiguous positions loaded and transposed, the kept indices
/// compressed.
///
/// # Safety
/// The CPU has AVX-512 F/VL; `lo < hi <= x.len()`; `nbr.len() >= len + (hi − lo) + 8`.
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) unsafe fn scan_cell(
    xi: [f64; 3],
    x: &[[f64; 3]],
    lo: usize,
    hi: usize,
    cutsq: f64,
    nbr: &mut [u32],
    mut len: usize,
) -> usize {
    let base = x.as_ptr() as *const f64;
    let (xi0, xi1, xi2) = (
        _mm512_set1_pd(xi[0]),
        _mm512_set1_pd(xi[1]),
        _mm512_set1_pd(xi[2]),
    );
    let cut = _mm512_set1_pd(cutsq);
    let iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    let mut j0 = lo;
    while j0 < hi {
        let lanes = (hi - j0).min(8);
        let lm: __mmask8 = ((1u32 << lanes) - 1) as u8;
        // SAFETY: atoms j0..j0 + lanes exist (hi <= x.len()); lanes past them repeat the
        // last; the store writes 8 entries from `len` < nbr.len() − 8.
        unsafe {
            let at =
                |t: usize| _mm256_maskz_loadu_pd(0b0111, base.add(3 * (j0 + t.min(lanes - 1))));
            let [gx, gy, gz] = transpose8([at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7)]);
            let dx = _mm512_sub_pd(xi0, gx);
            let dy = _mm512_sub_pd(xi1, gy);
            let dz = _mm512_sub_pd(xi2, gz);
            let rsq = _mm512_add_pd(
                _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                _mm512_mul_pd(dz, dz),
            );
            let keep = _mm512_mask_cmp_pd_mask::<_CMP_LT_OQ>(lm, rsq, cut);
            let jv = _mm256_add_epi32(_mm256_set1_epi32(j0 as i32), iota);
            _mm256_storeu_si256(
                nbr.as_mut_ptr().add(len) as *mut __m256i,
                _mm256_maskz_compress_epi32(keep, jv),
            );
            len += keep.count_ones() as usize;
        }
        j0 += 8;
    }
    len
}

/// # Safety
/// The CPU has AVX-512 F/DQ/VL/BW, and every index in `r.row` is < `pc.x.len()` =
/// `pc.v.len()` = `pc.tag.len()` (and, with more than one type, `r.row_t + typ[j] <
/// pc.rcsq.len()` and `typ[j] < pc.inv_mass.len()`).
// Kept in one piece (over 120 lines) on purpose: the hot loop, so the compiler sees the whole
// lane loop under one `target_feature` (a helper would need the same attribute to inline).
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) unsafe fn near_row<const ONE_TYPE: bool>(
    r: &RowArgs,
    pc: &PassConst,
    p: &mut Pending,
    len: &mut usize,
    far_list: &mut Vec<u32>,
    sink: &mut Sink,
) {
    let xi = [
        _mm512_set1_pd(r.xi[0]),
        _mm512_set1_pd(r.xi[1]),
        _mm512_set1_pd(r.xi[2]),
    ];
    let q = [
        _mm512_set1_pd(pc.quarter[0]),
        _mm512_set1_pd(pc.quarter[1]),
        _mm512_set1_pd(pc.quarter[2]),
    ];
    let rc_one = _mm512_set1_pd(pc.one_rcsq);
    let min_sq = _mm512_set1_pd(pc.min_sq);
    let ivec = _mm256_set1_epi32(r.i as i32);
    let cvec = _mm256_set1_epi32(pc.one_coeff as i32);
    let rowt = _mm256_set1_epi32(r.row_t as i32);
    let xp = pc.x.as_ptr() as *const f64;
    let vp = pc.v.as_ptr() as *const f64;
    let vi = [
        _mm512_set1_pd(r.vi[0]),
        _mm512_set1_pd(r.vi[1]),
        _mm512_set1_pd(r.vi[2]),
    ];
    let tagi = _mm256_set1_epi32(r.tag_i as i32);
    let ims_one = _mm512_set1_pd(pc.ims_one);
    let inv_mi = _mm512_set1_pd(r.inv_mi);
    let zero = _mm512_setzero_pd();
    let m = r.row.len();
    let mut k0 = 0;
    while k0 < m {
        if *len > BATCH - 8 {
            sink.evaluate::<ONE_TYPE>(p, len);
        }
        let lanes = (m - k0).min(8);
        let lm: __mmask8 = ((1u32 << lanes) - 1) as u8;
        // SAFETY (all pointer reads and writes below): masked-off lanes touch no memory;
        // `k0 + lanes <= m`; indices are valid by the caller's contract; `*len + 8 <= BATCH`.
        unsafe {
            let jv = _mm256_maskz_loadu_epi32(lm, r.row.as_ptr().add(k0) as *const i32);
            let [gx, gy, gz] = load_xyz(xp, r.row, k0);
            let dx = _mm512_sub_pd(xi[0], gx);
            let dy = _mm512_sub_pd(xi[1], gy);
            let dz = _mm512_sub_pd(xi[2], gz);
            let rsq = _mm512_add_pd(
                _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                _mm512_mul_pd(dz, dz),
            );
            let (rcsq, coeff, ims) = if ONE_TYPE {
                (rc_one, cvec, ims_one)
            } else {
                let tj = _mm256_mmask_i32gather_epi32::<4>(
                    _mm256_setzero_si256(),
                    lm,
                    jv,
                    pc.typ.as_ptr() as *const i32,
                );
                let ci = _mm256_add_epi32(rowt, tj);
                (
                    _mm512_mask_i32gather_pd::<8>(zero, lm, ci, pc.rcsq.as_ptr()),
                    ci,
                    _mm512_add_pd(
                        inv_mi,
                        _mm512_mask_i32gather_pd::<8>(zero, lm, tj, pc.inv_mass.as_ptr()),
                    ),
                )
            };
            let inside = _mm512_mask_cmp_pd_mask::<_CMP_LT_OQ>(lm, rsq, rcsq)
                & _mm512_cmp_pd_mask::<_CMP_GE_OQ>(rsq, min_sq);
            let far = _mm512_mask_cmp_pd_mask::<_CMP_GE_OQ>(lm, _mm512_abs_pd(dx), q[0])
                | _mm512_mask_cmp_pd_mask::<_CMP_GE_OQ>(lm, _mm512_abs_pd(dy), q[1])
                | _mm512_mask_cmp_pd_mask::<_CMP_GE_OQ>(lm, _mm512_abs_pd(dz), q[2]);
            let ok = inside & !far;
            let at = *len;
            let b = &mut p.batch;
            // Compress in registers, then store all 8 lanes (the batch has room; lanes past
            // the kept ones are overwritten later): much faster than compress-to-memory on
            // AMD cores.
            _mm512_storeu_pd(
                b.dr[0].as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, dx),
            );
            _mm512_storeu_pd(
                b.dr[1].as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, dy),
            );
            _mm512_storeu_pd(
                b.dr[2].as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, dz),
            );
            _mm256_storeu_si256(
                b.coeff.as_mut_ptr().add(at) as *mut __m256i,
                _mm256_maskz_compress_epi32(ok, coeff),
            );
            _mm256_storeu_si256(
                p.j.as_mut_ptr().add(at) as *mut __m256i,
                _mm256_maskz_compress_epi32(ok, jv),
            );
            _mm256_storeu_si256(p.i.as_mut_ptr().add(at) as *mut __m256i, ivec);
            // v_ij, tags and 1/m_i + 1/m_j of the kept pairs.
            let [wx, wy, wz] = load_xyz(vp, r.row, k0);
            _mm512_storeu_pd(
                b.dv[0].as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, _mm512_sub_pd(vi[0], wx)),
            );
            _mm512_storeu_pd(
                b.dv[1].as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, _mm512_sub_pd(vi[1], wy)),
            );
            _mm512_storeu_pd(
                b.dv[2].as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, _mm512_sub_pd(vi[2], wz)),
            );
            let tj = _mm256_mmask_i32gather_epi32::<4>(
                _mm256_setzero_si256(),
                ok,
                jv,
                pc.tag.as_ptr() as *const i32,
            );
            _mm256_storeu_si256(
                b.tag_j.as_mut_ptr().add(at) as *mut __m256i,
                _mm256_maskz_compress_epi32(ok, tj),
            );
            _mm256_storeu_si256(b.tag_i.as_mut_ptr().add(at) as *mut __m256i, tagi);
            _mm512_storeu_pd(
                b.inv_mass_sum.as_mut_ptr().add(at),
                _mm512_maskz_compress_pd(ok, ims),
            );
            *len = at + ok.count_ones() as usize;
            let mut f = far;
            while f != 0 {
                far_list.push(k0 as u32 + f.trailing_zeros());
                f &= f - 1;
            }
        }
        k0 += 8;
    }
    if *len == BATCH {
        sink.evaluate::<ONE_TYPE>(p, len);
    }
}
