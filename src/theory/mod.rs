//! Closed-form theory of the ideal DPD fluid (conservative force a = 0).
//!
//! - [`kinetic_theory`]: viscosity, self-diffusion and Schmidt number for a dissipative weight
//!   w_D(r) = (1 − r/r_c)^s of any exponent s > 0, in 2-D or 3-D (`docs/models.md` §3.2;
//!   weighting-function paper eqs. 23–24 and 60).
//! - [`design_from_targets`]: the (γ, s) that give a target viscosity η and Schmidt number Sc,
//!   by the exact closed-form inversion of the kinetic theory; [`design_paper_approx`] is the
//!   weighting-function paper's own recipe (it fixes η0 and approximates η ≈ η0, eqs. 52–53, 65).
//! - [`sdpd`]: the same theory for the sDPD kernels (Lucy, quintic, proposed; Table 1).
//! - [`euler_temperature_ratio`], [`euler_critical_dt`], [`euler_critical_density`]: the
//!   finite-step equilibrium temperature of the Euler (Hoogerbrugge–Koelman) integrator
//!   (`docs/models.md` §2.2; finite-step paper eqs. 20–26).
//!
//! # Conventions
//! The pair forces are those of `docs/models.md` §3.1: F^D_ij = −γ w_D(r) (e_ij · v_ij) e_ij
//! with γ ≥ 0 (γ is `gamma0` of `pair_coeff`), F^R_ij = σ w_R(r) ξ_ij δt^(−1/2) e_ij, σ² = 2 γ kT
//! and w_R² = w_D. All particles have one mass m. Units are a LAMMPS unit style's
//! ([`crate::units`]): n is particles per unit volume (3-D) or per unit area (2-D), γ is
//! force·time/length, η is force·time/length^(d−1) = energy·time/length^d (LAMMPS's native
//! viscosity; `lj` m/(σ τ), a 2-D viscosity per area), D is length²/time, Sc = η/(m n D) is a
//! pure number, kT is an energy and δt a time. The style enters only through the mass: where
//! the formulas need m in force·time²/length (m kT, m D/kT, kT/m) they use m·mvv2e
//! ([`Fluid::mvv2e`], [`Fluid::inertia`]), which is m itself in `units lj`.
//!
//! The integrals are \[f\] = ∫_{r<r_c} f(r) d^d r, all in closed form ([`radial_moment`]); no
//! quadrature. "The weighting-function paper" is Mai-Duy, Phan-Thien & Tran-Cong, Appl. Math.
//! Model. (2017); "the finite-step paper" is Marsh & Yeomans, Europhys. Lett. 37 (1997). Their
//! equation numbers ("eq. 60", "eqs. 20–26") are the papers' own, labelled WF-60, FS-20 … in
//! `docs/models.md`.
//!
//! # Derivation check (weighting-function paper vs `docs/models.md` §3.3)
//! With \[r^k (1 − r/r_c)^s\] = S_d r_c^(d+k) (d+k−1)! / ∏_{j=1}^{d+k} (s+j), S_2 = 2π, S_3 = 4π,
//! the weight γ w_D(r) = 2(d+2) η0 K_d(s) / (n² r_c^(d+2)) · (1 − r/r_c)^s with
//! K_d(s) = d ∏_{j=1}^{d+2}(s+j) / (S_d (d+1)!) (K_3 = (s+1)…(s+5)/(32π), eq. 43;
//! K_2 = (s+1)…(s+4)/(6π), eq. 58) gives
//! η_D = γ n² \[R² w_D\] / (2d(d+2)) = η0 K_d S_d (d+1)! / (d ∏_{j=1}^{d+2}(s+j)) = η0 exactly, and
//! Γ = γ \[w_D\] = 2(d+2) η0 P_d(s) / ((d+1) n² r_c²) with P_3 = (s+4)(s+5), P_2 = (s+3)(s+4), so
//! η_K = d m kT / (2Γ) = c_d m kT n² r_c² / (η0 P_d(s)), c_d = d(d+1) / (4(d+2)):
//! c_3 = 3/5 (eq. 45), c_2 = 3/8 (eq. 60). This reproduces eqs. 44, 45, 59 and 60 of the paper
//! and `docs/models.md` §3.3; no disagreement was found. One remark on the paper's text: its claim
//! that with s from eq. 53/65 "the S_c predicted by kinetic theory will be exactly equal to this
//! specified value" holds only for C built from η̄η0; with its approximation C ≈ …/η0² (used in
//! its Tables 4–5) the kinetic-theory Schmidt number is exactly Sc0 + 1/2 (see
//! [`design_paper_approx`]).

