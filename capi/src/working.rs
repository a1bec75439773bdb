//! The working copy of a LAMMPS neighbour list that a pair-style handle keeps between calls
//! ([`WorkingList`]): the standalone engine's working list (`dpdnl::engine::neighbor`, the same
//! margin and lifetime rule) over a list that LAMMPS builds.
//!
//! LAMMPS's list holds every pair within the cut-off plus the skin; most of its entries are
//! beyond the cut-off (n = 16, skin 0.3: 73.5 listed for 33.5 in range per atom), and every
//! call's distance filter reads them all. The copy keeps, of each row and in its order, the
//! entries within the row's cut-off plus a margin (a third of the skin) at its refresh. While
//! no atom (owned or ghost, in the coordinates the walk reads) has moved more than half the
//! margin since, a pair of LAMMPS's list in range now was within the cut-off plus the margin at
//! the refresh, so it is in the copy: walking the copy evaluates the same pairs in the same
//! order as walking LAMMPS's list, the same bits. The copy is refreshed when an atom has moved
//! that far, and dropped when LAMMPS builds its list again (`DpdnlNeighList::build`, LAMMPS's
//! `neighbor->ncalls`) or anything else about the list changes (counts, pointers, mask, the
//! cut-offs); lists that LAMMPS rebuilds within 12 force calls are walked as they are.

use dpdnl::host::{INNER_MARGIN, INNER_MIN_LIFE};

use crate::Error;
use crate::list::{DpdnlNeighList, check_row, list_row, moved_half_margin};

/// What identifies the LAMMPS list a copy was taken from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ListKey {
    build: i64,
    inum: i32,
    ilist: usize,
    numneigh: usize,
    firstneigh: usize,
    neighmask: i32,
    full: i32,
    nlocal: usize,
    nall: usize,
    skin: u64,
}

/// The working copy of a LAMMPS list (module docs), kept by a pair-style handle.
#[derive(Debug, Default)]
pub(crate) struct WorkingList {
    key: Option<ListKey>,
    /// The largest cut-off² per type row the copy was taken for.
    row_cutsq: Vec<f64>,
    /// Whether the copy is in use for the current LAMMPS list.
    on: bool,
    /// The copy must be taken again before it is walked.
    stale: bool,
    /// Force calls on the current LAMMPS list, and on the previous one.
    calls: u64,
    last_life: u64,
    /// Positions at the refresh (3 nall).
    x0: Vec<f64>,
    /// Rows: (atom, first entry, end) in `nbr`.
    rows: Vec<(u32, u32, u32)>,
    /// The kept raw entries (special-bond bits included).
    nbr: Vec<i32>,
    /// Refreshes so far (for tests and benchmarks).
    refreshes: u64,
}

