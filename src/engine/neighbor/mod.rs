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
//! style's [`PairKernel`] (`pair.rs`; for `dpd/nonlinear` [`crate::forces::dpd::kernel::pair_forces_batch`],
//! the same function as [`crate::forces::dpd::kernel::pair_force`], in SIMD lanes). The displacement of every
//! pair is the box's minimum image, computed per pair.

use super::atoms::Atoms;
use super::domain::{LeesEdwards, SimBox};
use crate::forces::Isa;
use crate::forces::batcher::PairKernel;
use rayon::prelude::*;

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
mod build;
mod density;
mod rebuild;
mod slab;

use build::*;
use slab::*;

/// The instruction-set level of the distance passes (`slab_run`, `build_rows`): a const
/// generic, so each level is compiled into its own `#[target_feature]` function.
const PORTABLE: u8 = 0;
const AVX2: u8 = 1;
const AVX512: u8 = 2;

/// Fewest cells the grid may always have (see [`cell_grid`]).
const MIN_CELL_CAP: usize = 4096;
/// Most cells along one axis (the per-axis stencil tables hold one entry per cell).
const AXIS_CELL_CAP: f64 = 65536.0;

/// Cells per axis of a grid over a box of side lengths `len` (the first `dim` axes) for pair
/// cut-off `cutoff` and `natoms` atoms: ⌊L/cutoff⌋ per axis, at least 1, so every cell is at
/// least `cutoff` wide. A sparse box (a huge box, a tiny cut-off) would ask for more cells than
/// memory holds (a fuzzer's box of side 5000 with cut-off 1.3: 6·10¹⁰ cells, an abort in the
/// allocator), or for far more cells than atoms, every one visited at each build (a fuzzer's
/// sparse sheared 3-D box under the former floor of 2²¹ cells: a timeout). The grid is then
/// coarsened to at most max(4·natoms, 4096) cells in all and 65536 along any axis, the axes with
/// the fewest cells first keeping theirs, the others sharing the rest evenly. Wider cells only
/// add candidate pairs that the distance test drops, so forces are unchanged; a grid within both
/// caps is kept as it is, so every dense system keeps its bits. A non-finite ratio (an infinite
/// length) gives one cell on that axis.
pub(crate) fn cell_grid(len: [f64; 3], dim: usize, cutoff: f64, natoms: usize) -> [usize; 3] {
    let mut want = [1.0f64; 3];
    for d in 0..dim {
        let q = (len[d] / cutoff).floor();
        want[d] = if q.is_finite() {
            q.clamp(1.0, AXIS_CELL_CAP)
        } else {
            1.0
        };
    }
    let mut room = natoms
        .saturating_mul(4)
        .max(MIN_CELL_CAP)
        .min(u32::MAX as usize - 1) as f64;
    if want.iter().product::<f64>() > room {
        let mut order: Vec<usize> = (0..dim).collect();
        order.sort_by(|&a, &b| want[a].total_cmp(&want[b]));
        for (k, &d) in order.iter().enumerate() {
            let share = room.powf(1.0 / (dim - k) as f64).floor().max(1.0);
            want[d] = want[d].min(share);
            room = (room / want[d]).max(1.0);
        }
    }
    want.map(|w| w as usize)
}

/// The per-slab output slices of a slab-parallel pass over per-atom arrays `own` and `next`
/// (both of the atoms' length): slab k gets `own[slab k]` and `next[slab k + 1]`
/// (periodically), disjoint slices, so the tasks write without sharing.
fn own_next_slices<'a, T>(
    slabs: &[Slab],
    own: &'a mut [T],
    next: &'a mut [T],
) -> (Vec<&'a mut [T]>, Vec<&'a mut [T]>) {
    let mut own_k: Vec<&mut [T]> = Vec::with_capacity(slabs.len());
    let mut next_k: Vec<&mut [T]> = Vec::with_capacity(slabs.len());
    let (mut rest_o, mut rest_n) = (own, next);
    for s in slabs {
        let (a, b) = std::mem::take(&mut rest_o).split_at_mut(s.end - s.start);
        let (c, d) = std::mem::take(&mut rest_n).split_at_mut(s.end - s.start);
        own_k.push(a);
        next_k.push(c);
        rest_o = b;
        rest_n = d;
    }
    next_k.rotate_left(1);
    (own_k, next_k)
}

impl NeighborList {
    /// The axes along which the box is shorter than 2 r_c, with the image key's frame
    /// (P-4b), or None when every axis is long enough for one image per pair.
    fn short_axes(&self, bx: &SimBox) -> Option<([bool; 3], crate::rng::ImageFrame)> {
        let len = bx.len();
        let short: [bool; 3] = std::array::from_fn(|k| k < bx.dim && len[k] < 2.0 * self.rc_max);
        short
            .contains(&true)
            .then(|| (short, bx.image_frame(self.le.as_ref())))
    }
}

