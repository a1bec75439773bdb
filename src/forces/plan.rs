//! What a style reports about a run and a design, through traits each style implements, so
//! that `dpdnl theory SCRIPT`, dry runs and `dpdnl design` never name a style:
//!
//! - [`StylePlan`]: what a run of a style would use, as its set-up resolved it
//!   ([`crate::forces::StyleRecord::plan`]): kT, the words of a run's heading, notes, and each
//!   type pair's coefficients with its kinetic theory ([`PairPlan`]). The defaults are a style
//!   without a thermostat or a kinetic theory: no kT, no pairs, no notes.
//! - [`DesignMethod`]: how a style is designed from target (η, Sc) (`dpdnl design --method`,
//!   the registry entry's `design`): its check and its input lines.
//!
//! The values are typed; the command line and the Python package format them (the text and
//! JSON of `report::theory`).

use std::fmt::Debug;

use crate::forces::SetupNote;
use crate::theory::{Design, Fluid, TheoryError, Transport};

/// The state point a planned run's pairs are predicted at (masses in the theory's units).
#[derive(Clone, Copy, Debug)]
pub struct PlanPoint {
    /// 2 or 3.
    pub dim: u32,
    /// n = N / V.
    pub density: f64,
    /// The lightest mass (the one-mass kinetic theory's m).
    pub mass: f64,
    /// The unit style's m v² → energy factor (1 in `lj`).
    pub mvv2e: f64,
}

impl PlanPoint {
    /// The ideal fluid of this point with cut-off `rc` at `kt`.
    pub fn fluid(&self, rc: f64, kt: f64) -> Result<Fluid, TheoryError> {
        Fluid::new(self.dim, self.density, rc, self.mass, kt)?.with_mvv2e(self.mvv2e)
    }
}

/// What a run of a pair style would use, as its set-up resolved it: what `dpdnl theory
/// SCRIPT` and dry runs read, so that no caller needs to know the style's type.
pub trait StylePlan: Debug + Send + Sync {
    /// kT of the random force (boltz T, an energy); `None` for a style without a thermostat.
    fn kt(&self) -> Option<f64> {
        None
    }
    /// The weight exponent s a run's record shows (`s` of `dpdnl theory SCRIPT --json`), if
    /// the style has one.
    fn weight_exponent(&self) -> Option<f64> {
        None
    }
    /// The style's words at the end of a run's heading (`friction cross, noise plain, weight
    /// s = 2`); `None`: `pair_style NAME`.
    fn summary(&self) -> Option<String> {
        None
    }
    /// Lines a planned run adds after its set-up's notes (why there is no prediction, …).
    fn notes(&self) -> Vec<SetupNote> {
        Vec::new()
    }
    /// Each type pair i ≤ j with coefficients, and its kinetic theory at `at`; none for a
    /// style without a pair-wise kinetic theory.
    fn pairs(&self, _at: &PlanPoint) -> Result<Vec<PairPlan>, TheoryError> {
        Ok(Vec::new())
    }
}

/// One type pair of a plan: its coefficients and, where a kinetic theory applies, its
/// prediction.
#[derive(Clone, Debug)]
pub struct PairPlan {
    /// The types, i ≤ j.
    pub i: usize,
    /// The types, i ≤ j.
    pub j: usize,
    /// What the pair's line adds in parentheses after its types (`sdpd, kernel lucy`), if
    /// anything.
    pub label: Option<String>,
    /// The coefficients, (key, value), in the order they are printed and recorded.
    pub coeffs: Vec<(&'static str, f64)>,
    /// Words recorded after the coefficients (`("kernel", "lucy")`).
    pub words: Vec<(&'static str, &'static str)>,
    /// The prediction, or why there is none (a comment).
    pub theory: Result<PairTheory, String>,
}

/// The kinetic theory of one type pair.
#[derive(Clone, Debug)]
pub struct PairTheory {
    /// The ideal fluid it is of.
    pub fluid: Fluid,
    /// The comment that names the theory and what it leaves out.
    pub title: String,
    /// η_K, η_D, η, D, Sc.
    pub predicted: Transport,
    /// (γ0, s) when the pair's friction is DPD's γ0 w_D with w_D = (1 − r/r_c)^s: the Euler
    /// finite-step temperature (finite-step paper) and the measured velocity-Verlet heating
    /// then apply and are reported; `None`: neither is (the record has no such keys).
    pub finite_step: Option<(f64, f64)>,
}

/// The words of `dpdnl design` a method's input lines read.
#[derive(Clone, Copy, Debug)]
pub struct DesignInputs {
    /// The `pair_style` line's T (a temperature outside `units lj`, where kT = boltz T).
    pub temp: f64,
    /// The seed of the `pair_style` line.
    pub seed: u32,
    /// The sound speed of the `pair_coeff` line, where the style has one (`--c0`).
    pub c0: Option<f64>,
}

/// The check of a design by the style's own kinetic theory.
#[derive(Clone, Debug)]
pub struct DesignCheck {
    /// Values printed before the check (`gamma`), (key, value).
    pub values: Vec<(&'static str, f64)>,
    /// The comment that names the check.
    pub title: String,
    /// The kinetic theory of the designed style.
    pub predicted: Transport,
}

/// How a style is designed from target (η, Sc): the kinetic theory's (η0, s) inversion
/// (`theory::design_from_targets`), checked and printed as the style's input lines.
pub trait DesignMethod: Sync {
    /// The word of `dpdnl design --method`.
    fn method(&self) -> &'static str;
    /// The check of `design` at `fluid` by the style's kinetic theory.
    fn check(&self, design: &Design, fluid: &Fluid) -> Result<DesignCheck, String>;
    /// The comment before the input lines.
    fn lines_note(&self) -> &'static str;
    /// The `pair_style` and `pair_coeff` lines of `design` at `fluid`.
    fn lines(&self, design: &Design, fluid: &Fluid, inputs: &DesignInputs) -> (String, String);
}
