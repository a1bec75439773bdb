//! The pair loop of one slab: the distance pass over each row (portable here, AVX-512 in
//! `avx512.rs`), the batch of in-range pairs, and [`flush`], which evaluates a batch through
//! the pair style's kernel and adds the forces in batch order.

use super::*;
use crate::forces::lanes::MIN_PAIR_DISTANCE;
use crate::forces::{BATCH, Isa, PairBatch};

/// Everything a slab task reads.
pub(super) struct Ctx<'a> {
    /// Bonded partners and what their pairs get (None: no special pairs).
    pub(super) special: Option<&'a crate::engine::topology::SpecialPairs>,
    /// Lees–Edwards boundaries of this step (None: periodic).
    pub(super) le: Option<LeesEdwards>,
    /// A box shorter than 2 r_c: the short axes and the image key's frame (P-4b). Every
    /// candidate pair then goes through [`SimBox::images_within`], each image keyed apart.
    pub(super) short: Option<([bool; 3], crate::rng::ImageFrame)>,
    /// Iterate the working list instead of the list.
    pub(super) inner: bool,
    /// The instruction set of the pair loop (supported by this CPU).
    pub(super) isa: Isa,
    pub(super) bx: &'a SimBox,
    /// The pair style's batch evaluation (`pair.rs`).
    pub(super) kernel: &'a dyn PairKernel,
    pub(super) rcsq: &'a [f64],
    pub(super) inv_mass: &'a [f64],
    pub(super) nt: usize,
    pub(super) step: u64,
    pub(super) x: &'a [[f64; 3]],
    pub(super) v: &'a [[f64; 3]],
    pub(super) tag: &'a [u32],
    pub(super) typ: &'a [u32],
}

/// A batch of in-range pairs with the atom indices they belong to.
pub(super) struct Pending {
    pub(super) batch: PairBatch,
    pub(super) i: [u32; BATCH],
    pub(super) j: [u32; BATCH],
}

/// One row's candidate pairs after the distance pass (reused between rows and steps).
#[derive(Clone, Debug, Default)]
pub(super) struct RowScratch {
    pub(super) dr: [Vec<f64>; 3],
    pub(super) keep: Vec<u32>,
    /// Row positions of the entries through a periodic boundary.
    pub(super) far: Vec<u32>,
    /// Their minimum-image separations and in-range flags.
    pub(super) far_dr: [Vec<f64>; 3],
    pub(super) far_keep: Vec<u32>,
    /// Under Lees–Edwards, their boundary velocity jumps Δv_x.
    pub(super) far_dvx: Vec<f64>,
}

impl Slab {
    /// All pairs of this slab's rows: forces on slab atoms into `own` (indexed from `start`),
    /// on next-slab atoms into `next` (indexed from `next_start`), both overwritten.
    /// `va`: when Some, each pair's per-atom virial (½ r_a F_b to each atom) into these two
    /// arrays, indexed as `own` and `next` (LAMMPS's `vflag_atom`; None leaves the loop as it
    /// is).
    pub(super) fn compute(
        &mut self,
        ctx: &Ctx,
        own: &mut [[f64; 3]],
        next: &mut [[f64; 3]],
        va: Option<VirialOut>,
    ) {
        own.fill([0.0; 3]);
        next.fill([0.0; 3]);
        let va = va.map(|(o, n)| {
            o.fill([0.0; 6]);
            n.fill([0.0; 6]);
            (o, n)
        });
        let mut work = SlabWork {
            va,
            start: self.start,
            end: self.end,
            next_start: self.next_start,
            row_start: if ctx.inner {
                &self.in_row_start
            } else {
                &self.row_start
            },
            nbr: if ctx.inner { &self.in_nbr } else { &self.nbr },
            scratch: &mut self.scratch,
        };
        // A local copy of the box: the optimiser then sees its dimension as a constant.
        let bx = ctx.bx.clone();
        let isa = ctx.isa;
        let tally = match (bx.dim, ctx.nt == 2) {
            (3, true) => slab_isa::<3, true>(isa, &mut work, ctx, &bx, own, next),
            (3, false) => slab_isa::<3, false>(isa, &mut work, ctx, &bx, own, next),
            (_, true) => slab_isa::<2, true>(isa, &mut work, ctx, &bx, own, next),
            (_, false) => slab_isa::<2, false>(isa, &mut work, ctx, &bx, own, next),
        };
        self.energy = tally.energy;
        self.virial = tally.virial;
    }
}