impl WorkingList {
    /// Ready the copy for a call on `list` (the atoms' positions `x`, types `ty`, `nlocal`
    /// owned of `nall`; `row_cutsq` the largest cut-off² of each type's row): true when the
    /// walk is to take [`WorkingList::rows`], false when it walks `list` itself.
    ///
    /// # Safety
    /// `list` as documented on [`DpdnlNeighList`], `ilist` its `inum` entries; `x` holds
    /// 3 nall positions and `ty` nall types, each an index of `row_cutsq`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) unsafe fn prepare(
        &mut self,
        list: &DpdnlNeighList,
        ilist: &[i32],
        x: &[f64],
        ty: &[i32],
        row_cutsq: &[f64],
        nlocal: usize,
        nall: usize,
    ) -> Result<bool, Error> {
        if list.build < 1 || !(list.skin.is_finite() && list.skin > 0.0) {
            self.key = None;
            self.on = false;
            return Ok(false);
        }
        let key = ListKey {
            build: list.build,
            inum: list.inum,
            ilist: list.ilist as usize,
            numneigh: list.numneigh as usize,
            firstneigh: list.firstneigh as usize,
            neighmask: list.neighmask,
            full: list.full,
            nlocal,
            nall,
            skin: list.skin.to_bits(),
        };
        if self.key != Some(key) || self.row_cutsq != row_cutsq {
            if self.key.is_some() {
                self.last_life = self.calls;
            }
            self.key = Some(key);
            self.row_cutsq.clear();
            self.row_cutsq.extend_from_slice(row_cutsq);
            self.calls = 0;
            self.on = self.last_life >= INNER_MIN_LIFE;
            self.stale = true;
        }
        self.calls += 1;
        if !self.on && self.calls >= INNER_MIN_LIFE {
            // This list lives long: take the copy from now on.
            self.on = true;
            self.stale = true;
        }
        if !self.on {
            return Ok(false);
        }
        let margin = INNER_MARGIN * list.skin;
        if !self.stale {
            let moved = moved_half_margin(x, &self.x0, margin);
            if !moved {
                return Ok(true);
            }
        }
        // SAFETY: forwarded caller's contract.
        unsafe { self.refresh(list, ilist, x, ty, margin, nall)? };
        Ok(true)
    }

    /// Take the copy: of each row of `list`, in order, the entries within the row's cut-off
    /// plus `margin`.
    ///
    /// # Safety
    /// As [`WorkingList::prepare`].
    unsafe fn refresh(
        &mut self,
        list: &DpdnlNeighList,
        ilist: &[i32],
        x: &[f64],
        ty: &[i32],
        margin: f64,
        nall: usize,
    ) -> Result<(), Error> {
        let mask = list.neighmask as u32 as usize;
        let cutsq: Vec<f64> = self
            .row_cutsq
            .iter()
            .map(|&c| {
                let c = c.sqrt() + margin;
                c * c
            })
            .collect();
        self.rows.clear();
        self.nbr.clear();
        for &i in ilist {
            // SAFETY: forwarded caller's contract.
            let (i, jlist) = unsafe { list_row(list, i, nall)? };
            check_row(i, jlist, mask, nall)?;
            let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
            let csq = cutsq[ty[i] as usize];
            let start = self.nbr.len();
            self.nbr.extend(jlist.iter().filter(|&&jr| {
                let j = jr as u32 as usize & mask;
                let d = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < csq
            }));
            let too_many =
                || Error::invalid("the working copy of the neighbour list exceeds 2^32 entries");
            let start = u32::try_from(start).map_err(|_| too_many())?;
            let end = u32::try_from(self.nbr.len()).map_err(|_| too_many())?;
            self.rows.push((i as u32, start, end));
        }
        self.x0.clear();
        self.x0.extend_from_slice(x);
        self.stale = false;
        self.refreshes += 1;
        Ok(())
    }

    /// The rows of the copy, in list order: (atom, raw entries).
    pub(crate) fn rows(&self) -> impl Iterator<Item = (usize, &[i32])> + '_ {
        self.rows
            .iter()
            .map(|&(i, s, e)| (i as usize, &self.nbr[s as usize..e as usize]))
    }

    /// Refreshes so far.
    #[cfg(test)]
    pub(crate) fn refreshes(&self) -> u64 {
        self.refreshes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three atoms on a line: 0–1 at 1.0 (in range of cut-off 1.1), 0–2 at 1.5 (in LAMMPS's
    /// list of skin 0.6, beyond the copy's 1.1 + 0.2).
    struct Line {
        x: Vec<f64>,
        ty: Vec<i32>,
        rows: Vec<Vec<i32>>,
        ilist: Vec<i32>,
        numneigh: Vec<i32>,
        first: Vec<*const i32>,
    }

    impl Line {
        fn new() -> Line {
            let rows = vec![vec![1, 2], vec![2], vec![]];
            Line {
                x: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.5, 0.0, 0.0],
                ty: vec![1, 1, 1],
                numneigh: rows.iter().map(|r| r.len() as i32).collect(),
                first: rows.iter().map(|r| r.as_ptr()).collect(),
                ilist: vec![0, 1, 2],
                rows,
            }
        }

        fn list(&self, build: i64) -> DpdnlNeighList {
            DpdnlNeighList {
                inum: 3,
                ilist: self.ilist.as_ptr(),
                numneigh: self.numneigh.as_ptr(),
                firstneigh: self.first.as_ptr(),
                neighmask: 0x1FFF_FFFF,
                full: 0,
                build,
                skin: 0.6,
            }
        }
    }

    fn prepare(w: &mut WorkingList, l: &Line, build: i64) -> bool {
        let cutsq = [0.0, 1.21];
        // SAFETY: the list's arrays are alive and sized as documented.
        let r = unsafe { w.prepare(&l.list(build), &l.ilist, &l.x, &l.ty, &cutsq, 3, 3) };
        r.unwrap_or_else(|_| panic!("prepare failed"))
    }

    fn copy(w: &WorkingList) -> Vec<(usize, Vec<i32>)> {
        w.rows().map(|(i, r)| (i, r.to_vec())).collect()
    }

    #[test]
    fn the_copy_starts_after_twelve_calls_and_follows_the_atoms() {
        let mut l = Line::new();
        assert!(!l.rows.is_empty());
        let mut w = WorkingList::default();
        // Unknown builds are never copied.
        assert!((0..20).all(|_| !prepare(&mut w, &l, 0)));
        // A new list: walked as it is for 11 calls, copied from the 12th.
        for call in 1..=11 {
            assert!(!prepare(&mut w, &l, 1), "call {call}");
        }
        assert!(prepare(&mut w, &l, 1));
        assert_eq!(w.refreshes(), 1);
        assert_eq!(copy(&w), vec![(0, vec![1]), (1, vec![2]), (2, vec![])]);
        // Atom 2 moves 0.09 (under half the margin, 0.1): the same copy.
        l.x[6] = 1.41;
        assert!(prepare(&mut w, &l, 1));
        assert_eq!(w.refreshes(), 1);
        // 0.11: taken again, and atom 2 (now 1.29 from atom 0, 0.29 from atom 1) is in.
        l.x[6] = 1.29;
        assert!(prepare(&mut w, &l, 1));
        assert_eq!(w.refreshes(), 2);
        assert_eq!(copy(&w), vec![(0, vec![1, 2]), (1, vec![2]), (2, vec![])]);
        // LAMMPS builds again: the last list lived 14 calls, so the new one is copied at once.
        assert!(prepare(&mut w, &l, 2));
        assert_eq!(w.refreshes(), 3);
        // That list lived one call: the next one waits for 12 calls again.
        assert!(!prepare(&mut w, &l, 3));
    }
}
