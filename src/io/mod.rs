//! LAMMPS file formats: data files ([`data`]), text dumps ([`dump_read`]) and logs
//! ([`lammps_log`]); how the difference of two runs grows from the first step ([`growth`]); and
//! the standalone engine's own binary restart files ([`restart`]); the frames of `fix
//! dpdnl/frames` that `dpdnl verify` reads ([`frames`]).
//!
//! Every reader refuses non-finite numbers (`nan`, `inf`, `-inf`, and decimal literals beyond
//! the range of a double such as `1e999`) where it reads a value, naming the line and column
//! ([`finite_f64`]); the one exception is the thermo rows of a log, where LAMMPS itself prints
//! `nan`/`inf` after a blow-up (see [`lammps_log::parse_log`]).

pub mod data;
pub mod dump_read;
pub mod frames;
pub mod growth;
// The fields of the log's thermo blocks and comparison reports are their columns and counts,
// documented on each struct.
#[allow(missing_docs)]
pub mod lammps_log;
pub mod restart;

/// Why a token is not a finite number ([`finite_f64`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NumError {
    /// Not a number at all (`0.32x7`, `abc`).
    NotANumber,
    /// `nan`, `NaN`, `-nan`.
    NaN,
    /// `inf`, `-inf`, `infinity`.
    Infinite,
    /// A decimal literal whose value is beyond the largest double (`1e999`).
    Overflow,
}

impl NumError {
    /// What is wrong with `tok`, e.g. `'nan' is not a finite number (NaN is refused)`.
    pub(crate) fn describe(self, tok: &str) -> String {
        match self {
            NumError::NotANumber => format!("cannot read '{tok}' as a number"),
            NumError::NaN => format!("'{tok}' is not a finite number (NaN is refused)"),
            NumError::Infinite => {
                format!("'{tok}' is not a finite number (an infinity is refused)")
            }
            NumError::Overflow => format!(
                "'{tok}' is not a finite number (it is beyond the range of a double, about \
                 1.8e308)"
            ),
        }
    }
}

/// Reads `tok` as a finite `f64` (Rust's `f64` parser accepts `nan`, `inf` and overflowing
/// literals as non-finite values; this refuses them).
pub(crate) fn finite_f64(tok: &str) -> Result<f64, NumError> {
    match tok.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) if v.is_nan() => Err(NumError::NaN),
        Ok(_) if spelled_infinity(tok) => Err(NumError::Infinite),
        Ok(_) => Err(NumError::Overflow),
        Err(_) => Err(NumError::NotANumber),
    }
}

/// `inf`, `-Inf`, `+infinity`, …: an infinity written as a word rather than an overflowing
/// decimal literal.
pub(crate) fn spelled_infinity(tok: &str) -> bool {
    tok.trim_start_matches(['+', '-'])
        .get(..3)
        .is_some_and(|s| s.eq_ignore_ascii_case("inf"))
}