/// The per-atom virial arrays of a slab's task (its own atoms, the next slab's).
pub(super) type VirialOut<'a> = (&'a mut [[f64; 6]], &'a mut [[f64; 6]]);

/// What the slab loop reads and the scratch it writes.
pub(super) struct SlabWork<'a> {
    /// The per-atom virial output, when it is tallied.
    pub(super) va: Option<VirialOut<'a>>,
    pub(super) start: usize,
    pub(super) end: usize,
    pub(super) next_start: usize,
    pub(super) row_start: &'a [u32],
    pub(super) nbr: &'a [u32],
    pub(super) scratch: &'a mut RowScratch,
}

pub(super) fn slab_isa<const DIM: usize, const ONE_TYPE: bool>(
    isa: Isa,
    w: &mut SlabWork,
    ctx: &Ctx,
    bx: &SimBox,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
) -> PairTally {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `ctx.isa` is one the CPU supports (`compute_forces` checks an override against
        // `Isa::best_supported`, and `Isa::detect` never exceeds it).
        Isa::Avx512 => unsafe { slab_avx512::<DIM, ONE_TYPE>(w, ctx, bx, own, next) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Isa::Avx2 => unsafe { slab_avx2::<DIM, ONE_TYPE>(w, ctx, bx, own, next) },
        _ => slab_run::<DIM, ONE_TYPE, PORTABLE>(w, ctx, bx, own, next),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) fn slab_avx512<const DIM: usize, const ONE_TYPE: bool>(
    w: &mut SlabWork,
    ctx: &Ctx,
    bx: &SimBox,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
) -> PairTally {
    slab_run::<DIM, ONE_TYPE, AVX512>(w, ctx, bx, own, next)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
pub(super) fn slab_avx2<const DIM: usize, const ONE_TYPE: bool>(
    w: &mut SlabWork,
    ctx: &Ctx,
    bx: &SimBox,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
) -> PairTally {
    slab_run::<DIM, ONE_TYPE, AVX2>(w, ctx, bx, own, next)
}

/// One row's inputs to the distance pass.
pub(super) struct RowArgs<'a> {
    pub(super) i: usize,
    pub(super) xi: [f64; 3],
    pub(super) vi: [f64; 3],
    pub(super) tag_i: u32,
    /// 1/m_i.
    pub(super) inv_mi: f64,
    pub(super) row: &'a [u32],
    /// `typ[i] · (ntypes + 1)`: the row of i's type in the coefficient table.
    pub(super) row_t: usize,
}

/// Per-slab constants of the distance pass.
pub(super) struct PassConst<'a> {
    pub(super) x: &'a [[f64; 3]],
    pub(super) v: &'a [[f64; 3]],
    pub(super) tag: &'a [u32],
    pub(super) typ: &'a [u32],
    /// 1/m by type.
    pub(super) inv_mass: &'a [f64],
    /// 1/m_i + 1/m_j with one atom type.
    pub(super) ims_one: f64,
    pub(super) rcsq: &'a [f64],
    pub(super) one_coeff: usize,
    pub(super) one_rcsq: f64,
    pub(super) min_sq: f64,
    pub(super) quarter: [f64; 3],
}

/// The slab loop. The pairs of each row enter the batch in a fixed order, the same with every
/// instruction set: first the pairs whose raw separation x_i − x_j is its own minimum image
/// (every component below a quarter of the box length; no image is crossed, so under
/// Lees–Edwards no offset either) and in range, in row order; then the others, through
/// `SimBox::min_image`, in row order. The distance pass over a row has no branches and runs in
/// SIMD lanes; full batches are evaluated by [`flush`].
// Kept in one piece (over 120 lines) on purpose: the hot loop, so the compiler sees the whole
// row and lane loop of each (DIM, ONE_TYPE, SIMD) instance at once.
#[inline(always)]
pub(super) fn slab_run<const DIM: usize, const ONE_TYPE: bool, const SIMD: u8>(
    w: &mut SlabWork,
    ctx: &Ctx,
    bx: &SimBox,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
) -> PairTally {
    let mut tally = PairTally::default();
    if bx.dim != DIM {
        return tally;
    }
    let mut p = Pending {
        batch: PairBatch::default(),
        i: [0; BATCH],
        j: [0; BATCH],
    };
    p.batch.images = ctx.short.map(|(_, frame)| frame);
    let (x, typ) = (ctx.x, ctx.typ);
    if x.is_empty() || typ.len() != x.len() || ctx.rcsq.is_empty() {
        return tally;
    }
    let box_len = bx.len();
    // One atom type: every pair has the coefficients of (1, 1), table index nt + 1.
    let one_coeff = ctx.nt + 1;
    if ctx.v.len() != x.len() || ctx.tag.len() != x.len() || ctx.inv_mass.len() < ctx.nt {
        return tally;
    }
    let pc = PassConst {
        x,
        v: ctx.v,
        tag: ctx.tag,
        typ,
        inv_mass: ctx.inv_mass,
        ims_one: ctx.inv_mass[1] + ctx.inv_mass[1],
        rcsq: ctx.rcsq,
        one_coeff,
        one_rcsq: ctx.rcsq.get(one_coeff).copied().unwrap_or(0.0),
        min_sq: MIN_PAIR_DISTANCE * MIN_PAIR_DISTANCE,
        // In a box shorter than 2 r_c every entry takes the image pass (a quarter of 0).
        quarter: if ctx.short.is_some() {
            [0.0; 3]
        } else {
            [0.25 * box_len[0], 0.25 * box_len[1], 0.25 * box_len[2]]
        },
    };
    let at = (w.start, w.next_start);
    let mut len = 0;
    let mut sink = Sink {
        ctx,
        own,
        next,
        at,
        tally: &mut tally,
        va: w.va.take(),
    };
    for i in w.start..w.end {
        let r = RowArgs {
            i,
            xi: x[i],
            vi: pc.v[i],
            tag_i: pc.tag[i],
            inv_mi: pc.inv_mass[typ[i] as usize],
            row: &w.nbr[w.row_start[i - w.start] as usize..w.row_start[i - w.start + 1] as usize],
            row_t: typ[i] as usize * ctx.nt,
        };
        let sc = &mut *w.scratch;
        sc.far.clear();
        #[cfg(target_arch = "x86_64")]
        if SIMD == AVX512 {
            // SAFETY: `SIMD` is AVX512 only inside `slab_avx512`, which runs only on CPUs with
            // AVX-512 (see `slab_isa`); every index in the row is < x.len() (list invariant,
            // checked in `compute_forces`), v and tag have x's length and every type < nt <=
            // inv_mass.len() (checked above and in `compute_forces`).
            unsafe {
                avx512::near_row::<ONE_TYPE>(&r, &pc, &mut p, &mut len, &mut sc.far, &mut sink)
            };
        } else if SIMD == AVX2 {
            // SAFETY: as above, with AVX2 (`slab_avx2`).
            unsafe {
                avx2::near_row::<ONE_TYPE>(&r, &pc, &mut p, &mut len, &mut sc.far, &mut sink)
            };
        } else {
            near_row::<ONE_TYPE>(&r, &pc, sc, &mut p, &mut len, &mut sink);
        }
        #[cfg(not(target_arch = "x86_64"))]
        near_row::<ONE_TYPE>(&r, &pc, sc, &mut p, &mut len, &mut sink);
        // Pairs through a periodic boundary: minimum images in a branch-free pass (it
        // vectorises), then the in-range ones appended in row order.
        let nf = sc.far.len();
        if let Some((short, _)) = ctx.short {
            // Every image in range, each its own pair (P-4b): scalar, small boxes only.
            far_images::<ONE_TYPE>(
                &r,
                &pc,
                &sc.far,
                short,
                (bx, ctx),
                &mut p,
                &mut len,
                &mut sink,
            );
        } else if nf > 0 {
            for v in sc.far_dr.iter_mut() {
                if v.len() < nf {
                    v.resize(nf, 0.0);
                }
            }
            if sc.far_keep.len() < nf {
                sc.far_keep.resize(nf, 0);
            }
            if ctx.le.is_some() && sc.far_dvx.len() < nf {
                sc.far_dvx.resize(nf, 0.0);
            }
            let (m, last) = (r.row.len(), x.len() - 1);
            let [fx, fy, fz] = &mut sc.far_dr;
            let (fx, fy, fz, fkeep) = (
                &mut fx[..nf],
                &mut fy[..nf],
                &mut fz[..nf],
                &mut sc.far_keep[..nf],
            );
            let xi = r.xi;
            let rcsq_of = |j: usize| {
                if ONE_TYPE {
                    pc.one_rcsq
                } else {
                    ctx.rcsq[(r.row_t + typ[j] as usize).min(ctx.rcsq.len() - 1)]
                }
            };
            match ctx.le {
                None => {
                    for q in 0..nf {
                        // Clamped indices (no-ops for a valid list): no exits, so the loop
                        // vectorises.
                        let j = (r.row[(sc.far[q] as usize).min(m - 1)] as usize).min(last);
                        let xj = x[j];
                        let d = bx.min_image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                        let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        let rcsq = rcsq_of(j);
                        fx[q] = d[0];
                        fy[q] = d[1];
                        fz[q] = d[2];
                        fkeep[q] = u32::from((rsq < rcsq) & (rsq >= pc.min_sq));
                    }
                }
                Some(le) => {
                    // The sliding-brick image of the current offset, and the velocity jump of
                    // the boundary the pair crosses (domain.rs `min_image_le`).
                    let fdvx = &mut sc.far_dvx[..nf];
                    for q in 0..nf {
                        let j = (r.row[(sc.far[q] as usize).min(m - 1)] as usize).min(last);
                        let xj = x[j];
                        let (d, dvx) =
                            bx.min_image_le([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]], &le);
                        let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        let rcsq = rcsq_of(j);
                        fx[q] = d[0];
                        fy[q] = d[1];
                        fz[q] = d[2];
                        fdvx[q] = dvx;
                        fkeep[q] = u32::from((rsq < rcsq) & (rsq >= pc.min_sq));
                    }
                }
            }
            let sheared = ctx.le.is_some();
            for q in 0..nf {
                let j = r.row[sc.far[q] as usize];
                let b = &mut p.batch;
                b.dr[0][len] = fx[q];
                b.dr[1][len] = fy[q];
                b.dr[2][len] = fz[q];
                append_rest::<ONE_TYPE>(&r, &pc, p_lane(&mut p, len), j);
                if sheared {
                    // v_ij with the boundary velocity jump.
                    p.batch.dv[0][len] += sc.far_dvx[q];
                }
                len += fkeep[q] as usize;
                if len == BATCH {
                    sink.evaluate::<ONE_TYPE>(&mut p, &mut len);
                }
            }
        }
    }
    sink.evaluate::<ONE_TYPE>(&mut p, &mut len);
    tally
}

