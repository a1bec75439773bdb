//! `dpdnl-capi`: a C ABI over the `dpdnl` pair kernels, for the LAMMPS shim and other C/C++
//! callers. The header `capi/include/dpdnl.h` is generated from this file by cbindgen (the test
//! `tests/header.rs` fails when the committed header is stale; `DPDNL_BLESS_HEADER=1` rewrites it).
//!
//! # Contract
//! - Every function returns a [`DpdnlStatus`]; on failure a message is kept per thread and
//!   [`dpdnl_last_error`] returns it. No panic ever unwinds into the caller: every entry point runs
//!   inside `catch_unwind` and turns a panic into [`DpdnlStatus::Internal`].
//! - Parameters are validated here, once, with the core crate's own checks
//!   ([`PairCoeff::validate`], [`Weight::new`], [`Friction::from_keyword`], [`Noise::from_keyword`]);
//!   the kernels then trust them.
//! - [`dpdnl_compute`] walks a whole LAMMPS neighbour list in Rust: the hot loop never crosses the
//!   boundary per pair. Pairs in range are evaluated in batches of 64 by
//!   [`dpdnl::kernel::pair_forces_batch`] (SIMD lanes, the same bits as `pair_force`), and their
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

use dpdnl::{Friction, Noise, PairCoeff, PairInput, PairModel, Weight, pair_force, pair_gaussian};

mod compute;
mod init;
mod pair;
mod styles;
mod team;
mod working;
pub use compute::*;
pub use init::*;
pub use pair::*;
pub use styles::*;
pub use team::{DpdnlLaunch, DpdnlTeamBody};

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

/// The validated parameter table of `pair_style dpd/nonlinear` + `pair_coeff` (opaque to C).
pub struct DpdnlParams {
    kt: f64,
    seed: u32,
    friction: Friction,
    noise: Noise,
    weight: Weight,
    /// force × time / mass → velocity of the caller's units (1 until [`dpdnl_params_set_units`]).
    ftm2v: f64,
    ntypes: usize,
    /// `coeff[i * (ntypes + 1) + j]`, types 1-based; `None` until set.
    coeff: Vec<Option<PairCoeff>>,
}

/// The four force parts of one pair as projections on e_ij, plus the conservative energy and
/// 1/r (force on i = `(fc + fd + fr + fa) * inv_r * r_ij`). Mirrors `dpdnl::kernel::PairForce`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DpdnlPairForce {
    /// Conservative part.
    pub fc: f64,
    /// Dissipative part.
    pub fd: f64,
    /// Random part.
    pub fr: f64,
    /// Spurious-drift correction (`noise corrected` only).
    pub fa: f64,
    /// Conservative pair energy a r_c (1 − r/r_c)² / 2.
    pub energy: f64,
    /// 1/r (0 when the pair is outside the cut-off).
    pub inv_r: f64,
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

impl DpdnlParams {
    fn new(
        kt: f64,
        seed: i64,
        friction: &str,
        noise: &str,
        weight_s: f64,
        ntypes: i32,
    ) -> Result<DpdnlParams, Error> {
        if !(kt.is_finite() && kt > 0.0) {
            return Err(Error::invalid(format!(
                "temperature kT = {kt} must be a finite number > 0"
            )));
        }
        if !(1..=i64::from(i32::MAX)).contains(&seed) {
            return Err(Error::invalid(format!(
                "seed = {seed} must be an integer in 1..={}",
                i32::MAX
            )));
        }
        let friction = Friction::from_keyword(friction).ok_or_else(|| {
            Error::invalid(format!(
                "unknown friction '{friction}' (expected none, cross or dot)"
            ))
        })?;
        let noise = Noise::from_keyword(noise).ok_or_else(|| {
            Error::invalid(format!(
                "unknown noise '{noise}' (expected plain, corrected or twostep)"
            ))
        })?;
        let weight = Weight::new(weight_s).ok_or_else(|| {
            Error::invalid(format!(
                "weight exponent s = {weight_s} must be a finite number > 0"
            ))
        })?;
        if ntypes < 1 {
            return Err(Error::invalid(format!(
                "number of atom types = {ntypes} must be >= 1"
            )));
        }
        let ntypes = ntypes as usize;
        Ok(DpdnlParams {
            kt,
            seed: seed as u32,
            friction,
            noise,
            weight,
            ftm2v: 1.0,
            ntypes,
            coeff: vec![None; (ntypes + 1) * (ntypes + 1)],
        })
    }

