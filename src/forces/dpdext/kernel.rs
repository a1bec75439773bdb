//! The pure pair kernel of `dpd/nonlinear/ext` (and its thermostat-only forms): the parallel
//! part of `dpd/nonlinear` (its non-linear friction γ∥(S), noise scheme and weight, computed by
//! the same function, [`crate::forces::dpd::kernel`], so the same bits) with a per type-pair
//! weight, plus LAMMPS's `dpd/ext` perpendicular friction and noise (docs/models.md §4.11):
//!
//! F_ij = F^C + F∥ + F⊥ with
//! F⊥ = −γ⊥ w⊥² (I − e eᵀ) v_ij + sqrt(2 kT γ⊥) w⊥ (I − e eᵀ) ξ⃗_ij δt^(−1/2) (P-30),
//! w⊥ = (1 − r/r_c)^s⊥, ξ⃗_ij three unit variates keyed as ξ_ij on their own streams and
//! antisymmetric, ξ⃗_ji = −ξ⃗_ij (P-31), so F_ji = −F_ij holds term by term.
//!
//! Conventions as [`crate::forces::dpd::kernel`]: r_ij = r_i − r_j, v_ij = v_i − v_j, forces
//! on i. The parallel weight is given as LAMMPS's `dpd/ext` gives it, w∥ = (1 − r/r_c)^s∥ for
//! the random force and w∥² for the friction: `Weight` of exponent 2 s∥.

use crate::forces::dpd::kernel::{
    Derived, PairCoeff, PairForce, PairInput, PairModel, Weight, pair_parts,
};
use crate::forces::lanes::{
    BATCH, Isa, PairBatch, dot, in_range, pair_noise, pair_transverse_noise,
};

/// The coefficients of one type pair: `pair_coeff I J a γ∥ γ⊥ s∥ s⊥ [rc] [gamma1 G]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtCoeff {
    /// The parallel part: a, γ0 (= γ∥ at S = 0), γ1, r_c as `dpd/nonlinear`'s.
    pub par: PairCoeff,
    /// The perpendicular friction γ⊥ ≥ 0 (constant).
    pub gamma_perp: f64,
    /// The parallel weight: w_D∥ = (1 − r/r_c)^(2 s∥).
    pub w_par: Weight,
    /// The perpendicular weight: w_D⊥ = (1 − r/r_c)^(2 s⊥).
    pub w_perp: Weight,
}

impl ExtCoeff {
    /// An inert entry (unset type pairs of the dense table).
    pub const INERT: ExtCoeff = ExtCoeff {
        par: PairCoeff {
            a: 0.0,
            gamma0: 0.0,
            gamma1: 0.0,
            rc: 0.0,
        },
        gamma_perp: 0.0,
        w_par: Weight::STANDARD,
        w_perp: Weight::STANDARD,
    };
}

/// What one pair needs: the parallel part's input and the transverse noise vector ξ⃗_ij
/// ([`crate::rng::pair_transverse`], already antisymmetric in the tags).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtInput {
    /// r_ij, v_ij, 1/m_i + 1/m_j, ξ_ij.
    pub pair: PairInput,
    /// ξ⃗_ij.
    pub xt: [f64; 3],
}

/// The force parts of one pair: the central parts as [`PairForce`] and the perpendicular
/// friction and noise as vectors (force on i).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExtForce {
    /// Conservative, parallel friction, parallel noise, correction; energy; 1/r.
    pub par: PairForce,
    /// −γ⊥ w⊥² (I − e eᵀ) v_ij.
    pub fd_perp: [f64; 3],
    /// sqrt(2 kT γ⊥) w⊥ (I − e eᵀ) ξ⃗_ij δt^(−1/2).
    pub fr_perp: [f64; 3],
}

impl ExtForce {
    /// The total force on i.
    #[inline(always)]
    pub fn vector(&self, dr: [f64; 3]) -> [f64; 3] {
        let c = self.par.vector(dr);
        let t = self.perp();
        [c[0] + t[0], c[1] + t[1], c[2] + t[2]]
    }

    /// The perpendicular part, friction plus noise.
    #[inline(always)]
    pub fn perp(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.fd_perp[k] + self.fr_perp[k])
    }
}

/// Per type-pair constants: the parallel part's and σ⊥ = sqrt(2 kT γ⊥).
#[derive(Clone, Copy, Debug, PartialEq)]
struct ExtDerived {
    d: Derived,
    sigma_perp: f64,
}

impl ExtDerived {
    #[inline(always)]
    fn new(model: &PairModel, c: &ExtCoeff) -> ExtDerived {
        ExtDerived {
            d: Derived::new(model, &c.par),
            sigma_perp: (2.0 * model.kt * c.gamma_perp).sqrt(),
        }
    }
}

