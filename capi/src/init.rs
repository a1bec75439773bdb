//! Init-time resolution shared with the standalone engine (`dpdnl::init`): the same numbers
//! and the same log lines in both engines.

use std::cell::RefCell;
use std::ffi::{CString, c_char};

use crate::{DpdnlStatus, Error, guard};

thread_local! {
    static LAST_MESSAGE: RefCell<CString> = RefCell::new(CString::default());
}

pub(crate) fn set_last_message(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_MESSAGE.with(|e| *e.borrow_mut() = text);
}

/// The line to log left by the last successful [`dpdnl_design_pair`], [`dpdnl_common_exponent`]
/// or [`dpdnl_euler_warning`] on this thread ("" when there is nothing to say). Valid until the
/// next such call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_last_message() -> *const c_char {
    LAST_MESSAGE.with(|e| e.borrow().as_ptr())
}

/// `pair_coeff I J a eta E sc S`: the `gamma0` and weight exponent s that give viscosity `eta`
/// and Schmidt number `sc` at number density `density` (N/V; per area in 2-D), cut-off `rc`,
/// mass `mass`, thermostat `kt` (exact kinetic-theory inversion, `dpdnl::init::resolve_design`).
/// On success `*gamma0` and `*s` are set and [`dpdnl_last_message`] holds the line to log.
///
/// # Safety
/// `gamma0` and `s` are null or valid for writing.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dpdnl_design_pair(
    itype: i32,
    jtype: i32,
    dimension: i32,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
    eta: f64,
    sc: f64,
    gamma0: *mut f64,
    s: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        if gamma0.is_null() {
            return Err(Error::null("gamma0"));
        }
        if s.is_null() {
            return Err(Error::null("s"));
        }
        let dim = u32::try_from(dimension)
            .map_err(|_| Error::invalid(format!("dimension {dimension} must be 2 or 3")))?;
        let label = format!("{itype} {jtype}");
        let r = dpdnl::init::resolve_design(&label, dim, density, rc, mass, kt, eta, sc)
            .map_err(Error::invalid)?;
        // SAFETY: both pointers are non-null and valid for writing by the caller's contract.
        unsafe {
            *gamma0 = r.gamma;
            *s = r.s;
        }
        set_last_message(&r.message);
        Ok(())
    })
}

/// The one weight exponent of `n` designed pairs (`itype[k] jtype[k]` needs `s[k]`): an error
/// if they differ (the exponent is global in the pair style). `current` is the pair style's
/// exponent; `*s_out` gets the common one (or `current` when `n` is 0), and
/// [`dpdnl_last_message`] says so when it replaces `current`.
///
/// # Safety
/// `itype`, `jtype` and `s` hold `n` entries (or are null when `n` is 0); `s_out` is valid for
/// writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_common_exponent(
    n: i32,
    itype: *const i32,
    jtype: *const i32,
    s: *const f64,
    current: f64,
    s_out: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        if s_out.is_null() {
            return Err(Error::null("s_out"));
        }
        let n = usize::try_from(n).map_err(|_| Error::invalid(format!("n = {n} < 0")))?;
        let mut designs = Vec::with_capacity(n);
        if n > 0 {
            if itype.is_null() || jtype.is_null() || s.is_null() {
                return Err(Error::null("itype, jtype or s"));
            }
            // SAFETY: non-null and holding n entries by the caller's contract.
            let (it, jt, sv) = unsafe {
                (
                    std::slice::from_raw_parts(itype, n),
                    std::slice::from_raw_parts(jtype, n),
                    std::slice::from_raw_parts(s, n),
                )
            };
            for k in 0..n {
                designs.push((format!("{} {}", it[k], jt[k]), sv[k]));
            }
        }
        let (value, note) = dpdnl::init::common_exponent("dpd/nonlinear", &designs, current)
            .map_err(Error::invalid)?
            .unwrap_or((current, None));
        // SAFETY: non-null and valid for writing by the caller's contract.
        unsafe { *s_out = value };
        set_last_message(note.as_deref().unwrap_or(""));
        Ok(())
    })
}

/// The Euler finite-step heating check of `dpdnl::init::euler_warning` (finite-step paper
/// eqs. 22 and 25): [`dpdnl_last_message`] holds the warning text, or "" when δt is small
/// enough. `gamma` is the largest `gamma0`, `mass` the lightest mass, `conservative` non-zero
/// when some pair has a ≠ 0, `nonlinear` non-zero for friction cross/dot.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn dpdnl_euler_warning(
    dimension: i32,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
    gamma: f64,
    s: f64,
    dt: f64,
    conservative: i32,
    nonlinear: i32,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        let dim = u32::try_from(dimension)
            .map_err(|_| Error::invalid(format!("dimension {dimension} must be 2 or 3")))?;
        let w = dpdnl::init::euler_warning(
            dim,
            density,
            rc,
            mass,
            kt,
            gamma,
            s,
            dt,
            conservative != 0,
            nonlinear != 0,
        )
        .map_err(Error::invalid)?;
        set_last_message(w.as_deref().unwrap_or(""));
        Ok(())
    })
}

/// The set-up box check of both engines (`dpdnl::init::check_box_images`): every periodic
/// dimension (`periodic[d]` nonzero, d < `dimension`) of the box `len` (3 doubles) must be at
/// least 2 `rc_max` long. Call it at every `init` and after every box change.
///
/// # Safety
/// `len` and `periodic` point to 3 values each.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_box_check(
    len: *const f64,
    periodic: *const i32,
    dimension: i32,
    rc_max: f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: 3 values each by the caller's contract.
        let (len, per) = unsafe {
            (
                crate::slice(len, 3, "len")?,
                crate::slice(periodic, 3, "periodic")?,
            )
        };
        dpdnl::init::check_box_images(
            [len[0], len[1], len[2]],
            [per[0] != 0, per[1] != 0, per[2] != 0],
            usize::try_from(dimension).unwrap_or(0),
            rc_max,
        )
        .map_err(Error::invalid)
    })
}