    fn type_index(&self, t: i32, what: &str) -> Result<usize, Error> {
        if t < 1 || t as usize > self.ntypes {
            return Err(Error::invalid(format!(
                "{what} = {t} is not an atom type in 1..={}",
                self.ntypes
            )));
        }
        Ok(t as usize)
    }

    fn coeff(&self, i: i32, j: i32) -> Result<PairCoeff, Error> {
        let (i, j) = (self.type_index(i, "type I")?, self.type_index(j, "type J")?);
        self.coeff[i * (self.ntypes + 1) + j].ok_or_else(|| Error {
            status: DpdnlStatus::Incomplete,
            message: format!("pair coefficients for types {i} {j} are not set"),
        })
    }

    fn model(&self, dt: f64) -> Result<PairModel, Error> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid(format!(
                "time step dt = {dt} must be a finite number > 0"
            )));
        }
        Ok(
            PairModel::new(self.kt, self.friction, self.noise, self.weight, dt)
                .with_ftm2v(self.ftm2v),
        )
    }

    /// The dense table the hot loop reads; unset pairs get rc = 0 and never interact.
    fn dense_table(&self) -> Vec<PairCoeff> {
        let inert = PairCoeff {
            a: 0.0,
            gamma0: 0.0,
            gamma1: 0.0,
            rc: 0.0,
        };
        self.coeff.iter().map(|c| c.unwrap_or(inert)).collect()
    }
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

/// Create a parameter table: `pair_style dpd/nonlinear` settings for `ntypes` atom types.
/// `friction` is "none", "cross" or "dot"; `noise` is "plain", "corrected" or "twostep";
/// `kt > 0`, `1 <= seed <= 2^31 − 1`, `weight_s > 0`, `ntypes >= 1`. On success `*out` holds a
/// table to release with [`dpdnl_params_free`]; on failure `*out` is null.
///
/// # Safety
/// `friction` and `noise` are NUL-terminated strings; `out` is null or valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_new(
    kt: f64,
    seed: i64,
    friction: *const c_char,
    noise: *const c_char,
    weight_s: f64,
    ntypes: i32,
    out: *mut *mut DpdnlParams,
) -> DpdnlStatus {
    guard(|| {
        if out.is_null() {
            return Err(Error::null("out"));
        }
        // SAFETY: `out` is non-null and valid for writing by the caller's contract.
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: NUL-terminated strings by the caller's contract.
        let (friction, noise) = unsafe { (c_str(friction, "friction")?, c_str(noise, "noise")?) };
        let p = DpdnlParams::new(kt, seed, friction, noise, weight_s, ntypes)?;
        // SAFETY: as above.
        unsafe { *out = Box::into_raw(Box::new(p)) };
        Ok(())
    })
}

/// The caller's unit style (LAMMPS's constants, [`DpdnlUnits`]): the kernel's two-step kick
/// and the correction of `noise corrected` take its `ftm2v` (a table starts in `units lj`,
/// ftm2v = 1). The table's kT stays the energy given to [`dpdnl_params_new`] (this low-level
/// table takes kT, not the temperature T of the pair styles). Every constant must be finite and
/// > 0.
///
/// # Safety
/// `params` is null or a live table, not used concurrently; `units` is null or valid for
/// reading, its `style` a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_set_units(
    params: *mut DpdnlParams,
    units: *const DpdnlUnits,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live, unaliased table by the caller's contract.
        let p = unsafe { params.as_mut() }.ok_or_else(|| Error::null("params"))?;
        // SAFETY: null or valid for reading by the caller's contract.
        let u = unsafe { units.as_ref() }.ok_or_else(|| Error::null("units"))?;
        // SAFETY: forwarded caller's contract.
        p.ftm2v = unsafe { pair::units_of(u)? }.ftm2v;
        Ok(())
    })
}

/// Release a table from [`dpdnl_params_new`] (null is ignored).
///
/// # Safety
/// `params` is null or a pointer returned by `dpdnl_params_new` and not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_free(params: *mut DpdnlParams) {
    if params.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the pointer came from `Box::into_raw` in `dpdnl_params_new` (caller's contract).
        drop(unsafe { Box::from_raw(params) });
    }));
}

