//! What both engines do when a run is initialised, so that the standalone engine and the LAMMPS
//! pair style (through the C ABI) resolve the same parameters and print the same lines:
//!
//! - [`resolve_design`]: `pair_coeff I J a eta E sc S …` — the γ (`gamma0`) and the weight exponent
//!   s that give the target viscosity η and Schmidt number Sc at the current number density, by the
//!   exact inversion of the kinetic theory ([`crate::theory::design_from_targets`],
//!   `docs/models.md` §3.4).
//! - [`euler_warning`]: the finite-step heating of the Euler integrator (finite-step paper eqs. 22
//!   and 25, `docs/models.md` §2.2) for the run's step, with the thresholds documented in
//!   `docs/theory.md`.
//!
//! Equation numbers are the papers' own: "eq. 22", "eq. 25" the finite-step paper's (FS-22,
//! FS-25 in `docs/models.md`), "eq. 43 / 58" the weighting-function paper's (WF-43, WF-58).
//!
//! Nothing here prints: each function returns the text, the caller logs it.

use crate::fmtnum::fmt_g as g;
use crate::theory::{self, Fluid, Targets, TheoryError};

/// Warn when δt exceeds this fraction of the Euler critical step δt_c (eq. 25).
pub(crate) const EULER_WARN_DT_FRACTION: f64 = 0.1;
/// Warn when eq. 22 predicts more heating than this (T_eq/T0 − 1).
pub(crate) const EULER_WARN_HEATING: f64 = 0.01;

/// A design target resolved at init: the `pair_coeff` parameters that realise (η, Sc).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ResolvedDesign {
    /// `gamma0` of the pair (γ of eq. 43 / 58, so that γ w_D gives η_D = η0).
    pub gamma: f64,
    /// The weight exponent s (`weight s` of the pair style).
    pub s: f64,
    /// The line to log, e.g. `pair_coeff 1 1: eta 10 sc 400 at n = 4 … -> gamma0 = …, s = …`.
    pub message: String,
}

/// Resolve `pair_coeff … eta E sc S` for one type pair (`label`, e.g. "1 1") at number density
/// `density` (N/V, per area in 2-D), cut-off `rc`, particle mass `mass`, thermostat `kt` (an
/// energy) and the unit style's `mvv2e` (1 in `units lj`; [`crate::theory::Fluid::mvv2e`]).
///
/// Errors name the pair and say which bound of the design was hit (eqs. 54–55 / 63–64).
#[allow(clippy::too_many_arguments)]
pub(crate) fn resolve_design(
    label: &str,
    dim: u32,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
    mvv2e: f64,
    eta: f64,
    sc: f64,
) -> Result<ResolvedDesign, String> {
    let fail = |e: TheoryError| format!("pair_coeff {label} eta {} sc {}: {e}", g(eta), g(sc));
    let fluid = Fluid::new(dim, density, rc, mass, kt)
        .and_then(|f| f.with_mvv2e(mvv2e))
        .map_err(fail)?;
    let design = theory::design_from_targets(&Targets { fluid, eta, sc }).map_err(fail)?;
    let tr = theory::kinetic_theory(&fluid, design.gamma, design.s).map_err(fail)?;
    use crate::fmtnum::fixed;
    let message = format!(
        "pair_coeff {label}: eta {eta} sc {sc} at n = {} (N/V), m = {mass}, kT = {kt}, \
         rc = {rc}, d = {dim} -> gamma0 = {}, weight s = {} (kinetic theory: eta_D = {}, \
         eta_K = {}, D = {}, Sc = {}; ideal fluid, a = 0)",
        fixed(density, 10),
        fixed(design.gamma, 10),
        fixed(design.s, 10),
        fixed(tr.eta_d, 6),
        fixed(tr.eta_k, 6),
        fixed(tr.diffusion, 6),
        fixed(tr.schmidt, 6)
    );
    Ok(ResolvedDesign {
        gamma: design.gamma,
        s: design.s,
        message,
    })
}

/// Check that every designed pair implies the same exponent (it is global in `pair_style
/// dpd/nonlinear`'s weight and `pair_style sdpd`'s kernel; `style` names the style, `what` its
/// exponent's owner, "weight" or "kernel").
/// `designs` holds (pair label, s); `current` is the pair style's exponent. Returns the common
/// s and, when it differs from `current`, the line to log.
pub(crate) fn common_exponent(
    style: &str,
    what: &str,
    designs: &[(String, f64)],
    current: f64,
) -> Result<Option<(f64, Option<String>)>, String> {
    let Some((first_label, s0)) = designs.first() else {
        return Ok(None);
    };
    for (label, s) in &designs[1..] {
        if (s - s0).abs() > 1e-12 * s0.abs().max(1.0) {
            return Err(format!(
                "the (eta, sc) targets of pairs {first_label} and {label} need different {what} \
                 exponents (s = {s0} and s = {s}), but the {what} exponent of pair_style \
                 {style} is one for all pairs: give every pair the same targets and cut-off, \
                 or set the coefficients explicitly"
            ));
        }
    }
    let note = (current != *s0).then(|| {
        format!(
            "pair_style {style}: {what} exponent s = {s0:.10} from the (eta, sc) design \
             replaces {current} for every pair"
        )
    });
    Ok(Some((*s0, note)))
}