/// The squared length of the nearest image of separation `d` for the lists' cut-off tests in a
/// box shorter than twice the cut-off along y, its x component less `allow` (the tilt
/// allowance; 0 for a test at the current offset). Periodic: the minimum image
/// ([`pair_image`]). Sheared: the nearest of the sliding-brick images one box either side along
/// y too, as [`SimBox::images_within`] forms them (the brick's rounding in y first need not find
/// the nearest image there, so a pair whose only image in range crosses y would be missed).
#[inline]
fn nearest_sq(bx: &SimBox, le: Option<&LeesEdwards>, d: [f64; 3], allow: f64) -> f64 {
    let sq = |d: [f64; 3]| {
        let dx = (d[0].abs() - allow).max(0.0);
        dx * dx + d[1] * d[1] + d[2] * d[2]
    };
    let dm = pair_image(bx, le, d);
    let Some(le) = le else {
        return sq(dm);
    };
    let (len, off) = (bx.len(), le.offset);
    let mut best = sq(dm);
    for ny in [-1.0f64, 1.0] {
        let mut x = dm[0] + ny * off;
        x -= len[0] * (x / len[0]).round();
        best = best.min(sq([x, dm[1] + ny * len[1], dm[2]]));
    }
    best
}

/// The minimum image of a separation: the periodic one, or under Lees–Edwards the sliding-brick
/// one ([`SimBox::min_image_le`], its velocity jump dropped).
#[inline(always)]
fn pair_image(bx: &SimBox, le: Option<&LeesEdwards>, d: [f64; 3]) -> [f64; 3] {
    match le {
        None => bx.min_image(d),
        Some(le) => bx.min_image_le(d, le).0,
    }
}

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
    /// The same for the scalar sums of [`NeighborList::pair_sum`] (sDPD densities).
    next_d: Vec<f64>,
    /// Whether [`NeighborList::compute_forces`] tallies the per-atom virial (LAMMPS's
    /// `vflag_atom`, on while a `compute stress/atom` is defined).
    pub(crate) virial_atom_on: bool,
    /// The per-atom virial of the last evaluation with it on (½ r_a F_b of each pair to each
    /// of its atoms; xx yy zz xy xz yz), in the atoms' current order; empty otherwise.
    pub(crate) virial_atom: Vec<[f64; 6]>,
    /// Slab k's per-atom virial on the atoms of slab k + 1.
    next_va: Vec<[f64; 6]>,
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
    /// Lees–Edwards boundaries of the current step (None: a periodic box), and the tilt xy now
    /// and at the last build (see [`NeighborList::set_shear`]).
    le: Option<LeesEdwards>,
    xy_now: f64,
    xy_at_build: f64,
    /// The tilt at the working list's last refresh.
    xy_at_inner: f64,
    /// The tilt's mean change per step (|γ̇| L_y δt), and the tilt allowance D of the last
    /// build: its rows through the y boundary hold every pair within the list cut-off for any
    /// offset within ±D of the build's (see [`NeighborList::set_shear`]).
    tilt_drift: f64,
    tilt_allow: f64,
}

