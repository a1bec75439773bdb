//! The walk of [`crate::dpdnl_pair_compute`]: one LAMMPS neighbour list walked in Rust, its pairs
//! evaluated through the pair-style seam (`dpdnl::engine::pair`) and added with LAMMPS's
//! `ev_tally` conventions.

use dpdnl::engine::pair::{Batcher, lane_force};
use dpdnl::engine::simd::within_cut;
use dpdnl::engine::topology::SpecialRule;
use dpdnl::kernel::Isa;
use dpdnl::{PairBatch, PairKernel};

use crate::team::{DpdnlLaunch, Team};
use crate::working::WorkingList;
use crate::{DpdnlStatus, Error, guard, slice, slice_mut};

/// Per-atom arrays of one MPI rank, owned atoms first then ghosts (LAMMPS layout).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlAtoms {
    /// Positions, `nall * 3` doubles (LAMMPS `&x[0][0]`).
    pub x: *const f64,
    /// Velocities, `nall * 3` doubles; ghost velocities must be current (`comm_modify vel yes`).
    pub v: *const f64,
    /// Global ids (LAMMPS `tagint`, 32-bit under SMALLBIG), `nall` entries, all > 0.
    pub tag: *const i32,
    /// Atom types, 1-based, `nall` entries.
    pub atom_type: *const i32,
    /// Per-type masses, 1-based: `ntypes + 1` entries (entry 0 unused). Ignored if `rmass` is set.
    pub mass: *const f64,
    /// Per-atom masses (`nall` entries), or null to use `mass`.
    pub rmass: *const f64,
    /// Number of owned atoms.
    pub nlocal: i32,
    /// Owned plus ghost atoms.
    pub nall: i32,
}

/// A LAMMPS neighbour list (`NeighList`): `inum`, `ilist`, `numneigh`, `firstneigh`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlNeighList {
    /// Number of atoms with a list.
    pub inum: i32,
    /// Their indices, `inum` entries.
    pub ilist: *const i32,
    /// `numneigh[i]`: length of atom i's list, valid for every i in `ilist`.
    pub numneigh: *const i32,
    /// `firstneigh[i]`: atom i's neighbours, valid for every i in `ilist`.
    pub firstneigh: *const *const i32,
    /// Mask applied to every neighbour entry (LAMMPS `NEIGHMASK`; the upper bits flag special
    /// bonds). 0x3FFFFFFF in LAMMPS 2021–2022, 0x1FFFFFFF in later versions: pass the header's.
    pub neighmask: i32,
    /// 0: half list (each pair once); 1: full list (each pair seen from both atoms).
    pub full: i32,
    /// Which build of the list this is (LAMMPS `neighbor->ncalls`), ≥ 1; 0 when unknown. While
    /// it, the counts and the pointers stay the same, the list's entries must be unchanged: a
    /// pair-style handle then keeps a working copy of the list's rows within the cut-off plus
    /// a margin (a third of `skin`), refreshed when an atom has moved half the margin, and walks
    /// that instead (the same pairs in the same order, so the same bits). 0: the list itself
    /// is walked at every call.
    pub build: i64,
    /// The list's skin (LAMMPS `neighbor->skin`), ≥ 0; only read when `build` ≥ 1.
    pub skin: f64,
}

/// Step-level settings of one force evaluation.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlStep {
    /// Time step number used as the key of the pair noise (LAMMPS `update->ntimestep`), ≥ 0.
    pub step: i64,
    /// Time step δt (> 0): the random force scales as δt^(−1/2).
    pub dt: f64,
    /// LAMMPS `force->newton_pair` (half lists: 1 also updates ghost forces).
    pub newton_pair: i32,
    /// 2 or 3. Coordinates are used as given (z = 0 in 2-D under `fix enforce2d`).
    pub dimension: i32,
    /// Box lengths (LAMMPS `domain->xprd`, `yprd`, `zprd`), for the pair noise's image key:
    /// along a periodic axis shorter than 2 r_c a pair meets several images of its partner
    /// (ghosts), each keyed apart (`dpdnl::rng::ImageFrame`, docs/models.md P-4b).
    pub boxlen: [f64; 3],
    /// Tilts xy, xz, yz (LAMMPS `domain->xy`, `xz`, `yz`; 0 for an orthogonal box).
    pub tilt: [f64; 3],
    /// Periodic axes (LAMMPS `domain->periodicity`). All 0: no image key (the plain key of
    /// a box at least 2 r_c long).
    pub periodic: [i32; 3],
}

/// Energy and virial accumulators, following LAMMPS `Pair::ev_tally` / `ev_tally_full`.
/// Every pointer may be null when its flag is 0; results are added to what is there.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlTally {
    /// Nonzero: add the conservative energy to `*eng_vdwl`.
    pub eflag_global: i32,
    /// Nonzero: add the pair virial to `virial[0..6]` (xx, yy, zz, xy, xz, yz).
    pub vflag_global: i32,
    /// Global energy accumulator (LAMMPS `Pair::eng_vdwl`).
    pub eng_vdwl: *mut f64,
    /// Global virial accumulator, 6 doubles (LAMMPS `Pair::virial`).
    pub virial: *mut f64,
    /// Per-atom energy (`nall` doubles) or null.
    pub eatom: *mut f64,
    /// Per-atom virial (`nall * 6` doubles, LAMMPS `&vatom[0][0]`) or null.
    pub vatom: *mut f64,
}

/// Where the tallies go, resolved to slices once.
pub(crate) struct Sinks<'a> {
    eng: Option<&'a mut f64>,
    virial: Option<&'a mut [f64]>,
    eatom: Option<&'a mut [f64]>,
    vatom: Option<&'a mut [f64]>,
}

/// LAMMPS's special-bond class of a raw neighbour entry (bits 30–31, `SBBITS` = 30 in every
/// LAMMPS since 2012): 0 for an ordinary pair, 1–3 for 1-2, 1-3, 1-4 neighbours.
#[inline(always)]
pub(crate) fn special_class(jraw: i32) -> usize {
    (jraw as u32 >> 30) as usize
}

