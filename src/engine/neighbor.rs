//! Cell-sorted half neighbour list and the deterministic pair-force evaluation.
//!
//! Atoms are sorted by cell (cells of side ≥ cut-off + skin, x fastest), so the atoms of one
//! layer of cells along the *slab axis* (z in 3-D, y in 2-D) form a contiguous index range, a
//! *slab*. With at least 3 slabs, the half list of an atom i in slab k holds
//! - the atoms j > i of its own slab in the neighbouring cells, and
//! - all atoms of slab k + 1 (periodically) in the neighbouring cells,
//!
//! so a slab's pairs touch only slab k and slab k + 1. Slabs are the parallel tasks, and need no
//! colouring: task k adds its forces on slab-k atoms into `f` (which it alone writes there) and its
//! forces on slab-(k+1) atoms into a second array (which it alone writes there), both starting from
//! zero in its fixed pair order. The force on an atom is then the sum of exactly two partial sums,
//! `own + next`, and IEEE addition is commutative: the result has the same bits whatever thread ran
//! which slab, and F_ji = −F_ij exactly (both come from one evaluation). Energy and virial are
//! summed per slab, then over slabs in order. Fewer than 3 slabs (small boxes): one task over the
//! whole list (j > i in every neighbouring cell).
//!
//! Inside a task, in-range pairs are gathered into a [`PairBatch`] and evaluated by the pair
//! style's [`PairKernel`] (`pair.rs`; for `dpd/nonlinear` [`crate::kernel::pair_forces_batch`],
//! the same function as [`crate::kernel::pair_force`], in SIMD lanes). The displacement of every
//! pair is the box's minimum image, computed per pair.

use super::atoms::Atoms;
use super::domain::SimBox;
use super::pair::PairKernel;
use crate::kernel::{BATCH, Isa, MIN_PAIR_DISTANCE, PairBatch, PairCoeff};
use rayon::prelude::*;

/// The linear index of cell coordinates (x fastest).
#[inline]
fn cell_id(c: [usize; 3], ncell: [usize; 3]) -> usize {
    (c[2] * ncell[1] + c[1]) * ncell[0] + c[0]
}

/// One slab (or, in serial mode, all atoms): its atoms' rows and its tallies.
#[derive(Clone, Debug, Default)]
struct Slab {
    start: usize,
    end: usize,
    /// First atom of the next slab (where the `next` forces go); `end` in serial mode.
    next_start: usize,
    row_start: Vec<u32>,
    nbr: Vec<u32>,
    /// The working list: each row's entries within `rc_max + margin` at its build, in row order.
    in_row_start: Vec<u32>,
    in_nbr: Vec<u32>,
    scratch: RowScratch,
    virial: [f64; 6],
    energy: f64,
}

/// Energy and virial of one force evaluation (sums over pairs, not normalised).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairTally {
    /// Σ conservative pair energy.
    pub energy: f64,
    /// Σ_{pairs} r_ij,a F_ij,b in LAMMPS order xx, yy, zz, xy, xz, yz (all force parts).
    pub virial: [f64; 6],
}

impl PairTally {
    /// Adds one pair: its conservative energy and r_ij,a F_ij,b (xx, yy, zz, xy, xz, yz), in this
    /// order, so every pair loop sums the same way.
    #[inline(always)]
    pub fn add_pair(&mut self, dr: [f64; 3], fv: [f64; 3], energy: f64) {
        self.energy += energy;
        self.virial[0] += dr[0] * fv[0];
        self.virial[1] += dr[1] * fv[1];
        self.virial[2] += dr[2] * fv[2];
        self.virial[3] += dr[0] * fv[1];
        self.virial[4] += dr[0] * fv[2];
        self.virial[5] += dr[1] * fv[2];
    }
}