/// The working list's margin as a fraction of the skin, and the list lifetime (force
/// evaluations) from which it pays: it is rebuilt, by a filter pass over the list, whenever an
/// atom has moved margin/2, so it needs lists that live long (slow atoms, small steps). The
/// LAMMPS styles' working copy of LAMMPS's list (`capi`) follows the same two numbers.
pub const INNER_MARGIN: f64 = 1.0 / 3.0;
/// See [`INNER_MARGIN`].
pub const INNER_MIN_LIFE: u64 = 12;

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

    /// Lees–Edwards boundaries for the coming builds and force evaluations: `Some((le, xy,
    /// drift))` with the sliding-brick state of the current step, the tilt xy (unwrapped,
    /// continuous in time) and its mean change per step |γ̇| L_y δt; or None for a periodic box.
    /// Set it before [`NeighborList::needs_rebuild`] at every step of a sheared run.
    ///
    /// A build lists the pairs through the y boundary for every offset within ±D of its own
    /// (the tilt allowance D: x separations within the list cut-off + D; D = drift × (the
    /// previous list's lifetime + 2), at most L_x/2 − cut-off, so no other x image can come in
    /// range), so a list stays valid while 2·(largest displacement) + max(0, |xy − xy_build| − D)
    /// does not exceed the skin (with D = 0, the criterion LAMMPS applies to a changing
    /// triclinic box). Fast shear of a wide box (2-D, L = 70, γ̇ = 0.2, δt = 0.005: 0.07 a step
    /// against a skin of 0.3) then keeps a list as long as the atoms' motion allows, for a few
    /// more candidates in the boundary rows. The force and density passes use the current
    /// offset and the boundary velocity jump.
    pub fn set_shear(&mut self, shear: Option<(LeesEdwards, f64, f64)>) {
        match shear {
            Some((le, xy, drift)) => {
                self.le = Some(le);
                self.xy_now = xy;
                self.tilt_drift = if drift.is_finite() { drift.abs() } else { 0.0 };
            }
            None => {
                self.le = None;
                self.xy_now = 0.0;
                self.xy_at_build = 0.0;
                self.tilt_drift = 0.0;
                self.tilt_allow = 0.0;
            }
        }
    }

    /// Under Lees–Edwards, wrap every atom that has left the box since the last build
    /// ([`SimBox::wrap_le`]: x shifted by the offset and v_x by the jump on a y crossing), and
    /// shift its position at the build (and at the working list's refresh) by the same vector,
    /// so the displacement checks still see the atom's motion. The list keeps its pairs: a
    /// wrapped atom's pairs have raw separations of about a box length and go through the far
    /// pass, which takes the sliding-brick image and the velocity jump of the current offset.
    /// So measurements at every step see atoms in the box with the velocity of where they are
    /// (binned velocity profiles have no stray atoms at the y boundary). Periodic boxes: nothing.
    pub fn wrap_sheared(&mut self, atoms: &mut Atoms, bx: &SimBox) {
        let Some(le) = self.le else { return };
        let n = atoms.len();
        if self.builds == 0 || self.x_at_build.len() != n {
            return;
        }
        // The displacement of one atom's wrap (zero when it stayed in the box).
        let wrap = |x: &mut [f64; 3], v: &mut [f64; 3], im: &mut [i32; 3]| {
            let old = *x;
            bx.wrap_le(x, v, im, &le);
            [x[0] - old[0], x[1] - old[1], x[2] - old[2]]
        };
        let add = |x0: &mut [f64; 3], d: [f64; 3]| {
            if d != [0.0; 3] {
                x0[0] += d[0];
                x0[1] += d[1];
                x0[2] += d[2];
            }
        };
        let atoms_iter = atoms
            .x
            .par_iter_mut()
            .zip(atoms.v.par_iter_mut())
            .zip(atoms.image.par_iter_mut());
        if self.x_at_inner.len() == n {
            atoms_iter
                .zip(self.x_at_build.par_iter_mut())
                .zip(self.x_at_inner.par_iter_mut())
                .for_each(|((((x, v), im), x0), x1)| {
                    let d = wrap(x, v, im);
                    add(x0, d);
                    add(x1, d);
                });
        } else {
            atoms_iter
                .zip(self.x_at_build.par_iter_mut())
                .for_each(|(((x, v), im), x0)| add(x0, wrap(x, v, im)));
        }
    }

    /// True when some atom moved more than half the skin since the last build (or never built);
    /// under Lees–Edwards, more than half of what the tilt change beyond the build's allowance
    /// leaves of it.
    pub fn needs_rebuild(&self, atoms: &Atoms) -> bool {
        if self.x_at_build.len() != atoms.len() || self.builds == 0 {
            return true;
        }
        let mut room = self.skin;
        if self.le.is_some() {
            room -= ((self.xy_now - self.xy_at_build).abs() - self.tilt_allow).max(0.0);
            if room.is_nan() || room <= 0.0 {
                return true;
            }
        }
        let limit = 0.25 * room * room;
        atoms
            .x
            .par_iter()
            .zip(self.x_at_build.par_iter())
            .any(|(x, x0)| {
                let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
            })
    }

    /// The tilt xy of the last build (Lees–Edwards).
    pub(crate) fn xy_at_build(&self) -> f64 {
        self.xy_at_build
    }

    /// LAMMPS's displacement check (`Neighbor::check_distance`) with its threshold: true when
    /// the list was never built or some atom moved more than √`deltasq` since the last build
    /// (the caller forms `deltasq` from the skin and the box's change, as LAMMPS does).
    pub(crate) fn moved_beyond(&self, atoms: &Atoms, deltasq: f64) -> bool {
        if self.x_at_build.len() != atoms.len() || self.builds == 0 {
            return true;
        }
        atoms
            .x
            .par_iter()
            .zip(self.x_at_build.par_iter())
            .any(|(x, x0)| {
                let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > deltasq
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
            + self.next_d.capacity() * 8
            + self.x_at_build.capacity() * 24
            + self.x_at_inner.capacity() * 24
            + (self.cell_of.capacity() + self.perm.capacity()) * 4
            + (self.cell_count.capacity() + self.cell_start.capacity()) * 4
            + self.perm_scratch.vec3.capacity() * 24
            + self.perm_scratch.u32s.capacity() * 4
            + self.perm_scratch.int3.capacity() * 12
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
    /// return the energy and virial. `cut` holds the cut-offs of the `ntypes` types (dense,
    /// `(ntypes + 1)²`), `inv_mass[t]` is 1/m of type t. Requires a current list; `isa` is the
    /// instruction set of the distance pass (the kernel has its own). `special`: the bonded
    /// partners of each atom of the current order and what their pairs get (left out, or
    /// another coefficient block), applied to each batch before it is evaluated; `None` (no
    /// special pairs) leaves the loop as it is without a topology.
    #[allow(clippy::too_many_arguments)]
    pub fn compute_forces(
        &mut self,
        atoms: &mut Atoms,
        bx: &SimBox,
        kernel: &dyn PairKernel,
        cut: &[f64],
        ntypes: usize,
        inv_mass: &[f64],
        step: u64,
        special: Option<&crate::engine::topology::SpecialPairs>,
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
            cut.len() == nt * nt && atoms.typ.par_iter().all(|&t| (t as usize) < nt),
            "atom type outside the coefficient table"
        );
        self.evals_since_build += 1;
        self.refresh_inner(atoms, bx);
        self.rcsq.clear();
        self.rcsq.extend(cut.iter().map(|&rc| rc * rc));
        let isa = self.isa();
        if let Some(sp) = special {
            assert_eq!(
                sp.start.len(),
                atoms.len() + 1,
                "special partners of another order"
            );
        }
        let ctx = Ctx {
            special,
            le: self.le,
            short: self.short_axes(bx),
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
        let va_on = self.virial_atom_on;
        let natoms = f.len();
        self.virial_atom.clear();
        if va_on {
            self.virial_atom.resize(f.len(), [0.0; 6]);
        }
        if self.slabs.len() == 1 {
            let s = &mut self.slabs[0];
            let va = va_on.then(|| (&mut self.virial_atom[..], &mut [][..]));
            s.compute(&ctx, f, &mut [], va);
        } else {
            let (own, next) = own_next_slices(&self.slabs, f, &mut self.next_f);
            let mut va: Vec<Option<slab::VirialOut>> = Vec::new();
            if va_on {
                self.next_va.clear();
                self.next_va.resize(natoms, [0.0; 6]);
                let (vo, vn) =
                    own_next_slices(&self.slabs, &mut self.virial_atom, &mut self.next_va);
                va.extend(vo.into_iter().zip(vn).map(Some));
            } else {
                va.resize_with(self.slabs.len(), || None);
            }
            self.slabs
                .par_iter_mut()
                .zip(own.into_par_iter().zip(next.into_par_iter()))
                .zip(va.into_par_iter())
                .for_each(|((s, (own, next)), va)| s.compute(&ctx, own, next, va));
            if va_on {
                // The same sum as the forces': own + next, once per atom.
                for (v, n) in self.virial_atom.iter_mut().zip(&self.next_va) {
                    for c in 0..6 {
                        v[c] += n[c];
                    }
                }
            }
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

#[cfg(test)]
mod grid_tests {
    use super::cell_grid;

    #[test]
    fn dense_grids_are_kept_and_sparse_ones_capped() {
        // Dense boxes: ⌊L/cutoff⌋ per axis, as before the caps.
        assert_eq!(cell_grid([20.0, 20.0, 20.0], 3, 1.3, 128_000), [15, 15, 15]);
        assert_eq!(cell_grid([1.0, 1.0, 1.0], 3, 1.3, 10), [1, 1, 1]);
        assert_eq!(cell_grid([300.0, 3.0, 0.0], 2, 1.3, 2000), [230, 2, 1]);
        // Sparse: the total and each axis within the caps, at least one cell per axis.
        for (len, dim, n) in [
            ([5000.0, 5000.0, 5000.0], 3, 150),
            ([1e12, 3.0, 1.0], 2, 50),
            ([1e6, 1e6, 1.0], 2, 50),
            ([f64::INFINITY, 1e300, 4.0], 3, 10),
            ([1e9, 1e9, 1e9], 3, 100_000_000),
        ] {
            let g = cell_grid(len, dim, 1.3, n);
            let total: usize = g.iter().product();
            assert!(total <= (4 * n).max(4096), "{len:?}: {g:?}");
            assert!(
                g.iter().all(|&m| (1..=65536).contains(&m)),
                "{len:?}: {g:?}"
            );
        }
        assert_eq!(cell_grid([1e12, 3.0, 1.0], 2, 1.3, 50), [2048, 2, 1]);
        // A small dense box keeps its grid under the floor of 4096 cells.
        assert_eq!(cell_grid([21.0, 21.0, 21.0], 3, 1.3, 900), [16, 16, 16]);
    }
}
