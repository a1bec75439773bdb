//! One C handle for every pair style: an opaque [`DpdnlPair`] holds the style object of the
//! standalone engine (`dpdnl::PairStyle`: the same grammar, set-up, kernel and
//! restart lines), so a LAMMPS style forwards `narg/arg`, marshals arrays and does MPI, and
//! knows no coefficient, rule or equation of its own.
//!
//! One force evaluation:
//! - a style with a pre-pass ([`DpdnlPairInfo::values_per_atom`] = 1, e.g. `sdpd`'s density):
//!   [`dpdnl_pair_prepass`] sums over the half list into `values` (owned atoms, and ghosts with
//!   newton on; the C++ style then sums ghost parts into their owners, `reverse_comm`),
//!   [`dpdnl_pair_prepass_finish`] completes the owned atoms and tallies their energy, the
//!   style sends the owners' values to their ghosts (`forward_comm`);
//! - [`dpdnl_pair_compute`]: the pair forces through the style's kernel, the same list walk and
//!   `ev_tally` conventions (half list: newton on or off; full list: `ev_tally_full`).
// cbindgen writes the C declarations in the order in which it reads them: this file, then these
// modules in the order declared, which is the order of capi/include/dpdnl.h. One module per group,
// so that rustfmt keeps that order.
mod types;

mod registry;

mod handle;

mod init;

mod compute;

mod restart;

pub use compute::{
    dpdnl_pair_compute, dpdnl_pair_own_list, dpdnl_pair_prepass, dpdnl_pair_prepass_finish,
};
pub use handle::{
    dpdnl_pair_coeff, dpdnl_pair_cutoff, dpdnl_pair_free, dpdnl_pair_info, dpdnl_pair_launcher,
    dpdnl_pair_new, dpdnl_pair_settings, dpdnl_pair_threads,
};
pub use init::{dpdnl_pair_init, dpdnl_pair_list_choice, dpdnl_pair_special};
pub use registry::{
    DPDNL_PAIR_STYLE_SLOTS, DpdnlLammpsStyle, dpdnl_lammps_style, dpdnl_lammps_style_count,
    dpdnl_pair_style_count, dpdnl_pair_style_info, dpdnl_pair_style_name,
};
pub(crate) use restart::describe;
pub use restart::{
    dpdnl_pair_data, dpdnl_pair_from_restart, dpdnl_pair_restart, dpdnl_pair_single,
};
pub use types::{DpdnlPairInfo, DpdnlSetup, DpdnlUnits};

use crate::Error;
use crate::compute::Workers;
use crate::ownlist::OwnList;
use crate::styles::put;
use crate::team::DpdnlLaunch;
use crate::working::WorkingList;
use dpdnl::PairStyle;

/// A pair style and its coefficients (opaque to C).
pub struct DpdnlPair {
    style: Box<dyn PairStyle>,
    /// The special-bond factors of the last set-up.
    special: [f64; 4],
    /// The types of the atoms of the last [`dpdnl_pair_compute`] (scratch).
    typ: Vec<u32>,
    /// The text of the last [`dpdnl_pair_restart`].
    text: Vec<u8>,
    /// The threads of [`dpdnl_pair_compute`] when more than one ([`dpdnl_pair_threads`]).
    workers: Option<Workers>,
    /// The host's parallel launcher for those threads ([`dpdnl_pair_launcher`]).
    launch: DpdnlLaunch,
    /// The working copy of the LAMMPS list of [`dpdnl_pair_compute`].
    working: WorkingList,
    /// The pair list the style builds for itself ([`dpdnl_pair_own_list`]).
    own: OwnList,
    /// Whether the last set-up was for per-atom masses (`DpdnlSetup::per_atom_mass`).
    per_atom_mass: bool,
}

/// The handle behind `h`.
///
/// # Safety
/// `h` is null or a live handle not used concurrently.
unsafe fn handle<'a>(h: *mut DpdnlPair) -> Result<&'a mut DpdnlPair, Error> {
    // SAFETY: caller's contract.
    unsafe { h.as_mut() }.ok_or_else(|| Error::null("pair handle"))
}

/// A type count from C (at least 1: LAMMPS may define a pair style before its box).
fn type_count(ntypes: i32) -> usize {
    usize::try_from(ntypes).unwrap_or(0).max(1)
}

/// Words as owned strings.
fn owned(w: &[&str]) -> Vec<String> {
    w.iter().map(|s| s.to_string()).collect()
}

/// Write a new handle for `style` through `out` (null first, so a failure leaves null).
///
/// # Safety
/// `out` is null or valid for writing.
unsafe fn emit(out: *mut *mut DpdnlPair, style: Box<dyn PairStyle>) -> Result<(), Error> {
    let h = Box::new(DpdnlPair {
        style,
        special: [1.0; 4],
        typ: Vec::new(),
        text: Vec::new(),
        workers: None,
        launch: None,
        working: WorkingList::default(),
        own: OwnList::default(),
        per_atom_mass: false,
    });
    // SAFETY: forwarded caller's contract.
    unsafe { put(out, Box::into_raw(h)) }
}

/// Checked 1-based types of the style.
fn type_pair(h: &DpdnlPair, i: i32, j: i32) -> Result<(usize, usize), Error> {
    let nt = h.style.ntypes() as i32;
    if !(1..=nt).contains(&i) || !(1..=nt).contains(&j) {
        return Err(Error::invalid(format!("types {i} {j} outside 1..={nt}")));
    }
    Ok((i as usize, j as usize))
}
