//! The LAMMPS-input subset the standalone engine reads (see `docs/input.md`).
//!
//! - [`lexer`]: continuation lines, comments, quoted words;
//! - [`expr`]: equal-style variable formulas;
//! - [`format`]: C printf-style formats for thermo and dump output;
//! - [`observe`]: computes and time-averaging fixes (ave/time, ave/chunk, ave/histo), and the
//!   per-atom values of atom-style formulas; a directory, one file per kind: `compute`, `global`
//!   (values of `c_`, `f_`, `v_` references), `average` (schedule and averager), `fix` (what the
//!   fixes share), `ave_time`, `ave_chunk`, `ave_histo`, `per_atom`;
//! - [`script`]: the interpreter that turns commands into engine state and runs it; a directory,
//!   one file per command family: `mod.rs` (the interpreter, variables, dispatch), `setup`,
//!   `velocity`, `pair`, `fix`, `thermo`, `output` (dumps, print, log), `run`.
//!
//! The engine does not depend on this module: everything that evaluates the script language on
//! a system (formulas, computes, averaging) lives here.
pub mod expr;
pub mod format;
pub mod lexer;
pub mod observe;
pub mod script;

pub use script::{
    CARRIED, Collect, Console, FromState, Interpreter, Options, PlannedRun, ScriptError,
    StateReport, first_run_line, setup_groups,
};
