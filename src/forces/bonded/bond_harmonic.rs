//! `bond_style harmonic`: E = K (r − r0)² (no ½, as LAMMPS); coefficients K r0
//! (docs/models.md §4.9).

use super::{BondFlag, BondForm, Form};

/// The harmonic bond.
#[derive(Debug)]
pub(super) struct Harmonic;

impl Form for Harmonic {
    fn word(&self) -> &'static str {
        "harmonic"
    }

    fn usage(&self) -> &'static str {
        "bond_coeff N K r0"
    }

    fn names(&self) -> &'static [&'static str] {
        &["K", "r0"]
    }
}

impl BondForm for Harmonic {
    #[inline]
    fn eval(&self, c: &[f64], rsq: f64) -> (f64, f64, BondFlag) {
        let r = rsq.sqrt();
        let dr = r - c[1];
        let rk = c[0] * dr;
        let fbond = if r > 0.0 { -2.0 * rk / r } else { 0.0 };
        (fbond, rk * dr, BondFlag::Ok)
    }
}
