//! The pair-style seam: how every driver of a pair loop (the slab loop of `neighbor/`, for
//! periodic and sheared boxes, and the LAMMPS neighbour-list walk of `capi/`) reaches the pair
//! computation.
//!
//! A driver finds the pairs in range, fills the lanes of a [`PairBatch`] with r_ij and the
//! coefficient index (and, for the kernels that use them, v_ij, 1/m_i + 1/m_j and the tags),
//! hands full batches to a [`PairKernel`], and adds the returned central forces
//! `fpair · r_ij` (plus the non-central part `ft` of a kernel that sets
//! [`PairBatch::transverse`]) to atom i and subtracts them from atom j, so momentum is conserved
//! exactly whatever the kernel. A second pair style is a second `PairKernel`; it sees the atom indices
//! of each lane, so a many-body style (sDPD's densities) gathers its per-atom values there.
//!
//! [`Batcher`] is the gather → batch → apply driver of the C ABI path (a LAMMPS neighbour
//! list); the standalone slab loop appends lanes from its SIMD distance pass directly and
//! evaluates through the same kernel.

use crate::forces::{BATCH, PairBatch};

/// A pair style's evaluation of a batch of in-range pairs: from the lanes `0..b.len` of `b`
/// (and the atoms `i[l]`, `j[l]` of each lane) into `b.fpair` (force on i along r_ij, divided
/// by r: F_i = fpair · r_ij) and `b.energy`.
pub trait PairKernel: Sync {
    /// Evaluate the batch of noise key `step`.
    fn evaluate(&self, step: u64, b: &mut PairBatch, i: &[u32], j: &[u32]);
}

/// Pairs gathered into a batch with the atoms they belong to (the driver of the C ABI loop).
///
/// A caller hands its candidate pairs to [`Batcher::extend`], which has each written into the
/// next lane and kept or not: a lane that is not kept is overwritten by the next pair, so the
/// append needs no branch. A full batch is [`Batcher::flush`]ed: `gather` completes each kept
/// lane, the kernel evaluates it, and `apply` receives the batch with every lane's atoms, to
/// add the lanes in order.
#[derive(Clone, Debug)]
pub struct Batcher {
    /// The lanes.
    pub batch: Box<PairBatch>,
    i: [u32; BATCH],
    j: [u32; BATCH],
}

impl Default for Batcher {
    fn default() -> Batcher {
        Batcher {
            batch: Box::default(),
            i: [0; BATCH],
            j: [0; BATCH],
        }
    }
}

impl Batcher {
    /// Each of `items`, in order, into the next lane: `fill(batch, lane, item)` writes the
    /// lane (`dr`, `coeff`, ...) and returns the pair's atoms (i, j) and whether it is kept;
    /// full batches are [`Batcher::flush`]ed on the way (`kernel`, `step`, `gather`, `apply`
    /// as there). The lane count stays in a register through the loop: committing pair by
    /// pair stored and reloaded it, a store-to-load chain per candidate.
    #[inline(always)]
    pub fn extend<T, K: PairKernel + ?Sized>(
        &mut self,
        items: impl IntoIterator<Item = T>,
        mut fill: impl FnMut(&mut PairBatch, usize, T) -> (u32, u32, bool),
        kernel: &K,
        step: u64,
        gather: &mut impl FnMut(&mut PairBatch, usize, usize, usize),
        apply: &mut impl FnMut(&PairBatch, &[u32], &[u32]),
    ) {
        let mut len = self.batch.len;
        for item in items {
            let (i, j, keep) = fill(&mut self.batch, len, item);
            self.i[len] = i;
            self.j[len] = j;
            len += usize::from(keep);
            if len == BATCH {
                self.batch.len = len;
                self.flush(kernel, step, &mut *gather, &mut *apply);
                len = 0;
            }
        }
        self.batch.len = len;
    }

    /// Complete the kept lanes with `gather(batch, lane, i, j)`, evaluate them with `kernel`
    /// at `step`, pass the batch to `apply(batch, i, j)` (lane l: atoms `i[l]`, `j[l]`), and
    /// empty the batch. One call per batch, so that the caller's running sums (a row's force)
    /// live in registers through its loop over the lanes rather than in memory behind a
    /// pointer: a per-lane closure kept them in memory, a store-to-load chain per lane.
    #[inline]
    pub fn flush<K: PairKernel + ?Sized>(
        &mut self,
        kernel: &K,
        step: u64,
        mut gather: impl FnMut(&mut PairBatch, usize, usize, usize),
        mut apply: impl FnMut(&PairBatch, &[u32], &[u32]),
    ) {
        let n = self.batch.len;
        if n == 0 {
            return;
        }
        let b = &mut *self.batch;
        for l in 0..n {
            gather(b, l, self.i[l] as usize, self.j[l] as usize);
        }
        kernel.evaluate(step, b, &self.i[..n], &self.j[..n]);
        apply(b, &self.i[..n], &self.j[..n]);
        self.batch.len = 0;
    }
}

/// The force of lane `l` with r_ij: fpair · r_ij, plus the non-central part `ft` when the
/// kernel wrote one ([`PairBatch::transverse`]): the force on i; −it on j.
#[inline(always)]
pub fn lane_force(b: &PairBatch, l: usize) -> ([f64; 3], [f64; 3]) {
    let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
    let s = b.fpair[l];
    let fv = [s * dr[0], s * dr[1], s * dr[2]];
    if b.transverse {
        (
            dr,
            [fv[0] + b.ft[0][l], fv[1] + b.ft[1][l], fv[2] + b.ft[2][l]],
        )
    } else {
        (dr, fv)
    }
}
