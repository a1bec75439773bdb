//! The walk of [`crate::dpdnl_pair_compute`]: one LAMMPS neighbour list walked in Rust, its pairs
//! evaluated through the pair-style seam (`dpdnl::forces::batcher`) and added with LAMMPS's
//! `ev_tally` conventions. `walk.rs`: the rows and their batches (one thread); `threads.rs`:
//! the same walk on a team of threads, the same bits; `tally.rs`: LAMMPS's tally conventions.

use dpdnl::PairKernel;
use dpdnl::host::Batcher;
use dpdnl::host::Isa;
use dpdnl::host::SpecialRule;

use crate::list::*;
use crate::types::*;
use crate::working::WorkingList;
use crate::{DpdnlStatus, Error, guard, slice, slice_mut};

mod owned;
mod tally;
mod threads;
mod walk;

pub(crate) use tally::*;
pub(crate) use threads::*;
use walk::*;

/// The image key's frame of a step's box when some periodic length is below 2 r_c (the
/// largest cut-off of `cut`), else None (`dpdnl::host::images_keyed`).
fn image_frame(st: &DpdnlStep, cut: &[f64]) -> Option<dpdnl::host::ImageFrame> {
    let dim = if st.dimension == 2 { 2 } else { 3 };
    let periodic = st.periodic.map(|p| p != 0);
    let rc = cut.iter().copied().fold(0.0, f64::max);
    dpdnl::host::images_keyed(st.boxlen, periodic, dim, rc)
        .then(|| dpdnl::host::ImageFrame::new(dim, st.boxlen, st.tilt, periodic))
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
    // SAFETY: forwarded caller's contract.
    let (inv_mass, per_atom) = match unsafe { atom_masses(atoms, nall)? } {
        Some(rmass) => (inverse_masses(rmass, 0)?, true),
        None => {
            // SAFETY: `ntypes + 1` doubles (caller's contract).
            let mass = unsafe { slice(atoms.mass, nt + 1, "mass")? };
            (inverse_masses(&mass[1..], 1)?, false)
        }
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

/// The per-atom masses of `atoms` (`nall` of them, each checked finite and > 0), or `None` when
/// the atoms have per-type masses: the one place where every pass of a pair style (the walk's
/// 1/m_i + 1/m_j, the pre-pass's weights, its energies, the style's per-atom terms) chooses.
/// LAMMPS's driver passes `atom->rmass` where the atom style has it (`atom->rmass_flag`), as
/// LAMMPS's own styles and fixes read per-atom masses before per-type ones.
///
/// # Safety
/// `atoms.rmass` is null or holds `nall` doubles.
pub(crate) unsafe fn atom_masses(atoms: &DpdnlAtoms, nall: usize) -> Result<Option<&[f64]>, Error> {
    if atoms.rmass.is_null() {
        return Ok(None);
    }
    // SAFETY: `nall` doubles (caller's contract).
    let m = unsafe { slice(atoms.rmass, nall, "rmass")? };
    if let Some(k) = m.iter().position(|&x| !(x.is_finite() && x > 0.0)) {
        return Err(Error::invalid(format!(
            "rmass[{k}] = {} must be a finite number > 0",
            m[k]
        )));
    }
    Ok(Some(m))
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

/// The blow-up check of the standalone engine (`dpdnl::host::check_atoms`) on the owned atoms:
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
        dpdnl::host::check_atoms(
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