mod error;
pub mod sdpd;
pub mod vv_measured;

pub use error::{OutOfReach, TheoryError, Unreachable};

use std::f64::consts::PI;
use std::fmt;

/// Space dimension of the fluid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// Two dimensions (n is particles per unit area).
    Two,
    /// Three dimensions.
    Three,
}

impl Dim {
    /// `Dim` from the number 2 or 3.
    pub fn new(d: u32) -> Result<Dim, TheoryError> {
        match d {
            2 => Ok(Dim::Two),
            3 => Ok(Dim::Three),
            _ => Err(TheoryError::Dimension(d)),
        }
    }

    /// d as a number.
    pub fn get(self) -> u32 {
        match self {
            Dim::Two => 2,
            Dim::Three => 3,
        }
    }

    fn f(self) -> f64 {
        f64::from(self.get())
    }

    /// S_d, the area of the unit sphere: 2π in 2-D, 4π in 3-D.
    fn sphere(self) -> f64 {
        match self {
            Dim::Two => 2.0 * PI,
            Dim::Three => 4.0 * PI,
        }
    }

    /// c_d of η_K = c_d m kT n² r_c² / (η0 P_d(s)): 3/8 in 2-D (eq. 60), 3/5 in 3-D (eq. 45).
    pub fn c(self) -> f64 {
        let d = self.f();
        d * (d + 1.0) / (4.0 * (d + 2.0))
    }

    /// P_d(s) = (s+d+1)(s+d+2): (s+3)(s+4) in 2-D (eq. 60), (s+4)(s+5) in 3-D (eq. 45).
    pub fn p(self, s: f64) -> f64 {
        let d = self.f();
        (s + d + 1.0) * (s + d + 2.0)
    }

    /// The positive root s of P_d(s) = p, or `None` if it is not > 0 (p ≤ P_d(0)).
    ///
    /// s = (−(2d+3) + sqrt(1 + 4p)) / 2 (eq. 53 in 3-D, eq. 65 in 2-D), written as
    /// 2 (p − P_d(0)) / (sqrt(1 + 4p) + 2d + 3) so that it keeps full precision near s = 0.
    pub fn exponent_for(self, p: f64) -> Option<f64> {
        let p0 = self.p(0.0);
        let b = 2.0 * self.f() + 3.0;
        let s = 2.0 * (p - p0) / ((1.0 + 4.0 * p).sqrt() + b);
        (s > 0.0 && s.is_finite()).then_some(s)
    }

    /// K_d(s) = d ∏_{j=1}^{d+2}(s+j) / (S_d (d+1)!): eq. 43 (3-D) and eq. 58 (2-D) without
    /// their 1/(n² r_c^(d+3)).
    pub fn k(self, s: f64) -> f64 {
        let d = self.get();
        let prod: f64 = (1..=d + 2).map(|j| s + f64::from(j)).product();
        let fact: f64 = (1..=d + 1).map(f64::from).product();
        self.f() * prod / (self.sphere() * fact)
    }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-D", self.get())
    }
}

/// The state point of an ideal DPD fluid. Every field must be finite and > 0 ([`Fluid::new`]
/// checks; every function of this module checks again).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fluid {
    /// Space dimension d.
    pub dim: Dim,
    /// Number density n (per unit area in 2-D).
    pub density: f64,
    /// Cut-off radius r_c of the dissipative and random forces.
    pub cutoff: f64,
    /// Particle mass m.
    pub mass: f64,
    /// Thermal energy kT (k_B T; the LAMMPS `pair_style` temperature in `units lj`).
    pub kt: f64,
    /// The unit style's mass × velocity² → energy factor (LAMMPS's `force->mvv2e`; 1 in `units
    /// lj`, the default of [`Fluid::new`]; [`Fluid::with_mvv2e`]).
    pub mvv2e: f64,
}

