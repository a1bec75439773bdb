//! Kinetic theory of the sDPD fluid (`pair_style sdpd`; `docs/models.md` §3.7, the
//! weighting-function paper's Table 1 and eqs. 29–34, 37–40, 45–53, 60–65).
//!
//! With d_i = d_j = n (the ideal-fluid closure of the paper) the dissipative and random forces of
//! sDPD are DPD's with γ w_D(r) = 2(d+2) η0 F(r)/n², so the theory of [`super::kinetic_theory`]
//! applies with Γ = γ \[w_D\] = 2(d+2) η0 \[F\]/n²:
//!
//! η_K = d m kT / (2Γ) = c m kT n² r_c² / η0,  c = d / (4(d+2) \[F\] r_c²),
//! η_D = γ n² \[r² w_D\] / (2d(d+2)) = η0 \[r² F\]/d = η0 (integrating by parts, \[r² F\] = d \[W\]),
//! D = 2 η_K / (m n), Sc = η / (2 η_K).
//!
//! \[F\] is computed here in closed form for each kernel (no quadrature); the coefficients c are
//! then Table 1's: 1/70 and 1/80 (Lucy, 3-D and 2-D), 1/120 and 239/33264 (quintic), and
//! 3/(5(s+4)(s+5)) and 3/(8(s+3)(s+4)) for the proposed kernel (eqs. 45, 60) — the proposed
//! DPD's, so a target (η, Sc) designs (η0, s) exactly as [`super::design_from_targets`] does.

use super::{Dim, Fluid, TheoryError, Transport, positive, radial_moment};
use std::f64::consts::PI;

/// The sDPD kernel family of `pair_style sdpd … kernel NAME [s]` (the shapes themselves, W and
/// F, are `forces::sdpd::kernel`'s `KernelShape`; the theory needs only which kernel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Smoothing {
    /// Lucy's kernel (WF-25): the proposed kernel with s = 2.
    Lucy,
    /// The quintic spline with h = r_c / 3.
    Quintic,
    /// The weighting-function paper's kernel (WF-41/56) with exponent s > 0.
    Proposed(f64),
}

impl Smoothing {
    /// The proposed kernel of exponent `s`; `None` unless `s` is finite and > 0.
    pub fn proposed(s: f64) -> Option<Smoothing> {
        (s.is_finite() && s > 0.0).then_some(Smoothing::Proposed(s))
    }

    /// The keyword of `kernel NAME`.
    pub fn keyword(self) -> &'static str {
        match self {
            Smoothing::Lucy => "lucy",
            Smoothing::Quintic => "quintic",
            Smoothing::Proposed(_) => "proposed",
        }
    }

    /// The exponent s of the polynomial form (1 − u)^s of F: 2 for Lucy, s for the proposed
    /// kernel, `None` for the quintic spline (piecewise).
    pub fn exponent(self) -> Option<f64> {
        match self {
            Smoothing::Lucy => Some(2.0),
            Smoothing::Quintic => None,
            Smoothing::Proposed(s) => Some(s),
        }
    }
}

impl std::fmt::Display for Smoothing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Smoothing::Proposed(s) => write!(f, "proposed (s = {s})"),
            k => f.write_str(k.keyword()),
        }
    }
}

