//! The pair list that a LAMMPS pair style builds for itself (issue 44): a half list over the
//! owned and ghost atoms of one rank, in the layout of a LAMMPS list ([`DpdnlNeighList`]), so
//! every pass that reads a LAMMPS list (the force walk, its threads, the pre-pass) reads it
//! unchanged.
//!
//! **Which pairs.** Row i (every owned atom, in index order) holds atoms j within the row's
//! largest cut-off plus the list's margin m:
//! - j owned: each owned pair once, as in LAMMPS's half lists, in the row of the atom whose bin
//!   comes first (z, then y, then x), or of the earlier one in their common bin;
//! - j a ghost, newton off: always (each rank computes the force on its own atom);
//! - j a ghost, newton on: when tag(i) < tag(j), or for an image of i itself (equal tags) when
//!   the displacement x_j − x_i is positive in z, then y, then x. The pair seen from the other
//!   side (j owned on another rank, or another image on this one) has the opposite tag order or
//!   the opposite displacement, so each pair is listed on exactly one rank, once. LAMMPS's own
//!   lists decide by the coordinates alone; tags decide the same thing without comparing two
//!   rounded coordinates that should be equal.
//!
//! A bonded neighbour of i (its `atom->special` tags) is flagged with its class (1-2, 1-3, 1-4)
//! in bits 30–31 of the entry, as LAMMPS flags it; the walk leaves it out or scales it by the
//! factor in force (`SpecialRule`), so a factor-0 pair that LAMMPS would drop from its list
//! contributes nothing here either.
//!
//! **When it is built.** The ghost atoms and the atoms' order change only when LAMMPS
//! re-neighbours (`neighbor->ncalls`, passed as `build`), so the list is built again then; and,
//! between those, as soon as any atom (owned or ghost) has moved more than m/2 since the list
//! was built: a pair within the cut-off now was within cut-off + m then. LAMMPS's ghosts stay
//! sufficient between its builds (its own skin rule), so m may be below LAMMPS's skin: a
//! shorter list costs a build more often but a cheaper walk at every step.
//!
//! **How.** The owned atoms and the ghosts are sorted, apart, into bins of side ≥ r_c + m over
//! the box that holds them all (wider bins than LAMMPS's half-width ones: fewer, longer runs
//! of candidates suit the vector loop; Groot–Warren, 300 steps on one AMD EPYC core: 2.50 s
//! against 3.08 s with half-width bins). A row visits the upper half of the 27-bin stencil among
//! the owned atoms and the whole stencil among the ghosts (skipped where no ghost is within
//! reach, most of a large rank's bins), each row of bins along x one contiguous run in bin
//! order, and keeps the candidates without a branch (eight at a time with AVX-512). Rows are
//! built in blocks, on the pair style's threads when it has them; a row's entries do not depend
//! on the block, so the list is the same for any thread count. The passes over all atoms before
//! the rows (bounding box, bins, the moved-half-margin check, the two counting sorts) run on the
//! same threads, in pieces whose outputs do not overlap, with the same result.

use crate::Error;
use crate::list::{DpdnlNeighList, moved_half_margin};
use crate::team::Team;

/// The mask of an entry's atom index: bits 30–31 carry the special-bond class.
const INDEX_MASK: i32 = (1 << 30) - 1;

/// The bonded neighbours of one rank's owned atoms, as LAMMPS keeps them (`atom->nspecial`,
/// `atom->special`): for owned atom i, `nspecial[3i..3i+3]` are the cumulative counts of its
/// 1-2, 1-3 and 1-4 neighbours and `special[i maxspecial..]` their tags.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlSpecial {
    /// `3 nlocal` ints (LAMMPS `&nspecial[0][0]`), or null when the atom style has no bonds.
    pub nspecial: *const i32,
    /// `nlocal * maxspecial` tags (LAMMPS `&special[0][0]`), or null.
    pub special: *const i32,
    /// Entries per atom of `special` (LAMMPS `atom->maxspecial`).
    pub maxspecial: i32,
}

/// The atoms one build reads.
pub(crate) struct Cloud<'a> {
    /// Positions, 3 per atom, owned first.
    pub(crate) x: &'a [f64],
    /// Types (1-based), indices of `row_cut`.
    pub(crate) ty: &'a [i32],
    /// Global ids.
    pub(crate) tag: &'a [i32],
    /// Owned atoms.
    pub(crate) nlocal: usize,
    /// Bonded neighbours: (cumulative counts, 3 per owned atom; tags, `stride` per owned atom).
    pub(crate) special: Option<(&'a [i32], &'a [i32], usize)>,
    /// LAMMPS's newton_pair.
    pub(crate) newton: bool,
    /// 2 or 3.
    pub(crate) dim: usize,
}

/// What identifies the atoms a list was built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Key {
    build: i64,
    nlocal: usize,
    nall: usize,
    x: usize,
    newton: bool,
    margin: u64,
}

/// Atoms sorted by bin: where each bin starts, and each atom's index, position and tag in bin
/// order (structure of arrays: the distance loop reads them contiguously).
#[derive(Debug, Default)]
struct Sorted {
    start: Vec<u32>,
    order: Vec<u32>,
    sx: Vec<f64>,
    sy: Vec<f64>,
    sz: Vec<f64>,
    stag: Vec<i32>,
}

/// One run of a [`Sorted`]: positions, atom indices and tags.
type RunView<'a> = (&'a [f64], &'a [f64], &'a [f64], &'a [u32], &'a [i32]);

