//! The style as restart text and back, its `write_data` coefficients, and LAMMPS's
//! `Pair::single`.

use super::{DpdnlPair, emit, handle, type_count, type_pair};
use crate::styles::put;
use crate::{DpdnlStatus, Error, guard, slice, slice_mut};
use dpdnl::host::from_restart_lines;
use std::ffi::c_char;

/// Separates the words of a line in the restart text.
const WORD_SEP: char = '\u{1f}';
/// The first line of the restart text.
const RESTART_MAGIC: &str = "dpdnl-pair-restart 1";

/// The style as restart text (its `restart_lines`: the `pair_style` line and, unless
/// `settings_only`, its `pair_coeff` lines): `*data` and `*len` get bytes valid until the next
/// call on `h`. [`dpdnl_pair_from_restart`] reads them back.
///
/// # Safety
/// `h` is a live handle; `data` and `len` are valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_restart(
    h: *mut DpdnlPair,
    settings_only: i32,
    data: *mut *const c_char,
    len: *mut i64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let mut lines = h.style.restart_lines();
        if settings_only != 0 {
            lines.truncate(1);
        }
        let mut text = String::from(RESTART_MAGIC);
        for l in &lines {
            text.push('\n');
            text.push_str(&l.join(&WORD_SEP.to_string()));
        }
        h.text = text.into_bytes();
        // SAFETY: valid for writing (caller's contract).
        unsafe {
            put(data, h.text.as_ptr().cast::<c_char>())?;
            put(len, h.text.len() as i64)
        }
    })
}

/// The style's name and its settings as text (its restart lines, one per line, words
/// separated by spaces): what a frame of `fix dpdnl/frames` records of the style.
///
/// # Safety
/// `h` is null or a live handle.
pub(crate) unsafe fn describe(h: *mut DpdnlPair) -> Result<(String, String), Error> {
    // SAFETY: forwarded caller's contract.
    let h = unsafe { handle(h)? };
    let lines: Vec<String> = h
        .style
        .restart_lines()
        .iter()
        .map(|l| l.join(" "))
        .collect();
    Ok((h.style.name().to_string(), lines.join("\n")))
}

/// A style from the text of [`dpdnl_pair_restart`] (`len` bytes at `data`) for `ntypes` types;
/// `*out` gets a new handle (null on failure: a corrupt or foreign text is named).
///
/// # Safety
/// `data` holds `len` bytes; `out` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_from_restart(
    data: *const c_char,
    len: i64,
    ntypes: i32,
    out: *mut *mut DpdnlPair,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        unsafe { put(out, std::ptr::null_mut())? };
        let n = usize::try_from(len)
            .map_err(|_| Error::invalid(format!("restart text length {len} < 0")))?;
        // SAFETY: `len` bytes (caller's contract).
        let bytes = unsafe { slice(data.cast::<u8>(), n, "data")? };
        let corrupt = |why: &str| Error::invalid(format!("corrupt pair style restart text: {why}"));
        let text = std::str::from_utf8(bytes).map_err(|_| corrupt("not UTF-8"))?;
        let mut it = text.split('\n');
        if it.next() != Some(RESTART_MAGIC) {
            return Err(corrupt("no 'dpdnl-pair-restart 1' header"));
        }
        let lines: Vec<Vec<String>> = it
            .map(|l| l.split(WORD_SEP).map(str::to_string).collect())
            .collect();
        let style = from_restart_lines(&lines, type_count(ntypes), 1.0).map_err(Error::invalid)?;
        // SAFETY: forwarded caller's contract.
        unsafe { emit(out, style) }
    })
}

/// The numbers of a `write_data` coefficient line of type pair (i, j): up to `cap` doubles into
/// `out`, their count in `*n` (0 when the style writes no data coefficients or the pair is not
/// set).
///
/// # Safety
/// `h` is a live handle; `out` holds `cap` doubles; `n` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_data(
    h: *mut DpdnlPair,
    i: i32,
    j: i32,
    out: *mut f64,
    cap: i32,
    n: *mut i32,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let (i, j) = type_pair(h, i, j)?;
        let v = h.style.data_coeffs(i, j).unwrap_or_default();
        let cap = usize::try_from(cap).unwrap_or(0);
        if v.len() > cap {
            return Err(Error::invalid(format!(
                "{} numbers do not fit in {cap}",
                v.len()
            )));
        }
        // SAFETY: `cap` doubles (caller's contract).
        let dst = unsafe { slice_mut(out, v.len(), "out")? };
        dst.copy_from_slice(&v);
        // SAFETY: valid for writing (caller's contract).
        unsafe { put(n, v.len() as i32) }
    })
}

/// LAMMPS's `Pair::single` for types (i, j) at distance² `rsq`: the conservative force F/r
/// into `*fforce` and the energy into the return slot `*energy`, both scaled by `factor`
/// (LAMMPS's special-bond factor, as `pair dpd` scales them). A style without a pair-wise
/// answer (many-body) is an error.
///
/// # Safety
/// `h` is a live handle; `fforce` and `energy` are valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_single(
    h: *mut DpdnlPair,
    i: i32,
    j: i32,
    rsq: f64,
    factor: f64,
    fforce: *mut f64,
    energy: *mut f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let (i, j) = type_pair(h, i, j)?;
        if h.style.cutoff(i, j).is_none() {
            return Err(Error::invalid(format!(
                "pair_style {} has no coefficients for types {i} {j} (single)",
                h.style.name()
            )));
        }
        let (fpair, e) = h.style.single(i, j, rsq).ok_or_else(|| {
            Error::invalid(format!("pair style {} has no single()", h.style.name()))
        })?;
        // SAFETY: valid for writing (caller's contract).
        unsafe {
            put(fforce, factor * fpair)?;
            put(energy, factor * e)
        }
    })
}
