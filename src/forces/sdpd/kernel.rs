//! Pure kernels of smoothed DPD (sDPD), `pair_style sdpd` (`docs/models.md` §3.7; the
//! weighting-function paper's equations, labelled WF-n there).
//!
//! - [`Smoothing`] and [`KernelShape`]: the kernels W(r) and F(r) = −W'(r)/r of Lucy (WF-25),
//!   the quintic spline and the proposed kernel of any s > 0 (WF-41–42 in 3-D, WF-56–57 in 2-D),
//!   normalised to \[W\] = ∫ W d^d r = 1 (WF-7), in 2-D and 3-D, with support r_c.
//! - [`Tait`]: the equation of state P = P0 \[(ρ/ρ0)⁷ − 1\], P0 = c_s² ρ0 / 7 (WF-10), with the
//!   per-particle energy u(d) whose derivative is P/d², so that the conservative force is −∇ of
//!   Σ_i u(d_i) (`docs/models.md` §3.7, P-20).
//! - [`sdpd_pair_force`]: the three central parts of the force on i due to j (WF-12, with the
//!   random amplitude under the root, WF-19): conservative (P_i/d_i² + P_j/d_j²) r F(r),
//!   dissipative −2(D+2) η0 F(r)/(d_i d_j) (e·v), random sqrt(2 kT · 2(D+2) η0 F/(d_i d_j)) ξ δt^(−1/2).
//!   Every part is symmetric in (i, j) up to the sign of e_ij, so F_ji = −F_ij to the bit.
//!
//! Conventions as in [`super`]: r_ij = r_i − r_j, v_ij = v_i − v_j (minimum image and any
//! Lees–Edwards velocity jump applied by the caller), 3-component vectors with z = 0 in 2-D.
//! d_i is a number density (particles per volume, per area in 2-D), ρ_i = m_i d_i.

use crate::forces::lanes::{MIN_PAIR_DISTANCE, dot};
use std::f64::consts::PI;

pub use crate::theory::sdpd::Smoothing;

/// (1 − u)^s for the polynomial kernels, with exact products for s = 1 and s = 2 (Lucy).
#[inline(always)]
fn pow_s(v: f64, s: f64) -> f64 {
    if s == 2.0 {
        v * v
    } else if s == 1.0 {
        v
    } else {
        v.powf(s)
    }
}

/// A kernel of one family at one cut-off and dimension, with its normalisations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KernelShape {
    /// The family.
    pub kind: Smoothing,
    /// Dimension, 2 or 3.
    pub dim: u32,
    /// Support (cut-off) r_c.
    pub rc: f64,
    inv_rc: f64,
    /// Polynomial kernels: s. Quintic: unused.
    s: f64,
    /// Prefactor of W (A of A (1 − u)^(s+1) [1 + (1+s) u]; σ_d/h^d for the quintic).
    w_norm: f64,
    /// Prefactor of F (B of B (1 − u)^s; 5 σ_d / h^(d+2) for the quintic).
    f_norm: f64,
}

/// σ_d of the quintic spline: 1/(120π) in 3-D, 7/(478π) in 2-D (`docs/models.md` §3.7).
fn quintic_sigma(dim: u32) -> f64 {
    if dim == 3 {
        1.0 / (120.0 * PI)
    } else {
        7.0 / (478.0 * PI)
    }
}

/// The quintic pieces Σ_k c_k (a_k − R)_+^p for (a, c) = (3, 1), (2, −6), (1, 15).
#[inline(always)]
fn quintic_sum(r: f64, p: i32) -> f64 {
    let t3 = (3.0 - r).max(0.0);
    let t2 = (2.0 - r).max(0.0);
    let t1 = (1.0 - r).max(0.0);
    t3.powi(p) - 6.0 * t2.powi(p) + 15.0 * t1.powi(p)
}

