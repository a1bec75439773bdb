//! `pair_style sdpd` over the C ABI: an opaque [`DpdnlSdpd`] holds the style (the standalone
//! engine's `dpdnl::engine::sdpd::SdpdField`: parsed by the same grammar, resolved by the same
//! set-up), and one force evaluation is three calls around LAMMPS's communication:
//!
//! 1. [`dpdnl_sdpd_density`]: Σ_j W(r_ij) over the half list into `rho` (owned atoms, and ghosts
//!    with newton on; the C++ style then sums ghost parts into their owners, `reverse_comm`);
//! 2. [`dpdnl_sdpd_finish`]: the self term W(0) and the Tait energy of the owned atoms (a
//!    non-finite pressure is an error naming the atom); the style then sends the owners'
//!    densities to their ghosts (`forward_comm`);
//! 3. [`dpdnl_sdpd_compute`]: the pair forces (WF-12/19) from every atom's density, through the
//!    same list walk and tallies as `dpdnl_compute`.

use std::ffi::c_char;

use dpdnl::engine::sdpd::SdpdField;
use dpdnl::grammar;
use dpdnl::kernel::sdpd::SdpdAtom;

use crate::compute::{for_each_row, walk_pairs};
use crate::init::set_last_message;
use crate::styles::{put, words};
use crate::{
    DpdnlAtoms, DpdnlNeighList, DpdnlStatus, DpdnlStep, DpdnlTally, Error, guard, slice, slice_mut,
};

/// `pair_style sdpd` and its coefficients (opaque to C).
pub struct DpdnlSdpd {
    field: SdpdField,
    /// Per-atom terms of the current evaluation (owned + ghost atoms).
    atoms: Vec<SdpdAtom>,
}

/// Create the style from the words after `pair_style sdpd` for `ntypes` atom types; `*out` gets
/// a handle to release with [`dpdnl_sdpd_free`] (null on failure, the message says why).
///
/// # Safety
/// `arg` points to `narg` NUL-terminated strings; `out` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_new(
    narg: i32,
    arg: *const *const c_char,
    ntypes: i32,
    out: *mut *mut DpdnlSdpd,
) -> DpdnlStatus {
    guard(|| {
        if out.is_null() {
            return Err(Error::null("out"));
        }
        // SAFETY: valid for writing (checked non-null; caller's contract).
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: forwarded caller's contract.
        let w = unsafe { words(narg, arg)? };
        let style = grammar::sdpd::pair_style(&w).map_err(Error::invalid)?;
        let nt = usize::try_from(ntypes)
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| Error::invalid(format!("ntypes = {ntypes} must be >= 1")))?;
        let h = Box::new(DpdnlSdpd {
            field: SdpdField::new(style, nt),
            atoms: Vec::new(),
        });
        // SAFETY: as above.
        unsafe { put(out, Box::into_raw(h)) }
    })
}

/// Release a handle from [`dpdnl_sdpd_new`] (null is ignored).
///
/// # Safety
/// `h` is null or a live handle, not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_free(h: *mut DpdnlSdpd) {
    if !h.is_null() {
        // SAFETY: a pointer from Box::into_raw in dpdnl_sdpd_new, freed once (caller's contract).
        drop(unsafe { Box::from_raw(h) });
    }
}

/// The handle behind `h`.
///
/// # Safety
/// `h` is null or a live handle not used concurrently.
unsafe fn handle<'a>(h: *mut DpdnlSdpd) -> Result<&'a mut DpdnlSdpd, Error> {
    // SAFETY: caller's contract.
    unsafe { h.as_mut() }.ok_or_else(|| Error::null("sdpd handle"))
}

/// Apply one `pair_coeff` line of `sdpd` (all its words, types first).
///
/// # Safety
/// `h` is a live handle; `arg` points to `narg` NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_coeff(
    h: *mut DpdnlSdpd,
    narg: i32,
    arg: *const *const c_char,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, w) = unsafe { (handle(h)?, words(narg, arg)?) };
        let line = grammar::sdpd::pair_coeff(&w, h.field.ntypes(), &h.field.style)
            .map_err(Error::invalid)?;
        h.field.set_line(&line);
        Ok(())
    })
}

/// Whether type pair (i, j) has coefficients (1) or not (0), and its cut-off in `*rc`.
///
/// # Safety
/// `h` is a live handle; `rc` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_pair(
    h: *mut DpdnlSdpd,
    i: i32,
    j: i32,
    rc: *mut f64,
    set: *mut i32,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let nt = h.field.ntypes() as i32;
        if !(1..=nt).contains(&i) || !(1..=nt).contains(&j) {
            return Err(Error::invalid(format!("types {i} {j} outside 1..={nt}")));
        }
        let p = h.field.get(i as usize, j as usize).copied();
        // SAFETY: valid for writing (caller's contract).
        unsafe {
            put(rc, p.map_or(0.0, |p| p.rc))?;
            put(set, i32::from(p.is_some()))
        }
    })
}

