//! Helpers shared by the C ABI's test crates: a pair handle made, given coefficients and set
//! up through the C functions the LAMMPS styles call, and the thread's messages.

use std::ffi::{CStr, CString, c_char};
use std::ptr::{null, null_mut};

use dpdnl_capi::*;

/// The time step of every set-up made here.
pub const SETUP_DT: f64 = 0.01;

#[allow(dead_code)] // not every test crate uses every helper
pub fn last_error() -> String {
    // SAFETY: a valid NUL-terminated string owned by this thread.
    unsafe { CStr::from_ptr(dpdnl_last_error()) }
        .to_string_lossy()
        .into_owned()
}

#[allow(dead_code)] // not every test crate uses every helper
pub fn last_message() -> String {
    // SAFETY: a valid NUL-terminated string owned by this thread.
    unsafe { CStr::from_ptr(dpdnl_last_message()) }
        .to_string_lossy()
        .into_owned()
}

#[allow(dead_code)] // not every test crate uses every helper
#[derive(Debug)]
pub struct Handle(pub *mut DpdnlPair);

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: a handle from dpdnl_pair_new / _from_restart, freed once.
        unsafe { dpdnl_pair_free(self.0) };
    }
}

#[allow(dead_code)] // not every test crate uses every helper
pub fn cwords(words: &[&str]) -> (Vec<CString>, Vec<*const c_char>) {
    let c: Vec<CString> = words.iter().map(|w| CString::new(*w).unwrap()).collect();
    let p = c.iter().map(|s| s.as_ptr()).collect();
    (c, p)
}

#[allow(dead_code)] // not every test crate uses every helper
pub fn new_style(name: &str, words: &[&str], ntypes: i32) -> Result<Handle, String> {
    let n = CString::new(name).unwrap();
    let (_c, p) = cwords(words);
    let mut h = null_mut();
    // SAFETY: valid strings that outlive the call; `h` is valid for writing.
    let st = unsafe { dpdnl_pair_new(n.as_ptr(), p.len() as i32, p.as_ptr(), ntypes, &mut h) };
    if st != DpdnlStatus::Ok {
        assert!(h.is_null());
        return Err(last_error());
    }
    Ok(Handle(h))
}

#[allow(dead_code)] // not every test crate uses every helper
pub fn coeff(h: &Handle, ntypes: i32, words: &[&str]) -> Result<(), String> {
    let (_c, p) = cwords(words);
    // SAFETY: a live handle; valid strings.
    let st = unsafe { dpdnl_pair_coeff(h.0, ntypes, p.len() as i32, p.as_ptr()) };
    if st == DpdnlStatus::Ok {
        Ok(())
    } else {
        Err(last_error())
    }
}

#[allow(dead_code)] // not every test crate uses every helper
pub const MASS: [f64; 3] = [0.0, 1.0, 2.5];

/// LAMMPS's `units lj` as the styles pass it.
#[allow(dead_code)] // not every test crate uses every helper
pub fn lj_units() -> DpdnlUnits {
    DpdnlUnits {
        style: c"lj".as_ptr(),
        boltz: 1.0,
        mvv2e: 1.0,
        ftm2v: 1.0,
        nktv2p: 1.0,
        mv2d: 1.0,
    }
}

#[allow(dead_code)] // not every test crate uses every helper
pub fn init(h: &Handle, natoms: i64, volume: f64) -> Result<f64, String> {
    init_in(h, natoms, volume, lj_units())
}

/// LAMMPS's `units real` as the styles pass it (`force->boltz`, …).
#[allow(dead_code)] // not every test crate uses every helper
pub fn real_units() -> DpdnlUnits {
    let u = dpdnl::Units::REAL;
    DpdnlUnits {
        style: c"real".as_ptr(),
        boltz: u.boltz,
        mvv2e: u.mvv2e,
        ftm2v: u.ftm2v,
        nktv2p: u.nktv2p,
        mv2d: u.mv2d,
    }
}

/// [`init`] in the host's unit style `units`.
#[allow(dead_code)] // not every test crate uses every helper
pub fn init_in(h: &Handle, natoms: i64, volume: f64, units: DpdnlUnits) -> Result<f64, String> {
    init_as(h, natoms, volume, units, 0)
}

/// [`init`] as the top-level style (`substyle` 0) or as a sub-style of `pair_style hybrid` (1).
#[allow(dead_code)] // not every test crate uses every helper
pub fn init_as(
    h: &Handle,
    natoms: i64,
    volume: f64,
    units: DpdnlUnits,
    substyle: i32,
) -> Result<f64, String> {
    let s = DpdnlSetup {
        dimension: 3,
        natoms,
        volume,
        mass: MASS.as_ptr(),
        dt: SETUP_DT,
        euler: 0,
        special_lj: null(),
        units,
        substyle,
        per_atom_mass: 0,
    };
    init_with(h, &s)
}

/// `dpdnl_pair_init` of `h` with set-up `s`: the largest cut-off, or the thread's error.
#[allow(dead_code)] // not every test crate uses every helper
pub fn init_with(h: &Handle, s: &DpdnlSetup) -> Result<f64, String> {
    let mut rc = 0.0;
    // SAFETY: a live handle; `s` (its pointers valid for the call) and `rc` valid.
    let st = unsafe { dpdnl_pair_init(h.0, s, &mut rc) };
    if st == DpdnlStatus::Ok {
        Ok(rc)
    } else {
        Err(last_error())
    }
}
