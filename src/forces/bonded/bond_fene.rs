//! `bond_style fene`: E = −½ K R0² ln(1 − (r/R0)²) + 4ε[(σ/r)¹² − (σ/r)⁶] + ε for
//! r < 2^(1/6) σ; coefficients K R0 ε σ, with LAMMPS's checks of a stretched bond
//! (docs/models.md §4.9).

use super::{BondFlag, BondForm, Form};

/// LAMMPS's 2^(1/3) (`MY_CUBEROOT2`): the WCA cut-off of `bond fene`, squared over σ².
const CUBEROOT2: f64 = 1.259_921_049_894_873_2;

/// The FENE bond with its WCA core.
#[derive(Debug)]
pub(super) struct Fene;

impl Form for Fene {
    fn word(&self) -> &'static str {
        "fene"
    }

    fn usage(&self) -> &'static str {
        "bond_coeff N K R0 epsilon sigma"
    }

    fn names(&self) -> &'static [&'static str] {
        &["K", "R0", "epsilon", "sigma"]
    }

    fn check(&self, c: &[f64]) -> Result<(), String> {
        if c[1] <= 0.0 {
            return Err(format!("bond fene: R0 = {} must be > 0", c[1]));
        }
        Ok(())
    }
}

impl BondForm for Fene {
    /// 1 − (r/R0)² below 0.1 is LAMMPS's "FENE bond too long" (warned, 0.1 used), at or below
    /// −3 its "Bad FENE bond" (an error).
    #[inline]
    fn eval(&self, c: &[f64], rsq: f64) -> (f64, f64, BondFlag) {
        let (k, r0, eps, sigma) = (c[0], c[1], c[2], c[3]);
        let r0sq = r0 * r0;
        let mut rlogarg = 1.0 - rsq / r0sq;
        let mut flag = BondFlag::Ok;
        if rlogarg < 0.1 {
            flag = if rlogarg <= -3.0 {
                BondFlag::Bad
            } else {
                BondFlag::TooLong
            };
            rlogarg = 0.1;
        }
        let mut fbond = -k / rlogarg;
        let mut e = -0.5 * k * r0sq * rlogarg.ln();
        if rsq < CUBEROOT2 * sigma * sigma {
            let sr2 = sigma * sigma / rsq;
            let sr6 = sr2 * sr2 * sr2;
            fbond += 48.0 * eps * sr6 * (sr6 - 0.5) / rsq;
            e += 4.0 * eps * sr6 * (sr6 - 1.0) + eps;
        }
        (fbond, e, flag)
    }

    /// LAMMPS's warning of `bond_style fene` with other factors than 0 1 1.
    fn special_warning(&self, lj: [f64; 4]) -> Option<&'static str> {
        (lj[1..] != [0.0, 1.0, 1.0]).then_some("Use special bonds = 0,1,1 with bond style fene")
    }
}
