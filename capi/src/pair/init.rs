//! A run's set-up (`Pair::init_style`) and the special-bond factors given before each
//! evaluation.

use super::types::units_of;
use super::{DpdnlPair, DpdnlSetup, handle};
use crate::init::set_last_message;
use crate::styles::put;
use crate::{DpdnlStatus, Error, guard, slice};
use dpdnl::SetupContext;
use dpdnl::StyleDerived;
use dpdnl::host::SetupNote;
use dpdnl::host::check_special;

/// A set-up error as LAMMPS users meet it: a type pair without coefficients in the top-level
/// style is most often meant for another style, which `pair_style hybrid` provides.
fn lammps_hint(e: String) -> String {
    if e.contains("are not set (pair_coeff)") {
        format!(
            "{e}; as the top-level pair style this style needs coefficients for every type pair \
             (under pair_style hybrid or hybrid/overlay it may take some type pairs only, the \
             others going to other styles)"
        )
    } else {
        e
    }
}

/// Set-up of a run (`Pair::init_style`): every pair set (as a sub-style, `setup.substyle`,
/// the pairs with coefficients only; the others get no interaction and `*rc_max` is over the
/// style's own pairs), kT = boltz T in the host's units,
/// (η, Sc) targets resolved at the current density, the per-run tables built, the Euler
/// warning. `*rc_max` gets the largest cut-off; [`crate::dpdnl_last_message`] holds the lines
/// to log, one per line, warnings starting with "WARNING: ".
///
/// # Safety
/// `h` is a live handle; `setup` is valid for reading (its `mass` null or `ntypes + 1`
/// doubles, read only when `per_atom_mass` is 0; its `units.style` a NUL-terminated string); `rc_max` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_init(
    h: *mut DpdnlPair,
    setup: *const DpdnlSetup,
    rc_max: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, s) = unsafe {
            (
                handle(h)?,
                setup.as_ref().ok_or_else(|| Error::null("setup"))?,
            )
        };
        let nt = h.style.ntypes();
        let dim = match s.dimension {
            2 => 2,
            3 => 3,
            d => return Err(Error::invalid(format!("dimension {d} must be 2 or 3"))),
        };
        if !(s.dt.is_finite() && s.dt > 0.0) {
            return Err(Error::invalid(format!("timestep {} must be > 0", s.dt)));
        }
        // SAFETY: forwarded caller's contract.
        let units = unsafe { units_of(&s.units)? };
        // Per-atom masses where the atom style has them (the choice of every evaluation:
        // `crate::compute::atom_masses`), else per-type ones.
        let per_atom = s.per_atom_mass != 0;
        let mass: Vec<Option<f64>> = if per_atom || s.mass.is_null() {
            vec![None; nt + 1]
        } else {
            // SAFETY: ntypes + 1 doubles (caller's contract).
            let m = unsafe { slice(s.mass, nt + 1, "mass")? };
            m.iter()
                .enumerate()
                .map(|(t, &x)| (t > 0).then_some(x))
                .collect()
        };
        let natoms = usize::try_from(s.natoms).unwrap_or(0);
        let special = if s.special_lj.is_null() {
            [1.0; 4]
        } else {
            // SAFETY: 4 doubles (caller's contract).
            let f = unsafe { slice(s.special_lj, 4, "special_lj")? };
            [1.0, f[1], f[2], f[3]]
        };
        check_special(&*h.style, special).map_err(Error::invalid)?;
        h.special = special;
        let ctx = SetupContext {
            dim,
            natoms,
            density: s.natoms as f64 / s.volume,
            mass: &mass,
            dt: s.dt,
            euler: s.euler != 0,
            special_lj: special,
            units,
            substyle: s.substyle != 0,
            per_atom_mass: per_atom,
        };
        let notes = h
            .style
            .setup(&ctx)
            .map_err(|e| Error::invalid(lammps_hint(e)))?;
        h.per_atom_mass = per_atom;
        let mut text: Vec<String> = notes
            .into_iter()
            .map(|n| match n {
                SetupNote::Info(t) => t,
                SetupNote::Warning(t) => format!("WARNING: {t}"),
            })
            .collect();
        if let Some(w) = &h.workers {
            text.push(format!(
                "pair_style {}: {} threads per MPI task, {} (the same bits for every count)",
                h.style.name(),
                w.threads(),
                if w.on_host_threads() {
                    "on the host's threads (LAMMPS: its OpenMP threads)"
                } else {
                    "on dpdnl's own thread pool"
                }
            ));
        }
        // SAFETY: valid for writing (caller's contract).
        unsafe { put(rc_max, h.style.rc_max())? };
        set_last_message(&text.join("\n"));
        Ok(())
    })
}

/// The special-bond factors in force for the next [`dpdnl_pair_compute`] (LAMMPS's
/// `force->special_lj`, 4 doubles: entry 0 unused, then 1-2, 1-3, 1-4), given before every
/// evaluation: under `pair_style hybrid`, `pair_modify pair NAME special lj …` sets a sub-style's
/// own factors only around its evaluation, after its set-up. Factors equal to the last ones
/// change nothing; others are checked as at set-up (`check_special`) and the style's scaled
/// coefficient blocks rebuilt.
///
/// # Safety
/// `h` is a live handle; `special_lj` is null (no change) or holds 4 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_special(
    h: *mut DpdnlPair,
    special_lj: *const f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        if special_lj.is_null() {
            return Ok(());
        }
        // SAFETY: 4 doubles (caller's contract).
        let f = unsafe { slice(special_lj, 4, "special_lj")? };
        let special = [1.0, f[1], f[2], f[3]];
        if special != h.special {
            check_special(&*h.style, special).map_err(Error::invalid)?;
            h.style.set_special(special);
            h.special = special;
        }
        Ok(())
    })
}

/// Whether the style builds its own pair list ([`crate::dpdnl_pair_own_list`]) or walks the
/// half list it asks LAMMPS for: `*own` gets 1 for its own list, 0 for LAMMPS's. LAMMPS's list
/// is kept where it does something the own list does not: under `pair_style hybrid` or
/// `hybrid/overlay` (`substyle` non-zero; PairHybrid turns the request into a list of this
/// style's type pairs) and with `neigh_modify exclude` (`exclude` non-zero). The environment
/// variable `DPDNL_PAIR_LIST` chooses otherwise: `lammps` walks LAMMPS's list always (the
/// former path, kept for one release as the A/B switch), `own` (or unset) as above; any other
/// value is an error.
///
/// # Safety
/// `own` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_list_choice(
    substyle: i32,
    exclude: i32,
    own: *mut i32,
) -> DpdnlStatus {
    guard(|| {
        let wanted = match std::env::var("DPDNL_PAIR_LIST") {
            Err(std::env::VarError::NotPresent) => true,
            Ok(v) if v == "own" => true,
            Ok(v) if v == "lammps" => false,
            Ok(v) => {
                return Err(Error::invalid(format!(
                    "DPDNL_PAIR_LIST = '{v}': expected 'own' (the style builds its pair list, \
                     the default) or 'lammps' (it walks LAMMPS's list)"
                )));
            }
            Err(e) => return Err(Error::invalid(format!("DPDNL_PAIR_LIST: {e}"))),
        };
        let choice = wanted && substyle == 0 && exclude == 0;
        // SAFETY: forwarded caller's contract.
        unsafe { put(own, i32::from(choice)) }
    })
}
