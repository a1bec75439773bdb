//! `dpdnl design` and `dpdnl theory` results and their JSON (`--json`, and the Python
//! package's dicts). The structs ending in `Json` are serialised with serde: their fields are
//! the keys, in the order `--json` prints them ([`super::to_line`]).

use crate::forces::DesignMethod;
use crate::forces::plan::{DesignInputs, PairPlan, PairTheory};
use crate::theory::sdpd::Smoothing;
use crate::theory::vv_measured::vv_verdict;
use crate::theory::{
    Design, DesignMode, Dim, Fluid, Targets, TheoryError, Transport, design_from_targets,
    design_paper_approx, euler_critical_density, euler_critical_dt, euler_temperature_ratio,
    kinetic_theory, sdpd,
};
use serde::Serialize;

/// The fluid from the command line's numbers (`dim` checked to be 2 or 3).
pub fn fluid_of(dim: i64, density: f64, rc: f64, mass: f64, kt: f64) -> Result<Fluid, TheoryError> {
    let d = u32::try_from(dim)
        .map_err(|_| TheoryError::Parameter {
            name: "dimension d",
            value: dim as f64,
            requirement: "2 or 3",
        })
        .and_then(Dim::new)?;
    Fluid::new(d.get(), density, rc, mass, kt)
}

