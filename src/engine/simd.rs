//! SIMD helpers shared by the engine's distance passes (`neighbor/avx2.rs`) and the C ABI's
//! walk over a LAMMPS list ([`within_cut`]): the same arithmetic as the portable loops, so the
//! same pairs are kept with every instruction set.

use crate::forces::Isa;

/// The atoms of `jlist` (each entry masked with `mask`: LAMMPS's `NEIGHMASK`) within `cutsq` of
/// `xi`, in list order: |x_i − x_j|² < `cutsq` with the pair loops' arithmetic ((dx² + dy²) +
/// dz², no FMA), x_j = `x[3j..3j + 3]`. Their indices are written to `out[..count]`, grown to
/// at least `jlist.len() + 4` entries (never shrunk, so a reused buffer is not zeroed again);
/// returns the count. An entry outside the atoms of `x` is clamped to the last atom (a caller
/// bug: LAMMPS lists are validated before, in `for_each_row`), so no index reads out of bounds.
pub fn within_cut(
    isa: Isa,
    xi: [f64; 3],
    x: &[f64],
    jlist: &[i32],
    mask: u32,
    cutsq: f64,
    out: &mut Vec<u32>,
) -> usize {
    if out.len() < jlist.len() + 4 {
        out.resize(jlist.len() + 4, 0);
    }
    let natoms = x.len() / 3;
    if natoms == 0 || jlist.is_empty() {
        return 0;
    }
    #[cfg(target_arch = "x86_64")]
    if (isa as u8) >= (Isa::Avx2 as u8) && Isa::best_supported() as u8 >= Isa::Avx2 as u8 {
        // SAFETY: the CPU has AVX2 (checked above); `x` holds `natoms` atoms; `out` has room
        // for jlist.len() + 4 entries.
        return unsafe { avx2::within_cut(xi, x, natoms, jlist, mask, cutsq, out) };
    }
    let _ = isa;
    let mut n = 0;
    for &jr in jlist {
        let j = (jr as u32 & mask) as usize;
        let j = j.min(natoms - 1);
        let d = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
        out[n] = j as u32;
        n += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutsq);
    }
    n
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2 {
    //! AVX2 building blocks: four lanes of f64, kept lanes moved to the front by a
    //! permutation table (AVX2 has no compress). Written for cores that execute 256-bit
    //! operations as two 128-bit halves (AMD Zen 1) as well as for those that do not: no
    //! gathers (microcoded there), no masked stores, lane crossing only by `vinsertf128` and
    //! one `vpermps` per compressed vector.
    use std::arch::x86_64::*;

    /// For each 4-bit lane mask, the 32-bit indices for `_mm256_permutevar8x32_ps` that move the
    /// kept 64-bit lanes (two 32-bit halves each) to the front, in order (the rest: lane 0).
    static PD_FRONT: [[u32; 8]; 16] = pd_front();
    /// For each 4-bit lane mask, the bytes for `_mm_shuffle_epi8` that move the kept 32-bit lanes
    /// to the front, in order (the rest: zero).
    static EPI32_FRONT: [[u8; 16]; 16] = epi32_front();

    const fn pd_front() -> [[u32; 8]; 16] {
        let mut t = [[0u32; 8]; 16];
        let mut m = 0;
        while m < 16 {
            let (mut k, mut l) = (0, 0);
            while l < 4 {
                if m & (1 << l) != 0 {
                    t[m][2 * k] = 2 * l as u32;
                    t[m][2 * k + 1] = 2 * l as u32 + 1;
                    k += 1;
                }
                l += 1;
            }
            m += 1;
        }
        t
    }

    const fn epi32_front() -> [[u8; 16]; 16] {
        let mut t = [[0x80u8; 16]; 16];
        let mut m = 0;
        while m < 16 {
            let (mut k, mut l) = (0, 0);
            while l < 4 {
                if m & (1 << l) != 0 {
                    let mut b = 0;
                    while b < 4 {
                        t[m][4 * k + b] = (4 * l + b) as u8;
                        b += 1;
                    }
                    k += 1;
                }
                l += 1;
            }
            m += 1;
        }
        t
    }

    /// The kept lanes of `v` (mask `m`, 4 bits) at the front.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
    #[inline]
    pub(crate) fn front_pd(v: __m256d, m: usize) -> __m256d {
        // SAFETY: m < 16 (a 4-lane movemask), so the row exists; an unaligned 256-bit load of it.
        let idx = unsafe { _mm256_loadu_si256(PD_FRONT[m & 15].as_ptr() as *const __m256i) };
        _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), idx))
    }

    /// The kept 32-bit lanes of `v` (mask `m`, 4 bits) at the front.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
    #[inline]
    pub(crate) fn front_epi32(v: __m128i, m: usize) -> __m128i {
        // SAFETY: as in `front_pd`: a 128-bit load of row m < 16.
        let idx = unsafe { _mm_loadu_si128(EPI32_FRONT[m & 15].as_ptr() as *const __m128i) };
        _mm_shuffle_epi8(v, idx)
    }

    /// The components of four 3-vectors `base[3·j_t ..]` (t = 0..4) as three 4-lane vectors:
    /// 128-bit (x, y) and 64-bit z loads, unpacked per half and joined.
    ///
    /// # Safety
    /// `base` points to 3·n doubles and every `j_t` < n.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
    #[inline]
    pub(crate) unsafe fn load4(base: *const f64, j: [usize; 4]) -> [__m256d; 3] {
        // SAFETY: each load reads doubles 3·j_t .. 3·j_t + 3 of the array (caller's contract).
        unsafe {
            let xy = |t: usize| _mm_loadu_pd(base.add(3 * j[t]));
            let z = |t: usize, u: usize| {
                _mm_loadh_pd(_mm_load_sd(base.add(3 * j[t] + 2)), base.add(3 * j[u] + 2))
            };
            let (a0, a1, a2, a3) = (xy(0), xy(1), xy(2), xy(3));
            [
                _mm256_set_m128d(_mm_unpacklo_pd(a2, a3), _mm_unpacklo_pd(a0, a1)),
                _mm256_set_m128d(_mm_unpackhi_pd(a2, a3), _mm_unpackhi_pd(a0, a1)),
                _mm256_set_m128d(z(2, 3), z(0, 1)),
            ]
        }
    }

    /// r = x_i − x_j by component and |r|² = (dx² + dy²) + dz², the pair loops' arithmetic
    /// (no FMA), for four pairs: `xi` broadcast, `xj` the four atoms' components.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
    #[inline]
    pub(crate) fn separation(xi: [__m256d; 3], xj: [__m256d; 3]) -> ([__m256d; 3], __m256d) {
        let d = [0, 1, 2].map(|c| _mm256_sub_pd(xi[c], xj[c]));
        let rsq = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1])),
            _mm256_mul_pd(d[2], d[2]),
        );
        (d, rsq)
    }

    /// [`super::within_cut`] with AVX2, four entries at a time.
    ///
    /// # Safety
    /// The CPU has AVX2; `x` holds at least `natoms` ≥ 1 atoms (3 doubles each); `out.len() >=
    /// jlist.len() + 4`.
    #[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
    pub(crate) unsafe fn within_cut(
        xi: [f64; 3],
        x: &[f64],
        natoms: usize,
        jlist: &[i32],
        mask: u32,
        cutsq: f64,
        out: &mut [u32],
    ) -> usize {
        let xv = xi.map(|c| _mm256_set1_pd(c));
        let cut = _mm256_set1_pd(cutsq);
        let base = x.as_ptr();
        let m = jlist.len();
        let last = natoms - 1;
        let mut n = 0;
        let mut k0 = 0;
        while k0 < m {
            let lanes = (m - k0).min(4);
            // Entries past the list's end repeat its last one; their lanes are masked off.
            let jt: [u32; 4] = std::array::from_fn(|t| {
                ((jlist[(k0 + t).min(m - 1)] as u32 & mask) as usize).min(last) as u32
            });
            // SAFETY: every index is < natoms (clamped), so load4 reads inside `x`; the store
            // writes 4 entries from n <= k0, and k0 + 4 <= jlist.len() + 4 <= out.len().
            unsafe {
                let (_, rsq) = separation(xv, load4(base, jt.map(|j| j as usize)));
                let keep = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(rsq, cut)) as usize
                    & ((1usize << lanes) - 1);
                let jv = _mm_loadu_si128(jt.as_ptr() as *const __m128i);
                _mm_storeu_si128(
                    out.as_mut_ptr().add(n) as *mut __m128i,
                    front_epi32(jv, keep),
                );
                n += keep.count_ones() as usize;
            }
            k0 += 4;
        }
        n
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        /// The tables move the kept lanes to the front in order, for every mask.
        #[test]
        fn compress_tables() {
            for m in 0..16usize {
                let kept: Vec<u32> = (0..4).filter(|l| m & (1 << l) != 0).collect();
                for (k, &l) in kept.iter().enumerate() {
                    assert_eq!(PD_FRONT[m][2 * k], 2 * l);
                    assert_eq!(PD_FRONT[m][2 * k + 1], 2 * l + 1);
                    for b in 0..4 {
                        assert_eq!(EPI32_FRONT[m][4 * k + b] as u32, 4 * l + b as u32);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::keyed_uniform;

    /// Every instruction set keeps the same entries in the same order, for row lengths 0–11
    /// (whole chunks and every tail), masked entries (upper flag bits set) and positions on
    /// the cut-off's edge.
    #[test]
    fn within_cut_is_the_same_with_every_isa() {
        let natoms = 40;
        let mut x: Vec<f64> = (0..3 * natoms as u32)
            .map(|k| 2.0 * keyed_uniform(7, 1, 0, k, 0))
            .collect();
        // One atom exactly at distance 1 from atom 0 (excluded: the test is strict).
        x[3] = x[0] + 1.0;
        x[4] = x[1];
        x[5] = x[2];
        let xi = [x[0], x[1], x[2]];
        let mask = 0x1FFF_FFFF;
        for len in 0..12u32 {
            let jlist: Vec<i32> = (0..len)
                .map(|k| {
                    let j = (k * 7 + 1) % natoms as u32;
                    (j | if k % 3 == 0 { 1 << 30 } else { 0 }) as i32
                })
                .collect();
            let mut want = Vec::new();
            let n0 = within_cut(Isa::Baseline, xi, &x, &jlist, mask, 1.0, &mut want);
            let direct: Vec<u32> = jlist
                .iter()
                .map(|&j| j as u32 & mask)
                .filter(|&j| {
                    let j = j as usize;
                    let d = [0, 1, 2].map(|c| xi[c] - x[3 * j + c]);
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < 1.0
                })
                .collect();
            assert_eq!(&want[..n0], &direct[..], "baseline, {len} entries");
            for isa in [Isa::Avx2, Isa::Avx512] {
                let mut got = Vec::new();
                let n = within_cut(isa, xi, &x, &jlist, mask, 1.0, &mut got);
                assert_eq!(&got[..n], &direct[..], "{isa:?}, {len} entries");
            }
        }
    }
}