/// \[F\] = ∫ F(r) d^d r of the kernel at cut-off `rc` (F = −W'/r), in closed form.
///
/// Polynomial kernels: F = B (1 − r/r_c)^s, \[F\] = B · \[(1 − r/r_c)^s\]. Quintic: F =
/// 5σ_d/(h^(d+2) R) Σ_k c_k (a_k − R)_+⁴ with R = r/h, so \[F\] = 5 σ_d S_d / h² · Σ_k c_k
/// ∫_0^{a_k} R^(d−2) (a_k − R)⁴ dR = 5 σ_d S_d / h² · Σ_k c_k a_k^(d+3) (d−2)! 4! / (d+3)!.
pub fn kernel_moment(dim: Dim, kernel: Smoothing, rc: f64) -> Result<f64, TheoryError> {
    positive("cut-off r_c", rc)?;
    let d = dim.get();
    match kernel.exponent() {
        Some(s) => {
            positive("kernel exponent s", s)?;
            // B = K_d(s) / r_c^(d+2), K_d(s) = d ∏_{j=1}^{d+2} (s+j) / (S_d (d+1)!) (WF-42, WF-57).
            let b = dim.k(s) / rc.powi(d as i32 + 2);
            Ok(b * radial_moment(dim, 0, s, rc))
        }
        None => {
            let h = rc / 3.0;
            let (sigma, sphere) = match dim {
                Dim::Three => (1.0 / (120.0 * PI), 4.0 * PI),
                Dim::Two => (7.0 / (478.0 * PI), 2.0 * PI),
            };
            let fact = |n: u32| -> f64 { (1..=n).map(f64::from).product() };
            let beta = fact(d - 2) * fact(4) / fact(d + 3);
            let sum: f64 = [(3.0f64, 1.0), (2.0, -6.0), (1.0, 15.0)]
                .iter()
                .map(|&(a, c)| c * a.powi(d as i32 + 3))
                .sum();
            Ok(5.0 * sigma * sphere / (h * h) * beta * sum)
        }
    }
}

/// c of η_K = c m kT n² r_c² / η0 (Table 1): d / (4(d+2) \[F\] r_c²), independent of r_c.
pub fn kinetic_coefficient(dim: Dim, kernel: Smoothing) -> Result<f64, TheoryError> {
    let f = kernel_moment(dim, kernel, 1.0)?;
    let d = f64::from(dim.get());
    Ok(d / (4.0 * (d + 2.0) * f))
}

/// Kinetic theory of the ideal sDPD fluid with dissipative viscosity `eta0` (module notes):
/// η_K = c X/η0, η_D = η0, D = 2 η_K/(m n), Sc = η/(2 η_K), X = m kT n² r_c² (eqs. 29, 33–34
/// for Lucy in 3-D, 37–39 quintic, 45–47 and 60–62 proposed).
pub fn kinetic_theory(
    fluid: &Fluid,
    kernel: Smoothing,
    eta0: f64,
) -> Result<Transport, TheoryError> {
    fluid.validate()?;
    positive("dissipative viscosity η0", eta0)?;
    let c = kinetic_coefficient(fluid.dim, kernel)?;
    let eta_k = c * fluid.x() / eta0;
    let eta = eta_k + eta0;
    let diffusion = 2.0 * eta_k / (fluid.inertia() * fluid.density);
    Ok(Transport {
        eta_k,
        eta_d: eta0,
        eta,
        diffusion,
        schmidt: eta / (2.0 * eta_k),
    })
}

/// The smallest viscosity the kernel reaches at this state point, η_min = 2 sqrt(c X), at
/// η0 = sqrt(c X) (eq. 31 for Lucy in 3-D, eq. 50 proposed 3-D, eq. 64 proposed 2-D).
pub fn eta_min(fluid: &Fluid, kernel: Smoothing) -> Result<f64, TheoryError> {
    fluid.validate()?;
    let c = kinetic_coefficient(fluid.dim, kernel)?;
    Ok(2.0 * (c * fluid.x()).sqrt())
}

/// η0 for a target viscosity η with a fixed kernel: the liquid root of η0² − η η0 + c X = 0,
/// η0 = (η + sqrt(η² − 4cX))/2 (eqs. 30–32; the other root is the kinetic part). η below
/// [`eta_min`] has no solution.
pub fn eta0_for(fluid: &Fluid, kernel: Smoothing, eta: f64) -> Result<f64, TheoryError> {
    positive("viscosity η", eta)?;
    let min = eta_min(fluid, kernel)?;
    if eta < min {
        return Err(TheoryError::Parameter {
            name: "viscosity η",
            value: eta,
            requirement: "at least eta_min = 2 sqrt(c m kT n² r_c²) of this kernel (eq. 31)",
        });
    }
    let c = kinetic_coefficient(fluid.dim, kernel)?;
    let disc = (eta * eta - 4.0 * c * fluid.x()).max(0.0);
    Ok(0.5 * (eta + disc.sqrt()))
}