/// The pairs of row `r` at its entries `far` in a box shorter than 2 r_c along the axes
/// `short`: every periodic image of each partner in range (`SimBox::images_within`), each its
/// own lane, keyed apart through the batch's image frame (P-4b). Out of line: the hot loop of
/// the ordinary box keeps its shape.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn far_images<const ONE_TYPE: bool>(
    r: &RowArgs,
    pc: &PassConst,
    far: &[u32],
    short: [bool; 3],
    (bx, ctx): (&SimBox, &Ctx),
    p: &mut Pending,
    len: &mut usize,
    sink: &mut Sink,
) {
    let mut images = Vec::with_capacity(27);
    for &q in far {
        let j = r.row[q as usize];
        let xj = pc.x[j as usize];
        let rcsq = if ONE_TYPE {
            pc.one_rcsq
        } else {
            ctx.rcsq[r.row_t + pc.typ[j as usize] as usize]
        };
        images.clear();
        bx.images_within(
            [r.xi[0] - xj[0], r.xi[1] - xj[1], r.xi[2] - xj[2]],
            ctx.le.as_ref(),
            short,
            rcsq,
            pc.min_sq,
            &mut images,
        );
        for &(d, dvx) in &images {
            let b = &mut p.batch;
            b.dr[0][*len] = d[0];
            b.dr[1][*len] = d[1];
            b.dr[2][*len] = d[2];
            append_rest::<ONE_TYPE>(r, pc, p_lane(p, *len), j);
            p.batch.dv[0][*len] += dvx;
            *len += 1;
            if *len == BATCH {
                sink.evaluate::<ONE_TYPE>(p, len);
            }
        }
    }
}