impl KernelShape {
    /// The kernel `kind` with support `rc` in dimension `dim`; the message names what is wrong
    /// (dimension not 2 or 3, r_c not finite and > 0).
    pub fn new(kind: Smoothing, dim: u32, rc: f64) -> Result<KernelShape, String> {
        if dim != 2 && dim != 3 {
            return Err(format!("sdpd kernel: dimension {dim} must be 2 or 3"));
        }
        if !(rc.is_finite() && rc > 0.0) {
            return Err(format!("sdpd kernel: cut-off rc = {rc} must be > 0"));
        }
        let (s, w_norm, f_norm) = match kind.exponent() {
            Some(s) => {
                if !(s.is_finite() && s > 0.0) {
                    return Err(format!("sdpd kernel: exponent s = {s} must be > 0"));
                }
                let (a, b) = if dim == 3 {
                    // WF-41, WF-42.
                    let a = (s + 3.0) * (s + 4.0) * (s + 5.0) / (32.0 * PI);
                    (a, a * (s + 1.0) * (s + 2.0))
                } else {
                    // WF-56, WF-57.
                    let a = (s + 3.0) * (s + 4.0) / (6.0 * PI);
                    (a, a * (s + 1.0) * (s + 2.0))
                };
                let d = dim as i32;
                (s, a / rc.powi(d), b / rc.powi(d + 2))
            }
            None => {
                let h = rc / 3.0;
                let sigma = quintic_sigma(dim);
                let d = dim as i32;
                (0.0, sigma / h.powi(d), 5.0 * sigma / h.powi(d + 2))
            }
        };
        Ok(KernelShape {
            kind,
            dim,
            rc,
            inv_rc: 1.0 / rc,
            s,
            w_norm,
            f_norm,
        })
    }

    /// W(r) (0 for r ≥ r_c).
    #[inline(always)]
    pub fn w(&self, r: f64) -> f64 {
        if r >= self.rc {
            return 0.0;
        }
        let u = r * self.inv_rc;
        match self.kind {
            Smoothing::Quintic => self.w_norm * quintic_sum(3.0 * u, 5),
            _ => {
                let v = 1.0 - u;
                self.w_norm * pow_s(v, self.s) * v * (1.0 + (1.0 + self.s) * u)
            }
        }
    }

    /// `out[k] = W(sqrt(rsq[k]))` for every k (0 at and beyond r_c): [`KernelShape::w`] in a
    /// loop without calls or branches for Lucy, the quintic and s = 1 (SIMD lanes), the same bits.
    pub fn w_of_squares(&self, rsq: &[f64], out: &mut [f64]) {
        let rcsq = self.rc * self.rc;
        let (w_norm, inv_rc, s) = (self.w_norm, self.inv_rc, self.s);
        let n = rsq.len().min(out.len());
        let (rsq, out) = (&rsq[..n], &mut out[..n]);
        macro_rules! lanes {
            ($u:ident, $w:expr) => {
                for (o, &q) in out.iter_mut().zip(rsq) {
                    let $u = q.sqrt() * inv_rc;
                    let w = $w;
                    *o = if q < rcsq { w } else { 0.0 };
                }
            };
        }
        match self.kind {
            Smoothing::Quintic => lanes!(u, w_norm * quintic_sum(3.0 * u, 5)),
            _ if s == 2.0 => lanes!(u, {
                let v = 1.0 - u;
                w_norm * (v * v) * v * (1.0 + (1.0 + s) * u)
            }),
            _ if s == 1.0 => lanes!(u, {
                let v = 1.0 - u;
                w_norm * v * v * (1.0 + (1.0 + s) * u)
            }),
            _ => lanes!(u, {
                let v = 1.0 - u;
                w_norm * pow_s(v, s) * v * (1.0 + (1.0 + s) * u)
            }),
        }
    }

    /// W(0), the self term of the density sum.
    pub fn w0(&self) -> f64 {
        self.w(0.0)
    }

    /// F(r) = −W'(r)/r (0 for r ≥ r_c; finite as r → 0).
    #[inline]
    pub fn f(&self, r: f64) -> f64 {
        if r >= self.rc {
            return 0.0;
        }
        let u = r * self.inv_rc;
        match self.kind {
            Smoothing::Quintic => {
                // −W' / r = 5 σ/h^(d+2) · Σ c_k (a_k − R)⁴ / R; at R → 0 the sum vanishes like
                // 24 R, so its limit 5σ/h^(d+2) · 24 is used below R = 1e-8.
                let big_r = 3.0 * u;
                if big_r < 1e-8 {
                    self.f_norm * 24.0
                } else {
                    self.f_norm * quintic_sum(big_r, 4) / big_r
                }
            }
            _ => self.f_norm * pow_s(1.0 - u, self.s),
        }
    }
}

/// The Tait equation of state of one atom type (WF-10) and its energy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tait {
    /// Reference mass density ρ0 (> 0).
    pub rho0: f64,
    /// Sound speed c_s (> 0).
    pub c0: f64,
    /// Particle mass m (> 0).
    pub mass: f64,
    /// P0 = c_s² ρ0 / 7 as an energy per volume (× mvv2e of the unit style, 1 in `units lj`:
    /// [`Tait::in_units`]).
    pub p0: f64,
    /// The reference number density d0 = ρ0 / m.
    pub d0: f64,
}