impl Sorted {
    /// The atoms `run` (in bin order).
    fn run(&self, run: std::ops::Range<usize>) -> RunView<'_> {
        (
            &self.sx[run.clone()],
            &self.sy[run.clone()],
            &self.sz[run.clone()],
            &self.order[run.clone()],
            &self.stag[run],
        )
    }

    /// Counting sort of the atoms `atoms` by their bin `bins[a]` (of `nbins`), stable (atoms
    /// of one bin in index order). With a team, the placing and the gathering run on its
    /// threads: each thread places the atoms of one range of bins (a range of the output, so
    /// the threads write apart) and gathers one range of the output; the result is the same.
    fn sort(
        &mut self,
        atoms: std::ops::Range<usize>,
        bins: &[u32],
        nbins: usize,
        c: &Cloud,
        team: Option<&Team>,
    ) {
        self.start.clear();
        self.start.resize(nbins + 1, 0);
        for a in atoms.clone() {
            self.start[bins[a] as usize + 1] += 1;
        }
        for b in 0..nbins {
            self.start[b + 1] += self.start[b];
        }
        let n = atoms.len();
        self.order.clear();
        self.order.resize(n, 0);
        // The bin ranges: about n / parts atoms each.
        let parts = match team {
            Some(t) if n >= 2 * CHUNK_ATOMS => t.threads(),
            _ => 1,
        };
        let mut cuts = vec![0usize];
        for k in 1..parts {
            let want = (n * k / parts) as u32;
            let b = self.start.partition_point(|&s| s < want).min(nbins);
            if b > *cuts.last().unwrap_or(&0) {
                cuts.push(b);
            }
        }
        cuts.push(nbins);
        struct Place<'o> {
            bins: std::ops::Range<usize>,
            out: &'o mut [u32],
        }
        let mut places = Vec::with_capacity(cuts.len() - 1);
        let mut rest: &mut [u32] = &mut self.order;
        for w in cuts.windows(2) {
            let len = (self.start[w[1]] - self.start[w[0]]) as usize;
            let (head, tail) = rest.split_at_mut(len);
            places.push(Place {
                bins: w[0]..w[1],
                out: head,
            });
            rest = tail;
        }
        let start = &self.start;
        let (a0, a1) = (atoms.start, atoms.end);
        par_items(team, &mut places, &|_, p| {
            let (lo, hi) = (p.bins.start as u32, p.bins.end as u32);
            let base = start[p.bins.start];
            let mut fill: Vec<u32> = start[p.bins.clone()].iter().map(|&s| s - base).collect();
            for (a, &b) in bins[a0..a1].iter().enumerate() {
                if b >= lo && b < hi {
                    let f = &mut fill[(b - lo) as usize];
                    p.out[*f as usize] = (a0 + a) as u32;
                    *f += 1;
                }
            }
        });
        for v in [&mut self.sx, &mut self.sy, &mut self.sz] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.stag.clear();
        self.stag.resize(n, 0);
        struct Gather<'o> {
            order: &'o [u32],
            sx: &'o mut [f64],
            sy: &'o mut [f64],
            sz: &'o mut [f64],
            stag: &'o mut [i32],
        }
        let mut gathers: Vec<Gather> = self
            .order
            .chunks(CHUNK_ATOMS)
            .zip(self.sx.chunks_mut(CHUNK_ATOMS))
            .zip(self.sy.chunks_mut(CHUNK_ATOMS))
            .zip(self.sz.chunks_mut(CHUNK_ATOMS))
            .zip(self.stag.chunks_mut(CHUNK_ATOMS))
            .map(|((((order, sx), sy), sz), stag)| Gather {
                order,
                sx,
                sy,
                sz,
                stag,
            })
            .collect();
        par_items(team, &mut gathers, &|_, g| {
            for (k, &a) in g.order.iter().enumerate() {
                let a = a as usize;
                g.sx[k] = c.x[3 * a];
                g.sy[k] = c.x[3 * a + 1];
                g.sz[k] = c.x[3 * a + 2];
                g.stag[k] = c.tag[a];
            }
        });
    }
}

/// The bins of one build: the owned atoms and the ghosts, each in bin order.
#[derive(Debug, Default)]
struct Grid {
    /// Bins per axis.
    nb: [usize; 3],
    own: Sorted,
    ghost: Sorted,
    /// Each atom's bin.
    bins: Vec<u32>,
    /// Each owned atom's place in `own`'s bin order.
    pos: Vec<u32>,
    /// Whether a bin's stencil holds any ghost (most of a large rank's bins: none).
    ghost_near: Vec<bool>,
    /// (y offset, z offset, largest x offset) of the bins a row visits.
    stencil: Vec<(i64, i64, i64)>,
    /// (cut-off + margin)² of each type's row.
    row_sq: Vec<f64>,
}

/// The rows `rows` of the list: their entries one after another, and where each row starts.
#[derive(Debug, Default)]
struct Block {
    rows: std::ops::Range<usize>,
    nbr: Vec<i32>,
    offsets: Vec<usize>,
}

/// Bin side over the list's reach (module docs: 1.0 beat 0.5 and 0.75).
const BIN_FRACTION: f64 = 1.0;

/// Rows per block of a threaded build (blocks are handed out to the threads dynamically).
const BLOCK_ROWS: usize = 512;

/// Atoms per item of the threaded passes over all atoms (bins, bounding box, moved check,
/// gathers).
const CHUNK_ATOMS: usize = 4096;

/// `f(k, &mut items[k])` for every item: on the team's threads when there is a team of more
/// than one and more than one item, else in order on this thread. Every item is processed
/// once, by one thread, so results do not depend on the team.
fn par_items<T: Send>(team: Option<&Team>, items: &mut [T], f: &(dyn Fn(usize, &mut T) + Sync)) {
    match team {
        Some(t) if t.threads() > 1 && items.len() > 1 => t.scope(|| t.for_each(items, f)),
        _ => items.iter_mut().enumerate().for_each(|(k, it)| f(k, it)),
    }
}