/// Lane `l` of the pending batch, for [`append_rest`].
#[inline(always)]
pub(super) fn p_lane(p: &mut Pending, l: usize) -> (&mut Pending, usize) {
    (p, l)
}

/// Fill lane `at.1` of the batch, apart from r_ij, for the pair (r.i, j): v_ij, the tags,
/// 1/m_i + 1/m_j, the coefficient index and the atom indices.
#[inline(always)]
pub(super) fn append_rest<const ONE_TYPE: bool>(
    r: &RowArgs,
    pc: &PassConst,
    at: (&mut Pending, usize),
    j: u32,
) {
    let (p, l) = at;
    let ju = j as usize;
    let vj = pc.v[ju];
    let b = &mut p.batch;
    b.dv[0][l] = r.vi[0] - vj[0];
    b.dv[1][l] = r.vi[1] - vj[1];
    b.dv[2][l] = r.vi[2] - vj[2];
    b.tag_i[l] = r.tag_i;
    b.tag_j[l] = pc.tag[ju];
    if ONE_TYPE {
        b.inv_mass_sum[l] = pc.ims_one;
        b.coeff[l] = pc.one_coeff as u32;
    } else {
        let tj = pc.typ[ju] as usize;
        b.inv_mass_sum[l] = r.inv_mi + pc.inv_mass[tj];
        b.coeff[l] = (r.row_t + tj) as u32;
    }
    p.i[l] = r.i as u32;
    p.j[l] = j;
}