/// The rows of a LAMMPS neighbour list, checked: `visit(i, row, mask)` for every i of `ilist`,
/// in order, with its raw neighbour entries; `j = entry as u32 as usize & mask` (the
/// special-bond bits off) is < `nall` for every entry, checked before the visit. The list walk
/// of the single-threaded passes over a LAMMPS list (sDPD's densities).
///
/// # Safety
/// `list` as documented on [`DpdnlNeighList`]: `ilist` holds `inum` ints, and `numneigh` and
/// `firstneigh` are valid for every atom index in it.
pub(crate) unsafe fn for_each_row(
    list: &DpdnlNeighList,
    nall: usize,
    mut visit: impl FnMut(usize, &[i32], usize) -> Result<(), Error>,
) -> Result<(), Error> {
    // SAFETY: forwarded caller's contract.
    let ilist = unsafe { list_ilist(list)? };
    let mask = list.neighmask as u32 as usize;
    for &i in ilist {
        // SAFETY: forwarded caller's contract.
        let (i, jlist) = unsafe { list_row(list, i, nall)? };
        check_row(i, jlist, mask, nall)?;
        visit(i, jlist, mask)?;
    }
    Ok(())
}

/// The `ilist` of `list` (`inum` checked), with `numneigh`/`firstneigh` present when it has
/// rows.
///
/// # Safety
/// As [`for_each_row`].
pub(crate) unsafe fn list_ilist<'a>(list: &DpdnlNeighList) -> Result<&'a [i32], Error> {
    if list.inum < 0 {
        return Err(Error::invalid(format!("inum = {} must be >= 0", list.inum)));
    }
    let inum = list.inum as usize;
    // SAFETY: `inum` ints (caller's contract).
    let ilist = unsafe { slice(list.ilist, inum, "ilist")? };
    if inum > 0 && (list.numneigh.is_null() || list.firstneigh.is_null()) {
        return Err(Error::null("numneigh/firstneigh"));
    }
    Ok(ilist)
}

/// Row `i` (an `ilist` entry) of `list`: the index, checked against `nall`, and its raw
/// neighbour entries (checked by [`check_row`]).
///
/// # Safety
/// As [`for_each_row`], and `list_ilist(list)` succeeded.
#[inline(always)]
pub(crate) unsafe fn list_row<'a>(
    list: &DpdnlNeighList,
    i: i32,
    nall: usize,
) -> Result<(usize, &'a [i32]), Error> {
    if i < 0 || i as usize >= nall {
        return Err(Error::invalid(format!("ilist entry {i} outside 0..{nall}")));
    }
    let i = i as usize;
    // SAFETY: `numneigh` and `firstneigh` are valid for every i in ilist (caller's contract).
    let (n, first) = unsafe { (*list.numneigh.add(i), *list.firstneigh.add(i)) };
    // SAFETY: `firstneigh[i]` holds `numneigh[i]` ints (caller's contract).
    let jlist = unsafe { slice(first, n.max(0) as usize, "firstneigh[i]")? };
    Ok((i, jlist))
}

/// Every entry of atom i's row names an atom below `nall` (special-bond bits masked off);
/// true when some entry carries special-bond bits. One pass without early exit (a max and an
/// or, in SIMD lanes): the per-row checks were two scalar searches, 5 % of the LAMMPS path.
#[inline(always)]
pub(crate) fn check_row(i: usize, jlist: &[i32], mask: usize, nall: usize) -> Result<bool, Error> {
    let mask = mask as u32;
    let (top, bits) = jlist.iter().fold((0u32, 0u32), |(top, bits), &j| {
        let u = j as u32;
        (top.max(u & mask), bits | u)
    });
    if !jlist.is_empty() && top as usize >= nall {
        let bad = jlist
            .iter()
            .map(|&j| j as u32 & mask)
            .find(|&j| j as usize >= nall)
            .unwrap_or(top);
        return Err(Error::invalid(format!(
            "neighbour index {bad} of atom {i} outside 0..{nall}"
        )));
    }
    Ok(special_class(bits as i32) != 0)
}

/// Row blocks per thread of a threaded walk (the team's threads take them as they finish).
const BLOCKS_PER_THREAD: usize = 4;

/// Rows of a threaded walk's window: its events or records (33 pairs a row at n = 16, 32 B
/// each: about 1 MB) stay in the cache from phase 1 to phase 2. On the 2-vCPU Xeon of the
/// commit (n = 16, 20000 atoms, 2 threads) 2048 or 4096 rows were within the noise of 1024
/// (pair time −3 %), 512 rows and one window for the whole list slower.
const WINDOW_ROWS: usize = 1024;

/// The threads of a pair style's walk over a LAMMPS list ([`walk_pairs`]) and their buffers,
/// kept from step to step. The rows are taken in windows of [`WINDOW_ROWS`], in list order.
/// Phase 1 splits a window into contiguous row blocks, evaluated in parallel; phase 2 adds
/// their results in list order, each task to a contiguous range of atoms, so that every atom's
/// force (and per-atom tallies) is summed in the single-threaded order. The bits do not depend
/// on the thread count (tested with 1, 2 and 3).
///
/// Force-only steps: each block emits the single-threaded walk's additions to f as events
/// (`f[atom] += v`: −f_ij on j for each pair, the row's sum on i after its last pair, in the
/// order [`Apply`] performs them), bucketed by the phase-2 task owning the atom; task t reads
/// bucket t of every block, in block order, so each event is read once. Tally steps: each block
/// stores, in list order, atom i, atom j, the force on i and what the tallies need; each task
/// scans every record and adds only to its atoms, and one more task sums the global energy and
/// virial over all records.
pub(crate) struct Workers {
    team: Team,
    blocks: Vec<Block>,
}