/// The neighbour list with its cell sort and force buffers. Buffers are reused between builds, so
/// the step loop does not allocate once they have reached their working size.
#[derive(Debug, Default)]
pub struct NeighborList {
    /// Skin distance added to the largest cut-off.
    pub skin: f64,
    /// Number of builds so far.
    pub builds: u64,
    slabs: Vec<Slab>,
    /// Forces of slab k's task on the atoms of slab k + 1 (slab mode only).
    next_f: Vec<[f64; 3]>,
    x_at_build: Vec<[f64; 3]>,
    cell_of: Vec<u32>,
    cell_count: Vec<u32>,
    cell_start: Vec<u32>,
    perm: Vec<u32>,
    perm_scratch: PermScratch,
    rcsq: Vec<f64>,
    ncell: [usize; 3],
    stencil_axes: [Vec<Vec<(usize, i8)>>; 3],
    xruns: Vec<Vec<(usize, usize, i8)>>,
    isa: Option<Isa>,
    /// Working list: on/off override (None: decided from the list's lifetime).
    inner_override: Option<bool>,
    /// Whether the working list is in use for the current list.
    inner_on: bool,
    /// Its rows need rebuilding (new list, or atoms moved more than margin/2).
    inner_stale: bool,
    /// Force evaluations since the last build, and over the whole previous list.
    evals_since_build: u64,
    last_life: u64,
    /// Cut-off of the list (rc_max + skin) and of the working list (rc_max + margin).
    cutoff: f64,
    rc_max: f64,
    x_at_inner: Vec<[f64; 3]>,
}

/// The working list's margin as a fraction of the skin, and the list lifetime (force
/// evaluations) from which it pays: it is rebuilt, by a filter pass over the list, whenever an
/// atom has moved margin/2, so it needs lists that live long (slow atoms, small steps).
const INNER_MARGIN: f64 = 1.0 / 3.0;
const INNER_MIN_LIFE: u64 = 12;

impl NeighborList {
    /// Use this instruction set for the pair loop instead of the best one ([`Isa::detect`]);
    /// one the CPU lacks falls back to [`Isa::Baseline`]. For tests and benchmarks: the results
    /// are the same bits with every instruction set.
    pub fn set_isa(&mut self, isa: Option<Isa>) {
        self.isa = isa;
    }

    /// Force the working list (a subsequence of the list with margin skin/3, rebuilt from it
    /// when an atom has moved skin/6) on or off; `None` (the default) uses it when lists last
    /// at least 12 force evaluations. For tests and benchmarks: the results are the same bits
    /// either way, because a pair enters the kernel batch in the same order.
    pub fn set_working_list(&mut self, on: Option<bool>) {
        self.inner_override = on;
    }

    /// True when the working list is in use.
    pub fn working_list(&self) -> bool {
        self.inner_on
    }

    /// An empty list with the given skin.
    pub fn new(skin: f64) -> NeighborList {
        NeighborList {
            skin,
            ..Default::default()
        }
    }

    /// True when some atom moved more than half the skin since the last build (or never built).
    pub fn needs_rebuild(&self, atoms: &Atoms) -> bool {
        if self.x_at_build.len() != atoms.len() || self.builds == 0 {
            return true;
        }
        let limit = 0.25 * self.skin * self.skin;
        atoms
            .x
            .par_iter()
            .zip(self.x_at_build.par_iter())
            .any(|(x, x0)| {
                let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
            })
    }

    /// Number of pairs held in the list.
    pub fn pairs(&self) -> usize {
        self.slabs.iter().map(|b| b.nbr.len()).sum()
    }

    /// Number of pairs held in the working list (0 when it is off).
    pub fn working_pairs(&self) -> usize {
        if self.inner_on {
            self.slabs.iter().map(|b| b.in_nbr.len()).sum()
        } else {
            0
        }
    }

    /// Bytes held by the list and its buffers (for the memory report).
    pub fn bytes(&self) -> usize {
        let rows: usize = self
            .slabs
            .iter()
            .map(|b| {
                (b.row_start.capacity() + b.nbr.capacity()) * 4
                    + (b.in_row_start.capacity() + b.in_nbr.capacity()) * 4
            })
            .sum();
        rows + self.next_f.capacity() * 24
            + self.x_at_build.capacity() * 24
            + self.x_at_inner.capacity() * 24
            + (self.cell_of.capacity() + self.perm.capacity()) * 4
            + (self.cell_count.capacity() + self.cell_start.capacity()) * 4
            + self.perm_scratch.vec3.capacity() * 24
            + self.perm_scratch.u32s.capacity() * 4
            + self.perm_scratch.int3.capacity() * 12
    }

