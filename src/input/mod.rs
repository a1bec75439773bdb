//! placeholder
pub mod format;
pub mod expr;