/// One row block's buffers (phase 1).
#[derive(Default)]
struct Block {
    bt: Batcher,
    near: Vec<u32>,
    pairs: Vec<PairRec>,
    tally: Vec<TallyRec>,
    /// Force events by phase-2 task (force-only steps).
    events: Vec<Vec<Event>>,
    err: Option<Error>,
}

/// A force event of phase 1: `f[atom] += v`.
#[derive(Clone, Copy)]
struct Event {
    v: [f64; 3],
    atom: u32,
}

/// Phase 1 of a force-only step: a block's pairs, in list order, turned into the additions
/// [`Apply::pair`] and [`Apply::finish_row`] perform, in the same order, each pushed to the
/// bucket of the task owning its atom (`atom / chunk`). `f[j] -= fv` becomes `f[j] += -fv`,
/// the same IEEE result.
struct Emit<'e> {
    buckets: &'e mut [Vec<Event>],
    chunk: u32,
    /// Half list: j's side is added when newton is on or j is owned (j < `nlocal`).
    half: bool,
    newton: bool,
    nlocal: u32,
    /// The row being summed: atom i and the force on it so far.
    row: Option<(u32, [f64; 3])>,
}

impl Emit<'_> {
    #[inline(always)]
    fn push(&mut self, atom: u32, v: [f64; 3]) {
        self.buckets[(atom / self.chunk) as usize].push(Event { v, atom });
    }

    /// The lanes of a batch, in order (the row's running force in locals, as in [`Sum`]).
    #[inline(always)]
    fn batch(&mut self, b: &PairBatch, is: &[u32], js: &[u32]) {
        let mut row = self.row.take();
        for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
            let fv = lane_force(b, l).1;
            if let Some((r, fr)) = row
                && r != i
            {
                self.push(r, fr);
                row = None;
            }
            let fi = &mut row.get_or_insert((i, [0.0; 3])).1;
            fi[0] += fv[0];
            fi[1] += fv[1];
            fi[2] += fv[2];
            if self.half && (self.newton || j < self.nlocal) {
                self.push(j, [-fv[0], -fv[1], -fv[2]]);
            }
        }
        self.row = row;
    }

    fn finish_row(&mut self) {
        if let Some((i, fi)) = self.row.take() {
            self.push(i, fi);
        }
    }
}

/// An evaluated pair: atoms i and j and the force on i (−it on j).
#[derive(Clone, Copy)]
struct PairRec {
    i: u32,
    j: u32,
    f: [f64; 3],
}

/// What the tallies of an evaluated pair need: energy, fpair, r_ij.
#[derive(Clone, Copy)]
struct TallyRec {
    energy: f64,
    fpair: f64,
    dr: [f64; 3],
}

impl Workers {
    /// `threads` (≥ 2) threads: the host's through `launch` ([`crate::dpdnl_pair_launcher`]),
    /// else a pool shared by every handle with that count and created once.
    pub(crate) fn new(threads: usize, launch: DpdnlLaunch) -> Result<Workers, Error> {
        Ok(Workers {
            team: Team::new(threads, launch).map_err(Error::invalid)?,
            blocks: (0..threads * BLOCKS_PER_THREAD)
                .map(|_| Block::default())
                .collect(),
        })
    }

    /// The number of threads.
    pub(crate) fn threads(&self) -> usize {
        self.team.threads()
    }

    /// The same number of threads, now the host's through `launch` (or the pool's); the
    /// blocks' buffers are kept.
    pub(crate) fn set_launch(&mut self, launch: DpdnlLaunch) -> Result<(), Error> {
        self.team = Team::new(self.threads(), launch).map_err(Error::invalid)?;
        Ok(())
    }

    /// Whether the threads are the host's ([`crate::dpdnl_pair_launcher`]).
    pub(crate) fn on_host_threads(&self) -> bool {
        self.team.is_host()
    }
}

/// What the walk over a LAMMPS list reads, checked once per call (shared by its threads).
struct Walk<'a> {
    kernel: &'a dyn PairKernel,
    cut: &'a [f64],
    nt: usize,
    special: Option<SpecialRule>,
    x: &'a [f64],
    v: &'a [f64],
    tag: &'a [i32],
    ty: &'a [i32],
    /// 1/m per atom (`per_atom`) or per type.
    inv_mass: Vec<f64>,
    per_atom: bool,
    /// The largest cut-off² of each type's row of the table.
    row_cutsq: Vec<f64>,
    isa: Isa,
    step: u64,
    mask: usize,
    nall: usize,
    /// The image key's frame when the box is shorter than 2 r_c (P-4b).
    images: Option<dpdnl::rng::ImageFrame>,
}

