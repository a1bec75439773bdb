//! The errors of the theory functions ([`TheoryError`]) and their messages.

use super::{DesignLimits, DesignMode, Dim, Fluid};
use crate::fmtnum::fmt_g as g;
use std::fmt;

/// Errors of the theory functions: bad inputs, unreachable targets, unstable steps.
#[derive(Clone, Debug, PartialEq)]
pub enum TheoryError {
    /// d is not 2 or 3.
    Dimension(u32),
    /// A parameter is not finite or not in its range.
    Parameter {
        /// What it is, e.g. "density n".
        name: &'static str,
        /// The value given.
        value: f64,
        /// The requirement, e.g. "finite and > 0".
        requirement: &'static str,
    },
    /// Sc ≤ 1/2: Sc = η / (2 η_K) exceeds 1/2 for every ideal DPD fluid.
    SchmidtBelowHalf {
        /// The Sc asked for.
        sc: f64,
    },
    /// The targets would need s ≤ 0, i.e. P_d(s) ≤ P_d(0) (eqs. 54–55 in 3-D, 63–64 in 2-D).
    ExponentNotPositive(Box<Unreachable>),
    /// The targets need s > 0, but the design (γ, s, or its kinetic theory) is beyond the range
    /// of a double: η (η0) is below the smallest value reachable for this Sc (Sc0). γ grows as
    /// η^−(d+1) when η → 0 at fixed Sc, and without bound as Sc → ∞ at fixed η.
    OutOfReach(Box<OutOfReach>),
    /// Euler: δt ≥ δt_c, the finite-step temperature is infinite or negative (eq. 25).
    EulerUnstable {
        /// The step.
        dt: f64,
        /// δt_c (eq. 25).
        dt_c: f64,
    },
    /// Euler: δt ≥ 2 A1 / A2, so n_c ≤ 0 and no density is stable (eq. 26).
    EulerNoStableDensity {
        /// The step.
        dt: f64,
        /// 2 A1 / A2, the δt_c of the dilute limit n → 0.
        dt_max: f64,
    },
}

/// The details of [`TheoryError::ExponentNotPositive`]: what was asked and which bounds to move.
#[derive(Clone, Debug, PartialEq)]
pub struct Unreachable {
    /// Exact inversion or the paper's approximation.
    pub mode: DesignMode,
    /// The fluid.
    pub fluid: Fluid,
    /// The viscosity asked for: η (exact) or η0 (paper).
    pub eta: f64,
    /// The Schmidt number asked for: Sc (exact) or Sc0 (paper).
    pub sc: f64,
    /// The bounds that would have to be moved.
    pub limits: DesignLimits,
}

/// The details of [`TheoryError::OutOfReach`].
#[derive(Clone, Debug, PartialEq)]
pub struct OutOfReach {
    /// Exact inversion or the paper's approximation.
    pub mode: DesignMode,
    /// The fluid.
    pub fluid: Fluid,
    /// The viscosity asked for: η (exact) or η0 (paper).
    pub eta: f64,
    /// The Schmidt number asked for: Sc (exact) or Sc0 (paper).
    pub sc: f64,
    /// The lower bound: the smallest η (η0) whose design is finite in double precision for this
    /// Sc (Sc0), found by bisection; `None` when no η is (an extreme fluid).
    pub eta_min: Option<f64>,
}

impl fmt::Display for TheoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TheoryError::Dimension(d) => {
                write!(f, "dimension d = {d} is not supported: use 2 or 3")
            }
            TheoryError::Parameter {
                name,
                value,
                requirement,
            } => {
                write!(
                    f,
                    "{name} = {} is invalid: it must be {requirement}",
                    g(*value)
                )
            }
            TheoryError::SchmidtBelowHalf { sc } => write!(
                f,
                "Sc = {} is unreachable: an ideal DPD fluid has Sc = η/(2 η_K) > 1/2 \
                 (Sc = 1/2 would mean no dissipative viscosity); raise Sc above 0.5",
                g(*sc)
            ),
            TheoryError::ExponentNotPositive(u) => write_unreachable(f, u),
            TheoryError::OutOfReach(o) => write_out_of_reach(f, o),
            TheoryError::EulerUnstable { dt, dt_c } => write!(
                f,
                "δt = {} is at or beyond the Euler stability limit δt_c = {} \
                 (finite-step paper eq. 25): lower δt, γ or n",
                g(*dt),
                g(*dt_c)
            ),
            TheoryError::EulerNoStableDensity { dt, dt_max } => write!(
                f,
                "δt = {} is at or beyond 2 A1 / A2 = {}: no density is stable with the Euler \
                 integrator (finite-step paper eq. 26 gives n_c <= 0); lower δt or γ",
                g(*dt),
                g(*dt_max)
            ),
        }
    }
}

