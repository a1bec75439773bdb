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
//! Inside a task, in-range pairs are gathered into a [`PairBatch`] and evaluated by
//! [`crate::kernel::pair_forces_batch`] (the same function as [`crate::kernel::pair_force`], in SIMD lanes). The
//! displacement of every pair is the box's minimum image, computed per pair.

use super::atoms::Atoms;
use super::domain::SimBox;
use super::forcefield::ForceField;
use crate::kernel::{
    BATCH, Isa, MIN_PAIR_DISTANCE, PairBatch, PairCoeff, PairTable, pair_forces_batch_isa,
};
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
    visited: Vec<u64>,
    rcsq: Vec<f64>,
    ncell: [usize; 3],
    stencil_axes: [Vec<Vec<usize>>; 3],
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
            + self.visited.capacity() * 8
    }

    /// Wrap positions into the box, sort atoms by cell, and build the half list with cut-off
    /// `rc_max + skin`. Atom order changes; every per-atom array travels with the atoms.
    pub fn build(&mut self, atoms: &mut Atoms, bx: &SimBox, rc_max: f64) {
        let n = atoms.len();
        for (x, im) in atoms.x.iter_mut().zip(atoms.image.iter_mut()) {
            bx.wrap(x, im);
        }
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
                self.stencil_axes[d] = (0..m)
                    .map(|c| {
                        if m >= 3 {
                            vec![(c + m - 1) % m, c, (c + 1) % m]
                        } else {
                            (0..m).collect()
                        }
                    })
                    .collect();
            }
        }
        let total_cells = ncell[0] * ncell[1] * ncell[2];
        let cell_coords = |x: &[f64; 3]| -> [usize; 3] {
            let mut c = [0usize; 3];
            for d in 0..bx.dim {
                let f = ((x[d] - bx.lo[d]) / len[d] * ncell[d] as f64).floor();
                c[d] = (f.max(0.0) as usize).min(ncell[d] - 1);
            }
            c
        };
        // Counting sort by cell, stable in the current order.
        self.cell_of.clear();
        self.cell_of.extend(
            atoms
                .x
                .iter()
                .map(|x| cell_id(cell_coords(x), ncell) as u32),
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
        permute_in_place(atoms, &self.perm, &mut self.visited);

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
        let cutsq = cutoff * cutoff;
        let quarter = [0.25 * len[0], 0.25 * len[1], 0.25 * len[2]];
        let x = &atoms.x;
        let cell_start = &self.cell_start;
        let axes = &self.stencil_axes;
        self.slabs.par_iter_mut().for_each(|s| {
            s.row_start.clear();
            s.nbr.clear();
            s.row_start.push(0);
            let mut len = 0usize;
            for i in s.start..s.end {
                let xi = x[i];
                let c = cell_coords(&xi);
                // The neighbouring cells, with the first candidate index in each.
                let mut scan = |cell: usize, first: usize| {
                    let lo = (cell_start[cell] as usize).max(first);
                    let hi = cell_start[cell + 1] as usize;
                    if hi <= lo {
                        return;
                    }
                    // Branch-free append: write every candidate, keep those within the cut-off.
                    // A raw separation below a quarter box length in every component is its
                    // own minimum image; only the others (whole cells across a boundary, so the
                    // branch is well predicted) go through `SimBox::min_image`.
                    s.nbr.resize(len + (hi - lo), 0);
                    for j in lo..hi {
                        let xj = x[j];
                        let mut d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                        if (d[0].abs() >= quarter[0])
                            | (d[1].abs() >= quarter[1])
                            | (d[2].abs() >= quarter[2])
                        {
                            d = bx.min_image(d);
                        }
                        s.nbr[len] = j as u32;
                        len += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutsq);
                    }
                    s.nbr.truncate(len);
                };
                let mut cc = c;
                if slab_mode {
                    // Own layer: j > i; next layer: every j.
                    let layer_ax: [&[usize]; 2] = other_axes(axes, axis, c);
                    for (dl, first) in [(0, i + 1), (1, 0)] {
                        cc[axis] = (c[axis] + dl) % layers;
                        for &ca in layer_ax[1] {
                            for &cb in layer_ax[0] {
                                set_other(&mut cc, axis, cb, ca);
                                scan(cell_id(cc, ncell), first);
                            }
                        }
                    }
                } else {
                    for &cz in &axes[2][c[2]] {
                        for &cy in &axes[1][c[1]] {
                            for &cx in &axes[0][c[0]] {
                                scan(cell_id([cx, cy, cz], ncell), i + 1);
                            }
                        }
                    }
                }
                s.row_start.push(len as u32);
            }
        });

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

    /// Evaluate all pair forces at `step` (the noise key), overwrite `atoms.f`, and return the
    /// energy and virial. `inv_mass[t]` is 1/m of type t. Requires a current list.
    pub fn compute_forces(
        &mut self,
        atoms: &mut Atoms,
        bx: &SimBox,
        ff: &ForceField,
        table: &[PairCoeff],
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
        let nt = ff.ntypes() + 1;
        assert!(
            table.len() == nt * nt && atoms.typ.par_iter().all(|&t| (t as usize) < nt),
            "atom type outside the coefficient table"
        );
        self.evals_since_build += 1;
        self.refresh_inner(atoms, bx);
        self.rcsq.clear();
        self.rcsq.extend(table.iter().map(|c| c.rc * c.rc));
        let pair_table = PairTable::new(&ff.model, table);
        let isa = match self.isa {
            Some(i) if (i as u8) <= (Isa::best_supported() as u8) => i,
            Some(_) => Isa::Baseline,
            None => Isa::detect(),
        };
        let ctx = Ctx {
            inner: self.inner_on,
            isa,
            bx,
            ff,
            table: &pair_table,
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
    ff: &'a ForceField,
    table: &'a PairTable,
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
    row: &'a [u32],
    /// `typ[i] · (ntypes + 1)`: the row of i's type in the coefficient table.
    row_t: usize,
}

/// Per-slab constants of the distance pass.
struct PassConst<'a> {
    x: &'a [[f64; 3]],
    typ: &'a [u32],
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
    let pc = PassConst {
        x,
        typ,
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
            row: &w.nbr[w.row_start[i - w.start] as usize..w.row_start[i - w.start + 1] as usize],
            row_t: typ[i] as usize * ctx.nt,
        };
        let sc = &mut *w.scratch;
        sc.far.clear();
        #[cfg(target_arch = "x86_64")]
        if AVX512 {
            // SAFETY: `AVX512` is true only inside `slab_avx512`, which runs only on CPUs with
            // AVX-512 (see `slab_isa`); every index in the row is < x.len() (list invariant,
            // checked in `compute_forces`).
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
                b.coeff[len] = if ONE_TYPE {
                    one_coeff as u32
                } else {
                    (r.row_t + typ[j as usize] as usize) as u32
                };
                p.i[len] = i as u32;
                p.j[len] = j;
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
        b.coeff[*len] = if ONE_TYPE {
            pc.one_coeff as u32
        } else {
            (r.row_t + pc.typ[j as usize] as usize) as u32
        };
        p.i[*len] = r.i as u32;
        p.j[*len] = j;
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

    /// # Safety
    /// The CPU has AVX-512 F/DQ/VL/BW, and every index in `r.row` is < `pc.x.len()` (and, with
    /// more than one type, `r.row_t + typ[j] < pc.rcsq.len()`).
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
                let j64 = _mm512_cvtepu32_epi64(jv);
                let off = _mm512_add_epi64(_mm512_slli_epi64::<1>(j64), j64);
                let gx = _mm512_mask_i64gather_pd::<8>(zero, lm, off, xp);
                let gy = _mm512_mask_i64gather_pd::<8>(zero, lm, off, xp.add(1));
                let gz = _mm512_mask_i64gather_pd::<8>(zero, lm, off, xp.add(2));
                let dx = _mm512_sub_pd(xi[0], gx);
                let dy = _mm512_sub_pd(xi[1], gy);
                let dz = _mm512_sub_pd(xi[2], gz);
                let rsq = _mm512_add_pd(
                    _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                    _mm512_mul_pd(dz, dz),
                );
                let (rcsq, coeff) = if ONE_TYPE {
                    (rc_one, cvec)
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

/// Evaluate the pending pairs and add their forces, energy and virial, in batch order. `own`
/// starts at atom `at.0`, `next` at atom `at.1`. Kept out of line: its gathers and scatters are
/// faster as scalar loads and stores than as the SIMD gathers the AVX-512 context would make of
/// them.
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
    let (v, tag, typ, inv_mass) = (ctx.v, ctx.tag, ctx.typ, ctx.inv_mass);
    let natoms = v.len();
    if natoms == 0 || tag.len() != natoms || typ.len() != natoms || inv_mass.is_empty() {
        return;
    }
    let (last, last_t) = (natoms - 1, inv_mass.len() - 1);
    let ims_one = inv_mass.get(1).map_or(0.0, |m| m + m);
    let b = &mut p.batch;
    // Gather (clamped indices: no exits, so it vectorises).
    for l in 0..n {
        let (i, j) = ((p.i[l] as usize).min(last), (p.j[l] as usize).min(last));
        let (vi, vj) = (v[i], v[j]);
        b.dv[0][l] = vi[0] - vj[0];
        b.dv[1][l] = vi[1] - vj[1];
        b.dv[2][l] = vi[2] - vj[2];
        b.inv_mass_sum[l] = if ONE_TYPE {
            ims_one
        } else {
            inv_mass[(typ[i] as usize).min(last_t)] + inv_mass[(typ[j] as usize).min(last_t)]
        };
        b.tag_i[l] = tag[i];
        b.tag_j[l] = tag[j];
    }
    pair_forces_batch_isa(ctx.isa, &ctx.ff.model, ctx.table, ctx.ff.seed, ctx.step, b);
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
        tally.energy += b.energy[l];
        tally.virial[0] += dr[0] * fv[0];
        tally.virial[1] += dr[1] * fv[1];
        tally.virial[2] += dr[2] * fv[2];
        tally.virial[3] += dr[0] * fv[1];
        tally.virial[4] += dr[0] * fv[2];
        tally.virial[5] += dr[1] * fv[2];
    }
    own[cur] = fi;
    b.len = 0;
}

/// The stencil lists of the two axes other than the slab axis, (faster, slower) in cell order.
fn other_axes(axes: &[Vec<Vec<usize>>; 3], axis: usize, c: [usize; 3]) -> [&[usize]; 2] {
    match axis {
        2 => [&axes[0][c[0]], &axes[1][c[1]]],
        _ => [&axes[0][c[0]], &axes[2][c[2]]],
    }
}

/// Set the coordinates of the two axes other than the slab axis.
fn set_other(cc: &mut [usize; 3], axis: usize, fast: usize, slow: usize) {
    match axis {
        2 => {
            cc[0] = fast;
            cc[1] = slow;
        }
        _ => {
            cc[0] = fast;
            cc[2] = slow;
        }
    }
}

/// Reorder every per-atom array in place by `perm` (new index k holds old atom `perm[k]`),
/// following the permutation's cycles, so no second copy of the atoms is needed. The
/// destructuring names every field of [`Atoms`]: a field added there fails to compile here
/// until it is permuted too.
fn permute_in_place(atoms: &mut Atoms, perm: &[u32], visited: &mut Vec<u64>) {
    let Atoms {
        x,
        v,
        f,
        tag,
        typ,
        image,
    } = atoms;
    let n = perm.len();
    visited.clear();
    visited.resize(n.div_ceil(64), 0);
    for start in 0..n {
        if visited[start / 64] >> (start % 64) & 1 == 1 {
            continue;
        }
        let saved = (
            x[start],
            v[start],
            f[start],
            tag[start],
            typ[start],
            image[start],
        );
        let mut k = start;
        loop {
            visited[k / 64] |= 1 << (k % 64);
            let src = perm[k] as usize;
            if src == start {
                (x[k], v[k], f[k], tag[k], typ[k], image[k]) = saved;
                break;
            }
            x[k] = x[src];
            v[k] = v[src];
            f[k] = f[src];
            tag[k] = tag[src];
            typ[k] = typ[src];
            image[k] = image[src];
            k = src;
        }
    }
}