/// Whether any atom has moved more than half the margin since `x0` ([`moved_half_margin`]),
/// in chunks on the team's threads.
fn moved_half_margin_par(x: &[f64], x0: &[f64], margin: f64, team: Option<&Team>) -> bool {
    if x0.len() != x.len() {
        return true;
    }
    let n = 3 * CHUNK_ATOMS;
    let mut parts: Vec<(&[f64], &[f64], bool)> = x
        .chunks(n)
        .zip(x0.chunks(n))
        .map(|(a, b)| (a, b, false))
        .collect();
    par_items(team, &mut parts, &|_, p| {
        p.2 = moved_half_margin(p.0, p.1, margin);
    });
    parts.iter().any(|p| p.2)
}

/// A rank's own half list (module docs).
#[derive(Debug, Default)]
pub(crate) struct OwnList {
    key: Option<Key>,
    /// The largest cut-off of each type's row the list was built for.
    row_cut: Vec<f64>,
    /// Positions at the build (3 nall).
    x0: Vec<f64>,
    ilist: Vec<i32>,
    numneigh: Vec<i32>,
    first: Vec<*const i32>,
    /// The rows' entries, in blocks of consecutive rows (built in parallel with a team).
    blocks: Vec<Block>,
    grid: Grid,
    /// Builds so far.
    builds: u64,
}

impl OwnList {
    /// The list for `cloud` (built again if needed, module docs), as a LAMMPS list whose
    /// pointers stay valid until the next call: `build` is LAMMPS's build count,
    /// `row_cut[t]` the largest cut-off of type t's row, `margin` ≥ 0 the list's skin (checked
    /// by the caller, `dpdnl_pair_own_list`).
    pub(crate) fn prepare(
        &mut self,
        cloud: &Cloud,
        build: i64,
        row_cut: &[f64],
        margin: f64,
        team: Option<&Team>,
    ) -> Result<DpdnlNeighList, Error> {
        let nall = cloud.ty.len();
        let key = Key {
            build,
            nlocal: cloud.nlocal,
            nall,
            x: cloud.x.as_ptr() as usize,
            newton: cloud.newton,
            margin: margin.to_bits(),
        };
        let fresh = self.key == Some(key)
            && self.row_cut == row_cut
            && !moved_half_margin_par(cloud.x, &self.x0, margin, team);
        if !fresh {
            self.build(cloud, row_cut, margin, team)?;
            self.key = Some(key);
            self.row_cut.clear();
            self.row_cut.extend_from_slice(row_cut);
        }
        Ok(DpdnlNeighList {
            inum: cloud.nlocal as i32,
            ilist: self.ilist.as_ptr(),
            numneigh: self.numneigh.as_ptr(),
            firstneigh: self.first.as_ptr(),
            neighmask: INDEX_MASK,
            full: 0,
            // Which build this is, and its margin: a list that lives long (a small time step)
            // gets the walk's working copy of its entries within the cut-off plus a third of
            // the margin, as LAMMPS's lists do (`crate::working`).
            build: self.builds as i64,
            skin: margin,
        })
    }

    /// Builds so far.
    #[cfg(test)]
    pub(crate) fn builds(&self) -> u64 {
        self.builds
    }