impl Tait {
    /// The equation of state for ρ0, c_s and the mass; each must be finite and > 0 (`units lj`).
    pub fn new(rho0: f64, c0: f64, mass: f64) -> Result<Tait, String> {
        Tait::in_units(rho0, c0, mass, 1.0)
    }

    /// [`Tait::new`] in a unit style whose mass × velocity² is `mvv2e` energy units (LAMMPS's
    /// `force->mvv2e`): P0 = c_s² ρ0 mvv2e / 7, an energy per volume, so the forces are in
    /// force units and the energy u(d) in energy units.
    pub fn in_units(rho0: f64, c0: f64, mass: f64, mvv2e: f64) -> Result<Tait, String> {
        for (name, v) in [("rho0", rho0), ("c0", c0), ("mass", mass)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} = {v} must be > 0"));
            }
        }
        let p0 = c0 * c0 * rho0 / 7.0 * mvv2e;
        if !p0.is_finite() {
            return Err(format!(
                "P0 = c0^2 rho0 / 7 overflows (c0 = {c0}, rho0 = {rho0})"
            ));
        }
        Ok(Tait {
            rho0,
            c0,
            mass,
            p0,
            d0: rho0 / mass,
        })
    }

    /// The same equation of state for particles of mass `mass` (> 0; per-atom masses): the same
    /// bits as [`Tait::in_units`] with that mass (P0 does not depend on it, d0 = ρ0 / m).
    #[inline]
    pub fn with_mass(self, mass: f64) -> Tait {
        Tait {
            mass,
            d0: self.rho0 / mass,
            ..self
        }
    }

    /// x⁷ with x = ρ/ρ0 = d/d0, by products.
    #[inline(always)]
    fn x7(x: f64) -> f64 {
        let x2 = x * x;
        let x4 = x2 * x2;
        x4 * x2 * x
    }

    /// P(d) = P0 [(m d/ρ0)⁷ − 1] at number density `d`.
    #[inline]
    pub fn pressure(&self, d: f64) -> f64 {
        self.p0 * (Self::x7(d / self.d0) - 1.0)
    }

    /// P(d)/d², the factor of the conservative force.
    #[inline]
    pub fn pressure_term(&self, d: f64) -> f64 {
        self.pressure(d) / (d * d)
    }

    /// u(d) = (P0/d0) [(x⁶ − 1)/6 + 1/x − 1], x = d/d0: u(d0) = 0 and du/dd = P(d)/d², so the
    /// conservative forces are −∇ Σ_i u(d_i) (energy of `pair_style sdpd`).
    #[inline]
    pub fn energy(&self, d: f64) -> f64 {
        let x = d / self.d0;
        let x2 = x * x;
        let x6 = x2 * x2 * x2;
        self.p0 / self.d0 * ((x6 - 1.0) / 6.0 + 1.0 / x - 1.0)
    }
}

/// What [`sdpd_pair_force`] needs of one particle: 1/d and P/d² at its current density.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SdpdAtom {
    /// 1/d_i.
    pub inv_d: f64,
    /// P_i/d_i².
    pub pterm: f64,
}

/// Per type-pair coefficients of `pair_style sdpd`, with what the hot loop needs precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdpdCoeff {
    /// The kernel at this pair's cut-off.
    pub shape: KernelShape,
    /// Dissipative viscosity η0 (> 0).
    pub eta0: f64,
    /// 2(D+2) η0, the friction of F^D = −2(D+2) η0 F/(d_i d_j) (e·v) e.
    pub friction: f64,
    /// 2 kT · 2(D+2) η0 / δt: σ² of the random part per unit F/(d_i d_j).
    pub noise_sq: f64,
}

impl SdpdCoeff {
    /// Coefficients for a kernel, η0 > 0, kT >= 0 (0: no random part) and δt > 0.
    pub fn new(shape: KernelShape, eta0: f64, kt: f64, dt: f64) -> Result<SdpdCoeff, String> {
        if !(eta0.is_finite() && eta0 > 0.0) {
            return Err(format!("eta0 = {eta0} must be > 0"));
        }
        let friction = 2.0 * f64::from(shape.dim + 2) * eta0;
        Ok(SdpdCoeff {
            shape,
            eta0,
            friction,
            noise_sq: 2.0 * kt * friction / dt,
        })
    }
}

/// The parts of one sDPD pair force along e_ij (the force on i is (fc + fd + fr) e_ij).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SdpdForce {
    /// Conservative part (P_i/d_i² + P_j/d_j²) r F(r).
    pub fc: f64,
    /// Dissipative part −2(D+2) η0 F/(d_i d_j) (e·v).
    pub fd: f64,
    /// Random part sqrt(2 kT 2(D+2) η0 F/(d_i d_j) / δt) ξ.
    pub fr: f64,
}

