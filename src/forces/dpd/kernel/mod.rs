//! Pure pair kernels of DPD with non-linear friction.
//!
//! One call, [`pair_force`], takes everything a pair needs ([`PairInput`], the pair's
//! [`PairCoeff`] and the global [`PairModel`]) and returns the force parts separately
//! ([`PairForce`]). Every DPD pair force is central, so each part is a scalar projection on
//! e_ij = r_ij / r: the force on i due to j is `F_ij = (fc + fd + fr + fa) e_ij`, and
//! `F_ji = −F_ij` holds exactly because the engine applies the same numbers with opposite sign.
//!
//! Conventions: r_ij = r_i − r_j, v_ij = v_i − v_j (minimum image, and under Lees–Edwards the
//! boundary velocity jump, already applied by the caller). Vectors are 3-component; a 2-D caller
//! passes z = 0, and every formula below reduces to its 2-D form (the cross estimator becomes
//! (x v_y − y v_x)²). Units are LAMMPS's: forces in force units, velocities in velocity units,
//! kT in energy units; where a force × time / mass becomes a velocity (the two-step kick, the
//! correction of `noise corrected`) the model's [`PairModel::ftm2v`] converts (1 in `units lj`,
//! [`crate::units`]).
//! Sections (§) refer to `docs/models.md`; equation numbers ("eq. 32") are the non-linear
//! paper's (Naseri, Salueña Perez & Bonet Avalos, PCCP 2025), labelled NL-32 … there, unless
//! stated.

use crate::forces::lanes::{BATCH, Isa, NoiseDist, PairBatch, cross, dot, in_range};

/// The dissipative weight w_D(r) = (1 − r/r_c)^s and w_R = sqrt(w_D) (§1.1; non-linear
/// paper eq. 10 for s = 2; weighting-function paper eq. 43/58 for general s > 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weight {
    s: f64,
}

impl Weight {
    /// The usual DPD weight, s = 2.
    pub const STANDARD: Weight = Weight { s: 2.0 };

    /// A weight of exponent `s`; `None` unless `s` is finite and > 0.
    pub fn new(s: f64) -> Option<Weight> {
        (s.is_finite() && s > 0.0).then_some(Weight { s })
    }

    /// The exponent s.
    pub fn exponent(&self) -> f64 {
        self.s
    }

    /// `(w_D, w_R)` at `q = 1 − r/r_c ∈ (0, 1]`.
    #[inline(always)]
    pub fn wd_wr(&self, q: f64) -> (f64, f64) {
        if self.s == 2.0 {
            (q * q, q)
        } else if self.s == 1.0 {
            (q, q.sqrt())
        } else {
            let wr = q.powf(0.5 * self.s);
            (wr * wr, wr)
        }
    }
}

impl Default for Weight {
    fn default() -> Self {
        Weight::STANDARD
    }
}

/// The friction model γ(S) with its pairwise strain-rate estimator S(r_ij, v_ij) (§1.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Friction {
    /// Constant friction γ = γ0 (standard DPD; γ1 is ignored).
    #[default]
    None,
    /// γ = γ0 exp(−γ1 S×), S× = |r_ij × v_ij|² (eqs. 28, 30).
    Cross,
    /// γ = γ0 exp(−γ1 S·), S· = (r_ij · v_ij)² (eqs. 29, 30).
    Dot,
}

impl Friction {
    /// The strain-rate estimator S_ij (eq. 28 or 29); 0 for `None`.
    #[inline(always)]
    pub fn rate(self, dr: [f64; 3], dv: [f64; 3]) -> f64 {
        match self {
            Friction::None => 0.0,
            Friction::Cross => {
                let c = cross(dr, dv);
                dot(c, c)
            }
            Friction::Dot => {
                let d = dot(dr, dv);
                d * d
            }
        }
    }

    /// e_ij · ∂S/∂v_ij, the projection of the estimator's velocity gradient on the pair axis.
    /// For dot: 2 (r_ij · v_ij) r = 2 r² (e_ij · v_ij). For cross: ∂S/∂v = 2 (r × v) × r is
    /// perpendicular to r_ij, so 0 (eq. 72). For none: 0.
    #[inline(always)]
    pub fn rate_gradient_along_e(self, r: f64, rdotv: f64) -> f64 {
        match self {
            Friction::None | Friction::Cross => 0.0,
            Friction::Dot => 2.0 * rdotv * r,
        }
    }

