//! Velocity-Verlet's finite-step temperature, **measured, not theory** (issue 14, section 4).
//!
//! The finite-step paper treats the Euler scheme only (eqs. 22–26). For `fix nve` (LAMMPS's
//! velocity-Verlet, the pair forces of step n + 1 evaluated with the half-step velocities) there
//! is no closed form here; instead this module carries the equilibrium T/T0 measured with this
//! project's engine (`validation/finite_step/README.md`, section "Velocity-Verlet"; the table
//! `vv_measured.csv` beside this file is a copy of the committed results) on
//! - the 2-D ideal fluid of the finite-step paper (a = 0, γ = σ = 1, w_D = (1 − r)², r_c = 1,
//!   N = 1600) at n = 1, 4, 16, and
//! - the weighting paper's Table 3 fluid (2-D, n = 4, s = ½, γ = 15.67, the fluid of its Couette
//!   runs), and
//! - the non-linear paper's 3-D fluid (n = 16, kT = 0.1, γ0 = 5, r_c = 1) for each of its models,
//!
//! as a function of x = δt √(kT/m) / r_c, the distance a thermal particle moves in one step in
//! units of the cut-off. That variable, not δt/δt_c (δt_c the Euler critical step of eq. 25),
//! brings the measured families together: velocity-Verlet's heating follows the displacement
//! per step, Euler's the friction per step.
//! [`vv_verdict`] interpolates the measured family nearest to a fluid (same dimension, nearest
//! number of neighbours within r_c and weight exponent); the answer is a measurement on that
//! family, labelled so. At δt/δt_c = 0.18 the s = 2, γ = 1 fluid at n = 4 heats by 7 % and the
//! s = ½, γ = 15.7 fluid at the same n by 0.2 ± 0.2 %; at x ≈ 0.14 the three s = 2 families
//! heat by 7–10 % (see the validation report).

/// One measured point.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct VvPoint {
    /// The family: `2d-ideal` (finite-step paper fluid) or `nonlinear-MODEL`.
    pub family: String,
    /// 2 or 3.
    pub dim: u32,
    /// Number density.
    pub density: f64,
    /// Mean number of neighbours within r_c (n V_d r_c^d).
    pub neighbours: f64,
    /// Weight exponent s of w_D = (1 − r/r_c)^s, and the friction γ (γ0).
    pub s: f64,
    pub gamma: f64,
    /// kT and the step δt (m = r_c = 1 in every measured fluid).
    pub kt: f64,
    pub dt: f64,
    /// x = δt √(kT/m) / r_c, the interpolation variable.
    pub x: f64,
    /// δt / δt_c (eq. 25).
    pub dt_over_dtc: f64,
    /// Measured T/T0 and its standard error (block averages).
    pub t_ratio: f64,
    pub err: f64,
}

/// The measured table (a copy of the validation results; see the module notes).
const TABLE: &str = include_str!("vv_measured.csv");

/// Every measured point, in the table's order (family, then δt/δt_c increasing).
pub(crate) fn vv_points() -> Vec<VvPoint> {
    TABLE
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').map(str::trim).collect();
            let num = |k: usize| f.get(k)?.parse::<f64>().ok();
            Some(VvPoint {
                family: f.first()?.to_string(),
                dim: f.get(1)?.parse().ok()?,
                density: num(2)?,
                neighbours: num(3)?,
                s: num(4)?,
                gamma: num(5)?,
                kt: num(6)?,
                dt: num(7)?,
                x: num(8)?,
                dt_over_dtc: num(9)?,
                t_ratio: num(10)?,
                err: num(11)?,
            })
        })
        .collect()
}