/// Set-up of a run (`Pair::init_style`): every pair set, (η, Sc) targets resolved at number
/// density `density`, kernels and equations of state built for dimension `dim`, per-type masses
/// `mass[0..=ntypes]` (entry 0 unused) and step `dt`. `*rc_max` gets the largest cut-off;
/// [`crate::dpdnl_last_message`] holds the lines to log, one per line, warnings starting
/// with "WARNING: ".
///
/// # Safety
/// `h` is a live handle; `mass` holds `ntypes + 1` doubles; `rc_max` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_init(
    h: *mut DpdnlSdpd,
    dim: i32,
    density: f64,
    mass: *const f64,
    dt: f64,
    rc_max: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let nt = h.field.ntypes();
        // SAFETY: ntypes + 1 doubles (caller's contract).
        let m = unsafe { slice(mass, nt + 1, "mass")? };
        if dim != 2 && dim != 3 {
            return Err(Error::invalid(format!("dimension {dim} must be 2 or 3")));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid(format!("timestep {dt} must be > 0")));
        }
        if let Some((i, j)) = h.field.missing() {
            return Err(Error::invalid(format!(
                "pair coefficients for types {i} {j} are not set (pair_coeff)"
            )));
        }
        let masses: Vec<Option<f64>> = m
            .iter()
            .enumerate()
            .map(|(t, &x)| (t > 0).then_some(x))
            .collect();
        let notes = h
            .field
            .resolve(dim as u32, density, &masses, dt)
            .map_err(Error::invalid)?;
        // SAFETY: valid for writing (caller's contract).
        unsafe { put(rc_max, h.field.rc_max())? };
        set_last_message(&notes.join("\n"));
        Ok(())
    })
}

/// Positions (`3 nall`), types (`nall`), nlocal and nall of one rank's atoms.
type AtomViews<'a> = (&'a [f64], &'a [i32], usize, usize);

/// Checked views of the atoms' positions and types (`nall` entries).
///
/// # Safety
/// As [`DpdnlAtoms`].
unsafe fn positions_types<'a>(a: &DpdnlAtoms, nt: usize) -> Result<AtomViews<'a>, Error> {
    if a.nlocal < 0 || a.nall < a.nlocal {
        return Err(Error::invalid(format!(
            "nlocal = {} and nall = {} must satisfy 0 <= nlocal <= nall",
            a.nlocal, a.nall
        )));
    }
    let (nlocal, nall) = (a.nlocal as usize, a.nall as usize);
    // SAFETY: sizes as documented on DpdnlAtoms (caller's contract).
    let (x, ty) = unsafe {
        (
            slice(a.x, 3 * nall, "x")?,
            slice(a.atom_type, nall, "type")?,
        )
    };
    if let Some(bad) = ty.iter().position(|&t| t < 1 || t as usize > nt) {
        return Err(Error::invalid(format!(
            "atom {bad} has type {} outside 1..={nt}",
            ty[bad]
        )));
    }
    Ok((x, ty, nlocal, nall))
}

/// Pass 1: `rho[0..nall]` is overwritten with Σ_j W(r_ij) over the half list `list`, added to i
/// and to j (j owned, or any j when `newton_pair` is non-zero). Without the self term.
///
/// # Safety
/// `h` is a live handle; `atoms` and `list` as for `dpdnl_compute`; `rho` holds `nall` doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_density(
    h: *mut DpdnlSdpd,
    atoms: *const DpdnlAtoms,
    list: *const DpdnlNeighList,
    newton_pair: i32,
    rho: *mut f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a, list) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
                list.as_ref().ok_or_else(|| Error::null("list"))?,
            )
        };
        let nt = h.field.ntypes();
        // SAFETY: forwarded caller's contract.
        let (x, ty, nlocal, nall) = unsafe { positions_types(a, nt)? };
        // SAFETY: nall doubles (caller's contract).
        let rho = unsafe { slice_mut(rho, nall, "rho")? };
        rho.fill(0.0);
        if h.field.rcsq().len() != (nt + 1) * (nt + 1) {
            return Err(Error::invalid("dpdnl_sdpd_init has not run"));
        }
        let newton = newton_pair != 0;
        let rcsq = h.field.rcsq();
        // SAFETY: forwarded caller's contract.
        unsafe {
            for_each_row(list, nall, |i, jlist, mask| {
                let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
                let row = ty[i] as usize * (nt + 1);
                let mut di = 0.0;
                for &jraw in jlist {
                    let j = jraw as u32 as usize & mask;
                    let k = row + ty[j] as usize;
                    let dr = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
                    let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
                    if rsq < rcsq[k] {
                        let w = h.field.w_pair(k, rsq);
                        di += w;
                        if newton || j < nlocal {
                            rho[j] += w;
                        }
                    }
                }
                rho[i] += di;
                Ok(())
            })?
        };
        Ok(())
    })
}