impl SdpdForce {
    /// fc + fd + fr.
    #[inline]
    pub fn total(&self) -> f64 {
        self.fc + self.fd + self.fr
    }
}

/// The sDPD force on i due to j (WF-12/19; `docs/models.md` §3.7) for separation `dr` = r_ij,
/// relative velocity `dv` = v_ij and the pair's standard Gaussian `xi`. Zero beyond the cut-off
/// or below `MIN_PAIR_DISTANCE`.
#[inline]
pub fn sdpd_pair_force(
    c: &SdpdCoeff,
    dr: [f64; 3],
    dv: [f64; 3],
    xi: f64,
    ai: SdpdAtom,
    aj: SdpdAtom,
) -> SdpdForce {
    let rsq = dot(dr, dr);
    let in_range = rsq < c.shape.rc * c.shape.rc;
    if !in_range || rsq < MIN_PAIR_DISTANCE * MIN_PAIR_DISTANCE {
        return SdpdForce::default();
    }
    let r = rsq.sqrt();
    let f = c.shape.f(r);
    let wd = f * (ai.inv_d * aj.inv_d);
    let ev = dot(dr, dv) / r;
    SdpdForce {
        fc: (ai.pterm + aj.pterm) * r * f,
        fd: -c.friction * wd * ev,
        fr: (c.noise_sq * wd).sqrt() * xi,
    }
}

/// The kernel family as the batch loop specialises it.
const K_SQUARE: u8 = 0; // (1 − u)² (Lucy, proposed s = 2)
const K_POW: u8 = 1; // (1 − u)^s
const K_QUINTIC: u8 = 2;
const K_LINEAR: u8 = 3; // (1 − u) (proposed s = 1)