impl Walk<'_> {
    /// Candidate j of row i (position `xi`, `row` = type(i) (ntypes + 1)), with its
    /// coefficients `extra` past its type pair's (a special class's block), written to lane `l`
    /// of `b` ([`Batcher::extend`]'s `fill`); only a pair in range is kept (the kernel checks
    /// again): with several types some candidates are beyond their pair's cut-off, and a branch
    /// would be mispredicted. The rest of the lane (velocities, masses, tags) is gathered for
    /// the kept pairs only, at the flush.
    #[inline(always)]
    fn offer(
        &self,
        b: &mut PairBatch,
        l: usize,
        (i, xi, row): (usize, [f64; 3], usize),
        j: usize,
        extra: usize,
    ) -> (u32, u32, bool) {
        let x = self.x;
        let k = row + self.ty[j] as usize;
        let rc = self.cut[k];
        let dr = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
        let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
        for (lane, &c) in b.dr.iter_mut().zip(&dr) {
            lane[l] = c;
        }
        b.coeff[l] = (k + extra) as u32;
        (i as u32, j as u32, rsq < rc * rc)
    }

    /// The rows `rows` (atom, raw entries), in order, each checked: every pair in range
    /// through the kernel, handed batch by batch to `apply(batch, i, j)` (lane l: atoms
    /// `i[l]`, `j[l]`) in list order; the last batch is flushed.
    #[inline(always)]
    fn rows<'r>(
        &self,
        rows: impl Iterator<Item = Result<(usize, &'r [i32]), Error>>,
        bt: &mut Batcher,
        near: &mut Vec<u32>,
        mut apply: impl FnMut(&PairBatch, &[u32], &[u32]),
    ) -> Result<(), Error> {
        let (x, ty, nt, mask) = (self.x, self.ty, self.nt, self.mask);
        bt.batch.images = self.images;
        let kernel = self.kernel;
        let step = self.step;
        // The lanes' v_ij, 1/m_i + 1/m_j and tags (r_ij and the coefficient index are in place).
        let (v, tag, inv_mass, per_atom) = (self.v, self.tag, &self.inv_mass[..], self.per_atom);
        let mut gather = |b: &mut PairBatch, l: usize, i: usize, j: usize| {
            debug_assert!(i < self.nall && j < self.nall && l < b.len);
            // SAFETY: i and j are below nall: i from `list_row`, j from a row `check_row`
            // passed. `v` holds 3 nall values and `tag` and `ty` nall (`walk_pairs`); every type
            // is in 1..=ntypes (checked by `walk_pairs`) and `inv_mass` holds ntypes values, or
            // nall when `per_atom`. Without the checks the gather is 10 % faster (the shim's pair
            // time at n = 16).
            unsafe {
                let inv_m = |a: usize| {
                    if per_atom {
                        *inv_mass.get_unchecked(a)
                    } else {
                        *inv_mass.get_unchecked(*ty.get_unchecked(a) as usize - 1)
                    }
                };
                for d in 0..3 {
                    b.dv[d][l] = v.get_unchecked(3 * i + d) - v.get_unchecked(3 * j + d);
                }
                b.inv_mass_sum[l] = inv_m(i) + inv_m(j);
                b.tag_i[l] = *tag.get_unchecked(i) as u32;
                b.tag_j[l] = *tag.get_unchecked(j) as u32;
            }
        };
        for r in rows {
            let (i, jlist) = r?;
            let bonded = check_row(i, jlist, mask, self.nall)?;
            let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
            let row = ty[i] as usize * (nt + 1);
            // A row with bonded neighbours: each entry with its special class, in list order
            // (rows without them take the filtered pass below).
            let at = (i, xi, row);
            if let Some(sp) = self.special
                && bonded
            {
                let kept = jlist.iter().filter(|&&jr| !sp.excludes(special_class(jr)));
                let fill = |b: &mut PairBatch, l, &jr: &i32| {
                    let extra = sp.offset(special_class(jr)) as usize;
                    self.offer(b, l, at, jr as u32 as usize & mask, extra)
                };
                bt.extend(kept, fill, kernel, step, &mut gather, &mut apply);
                continue;
            }
            let n = within_cut(
                self.isa,
                xi,
                x,
                jlist,
                mask as u32,
                self.row_cutsq[ty[i] as usize],
                near,
            );
            let fill = |b: &mut PairBatch, l, &j: &u32| self.offer(b, l, at, j as usize, 0);
            bt.extend(&near[..n], fill, kernel, step, &mut gather, &mut apply);
        }
        bt.flush(kernel, step, gather, &mut apply);
        Ok(())
    }
}

/// The image key's frame of a step's box when some periodic length is below 2 r_c (the
/// largest cut-off of `cut`), else None (`dpdnl::init::images_keyed`).
fn image_frame(st: &DpdnlStep, cut: &[f64]) -> Option<dpdnl::rng::ImageFrame> {
    let dim = if st.dimension == 2 { 2 } else { 3 };
    let periodic = st.periodic.map(|p| p != 0);
    let rc = cut.iter().copied().fold(0.0, f64::max);
    dpdnl::init::images_keyed(st.boxlen, periodic, dim, rc)
        .then(|| dpdnl::rng::ImageFrame::new(dim, st.boxlen, st.tilt, periodic))
}