/// The coefficient table of [`ext_forces_batch_isa`]: the coefficients and their constants for
/// one model (its kT: a temperature ramp builds it again at each step).
#[derive(Clone, Debug, Default)]
pub struct ExtTable {
    kt: f64,
    coeff: Vec<ExtCoeff>,
    derived: Vec<ExtDerived>,
}

impl ExtTable {
    /// The table for `model`; index as `table`.
    pub fn new(model: &PairModel, table: &[ExtCoeff]) -> ExtTable {
        ExtTable {
            kt: model.kt,
            coeff: table.to_vec(),
            derived: table.iter().map(|c| ExtDerived::new(model, c)).collect(),
        }
    }
}

/// All force parts of one pair (P-30, P-31, P-33, P-34); zero out of range. `transverse` false: the
/// perpendicular part is skipped (the thermostat-only form of `dpd/nonlinear`).
#[inline(always)]
pub fn ext_pair_force(model: &PairModel, c: &ExtCoeff, p: &ExtInput, transverse: bool) -> ExtForce {
    let rsq = dot(p.pair.dr, p.pair.dr);
    if !in_range(rsq, c.par.rc) {
        return ExtForce::default();
    }
    ext_parts(model, c, &ExtDerived::new(model, c), p, rsq, transverse)
}

#[inline(always)]
fn ext_parts(
    model: &PairModel,
    c: &ExtCoeff,
    d: &ExtDerived,
    p: &ExtInput,
    rsq: f64,
    transverse: bool,
) -> ExtForce {
    let w = c.w_par;
    let par = if w == Weight::STANDARD {
        pair_parts(
            model.friction,
            model.noise,
            |q| (q * q, q),
            model,
            &c.par,
            &d.d,
            &p.pair,
            rsq,
        )
    } else {
        pair_parts(
            model.friction,
            model.noise,
            |q| w.wd_wr(q),
            model,
            &c.par,
            &d.d,
            &p.pair,
            rsq,
        )
    };
    if !transverse {
        return ExtForce {
            par,
            ..ExtForce::default()
        };
    }
    // The same r and q as the parallel part's.
    let r = rsq.sqrt();
    let q = 1.0 - r * d.d.inv_rc;
    let (wd, wr) = c.w_perp.wd_wr(q);
    let inv_r = par.inv_r;
    let e = p.pair.dr.map(|x| x * inv_r);
    let project = |u: [f64; 3]| {
        let eu = dot(e, u);
        [u[0] - eu * e[0], u[1] - eu * e[1], u[2] - eu * e[2]]
    };
    let pv = project(p.pair.dv);
    let px = project(p.xt);
    let drag = -c.gamma_perp * wd;
    let kick = d.sigma_perp * wr * model.inv_sqrt_dt();
    ExtForce {
        par,
        fd_perp: pv.map(|x| drag * x),
        fr_perp: px.map(|x| kick * x),
    }
}

/// Evaluate every pair of `b` at `step`, as [`ext_pair_force`] with ξ_ij =
/// `model.dist.pair_xi(seed, step, tag_i, tag_j)` and ξ⃗_ij = `pair_transverse(model.dist,
/// seed, step, tag_i, tag_j, dim)` (the same bits): `fpair` the central force / r, `ft` the
/// perpendicular part (`transverse`; then [`PairBatch::transverse`] is set), `energy`.
#[allow(clippy::too_many_arguments)]
pub fn ext_forces_batch_isa(
    _isa: Isa,
    model: &PairModel,
    table: &ExtTable,
    seed: u32,
    step: u64,
    dim: u32,
    transverse: bool,
    b: &mut PairBatch,
) {
    let n = b.len.min(BATCH);
    b.len = n;
    b.transverse = transverse;
    if n == 0 {
        return;
    }
    debug_assert_eq!(
        table.kt.to_bits(),
        model.kt.to_bits(),
        "ExtTable of another model"
    );
    pair_noise(b, seed, step, model.dist);
    if transverse {
        pair_transverse_noise(b, seed, step, model.dist, dim);
    }
    for l in 0..n {
        let k = b.coeff[l] as usize;
        let (c, d) = (&table.coeff[k], &table.derived[k]);
        let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
        let input = ExtInput {
            pair: PairInput {
                dr,
                dv: [b.dv[0][l], b.dv[1][l], b.dv[2][l]],
                inv_mass_sum: b.inv_mass_sum[l],
                xi: b.scratch.xi[l],
            },
            xt: [b.scratch.xt[0][l], b.scratch.xt[1][l], b.scratch.xt[2][l]],
        };
        let rsq = dot(dr, dr);
        let f = if in_range(rsq, c.par.rc) {
            ext_parts(model, c, d, &input, rsq, transverse)
        } else {
            ExtForce::default()
        };
        b.fpair[l] = f.par.total() * f.par.inv_r;
        b.energy[l] = f.par.energy;
        let t = f.perp();
        for (k, tk) in t.iter().enumerate() {
            b.ft[k][l] = *tk;
        }
    }
}