    /// Wrap positions into the box, sort atoms by cell, and build the half list with cut-off
    /// `rc_max + skin`. Atom order changes; every per-atom array travels with the atoms.
    pub fn build(&mut self, atoms: &mut Atoms, bx: &SimBox, rc_max: f64) {
        let n = atoms.len();
        atoms
            .x
            .par_iter_mut()
            .zip(atoms.image.par_iter_mut())
            .for_each(|(x, im)| bx.wrap(x, im));
        let cutoff = rc_max + self.skin;
        let len = bx.len();
        let mut ncell = [1usize; 3];
        for d in 0..bx.dim {
            ncell[d] = ((len[d] / cutoff).floor() as usize).max(1);
        }
        if ncell != self.ncell {
            self.ncell = ncell;
            for d in 0..3 {
                let m = ncell[d];
                // (neighbour coordinate, image): the neighbour cell is reached directly (0) or
                // through the periodic boundary; then its atoms' nearest images are at x_j − L
                // (+1: the cell below 0 is m − 1) or x_j + L (−1: the cell above m − 1 is 0),
                // and x_i − image = (x_i ± L) − x_j. With fewer than 3 cells the neighbours are
                // all cells and the image is decided per pair (AMBIGUOUS).
                let periodic = d < bx.dim;
                self.stencil_axes[d] = (0..m)
                    .map(|c| {
                        if m >= 3 {
                            vec![
                                ((c + m - 1) % m, if c == 0 { 1 } else { 0 }),
                                (c, 0),
                                ((c + 1) % m, if c == m - 1 { -1 } else { 0 }),
                            ]
                        } else {
                            let img = if periodic { AMBIGUOUS } else { 0 };
                            (0..m).map(|k| (k, img)).collect()
                        }
                    })
                    .collect();
            }
            let m = ncell[0];
            self.xruns = (0..m)
                .map(|c| {
                    if m < 3 {
                        (0..m).map(|k| (k, k, AMBIGUOUS)).collect()
                    } else if c == 0 {
                        vec![(0, 1, 0), (m - 1, m - 1, 1)]
                    } else if c == m - 1 {
                        vec![(0, 0, -1), (m - 2, m - 1, 0)]
                    } else {
                        vec![(c - 1, c + 1, 0)]
                    }
                })
                .collect();
        }
        let total_cells = ncell[0] * ncell[1] * ncell[2];
        let cell_coords = CellCoords {
            lo: bx.lo,
            len,
            ncell,
            dim: bx.dim,
        };
        // Counting sort by cell, stable in the current order.
        self.cell_of.clear();
        self.cell_of.par_extend(
            atoms
                .x
                .par_iter()
                .map(|x| cell_id(cell_coords.of(x), ncell) as u32),
        );
        self.cell_count.clear();
        self.cell_count.resize(total_cells + 1, 0);
        for &c in &self.cell_of {
            self.cell_count[c as usize + 1] += 1;
        }
        for c in 0..total_cells {
            self.cell_count[c + 1] += self.cell_count[c];
        }
        self.cell_start.clear();
        self.cell_start.extend_from_slice(&self.cell_count);
        self.perm.clear();
        self.perm.resize(n, 0);
        for (i, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut self.cell_count[c as usize];
            self.perm[*slot as usize] = i as u32;
            *slot += 1;
        }
        permute(atoms, &self.perm, &mut self.perm_scratch);

        // Slabs: layers of cells along the last periodic axis (contiguous in the cell order).
        let axis = bx.dim - 1;
        let layers = ncell[axis];
        let slab_mode = layers >= 3;
        let nslabs = if slab_mode { layers } else { 1 };
        let cells_per_slab = total_cells / nslabs;
        self.slabs.resize_with(nslabs, Slab::default);
        for (k, s) in self.slabs.iter_mut().enumerate() {
            s.start = self.cell_start[k * cells_per_slab] as usize;
            s.end = self.cell_start[(k + 1) * cells_per_slab] as usize;
            s.next_start = if slab_mode {
                self.cell_start[((k + 1) % nslabs) * cells_per_slab] as usize
            } else {
                s.end
            };
        }
        if slab_mode {
            self.next_f.resize(n, [0.0; 3]);
        } else {
            self.next_f = Vec::new();
        }

        // Rows, slab by slab (each slab independent: parallel and deterministic).
        let rows = RowBuild {
            x: &atoms.x,
            bx,
            cells: cell_coords,
            cell_start: &self.cell_start,
            axes: &self.stencil_axes,
            xruns: &self.xruns,
            len,
            cutsq: cutoff * cutoff,
            slab_axis: if slab_mode { Some(bx.dim - 1) } else { None },
        };
        let isa = match self.isa {
            Some(i) if (i as u8) <= (Isa::best_supported() as u8) => i,
            Some(_) => Isa::Baseline,
            None => Isa::detect(),
        };
        self.slabs
            .par_iter_mut()
            .for_each(|s| build_rows_isa(isa, &rows, s));

        self.x_at_build.clear();
        self.x_at_build.extend_from_slice(&atoms.x);
        self.builds += 1;
        self.last_life = self.evals_since_build;
        self.evals_since_build = 0;
        self.cutoff = cutoff;
        self.rc_max = rc_max;
        self.inner_on = self.skin > 0.0
            && self
                .inner_override
                .unwrap_or(self.last_life >= INNER_MIN_LIFE);
        self.inner_stale = true;
        if !self.inner_on {
            for s in self.slabs.iter_mut() {
                s.in_row_start = Vec::new();
                s.in_nbr = Vec::new();
            }
            self.x_at_inner = Vec::new();
        }
    }