/// The list walk of [`crate::dpdnl_pair_compute`] for any pair style: every listed pair within `cut[k]`
/// (k the dense type-pair index, `ntypes + 1` per row) through `kernel`, forces and tallies
/// added with LAMMPS's conventions. Checks the step, dimension, counts, types and masses.
///
/// With `special`, a pair flagged as a bonded neighbour of class b is left out when its factor
/// is 0 and otherwise evaluated with the coefficients of block b (`k + b (ntypes + 1)²`) when
/// the table is scaled; without it the flags are masked away and every pair has its full
/// strength.
///
/// With `workers` of 2 or more threads the rows are evaluated in parallel and added in list
/// order ([`Workers`]): the same bits as one thread. With `working`, the rows of its copy of
/// the list are walked when it has one ([`WorkingList`]): the same pairs in the same order.
///
/// # Safety
/// As [`crate::dpdnl_pair_compute`].
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn walk_pairs(
    kernel: &dyn PairKernel,
    cut: &[f64],
    ntypes: usize,
    special: Option<SpecialRule>,
    atoms: &DpdnlAtoms,
    list: &DpdnlNeighList,
    st: &DpdnlStep,
    f: *mut f64,
    tally: Option<DpdnlTally>,
    workers: Option<&mut Workers>,
    working: Option<&mut WorkingList>,
) -> Result<(), Error> {
    let (nlocal, nall) = counts(st, atoms)?;
    let nt = ntypes;
    // SAFETY: sizes as documented on `DpdnlAtoms`, `DpdnlNeighList` (caller's contract).
    let (x, v, tag, ty) = unsafe {
        (
            slice(atoms.x, 3 * nall, "x")?,
            slice(atoms.v, 3 * nall, "v")?,
            slice(atoms.tag, nall, "tag")?,
            slice(atoms.atom_type, nall, "type")?,
        )
    };
    // SAFETY: `nall * 3` doubles, not aliased by the read-only arrays (caller's contract).
    let f = unsafe { slice_mut(f, 3 * nall, "f")? };
    if let Some(bad) = ty.iter().position(|&t| t < 1 || t as usize > nt) {
        return Err(Error::invalid(format!(
            "atom {bad} has type {} outside 1..={nt}",
            ty[bad]
        )));
    }
    // 1/m per atom (per-atom masses) or per type.
    let (inv_mass, per_atom) = if atoms.rmass.is_null() {
        // SAFETY: `ntypes + 1` doubles (caller's contract).
        let mass = unsafe { slice(atoms.mass, nt + 1, "mass")? };
        (inverse_masses(&mass[1..], 1)?, false)
    } else {
        // SAFETY: `nall` doubles (caller's contract).
        let rmass = unsafe { slice(atoms.rmass, nall, "rmass")? };
        (inverse_masses(rmass, 0)?, true)
    };

    // SAFETY: forwarded caller's contract.
    let mut sinks = unsafe { Sinks::of(tally, nall)? };
    let flags = Flags {
        full: list.full != 0,
        newton: st.newton_pair != 0,
        nlocal,
    };

    // The largest cut-off² of each type's row of the table: a first pass over a row keeps
    // the entries within it (`within_cut`, in SIMD lanes), the loop over them tests each
    // against its own type pair's cut-off (the same rsq, so the same pairs as testing all).
    let row_cutsq: Vec<f64> = (0..=nt)
        .map(|t| {
            cut[t * (nt + 1)..(t + 1) * (nt + 1)]
                .iter()
                .map(|&rc| rc * rc)
                .fold(0.0, f64::max)
        })
        .collect();
    let walk = Walk {
        kernel,
        cut,
        nt,
        special,
        x,
        v,
        tag,
        ty,
        inv_mass,
        per_atom,
        row_cutsq,
        isa: Isa::detect(),
        step: st.step as u64,
        mask: list.neighmask as u32 as usize,
        nall,
        images: image_frame(st, cut),
    };
    // SAFETY: `list` as documented (caller's contract).
    let ilist = unsafe { list_ilist(list)? };
    // SAFETY: `list` as documented, `list_ilist` succeeded; `x` and `ty` hold nall entries,
    // every type an index of `row_cutsq` (checked above).
    let copy = match working {
        Some(w) => {
            unsafe { w.prepare(list, ilist, x, ty, &walk.row_cutsq, nlocal, nall)? }.then_some(&*w)
        }
        None => None,
    };
    // SAFETY: `list` as documented, `list_ilist` succeeded (caller's contract).
    let row = |&i: &i32| unsafe { list_row(list, i, nall) };
    let rows = || match copy {
        Some(w) => Rows::Copy(w.rows().map(Ok)),
        None => Rows::List(ilist.iter().map(row)),
    };
    match workers {
        Some(w) if w.threads() > 1 && !ilist.is_empty() => {
            let rows = rows().collect::<Result<Vec<_>, Error>>()?;
            threaded(&walk, w, &rows, f, &mut sinks, flags)
        }
        // A force-only step: the lean sums of `Sum`, one copy per side-of-j rule.
        _ if !sinks.any() => {
            let (mut bt, mut near) = (Batcher::default(), Vec::new());
            let rows = rows();
            match (flags.full, flags.newton) {
                (true, _) => Sum::<J_NEVER>::walk(&walk, rows, f, flags, &mut bt, &mut near),
                (false, true) => Sum::<J_ALWAYS>::walk(&walk, rows, f, flags, &mut bt, &mut near),
                (false, false) => Sum::<J_OWNED>::walk(&walk, rows, f, flags, &mut bt, &mut near),
            }
        }
        _ => {
            // In-range pairs are gathered, in list order, into batches of BATCH (`Batcher`,
            // the seam's driver) evaluated through the pair style's kernel; `Apply` then adds
            // the forces and tallies in list order as the pair-by-pair loop did, so every sum
            // is formed in the same order.
            let mut apply = Apply::new(f, 0, &mut sinks, flags);
            let (mut bt, mut near) = (Batcher::default(), Vec::new());
            walk.rows(rows(), &mut bt, &mut near, |b, is, js| {
                for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
                    apply.lane(b, l, i as usize, j as usize);
                }
            })?;
            apply.finish_row();
            Ok(())
        }
    }
}

/// The rows of a walk: LAMMPS's list, or the working copy of it.
enum Rows<L, C> {
    List(L),
    Copy(C),
}