impl Fluid {
    /// A checked state point; `dim` must be 2 or 3 and the rest finite and > 0.
    pub fn new(
        dim: u32,
        density: f64,
        cutoff: f64,
        mass: f64,
        kt: f64,
    ) -> Result<Fluid, TheoryError> {
        let f = Fluid {
            dim: Dim::new(dim)?,
            density,
            cutoff,
            mass,
            kt,
            mvv2e: 1.0,
        };
        f.validate()?;
        Ok(f)
    }

    /// The same state point in a unit style whose mass × velocity² is `mvv2e` energy units
    /// (LAMMPS's `force->mvv2e`, [`crate::units::Units::mvv2e`]); checked finite and > 0.
    pub fn with_mvv2e(self, mvv2e: f64) -> Result<Fluid, TheoryError> {
        let f = Fluid { mvv2e, ..self };
        f.validate()?;
        Ok(f)
    }

    /// Checks that n, r_c, m, kT and mvv2e are finite and > 0.
    pub fn validate(&self) -> Result<(), TheoryError> {
        positive("density n", self.density)?;
        positive("cut-off r_c", self.cutoff)?;
        positive("mass m", self.mass)?;
        positive("kT", self.kt)?;
        positive("mvv2e", self.mvv2e)
    }

    /// The mass as the formulas need it, m·mvv2e (force·time²/length: kT/(m·mvv2e) is a
    /// squared velocity); m itself in `units lj`.
    pub fn inertia(&self) -> f64 {
        self.mass * self.mvv2e
    }

    /// X = m kT n² r_c², the combination in every formula of the weighting-function paper.
    fn x(&self) -> f64 {
        self.inertia() * self.kt * self.density * self.density * self.cutoff * self.cutoff
    }
}

fn positive(name: &'static str, value: f64) -> Result<(), TheoryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(TheoryError::Parameter {
            name,
            value,
            requirement: "finite and > 0",
        })
    }
}

/// \[r^k w\] = ∫_{r<r_c} r^k (1 − r/r_c)^s d^d r in closed form:
/// S_d r_c^(d+k) B(d+k, s+1) = S_d r_c^(d+k) (d+k−1)! / ∏_{j=1}^{d+k} (s+j),
/// with S_2 = 2π, S_3 = 4π (the \[·\] of `docs/models.md` §0 and of both papers).
///
/// The integral exists for s > −1; nothing is checked here (the public functions that call it
/// check s > 0 first). Used with k = 0 for \[w_D\], k = 2 for \[R² w_D\], and exponent 2s for
/// \[w_D²\].
pub fn radial_moment(dim: Dim, k: u32, s: f64, cutoff: f64) -> f64 {
    let dk = dim.get() + k;
    let fact: f64 = (1..dk).map(f64::from).product();
    let prod: f64 = (1..=dk).map(|j| s + f64::from(j)).product();
    dim.sphere() * cutoff.powi(dk as i32) * fact / prod
}

/// Kinetic-theory transport coefficients of an ideal DPD fluid (see [`kinetic_theory`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transport {
    /// Kinetic ("gas") viscosity η_K = d m kT / (2Γ).
    pub eta_k: f64,
    /// Dissipative ("liquid") viscosity η_D = γ n² \[R² w_D\] / (2d(d+2)).
    pub eta_d: f64,
    /// Shear viscosity η = η_K + η_D.
    pub eta: f64,
    /// Self-diffusion coefficient D = d kT / (n Γ) = 2 η_K / (m n).
    pub diffusion: f64,
    /// Schmidt number Sc = η / (m n D) = η / (2 η_K).
    pub schmidt: f64,
}

