//! The sDPD kinetic theory (`dpdnl::theory::sdpd`) against the weighting-function paper: Table 1's
//! coefficients, the η̄ column of the sDPD rows of Tables 2–4 and the s column of Table 4
//! (`tests/data/weighting_sdpd_tables_2d.csv`, a copy of the project's reference CSV), each at its
//! printed precision; and the kernel moments against a quadrature of the engine's kernels.

use dpdnl::forces::sdpd::kernel::{KernelShape, Smoothing};
use dpdnl::theory::sdpd::{eta_min, eta0_for, kernel_moment, kinetic_coefficient, kinetic_theory};
use dpdnl::theory::{Dim, Fluid, design_paper_approx};
use std::f64::consts::PI;

mod common;
use common::{agrees, paper_fluid};

const SDPD_CSV: &str = include_str!("data/weighting_sdpd_tables_2d.csv");

/// Table 1 (and eqs. 29, 37, 45, 60): c of η_K = c m kT n² r_c²/η0, from the closed-form \[F\]
/// of each kernel, equals the printed fractions to round-off (4 ulp).
#[test]
fn table_1_coefficients() {
    let half = Smoothing::proposed(0.5).unwrap();
    for (dim, kernel, num, den) in [
        (Dim::Three, Smoothing::Lucy, 1.0, 70.0),
        (Dim::Two, Smoothing::Lucy, 1.0, 80.0),
        (Dim::Three, Smoothing::Quintic, 1.0, 120.0),
        (Dim::Two, Smoothing::Quintic, 239.0, 33264.0),
        (Dim::Three, half, 4.0, 165.0),
        (Dim::Two, half, 1.0, 42.0),
    ] {
        let c = kinetic_coefficient(dim, kernel).unwrap();
        let want = num / den;
        assert!(
            ((c - want) / want).abs() < 4.0 * f64::EPSILON,
            "{dim} {kernel}: c = {c}, Table 1 {num}/{den}"
        );
    }
    // The proposed kernel's general forms (eqs. 45 and 60) for any s.
    for s in [0.0025, 0.07, 0.5, 1.0, 2.1113, 5.0] {
        let k = Smoothing::proposed(s).unwrap();
        let c3 = kinetic_coefficient(Dim::Three, k).unwrap();
        let c2 = kinetic_coefficient(Dim::Two, k).unwrap();
        let w3 = 3.0 / (5.0 * (s + 4.0) * (s + 5.0));
        let w2 = 3.0 / (8.0 * (s + 3.0) * (s + 4.0));
        assert!(
            ((c3 - w3) / w3).abs() < 1e-14 && ((c2 - w2) / w2).abs() < 1e-14,
            "s {s}"
        );
    }
}

/// \[F\] in closed form equals Simpson's rule on the engine's own F(r), in r = r_c (1 − t²) so
/// that the edge factor (1 − r/r_c)^s becomes t^(2s) (2·10⁵ intervals: error below 1e-10 for
/// s ≥ 0.07; tolerance 1e-8): theory and kernels describe one function.
#[test]
fn kernel_moments_match_the_engine_kernels() {
    for dim in [Dim::Two, Dim::Three] {
        for kernel in [
            Smoothing::Lucy,
            Smoothing::Quintic,
            Smoothing::proposed(0.07).unwrap(),
            Smoothing::proposed(0.5).unwrap(),
            Smoothing::proposed(3.0).unwrap(),
        ] {
            let rc = 2.5;
            let shape = KernelShape::new(kernel, dim.get(), rc).unwrap();
            let sphere = if dim == Dim::Three {
                4.0 * PI
            } else {
                2.0 * PI
            };
            let n = 200_000;
            let h = 1.0 / n as f64;
            let g = |t: f64| {
                let r = rc * (1.0 - t * t);
                shape.f(r) * sphere * r.powi(dim.get() as i32 - 1) * 2.0 * rc * t
            };
            let mut sum = g(0.0) + g(1.0);
            for k in 1..n {
                sum += if k % 2 == 1 { 4.0 } else { 2.0 } * g(k as f64 * h);
            }
            let quad = sum * h / 3.0;
            let closed = kernel_moment(dim, kernel, rc).unwrap();
            assert!(
                ((quad - closed) / closed).abs() < 1e-8,
                "{dim} {kernel}: [F] = {closed}, quadrature {quad}"
            );
        }
    }
}