impl<'r, L, C> Iterator for Rows<L, C>
where
    L: Iterator<Item = Result<(usize, &'r [i32]), Error>>,
    C: Iterator<Item = Result<(usize, &'r [i32]), Error>>,
{
    type Item = Result<(usize, &'r [i32]), Error>;

    #[inline(always)]
    fn next(&mut self) -> Option<Self::Item> {
        match self {
            Rows::List(l) => l.next(),
            Rows::Copy(c) => c.next(),
        }
    }
}

/// When [`Sum`] subtracts a pair's force from atom j: never (a full list), always (a half
/// list with newton on), or when j is owned (a half list with newton off).
const J_NEVER: u8 = 0;
const J_ALWAYS: u8 = 1;
const J_OWNED: u8 = 2;

/// The sums of a single-threaded force-only step: what [`Apply`] does without tallies, thread
/// ranges or run-time flags (the same additions in the same order, so the same bits), its
/// j-side rule a constant ([`J_NEVER`], [`J_ALWAYS`], [`J_OWNED`]). Apply's per-lane tests
/// were a tenth of the walk's time.
struct Sum<'a, const J: u8> {
    f: &'a mut [f64],
    nlocal: usize,
    /// The row being summed (`usize::MAX` before the first) and the force on it so far.
    i: usize,
    fi: [f64; 3],
}

impl<'a, const J: u8> Sum<'a, J> {
    /// Walk `rows` with `walk`, adding each pair's force to `f`.
    fn walk<'r>(
        walk: &Walk,
        rows: impl Iterator<Item = Result<(usize, &'r [i32]), Error>>,
        f: &'a mut [f64],
        flags: Flags,
        bt: &mut Batcher,
        near: &mut Vec<u32>,
    ) -> Result<(), Error> {
        let mut sum = Sum::<J> {
            f,
            nlocal: flags.nlocal,
            i: usize::MAX,
            fi: [0.0; 3],
        };
        walk.rows(rows, bt, near, |b, is, js| sum.batch(b, is, js))?;
        let (i, fi) = (sum.i, sum.fi);
        add_row(sum.f, i, fi);
        Ok(())
    }

    /// The lanes of a batch, in order (the row's running force in locals).
    #[inline(always)]
    fn batch(&mut self, b: &PairBatch, is: &[u32], js: &[u32]) {
        let f = &mut *self.f;
        let (mut cur, mut fi) = (self.i, self.fi);
        for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (_, fv) = lane_force(b, l);
            if i != cur {
                add_row(f, cur, fi);
                (cur, fi) = (i, [0.0; 3]);
            }
            fi[0] += fv[0];
            fi[1] += fv[1];
            fi[2] += fv[2];
            if J == J_ALWAYS || (J == J_OWNED && j < self.nlocal) {
                let fj = &mut f[3 * j..3 * j + 3];
                fj[0] -= fv[0];
                fj[1] -= fv[1];
                fj[2] -= fv[2];
            }
        }
        (self.i, self.fi) = (cur, fi);
    }
}

/// A finished row of [`Sum`]: `f[i] += fi` (nothing before the first row, `i = usize::MAX`).
#[inline(always)]
fn add_row(f: &mut [f64], i: usize, fi: [f64; 3]) {
    if i != usize::MAX {
        let fi_ = &mut f[3 * i..3 * i + 3];
        fi_[0] += fi[0];
        fi_[1] += fi[1];
        fi_[2] += fi[2];
    }
}

/// The list, newton and ownership settings of a walk's sums.
#[derive(Clone, Copy)]
struct Flags {
    full: bool,
    newton: bool,
    nlocal: usize,
}

/// [`walk_pairs`] on the threads of `w` ([`Workers`]).
fn threaded(
    walk: &Walk,
    w: &mut Workers,
    rows: &[(usize, &[i32])],
    f: &mut [f64],
    sinks: &mut Sinks,
    flags: Flags,
) -> Result<(), Error> {
    let tallying = sinks.any();
    // Phase 2's tasks: contiguous ranges of atoms, each with its part of f, eatom and vatom;
    // one more task for the global energy and virial.
    let nall = f.len() / 3;
    let tasks = w.blocks.len() / BLOCKS_PER_THREAD;
    let chunk = nall.div_ceil(tasks).max(1);
    let ntasks = nall.div_ceil(chunk);
    fn split(s: Option<&mut [f64]>, len: usize, count: usize) -> Vec<Option<&mut [f64]>> {
        match s {
            Some(s) => s.chunks_mut(len).map(Some).collect(),
            None => (0..count).map(|_| None).collect(),
        }
    }
    let eatom = split(sinks.eatom.as_deref_mut(), chunk, ntasks);
    let vatom = split(sinks.vatom.as_deref_mut(), 6 * chunk, ntasks);
    let mut parts: Vec<_> = f
        .chunks_mut(3 * chunk)
        .zip(eatom.into_iter().zip(vatom))
        .enumerate()
        .map(|(k, (f, (eatom, vatom)))| {
            let s = Sinks {
                eng: None,
                virial: None,
                eatom,
                vatom,
            };
            (k * chunk, f, s)
        })
        .collect();
    let mut global = Sinks {
        eng: sinks.eng.as_deref_mut(),
        virial: sinks.virial.as_deref_mut(),
        eatom: None,
        vatom: None,
    };
    let (team, blocks) = (&w.team, &mut w.blocks);
    let nb = blocks.len();
    // Window by window (whole rows, in list order), so that the records of a window stay in
    // the cache between the phases: one team scope per call (one pool `install`), the phases
    // inside it.
    team.scope(|| {
        for win in rows.chunks(WINDOW_ROWS) {
            // Phase 1: contiguous row blocks of the window, evaluated in parallel into their
            // records.
            let per = win.len().div_ceil(nb);
            team.for_each(blocks, &|k, b: &mut Block| {
                let part = &win[(k * per).min(win.len())..((k + 1) * per).min(win.len())];
                let rows = part.iter().map(|&r| Ok(r));
                b.err = if tallying {
                    b.pairs.clear();
                    b.tally.clear();
                    let (pairs, tally) = (&mut b.pairs, &mut b.tally);
                    walk.rows(rows, &mut b.bt, &mut b.near, |bt, is, js| {
                        for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
                            let (dr, fv) = lane_force(bt, l);
                            pairs.push(PairRec { i, j, f: fv });
                            tally.push(TallyRec {
                                energy: bt.energy[l],
                                fpair: bt.fpair[l],
                                dr,
                            });
                        }
                    })
                } else {
                    b.events.resize_with(ntasks, Vec::new);
                    b.events.iter_mut().for_each(Vec::clear);
                    let mut emit = Emit {
                        buckets: &mut b.events,
                        chunk: chunk as u32,
                        half: !flags.full,
                        newton: flags.newton,
                        nlocal: flags.nlocal as u32,
                        row: None,
                    };
                    let r = walk.rows(rows, &mut b.bt, &mut b.near, |bt, is, js| {
                        emit.batch(bt, is, js)
                    });
                    emit.finish_row();
                    r
                }
                .err();
            });
            if let Some(e) = blocks.iter_mut().find_map(|b| b.err.take()) {
                return Err(e);
            }
            let done: &[Block] = blocks;
            if !tallying {
                // Phase 2: each task adds its bucket of every block, in block order.
                team.for_each(&mut parts, &|t, (lo, f, _)| add_events(done, t, f, *lo));
                continue;
            }
            // Phase 2 of a tally step: every record of the window in list order, once per range
            // of atoms (forces and per-atom tallies), and once for the global energy and virial.
            let mut tasks: Vec<Replay> = global
                .any()
                .then_some(Replay::Global(&mut global))
                .into_iter()
                .chain(parts.iter_mut().map(Replay::Part))
                .collect();
            team.for_each(&mut tasks, &|_, task| match task {
                Replay::Global(g) => replay(done, &mut [], 0, g, flags),
                Replay::Part((lo, f, s)) => replay(done, f, *lo, s, flags),
            });
        }
        Ok(())
    })
}