/// The near pass of one row (portable): a branch-free distance pass into `sc`, then the
/// in-range near pairs appended in row order; the far entries' positions go to `sc.far`.
#[inline(always)]
pub(super) fn near_row<const ONE_TYPE: bool>(
    r: &RowArgs,
    pc: &PassConst,
    sc: &mut RowScratch,
    p: &mut Pending,
    len: &mut usize,
    sink: &mut Sink,
) {
    let m = r.row.len();
    for v in sc.dr.iter_mut() {
        if v.len() < m {
            v.resize(m, 0.0);
        }
    }
    if sc.keep.len() < m {
        sc.keep.resize(m, 0);
    }
    let last = pc.x.len() - 1;
    let xi = r.xi;
    let [drx, dry, drz] = &mut sc.dr;
    let (drx, dry, drz, keep) = (
        &mut drx[..m],
        &mut dry[..m],
        &mut drz[..m],
        &mut sc.keep[..m],
    );
    // Indices are clamped to the arrays (a no-op for a valid list) so that the loop has no
    // exits and can vectorise.
    for k in 0..m {
        let j = (r.row[k] as usize).min(last);
        let xj = pc.x[j];
        let d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
        let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let rcsq = if ONE_TYPE {
            pc.one_rcsq
        } else {
            pc.rcsq[(r.row_t + pc.typ[j] as usize).min(pc.rcsq.len() - 1)]
        };
        let far = (d[0].abs() >= pc.quarter[0])
            | (d[1].abs() >= pc.quarter[1])
            | (d[2].abs() >= pc.quarter[2]);
        drx[k] = d[0];
        dry[k] = d[1];
        drz[k] = d[2];
        keep[k] = u32::from((rsq < rcsq) & (rsq >= pc.min_sq) & !far) | (u32::from(far) << 1);
    }
    for k in 0..m {
        let j = r.row[k];
        if keep[k] > 1 {
            sc.far.push(k as u32);
        }
        let b = &mut p.batch;
        b.dr[0][*len] = drx[k];
        b.dr[1][*len] = dry[k];
        b.dr[2][*len] = drz[k];
        append_rest::<ONE_TYPE>(r, pc, p_lane(p, *len), j);
        *len += (keep[k] & 1) as usize;
        if *len == BATCH {
            sink.evaluate::<ONE_TYPE>(p, len);
        }
    }
}