    /// Rebuild the working list if it is in use and stale or an atom moved margin/2 since.
    fn refresh_inner(&mut self, atoms: &Atoms, bx: &SimBox) {
        if !self.inner_on
            && self.inner_override.is_none()
            && self.skin > 0.0
            && self.evals_since_build >= INNER_MIN_LIFE
        {
            // This list lives long: switch the working list on.
            self.inner_on = true;
            self.inner_stale = true;
        }
        if !self.inner_on {
            return;
        }
        let margin = INNER_MARGIN * self.skin;
        if !self.inner_stale {
            let limit = 0.25 * margin * margin;
            let moved = atoms
                .x
                .par_iter()
                .zip(self.x_at_inner.par_iter())
                .any(|(x, x0)| {
                    let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
                });
            if !moved {
                return;
            }
        }
        let cut = self.rc_max + margin;
        let cutsq = cut * cut;
        let len = bx.len();
        let quarter = [0.25 * len[0], 0.25 * len[1], 0.25 * len[2]];
        let x = &atoms.x;
        self.slabs.par_iter_mut().for_each(|s| {
            s.in_row_start.clear();
            s.in_nbr.clear();
            s.in_row_start.push(0);
            let mut len = 0usize;
            for (r, i) in (s.start..s.end).enumerate() {
                let row = &s.nbr[s.row_start[r] as usize..s.row_start[r + 1] as usize];
                let xi = x[i];
                // Branch-free append of the entries within the cut (a subsequence of the row).
                s.in_nbr.resize(len + row.len(), 0);
                for &j in row {
                    let xj = x[j as usize];
                    let mut d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                    if (d[0].abs() >= quarter[0])
                        | (d[1].abs() >= quarter[1])
                        | (d[2].abs() >= quarter[2])
                    {
                        d = bx.min_image(d);
                    }
                    s.in_nbr[len] = j;
                    len += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutsq);
                }
                s.in_nbr.truncate(len);
                s.in_row_start.push(len as u32);
            }
        });
        self.x_at_inner.clear();
        self.x_at_inner.extend_from_slice(x);
        self.inner_stale = false;
    }

    /// The instruction set the pair loop uses: the override of [`NeighborList::set_isa`] if
    /// this CPU supports it (else the baseline), or the best the CPU has.
    pub fn isa(&self) -> Isa {
        match self.isa {
            Some(i) if (i as u8) <= (Isa::best_supported() as u8) => i,
            Some(_) => Isa::Baseline,
            None => Isa::detect(),
        }
    }

    /// Evaluate all pair forces of `kernel` at `step` (the noise key), overwrite `atoms.f`, and
    /// return the energy and virial. `table` holds the cut-offs of the `ntypes` types (dense,
    /// `(ntypes + 1)²`), `inv_mass[t]` is 1/m of type t. Requires a current list; `isa` is the
    /// instruction set of the distance pass (the kernel has its own).
    #[allow(clippy::too_many_arguments)]
    pub fn compute_forces(
        &mut self,
        atoms: &mut Atoms,
        bx: &SimBox,
        kernel: &dyn PairKernel,
        table: &[PairCoeff],
        ntypes: usize,
        inv_mass: &[f64],
        step: u64,
    ) -> PairTally {
        // The invariants the unchecked (SIMD gather) reads rely on: the list was built for these
        // atoms (so every listed index is < n), and every type indexes the table.
        assert_eq!(
            atoms.len(),
            self.x_at_build.len(),
            "neighbour list built for a different number of atoms"
        );
        let nt = ntypes + 1;
        assert!(
            table.len() == nt * nt && atoms.typ.par_iter().all(|&t| (t as usize) < nt),
            "atom type outside the coefficient table"
        );
        self.evals_since_build += 1;
        self.refresh_inner(atoms, bx);
        self.rcsq.clear();
        self.rcsq.extend(table.iter().map(|c| c.rc * c.rc));
        let isa = self.isa();
        let ctx = Ctx {
            inner: self.inner_on,
            isa,
            bx,
            kernel,
            rcsq: &self.rcsq,
            inv_mass,
            nt,
            step,
            x: &atoms.x,
            v: &atoms.v,
            tag: &atoms.tag,
            typ: &atoms.typ,
        };
        let f = &mut atoms.f;
        if self.slabs.len() == 1 {
            let s = &mut self.slabs[0];
            s.compute(&ctx, f, &mut []);
        } else {
            // Slab k writes f[slab k] and next_f[slab k + 1] (periodically): disjoint slices.
            let mut own: Vec<&mut [[f64; 3]]> = Vec::with_capacity(self.slabs.len());
            let mut next: Vec<&mut [[f64; 3]]> = Vec::with_capacity(self.slabs.len());
            let (mut rest_f, mut rest_n) = (&mut f[..], &mut self.next_f[..]);
            for s in &self.slabs {
                let (a, b) = std::mem::take(&mut rest_f).split_at_mut(s.end - s.start);
                let (c, d) = std::mem::take(&mut rest_n).split_at_mut(s.end - s.start);
                own.push(a);
                next.push(c);
                rest_f = b;
                rest_n = d;
            }
            next.rotate_left(1);
            self.slabs
                .par_iter_mut()
                .zip(own.into_par_iter().zip(next.into_par_iter()))
                .for_each(|(s, (own, next))| s.compute(&ctx, own, next));
            // f = own + next: one addition of two partial sums per component (commutative).
            f.par_iter_mut()
                .zip(self.next_f.par_iter())
                .for_each(|(f, n)| {
                    f[0] += n[0];
                    f[1] += n[1];
                    f[2] += n[2];
                });
        }

        let mut tally = PairTally::default();
        for s in &self.slabs {
            tally.energy += s.energy;
            for a in 0..6 {
                tally.virial[a] += s.virial[a];
            }
        }
        tally
    }
}