/// A task of phase 2 of a tally step: a range of atoms (its first atom, its part of f and of
/// the per-atom tallies) or the global energy and virial.
enum Replay<'p, 's> {
    Part(&'p mut (usize, &'s mut [f64], Sinks<'s>)),
    Global(&'p mut Sinks<'s>),
}

/// Phase 2 of a force-only step of a threaded walk: bucket `t` of every block, in block order,
/// added to the atoms `lo..` of `f`.
fn add_events(blocks: &[Block], t: usize, f: &mut [f64], lo: usize) {
    for b in blocks {
        for e in &b.events[t] {
            let k = 3 * (e.atom as usize - lo);
            let fa = &mut f[k..k + 3];
            fa[0] += e.v[0];
            fa[1] += e.v[1];
            fa[2] += e.v[2];
        }
    }
}

/// Phase 2 of a threaded walk: every record of `blocks` in list order, added to the atoms `lo..`
/// of `f` and to `sinks` (its per-atom arrays start at atom `lo` too).
fn replay(blocks: &[Block], f: &mut [f64], lo: usize, sinks: &mut Sinks, flags: Flags) {
    let tallying = sinks.any();
    let mut apply = Apply::new(f, lo, sinks, flags);
    for b in blocks {
        if tallying {
            for (p, t) in b.pairs.iter().zip(&b.tally) {
                apply.pair(p.i as usize, p.j as usize, p.f, t.energy, t.fpair, t.dr);
            }
        } else {
            for p in &b.pairs {
                apply.pair(p.i as usize, p.j as usize, p.f, 0.0, 0.0, [0.0; 3]);
            }
        }
    }
    apply.finish_row();
}

/// The step's and the atoms' counts checked: (nlocal, nall).
fn counts(st: &DpdnlStep, atoms: &DpdnlAtoms) -> Result<(usize, usize), Error> {
    if st.step < 0 {
        return Err(Error::invalid(format!("step = {} must be >= 0", st.step)));
    }
    if st.dimension != 2 && st.dimension != 3 {
        return Err(Error::invalid(format!(
            "dimension = {} must be 2 or 3",
            st.dimension
        )));
    }
    if atoms.nlocal < 0 || atoms.nall < atoms.nlocal {
        return Err(Error::invalid(format!(
            "nlocal = {} and nall = {} must satisfy 0 <= nlocal <= nall",
            atoms.nlocal, atoms.nall
        )));
    }
    Ok((atoms.nlocal as usize, atoms.nall as usize))
}

impl<'a> Sinks<'a> {
    /// Whether anything is tallied.
    fn any(&self) -> bool {
        self.eng.is_some() || self.virial.is_some() || self.eatom.is_some() || self.vatom.is_some()
    }

    /// The tallies `tally` asks for (none without one), for `nall` atoms.
    ///
    /// # Safety
    /// Each pointer of `tally` is null or valid for its documented size and unaliased for `'a`.
    unsafe fn of(tally: Option<DpdnlTally>, nall: usize) -> Result<Sinks<'a>, Error> {
        let t = tally.unwrap_or(DpdnlTally {
            eflag_global: 0,
            vflag_global: 0,
            eng_vdwl: std::ptr::null_mut(),
            virial: std::ptr::null_mut(),
            eatom: std::ptr::null_mut(),
            vatom: std::ptr::null_mut(),
        });
        // SAFETY: each is null or valid for its documented size, unaliased (caller's contract).
        unsafe {
            Ok(Sinks {
                eng: if t.eflag_global != 0 {
                    Some(t.eng_vdwl.as_mut().ok_or_else(|| Error::null("eng_vdwl"))?)
                } else {
                    None
                },
                virial: if t.vflag_global != 0 {
                    Some(slice_mut(t.virial, 6, "virial")?)
                } else {
                    None
                },
                eatom: (!t.eatom.is_null())
                    .then(|| slice_mut(t.eatom, nall, "eatom"))
                    .transpose()?,
                vatom: (!t.vatom.is_null())
                    .then(|| slice_mut(t.vatom, 6 * nall, "vatom"))
                    .transpose()?,
            })
        }
    }
}

/// Adds evaluated pairs to the forces and tallies, in list order. The force on i is summed over
/// its row in `row` and added to f[i] when the next row starts (or at the end), as the
/// pair-by-pair loop did. Only atoms `lo..lo + n` are touched (`f` and the per-atom tallies hold
/// them): the single-threaded walk owns all atoms, a task of a threaded walk's phase 2 a range.
pub(crate) struct Apply<'a, 'b> {
    f: &'a mut [f64],
    lo: usize,
    n: usize,
    sinks: &'a mut Sinks<'b>,
    tallying: bool,
    flags: Flags,
    /// The row being summed: atom i and the force on it so far.
    row: Option<(usize, [f64; 3])>,
}

impl<'a, 'b> Apply<'a, 'b> {
    fn new(f: &'a mut [f64], lo: usize, sinks: &'a mut Sinks<'b>, flags: Flags) -> Self {
        Apply {
            n: f.len() / 3,
            f,
            lo,
            tallying: sinks.any(),
            sinks,
            flags,
            row: None,
        }
    }

    #[inline(always)]
    fn lane(&mut self, b: &PairBatch, l: usize, i: usize, j: usize) {
        let (dr, fv) = lane_force(b, l);
        self.pair(i, j, fv, b.energy[l], b.fpair[l], dr);
    }