/// Where evaluated pairs go: the slab's two force arrays (`own` from atom `at.0`, `next` from
/// atom `at.1`) and its tallies.
pub(super) struct Sink<'a, 'c> {
    pub(super) ctx: &'a Ctx<'c>,
    pub(super) own: &'a mut [[f64; 3]],
    pub(super) next: &'a mut [[f64; 3]],
    pub(super) at: (usize, usize),
    pub(super) tally: &'a mut PairTally,
    pub(super) va: Option<VirialOut<'a>>,
}

impl Sink<'_, '_> {
    /// Evaluate the `len` pending pairs ([`flush`]) and empty the batch.
    #[inline(always)]
    pub(super) fn evaluate<const ONE_TYPE: bool>(&mut self, p: &mut Pending, len: &mut usize) {
        p.batch.len = *len;
        flush::<ONE_TYPE>(self.ctx, p, self.own, self.next, self.at, self.tally);
        if let Some((vo, vn)) = self.va.as_mut() {
            virial_atoms(p, self.at, vo, vn);
        }
        p.batch.len = 0;
        *len = 0;
    }
}

/// Evaluate the pending pairs (filled completely by the passes that appended them) and add
/// their forces, energy and virial, in batch order. `own` starts at atom `at.0`, `next` at atom
/// `at.1`. Kept out of line: its scatter is faster as scalar code than as what the AVX-512
/// context would make of it.
#[inline(never)]
pub(super) fn flush<const ONE_TYPE: bool>(
    ctx: &Ctx,
    p: &mut Pending,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
    at: (usize, usize),
    tally: &mut PairTally,
) {
    let mut n = p.batch.len.min(BATCH);
    if let Some(sp) = ctx.special {
        n = apply_special(sp, p, n);
    }
    if n == 0 {
        return;
    }
    let b = &mut p.batch;
    ctx.kernel.evaluate(ctx.step, b, &p.i[..n], &p.j[..n]);
    let (start, next_start) = at;
    // The force on i is carried in registers over the consecutive pairs of its row and stored
    // when i changes: the same additions in the same order as adding into memory pair by pair
    // (j ≠ i, so no pair of the run touches own[i]), without a store-to-load chain.
    let mut cur = p.i[0] as usize - start;
    let mut fi = own[cur];
    // The tally in a local (registers), stored once: the same additions in the same order.
    let mut t = *tally;
    for l in 0..n {
        let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
        let s = b.fpair[l];
        let mut fv = [s * dr[0], s * dr[1], s * dr[2]];
        if b.transverse {
            // A kernel with a non-central part (`dpd/nonlinear/ext`): added as a vector.
            fv = [fv[0] + b.ft[0][l], fv[1] + b.ft[1][l], fv[2] + b.ft[2][l]];
        }
        let i = p.i[l] as usize - start;
        if i != cur {
            own[cur] = fi;
            cur = i;
            fi = own[cur];
        }
        fi[0] += fv[0];
        fi[1] += fv[1];
        fi[2] += fv[2];
        let j = p.j[l] as usize;
        let fj = match own.get_mut(j.wrapping_sub(start)) {
            Some(fj) => fj,
            None => &mut next[j - next_start],
        };
        fj[0] -= fv[0];
        fj[1] -= fv[1];
        fj[2] -= fv[2];
        t.add_pair(dr, fv, b.energy[l]);
    }
    own[cur] = fi;
    *tally = t;
    // The lanes evaluated (after the special pairs' filter), for `virial_atoms`.
    b.len = n;
}

