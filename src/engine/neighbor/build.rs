//! Building the list: cell coordinates, the rows of each slab (portable and AVX-512 scans of
//! neighbour-cell runs), and the cell-order permutation of the atoms.

use super::*;
use crate::forces::Isa;

/// Stencil image code: the neighbour cell's periodic image is decided per pair.
pub(super) const AMBIGUOUS: i8 = 2;

/// Cell coordinates of a position (the box is periodic and positions are wrapped, so the
/// scaled coordinate is ≥ 0 and truncation is the floor).
#[derive(Clone, Copy, Debug)]
pub(super) struct CellCoords {
    pub(super) lo: [f64; 3],
    pub(super) len: [f64; 3],
    pub(super) ncell: [usize; 3],
    pub(super) dim: usize,
}

impl CellCoords {
    #[inline(always)]
    pub(super) fn of(&self, x: &[f64; 3]) -> [usize; 3] {
        let mut c = [0usize; 3];
        for d in 0..self.dim {
            let f = (x[d] - self.lo[d]) / self.len[d] * self.ncell[d] as f64;
            c[d] = (f.max(0.0) as usize).min(self.ncell[d] - 1);
        }
        c
    }
}

/// What building the rows of a slab reads.
pub(super) struct RowBuild<'a> {
    pub(super) x: &'a [[f64; 3]],
    pub(super) bx: &'a SimBox,
    pub(super) cells: CellCoords,
    pub(super) cell_start: &'a [u32],
    pub(super) axes: &'a [Vec<Vec<(usize, i8)>>; 3],
    /// For each x cell coordinate, its neighbour cells along x as runs (first, last, image),
    /// in increasing order.
    pub(super) xruns: &'a [Vec<(usize, usize, i8)>],
    /// Box lengths (for image shifts).
    pub(super) len: [f64; 3],
    pub(super) cutsq: f64,
    /// The slab axis in slab mode; None: one task, j > i in every neighbouring cell.
    pub(super) slab_axis: Option<usize>,
    /// Lees–Edwards boundaries of the build (None: periodic).
    pub(super) le: Option<LeesEdwards>,
    /// The tilt allowance D: rows through the sheared boundary take every pair whose x
    /// separation is within the cut-off + D (`NeighborList::set_shear`).
    pub(super) tilt_allow: f64,
}

impl RowBuild<'_> {
    /// The x cells to scan in a row of cells reached along y with image `iy` (the stencil code
    /// of that axis), as runs (first, last, x image) in a fixed order. Periodic, or not
    /// through the y boundary: the x stencil `xruns[cx]`. Through a sheared y boundary: the
    /// row's atoms appear displaced by n_y·offset along x (n_y = −iy, the image's y shift in
    /// boxes), so the partners of an atom of cell cx (x − lo in [cx·w, (cx + 1)·w)) within the
    /// cut-off c for an offset within ±D of the build's lie in the cells covering
    /// [cx·w − n_y·offset − c − D, (cx + 1)·w − n_y·offset + c + D] (padded by 10⁻⁶ w against
    /// the round-off of the cell index): one run, or two where it wraps, every image decided
    /// per pair; all cells when that covers the row or the y image is ambiguous.
    #[inline(always)]
    fn x_runs(&self, cx: usize, iy: i8, out: &mut [(usize, usize, i8); 4]) -> usize {
        let m = self.cells.ncell[0];
        match self.le {
            Some(le) if iy != 0 => {
                let w = self.len[0] / m as f64;
                let reach = self.cutsq.sqrt() + self.tilt_allow + 1e-6 * w;
                let shift = -f64::from(iy) * le.offset;
                let lo = ((cx as f64 * w - shift - reach) / w).floor();
                let hi = (((cx + 1) as f64 * w - shift + reach) / w).floor();
                // A NaN window (no finite offset) also scans every cell.
                let narrow = hi - lo + 1.0 < m as f64;
                if iy == AMBIGUOUS || !narrow {
                    out[0] = (0, m - 1, AMBIGUOUS);
                    return 1;
                }
                let a = (lo as i64).rem_euclid(m as i64) as usize;
                let b = a + (hi - lo) as usize;
                if b < m {
                    out[0] = (a, b, AMBIGUOUS);
                    1
                } else {
                    out[0] = (0, b - m, AMBIGUOUS);
                    out[1] = (a, m - 1, AMBIGUOUS);
                    2
                }
            }
            _ => {
                let runs = &self.xruns[cx];
                out[..runs.len()].copy_from_slice(runs);
                runs.len()
            }
        }
    }
}

