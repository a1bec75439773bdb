//! Init-time checks shared with the standalone engine (`dpdnl::init`), and the lines a set-up
//! leaves to log: the same numbers and the same log lines in both engines.

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

/// The lines to log left by the last successful [`crate::dpdnl_pair_init`] on this thread (""
/// when there is nothing to say; warnings start with "WARNING: "). Valid until the next such
/// call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_last_message() -> *const c_char {
    LAST_MESSAGE.with(|e| e.borrow().as_ptr())
}

/// The set-up box check of both engines (`dpdnl::host::check_box_images`): every periodic
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
        dpdnl::host::check_box_images(
            [len[0], len[1], len[2]],
            [per[0] != 0, per[1] != 0, per[2] != 0],
            usize::try_from(dimension).unwrap_or(0),
            rc_max,
        )
        .map_err(Error::invalid)
    })
}