/// The per-atom virial of the pairs [`flush`] just evaluated: ½ r_a F_b of each pair to each
/// of its two atoms, LAMMPS's `v_tally` (the same products as the global tally's, so the sum
/// over atoms is the global virial to round-off). Out of the force loop, which it leaves as
/// it is.
#[inline(never)]
fn virial_atoms(
    p: &Pending,
    (start, next_start): (usize, usize),
    vo: &mut [[f64; 6]],
    vn: &mut [[f64; 6]],
) {
    let b = &p.batch;
    for l in 0..b.len.min(BATCH) {
        let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
        let s = b.fpair[l];
        let mut fv = [s * dr[0], s * dr[1], s * dr[2]];
        if b.transverse {
            fv = [fv[0] + b.ft[0][l], fv[1] + b.ft[1][l], fv[2] + b.ft[2][l]];
        }
        let w = [
            0.5 * dr[0] * fv[0],
            0.5 * dr[1] * fv[1],
            0.5 * dr[2] * fv[2],
            0.5 * dr[0] * fv[1],
            0.5 * dr[0] * fv[2],
            0.5 * dr[1] * fv[2],
        ];
        for k in [p.i[l] as usize, p.j[l] as usize] {
            let v = match vo.get_mut(k.wrapping_sub(start)) {
                Some(v) => v,
                None => &mut vn[k - next_start],
            };
            for c in 0..6 {
                v[c] += w[c];
            }
        }
    }
}

/// The special pairs of a batch of `n` lanes (`docs/models.md` §4.8): a pair of bonded
/// partners whose class has factor 0 is removed (the lanes after it move up, in order), one of
/// a fractional factor gets the coefficient index of its class's block. Returns the lanes left.
#[inline(never)]
fn apply_special(sp: &crate::engine::topology::SpecialPairs, p: &mut Pending, n: usize) -> usize {
    use crate::engine::topology::SpecialAction;
    let mut w = 0;
    for l in 0..n {
        let class = sp.class_of(p.i[l] as usize, p.batch.tag_j[l]);
        let keep = match sp.rule.action(class) {
            SpecialAction::Keep => true,
            SpecialAction::Exclude => false,
            SpecialAction::Offset(o) => {
                p.batch.coeff[l] += o;
                true
            }
        };
        if !keep {
            continue;
        }
        if w != l {
            let b = &mut p.batch;
            for c in 0..3 {
                b.dr[c][w] = b.dr[c][l];
                b.dv[c][w] = b.dv[c][l];
            }
            b.inv_mass_sum[w] = b.inv_mass_sum[l];
            b.coeff[w] = b.coeff[l];
            b.tag_i[w] = b.tag_i[l];
            b.tag_j[w] = b.tag_j[l];
            p.i[w] = p.i[l];
            p.j[w] = p.j[l];
        }
        w += 1;
    }
    p.batch.len = w;
    w
}
