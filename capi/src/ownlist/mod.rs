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
//!
//! The parts: `passes` (the threaded passes over all atoms), `sorted` (the counting sort by
//! bin), `grid` (the bins' geometry, stencil and ghost table), `candidates` (a run's distance
//! filter, scalar and AVX-512), `rows` (the rows, in blocks, laid out as a LAMMPS list).

mod candidates;
mod grid;
mod passes;
mod rows;
mod sorted;
#[cfg(test)]
mod tests;

use crate::Error;
use crate::list::DpdnlNeighList;
use crate::team::Team;
use grid::{Geometry, Grid};
use passes::{bounding_box, moved_half_margin_par};
use rows::Block;

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

/// Bin side over the list's reach (module docs: 1.0 beat 0.5 and 0.75).
const BIN_FRACTION: f64 = 1.0;

/// Rows per block of a threaded build (blocks are handed out to the threads dynamically).
const BLOCK_ROWS: usize = 512;

/// Atoms per item of the threaded passes over all atoms (bins, bounding box, moved check,
/// gathers).
const CHUNK_ATOMS: usize = 4096;

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

    /// A new list for `c` (module docs): the bins, the atoms sorted into them, the rows.
    fn build(
        &mut self,
        c: &Cloud,
        row_cut: &[f64],
        margin: f64,
        team: Option<&Team>,
    ) -> Result<(), Error> {
        let nall = checked_atoms(c)?;
        let reach = row_cut.iter().copied().fold(0.0, f64::max) + margin;
        let row_sq: Vec<f64> = row_cut
            .iter()
            .map(|&r| {
                let r = r + margin;
                r * r
            })
            .collect();
        // The bins: side >= reach along each axis of the atoms' bounding box.
        let (lo, hi) = bounding_box(c, team);
        if nall > 0 && (0..c.dim).any(|d| !(lo[d].is_finite() && hi[d].is_finite())) {
            return Err(Error::invalid(
                "an atom's position is not finite: the pair list cannot be built",
            ));
        }
        let geo = Geometry::new(c.dim, lo, hi, reach, nall);
        self.grid.fill(c, &geo, row_sq, team);
        self.build_rows(c, team)?;
        self.x0.clear();
        self.x0.extend_from_slice(c.x);
        self.builds += 1;
        Ok(())
    }
}

/// The number of atoms of `c`, once its arrays are checked to agree and fit the list's
/// entries.
fn checked_atoms(c: &Cloud) -> Result<usize, Error> {
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
    Ok(nall)
}