/// Evaluate every pair of `b` (lanes `0..b.len`, atoms `i[l]`, `j[l]`) with the sDPD force:
/// `b.fpair[l]` becomes exactly `sdpd_pair_force(&coeff[b.coeff[l]], r_ij, v_ij, ξ_ij, atoms[i],
/// atoms[j]).total() / r` (0 out of range), ξ_ij the lane's keyed Gaussian, and `b.energy[l]`
/// 0 (the Tait energy is per atom). The loops have no calls (for Lucy, quintic and s = 1) and no
/// branches, so they run in SIMD lanes of the instruction set `isa` (the same bits with each).
///
/// All coefficients must share one kernel family and exponent (they do: the kernel is global in
/// `pair_style sdpd`). Panics if an index is outside `coeff` or `atoms` (a caller bug).
#[allow(clippy::too_many_arguments)]
pub fn sdpd_forces_batch(
    isa: crate::forces::Isa,
    coeff: &[SdpdCoeff],
    atoms: &[SdpdAtom],
    seed: u32,
    step: u64,
    b: &mut crate::forces::PairBatch,
    i: &[u32],
    j: &[u32],
) {
    let n = b.len.min(crate::forces::BATCH).min(i.len()).min(j.len());
    b.len = n;
    if n == 0 {
        return;
    }
    let isa = if (isa as u8) > (crate::forces::Isa::best_supported() as u8) {
        crate::forces::Isa::Baseline
    } else {
        isa
    };
    let first = &coeff[b.coeff[0] as usize].shape;
    let kind = match first.kind {
        Smoothing::Quintic => K_QUINTIC,
        _ if first.s == 2.0 => K_SQUARE,
        _ if first.s == 1.0 => K_LINEAR,
        _ => K_POW,
    };
    let args = (coeff, atoms, seed, step, i, j);
    match (isa, kind) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `isa` is at most `Isa::best_supported()` (checked above), so the CPU has every
        // feature the function is compiled for.
        (crate::forces::Isa::Avx512, K_SQUARE) => unsafe { sdpd_avx512::<K_SQUARE>(args, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        (crate::forces::Isa::Avx512, K_QUINTIC) => unsafe { sdpd_avx512::<K_QUINTIC>(args, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        (crate::forces::Isa::Avx512, K_LINEAR) => unsafe { sdpd_avx512::<K_LINEAR>(args, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        (crate::forces::Isa::Avx2, K_SQUARE) => unsafe { sdpd_avx2::<K_SQUARE>(args, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        (crate::forces::Isa::Avx2, K_QUINTIC) => unsafe { sdpd_avx2::<K_QUINTIC>(args, b) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        (crate::forces::Isa::Avx2, K_LINEAR) => unsafe { sdpd_avx2::<K_LINEAR>(args, b) },
        (_, K_SQUARE) => sdpd_lanes::<K_SQUARE>(args, b),
        (_, K_QUINTIC) => sdpd_lanes::<K_QUINTIC>(args, b),
        (_, K_LINEAR) => sdpd_lanes::<K_LINEAR>(args, b),
        _ => sdpd_lanes::<K_POW>(args, b),
    }
}

/// The inputs of [`sdpd_lanes`] besides the batch.
type SdpdArgs<'a> = (
    &'a [SdpdCoeff],
    &'a [SdpdAtom],
    u32,
    u64,
    &'a [u32],
    &'a [u32],
);

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx512bw,avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
fn sdpd_avx512<const K: u8>(args: SdpdArgs<'_>, b: &mut crate::forces::PairBatch) {
    sdpd_lanes::<K>(args, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2,lzcnt")]
fn sdpd_avx2<const K: u8>(args: SdpdArgs<'_>, b: &mut crate::forces::PairBatch) {
    sdpd_lanes::<K>(args, b)
}

/// The lane loops of [`sdpd_forces_batch`] for kernel family `K`: the same operations, in the
/// same order, as [`sdpd_pair_force`] and [`KernelShape::f`].
#[inline(always)]
fn sdpd_lanes<const K: u8>(args: SdpdArgs<'_>, b: &mut crate::forces::PairBatch) {
    use crate::forces::BATCH;
    let (coeff, atoms, seed, step, i, j) = args;
    let n = b.len;
    crate::forces::lanes::pair_gaussians(b, seed, step);
    // Per-lane coefficients and atom terms (a broadcast for one type pair).
    let mut rcsq = [0.0; BATCH];
    let mut inv_rc = [0.0; BATCH];
    let mut f_norm = [0.0; BATCH];
    let mut fric = [0.0; BATCH];
    let mut nsq = [0.0; BATCH];
    let mut ptsum = [0.0; BATCH];
    let mut idd = [0.0; BATCH];
    let s = coeff[b.coeff[0] as usize].shape.s;
    let k0 = b.coeff[0];
    if b.coeff[..n].iter().all(|&k| k == k0) {
        let c = &coeff[k0 as usize];
        rcsq.fill(c.shape.rc * c.shape.rc);
        inv_rc.fill(c.shape.inv_rc);
        f_norm.fill(c.shape.f_norm);
        fric.fill(c.friction);
        nsq.fill(c.noise_sq);
    } else {
        for l in 0..n {
            let c = &coeff[b.coeff[l] as usize];
            rcsq[l] = c.shape.rc * c.shape.rc;
            inv_rc[l] = c.shape.inv_rc;
            f_norm[l] = c.shape.f_norm;
            fric[l] = c.friction;
            nsq[l] = c.noise_sq;
        }
    }
    for l in 0..n {
        let (ai, aj) = (atoms[i[l] as usize], atoms[j[l] as usize]);
        ptsum[l] = ai.pterm + aj.pterm;
        idd[l] = ai.inv_d * aj.inv_d;
    }
    let xi = crate::forces::lanes::lane_gaussians(b);
    let min_sq = MIN_PAIR_DISTANCE * MIN_PAIR_DISTANCE;
    let mut out = [0.0; BATCH];
    for l in 0..BATCH {
        let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
        let dv = [b.dv[0][l], b.dv[1][l], b.dv[2][l]];
        let rsq = dot(dr, dr);
        let ok = (rsq < rcsq[l]) & (rsq >= min_sq);
        let r = rsq.sqrt();
        let u = r * inv_rc[l];
        let f = match K {
            K_SQUARE => {
                let v = 1.0 - u;
                f_norm[l] * (v * v)
            }
            K_LINEAR => f_norm[l] * (1.0 - u),
            K_QUINTIC => {
                let big_r = 3.0 * u;
                let general = f_norm[l] * quintic_sum(big_r, 4) / big_r;
                if big_r < 1e-8 {
                    f_norm[l] * 24.0
                } else {
                    general
                }
            }
            _ => f_norm[l] * pow_s(1.0 - u, s),
        };
        let wd = f * idd[l];
        let ev = dot(dr, dv) / r;
        let fc = ptsum[l] * r * f;
        let fd = -fric[l] * wd * ev;
        let fr = (nsq[l] * wd).sqrt() * xi[l];
        out[l] = if ok { (fc + fd + fr) / r } else { 0.0 };
    }
    b.fpair[..n].copy_from_slice(&out[..n]);
    b.energy[..n].fill(0.0);
}
