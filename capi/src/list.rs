//! A LAMMPS neighbour list as the C ABI receives it ([`DpdnlNeighList`]) and its checked
//! reading: the rows, their special-bond bits, every index below `nall`. Read by the force walk
//! (`compute`), the sDPD pre-pass (`pair.rs`) and the working copy of the list (`working.rs`).

use crate::{Error, slice};

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

/// Whether any atom of `x` (3 doubles each) has moved more than `margin`/2 from its place in
/// `x0`: the lifetime rule of a list holding the pairs within the cut-off plus `margin` (the
/// style's own list, `ownlist/`, and the working copy of a list, `working.rs`). Positions of
/// another length count as moved.
pub(crate) fn moved_half_margin(x: &[f64], x0: &[f64], margin: f64) -> bool {
    if x0.len() != x.len() {
        return true;
    }
    let limit = 0.25 * margin * margin;
    x.chunks_exact(3).zip(x0.chunks_exact(3)).any(|(a, b)| {
        let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
    })
}
