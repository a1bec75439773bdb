//! `dpdnl-capi`: a C ABI over the `dpdnl` pair kernels, for the LAMMPS shim and other C/C++
//! callers. The header `capi/include/dpdnl.h` is generated from this file by cbindgen (the test
//! `tests/header.rs` fails when the committed header is stale; `DPDNL_BLESS_HEADER=1` rewrites it).
//!
//! # Contract
//! - Every function returns a [`DpdnlStatus`]; on failure a message is kept per thread and
//!   [`dpdnl_last_error`] returns it. No panic ever unwinds into the caller: every entry point runs
//!   inside `catch_unwind` and turns a panic into [`DpdnlStatus::Internal`].
//! - Arguments are validated once, by the core crate's own grammar and set-up (the pair
//!   handle, [`dpdnl_pair_new`], parses LAMMPS's own words); the kernels then trust them.
//! - [`dpdnl_pair_compute`] walks a whole LAMMPS neighbour list in Rust: the hot loop never crosses the
//!   boundary per pair. Pairs in range are evaluated in batches of 64 by
//!   [`dpdnl::pair_forces_batch`] (SIMD lanes, the same bits as `pair_force`), and their
//!   forces and tallies are added in list order, so the result is that of the pair-by-pair loop.
//!   Forces, energy and virial follow LAMMPS's `ev_tally` (half list, newton on/off) and
//!   `ev_tally_full` (full list) conventions.
//! - The pair random number is [`dpdnl::rng::pair_gaussian`] keyed by (seed, step, tags), so every
//!   decomposition (MPI ranks, newton on/off) draws the same ξ_ij for the same pair and step.

#![warn(unreachable_pub)]
#![warn(missing_docs)]

use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

use dpdnl::pair_gaussian;

mod compute;
mod frames;
mod init;
mod list;
mod ownlist;
mod pair;
mod styles;
mod team;
mod types;
mod working;
pub use compute::*;
pub use frames::*;
pub use init::*;
pub use list::DpdnlNeighList;
pub use ownlist::DpdnlSpecial;
pub use pair::*;
pub use styles::*;
pub use team::{DpdnlLaunch, DpdnlTeamBody};
pub use types::*;

/// Result of every fallible call. Anything but `Ok` leaves a message for [`dpdnl_last_error`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DpdnlStatus {
    /// Success.
    Ok = 0,
    /// A required pointer was null.
    NullPointer = 1,
    /// An argument is out of range or malformed (the message names it).
    InvalidArgument = 2,
    /// A type pair has no coefficients (the message names the first one).
    Incomplete = 3,
    /// A bug inside the library (a caught panic); the message says where.
    Internal = 4,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

struct Error {
    status: DpdnlStatus,
    message: String,
}

impl Error {
    fn invalid(message: impl Into<String>) -> Error {
        Error {
            status: DpdnlStatus::InvalidArgument,
            message: message.into(),
        }
    }
    fn null(what: &str) -> Error {
        Error {
            status: DpdnlStatus::NullPointer,
            message: format!("{what} is a null pointer"),
        }
    }
}

fn set_last_error(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

/// Run one entry point: clear the message, catch any panic, turn errors into codes and text.
fn guard(f: impl FnOnce() -> Result<(), Error>) -> DpdnlStatus {
    set_last_error("");
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => DpdnlStatus::Ok,
        Ok(Err(e)) => {
            set_last_error(&e.message);
            e.status
        }
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            set_last_error(&format!("internal error in dpdnl (a bug): {what}"));
            DpdnlStatus::Internal
        }
    }
}

/// Read a C string argument.
///
/// # Safety
/// `p` is null or points to a NUL-terminated string valid for the call.
unsafe fn c_str<'a>(p: *const c_char, what: &str) -> Result<&'a str, Error> {
    if p.is_null() {
        return Err(Error::null(what));
    }
    // SAFETY: non-null and NUL-terminated by the caller's contract.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map_err(|_| Error::invalid(format!("{what} is not valid UTF-8")))
}

/// A shared slice from a C pointer and a length; a null pointer is accepted only when `len == 0`.
///
/// # Safety
/// If `len > 0`, `p` points to `len` initialised `T`s valid (and not mutated) for `'a`.
unsafe fn slice<'a, T>(p: *const T, len: usize, what: &str) -> Result<&'a [T], Error> {
    if len == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(Error::null(what));
    }
    // SAFETY: non-null, `len` valid elements by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

/// A mutable slice from a C pointer and a length; null accepted only when `len == 0`.
///
/// # Safety
/// If `len > 0`, `p` points to `len` initialised `T`s, valid and not aliased for `'a`.
unsafe fn slice_mut<'a, T>(p: *mut T, len: usize, what: &str) -> Result<&'a mut [T], Error> {
    if len == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(Error::null(what));
    }
    // SAFETY: non-null, `len` valid, unaliased elements by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

/// The library version (a static NUL-terminated string).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_version() -> *const c_char {
    c"dpdnl-capi 0.1.0".as_ptr()
}

/// The message of the last failed call on this thread ("" after a success). The pointer stays
/// valid until the next `dpdnl_*` call on the same thread.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// ξ_ij, the standard Gaussian of pair (tag_i, tag_j) at `step` (`dpdnl::rng::pair_gaussian`;
/// symmetric in the tags).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_gaussian(seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
    catch_unwind(|| pair_gaussian(seed, step, tag_i, tag_j)).unwrap_or(f64::NAN)
}