/// Check one set of pair coefficients without a table (`pair_coeff` argument validation):
/// finite a, gamma0 >= 0, gamma1 >= 0, rc > 0.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_coeff_check(a: f64, gamma0: f64, gamma1: f64, rc: f64) -> DpdnlStatus {
    guard(|| {
        PairCoeff {
            a,
            gamma0,
            gamma1,
            rc,
        }
        .validate()
        .map_err(Error::invalid)
    })
}

/// Set the coefficients of type pair (itype, jtype) and (jtype, itype); types are 1-based.
///
/// # Safety
/// `params` is null or a live table from [`dpdnl_params_new`], not used concurrently.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_set_coeff(
    params: *mut DpdnlParams,
    itype: i32,
    jtype: i32,
    a: f64,
    gamma0: f64,
    gamma1: f64,
    rc: f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live, unaliased table by the caller's contract.
        let p = unsafe { params.as_mut() }.ok_or_else(|| Error::null("params"))?;
        let (i, j) = (
            p.type_index(itype, "type I")?,
            p.type_index(jtype, "type J")?,
        );
        let c = PairCoeff {
            a,
            gamma0,
            gamma1,
            rc,
        };
        c.validate()
            .map_err(|m| Error::invalid(format!("types {i} {j}: {m}")))?;
        let n = p.ntypes + 1;
        p.coeff[i * n + j] = Some(c);
        p.coeff[j * n + i] = Some(c);
        Ok(())
    })
}

/// `Ok` if every type pair has coefficients, else `Incomplete` naming the first missing pair.
///
/// # Safety
/// `params` is null or a live table from [`dpdnl_params_new`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_check_complete(params: *const DpdnlParams) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live table by the caller's contract.
        let p = unsafe { params.as_ref() }.ok_or_else(|| Error::null("params"))?;
        for i in 1..=p.ntypes as i32 {
            for j in i..=p.ntypes as i32 {
                p.coeff(i, j)?;
            }
        }
        Ok(())
    })
}

/// ξ_ij, the standard Gaussian of pair (tag_i, tag_j) at `step` (`dpdnl::rng::pair_gaussian`;
/// symmetric in the tags).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_gaussian(seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
    catch_unwind(|| pair_gaussian(seed, step, tag_i, tag_j)).unwrap_or(f64::NAN)
}

/// One pair through the kernel (`dpdnl::kernel::pair_force`), for tests and `Pair::single`.
/// `dr` = r_i − r_j and `dv` = v_i − v_j (3 doubles each), `inv_mass_sum` = 1/m_i + 1/m_j,
/// `xi` the pair's Gaussian, `dt` > 0. Outside the cut-off every part is 0.
///
/// # Safety
/// `params` is null or a live table; `dr`, `dv` are null or point to 3 doubles; `out` is null or
/// valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_force(
    params: *const DpdnlParams,
    itype: i32,
    jtype: i32,
    dr: *const f64,
    dv: *const f64,
    inv_mass_sum: f64,
    xi: f64,
    dt: f64,
    out: *mut DpdnlPairForce,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live table by the caller's contract.
        let p = unsafe { params.as_ref() }.ok_or_else(|| Error::null("params"))?;
        // SAFETY: null or 3 doubles each by the caller's contract.
        let (dr, dv) = unsafe { (slice(dr, 3, "dr")?, slice(dv, 3, "dv")?) };
        // SAFETY: null or valid for writing by the caller's contract.
        let out = unsafe { out.as_mut() }.ok_or_else(|| Error::null("out"))?;
        let c = p.coeff(itype, jtype)?;
        let model = p.model(dt)?;
        let input = PairInput {
            dr: [dr[0], dr[1], dr[2]],
            dv: [dv[0], dv[1], dv[2]],
            inv_mass_sum,
            xi,
        };
        let f = pair_force(&model, &c, &input);
        *out = DpdnlPairForce {
            fc: f.fc,
            fd: f.fd,
            fr: f.fr,
            fa: f.fa,
            energy: f.energy,
            inv_r: f.inv_r,
        };
        Ok(())
    })
}