    /// γ(S) = γ0 exp(−γ1 S) (eq. 30); γ0 for `None`. The exponential is [`exp`] (fdlibm's,
    /// evaluated here, so both engines and every machine get the same bits).
    #[inline(always)]
    pub fn gamma(self, c: &PairCoeff, s: f64) -> f64 {
        match self {
            Friction::None => c.gamma0,
            Friction::Cross | Friction::Dot => c.gamma0 * exp(-c.gamma1 * s),
        }
    }

    /// dγ/dS given γ(S): −γ1 γ for the exponential models, 0 for `None`.
    #[inline(always)]
    pub fn dgamma_ds(self, c: &PairCoeff, gamma: f64) -> f64 {
        match self {
            Friction::None => 0.0,
            Friction::Cross | Friction::Dot => -c.gamma1 * gamma,
        }
    }

    /// The keyword used by `pair_style … friction KEYWORD`.
    pub fn keyword(self) -> &'static str {
        match self {
            Friction::None => "none",
            Friction::Cross => "cross",
            Friction::Dot => "dot",
        }
    }

    /// Parse a `friction` keyword value.
    pub fn from_keyword(s: &str) -> Option<Friction> {
        match s {
            "none" => Some(Friction::None),
            "cross" => Some(Friction::Cross),
            "dot" => Some(Friction::Dot),
            _ => None,
        }
    }
}

/// How the random force is built for a velocity-dependent friction (§1.3–1.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Noise {
    /// σ² = 2 kT γ(S_ij) at the state at t (eq. 31). Exact for `cross`, biased for `dot`.
    #[default]
    Plain,
    /// Plain noise plus the spurious-drift correction F^A (eq. 32, Appendix A).
    Corrected,
    /// The derivative-free two-step algorithm (eqs. 33–38), pair-local intermediate velocity.
    TwoStep,
}

impl Noise {
    /// The keyword used by `pair_style … noise KEYWORD`.
    pub fn keyword(self) -> &'static str {
        match self {
            Noise::Plain => "plain",
            Noise::Corrected => "corrected",
            Noise::TwoStep => "twostep",
        }
    }

    /// Parse a `noise` keyword value.
    pub fn from_keyword(s: &str) -> Option<Noise> {
        match s {
            "plain" => Some(Noise::Plain),
            "corrected" => Some(Noise::Corrected),
            "twostep" => Some(Noise::TwoStep),
            _ => None,
        }
    }
}

/// Per type-pair coefficients (`pair_coeff I J a gamma0 gamma1 [rc]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairCoeff {
    /// Conservative strength a_ij (0 = ideal DPD).
    pub a: f64,
    /// Friction at zero strain rate γ0 ≥ 0.
    pub gamma0: f64,
    /// Shear-thinning coefficient γ1 ≥ 0 of γ0 exp(−γ1 S).
    pub gamma1: f64,
    /// Cut-off r_c > 0.
    pub rc: f64,
}

impl PairCoeff {
    /// The conservative part alone at squared distance `rsq`, as LAMMPS's `pair dpd`
    /// `single()` returns it: (F/r, E) = (a (1 − r/r_c) / r, a r_c (1 − r/r_c)² / 2), and
    /// (0, 0) at r ≥ r_c (docs/models.md §1.1).
    pub fn conservative(&self, rsq: f64) -> (f64, f64) {
        if rsq >= self.rc * self.rc {
            return (0.0, 0.0);
        }
        let r = rsq.sqrt();
        let wr = 1.0 - r / self.rc;
        let fpair = if r > 0.0 { self.a * wr / r } else { 0.0 };
        (fpair, 0.5 * self.a * self.rc * wr * wr)
    }

    /// Check the ranges the kernel relies on; the message names the offending parameter.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |name: &str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(format!("{name} = {x} is not a finite number"))
            }
        };
        finite("a", self.a)?;
        finite("gamma0", self.gamma0)?;
        finite("gamma1", self.gamma1)?;
        finite("rc", self.rc)?;
        if self.gamma0 < 0.0 {
            return Err(format!("gamma0 = {} must be >= 0", self.gamma0));
        }
        if self.gamma1 < 0.0 {
            return Err(format!("gamma1 = {} must be >= 0", self.gamma1));
        }
        if self.rc <= 0.0 {
            return Err(format!("rc = {} must be > 0", self.rc));
        }
        Ok(())
    }
}

