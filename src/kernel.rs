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
//! (x v_y − y v_x)²). Units are whatever the caller uses consistently (LAMMPS `units lj`).
//! Equation numbers refer to `MODELS.md` (copied from the project's spec) and to the non-linear
//! paper (Avalos et al., PCCP 2025) unless stated.

/// Pairs closer than this are skipped (their direction e_ij is undefined), as LAMMPS's DPD does.
pub const MIN_PAIR_DISTANCE: f64 = 1.0e-10;

/// The dissipative weight w_D(r) = (1 − r/r_c)^s and w_R = sqrt(w_D) (MODELS §1; non-linear
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

/// The friction model γ(S) with its pairwise strain-rate estimator S(r_ij, v_ij) (MODELS §2).
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

    /// γ(S) = γ0 exp(−γ1 S) (eq. 30); γ0 for `None`.
    #[inline(always)]
    pub fn gamma(self, c: &PairCoeff, s: f64) -> f64 {
        match self {
            Friction::None => c.gamma0,
            Friction::Cross | Friction::Dot => c.gamma0 * (-c.gamma1 * s).exp(),
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

/// How the random force is built for a velocity-dependent friction (MODELS §2).
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
    /// Thermostat temperature kT (> 0).
    pub kt: f64,
    /// Friction model.
    pub friction: Friction,
    /// Noise scheme.
    pub noise: Noise,
    /// Weight w_D = (1 − r/r_c)^s.
    pub weight: Weight,
    sqrt_dt: f64,
    inv_sqrt_dt: f64,
}

impl PairModel {
    /// A model for time step `dt` (> 0). Call [`PairModel::set_timestep`] when δt changes.
    pub fn new(kt: f64, friction: Friction, noise: Noise, weight: Weight, dt: f64) -> PairModel {
        let mut m = PairModel {
            kt,
            friction,
            noise,
            weight,
            sqrt_dt: 1.0,
            inv_sqrt_dt: 1.0,
        };
        m.set_timestep(dt);
        m
    }

    /// Set δt: the random force scales as δt^(−1/2) (MODELS §1), the two-step impulse as δt^(1/2).
    pub fn set_timestep(&mut self, dt: f64) {
        self.sqrt_dt = dt.sqrt();
        self.inv_sqrt_dt = 1.0 / self.sqrt_dt;
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
    /// The pair's standard Gaussian ξ_ij (see [`crate::rng::pair_gaussian`]).
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

#[inline(always)]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// All force parts of one pair (MODELS §1–2). Zero for r ≥ r_c or r < [`MIN_PAIR_DISTANCE`].
///
/// - conservative F^C = a (1 − r/r_c) e (§1);
/// - dissipative F^D = −γ(S) w_D (e · v) e, S at t (§1, eq. 30, and eq. 38 for two-step);
/// - random: `plain`/`corrected` use σ² = 2 kT γ(S) (eq. 31); `twostep` draws the impulse
///   δp1 = sqrt(2 kT γ(S) w_D) ξ δt^(1/2), forms the pair-local v'' = v + (1/m_i + 1/m_j) δp1 e
///   (eq. 35), S'' = S(r, v'') (eq. 36) and uses sqrt(2 kT γ(S'') w_D) ξ δt^(−1/2) (eq. 37);
/// - correction (`corrected`, eq. 32): F^A = kT (1/m_i + 1/m_j) w_D (e · ∂γ/∂v) ξ², with
///   e · ∂γ/∂v = γ'(S) (e · ∂S/∂v); nonzero only for `dot`.
#[inline(always)]
pub fn pair_force(model: &PairModel, c: &PairCoeff, p: &PairInput) -> PairForce {
    let rsq = dot(p.dr, p.dr);
    if rsq >= c.rc * c.rc || rsq < MIN_PAIR_DISTANCE * MIN_PAIR_DISTANCE {
        return PairForce::default();
    }
    let r = rsq.sqrt();
    let inv_r = 1.0 / r;
    let q = 1.0 - r / c.rc;
    let (wd, wr) = model.weight.wd_wr(q);
    let rdotv = dot(p.dr, p.dv);
    let ev = rdotv * inv_r;
    let friction = model.friction;
    let s = friction.rate(p.dr, p.dv);
    let gamma = friction.gamma(c, s);

    let fc = c.a * q;
    let fd = -gamma * wd * ev;
    let (fr, fa) = match model.noise {
        Noise::Plain => (
            (2.0 * model.kt * gamma).sqrt() * wr * p.xi * model.inv_sqrt_dt,
            0.0,
        ),
        Noise::Corrected => {
            let fr = (2.0 * model.kt * gamma).sqrt() * wr * p.xi * model.inv_sqrt_dt;
            let de_gamma = friction.dgamma_ds(c, gamma) * friction.rate_gradient_along_e(r, rdotv);
            (fr, model.kt * p.inv_mass_sum * wd * de_gamma * p.xi * p.xi)
        }
        Noise::TwoStep => {
            let dp1 = (2.0 * model.kt * gamma).sqrt() * wr * p.xi * model.sqrt_dt;
            let kick = p.inv_mass_sum * dp1 * inv_r;
            let dv2 = [
                p.dv[0] + kick * p.dr[0],
                p.dv[1] + kick * p.dr[1],
                p.dv[2] + kick * p.dr[2],
            ];
            let gamma2 = friction.gamma(c, friction.rate(p.dr, dv2));
            (
                (2.0 * model.kt * gamma2).sqrt() * wr * p.xi * model.inv_sqrt_dt,
                0.0,
            )
        }
    };
    PairForce {
        fc,
        fd,
        fr,
        fa,
        energy: 0.5 * c.a * c.rc * q * q,
        inv_r,
    }
}