    fn build(
        &mut self,
        c: &Cloud,
        row_cut: &[f64],
        margin: f64,
        team: Option<&Team>,
    ) -> Result<(), Error> {
        let nall = c.ty.len();
        if c.x.len() != 3 * nall || c.tag.len() != nall || c.nlocal > nall {
            return Err(Error::invalid(
                "the pair list's atom arrays disagree in length",
            ));
        }
        if nall >= INDEX_MASK as usize {
            return Err(Error::invalid(format!(
                "{nall} owned and ghost atoms: the pair list holds at most 2^30 - 1"
            )));
        }
        let reach = row_cut.iter().copied().fold(0.0, f64::max) + margin;
        let row_sq: Vec<f64> = row_cut
            .iter()
            .map(|&r| {
                let r = r + margin;
                r * r
            })
            .collect();
        // The bins: side >= reach / 2 along each axis of the atoms' bounding box.
        let mut lo = [0.0f64; 3];
        let mut hi = [0.0f64; 3];
        for d in 0..c.dim {
            lo[d] = f64::INFINITY;
            hi[d] = f64::NEG_INFINITY;
        }
        let mut boxes: Vec<(&[f64], [f64; 3], [f64; 3])> =
            c.x.chunks(3 * CHUNK_ATOMS).map(|x| (x, lo, hi)).collect();
        par_items(team, &mut boxes, &|_, (x, lo, hi)| {
            for p in x.chunks_exact(3) {
                for d in 0..c.dim {
                    lo[d] = lo[d].min(p[d]);
                    hi[d] = hi[d].max(p[d]);
                }
            }
        });
        for (_, l, h) in &boxes {
            for d in 0..c.dim {
                lo[d] = lo[d].min(l[d]);
                hi[d] = hi[d].max(h[d]);
            }
        }
        if nall > 0 && (0..c.dim).any(|d| !(lo[d].is_finite() && hi[d].is_finite())) {
            return Err(Error::invalid(
                "an atom's position is not finite: the pair list cannot be built",
            ));
        }
        let mut side = if reach > 0.0 {
            BIN_FRACTION * reach
        } else {
            1.0
        };
        let count = |s: f64| -> [usize; 3] {
            let mut n = [1usize; 3];
            for d in 0..c.dim {
                n[d] = (((hi[d] - lo[d]) / s).floor() as usize).clamp(1, 1 << 20);
            }
            n
        };
        // A sparse cloud (a huge box, a tiny cut-off) is given wider bins: at most
        // max(4 nall, 4096) of them, so a build stays linear in the atoms.
        let cap = (4 * nall).max(4096) as f64;
        let mut nb = count(side);
        while nb.iter().map(|&k| k as f64).product::<f64>() > cap {
            side *= 1.5;
            nb = count(side);
        }
        let mut width = [1.0f64; 3];
        let mut reachb = [0i64; 3];
        for d in 0..c.dim {
            width[d] = ((hi[d] - lo[d]) / nb[d] as f64).max(side);
            reachb[d] = (reach / width[d]).ceil() as i64;
        }
        let bin_of = |p: &[f64]| -> usize {
            let mut b = 0usize;
            for d in (0..c.dim).rev() {
                let k = (((p[d] - lo[d]) / width[d]) as usize).min(nb[d] - 1);
                b = b * nb[d] + k;
            }
            b
        };
        // Counting sorts by bin: the owned atoms, and the ghosts.
        let nbins = nb[0] * nb[1] * nb[2];
        let g = &mut self.grid;
        g.bins.clear();
        g.bins.resize(nall, 0);
        let mut chunks: Vec<(&[f64], &mut [u32])> =
            c.x.chunks(3 * CHUNK_ATOMS)
                .zip(g.bins.chunks_mut(CHUNK_ATOMS))
                .collect();
        par_items(team, &mut chunks, &|_, (x, out)| {
            for (p, b) in x.chunks_exact(3).zip(out.iter_mut()) {
                *b = bin_of(p) as u32;
            }
        });
        g.own.sort(0..c.nlocal, &g.bins, nbins, c, team);
        g.ghost.sort(c.nlocal..nall, &g.bins, nbins, c, team);
        g.ghost_near.clear();
        g.ghost_near.resize(nbins, false);
        g.pos.clear();
        g.pos.resize(c.nlocal, 0);
        for (k, &a) in g.own.order.iter().enumerate() {
            g.pos[a as usize] = k as u32;
        }
        // The stencil: for each (y, z) bin offset whose nearest points can be within `reach`,
        // the x offsets that can (a run of bins contiguous in bin order, x fastest).
        let mut stencil: Vec<(i64, i64, i64)> = Vec::new();
        let r = |d: usize| if d < c.dim { reachb[d] } else { 0 };
        let gap = |o: i64, d: usize| {
            let g = (o.abs() - 1).max(0) as f64 * width[d];
            g * g
        };
        for oz in -r(2)..=r(2) {
            for oy in -r(1)..=r(1) {
                let g = gap(oy, 1) + if c.dim == 3 { gap(oz, 2) } else { 0.0 };
                if g >= reach * reach {
                    continue;
                }
                let ox = (0..=r(0))
                    .take_while(|&o| g + gap(o, 0) < reach * reach)
                    .last()
                    .unwrap_or(0);
                stencil.push((oy, oz, ox));
            }
        }
        // Which bins have a ghost within the stencil's reach (a box of ±reachb bins): from a
        // summed-volume table of the ghosts per bin.
        {
            let g = &mut self.grid;
            let (px, py, pz) = (nb[0] + 1, nb[1] + 1, nb[2] + 1);
            let mut sat = vec![0u32; px * py * pz];
            let at = |x: usize, y: usize, z: usize| (z * py + y) * px + x;
            for z in 0..nb[2] {
                for y in 0..nb[1] {
                    for x in 0..nb[0] {
                        let b = (z * nb[1] + y) * nb[0] + x;
                        let here = g.ghost.start[b + 1] - g.ghost.start[b];
                        sat[at(x + 1, y + 1, z + 1)] = here
                            + sat[at(x, y + 1, z + 1)]
                            + sat[at(x + 1, y, z + 1)]
                            + sat[at(x + 1, y + 1, z)]
                            + sat[at(x, y, z)]
                            - sat[at(x, y, z + 1)]
                            - sat[at(x, y + 1, z)]
                            - sat[at(x + 1, y, z)];
                    }
                }
            }
            let r = |d: usize| if d < c.dim { reachb[d] as usize } else { 0 };
            for z in 0..nb[2] {
                let (z0, z1) = (z.saturating_sub(r(2)), (z + r(2) + 1).min(nb[2]));
                for y in 0..nb[1] {
                    let (y0, y1) = (y.saturating_sub(r(1)), (y + r(1) + 1).min(nb[1]));
                    for x in 0..nb[0] {
                        let (x0, x1) = (x.saturating_sub(r(0)), (x + r(0) + 1).min(nb[0]));
                        let sum = (sat[at(x1, y1, z1)] as i64)
                            - sat[at(x0, y1, z1)] as i64
                            - sat[at(x1, y0, z1)] as i64
                            - sat[at(x1, y1, z0)] as i64
                            + sat[at(x0, y0, z1)] as i64
                            + sat[at(x0, y1, z0)] as i64
                            + sat[at(x1, y0, z0)] as i64
                            - sat[at(x0, y0, z0)] as i64;
                        g.ghost_near[(z * nb[1] + y) * nb[0] + x] = sum > 0;
                    }
                }
            }
        }
        self.grid.nb = nb;
        self.grid.stencil = stencil;
        self.grid.row_sq = row_sq;
        // The rows, in blocks of consecutive rows: on the team's threads when there is one
        // (each block is built by one thread, alone, so the list is the same for any count).
        self.ilist.clear();
        self.ilist.extend(0..c.nlocal as i32);
        let nblocks = match team {
            Some(t) if t.threads() > 1 => c.nlocal.div_ceil(BLOCK_ROWS),
            _ => 1,
        }
        .max(1);
        self.blocks.resize_with(nblocks, Block::default);
        let per = c.nlocal.div_ceil(nblocks);
        for (k, blk) in self.blocks.iter_mut().enumerate() {
            blk.rows = (k * per).min(c.nlocal)..((k + 1) * per).min(c.nlocal);
        }
        let grid = &self.grid;
        par_items(team, &mut self.blocks, &|_, blk| fill_rows(grid, c, blk));
        self.numneigh.clear();
        self.first.clear();
        for blk in &self.blocks {
            let base = blk.nbr.as_ptr();
            for (r, &o) in blk.offsets.iter().enumerate() {
                let end = blk.offsets.get(r + 1).copied().unwrap_or(blk.nbr.len());
                self.numneigh.push(
                    i32::try_from(end - o).map_err(|_| {
                        Error::invalid("a row of the pair list exceeds 2^31 entries")
                    })?,
                );
                // SAFETY: o <= blk.nbr.len(): within (or one past) the block's allocation.
                self.first.push(unsafe { base.add(o) });
            }
        }
        self.x0.clear();
        self.x0.extend_from_slice(c.x);
        self.builds += 1;
        Ok(())
    }
}

