//! `angle_style test/square` (cargo feature `test-style` only): E = K (1 − cos θ)²;
//! coefficient K. A test-only form: it shows that a new angle style is this file and its two
//! lines in `mod.rs` (tests/new_style.rs).

use super::{AngleForm, Form};

/// The squared-cosine angle.
#[derive(Debug)]
pub(super) struct Square;

impl Form for Square {
    fn word(&self) -> &'static str {
        "test/square"
    }

    fn usage(&self) -> &'static str {
        "angle_coeff N K"
    }

    fn names(&self) -> &'static [&'static str] {
        &["K"]
    }
}

impl AngleForm for Square {
    /// a = dE/d(cos θ) = −2 K (1 − cos θ).
    fn eval(&self, c: &[f64], cs: f64) -> (f64, f64) {
        let u = 1.0 - cs;
        (-2.0 * c[0] * u, c[0] * u * u)
    }
}