/// Everything a slab task reads.
struct Ctx<'a> {
    /// Iterate the working list instead of the list.
    inner: bool,
    /// The instruction set of the pair loop (supported by this CPU).
    isa: Isa,
    bx: &'a SimBox,
    /// The pair style's batch evaluation (`pair.rs`).
    kernel: &'a dyn PairKernel,
    rcsq: &'a [f64],
    inv_mass: &'a [f64],
    nt: usize,
    step: u64,
    x: &'a [[f64; 3]],
    v: &'a [[f64; 3]],
    tag: &'a [u32],
    typ: &'a [u32],
}

/// A batch of in-range pairs with the atom indices they belong to.
struct Pending {
    batch: PairBatch,
    i: [u32; BATCH],
    j: [u32; BATCH],
}

/// One row's candidate pairs after the distance pass (reused between rows and steps).
#[derive(Clone, Debug, Default)]
struct RowScratch {
    dr: [Vec<f64>; 3],
    keep: Vec<u32>,
    /// Row positions of the entries through a periodic boundary.
    far: Vec<u32>,
    /// Their minimum-image separations and in-range flags.
    far_dr: [Vec<f64>; 3],
    far_keep: Vec<u32>,
}

impl Slab {
    /// All pairs of this slab's rows: forces on slab atoms into `own` (indexed from `start`),
    /// on next-slab atoms into `next` (indexed from `next_start`), both overwritten.
    fn compute(&mut self, ctx: &Ctx, own: &mut [[f64; 3]], next: &mut [[f64; 3]]) {
        own.fill([0.0; 3]);
        next.fill([0.0; 3]);
        let mut work = SlabWork {
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

/// What the slab loop reads and the scratch it writes.
struct SlabWork<'a> {
    start: usize,
    end: usize,
    next_start: usize,
    row_start: &'a [u32],
    nbr: &'a [u32],
    scratch: &'a mut RowScratch,
}

fn slab_isa<const DIM: usize, const ONE_TYPE: bool>(
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
        _ => slab_run::<DIM, ONE_TYPE, false>(w, ctx, bx, own, next),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
fn slab_avx512<const DIM: usize, const ONE_TYPE: bool>(
    w: &mut SlabWork,
    ctx: &Ctx,
    bx: &SimBox,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
) -> PairTally {
    slab_run::<DIM, ONE_TYPE, true>(w, ctx, bx, own, next)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
fn slab_avx2<const DIM: usize, const ONE_TYPE: bool>(
    w: &mut SlabWork,
    ctx: &Ctx,
    bx: &SimBox,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
) -> PairTally {
    slab_run::<DIM, ONE_TYPE, false>(w, ctx, bx, own, next)
}

/// One row's inputs to the distance pass.
struct RowArgs<'a> {
    i: usize,
    xi: [f64; 3],
    vi: [f64; 3],
    tag_i: u32,
    /// 1/m_i.
    inv_mi: f64,
    row: &'a [u32],
    /// `typ[i] · (ntypes + 1)`: the row of i's type in the coefficient table.
    row_t: usize,
}

/// Per-slab constants of the distance pass.
struct PassConst<'a> {
    x: &'a [[f64; 3]],
    v: &'a [[f64; 3]],
    tag: &'a [u32],
    typ: &'a [u32],
    /// 1/m by type.
    inv_mass: &'a [f64],
    /// 1/m_i + 1/m_j with one atom type.
    ims_one: f64,
    rcsq: &'a [f64],
    one_coeff: usize,
    one_rcsq: f64,
    min_sq: f64,
    quarter: [f64; 3],
}

/// The slab loop. The pairs of each row enter the batch in a fixed order, the same with every
/// instruction set: first the pairs whose raw separation x_i − x_j is its own minimum image
/// (every component below a quarter of the box length; no image is crossed, so under
/// Lees–Edwards no offset either) and in range, in row order; then the others, through
/// `SimBox::min_image`, in row order. The distance pass over a row has no branches and runs in
/// SIMD lanes; full batches are evaluated by [`flush`].
#[inline(always)]
fn slab_run<const DIM: usize, const ONE_TYPE: bool, const AVX512: bool>(
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
        quarter: [0.25 * box_len[0], 0.25 * box_len[1], 0.25 * box_len[2]],
    };
    let at = (w.start, w.next_start);
    let mut len = 0;
    let mut sink = Sink {
        ctx,
        own,
        next,
        at,
        tally: &mut tally,
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
        if AVX512 {
            // SAFETY: `AVX512` is true only inside `slab_avx512`, which runs only on CPUs with
            // AVX-512 (see `slab_isa`); every index in the row is < x.len() (list invariant,
            // checked in `compute_forces`), v and tag have x's length and every type < nt <=
            // inv_mass.len() (checked above and in `compute_forces`).
            unsafe {
                avx512::near_row::<ONE_TYPE>(&r, &pc, &mut p, &mut len, &mut sc.far, &mut sink)
            };
        } else {
            near_row::<ONE_TYPE>(&r, &pc, sc, &mut p, &mut len, &mut sink);
        }
        #[cfg(not(target_arch = "x86_64"))]
        near_row::<ONE_TYPE>(&r, &pc, sc, &mut p, &mut len, &mut sink);
        // Pairs through a periodic boundary: minimum images in a branch-free pass (it
        // vectorises), then the in-range ones appended in row order.
        let nf = sc.far.len();
        if nf > 0 {
            for v in sc.far_dr.iter_mut() {
                if v.len() < nf {
                    v.resize(nf, 0.0);
                }
            }
            if sc.far_keep.len() < nf {
                sc.far_keep.resize(nf, 0);
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
            for q in 0..nf {
                // Clamped indices (no-ops for a valid list): no exits, so the loop vectorises.
                let j = (r.row[(sc.far[q] as usize).min(m - 1)] as usize).min(last);
                let xj = x[j];
                let d = bx.min_image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let rcsq = if ONE_TYPE {
                    pc.one_rcsq
                } else {
                    ctx.rcsq[(r.row_t + typ[j] as usize).min(ctx.rcsq.len() - 1)]
                };
                fx[q] = d[0];
                fy[q] = d[1];
                fz[q] = d[2];
                fkeep[q] = u32::from((rsq < rcsq) & (rsq >= pc.min_sq));
            }
            for q in 0..nf {
                let j = r.row[sc.far[q] as usize];
                let b = &mut p.batch;
                b.dr[0][len] = fx[q];
                b.dr[1][len] = fy[q];
                b.dr[2][len] = fz[q];
                append_rest::<ONE_TYPE>(&r, &pc, p_lane(&mut p, len), j);
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

/// Lane `l` of the pending batch, for [`append_rest`].
#[inline(always)]
fn p_lane(p: &mut Pending, l: usize) -> (&mut Pending, usize) {
    (p, l)
}

/// Fill lane `at.1` of the batch, apart from r_ij, for the pair (r.i, j): v_ij, the tags,
/// 1/m_i + 1/m_j, the coefficient index and the atom indices.
#[inline(always)]
fn append_rest<const ONE_TYPE: bool>(
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
fn near_row<const ONE_TYPE: bool>(
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
struct Sink<'a, 'c> {
    ctx: &'a Ctx<'c>,
    own: &'a mut [[f64; 3]],
    next: &'a mut [[f64; 3]],
    at: (usize, usize),
    tally: &'a mut PairTally,
}

impl Sink<'_, '_> {
    /// Evaluate the `len` pending pairs ([`flush`]) and empty the batch.
    #[inline(always)]
    fn evaluate<const ONE_TYPE: bool>(&mut self, p: &mut Pending, len: &mut usize) {
        p.batch.len = *len;
        flush::<ONE_TYPE>(self.ctx, p, self.own, self.next, self.at, self.tally);
        *len = 0;
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    //! The near pass of one row with AVX-512: 8 entries at a time, positions gathered, the
    //! in-range near pairs compressed into the batch. Same pairs, same order, same bits as the
    //! portable `near_row`.
    use super::{BATCH, PassConst, Pending, RowArgs, Sink};
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
                let [gx, gy, gz] =
                    transpose8([at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7)]);
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
}

/// Evaluate the pending pairs (filled completely by the passes that appended them) and add
/// their forces, energy and virial, in batch order. `own` starts at atom `at.0`, `next` at atom
/// `at.1`. Kept out of line: its scatter is faster as scalar code than as what the AVX-512
/// context would make of it.
#[inline(never)]
fn flush<const ONE_TYPE: bool>(
    ctx: &Ctx,
    p: &mut Pending,
    own: &mut [[f64; 3]],
    next: &mut [[f64; 3]],
    at: (usize, usize),
    tally: &mut PairTally,
) {
    let n = p.batch.len.min(BATCH);
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
    for l in 0..n {
        let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
        let s = b.fpair[l];
        let fv = [s * dr[0], s * dr[1], s * dr[2]];
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
        tally.add_pair(dr, fv, b.energy[l]);
    }
    own[cur] = fi;
    b.len = 0;
}

/// Stencil image code: the neighbour cell's periodic image is decided per pair.
const AMBIGUOUS: i8 = 2;

/// Cell coordinates of a position (the box is periodic and positions are wrapped, so the
/// scaled coordinate is ≥ 0 and truncation is the floor).
#[derive(Clone, Copy, Debug)]
struct CellCoords {
    lo: [f64; 3],
    len: [f64; 3],
    ncell: [usize; 3],
    dim: usize,
}

impl CellCoords {
    #[inline(always)]
    fn of(&self, x: &[f64; 3]) -> [usize; 3] {
        let mut c = [0usize; 3];
        for d in 0..self.dim {
            let f = (x[d] - self.lo[d]) / self.len[d] * self.ncell[d] as f64;
            c[d] = (f.max(0.0) as usize).min(self.ncell[d] - 1);
        }
        c
    }
}

/// What building the rows of a slab reads.
struct RowBuild<'a> {
    x: &'a [[f64; 3]],
    bx: &'a SimBox,
    cells: CellCoords,
    cell_start: &'a [u32],
    axes: &'a [Vec<Vec<(usize, i8)>>; 3],
    /// For each x cell coordinate, its neighbour cells along x as runs (first, last, image),
    /// in increasing order.
    xruns: &'a [Vec<(usize, usize, i8)>],
    /// Box lengths (for image shifts).
    len: [f64; 3],
    cutsq: f64,
    /// The slab axis in slab mode; None: one task, j > i in every neighbouring cell.
    slab_axis: Option<usize>,
}

fn build_rows_isa(isa: Isa, rb: &RowBuild, s: &mut Slab) {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `isa` is one the CPU supports (checked against `Isa::best_supported`).
        Isa::Avx512 => unsafe { build_rows_avx512(rb, s) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Isa::Avx2 => unsafe { build_rows_avx2(rb, s) },
        _ => build_rows::<false>(rb, s),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
fn build_rows_avx512(rb: &RowBuild, s: &mut Slab) {
    build_rows::<true>(rb, s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
fn build_rows_avx2(rb: &RowBuild, s: &mut Slab) {
    build_rows::<false>(rb, s)
}

/// The rows of one slab: for each atom, the atoms of the neighbouring cells (stencil order,
/// increasing index within a cell) within the list cut-off. A cell reached without crossing
/// the periodic boundary is scanned with raw separations (exact for the cut-off test: with at
/// least 3 cells of side ≥ cut-off per axis, a pair within the cut-off has its raw separation
/// as minimum image); the others go through `SimBox::min_image`.
#[inline(always)]
fn build_rows<const AVX512: bool>(rb: &RowBuild, s: &mut Slab) {
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
                s.nbr.resize(need.max(2 * s.nbr.len()), 0);
            }
            let mut l = len;
            if img.contains(&AMBIGUOUS) {
                for j in lo..hi {
                    let xj = x[j];
                    let d = rb
                        .bx
                        .min_image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                    s.nbr[l] = j as u32;
                    l += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < rb.cutsq);
                }
                len = l;
                return;
            }
            // x_i − (x_j − image · L) = (x_i + image · L) − x_j. (A sheared boundary would add
            // its offset here.)
            let xs = [0, 1, 2].map(|k| xi[k] + f64::from(img[k]) * rb.len[k]);
            #[cfg(target_arch = "x86_64")]
            if AVX512 {
                // SAFETY: only inside `build_rows_avx512` (AVX-512 present); lo..hi are atom
                // indices < x.len(); s.nbr has room for len + (hi − lo) + 8 entries.
                len = unsafe { avx512::scan_cell(xs, x, lo, hi, rb.cutsq, &mut s.nbr, l) };
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
        // one index range unless one of them is across the boundary.
        let xruns = &rb.xruns[c[0]];
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
                    for &(x0, x1, ix) in xruns {
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
                    for &(x0, x1, ix) in xruns {
                        let a = cell_id([x0, cy, cz], ncell);
                        scan((a, a + (x1 - x0)), i + 1, [ix, iy, iz]);
                    }
                }
            }
        }
        s.row_start.push(len as u32);
    }
    s.nbr.truncate(len);
}

/// Reorder every per-atom array by `perm` (new index k holds old atom `perm[k]`): a parallel
/// gather into one scratch array per element type, swapped with the field (so the scratch
/// holds the old array for the next field of that type). The destructuring names every field
/// of [`Atoms`]: a field added there fails to compile here until it is permuted too.
fn permute(atoms: &mut Atoms, perm: &[u32], scratch: &mut PermScratch) {
    fn gather<T: Copy + Send + Sync>(a: &mut Vec<T>, perm: &[u32], tmp: &mut Vec<T>) {
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
    } = atoms;
    gather(x, perm, &mut scratch.vec3);
    gather(v, perm, &mut scratch.vec3);
    gather(f, perm, &mut scratch.vec3);
    gather(tag, perm, &mut scratch.u32s);
    gather(typ, perm, &mut scratch.u32s);
    gather(image, perm, &mut scratch.int3);
}

/// Scratch arrays of [`permute`], one per element type (kept between builds).
#[derive(Clone, Debug, Default)]
struct PermScratch {
    vec3: Vec<[f64; 3]>,
    u32s: Vec<u32>,
    int3: Vec<[i32; 3]>,
}