/// The bins of a stencil entry from bin `bc`: (first bin of the row of bins, first x, last x),
/// or None when the row is outside the grid.
#[inline(always)]
fn bin_run(
    nb: [usize; 3],
    bc: [usize; 3],
    oy: i64,
    oz: i64,
    ox: i64,
) -> Option<(usize, usize, usize)> {
    let (ky, kz) = (bc[1] as i64 + oy, bc[2] as i64 + oz);
    if ky < 0 || ky >= nb[1] as i64 || kz < 0 || kz >= nb[2] as i64 {
        return None;
    }
    let x0 = (bc[0] as i64 - ox).max(0) as usize;
    let x1 = (bc[0] as i64 + ox).min(nb[0] as i64 - 1) as usize;
    Some(((kz as usize * nb[1] + ky as usize) * nb[0], x0, x1))
}

/// Which candidates in range a run keeps.
#[derive(Clone, Copy)]
enum Keep {
    /// All of them (owned partners; ghosts with newton off).
    All,
    /// Ghosts with newton on, for a row of tag t: a larger tag, or tag t (an image of the row's
    /// own atom) when x_j − x_i is positive in z, then y, then x (module docs).
    AboveTag(i32),
}

impl Keep {
    #[inline(always)]
    fn keeps(self, tj: i32, d: [f64; 3]) -> bool {
        match self {
            Keep::All => true,
            Keep::AboveTag(ti) => {
                let up = (d[2] > 0.0)
                    | ((d[2] == 0.0) & ((d[1] > 0.0) | ((d[1] == 0.0) & (d[0] > 0.0))));
                (ti < tj) | ((ti == tj) & up)
            }
        }
    }
}

/// Appends to `nbr` the atoms `run` of `sorted` within `csq` of `xi` that `keep` keeps, in
/// bin order. Branch-free: every candidate is written, the count advances when it is kept
/// (about a third are in range: a branch would be mispredicted). With AVX-512, eight at a
/// time with the same arithmetic ((dx² + dy²) + dz², no FMA), so the same pairs are kept with
/// every instruction set.
#[inline(always)]
fn push_run(
    nbr: &mut Vec<i32>,
    sorted: &Sorted,
    run: std::ops::Range<usize>,
    xi: [f64; 3],
    csq: f64,
    keep: Keep,
) {
    if run.is_empty() {
        return;
    }
    let at = nbr.len();
    #[cfg(target_arch = "x86_64")]
    if avx512() {
        // 16 entries of room past the run: the vector loop stores 16 lanes at a time, into
        // the spare capacity (not zeroed first: a memset per run cost 5 % of a Groot–Warren
        // step).
        nbr.reserve(run.len() + 16);
        let out = nbr.spare_capacity_mut().as_mut_ptr() as *mut i32;
        // SAFETY: the CPU has AVX-512F (checked); `run` is within `sorted`'s arrays (bin
        // starts); `out` has room for run.len() + 16 entries (reserved). The loop initialises
        // the first n of them, so the length may grow by n.
        unsafe {
            let n = run_avx512(out, sorted, run, xi, csq, keep);
            nbr.set_len(at + n);
        }
        return;
    }
    nbr.resize(at + run.len(), 0);
    let n = run_scalar(&mut nbr[at..], sorted, run, xi, csq, keep);
    nbr.truncate(at + n);
}

/// [`push_run`]'s portable loop: the kept candidates to the front of `out`; their count.
#[inline(always)]
fn run_scalar(
    out: &mut [i32],
    sorted: &Sorted,
    run: std::ops::Range<usize>,
    xi: [f64; 3],
    csq: f64,
    keep: Keep,
) -> usize {
    let mut n = 0usize;
    let (xs, ys, zs, order, tags) = sorted.run(run);
    for ((((&x, &y), &z), &j), &tj) in xs.iter().zip(ys).zip(zs).zip(order).zip(tags) {
        let d = [x - xi[0], y - xi[1], z - xi[2]];
        let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        out[n] = j as i32;
        n += ((rsq < csq) & keep.keeps(tj, d)) as usize;
    }
    n
}

/// Whether the CPU has AVX-512F (detected once; off under `cfg(test)` while
/// [`tests::SCALAR`] is set on the thread).
#[cfg(target_arch = "x86_64")]
fn avx512() -> bool {
    use std::sync::OnceLock;
    static HAS: OnceLock<bool> = OnceLock::new();
    #[cfg(test)]
    if tests::SCALAR.with(|s| s.get()) {
        return false;
    }
    *HAS.get_or_init(|| std::arch::is_x86_feature_detected!("avx512f"))
}