    /// Pair (i, j) with force `fv` on i; `energy`, `fpair` and `dr` for the tallies.
    #[inline(always)]
    fn pair(&mut self, i: usize, j: usize, fv: [f64; 3], energy: f64, fpair: f64, dr: [f64; 3]) {
        if self.row.is_some_and(|(r, _)| r != i) {
            self.finish_row();
        }
        if i.wrapping_sub(self.lo) < self.n {
            let fi = &mut self.row.get_or_insert((i, [0.0; 3])).1;
            fi[0] += fv[0];
            fi[1] += fv[1];
            fi[2] += fv[2];
        }
        let Flags {
            full,
            newton,
            nlocal,
        } = self.flags;
        let j_owned = j < nlocal;
        let lj = j.wrapping_sub(self.lo);
        if !full && (newton || j_owned) && lj < self.n {
            self.f[3 * lj] -= fv[0];
            self.f[3 * lj + 1] -= fv[1];
            self.f[3 * lj + 2] -= fv[2];
        }
        if self.tallying {
            tally_pair(
                self.sinks,
                (self.lo, self.n),
                i,
                j,
                energy,
                fpair,
                dr,
                self.flags,
            );
        }
    }

    fn finish_row(&mut self) {
        if let Some((i, fi)) = self.row.take() {
            let li = i - self.lo;
            self.f[3 * li] += fi[0];
            self.f[3 * li + 1] += fi[1];
            self.f[3 * li + 2] += fi[2];
        }
    }
}

/// `1/m` for each mass, checking they are finite and > 0 (`offset` shifts the reported index).
pub(crate) fn inverse_masses(m: &[f64], offset: usize) -> Result<Vec<f64>, Error> {
    m.iter()
        .enumerate()
        .map(|(k, &mk)| {
            if mk.is_finite() && mk > 0.0 {
                Ok(1.0 / mk)
            } else {
                Err(Error::invalid(format!(
                    "mass[{}] = {mk} must be a finite number > 0",
                    k + offset
                )))
            }
        })
        .collect()
}

/// LAMMPS `ev_tally` (half list) / `ev_tally_full` (full list) for one pair; the per-atom
/// tallies only for the atoms of `(lo, n)`, `lo..lo + n`, whose entries the per-atom arrays
/// start with.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn tally_pair(
    s: &mut Sinks,
    (lo, n): (usize, usize),
    i: usize,
    j: usize,
    evdwl: f64,
    fpair: f64,
    d: [f64; 3],
    Flags {
        full,
        newton,
        nlocal,
    }: Flags,
) {
    let (i_owned, j_owned) = (i < nlocal, j < nlocal);
    let v = [
        d[0] * d[0] * fpair,
        d[1] * d[1] * fpair,
        d[2] * d[2] * fpair,
        d[0] * d[1] * fpair,
        d[0] * d[2] * fpair,
        d[1] * d[2] * fpair,
    ];
    // Global sums, in LAMMPS's order of operations: ev_tally_full adds half to i; ev_tally adds
    // the whole pair with newton on, and half per owned partner with newton off.
    if let Some(e) = s.eng.as_deref_mut() {
        if full {
            *e += 0.5 * evdwl;
        } else if newton {
            *e += evdwl;
        } else {
            if i_owned {
                *e += 0.5 * evdwl;
            }
            if j_owned {
                *e += 0.5 * evdwl;
            }
        }
    }
    if let Some(vir) = s.virial.as_deref_mut() {
        if !full && newton {
            for k in 0..6 {
                vir[k] += v[k];
            }
        } else {
            let times = if full {
                1
            } else {
                u8::from(i_owned) + u8::from(j_owned)
            };
            for _ in 0..times {
                for k in 0..6 {
                    vir[k] += 0.5 * v[k];
                }
            }
        }
    }
    let (li, lj) = (i.wrapping_sub(lo), j.wrapping_sub(lo));
    let to_i = (full || newton || i_owned) && li < n;
    let to_j = !full && (newton || j_owned) && lj < n;
    if let Some(ea) = s.eatom.as_deref_mut() {
        let half = 0.5 * evdwl;
        if to_i {
            ea[li] += half;
        }
        if to_j {
            ea[lj] += half;
        }
    }
    if let Some(va) = s.vatom.as_deref_mut() {
        for k in 0..6 {
            let half = 0.5 * v[k];
            if to_i {
                va[6 * li + k] += half;
            }
            if to_j {
                va[6 * lj + k] += half;
            }
        }
    }
}

/// The blow-up check of the standalone engine (`dpdnl::engine::check_atoms`) on the owned atoms:
/// a non-finite position, velocity or force, or a velocity crossing half the box length `len`
/// (3 doubles) in one step of `dt`, is an error (status and [`crate::dpdnl_last_error`]) naming
/// the step, the atom's tag and the quantity. The LAMMPS pair styles call it at every neighbour
/// rebuild and every 100 steps, after their forces.
///
/// # Safety
/// `atoms` as for [`crate::dpdnl_pair_compute`] (x, v, tag of the `nlocal` owned atoms are read); `f` holds
/// `3 * nlocal` doubles; `len` 3 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_check_health(
    atoms: *const DpdnlAtoms,
    f: *const f64,
    step: i64,
    dt: f64,
    len: *const f64,
    dimension: i32,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or valid (caller's contract).
        let a = unsafe { atoms.as_ref() }.ok_or_else(|| Error::null("atoms"))?;
        let n = usize::try_from(a.nlocal)
            .map_err(|_| Error::invalid(format!("nlocal = {} < 0", a.nlocal)))?;
        // SAFETY: sizes as documented (caller's contract).
        let (x, v, tag, f, len) = unsafe {
            (
                slice(a.x, 3 * n, "x")?,
                slice(a.v, 3 * n, "v")?,
                slice(a.tag, n, "tag")?,
                slice(f, 3 * n, "f")?,
                slice(len, 3, "len")?,
            )
        };
        let v3 = |p: &[f64], i: usize| [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
        dpdnl::engine::check_atoms(
            step.max(0) as u64,
            dt,
            if dimension == 2 { 2 } else { 3 },
            [len[0], len[1], len[2]],
            n,
            |i| (tag[i] as u32, v3(x, i), v3(v, i), v3(f, i)),
        )
        .map_err(Error::invalid)
    })
}
