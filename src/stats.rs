//! Statistics helpers: placeholder until filled.