/// The global part of the model: `pair_style dpd/nonlinear T rc seed [friction] [noise] [weight]`
/// plus the time step the random force is scaled with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairModel {
    /// Thermostat temperature kT (>= 0; 0: no random force or correction, the friction kept).
    pub kt: f64,
    /// Friction model.
    pub friction: Friction,
    /// Noise scheme.
    pub noise: Noise,
    /// Weight w_D = (1 − r/r_c)^s.
    pub weight: Weight,
    /// Distribution of ξ_ij (Gaussian unless set with [`PairModel::with_dist`]).
    pub dist: NoiseDist,
    sqrt_dt: f64,
    inv_sqrt_dt: f64,
    /// force × time / mass → velocity (LAMMPS's `force->ftm2v`; 1 in `units lj`).
    ftm2v: f64,
}

impl PairModel {
    /// A model for time step `dt` (> 0). Call [`PairModel::set_timestep`] when δt changes.
    pub fn new(kt: f64, friction: Friction, noise: Noise, weight: Weight, dt: f64) -> PairModel {
        let mut m = PairModel {
            kt,
            friction,
            noise,
            weight,
            dist: NoiseDist::Gaussian,
            sqrt_dt: 1.0,
            inv_sqrt_dt: 1.0,
            ftm2v: 1.0,
        };
        m.set_timestep(dt);
        m
    }

    /// The same model in a unit style whose force × time / mass is `ftm2v` velocity units
    /// (LAMMPS's `force->ftm2v`; [`crate::units::Units::ftm2v`]). Every model starts with 1,
    /// `units lj`.
    pub fn with_ftm2v(mut self, ftm2v: f64) -> PairModel {
        self.ftm2v = ftm2v;
        self
    }

    /// Set the force × time / mass → velocity factor (see [`PairModel::with_ftm2v`]).
    pub fn set_ftm2v(&mut self, ftm2v: f64) {
        self.ftm2v = ftm2v;
    }

    /// The force × time / mass → velocity factor of the model's unit style.
    pub fn ftm2v(&self) -> f64 {
        self.ftm2v
    }

    /// The same model with ξ_ij drawn from `dist`.
    pub fn with_dist(mut self, dist: NoiseDist) -> PairModel {
        self.dist = dist;
        self
    }

    /// Set δt: the random force scales as δt^(−1/2) (§1.1), the two-step impulse as δt^(1/2).
    pub fn set_timestep(&mut self, dt: f64) {
        self.sqrt_dt = dt.sqrt();
        self.inv_sqrt_dt = 1.0 / self.sqrt_dt;
    }

    /// δt^(−1/2), the random force's factor.
    #[inline(always)]
    pub(crate) fn inv_sqrt_dt(&self) -> f64 {
        self.inv_sqrt_dt
    }

    /// The time step this model was set for.
    pub fn timestep(&self) -> f64 {
        self.sqrt_dt * self.sqrt_dt
    }
}

/// What one pair needs at one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairInput {
    /// r_ij = r_i − r_j (minimum image).
    pub dr: [f64; 3],
    /// v_ij = v_i − v_j (with any Lees–Edwards velocity jump).
    pub dv: [f64; 3],
    /// 1/m_i + 1/m_j.
    pub inv_mass_sum: f64,
    /// The pair's variate ξ_ij, zero mean and unit variance ([`NoiseDist::pair_xi`]).
    pub xi: f64,
}

/// The force parts of one pair, as projections on e_ij (force on i: `total() · e_ij`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairForce {
    /// Conservative a (1 − r/r_c).
    pub fc: f64,
    /// Dissipative −γ(S) w_D (e_ij · v_ij).
    pub fd: f64,
    /// Random σ(S) w_R ξ δt^(−1/2) (plain/corrected: S at t; two-step: S'' of eq. 36).
    pub fr: f64,
    /// Spurious-drift correction F^A of eq. 32 (`corrected` only; 0 otherwise).
    pub fa: f64,
    /// Conservative pair energy a r_c (1 − r/r_c)² / 2 (as LAMMPS `pair dpd`).
    pub energy: f64,
    /// 1/r, so a caller turns a projection into a vector as `part · inv_r · r_ij`.
    pub inv_r: f64,
}