/// Kinetic theory of the ideal DPD fluid (a = 0) with w_D = (1 − r/r_c)^s (`docs/models.md` §3.2;
/// weighting-function paper eqs. 23–24 in 3-D, eq. 60 in 2-D, after Marsh, Backx & Ernst):
///
/// Γ = γ \[w_D\], η_K = d m kT / (2Γ), η_D = γ n² \[R² w_D\] / (2d(d+2)), η = η_K + η_D,
/// D = d kT / (n Γ), Sc = η / (m n D).
///
/// `gamma` is the friction amplitude γ of F^D = −γ w_D (e·v) e (`gamma0` of `pair_coeff`), finite
/// and > 0; `s` the weight exponent, finite and > 0. Units: see the module documentation.
pub fn kinetic_theory(fluid: &Fluid, gamma: f64, s: f64) -> Result<Transport, TheoryError> {
    fluid.validate()?;
    positive("friction γ", gamma)?;
    positive("weight exponent s", s)?;
    let dim = fluid.dim;
    let d = dim.f();
    let (n, m, kt) = (fluid.density, fluid.inertia(), fluid.kt);
    let big_gamma = gamma * radial_moment(dim, 0, s, fluid.cutoff);
    let eta_k = d * m * kt / (2.0 * big_gamma);
    let eta_d = gamma * n * n * radial_moment(dim, 2, s, fluid.cutoff) / (2.0 * d * (d + 2.0));
    let eta = eta_k + eta_d;
    let diffusion = d * kt / (n * big_gamma);
    Ok(Transport {
        eta_k,
        eta_d,
        eta,
        diffusion,
        schmidt: eta / (m * n * diffusion),
    })
}

/// Targets for [`design_from_targets`]: the fluid and the wanted η and Sc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Targets {
    /// The state point (d, n, r_c, m, kT).
    pub fluid: Fluid,
    /// Target shear viscosity η = η_K + η_D (finite, > 0).
    pub eta: f64,
    /// Target Schmidt number Sc = η / (m n D) (finite, > 1/2).
    pub sc: f64,
}

/// How a [`Design`] was obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DesignMode {
    /// Exact inversion of the kinetic theory: η and Sc are met exactly.
    Exact,
    /// The weighting-function paper's recipe (eqs. 52–53, 65): η0 and Sc0 given, η ≈ η0 assumed
    /// in C; kinetic theory then gives η = η0 (1 + 1/(2 Sc0)) and Sc = Sc0 + 1/2.
    PaperApprox,
}

/// The bounds of s > 0 ⇔ P_d(s) > P_d(0) (eqs. 54–55 in 3-D, 63–64 in 2-D), each holding the
/// other inputs fixed. Crossing any one of them makes s ≤ 0. Serialised as the `limits` object
/// of `dpdnl design --json` (field order = key order).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DesignLimits {
    /// P_d(s) required by the targets (the paper's C, eq. 52/65).
    pub p: f64,
    /// P_d(0): 20 in 3-D, 12 in 2-D.
    pub p0: f64,
    /// Exact: the largest η for this Sc, sqrt(4 c_d X Sc² / (P_d(0)(2Sc − 1))), X = m kT n² r_c².
    /// Paper: the largest η0 for this Sc0, sqrt(2 c_d X Sc0 / P_d(0)) (eq. 54 / eq. 63).
    pub eta_max: f64,
    /// Exact: the smallest Sc for this η on the liquid branch (Q + sqrt(Q² − Q) with
    /// Q = P_d(0) η² / (4 c_d X); 1/2 when Q ≤ 1). Paper: P_d(0) η0² / (2 c_d X) (eq. 55 / 64).
    pub sc_min: f64,
    /// Exact only, when Q > 1: Sc in (1/2, this) also gives s > 0 (a gas-like fluid, η_K > η_D).
    pub sc_gas_max: Option<f64>,
    /// The smallest n (P ∝ n²): n sqrt(P_d(0)/P).
    pub density_min: f64,
    /// The smallest r_c (P ∝ r_c²): r_c sqrt(P_d(0)/P).
    pub cutoff_min: f64,
}

