//! The C structs of the pair handle: what a style needs from its driver, the host's units, and
//! what a run's set-up knows.

use crate::{Error, c_str};
use std::ffi::c_char;

/// What a style needs from its C++ driver.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DpdnlPairInfo {
    /// Values per atom of the style's pre-pass (0: none; 1: one double per owned and ghost atom,
    /// communicated between the passes).
    pub values_per_atom: i32,
    /// 1 when [`dpdnl_pair_single`] answers (LAMMPS's `single_enable`).
    pub single: i32,
    /// 1 when [`dpdnl_pair_data`] answers (LAMMPS's `writedata`).
    pub data: i32,
}

/// The host's unit style and its conversion constants (LAMMPS: `update->unit_style`,
/// `force->boltz`, `force->mvv2e`, `force->ftm2v`, `force->nktv2p`, `force->mv2d`), so that no
/// constant is written in the host's code: T of the pair styles is a temperature (kT = boltz
/// T, as for LAMMPS's `pair_style dpd`), the two-step kick and the correction of `noise
/// corrected` take ftm2v, the theory's mass and sDPD's pressure mvv2e (`dpdnl::units`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlUnits {
    /// The unit style's name, NUL-terminated: one of LAMMPS's (lj real metal si cgs electron
    /// micro nano); null is an error.
    pub style: *const c_char,
    /// Boltzmann's constant in energy / temperature.
    pub boltz: f64,
    /// mass × velocity² → energy.
    pub mvv2e: f64,
    /// force × time / mass → velocity.
    pub ftm2v: f64,
    /// energy / volume → pressure.
    pub nktv2p: f64,
    /// mass / volume → mass density.
    pub mv2d: f64,
}

/// The checked [`dpdnl::Units`] of `u` (every constant finite and > 0, a LAMMPS unit style).
///
/// # Safety
/// `u.style` is null or a NUL-terminated string.
pub(crate) unsafe fn units_of(u: &DpdnlUnits) -> Result<dpdnl::Units, Error> {
    // SAFETY: forwarded caller's contract.
    let style = unsafe { c_str(u.style, "units.style")? };
    dpdnl::Units::from_host(style, u.boltz, u.mvv2e, u.ftm2v, u.nktv2p, u.mv2d)
        .map_err(Error::invalid)
}

/// What a run's set-up knows (LAMMPS's state at `init_style`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlSetup {
    /// 2 or 3.
    pub dimension: i32,
    /// Atoms in the whole system (LAMMPS `atom->natoms`).
    pub natoms: i64,
    /// Volume of the box (area in 2-D).
    pub volume: f64,
    /// Per-type masses, `ntypes + 1` doubles (entry 0 unused), or null (none: LAMMPS's
    /// `atom->mass`); not used when `per_atom_mass` is non-zero.
    pub mass: *const f64,
    /// Non-zero when the atom style has per-atom masses (LAMMPS's `atom->rmass_flag`): every
    /// evaluation then reads `DpdnlAtoms::rmass` (required non-null) and the per-type masses are
    /// not used, as in LAMMPS; zero: the per-type masses (`DpdnlAtoms::rmass` must be null).
    pub per_atom_mass: i32,
    /// Time step.
    pub dt: f64,
    /// Nonzero when a `fix nve/euler` is defined (the finite-step warning).
    pub euler: i32,
    /// LAMMPS's `special_bonds lj` factors (`force->special_lj`, 4 doubles: entry 0 unused,
    /// then 1-2, 1-3, 1-4), or null: no bonded neighbours.
    pub special_lj: *const f64,
    /// The unit style and its constants.
    pub units: DpdnlUnits,
    /// Nonzero when the style is a sub-style of the host's `pair_style hybrid` or
    /// `hybrid/overlay` (LAMMPS: `force->pair != this`): type pairs without coefficients then
    /// belong to other styles and get no interaction from this one; zero: the top-level style,
    /// every type pair must be set (`dpdnl::host::coverage`, the rule).
    pub substyle: i32,
}