impl PairForce {
    /// The sum of all parts along e_ij.
    #[inline(always)]
    pub fn total(&self) -> f64 {
        self.fc + self.fd + self.fr + self.fa
    }

    /// The total force on i as a vector, given r_ij.
    #[inline(always)]
    pub fn vector(&self, dr: [f64; 3]) -> [f64; 3] {
        let s = self.total() * self.inv_r;
        [s * dr[0], s * dr[1], s * dr[2]]
    }
}

/// All force parts of one pair (§1.1–1.4). Zero for r ≥ r_c or r < `MIN_PAIR_DISTANCE`.
///
/// - conservative F^C = a (1 − r/r_c) e (§1.1);
/// - dissipative F^D = −γ(S) w_D (e · v) e, S at t (§1.1, eq. 30, and eq. 38 for two-step);
/// - random: `plain`/`corrected` use σ² = 2 kT γ(S) (eq. 31); `twostep` draws the impulse
///   δp1 = sqrt(2 kT γ(S) w_D) ξ δt^(1/2), forms the pair-local v'' = v + (1/m_i + 1/m_j) δp1 e
///   (eq. 35; × ftm2v, [`PairModel::ftm2v`]), S'' = S(r, v'') (eq. 36) and uses
///   sqrt(2 kT γ(S'') w_D) ξ δt^(−1/2) (eq. 37);
/// - correction (`corrected`, eq. 32): F^A = kT ftm2v (1/m_i + 1/m_j) w_D (e · ∂γ/∂v) ξ², with
///   e · ∂γ/∂v = γ'(S) (e · ∂S/∂v); nonzero only for `dot`.
///
/// Evaluation (exact in arithmetic, rounded differently from the literal formulas): γ and σ
/// come from one exponential e = exp(−γ1 S/2) as γ0 e² and sqrt(2 kT γ0) e; q = 1 − r · (1/r_c);
/// in `twostep`, S'' = S for `cross` (the kick is along r_ij) and (r · v + κ r²)² for `dot`.
///
/// [`pair_forces_batch`] evaluates the same function on many pairs at once, bit for bit.
#[inline(always)]
pub fn pair_force(model: &PairModel, c: &PairCoeff, p: &PairInput) -> PairForce {
    let rsq = dot(p.dr, p.dr);
    if !in_range(rsq, c.rc) {
        return PairForce::default();
    }
    let d = Derived::new(model, c);
    pair_parts(
        model.friction,
        model.noise,
        |q| model.weight.wd_wr(q),
        model,
        c,
        &d,
        p,
        rsq,
    )
}

/// Per type-pair constants of [`pair_parts`], computed once per type pair by the batch
/// ([`PairTable`]) and once per call by [`pair_force`], with the same operations, so both give
/// the same bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Derived {
    /// 1 / r_c (so that q = 1 − r · (1/r_c)).
    pub(crate) inv_rc: f64,
    /// sqrt(2 kT γ0): σ of constant friction (eq. 31 with γ = γ0).
    pub(crate) sigma0: f64,
    /// a r_c / 2, the prefactor of the conservative energy.
    pub(crate) half_a_rc: f64,
}

impl Derived {
    #[inline(always)]
    pub(crate) fn new(model: &PairModel, c: &PairCoeff) -> Derived {
        Derived {
            inv_rc: 1.0 / c.rc,
            sigma0: (2.0 * model.kt * c.gamma0).sqrt(),
            half_a_rc: 0.5 * c.a * c.rc,
        }
    }
}

/// The coefficient table of [`pair_forces_batch`]: the caller's [`PairCoeff`]s with their
/// per type-pair constants, prepared once (per force evaluation) for a model.
#[derive(Clone, Debug, Default)]
pub struct PairTable {
    kt: f64,
    coeff: Vec<PairCoeff>,
    derived: Vec<Derived>,
}