/// [`run_scalar`] eight candidates at a time: their distances, the tag test of
/// [`Keep::AboveTag`] in lanes (a tie, an image of the row's own atom, is settled lane by lane
/// as the scalar loop does), and the kept indices compressed to the front in a register and
/// stored 16 lanes wide.
///
/// # Safety
/// The CPU has AVX-512F; `run` is within `sorted`'s arrays; `out` is valid for writing
/// run.len() + 16 entries.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn run_avx512(
    out: *mut i32,
    sorted: &Sorted,
    run: std::ops::Range<usize>,
    xi: [f64; 3],
    csq: f64,
    keep: Keep,
) -> usize {
    use std::arch::x86_64::*;
    let (xs, ys, zs, order, tags) = sorted.run(run);
    let len = xs.len();
    let (x0, y0, z0) = (
        _mm512_set1_pd(xi[0]),
        _mm512_set1_pd(xi[1]),
        _mm512_set1_pd(xi[2]),
    );
    let cut = _mm512_set1_pd(csq);
    let mut n = 0usize;
    let mut k = 0usize;
    while k < len {
        let lanes = (len - k).min(8);
        let live: __mmask8 = if lanes == 8 { 0xFF } else { (1u8 << lanes) - 1 };
        // SAFETY: lanes past `len` are masked off in every load (no memory is read there);
        // the store writes 16 lanes from n <= k, and k + 16 <= len + 16 entries of `out`.
        unsafe {
            let dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(live, xs.as_ptr().add(k)), x0);
            let dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(live, ys.as_ptr().add(k)), y0);
            let dz = _mm512_sub_pd(_mm512_maskz_loadu_pd(live, zs.as_ptr().add(k)), z0);
            let rsq = _mm512_add_pd(
                _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                _mm512_mul_pd(dz, dz),
            );
            let mut m = _mm512_mask_cmp_pd_mask::<_CMP_LT_OQ>(live, rsq, cut);
            if let Keep::AboveTag(ti) = keep
                && m != 0
            {
                let t = _mm512_maskz_loadu_epi32(live as __mmask16, tags.as_ptr().add(k));
                let tiv = _mm512_set1_epi32(ti);
                let above = _mm512_cmpgt_epi32_mask(t, tiv) as __mmask8;
                let mut tie = _mm512_cmpeq_epi32_mask(t, tiv) as __mmask8 & m;
                let mut kept = m & above;
                while tie != 0 {
                    let l = tie.trailing_zeros() as usize;
                    let j = k + l;
                    let d = [xs[j] - xi[0], ys[j] - xi[1], zs[j] - xi[2]];
                    if keep.keeps(tags[j], d) {
                        kept |= 1 << l;
                    }
                    tie &= tie - 1;
                }
                m = kept;
            }
            let idx =
                _mm512_maskz_loadu_epi32(live as __mmask16, order.as_ptr().add(k) as *const i32);
            let packed = _mm512_maskz_compress_epi32(m as __mmask16, idx);
            _mm512_storeu_si512(out.add(n) as *mut _, packed);
            n += m.count_ones() as usize;
        }
        k += 8;
    }
    n
}

