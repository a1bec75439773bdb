//! `angle_style harmonic`: E = K (θ − θ0)²; coefficients K θ0 (θ0 in degrees, turned into
//! radians as LAMMPS does, θ0/180 · π) (docs/models.md §4.9).

use super::{AngleForm, Form};

/// LAMMPS's floor on sin θ in the angle forces (`SMALL` of `angle harmonic`).
const SMALL_SIN: f64 = 0.001;

/// The harmonic angle.
#[derive(Debug)]
pub(super) struct Harmonic;

impl Form for Harmonic {
    fn word(&self) -> &'static str {
        "harmonic"
    }

    fn usage(&self) -> &'static str {
        "angle_coeff N K theta0"
    }

    fn names(&self) -> &'static [&'static str] {
        &["K", "theta0"]
    }
}

impl AngleForm for Harmonic {
    #[inline]
    fn eval(&self, c: &[f64], cs: f64) -> (f64, f64) {
        let theta0 = c[1] / 180.0 * std::f64::consts::PI;
        let mut s = (1.0 - cs * cs).sqrt();
        if s < SMALL_SIN {
            s = SMALL_SIN;
        }
        s = 1.0 / s;
        let dtheta = cs.acos() - theta0;
        let tk = c[0] * dtheta;
        (-2.0 * tk * s, tk * dtheta)
    }
}
