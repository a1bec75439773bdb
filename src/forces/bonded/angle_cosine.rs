//! `angle_style cosine`: E = K (1 + cos θ); coefficient K (docs/models.md §4.9).

use super::{AngleForm, Form};

/// The cosine angle.
#[derive(Debug)]
pub(super) struct Cosine;

impl Form for Cosine {
    fn word(&self) -> &'static str {
        "cosine"
    }

    fn usage(&self) -> &'static str {
        "angle_coeff N K"
    }

    fn names(&self) -> &'static [&'static str] {
        &["K"]
    }
}

impl AngleForm for Cosine {
    #[inline]
    fn eval(&self, c: &[f64], cs: f64) -> (f64, f64) {
        (c[0], c[0] * (1.0 + cs))
    }
}