/// What the measurements say of a fluid's velocity-Verlet step.
#[derive(Clone, Debug, PartialEq)]
pub struct VvVerdict {
    /// The measured family used, its density, neighbour count, weight exponent and friction.
    pub family: String,
    /// The family's number density.
    pub density: f64,
    /// Its mean number of neighbours within the cut-off.
    pub neighbours: f64,
    /// Its weight exponent s.
    pub s: f64,
    /// Its friction γ.
    pub gamma: f64,
    /// The family's measured points (x, T/T0, error).
    pub points: Vec<(f64, f64, f64)>,
    /// T/T0 interpolated linearly in x between the measured points (from T/T0 = 1 at δt = 0);
    /// None beyond the largest measured x.
    pub t_ratio: Option<f64>,
    /// The x where the family's measured heating first reaches 1 % (linear interpolation
    /// between points, from 0 at δt = 0); None if it never does in range.
    pub one_percent_at: Option<f64>,
}

/// The measured velocity-Verlet heating of the family nearest to a fluid of dimension `dim`
/// with `neighbours` neighbours within r_c and weight exponent `s`, at step `x` = δt √(kT/m) /
/// r_c: nearest
/// by |ln(neighbours ratio)| + |ln(s ratio)|. Of the non-linear paper's fluid only the `ref`
/// family (no friction non-linearity, plain noise) stands for other fluids. None if no family
/// of that dimension was measured.
pub fn vv_verdict(dim: u32, neighbours: f64, s: f64, x: f64) -> Option<VvVerdict> {
    let pts = vv_points();
    let candidates: Vec<&VvPoint> = pts
        .iter()
        .filter(|p| {
            p.dim == dim && (!p.family.starts_with("nonlinear-") || p.family == "nonlinear-ref")
        })
        .collect();
    let distance = |p: &VvPoint| (p.neighbours / neighbours).ln().abs() + (p.s / s).ln().abs();
    let near = candidates
        .iter()
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))?;
    let fam: Vec<&VvPoint> = candidates
        .iter()
        .filter(|p| p.family == near.family && p.density == near.density && p.s == near.s)
        .copied()
        .collect();
    let mut points: Vec<(f64, f64, f64)> = fam.iter().map(|p| (p.x, p.t_ratio, p.err)).collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Piecewise linear through (0, 1) and the measured points.
    let mut line = vec![(0.0, 1.0)];
    line.extend(points.iter().map(|&(x, y, _)| (x, y)));
    let interp = |x: f64| -> Option<f64> {
        line.windows(2).find_map(|w| {
            let ((x0, y0), (x1, y1)) = (w[0], w[1]);
            (x >= x0 && x <= x1 && x1 > x0).then(|| y0 + (y1 - y0) * (x - x0) / (x1 - x0))
        })
    };
    let one_percent_at = line.windows(2).find_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        (y1 - 1.0 >= 0.01 && y0 - 1.0 < 0.01 && y1 > y0)
            .then(|| x0 + (x1 - x0) * (1.01 - y0) / (y1 - y0))
    });
    Some(VvVerdict {
        family: near.family.clone(),
        density: near.density,
        neighbours: near.neighbours,
        s: near.s,
        gamma: near.gamma,
        points,
        t_ratio: if x.is_finite() && x >= 0.0 {
            interp(x)
        } else {
            None
        },
        one_percent_at,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_parses_and_is_ordered() {
        let pts = vv_points();
        assert!(pts.len() >= 10, "{} points", pts.len());
        assert!(pts.iter().all(|p| p.t_ratio > 0.0 && p.err >= 0.0));
        assert!(pts.iter().any(|p| p.dim == 2) && pts.iter().any(|p| p.dim == 3));
    }

    #[test]
    fn interpolation_goes_through_the_points() {
        let v = vv_verdict(2, 12.0, 2.0, 0.0).expect("2-D family");
        assert_eq!(v.t_ratio, Some(1.0));
        for &(x, y, _) in &v.points {
            let w = vv_verdict(2, 12.0, 2.0, x).expect("2-D family");
            assert!((w.t_ratio.unwrap() - y).abs() < 1e-12);
        }
        let last = v.points.last().unwrap().0;
        assert_eq!(vv_verdict(2, 12.0, 2.0, last * 1.5).unwrap().t_ratio, None);
    }
}