/// Pass 1's end for the owned atoms: `rho[i] += W_ii(0)`, and the Tait energy Σ u(d_i) added to
/// `tally->eng_vdwl` (when `eflag_global`) and `tally->eatom[i]` (when not null). A non-finite
/// pressure is an error naming the atom's tag and density (`tag` may be null: the index is
/// named).
///
/// # Safety
/// `h` is a live handle; `atoms` as for `dpdnl_compute` (types and tags of the owned atoms are
/// read); `rho` holds `nlocal` doubles; `tally` is null or as for `dpdnl_compute`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_finish(
    h: *mut DpdnlSdpd,
    atoms: *const DpdnlAtoms,
    step: i64,
    rho: *mut f64,
    tally: *const DpdnlTally,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
            )
        };
        let nt = h.field.ntypes();
        // SAFETY: forwarded caller's contract.
        let (_, ty, nlocal, _) = unsafe { positions_types(a, nt)? };
        // SAFETY: nlocal entries (caller's contract).
        let (rho, tag) = unsafe {
            (
                slice_mut(rho, nlocal, "rho")?,
                if a.tag.is_null() {
                    &[][..]
                } else {
                    slice(a.tag, nlocal, "tag")?
                },
            )
        };
        // SAFETY: null or valid (caller's contract).
        let t = unsafe { tally.as_ref() }.copied();
        let mut energy = 0.0;
        // SAFETY: nall >= nlocal doubles when non-null (caller's contract).
        let mut eatom = match t {
            Some(t) if !t.eatom.is_null() => Some(unsafe { slice_mut(t.eatom, nlocal, "eatom")? }),
            _ => None,
        };
        for i in 0..nlocal {
            let ti = ty[i] as usize;
            let d = rho[i] + h.field.self_density(ti);
            rho[i] = d;
            let terms = h.field.atom_terms(ti, d);
            if !terms.pterm.is_finite() {
                let who = tag.get(i).map_or(format!("index {i}"), |t| t.to_string());
                return Err(Error::invalid(format!(
                    "sdpd at step {step}: the Tait pressure of atom {who} is not finite (number \
                     density d = {d}); reduce the time step or raise c0"
                )));
            }
            let u = h.field.atom_energy(ti, d);
            energy += u;
            if let Some(e) = eatom.as_deref_mut() {
                e[i] += u;
            }
        }
        if let Some(t) = t
            && t.eflag_global != 0
        {
            // SAFETY: valid for reading and writing when eflag_global (caller's contract).
            let e = unsafe { t.eng_vdwl.as_mut() }.ok_or_else(|| Error::null("eng_vdwl"))?;
            *e += energy;
        }
        Ok(())
    })
}

/// Pass 2: the pair forces of every listed pair from the densities `rho[0..nall]` (owned and
/// ghost atoms, ghosts communicated), accumulated into `f` and `tally` exactly as
/// `dpdnl_compute` does (the same list walk and `ev_tally` conventions).
///
/// # Safety
/// As `dpdnl_compute`; `h` is a live handle and `rho` holds `nall` doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_sdpd_compute(
    h: *mut DpdnlSdpd,
    atoms: *const DpdnlAtoms,
    list: *const DpdnlNeighList,
    step: *const DpdnlStep,
    rho: *const f64,
    f: *mut f64,
    tally: *mut DpdnlTally,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a, list, st) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
                list.as_ref().ok_or_else(|| Error::null("list"))?,
                step.as_ref().ok_or_else(|| Error::null("step"))?,
            )
        };
        let nt = h.field.ntypes();
        // SAFETY: forwarded caller's contract.
        let (_, ty, _, nall) = unsafe { positions_types(a, nt)? };
        // SAFETY: nall doubles (caller's contract).
        let rho = unsafe { slice(rho, nall, "rho")? };
        if h.field.rcsq().len() != (nt + 1) * (nt + 1) {
            return Err(Error::invalid("dpdnl_sdpd_init has not run"));
        }
        let mut terms = std::mem::take(&mut h.atoms);
        terms.clear();
        terms.extend(
            ty.iter()
                .zip(rho)
                .map(|(&t, &d)| h.field.atom_terms(t as usize, d)),
        );
        let cut: Vec<f64> = h.field.cut_table().iter().map(|c| c.rc).collect();
        let kernel = h.field.kernel_for(&terms);
        // SAFETY: null or valid (caller's contract).
        let t = unsafe { tally.as_ref() }.copied();
        // SAFETY: forwarded caller's contract.
        let r = unsafe { walk_pairs(&kernel, &cut, nt, a, list, st, f, t) };
        h.atoms = terms;
        r
    })
}
