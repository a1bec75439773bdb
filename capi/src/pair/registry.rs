//! The LAMMPS styles this library provides: every pair style, by index (their names and
//! LAMMPS's registration lines), and the fixes and computes whose classes the C++ side holds.
//! The C++ side registers exactly these names (lammps-plugin/src/dpdnl_styles.cpp) and stops
//! LAMMPS at load when its classes and this list disagree.

use dpdnl::host::PAIR_STYLES;
use std::ffi::{CString, c_char};
use std::sync::OnceLock;

/// How many pair styles the C++ side can register: the size of its table of creators (LAMMPS's
/// creator takes no name, so each style needs a function of its own). The build fails when the
/// registry outgrows it; the C++ side fails at load when the library it links lists more.
pub const DPDNL_PAIR_STYLE_SLOTS: i32 = 64;

const _: () = assert!(
    PAIR_STYLES.len() <= DPDNL_PAIR_STYLE_SLOTS as usize,
    "more pair styles than DPDNL_PAIR_STYLE_SLOTS: raise it (capi/src/pair/registry.rs)"
);

/// The fix and compute styles of the LAMMPS side, beside the pair styles: (command, name, what
/// LAMMPS prints on registering it).
const LAMMPS_STYLES: &[(&str, &str, &str)] = &[
    ("fix", "nve/euler", "explicit Euler"),
    ("fix", "pex/push", "PeX momentum exchange"),
    (
        "fix",
        "flip/momentum",
        "remap v's velocity jump at box flips",
    ),
    ("compute", "sdpd/density", "sDPD number densities"),
    (
        "fix",
        "dpdnl/frames",
        "frames of a dpdnl pair style for dpdnl verify",
    ),
];

/// A C string that lives as long as the library.
fn text(s: String) -> CString {
    CString::new(s).unwrap_or_default()
}

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

/// A fix or compute style of the LAMMPS side ([`dpdnl_lammps_style`]); static strings, all null
/// past the end of the list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlLammpsStyle {
    /// LAMMPS's kind of style: "fix" or "compute".
    pub command: *const c_char,
    /// The style's name in input scripts.
    pub name: *const c_char,
    /// The line LAMMPS prints when it is registered ("fix NAME (dpdnl: …)").
    pub info: *const c_char,
}

/// The fix and compute entries as C strings (command, name, info).
fn lammps_styles() -> &'static [(CString, CString, CString)] {
    static STYLES: OnceLock<Vec<(CString, CString, CString)>> = OnceLock::new();
    STYLES.get_or_init(|| {
        LAMMPS_STYLES
            .iter()
            .map(|&(command, name, what)| {
                (
                    text(command.to_string()),
                    text(name.to_string()),
                    text(format!("{command} {name} (dpdnl: {what})")),
                )
            })
            .collect()
    })
}

/// The number of fix and compute styles the LAMMPS side registers beside the pair styles.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_lammps_style_count() -> i32 {
    LAMMPS_STYLES.len() as i32
}

/// Fix or compute style `k` (0-based) of the LAMMPS side; every field null when `k` is out of
/// range.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_lammps_style(k: i32) -> DpdnlLammpsStyle {
    let entry = usize::try_from(k).ok().and_then(|k| lammps_styles().get(k));
    match entry {
        Some((command, name, info)) => DpdnlLammpsStyle {
            command: command.as_ptr(),
            name: name.as_ptr(),
            info: info.as_ptr(),
        },
        None => DpdnlLammpsStyle {
            command: std::ptr::null(),
            name: std::ptr::null(),
            info: std::ptr::null(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_fix_has_a_grammar_and_names_are_unique() {
        let mut seen = std::collections::BTreeSet::new();
        for &(command, name, _) in LAMMPS_STYLES {
            assert!(["fix", "compute"].contains(&command), "{command} {name}");
            assert!(
                seen.insert((command, name)),
                "{command} {name} listed twice"
            );
            if command == "fix" {
                assert!(dpdnl::forces::spec("fix", name).is_some(), "fix {name}");
            }
        }
    }
}