impl std::error::Error for TheoryError {}

/// The message of [`TheoryError::ExponentNotPositive`].
fn write_unreachable(f: &mut fmt::Formatter<'_>, u: &Unreachable) -> fmt::Result {
    let Unreachable {
        mode,
        fluid,
        eta,
        sc,
        limits,
    } = u;
    let d = fluid.dim;
    let (eqs, eta_name, sc_name, bound) = match (mode, d) {
        (DesignMode::Exact, Dim::Three) => ("exact form of eqs. 54-55", "η", "Sc", "maximum η"),
        (DesignMode::Exact, Dim::Two) => ("exact form of eqs. 63-64", "η", "Sc", "maximum η"),
        (DesignMode::PaperApprox, Dim::Three) => (
            "eqs. 54-55, paper's approximation η ≈ η0",
            "η0",
            "Sc0",
            "maximum η0",
        ),
        (DesignMode::PaperApprox, Dim::Two) => (
            "eqs. 63-64, paper's approximation η ≈ η0",
            "η0",
            "Sc0",
            "maximum η0",
        ),
    };
    write!(
        f,
        "{eta_name} = {} is too large for {sc_name} = {} at this density \
         ({d}, n = {}, r_c = {}, m = {}, kT = {}): it would need a weight exponent \
         s <= 0 (s > 0 needs P_{}(s) > P_{}(0) = {}, here P = {}; {eqs}). \
         Change one of: lower {eta_name} below the {bound} {} for this {sc_name}",
        g(*eta),
        g(*sc),
        g(fluid.density),
        g(fluid.cutoff),
        g(fluid.mass),
        g(fluid.kt),
        d.get(),
        d.get(),
        g(limits.p0),
        g(limits.p),
        g(limits.eta_max),
    )?;
    // The other ways out, only where they exist in double precision (for a huge η
    // every other bound is infinite: only lowering η helps).
    for (what, v) in [
        (sc_name, limits.sc_min),
        ("n", limits.density_min),
        ("r_c", limits.cutoff_min),
    ] {
        if v.is_finite() {
            write!(f, "; or raise {what} above {}", g(v))?;
        }
    }
    if let Some(gas) = limits.sc_gas_max.filter(|&x| x.is_finite() && x > 0.5) {
        write!(
            f,
            " (a gas-like design, η_K > η_D, also exists for 0.5 < Sc < {})",
            g(gas)
        )?;
    }
    Ok(())
}

/// The message of [`TheoryError::OutOfReach`].
fn write_out_of_reach(f: &mut fmt::Formatter<'_>, o: &OutOfReach) -> fmt::Result {
    let OutOfReach {
        mode,
        fluid,
        eta,
        sc,
        eta_min,
    } = o;
    let (eta_name, sc_name, sc_limits) = match mode {
        DesignMode::Exact => ("η", "Sc", "Sc → ∞ or Sc → 1/2"),
        DesignMode::PaperApprox => ("η0", "Sc0", "Sc0 → ∞"),
    };
    let d = fluid.dim;
    write!(
        f,
        "{eta_name} = {} is out of reach for {sc_name} = {} at this density ({d}, \
         n = {}, r_c = {}, m = {}, kT = {}): ",
        g(*eta),
        g(*sc),
        g(fluid.density),
        g(fluid.cutoff),
        g(fluid.mass),
        g(fluid.kt),
    )?;
    match eta_min {
        Some(lo) if lo > eta => write!(
            f,
            "it is below the lower bound {eta_name}_min = {} for this {sc_name}. \
             The weight exponent s and the friction γ of the design grow without \
             bound as {eta_name} → 0 (γ ~ {eta_name}^-{} at fixed {sc_name}) and as \
             {sc_limits} at fixed {eta_name}; below {eta_name}_min they exceed the \
             largest double ({}). Raise {eta_name} above {eta_name}_min; designs \
             near the bound need time steps far below any practical one",
            g(*lo),
            d.get() + 1,
            g(f64::MAX)
        ),
        _ => write!(
            f,
            "the design's weight exponent s or friction γ exceeds the largest double \
             ({}) even at {eta_name} = half its maximum for this {sc_name} (they \
             grow without bound as {sc_limits}); bring {sc_name} nearer 1 or change \
             the fluid (n, r_c, m, kT)",
            g(f64::MAX)
        ),
    }
}
