//! The many-body terms of `pair_style mdpd/nonlinear` (docs/models.md §4.10, P-27–P-29): the
//! density weight of the pre-pass and the density-dependent repulsion added to the DPD pair
//! force of `dpd/nonlinear`'s kernel.
//!
//! - P-27, the density of atom i: ρ̄_i = Σ_{j≠i} m_j w_ρ(r_ij), with LAMMPS's `mdpd/rhosum`
//!   weight, the 3-D Lucy kernel of range h = r_d: w_ρ(r) = 105/(16π h³) (1 + 3r/h)(1 − r/h)³
//!   for r < h (the same normalisation in 2-D, as LAMMPS has it).
//! - P-28, the conservative force on i: F^C_ij = [A w_C(r) + B (ρ̄_i + ρ̄_j) w_d(r)] r̂_ij with
//!   w_C = 1 − r/r_c and w_d = 1 − r/r_d for r < r_d (0 beyond): the first term is
//!   `dpd/nonlinear`'s conservative force with a = A, the second this module's.
//! - P-29, the pair energy LAMMPS's `mdpd` tallies: ½ A r_c w_C² + ½ B r_d (ρ̄_i + ρ̄_j) w_d².

use std::f64::consts::PI;

use crate::forces::{PairBatch, in_range};

/// 105/(16π): the 3-D Lucy kernel's normalisation (P-27).
pub const LUCY_3D: f64 = 105.0 / (16.0 * PI);

/// The many-body repulsion of one type pair (P-28): amplitude B (already scaled by the
/// `special_lj` factor in the special blocks) and range r_d.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ManyBodyCoeff {
    /// B.
    pub b: f64,
    /// r_d (0 for a pair without coefficients: no repulsion).
    pub rd: f64,
}

/// The density weight of one type pair, m w_ρ(r) (P-27), with the neighbour's mass m folded
/// in (per-type masses: one mass for every type of the style, so the sum is symmetric in i and
/// j); with per-atom masses the neighbour's own mass ([`DensityWeight::w_mass`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DensityWeight {
    h: f64,
    inv_h: f64,
    norm: f64,
}

impl DensityWeight {
    /// The weight of range `h` (> 0) for neighbours of mass `mass`.
    pub fn new(h: f64, mass: f64) -> DensityWeight {
        DensityWeight {
            h,
            inv_h: 1.0 / h,
            norm: mass * LUCY_3D / (h * h * h),
        }
    }

    /// m w_ρ at squared distance `rsq` (0 at and beyond h, and for an unset pair).
    #[inline(always)]
    pub fn w(&self, rsq: f64) -> f64 {
        let u = rsq.sqrt() * self.inv_h;
        let v = 1.0 - u;
        let w = self.norm * (1.0 + 3.0 * u) * (v * v * v);
        if rsq < self.h * self.h { w } else { 0.0 }
    }

    /// m w_ρ at squared distance `rsq` for a neighbour of mass `m` (per-atom masses): the same
    /// bits as [`DensityWeight::w`] of `DensityWeight::new(h, m)`.
    #[inline(always)]
    pub fn w_mass(&self, rsq: f64, m: f64) -> f64 {
        DensityWeight {
            norm: m * LUCY_3D / (self.h * self.h * self.h),
            ..*self
        }
        .w(rsq)
    }

    /// [`DensityWeight::w`] of every entry of `rsq` into `out` (a loop without calls or
    /// branches: SIMD lanes, the same bits).
    pub fn w_of_squares(&self, rsq: &[f64], out: &mut [f64]) {
        for (o, &q) in out.iter_mut().zip(rsq) {
            *o = self.w(q);
        }
    }
}

/// Add the many-body repulsion (P-28) and its energy (P-29) to the lanes `0..b.len` of a batch
/// whose DPD part is already evaluated: lane l is the pair (`i[l]`, `j[l]`) with coefficients
/// `coeff[b.coeff[l]]` and the atoms' densities `rho[i[l]]`, `rho[j[l]]`. A lane beyond r_d (or
/// closer than the kernels' minimum distance) is left as it is.
pub fn add_many_body(
    coeff: &[ManyBodyCoeff],
    rho: &[f64],
    b: &mut PairBatch,
    i: &[u32],
    j: &[u32],
) {
    let n = b.len.min(i.len()).min(j.len());
    for l in 0..n {
        let c = coeff[b.coeff[l] as usize];
        let rsq = b.dr[0][l] * b.dr[0][l] + b.dr[1][l] * b.dr[1][l] + b.dr[2][l] * b.dr[2][l];
        if !in_range(rsq, c.rd) {
            continue;
        }
        let r = rsq.sqrt();
        let wd = 1.0 - r / c.rd;
        let rho_sum = rho[i[l] as usize] + rho[j[l] as usize];
        b.fpair[l] += c.b * rho_sum * wd / r;
        b.energy[l] += 0.5 * c.b * c.rd * rho_sum * wd * wd;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weight is LAMMPS's form C (h + 3r)(h − r)³ / h⁷ to round-off, vanishes at h, and
    /// integrates to m over 3-D space (∫ 4π r² w dr = 1: a normalised kernel).
    #[test]
    fn lucy_weight() {
        let (h, m) = (0.75, 1.5);
        let w = DensityWeight::new(h, m);
        for r in [0.0, 0.1, 0.3, 0.5, 0.7, 0.7499] {
            let lammps = m * LUCY_3D * (h + 3.0 * r) * (h - r).powi(3) / h.powi(7);
            let got = w.w(r * r);
            assert!(
                (got - lammps).abs() <= 1e-14 * lammps.abs().max(1e-300),
                "r {r}: {got} vs {lammps}"
            );
        }
        assert_eq!(w.w(h * h), 0.0);
        assert_eq!(w.w(2.0), 0.0);
        let n = 200_000;
        let dr = h / n as f64;
        let integral: f64 = (0..n)
            .map(|k| {
                let r = (k as f64 + 0.5) * dr;
                4.0 * PI * r * r * w.w(r * r) * dr
            })
            .sum();
        assert!((integral - m).abs() < 1e-9, "{integral}");
        let rsq = [0.0, 0.01, 0.25, 0.5, 0.6];
        let mut out = [9.0; 5];
        w.w_of_squares(&rsq, &mut out);
        for (q, o) in rsq.iter().zip(out) {
            assert_eq!(o.to_bits(), w.w(*q).to_bits());
        }
    }
}