impl PairTable {
    /// The table for `model` (its kT enters the constants); index as the caller's `table`.
    pub fn new(model: &PairModel, table: &[PairCoeff]) -> PairTable {
        PairTable {
            kt: model.kt,
            coeff: table.to_vec(),
            derived: table.iter().map(|c| Derived::new(model, c)).collect(),
        }
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.coeff.len()
    }

    /// True when there are no entries.
    pub fn is_empty(&self) -> bool {
        self.coeff.is_empty()
    }
}

/// The body of [`pair_force`] for a pair in range, with the model's three choices passed
/// separately so that [`pair_forces_batch`] can fix them at compile time. It runs the stages
/// [`geom`], [`friction_at`], [`twostep_rate`] and [`assemble`]; the batch runs the same stages
/// as separate loops over its pairs (same operations, so every bit of the result is the same).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn pair_parts(
    friction: Friction,
    noise: Noise,
    weight: impl Fn(f64) -> (f64, f64),
    model: &PairModel,
    c: &PairCoeff,
    d: &Derived,
    p: &PairInput,
    rsq: f64,
) -> PairForce {
    let g = geom(friction, weight, d, p, rsq);
    let (gamma, sigma) = friction_at(friction, c, d, g.s);
    let sigma2 = if noise == Noise::TwoStep {
        friction_at(
            friction,
            c,
            d,
            twostep_rate(friction, model, &g, sigma, p, rsq),
        )
        .1
    } else {
        sigma
    };
    assemble(friction, noise, model, c, d, p, &g, gamma, sigma, sigma2)
}

/// Stage 1: the pair's geometry and strain-rate estimator at t.
#[derive(Clone, Copy, Debug)]
struct Geom {
    r: f64,
    inv_r: f64,
    /// q = 1 − r/r_c, evaluated as 1 − r · (1/r_c).
    q: f64,
    wd: f64,
    wr: f64,
    rdotv: f64,
    /// S(r_ij, v_ij) (eq. 28 or 29).
    s: f64,
}

#[inline(always)]
fn geom(
    friction: Friction,
    weight: impl Fn(f64) -> (f64, f64),
    d: &Derived,
    p: &PairInput,
    rsq: f64,
) -> Geom {
    let r = rsq.sqrt();
    let inv_r = 1.0 / r;
    let q = 1.0 - r * d.inv_rc;
    let (wd, wr) = weight(q);
    Geom {
        r,
        inv_r,
        q,
        wd,
        wr,
        rdotv: dot(p.dr, p.dv),
        s: friction.rate(p.dr, p.dv),
    }
}

/// Stage 2: γ(S) = γ0 exp(−γ1 S) (eq. 30) and σ(S) = sqrt(2 kT γ(S)) (eq. 31) from one
/// exponential: with e = exp(−γ1 S / 2), γ = γ0 e² and σ = σ0 e, σ0 = sqrt(2 kT γ0) (the type
/// pair's constant). No square root per pair, and σ² = 2 kT γ to rounding.
#[inline(always)]
fn friction_at(friction: Friction, c: &PairCoeff, d: &Derived, s: f64) -> (f64, f64) {
    match friction {
        Friction::None => (c.gamma0, d.sigma0),
        Friction::Cross | Friction::Dot => {
            let e = exp(-0.5 * c.gamma1 * s);
            (c.gamma0 * (e * e), d.sigma0 * e)
        }
    }
}

/// Stage 3 (`twostep`): S'' (eq. 36) after the pair-local kick v'' = v + κ r_ij with
/// κ = (1/m_i + 1/m_j) ftm2v δp1 / r and δp1 = σ(S) w_R ξ δt^(1/2) (eqs. 34–35; the impulse δp1
/// is a force × time, ftm2v makes (1/m) δp1 a velocity, 1 in `units lj`). The kick is along
/// r_ij, so S''× = |r × v''|² = S× exactly, and S''· = (r · v + κ r²)².
#[inline(always)]
fn twostep_rate(
    friction: Friction,
    model: &PairModel,
    g: &Geom,
    sigma: f64,
    p: &PairInput,
    rsq: f64,
) -> f64 {
    let dp1 = sigma * g.wr * p.xi * model.sqrt_dt;
    let kick = p.inv_mass_sum * model.ftm2v * dp1 * g.inv_r;
    match friction {
        Friction::None | Friction::Cross => g.s,
        Friction::Dot => {
            let rdv2 = g.rdotv + kick * rsq;
            rdv2 * rdv2
        }
    }
}