/// The fluid of the command line in unit style `units` (`--units`, lj by default): kT from
/// `--kt` or, with `--temp T`, boltz T; the theory's mass m·mvv2e ([`Fluid::with_mvv2e`]).
pub fn fluid_in(
    units: &crate::units::Units,
    dim: i64,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
) -> Result<Fluid, TheoryError> {
    fluid_of(dim, density, rc, mass, kt)?.with_mvv2e(units.mvv2e)
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

#[derive(Serialize)]
pub struct FluidJson {
    pub dim: u32,
    pub density: f64,
    pub cutoff: f64,
    pub mass: f64,
    pub kt: f64,
    /// The unit style's mass × velocity² → energy (written only outside `units lj`, where it
    /// is not 1).
    #[serde(skip_serializing_if = "is_one")]
    pub mvv2e: f64,
}

impl From<&Fluid> for FluidJson {
    fn from(f: &Fluid) -> Self {
        FluidJson {
            dim: f.dim.get(),
            density: f.density,
            cutoff: f.cutoff,
            mass: f.mass,
            kt: f.kt,
            mvv2e: f.mvv2e,
        }
    }
}

#[derive(Serialize)]
pub struct TransportJson {
    pub eta_k: f64,
    pub eta_d: f64,
    pub eta: f64,
    pub diffusion: f64,
    pub schmidt: f64,
}

impl From<&Transport> for TransportJson {
    fn from(t: &Transport) -> Self {
        TransportJson {
            eta_k: t.eta_k,
            eta_d: t.eta_d,
            eta: t.eta,
            diffusion: t.diffusion,
            schmidt: t.schmidt,
        }
    }
}

// ---------------------------------------------------------------- design

/// The input lines a design is printed as: a style's design method (its registry entry's,
/// [`crate::forces::design_method`]) and the sound speed where the style has one.
#[derive(Clone, Copy)]
pub struct InputLines {
    /// The method.
    pub method: &'static dyn DesignMethod,
    /// `--c0`: the sound speed of the `pair_coeff` line, for a style that has one.
    pub c0: Option<f64>,
}

impl InputLines {
    /// The lines of `dpdnl design --method NAME`, or `None` when no style is designed so.
    pub fn of(method: &str, c0: Option<f64>) -> Option<InputLines> {
        crate::forces::design_method(method).map(|method| InputLines { method, c0 })
    }
}

/// A design: γ and s for the targets, the kinetic theory's check, the two input lines.
pub struct DesignResult {
    pub fluid: Fluid,
    /// The targets as given (η, Sc; or η0, Sc0 of the paper's approximation).
    pub eta: f64,
    pub sc: f64,
    pub design: Design,
    pub predicted: Transport,
    pub pair_style: String,
    pub pair_coeff: String,
}

/// Designs (γ, s) for `eta`, `sc`: the exact inversion, or the weighting-function paper's
/// approximation η ≈ η0 (`units lj`: the `pair_style` line's T is kT).
pub fn design(
    fluid: Fluid,
    eta: f64,
    sc: f64,
    paper_approx: bool,
    seed: u32,
    lines: InputLines,
) -> Result<DesignResult, TheoryError> {
    design_at(fluid, fluid.kt, eta, sc, paper_approx, seed, lines)
}

/// [`design`] with the `pair_style` line's T given (a temperature outside `units lj`, where
/// kT = boltz T).
pub fn design_at(
    fluid: Fluid,
    temp: f64,
    eta: f64,
    sc: f64,
    paper_approx: bool,
    seed: u32,
    lines: InputLines,
) -> Result<DesignResult, TheoryError> {
    let design = if paper_approx {
        design_paper_approx(&fluid, eta, sc)?
    } else {
        design_from_targets(&Targets { fluid, eta, sc })?
    };
    let predicted = kinetic_theory(&fluid, design.gamma, design.s)?;
    let (pair_style, pair_coeff) = lines.method.lines(
        &design,
        &fluid,
        &DesignInputs {
            temp,
            seed,
            c0: lines.c0,
        },
    );
    Ok(DesignResult {
        fluid,
        eta,
        sc,
        design,
        predicted,
        pair_style,
        pair_coeff,
    })
}

#[derive(Serialize)]
#[serde(untagged)]
pub enum TargetsJson {
    Exact { eta: f64, sc: f64 },
    PaperApprox { eta0: f64, sc0: f64 },
}

#[derive(Serialize)]
pub struct DesignValuesJson {
    pub eta0: f64,
    pub s: f64,
    pub gamma: f64,
}

/// `dpdnl design --json`.
#[derive(Serialize)]
pub struct DesignJson {
    pub command: &'static str,
    pub mode: &'static str,
    pub fluid: FluidJson,
    pub targets: TargetsJson,
    pub design: DesignValuesJson,
    pub predicted: TransportJson,
    pub limits: crate::theory::DesignLimits,
    pub pair_style: String,
    pub pair_coeff: String,
}

impl DesignResult {
    pub fn json(&self) -> DesignJson {
        let (d, lim) = (&self.design, &self.design.limits);
        let (mode, targets) = match d.mode {
            DesignMode::Exact => (
                "exact",
                TargetsJson::Exact {
                    eta: self.eta,
                    sc: self.sc,
                },
            ),
            DesignMode::PaperApprox => (
                "paper-approx",
                TargetsJson::PaperApprox {
                    eta0: self.eta,
                    sc0: self.sc,
                },
            ),
        };
        DesignJson {
            command: "design",
            mode,
            fluid: (&self.fluid).into(),
            targets,
            design: DesignValuesJson {
                eta0: d.eta0,
                s: d.s,
                gamma: d.gamma,
            },
            predicted: (&self.predicted).into(),
            limits: *lim,
            pair_style: self.pair_style.clone(),
            pair_coeff: self.pair_coeff.clone(),
        }
    }
}

// ---------------------------------------------------------------- theory

/// The Euler integrator's finite-step temperature (finite-step paper eqs. 22-26).
#[derive(Serialize, Clone, Copy)]
pub struct Euler {
    pub dt: f64,
    /// dt < dt_c: a finite equilibrium temperature exists.
    pub stable: bool,
    /// T_eq/T0 (None when unstable).
    pub t_ratio: Option<f64>,
    pub dt_c: f64,
    /// The critical density (None when no density is stable at this dt).
    pub n_c: Option<f64>,
}

/// The Euler temperature of (γ, s) at step `dt`.
pub fn euler(fluid: &Fluid, gamma: f64, s: f64, dt: f64) -> Result<Euler, TheoryError> {
    let t_ratio = match euler_temperature_ratio(fluid, gamma, s, dt) {
        Ok(r) => Some(r),
        Err(TheoryError::EulerUnstable { .. }) => None,
        Err(e) => return Err(e),
    };
    let dt_c = euler_critical_dt(fluid, gamma, s)?;
    let n_c = match euler_critical_density(fluid, gamma, s, dt) {
        Ok(n) => Some(n),
        Err(TheoryError::EulerNoStableDensity { .. }) => None,
        Err(e) => return Err(e),
    };
    Ok(Euler {
        dt,
        stable: t_ratio.is_some(),
        t_ratio,
        dt_c,
        n_c,
    })
}

/// `dpdnl theory` without a script: the kinetic theory of (γ, s) and, with a step, the Euler
/// temperature.
pub struct TheoryResult {
    pub fluid: Fluid,
    pub gamma: f64,
    pub s: f64,
    pub predicted: Transport,
    pub euler: Option<Euler>,
}

pub fn theory(
    fluid: Fluid,
    gamma: f64,
    s: f64,
    dt: Option<f64>,
) -> Result<TheoryResult, TheoryError> {
    let predicted = kinetic_theory(&fluid, gamma, s)?;
    let euler = dt.map(|dt| euler(&fluid, gamma, s, dt)).transpose()?;
    Ok(TheoryResult {
        fluid,
        gamma,
        s,
        predicted,
        euler,
    })
}

/// `dpdnl theory --json`.
#[derive(Serialize)]
pub struct TheoryJson {
    pub command: &'static str,
    pub fluid: FluidJson,
    pub gamma: f64,
    pub s: f64,
    pub predicted: TransportJson,
    pub euler: Option<Euler>,
}

impl TheoryResult {
    pub fn json(&self) -> TheoryJson {
        TheoryJson {
            command: "theory",
            fluid: (&self.fluid).into(),
            gamma: self.gamma,
            s: self.s,
            predicted: (&self.predicted).into(),
            euler: self.euler,
        }
    }
}

/// `dpdnl theory --kernel …`: the sDPD kinetic theory of one kernel and η0.
pub struct SdpdTheory {
    pub kernel: Smoothing,
    pub fluid: Fluid,
    pub eta0: f64,
    /// The kernel's coefficient c of η = c m kT n² r_c² / η0 + η0.
    pub c: f64,
    pub predicted: Transport,
    /// The smallest viscosity of this kernel here.
    pub eta_min: f64,
}

pub fn sdpd_theory(fluid: Fluid, kernel: Smoothing, eta0: f64) -> Result<SdpdTheory, TheoryError> {
    let c = sdpd::kinetic_coefficient(fluid.dim, kernel)?;
    let predicted = sdpd::kinetic_theory(&fluid, kernel, eta0)?;
    let eta_min = sdpd::eta_min(&fluid, kernel)?;
    Ok(SdpdTheory {
        kernel,
        fluid,
        eta0,
        c,
        predicted,
        eta_min,
    })
}

/// `dpdnl theory --kernel … --json`.
#[derive(Serialize)]
pub struct SdpdTheoryJson {
    pub command: &'static str,
    pub method: &'static str,
    pub kernel: &'static str,
    pub s: Option<f64>,
    pub fluid: FluidJson,
    pub eta0: f64,
    pub c: f64,
    pub eta_min: f64,
    pub predicted: TransportJson,
}

impl SdpdTheory {
    pub fn json(&self) -> SdpdTheoryJson {
        SdpdTheoryJson {
            command: "theory",
            method: "sdpd",
            kernel: self.kernel.keyword(),
            s: self.kernel.exponent(),
            fluid: (&self.fluid).into(),
            eta0: self.eta0,
            c: self.c,
            eta_min: self.eta_min,
            predicted: (&self.predicted).into(),
        }
    }
}

// ---------------------------------------------------------------- theory SCRIPT

/// `dpdnl theory SCRIPT --json`: one entry per `run`.
#[derive(Serialize)]
pub struct ScriptJson {
    pub command: &'static str,
    pub script: String,
    pub runs: Vec<RunJson>,
}

#[derive(Serialize)]
pub struct RunJson {
    pub first_step: u64,
    pub steps: u64,
    pub dim: u32,
    pub natoms: usize,
    pub density: f64,
    pub kt: Option<f64>,
    pub dt: f64,
    pub integrator: String,
    pub s: Option<f64>,
    pub pairs: Vec<PairJson>,
}

/// One type pair of a run with a prediction, from its style's plan ([`PairPlan`]): `i`, `j`,
/// its coefficients and words, `fluid`, `predicted` and, where the finite-step theory applies
/// ([`crate::forces::plan::PairTheory::finite_step`]), `euler` and `vv_measured` (one of them
/// null: the run's integrator decides which).
pub struct PairJson {
    pub i: usize,
    pub j: usize,
    pub coeffs: Vec<(&'static str, f64)>,
    pub words: Vec<(&'static str, &'static str)>,
    pub fluid: FluidJson,
    pub predicted: TransportJson,
    pub finite_step: Option<(Option<EulerBriefJson>, Option<VvJson>)>,
}

impl PairJson {
    /// The record of `pair`'s prediction `theory`, with the finite-step parts.
    pub fn new(
        pair: &PairPlan,
        theory: &PairTheory,
        finite_step: Option<(Option<EulerBriefJson>, Option<VvJson>)>,
    ) -> PairJson {
        PairJson {
            i: pair.i,
            j: pair.j,
            coeffs: pair.coeffs.clone(),
            words: pair.words.clone(),
            fluid: (&theory.fluid).into(),
            predicted: (&theory.predicted).into(),
            finite_step,
        }
    }
}

impl Serialize for PairJson {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = ser.serialize_map(None)?;
        m.serialize_entry("i", &self.i)?;
        m.serialize_entry("j", &self.j)?;
        for (k, v) in &self.coeffs {
            m.serialize_entry(k, v)?;
        }
        for (k, v) in &self.words {
            m.serialize_entry(k, v)?;
        }
        m.serialize_entry("fluid", &self.fluid)?;
        m.serialize_entry("predicted", &self.predicted)?;
        if let Some((euler, vv)) = &self.finite_step {
            m.serialize_entry("euler", euler)?;
            m.serialize_entry("vv_measured", vv)?;
        }
        m.end()
    }
}

/// The Euler temperature of a run's step (None: unstable) and the critical step.
#[derive(Serialize)]
pub struct EulerBriefJson {
    pub t_ratio: Option<f64>,
    pub dt_c: f64,
}

/// Velocity-Verlet: the measured heating of the nearest measured fluid (never theory).
#[derive(Serialize)]
pub struct VvJson {
    pub verdict: Option<VvVerdictJson>,
    pub x: f64,
    pub dt_over_dtc: f64,
}

#[derive(Serialize)]
pub struct VvVerdictJson {
    pub family: String,
    pub density: f64,
    pub t_ratio: Option<f64>,
    pub one_percent_at: Option<f64>,
}

/// Mean number of neighbours within r_c: n π r_c² (2-D) or n (4/3) π r_c³ (3-D).
pub fn neighbours(fluid: &Fluid) -> f64 {
    let pi = std::f64::consts::PI;
    match fluid.dim {
        Dim::Two => fluid.density * pi * fluid.cutoff * fluid.cutoff,
        Dim::Three => fluid.density * 4.0 / 3.0 * pi * fluid.cutoff.powi(3),
    }
}

/// x = δt √(kT/m) / r_c: a thermal particle's displacement per step in cut-offs.
pub fn step_x(fluid: &Fluid, dt: f64) -> f64 {
    dt * (fluid.kt / fluid.inertia()).sqrt() / fluid.cutoff
}

/// The measured velocity-Verlet heating at step `dt` of the family nearest to `fluid` with
/// weight exponent `s`, as JSON.
pub fn vv_json(fluid: &Fluid, s: f64, dt: f64, dt_c: f64) -> VvJson {
    let x = step_x(fluid, dt);
    let verdict = vv_verdict(fluid.dim.get(), neighbours(fluid), s, x).map(|v| VvVerdictJson {
        family: v.family,
        density: v.density,
        t_ratio: v.t_ratio,
        one_percent_at: v.one_percent_at,
    });
    VvJson {
        verdict,
        x,
        dt_over_dtc: dt / dt_c,
    }
}