pub(super) fn build_rows_isa(isa: Isa, rb: &RowBuild, s: &mut Slab) {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `isa` is one the CPU supports (checked against `Isa::best_supported`).
        Isa::Avx512 => unsafe { build_rows_avx512(rb, s) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Isa::Avx2 => unsafe { build_rows_avx2(rb, s) },
        _ => build_rows::<PORTABLE>(rb, s),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) fn build_rows_avx512(rb: &RowBuild, s: &mut Slab) {
    build_rows::<AVX512>(rb, s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) fn build_rows_avx2(rb: &RowBuild, s: &mut Slab) {
    build_rows::<AVX2>(rb, s)
}

/// The rows of one slab: for each atom, the atoms of the neighbouring cells (stencil order,
/// increasing index within a cell) within the list cut-off. A cell reached without crossing
/// the periodic boundary is scanned with raw separations (exact for the cut-off test: with at
/// least 3 cells of side ≥ cut-off per axis, a pair within the cut-off has its raw separation
/// as minimum image); the others go through `SimBox::min_image`.
#[inline(always)]
pub(super) fn build_rows<const SIMD: u8>(rb: &RowBuild, s: &mut Slab) {
    let x = rb.x;
    let ncell = rb.cells.ncell;
    s.row_start.clear();
    s.row_start.push(0);
    // `s.nbr` is used as a buffer longer than the row data (grown, never shrunk, while
    // building); `len` is the data's length.
    let mut len = 0usize;
    for i in s.start..s.end {
        let xi = x[i];
        let c = rb.cells.of(&xi);
        // Scan the cells `cells.0..=cells.1` (consecutive along x, so their atoms are one
        // index range).
        // Scan the cells `cells.0..=cells.1` (consecutive along x, so their atoms are one
        // index range), whose atoms are seen through the periodic image `img` (per axis: 0,
        // ±1 for x_i shifted by ±L, AMBIGUOUS: decided per pair by `SimBox::min_image`).
        let mut scan = |cells: (usize, usize), first: usize, img: [i8; 3]| {
            let lo = (rb.cell_start[cells.0] as usize).max(first);
            let hi = rb.cell_start[cells.1 + 1] as usize;
            if hi <= lo {
                return;
            }
            let need = len + (hi - lo) + 8;
            if s.nbr.len() < need {
                grow_buffer(&mut s.nbr, need);
            }
            let mut l = len;
            if img.contains(&AMBIGUOUS) {
                // Under Lees–Edwards the x separation counts less the tilt allowance (0 in a
                // periodic box, where this is the plain test).
                let allow = rb.tilt_allow;
                // Sheared with y shorter than twice the list cut-off: the nearest of the
                // sliding-brick images along y too ([`nearest_sq`]; in a box of 2 r_c or more
                // the extra candidates are out of range and drop out of the pair loop).
                if rb.le.is_some() && rb.len[1] * rb.len[1] < 4.0 * rb.cutsq {
                    for j in lo..hi {
                        let xj = x[j];
                        let d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                        let rsq = nearest_sq(rb.bx, rb.le.as_ref(), d, allow);
                        s.nbr[l] = j as u32;
                        l += usize::from(rsq < rb.cutsq);
                    }
                    len = l;
                    return;
                }
                for j in lo..hi {
                    let xj = x[j];
                    let d = pair_image(
                        rb.bx,
                        rb.le.as_ref(),
                        [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]],
                    );
                    let dx = (d[0].abs() - allow).max(0.0);
                    s.nbr[l] = j as u32;
                    l += usize::from(dx * dx + d[1] * d[1] + d[2] * d[2] < rb.cutsq);
                }
                len = l;
                return;
            }
            // x_i − (x_j − image · L) = (x_i + image · L) − x_j. (Rows through a sheared
            // boundary have every image ambiguous: decided per pair above.)
            let xs = [0, 1, 2].map(|k| xi[k] + f64::from(img[k]) * rb.len[k]);
            #[cfg(target_arch = "x86_64")]
            if SIMD == AVX512 {
                // SAFETY: only inside `build_rows_avx512` (AVX-512 present); lo..hi are atom
                // indices < x.len(); s.nbr has room for len + (hi − lo) + 8 entries.
                len = unsafe { avx512::scan_cell(xs, x, lo, hi, rb.cutsq, &mut s.nbr, l) };
                return;
            } else if SIMD == AVX2 {
                // SAFETY: as above, inside `build_rows_avx2` (AVX2 present).
                len = unsafe { avx2::scan_cell(xs, x, lo, hi, rb.cutsq, &mut s.nbr, l) };
                return;
            }
            for j in lo..hi {
                let xj = x[j];
                let d = [xs[0] - xj[0], xs[1] - xj[1], xs[2] - xj[2]];
                s.nbr[l] = j as u32;
                l += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < rb.cutsq);
            }
            len = l;
        };
        // Neighbouring cells as runs along x (cells are x-fastest): x − 1, x, x + 1 merge into
        // one index range unless one of them is across the boundary (or, under Lees–Edwards,
        // the row is reached through the sheared y boundary: `RowBuild::x_runs`).
        let mut runs = [(0usize, 0usize, 0i8); 4];
        if let Some(axis) = rb.slab_axis {
            // Own layer: j > i; next layer: every j.
            let layers = ncell[axis];
            let slow = if axis == 2 { 1 } else { 2 };
            let mut cc = c;
            for (dl, first) in [(0, i + 1), (1, 0)] {
                cc[axis] = (c[axis] + dl) % layers;
                let mut img = [0i8; 3];
                img[axis] = if c[axis] + dl >= layers { -1 } else { 0 };
                for &(cs, is) in &rb.axes[slow][c[slow]] {
                    cc[slow] = cs;
                    img[slow] = is;
                    let nr = rb.x_runs(c[0], img[1], &mut runs);
                    for &(x0, x1, ix) in &runs[..nr] {
                        cc[0] = x0;
                        img[0] = ix;
                        let a = cell_id(cc, ncell);
                        scan((a, a + (x1 - x0)), first, img);
                    }
                }
            }
        } else {
            for &(cz, iz) in &rb.axes[2][c[2]] {
                for &(cy, iy) in &rb.axes[1][c[1]] {
                    let nr = rb.x_runs(c[0], iy, &mut runs);
                    for &(x0, x1, ix) in &runs[..nr] {
                        let a = cell_id([x0, cy, cz], ncell);
                        scan((a, a + (x1 - x0)), i + 1, [ix, iy, iz]);
                    }
                }
            }
        }
        s.row_start.push(len as u32);
    }
    s.nbr.truncate(len);
    trim_buffer(&mut s.nbr);
}