/// A design: the parameters to run and how they were obtained.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Design {
    /// Exact or the paper's approximation.
    pub mode: DesignMode,
    /// The dissipative viscosity η0 = η_D that the weight produces exactly.
    pub eta0: f64,
    /// The weight exponent s > 0 (`weight s` of `pair_style dpd/nonlinear`).
    pub s: f64,
    /// γ for `pair_coeff` (`gamma0`): γ (1 − r/r_c)^s equals eq. 43 (3-D) / eq. 58 (2-D),
    /// γ = 2(d+2) η0 K_d(s) / (n² r_c^(d+2)).
    pub gamma: f64,
    /// The bounds of s > 0 around this design.
    pub limits: DesignLimits,
}

/// γ of `pair_coeff` for the weighting-function paper's weight: γ w_D(r) =
/// 2(d+2) η0 K_d(s) / (n² r_c^(d+2)) (1 − r/r_c)^s (eq. 43 with eq. 21 in 3-D, eq. 58 in 2-D),
/// which makes η_D = η0 exactly for any s > 0.
pub fn gamma_for(fluid: &Fluid, eta0: f64, s: f64) -> Result<f64, TheoryError> {
    fluid.validate()?;
    positive("dissipative viscosity η0", eta0)?;
    positive("weight exponent s", s)?;
    let d = fluid.dim.get();
    let n = fluid.density;
    Ok(2.0 * f64::from(d + 2) * eta0 * fluid.dim.k(s) / (n * n * fluid.cutoff.powi(d as i32 + 2)))
}

/// η0, P_d(s) and the limits of a design, without checks (the callers validate).
fn plan(mode: DesignMode, fluid: &Fluid, eta: f64, sc: f64) -> (f64, f64, DesignLimits) {
    let (c, x, p0) = (fluid.dim.c(), fluid.x(), fluid.dim.p(0.0));
    match mode {
        DesignMode::Exact => {
            let eta_k = eta / (2.0 * sc);
            let eta0 = eta * (1.0 - 0.5 / sc); // η (2Sc − 1)/(2Sc), finite for any Sc
            let p = c * x / (eta0 * eta_k);
            let q = p0 * eta * eta / (4.0 * c * x);
            // Q + sqrt(Q² − Q) and its reciprocal partner Q − sqrt(Q² − Q), written so that they
            // stay finite for a huge Q.
            let (sc_min, sc_gas_max) = if q > 1.0 {
                let root = (1.0 - 1.0 / q).sqrt();
                (q * (1.0 + root), Some(1.0 / (1.0 + root)))
            } else {
                (0.5, None)
            };
            let ratio = (p0 / p).sqrt();
            let limits = DesignLimits {
                p,
                p0,
                // sqrt(4 c X Sc² / (P_d(0) (2 Sc − 1))) without forming Sc² (finite for any Sc).
                eta_max: (4.0 * c * x / p0).sqrt() * sc / (2.0 * sc - 1.0).sqrt(),
                sc_min,
                sc_gas_max,
                density_min: fluid.density * ratio,
                cutoff_min: fluid.cutoff * ratio,
            };
            (eta0, p, limits)
        }
        DesignMode::PaperApprox => {
            let (eta0, sc0) = (eta, sc);
            let p = 2.0 * c * sc0 * x / (eta0 * eta0);
            let ratio = (p0 / p).sqrt();
            let limits = DesignLimits {
                p,
                p0,
                eta_max: (2.0 * c * x * sc0 / p0).sqrt(),
                sc_min: p0 * eta0 * eta0 / (2.0 * c * x),
                sc_gas_max: None,
                density_min: fluid.density * ratio,
                cutoff_min: fluid.cutoff * ratio,
            };
            (eta0, p, limits)
        }
    }
}