/// Every sDPD row of the CSV: η̄ = η0 + η_K at the printed precision (Tables 2, 3, 4), and for
/// Table 4 the s of the paper's design (eq. 65 with η ≈ η0) at its printed precision.
#[test]
fn sdpd_rows_reproduce_eta_bar_and_s() {
    let mut checked = 0;
    for line in SDPD_CSV.lines() {
        if line.starts_with('#') || line.starts_with("table") || line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let (table, kernel, rc, sc0, eta0, s, eta_bar) = (f[0], f[2], f[3], f[4], f[5], f[6], f[7]);
        let fluid = paper_fluid(rc.parse().unwrap());
        let eta0: f64 = eta0.parse().unwrap();
        let k = match kernel {
            "lucy" => Smoothing::Lucy,
            "quintic" => Smoothing::Quintic,
            _ => {
                let s_used = if sc0.is_empty() {
                    s.parse().unwrap()
                } else {
                    let d = design_paper_approx(&fluid, eta0, sc0.parse().unwrap()).unwrap();
                    assert!(
                        agrees(d.s, s),
                        "table {table} eta0 {eta0}: s = {}, paper {s}",
                        d.s
                    );
                    d.s
                };
                Smoothing::proposed(s_used).unwrap()
            }
        };
        let t = kinetic_theory(&fluid, k, eta0).unwrap();
        assert!(
            agrees(t.eta, eta_bar),
            "table {table} {kernel} eta0 {eta0}: eta_bar = {}, paper {eta_bar}",
            t.eta
        );
        assert_eq!(t.eta_d, eta0);
        assert!(((t.schmidt - t.eta / (2.0 * t.eta_k)) / t.schmidt).abs() < 1e-15);
        checked += 1;
    }
    assert_eq!(checked, 34, "sDPD rows in the CSV");
}

/// Fig. 4's kinetic-theory D = 0.0306 (Sc0 = 400, η0 = 49, s = 0.0700, r_c = 2.5): D = 2η_K/(m n).
#[test]
fn figure_4_diffusion() {
    let fluid = paper_fluid(2.5);
    let d = design_paper_approx(&fluid, 49.0, 400.0).unwrap();
    let t = kinetic_theory(&fluid, Smoothing::proposed(d.s).unwrap(), 49.0).unwrap();
    assert!(agrees(t.diffusion, "0.0306"), "D = {}", t.diffusion);
}

/// The smallest viscosity (eqs. 31, 50, 64) and the liquid root of eq. 32: η0_for(η_min)
/// = sqrt(cX), η0_for(η) reproduces η through the kinetic theory, and η below η_min is refused.
/// Lucy 3-D at n = 4, m = kT = 1: η_min = sqrt(4X/70) = 0.9562 (r_c = 1), 2.3905 (r_c = 2.5).
#[test]
fn smallest_viscosity_and_liquid_root() {
    for (rc, printed) in [(1.0, "0.9562"), (2.5, "2.3905")] {
        let fluid = Fluid::new(3, 4.0, rc, 1.0, 1.0).unwrap();
        let m = eta_min(&fluid, Smoothing::Lucy).unwrap();
        assert!(agrees(m, printed), "rc {rc}: eta_min = {m}");
        for eta in [m, 1.5 * m, 10.0 * m] {
            let e0 = eta0_for(&fluid, Smoothing::Lucy, eta).unwrap();
            let t = kinetic_theory(&fluid, Smoothing::Lucy, e0).unwrap();
            assert!(((t.eta - eta) / eta).abs() < 1e-7, "{eta}: {}", t.eta);
            assert!(e0 >= 0.5 * eta, "liquid branch: eta0 = {e0} >= eta/2");
        }
        assert!(eta0_for(&fluid, Smoothing::Lucy, 0.99 * m).is_err());
    }
}
