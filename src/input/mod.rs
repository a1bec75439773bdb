//! The LAMMPS-input subset the standalone engine reads (see `docs/input.md`).
//!
//! - [`lexer`]: continuation lines, comments, quoted words;
//! - [`expr`]: equal-style variable formulas;
//! - [`format`]: C printf-style formats for thermo and dump output;
//! - [`observe`]: computes and time-averaging fixes (ave/time, ave/chunk, ave/histo);
//! - [`script`]: the interpreter that turns commands into engine state and runs it.
pub mod expr;
pub mod format;
pub mod lexer;
pub mod observe;
pub mod script;

pub use script::{Collect, Console, Interpreter, Options, PlannedRun, ScriptError};