/// Stage 4: the force parts. `sigma2` is σ(S'') for `twostep` (eq. 37), unused otherwise.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn assemble(
    friction: Friction,
    noise: Noise,
    model: &PairModel,
    c: &PairCoeff,
    d: &Derived,
    p: &PairInput,
    g: &Geom,
    gamma: f64,
    sigma: f64,
    sigma2: f64,
) -> PairForce {
    let ev = g.rdotv * g.inv_r;
    let fc = c.a * g.q;
    let fd = -gamma * g.wd * ev;
    let (fr, fa) = match noise {
        Noise::Plain => (sigma * g.wr * p.xi * model.inv_sqrt_dt, 0.0),
        Noise::Corrected => {
            let fr = sigma * g.wr * p.xi * model.inv_sqrt_dt;
            let de_gamma =
                friction.dgamma_ds(c, gamma) * friction.rate_gradient_along_e(g.r, g.rdotv);
            // kT (1/m_i + 1/m_j) ftm2v: kT/m as a squared velocity (1 in `units lj`).
            (
                fr,
                model.kt * model.ftm2v * p.inv_mass_sum * g.wd * de_gamma * p.xi * p.xi,
            )
        }
        Noise::TwoStep => (sigma2 * g.wr * p.xi * model.inv_sqrt_dt, 0.0),
    };
    PairForce {
        fc,
        fd,
        fr,
        fa,
        energy: d.half_a_rc * g.q * g.q,
        inv_r: g.inv_r,
    }
}

/// e^x: fdlibm's `__ieee754_exp` (error < 1 ulp) written as straight-line code, so that a batch
/// of pairs vectorises and every machine gets the same bits (no libm call). Overflows to +∞
/// above 709.78, underflows to 0 below −745.13 (results below 2⁻¹⁰²² are rounded twice), NaN
/// stays NaN.
// The constants are fdlibm's, digit for digit.
#[allow(clippy::excessive_precision)]
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    const INV_LN2: f64 = std::f64::consts::LOG2_E;
    const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
    const P1: f64 = 1.666_666_666_666_660_190_37e-1;
    const P2: f64 = -2.777_777_777_701_559_338_42e-3;
    const P3: f64 = 6.613_756_321_437_934_361_17e-5;
    const P4: f64 = -1.653_390_220_546_525_153_90e-6;
    const P5: f64 = 4.138_136_797_057_238_460_39e-8;
    // 1.5 · 2⁵²: adding it rounds to an integer, whose value sits in the low mantissa bits.
    const BIAS: f64 = 6_755_399_441_055_744.0;
    let xc = x.clamp(-746.0, 710.0);
    // k = round(x / ln 2) (ties to even; fdlibm rounds them away from 0, which changes only
    // which of two equally good reductions is used). |k| ≤ 1077.
    let kb = xc * INV_LN2 + BIAS;
    let kf = kb - BIAS;
    let k = kb.to_bits() as i64 - BIAS.to_bits() as i64;
    let hi = xc - kf * LN2_HI;
    let lo = kf * LN2_LO;
    let r = hi - lo;
    let t = r * r;
    let c = r - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
    let y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi);
    // y · 2^k as y · 2^k1 · 2^k2 (both factors normal; exact unless the result is subnormal).
    let k1 = k >> 1;
    let k2 = k - k1;
    let two = |e: i64| f64::from_bits(((e + 1023) as u64) << 52);
    y * two(k1) * two(k2)
}