/// (s, γ) for P_d(s) = `p` when s > 0 and the design is finite in double precision: s, γ and
/// every transport coefficient of its kinetic theory finite and > 0.
fn representable(fluid: &Fluid, eta0: f64, p: f64) -> Option<(f64, f64)> {
    let s = fluid.dim.exponent_for(p)?;
    let gamma = gamma_for(fluid, eta0, s).ok()?;
    let t = kinetic_theory(fluid, gamma, s).ok()?;
    [t.eta_k, t.eta_d, t.eta, t.diffusion, t.schmidt]
        .iter()
        .all(|v| v.is_finite() && *v > 0.0)
        .then_some((s, gamma))
}

/// The smallest η (η0 in paper mode) whose design is [`representable`] for this Sc: a bisection
/// in ln η between the smallest normal double and η_max / 2 (where P_d(s) = 4 P_d(0), a
/// moderate s). Representability is monotone in η there, since γ and s fall as η grows.
fn smallest_eta(mode: DesignMode, fluid: &Fluid, sc: f64, eta_max: f64) -> Option<f64> {
    let ok = |eta: f64| {
        let (eta0, p, _) = plan(mode, fluid, eta, sc);
        representable(fluid, eta0, p).is_some()
    };
    let (mut lo, mut hi) = (f64::MIN_POSITIVE, 0.5 * eta_max);
    if !(hi.is_finite() && hi > lo && ok(hi)) {
        return None;
    }
    if ok(lo) {
        return Some(lo);
    }
    for _ in 0..80 {
        let mid = (0.5 * (lo.ln() + hi.ln())).exp();
        if !(mid > lo && mid < hi) {
            break;
        }
        if ok(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

fn finish(fluid: &Fluid, mode: DesignMode, eta: f64, sc: f64) -> Result<Design, TheoryError> {
    let (eta0, p, limits) = plan(mode, fluid, eta, sc);
    if let Some((s, gamma)) = representable(fluid, eta0, p) {
        return Ok(Design {
            mode,
            eta0,
            s,
            gamma,
            limits,
        });
    }
    if p > limits.p0 {
        // s > 0 exists (P may have overflowed to +inf): the numbers are out of range.
        return Err(TheoryError::OutOfReach(Box::new(OutOfReach {
            mode,
            fluid: *fluid,
            eta,
            sc,
            eta_min: smallest_eta(mode, fluid, sc, limits.eta_max),
        })));
    }
    Err(TheoryError::ExponentNotPositive(Box::new(Unreachable {
        mode,
        fluid: *fluid,
        eta,
        sc,
        limits,
    })))
}

/// Exact design from targets (`docs/models.md` §3.4): with X = m kT n² r_c²,
/// η_K = η / (2 Sc), η0 = η (1 − 1/(2 Sc)), P_d(s) = c_d X / (η0 η_K), s the positive root
/// (eqs. 52–53 in 3-D, 65 in 2-D, here without the approximation η ≈ η0), and
/// γ = 2(d+2) η0 K_d(s) / (n² r_c^(d+2)) ([`gamma_for`]). Then [`kinetic_theory`] with
/// (γ, s) gives η_D = η0, η_K = η/(2Sc), so η and Sc are met to round-off.
///
/// Errors: bad fluid or η (not finite and > 0); Sc ≤ 1/2 ([`TheoryError::SchmidtBelowHalf`]);
/// s ≤ 0, i.e. P_d(s) ≤ P_d(0), the exact form of eqs. 54–55 / 63–64
/// ([`TheoryError::ExponentNotPositive`], which names the bounds to move); a design beyond the
/// range of a double, for η too small or Sc too large ([`TheoryError::OutOfReach`], which names
/// the smallest reachable η). P_d grows with
/// Sc, n and r_c and falls with η, so s ≤ 0 means η too large or Sc, n or r_c too small: the
/// Schmidt-number bound is a lower bound (for Q = P_d(0) η² / (4 c_d X) > 1 a second, gas-like
/// window 1/2 < Sc < Q − sqrt(Q² − Q) also exists; see [`DesignLimits`]).
pub fn design_from_targets(t: &Targets) -> Result<Design, TheoryError> {
    let fluid = &t.fluid;
    fluid.validate()?;
    positive("viscosity η", t.eta)?;
    positive("Schmidt number Sc", t.sc)?;
    if t.sc <= 0.5 {
        return Err(TheoryError::SchmidtBelowHalf { sc: t.sc });
    }
    finish(fluid, DesignMode::Exact, t.eta, t.sc)
}

/// The weighting-function paper's own design (labelled its approximation): given the
/// dissipative viscosity η0 and Sc0, C = 2 c_d Sc0 X / η0² (eq. 52 in 3-D: 6 Sc X / (5 η0²);
/// eq. 65 in 2-D: 3 Sc X / (4 η0²)), X = m kT n² r_c², s from eq. 53 / 65, γ from eq. 43 / 58.
///
/// This is what the paper's Tables 4–5 use. Kinetic theory then gives η_D = η0,
/// η_K = η0 / (2 Sc0), so η = η0 (1 + 1/(2 Sc0)) (the tables' η̄ column) and Sc = Sc0 + 1/2,
/// not Sc0. Limits: η0 < sqrt(2 c_d X Sc0 / P_d(0)) (eq. 54 / 63) and
/// Sc0 > P_d(0) η0² / (2 c_d X) (eq. 55 / 64).
pub fn design_paper_approx(fluid: &Fluid, eta0: f64, sc0: f64) -> Result<Design, TheoryError> {
    fluid.validate()?;
    positive("dissipative viscosity η0", eta0)?;
    positive("Schmidt number Sc0", sc0)?;
    finish(fluid, DesignMode::PaperApprox, eta0, sc0)
}

/// [`StepScales::stiff`]: a design is stiff when its Euler critical step δt_c (eq. 25) is below
/// this fraction of t0 = r_c sqrt(m/kT), the time a particle takes to cross the cut-off at
/// thermal speed. A run then needs more than 10⁴ steps per t0 (10⁵ at δt = 0.1 δt_c) just to
/// stay stable; typical DPD designs have δt_c of order t0 (Groot–Warren, γ = 4.5, s = 2, n = 3:
/// δt_c = 0.45 t0).
pub const STIFF_DT_C_FRACTION: f64 = 1e-4;

/// The time scales that bound the step of a design (γ, s) in a fluid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepScales {
    /// The Euler integrator's critical step δt_c (finite-step paper eq. 25): no finite
    /// temperature at or above it.
    pub dt_c: f64,
    /// The velocity relaxation time τ = m D / kT = d m / (n Γ), Γ = γ \[w_D\]: any explicit
    /// integrator (velocity-Verlet too) needs δt well below it. δt_c ≤ 2τ.
    pub tau: f64,
    /// t0 = r_c sqrt(m/kT), the time to cross the cut-off at thermal speed.
    pub t0: f64,
}

impl StepScales {
    /// δt_c < [`STIFF_DT_C_FRACTION`] t0: γ is so large that no practical step is stable.
    pub fn stiff(&self) -> bool {
        self.dt_c < STIFF_DT_C_FRACTION * self.t0
    }
}

/// [`StepScales`] of friction γ and weight exponent s in `fluid` (ideal fluid, a = 0).
pub fn step_scales(fluid: &Fluid, gamma: f64, s: f64) -> Result<StepScales, TheoryError> {
    let t = kinetic_theory(fluid, gamma, s)?;
    Ok(StepScales {
        dt_c: euler_critical_dt(fluid, gamma, s)?,
        tau: fluid.inertia() * t.diffusion / fluid.kt,
        t0: fluid.cutoff * (fluid.inertia() / fluid.kt).sqrt(),
    })
}

/// The coefficients of the finite-step paper, eq. 23, for w_D = (1 − r/r_c)^s, w_R² = w_D and
/// σ² = 2 γ kT0 (kT0 = `fluid.kt`, the temperature set in the thermostat):
/// A1 = γ \[w_D\] / (m d), A2 = 2 γ² \[w_D²\] / (m² d), A3 = σ² \[w_R²\] / d = 2 m kT0 A1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerCoefficients {
    /// A1 (1/time).
    pub a1: f64,
    /// A2 (1/time²).
    pub a2: f64,
    /// A3 (energy·mass/time).
    pub a3: f64,
}

/// [`EulerCoefficients`] (finite-step paper eq. 23) for friction γ > 0 and weight exponent s > 0.
/// `fluid.density` is not used.
pub fn euler_coefficients(
    fluid: &Fluid,
    gamma: f64,
    s: f64,
) -> Result<EulerCoefficients, TheoryError> {
    fluid.validate()?;
    positive("friction γ", gamma)?;
    positive("weight exponent s", s)?;
    let (dim, m, rc) = (fluid.dim, fluid.inertia(), fluid.cutoff);
    let d = dim.f();
    let a1 = gamma * radial_moment(dim, 0, s, rc) / (m * d);
    let a2 = 2.0 * gamma * gamma * radial_moment(dim, 0, 2.0 * s, rc) / (m * m * d);
    let sigma2 = 2.0 * gamma * fluid.kt;
    let a3 = sigma2 * radial_moment(dim, 0, s, rc) / d;
    Ok(EulerCoefficients { a1, a2, a3 })
}

/// Equilibrium temperature ratio T_eq(δt) / T0 of the Euler (Hoogerbrugge–Koelman) integrator for
/// the ideal fluid (finite-step paper eq. 22 with σ² = 2 γ kT0, w_R² = w_D; `docs/models.md` §2.2):
///
/// T_eq / T0 = 2 / (2 − A1 n δt − (A2/A1) δt) ≈ 1 + (A1 n + A2/A1) δt / 2 + O(δt²),
///
/// with A1, A2 from [`euler_coefficients`], n = `fluid.density`, δt = `dt` > 0. It is > 1: the
/// Euler integrator heats the fluid. `fluid.kt` does not enter the ratio.
///
/// Error [`TheoryError::EulerUnstable`] when δt ≥ δt_c (eq. 25), where the formula gives no
/// positive temperature. The velocity-Verlet integrator has no closed form in the finite-step
/// paper, so this module offers none for it.
pub fn euler_temperature_ratio(
    fluid: &Fluid,
    gamma: f64,
    s: f64,
    dt: f64,
) -> Result<f64, TheoryError> {
    positive("time step δt", dt)?;
    let a = euler_coefficients(fluid, gamma, s)?;
    let den = 2.0 - a.a1 * fluid.density * dt - a.a2 / a.a1 * dt;
    if den > 0.0 {
        Ok(2.0 / den)
    } else {
        Err(TheoryError::EulerUnstable {
            dt,
            dt_c: euler_critical_dt(fluid, gamma, s)?,
        })
    }
}

/// Critical Euler step δt_c = 2 A1 / (n A1² + A2) (finite-step paper eq. 25): for δt ≥ δt_c the
/// ideal fluid has no finite equilibrium temperature. n = `fluid.density`; time units.
pub fn euler_critical_dt(fluid: &Fluid, gamma: f64, s: f64) -> Result<f64, TheoryError> {
    let a = euler_coefficients(fluid, gamma, s)?;
    Ok(2.0 * a.a1 / (fluid.density * a.a1 * a.a1 + a.a2))
}

/// Critical density n_c = (2 A1 − A2 δt) / (A1² δt) of the Euler integrator at step δt
/// (finite-step paper eq. 26): densities n ≥ n_c are unstable. `fluid.density` is not used.
///
/// Error [`TheoryError::EulerNoStableDensity`] when δt ≥ 2 A1 / A2 (then n_c ≤ 0).
pub fn euler_critical_density(
    fluid: &Fluid,
    gamma: f64,
    s: f64,
    dt: f64,
) -> Result<f64, TheoryError> {
    positive("time step δt", dt)?;
    let a = euler_coefficients(fluid, gamma, s)?;
    let n_c = (2.0 * a.a1 - a.a2 * dt) / (a.a1 * a.a1 * dt);
    if n_c > 0.0 {
        Ok(n_c)
    } else {
        Err(TheoryError::EulerNoStableDensity {
            dt,
            dt_max: 2.0 * a.a1 / a.a2,
        })
    }
}