/// The rows `blk.rows` of the list (module docs) into `blk`.
fn fill_rows(g: &Grid, c: &Cloud, blk: &mut Block) {
    let nb = g.nb;
    let newton = c.newton;
    blk.nbr.clear();
    blk.offsets.clear();
    for i in blk.rows.clone() {
        let first = blk.nbr.len();
        blk.offsets.push(first);
        let (xi, yi, zi) = (c.x[3 * i], c.x[3 * i + 1], c.x[3 * i + 2]);
        let csq = g.row_sq[c.ty[i] as usize];
        let ti = c.tag[i];
        let b = g.bins[i] as usize;
        let bc = [b % nb[0], (b / nb[0]) % nb[1], b / (nb[0] * nb[1])];
        // Owned partners: each pair once, from the atom whose bin comes first (z, then y,
        // then x), or from the earlier of two in one bin.
        for &(oy, oz, ox) in &g.stencil {
            if (oz, oy) < (0, 0) {
                continue;
            }
            let Some((row, x0, x1)) = bin_run(nb, bc, oy, oz, ox) else {
                continue;
            };
            let s = if (oz, oy) == (0, 0) {
                g.pos[i] as usize + 1
            } else {
                g.own.start[row + x0] as usize
            };
            let e = g.own.start[row + x1 + 1] as usize;
            push_run(&mut blk.nbr, &g.own, s..e, [xi, yi, zi], csq, Keep::All);
        }
        // Ghost partners: with newton on, a pair is kept on the rank (or from the image) whose
        // atom has the smaller ID (module docs).
        let keep = if newton {
            Keep::AboveTag(ti)
        } else {
            Keep::All
        };
        let ghost_stencil: &[(i64, i64, i64)] = if g.ghost_near[b] { &g.stencil } else { &[] };
        for &(oy, oz, ox) in ghost_stencil {
            let Some((row, x0, x1)) = bin_run(nb, bc, oy, oz, ox) else {
                continue;
            };
            let (s, e) = (
                g.ghost.start[row + x0] as usize,
                g.ghost.start[row + x1 + 1] as usize,
            );
            push_run(&mut blk.nbr, &g.ghost, s..e, [xi, yi, zi], csq, keep);
        }
        // Bonded neighbours: their class in bits 30-31.
        if let Some((ns, sp, stride)) = c.special {
            let n = [ns[3 * i], ns[3 * i + 1], ns[3 * i + 2]];
            if n[2] > 0 {
                let tags = &sp[stride * i..stride * i + n[2] as usize];
                for e in &mut blk.nbr[first..] {
                    let class = match tags.iter().position(|&t| t == c.tag[*e as usize]) {
                        Some(p) if (p as i32) < n[0] => 1,
                        Some(p) if (p as i32) < n[1] => 2,
                        Some(_) => 3,
                        None => 0,
                    };
                    *e |= class << 30;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::list::for_each_row;

    thread_local! {
        /// Set: this thread's builds take the portable loop (to compare it with the vector one).
        pub(super) static SCALAR: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    }

    /// The atoms of a 3-D one-type cloud without bonds.
    fn atomic<'a>(
        x: &'a [f64],
        ty: &'a [i32],
        tag: &'a [i32],
        nlocal: usize,
        newton: bool,
    ) -> Cloud<'a> {
        Cloud {
            x,
            ty,
            tag,
            nlocal,
            special: None,
            newton,
            dim: 3,
        }
    }

    /// A small periodic box of random atoms, its ghosts the images within `ghost` of the box
    /// (as LAMMPS's borders make them on one rank).
    fn cloud(n: usize, len: f64, ghost: f64, seed: u64) -> (Vec<f64>, Vec<i32>, usize) {
        let mut s = seed;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let own: Vec<[f64; 3]> = (0..n)
            .map(|_| [rnd() * len, rnd() * len, rnd() * len])
            .collect();
        let mut x = Vec::new();
        let mut tag = Vec::new();
        for (k, p) in own.iter().enumerate() {
            x.extend_from_slice(p);
            tag.push(k as i32 + 1);
        }
        let range = |v: f64| -> Vec<i32> {
            let mut s = vec![];
            for m in -2i32..=2 {
                let w = v + m as f64 * len;
                if m != 0 && w > -ghost && w < len + ghost {
                    s.push(m);
                }
            }
            s.push(0);
            s
        };
        for (k, p) in own.iter().enumerate() {
            for mx in range(p[0]) {
                for my in range(p[1]) {
                    for mz in range(p[2]) {
                        if mx == 0 && my == 0 && mz == 0 {
                            continue;
                        }
                        x.extend_from_slice(&[
                            p[0] + mx as f64 * len,
                            p[1] + my as f64 * len,
                            p[2] + mz as f64 * len,
                        ]);
                        tag.push(k as i32 + 1);
                    }
                }
            }
        }
        (x, tag, n)
    }

    /// Every pair of atoms (with its image) within the cut-off is listed exactly once with
    /// newton on, and once per owned atom with newton off, for boxes longer and shorter than
    /// twice the cut-off (an atom then meets images of its partner, and its own).
    #[test]
    fn every_pair_in_range_is_listed_once() {
        for (len, n, rc, margin) in [
            (5.0, 300, 1.0, 0.3),
            (1.7, 12, 1.0, 0.3),
            (1.2, 10, 1.0, 0.3),
            (3.0, 80, 1.2, 0.0),
        ] {
            let ghost = rc + margin;
            let (x, tag, nlocal) = cloud(n, len, ghost, 7);
            let nall = tag.len();
            let ty = vec![1; nall];
            for newton in [true, false] {
                let c = atomic(&x, &ty, &tag, nlocal, newton);
                let mut own = OwnList::default();
                let list = own
                    .prepare(&c, 1, &[0.0, rc], margin, None)
                    .unwrap_or_else(|e| panic!("{}", e.message));
                // Count, per (tag, tag, image displacement), the listed pairs in range rc.
                let mut seen = std::collections::BTreeMap::new();
                // SAFETY: the list's arrays live in `own`, sized for nlocal rows.
                unsafe {
                    for_each_row(&list, nall, |i, row, mask| {
                        for &jr in row {
                            let j = jr as usize & mask;
                            let d: Vec<f64> = (0..3).map(|k| x[3 * j + k] - x[3 * i + k]).collect();
                            let r2: f64 = d.iter().map(|v| v * v).sum();
                            assert!(r2 < (rc + margin) * (rc + margin));
                            if r2 < rc * rc {
                                let (a, b, s) = if tag[i] <= tag[j] {
                                    (tag[i], tag[j], 1.0)
                                } else {
                                    (tag[j], tag[i], -1.0)
                                };
                                let key: Vec<i64> =
                                    d.iter().map(|v| (s * v * 1e6).round() as i64).collect();
                                *seen.entry((a, b, key)).or_insert(0) += 1;
                            }
                        }
                        Ok(())
                    })
                    .unwrap_or_else(|e| panic!("{}", e.message));
                }
                // Brute force over the owned atoms and every image.
                let mut want = std::collections::BTreeMap::new();
                for i in 0..nlocal {
                    for j in 0..nall {
                        let d: Vec<f64> = (0..3).map(|k| x[3 * j + k] - x[3 * i + k]).collect();
                        let r2: f64 = d.iter().map(|v| v * v).sum();
                        if j == i || r2 >= rc * rc {
                            continue;
                        }
                        let (a, b, s) = if tag[i] <= tag[j] {
                            (tag[i], tag[j], 1.0)
                        } else {
                            (tag[j], tag[i], -1.0)
                        };
                        let key: Vec<i64> =
                            d.iter().map(|v| (s * v * 1e6).round() as i64).collect();
                        // With newton off an owned-owned pair is listed once, a pair with a
                        // ghost once per owned atom (the physical pair, from each side).
                        let times = if newton || j < nlocal { 1 } else { 2 };
                        want.insert((a, b, key), times);
                    }
                }
                assert!(!want.is_empty());
                assert_eq!(seen, want, "len {len} newton {newton}");
                assert_eq!(own.builds(), 1);
            }
        }
    }

    /// Rows of a list as (atom, entries).
    fn rows_of(list: &DpdnlNeighList, nall: usize) -> Vec<(usize, Vec<i32>)> {
        let mut rows = Vec::new();
        // SAFETY: the caller's list lives in its OwnList, sized for its rows.
        unsafe {
            for_each_row(list, nall, |i, row, _| {
                rows.push((i, row.to_vec()));
                Ok(())
            })
            .unwrap_or_else(|e| panic!("{}", e.message));
        }
        rows
    }

    /// A team of threads builds the same list, row for row and entry for entry.
    #[test]
    fn threads_build_the_same_list() {
        // Enough atoms (owned and ghosts, each over 2 CHUNK_ATOMS) that the sorts, the bins
        // and the moved check run threaded too.
        let (x, tag, nlocal) = cloud(12000, 16.0, 2.0, 11);
        let nall = tag.len();
        assert!(nlocal > 2 * CHUNK_ATOMS && nall - nlocal > 2 * CHUNK_ATOMS);
        let ty = vec![1; nall];
        for threads in [2, 3] {
            let team = Team::new(threads, None).unwrap_or_else(|e| panic!("{e}"));
            for newton in [true, false] {
                let c = atomic(&x, &ty, &tag, nlocal, newton);
                let (mut one, mut two) = (OwnList::default(), OwnList::default());
                let a = one
                    .prepare(&c, 1, &[0.0, 1.0], 0.3, None)
                    .unwrap_or_else(|e| panic!("{}", e.message));
                let b = two
                    .prepare(&c, 1, &[0.0, 1.0], 0.3, Some(&team))
                    .unwrap_or_else(|e| panic!("{}", e.message));
                assert!(two.blocks.len() > 1);
                let ra = rows_of(&a, nall);
                assert_eq!(ra.len(), nlocal);
                assert!(ra.iter().map(|r| r.1.len()).sum::<usize>() > 10 * nlocal);
                assert_eq!(ra, rows_of(&b, nall));
                for (s1, s2) in [
                    (&one.grid.own, &two.grid.own),
                    (&one.grid.ghost, &two.grid.ghost),
                ] {
                    assert_eq!(
                        (&s1.start, &s1.order, &s1.stag),
                        (&s2.start, &s2.order, &s2.stag)
                    );
                    assert_eq!((&s1.sx, &s1.sy, &s1.sz), (&s2.sx, &s2.sy, &s2.sz));
                }
                assert_eq!(one.grid.bins, two.grid.bins);
            }
        }
    }

    /// The vector loop (AVX-512, where the CPU has it) and the portable one build the same list,
    /// in a large box and in one shorter than twice the reach (images of an atom's own tag).
    #[test]
    fn every_instruction_set_builds_the_same_list() {
        for (n, len, seed) in [(3000, 10.0, 5), (12, 1.2, 9)] {
            let (x, tag, nlocal) = cloud(n, len, 1.3, seed);
            let nall = tag.len();
            let ty = vec![1; nall];
            for newton in [true, false] {
                let c = atomic(&x, &ty, &tag, nlocal, newton);
                let mut rows = Vec::new();
                for scalar in [false, true] {
                    SCALAR.with(|s| s.set(scalar));
                    let mut own = OwnList::default();
                    let l = own
                        .prepare(&c, 1, &[0.0, 1.0], 0.3, None)
                        .unwrap_or_else(|e| panic!("{}", e.message));
                    rows.push(rows_of(&l, nall));
                }
                SCALAR.with(|s| s.set(false));
                assert!(rows[0].iter().map(|r| r.1.len()).sum::<usize>() > nlocal);
                assert_eq!(rows[0], rows[1], "n {n} newton {newton}");
            }
        }
    }

    /// Built again when LAMMPS builds, or when an atom has moved more than half the margin.
    #[test]
    fn built_again_when_an_atom_moves_half_the_margin() {
        let (mut x, tag, nlocal) = cloud(50, 4.0, 1.3, 3);
        let ty = vec![1; tag.len()];
        let mut own = OwnList::default();
        let mut run = |x: &[f64], build| {
            let c = atomic(x, &ty, &tag, nlocal, true);
            own.prepare(&c, build, &[0.0, 1.0], 0.3, None)
                .map(|_| own.builds())
                .unwrap_or_else(|e| panic!("{}", e.message))
        };
        assert_eq!(run(&x, 1), 1);
        x[0] += 0.14;
        assert_eq!(run(&x, 1), 1);
        x[0] += 0.02;
        assert_eq!(run(&x, 1), 2);
        assert_eq!(run(&x, 2), 3);
    }

    /// Bonded neighbours carry their class in bits 30-31.
    #[test]
    fn special_neighbours_are_flagged() {
        // Atoms 1-2-3-4 on a line 0.5 apart, one owned rank, no ghosts (non-periodic).
        let x: Vec<f64> = (0..4).flat_map(|k| [0.5 * k as f64, 0.0, 0.0]).collect();
        let tag = vec![1, 2, 3, 4];
        let ty = vec![1; 4];
        // Atom 1: 1-2 neighbour 2, 1-3 neighbour 3, 1-4 neighbour 4.
        let nspecial = vec![1, 2, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        let special = vec![2, 3, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        let c = Cloud {
            x: &x,
            ty: &ty,
            tag: &tag,
            nlocal: 4,
            special: Some((&nspecial, &special, 3)),
            newton: true,
            dim: 3,
        };
        let mut own = OwnList::default();
        let list = own
            .prepare(&c, 1, &[0.0, 2.0], 0.0, None)
            .unwrap_or_else(|e| panic!("{}", e.message));
        let mut row0 = Vec::new();
        // SAFETY: the list's arrays live in `own`.
        unsafe {
            for_each_row(&list, 4, |i, row, _| {
                if i == 0 {
                    row0 = row.to_vec();
                }
                Ok(())
            })
            .unwrap_or_else(|e| panic!("{}", e.message));
        }
        let mut want = vec![1 | 1 << 30, 2 | 2 << 30, 3 | 3 << 30];
        row0.sort();
        want.sort();
        assert_eq!(row0, want);
    }
}