/// Lengthen the row buffer `v` to at least `need` entries, by a quarter at least, with
/// exactly that capacity: `Vec`'s own growth doubles, and a list a little longer than the last
/// build's left up to half of the buffer unused (≈ 380 B/atom at n = 16).
#[inline(never)]
pub(super) fn grow_buffer(v: &mut Vec<u32>, need: usize) {
    let target = need.max(v.len() + v.len() / 4);
    v.reserve_exact(target - v.len());
    v.resize(target, 0);
}

/// Give back a finished list's spare capacity beyond 1/16 of its length (the growth of
/// [`grow_buffer`] while scanning leaves up to a quarter): one copy of the list per build
/// that grew it, ≈ 0.3 ms for 20 000 atoms at n = 16, against ≈ 50 ms per step.
pub(super) fn trim_buffer(v: &mut Vec<u32>) {
    let keep = v.len() + v.len() / 16 + 16;
    if v.capacity() > keep {
        v.shrink_to(keep);
    }
}

/// Reorder every per-atom array by `perm` (new index k holds old atom `perm[k]`): a parallel
/// gather into one scratch array per element type, swapped with the field (so the scratch
/// holds the old array for the next field of that type). The destructuring names every field
/// of [`Atoms`]: a field added there fails to compile here until it is permuted too.
pub(super) fn permute(atoms: &mut Atoms, perm: &[u32], scratch: &mut PermScratch) {
    pub(super) fn gather<T: Copy + Send + Sync>(a: &mut Vec<T>, perm: &[u32], tmp: &mut Vec<T>) {
        tmp.clear();
        tmp.par_extend(perm.par_iter().map(|&p| a[p as usize]));
        std::mem::swap(a, tmp);
    }
    let Atoms {
        x,
        v,
        f,
        tag,
        typ,
        image,
        mol,
        mask,
        vest,
    } = atoms;
    gather(x, perm, &mut scratch.vec3);
    gather(v, perm, &mut scratch.vec3);
    gather(f, perm, &mut scratch.vec3);
    gather(tag, perm, &mut scratch.u32s);
    gather(typ, perm, &mut scratch.u32s);
    gather(image, perm, &mut scratch.int3);
    if !mol.is_empty() {
        gather(mol, perm, &mut scratch.u32s);
    }
    if !mask.is_empty() {
        gather(mask, perm, &mut scratch.u32s);
    }
    if !vest.is_empty() {
        gather(vest, perm, &mut scratch.vec3);
    }
}

/// Scratch arrays of [`permute`], one per element type (kept between builds).
#[derive(Clone, Debug, Default)]
pub(super) struct PermScratch {
    pub(super) vec3: Vec<[f64; 3]>,
    pub(super) u32s: Vec<u32>,
    pub(super) int3: Vec<[i32; 3]>,
}
