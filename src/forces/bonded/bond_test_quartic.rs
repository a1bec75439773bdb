//! `bond_style test/quartic` (cargo feature `test-style` only): E = K (r − r0)⁴; coefficients
//! K r0. A test-only form: it shows that a new bond style is this file and its two lines in
//! `mod.rs` (tests/new_style.rs).

use super::{BondFlag, BondForm, Form};

/// The quartic bond.
#[derive(Debug)]
pub(super) struct Quartic;

impl Form for Quartic {
    fn word(&self) -> &'static str {
        "test/quartic"
    }

    fn usage(&self) -> &'static str {
        "bond_coeff N K r0"
    }

    fn names(&self) -> &'static [&'static str] {
        &["K", "r0"]
    }
}

impl BondForm for Quartic {
    fn eval(&self, c: &[f64], rsq: f64) -> (f64, f64, BondFlag) {
        let r = rsq.sqrt();
        let dr = r - c[1];
        let fbond = if r > 0.0 {
            -4.0 * c[0] * dr.powi(3) / r
        } else {
            0.0
        };
        (fbond, c[0] * dr.powi(4), BondFlag::Ok)
    }
}