mod batch;
pub use batch::*;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::keyed_uniform;

    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    /// [`exp`] against libm on [−745, 709.7] (normal results) and on the friction range
    /// [−50, 0]: both are fdlibm-grade (< 1 ulp from the exact value), so they may differ by
    /// 1 ulp where the exact value falls between two doubles.
    #[test]
    fn exp_matches_libm() {
        let mut worst = 0;
        for k in 0..300_000u32 {
            let u = keyed_uniform(1, 2, u64::from(k), 3, 4);
            for x in [-745.0 + 1454.7 * u, -50.0 * u, -1e-3 * u, 1e-9 * (u - 0.5)] {
                let (a, b) = (exp(x), x.exp());
                if b < f64::MIN_POSITIVE {
                    // Subnormal results: both round twice or once; only closeness matters.
                    assert!(
                        (a - b).abs() <= 2.0 * f64::from_bits(1),
                        "exp({x}) = {a} vs {b}"
                    );
                    continue;
                }
                worst = worst.max(ulps(a, b));
            }
        }
        assert!(worst <= 1, "exp differs from libm by {worst} ulp");
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-800.0), 0.0);
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert_eq!(exp(710.0), f64::INFINITY);
        assert!(exp(f64::NAN).is_nan());
    }

    /// The batch gives exactly `pair_force`'s bits for every friction, noise and weight, with
    /// each instruction set this CPU has; pairs out of range give 0.
    #[test]
    fn batch_is_bit_identical_to_pair_force() {
        let table = [
            PairCoeff {
                a: 25.0,
                gamma0: 4.5,
                gamma1: 0.7,
                rc: 1.0,
            },
            PairCoeff {
                a: 0.0,
                gamma0: 5.0,
                gamma1: 1.3,
                rc: 0.8,
            },
        ];
        let isas: Vec<Isa> = [Isa::Baseline, Isa::Avx2, Isa::Avx512]
            .into_iter()
            .filter(|&i| (i as u8) <= (Isa::best_supported() as u8))
            .collect();
        let u = |k: u32, c: u32| keyed_uniform(77, c, u64::from(k), 1, 2);
        let mut compared = 0;
        for friction in [Friction::None, Friction::Cross, Friction::Dot] {
            for noise in [Noise::Plain, Noise::Corrected, Noise::TwoStep] {
                for (s, dist) in [
                    (2.0, NoiseDist::Gaussian),
                    (1.0, NoiseDist::Gaussian),
                    (1.5, NoiseDist::Gaussian),
                    (2.0, NoiseDist::Uniform),
                    (0.5, NoiseDist::Uniform),
                ] {
                    let model =
                        PairModel::new(0.7, friction, noise, Weight::new(s).expect("s > 0"), 0.01)
                            .with_dist(dist);
                    for &isa in &isas {
                        let mut b = PairBatch {
                            len: BATCH - 3,
                            ..Default::default()
                        };
                        let mut want = Vec::new();
                        for l in 0..b.len {
                            let k = l as u32 + 1000 * (s as u32);
                            let dr = [0, 1, 2].map(|c| 2.4 * u(k, c) - 1.2);
                            let dv = [0, 1, 2].map(|c| 6.0 * u(k, c + 3) - 3.0);
                            let ims = 0.5 + u(k, 6);
                            let coeff = (k % 2) as usize;
                            let (ti, tj) = (k + 1, 7 * k + 3);
                            for c in 0..3 {
                                b.dr[c][l] = dr[c];
                                b.dv[c][l] = dv[c];
                            }
                            b.inv_mass_sum[l] = ims;
                            b.coeff[l] = coeff as u32;
                            b.tag_i[l] = ti;
                            b.tag_j[l] = tj;
                            let input = PairInput {
                                dr,
                                dv,
                                inv_mass_sum: ims,
                                xi: dist.pair_xi(99, 12345, ti, tj),
                            };
                            let pf = pair_force(&model, &table[coeff], &input);
                            want.push((pf.total() * pf.inv_r, pf.energy));
                        }
                        pair_forces_batch_isa(
                            isa,
                            &model,
                            &PairTable::new(&model, &table),
                            99,
                            12345,
                            &mut b,
                        );
                        let mut inside = 0;
                        for (l, &(fp, e)) in want.iter().enumerate() {
                            assert_eq!(
                                (b.fpair[l].to_bits(), b.energy[l].to_bits()),
                                (fp.to_bits(), e.to_bits()),
                                "{friction:?}/{noise:?}/s={s}/{dist:?}/{isa:?}, pair {l}"
                            );
                            inside += usize::from(fp != 0.0);
                            compared += 1;
                        }
                        assert!(inside > 5 && inside < want.len(), "mixed in/out of range");
                    }
                }
            }
        }
        assert!(compared > 0);
    }
}
