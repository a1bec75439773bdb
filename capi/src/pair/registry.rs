//! The pair styles this library provides, by index: their names and LAMMPS's registration
//! lines.

use dpdnl::host::PAIR_STYLES;
use std::ffi::{CString, c_char};
use std::sync::OnceLock;

/// The styles' names and LAMMPS's one-line descriptions, as C strings that live as long as the
/// library.
fn style_names() -> &'static [(CString, CString)] {
    static NAMES: OnceLock<Vec<(CString, CString)>> = OnceLock::new();
    NAMES.get_or_init(|| {
        PAIR_STYLES
            .iter()
            .map(
                |&dpdnl::host::PairStyleEntry {
                     name, about: what, ..
                 }| {
                    let text = |s: String| CString::new(s).unwrap_or_default();
                    (
                        text(name.to_string()),
                        text(format!("pair_style {name} (dpdnl: {what})")),
                    )
                },
            )
            .collect()
    })
}

/// The number of pair styles this library provides (the C++ side registers each of them with
/// LAMMPS under [`dpdnl_pair_style_name`]).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_style_count() -> i32 {
    PAIR_STYLES.len() as i32
}

/// The name of pair style `k` (0-based), a static string; null when `k` is out of range.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_style_name(k: i32) -> *const c_char {
    usize::try_from(k)
        .ok()
        .and_then(|k| style_names().get(k))
        .map_or(std::ptr::null(), |(n, _)| n.as_ptr())
}

/// The line LAMMPS prints when pair style `k` is registered ("pair_style NAME (dpdnl: …)"), a
/// static string; null when `k` is out of range.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_style_info(k: i32) -> *const c_char {
    usize::try_from(k)
        .ok()
        .and_then(|k| style_names().get(k))
        .map_or(std::ptr::null(), |(_, i)| i.as_ptr())
}