/// The warning for an Euler (`fix nve/euler`) run, or `None` when the step is small enough
/// (δt ≤ [`EULER_WARN_DT_FRACTION`] δt_c and predicted heating ≤ [`EULER_WARN_HEATING`]).
///
/// The prediction is eq. 22 for the ideal fluid at number density `density` with friction
/// `gamma` (the largest `gamma0` of the run), weight exponent `s`, cut-off `rc` and the lightest
/// mass `mass`. `conservative` says some pair has a ≠ 0 and `nonlinear` that the friction grows
/// with velocity (cross/dot): both make eq. 22 a rougher guide, and the text says so. `mvv2e`
/// is the unit style's (1 in `units lj`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn euler_warning(
    dim: u32,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
    mvv2e: f64,
    gamma: f64,
    s: f64,
    dt: f64,
    conservative: bool,
    nonlinear: bool,
) -> Result<Option<String>, String> {
    if gamma <= 0.0 {
        return Ok(None);
    }
    let fluid = Fluid::new(dim, density, rc, mass, kt)
        .and_then(|f| f.with_mvv2e(mvv2e))
        .map_err(|e| e.to_string())?;
    let dt_c = theory::euler_critical_dt(&fluid, gamma, s).map_err(|e| e.to_string())?;
    let frac = dt / dt_c;
    let mut caveats = String::new();
    if conservative {
        caveats.push_str(" Eq. 22 is for the ideal fluid (a = 0); here a != 0.");
    }
    if nonlinear {
        caveats.push_str(
            " It uses gamma0, the zero-velocity friction; the non-linear friction is larger.",
        );
    }
    let params = format!(
        "n = {density:.6}, gamma = {gamma:.6}, s = {s:.6}, rc = {rc}, m = {mass}, d = {dim}"
    );
    if frac >= 1.0 {
        return Ok(Some(format!(
            "Euler step dt = {dt} >= dt_c = {dt_c:.6} (finite-step paper eq. 25, {params}): the \
             ideal fluid has no equilibrium temperature at this step and will heat without bound. \
             Use dt < {:.6} (0.1 dt_c) or velocity-Verlet (fix nve).{caveats}",
            EULER_WARN_DT_FRACTION * dt_c
        )));
    }
    let ratio = 1.0 / (1.0 - frac);
    // eq. 22 as 2 / (2 − (A1 n + A2/A1) δt) = 1 / (1 − δt/δt_c); computed the long way too:
    let ratio_eq22 = theory::euler_temperature_ratio(&fluid, gamma, s, dt).unwrap_or(ratio);
    if frac <= EULER_WARN_DT_FRACTION && ratio_eq22 - 1.0 <= EULER_WARN_HEATING {
        return Ok(None);
    }
    Ok(Some(format!(
        "Euler step dt = {dt} is {:.3} dt_c (dt_c = {dt_c:.6}, eq. 25; {params}): eq. 22 predicts \
         T_eq/T0 = {ratio_eq22:.4} (+{:.1}% heating). Measured in 2-D ideal fluids \
         (docs/theory.md): the heating was 0.7-1.0 times eq. 22's up to 0.2 dt_c, and dense \
         fluids went unstable well below dt_c (n = 16: from 0.2-0.25 dt_c; n = 4: from 0.3-0.4 dt_c). \
         Reduce dt or use fix nve.{caveats}",
        frac,
        100.0 * (ratio_eq22 - 1.0)
    )))
}

/// The box check of every run's set-up, in both engines: along each periodic dimension the box
/// must be at least r_c long. Shorter, an atom would interact with its own periodic image,
/// which the keyed noise cannot tell from its partner (both tags equal). Between r_c and 2 r_c
/// a pair can interact with two or more images of its partner at once: each image draws its
/// own keyed number ([`crate::rng::ImageFrame`], `docs/models.md` P-4b). `len` are the box
/// lengths, `periodic` which of the first `dim` dimensions are periodic.
pub fn check_box_images(
    len: [f64; 3],
    periodic: [bool; 3],
    dim: usize,
    rc_max: f64,
) -> Result<(), String> {
    for d in 0..dim.min(3) {
        if periodic[d] && len[d] < rc_max {
            return Err(format!(
                "box length {} in {} is shorter than the largest cut-off rc = {}: an atom would \
                 interact with its own periodic image",
                len[d],
                ["x", "y", "z"][d],
                rc_max
            ));
        }
    }
    Ok(())
}

/// Whether a pair can meet more than one periodic image of its partner: some periodic box
/// length below 2 r_c (then the pair loops key the noise by image, P-4b). Box lengths, not
/// widths, decide it for a tilted box too: two images differ by a lattice vector, which is at
/// least one box length long ([`crate::rng::ImageFrame`]).
pub fn images_keyed(len: [f64; 3], periodic: [bool; 3], dim: usize, rc_max: f64) -> bool {
    (0..dim.min(3)).any(|d| periodic[d] && len[d] < 2.0 * rc_max)
}
