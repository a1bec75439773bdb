//! Tier (a): exact identities of the pair kernel (`docs/models.md` §1.1–1.4; "eq. N" below is
//! the non-linear paper's, NL-N there).

use dpdnl::forces::dpd::kernel::{
    Friction, Noise, PairCoeff, PairForce, PairInput, PairModel, Weight, pair_force,
};
use dpdnl::rng::keyed_gaussian;

const FRICTIONS: [Friction; 3] = [Friction::None, Friction::Cross, Friction::Dot];
const NOISES: [Noise; 3] = [Noise::Plain, Noise::Corrected, Noise::TwoStep];

fn coeff() -> PairCoeff {
    PairCoeff {
        a: 25.0,
        gamma0: 5.0,
        gamma1: 1.0,
        rc: 1.0,
    }
}

/// Deterministic pseudo-random pair states inside the cut-off.
fn states(n: u32) -> Vec<PairInput> {
    (0..n)
        .filter_map(|k| {
            let g = |c: u32| keyed_gaussian(5, 99, u64::from(k), c, 0);
            let dr = [0.4 * g(0), 0.4 * g(1), 0.4 * g(2)];
            let r2: f64 = dr.iter().map(|x| x * x).sum();
            (r2 < 0.95 && r2 > 1e-4).then(|| PairInput {
                dr,
                dv: [0.5 * g(3), 0.5 * g(4), 0.5 * g(5)],
                inv_mass_sum: 1.0 + 1.0 / (1.5 + g(6).abs()),
                xi: g(7),
            })
        })
        .collect()
}

fn model(f: Friction, n: Noise, dt: f64) -> PairModel {
    PairModel::new(0.1, f, n, Weight::STANDARD, dt)
}

/// F_ji = −F_ij exactly: the pair seen from j (r_ji = −r_ij, v_ji = −v_ij, same ξ) gives the
/// bit-for-bit opposite vector.
#[test]
fn antisymmetry_is_exact() {
    for f in FRICTIONS {
        for n in NOISES {
            let m = model(f, n, 1e-3);
            for p in states(300) {
                let q = PairInput {
                    dr: p.dr.map(|x| -x),
                    dv: p.dv.map(|x| -x),
                    ..p
                };
                let a = pair_force(&m, &coeff(), &p).vector(p.dr);
                let b = pair_force(&m, &coeff(), &q).vector(q.dr);
                for k in 0..3 {
                    assert_eq!(a[k].to_bits(), (-b[k]).to_bits(), "{f:?} {n:?}");
                }
            }
        }
    }
}

fn rotate(r: [[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| r[i][0] * x[0] + r[i][1] * x[1] + r[i][2] * x[2])
}

/// Rotating r_ij and v_ij together leaves every projection on e_ij unchanged (to round-off).
#[test]
fn rotation_invariance() {
    let (a, b, c) = (0.3f64, 1.1f64, -0.7f64);
    let rz = [
        [a.cos(), -a.sin(), 0.0],
        [a.sin(), a.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ];
    let rx = [
        [1.0, 0.0, 0.0],
        [0.0, b.cos(), -b.sin()],
        [0.0, b.sin(), b.cos()],
    ];
    let ry = [
        [c.cos(), 0.0, c.sin()],
        [0.0, 1.0, 0.0],
        [-c.sin(), 0.0, c.cos()],
    ];
    for f in FRICTIONS {
        for n in NOISES {
            let m = model(f, n, 1e-3);
            for p in states(200) {
                let rot = |x| rotate(ry, rotate(rx, rotate(rz, x)));
                let q = PairInput {
                    dr: rot(p.dr),
                    dv: rot(p.dv),
                    ..p
                };
                let (x, y) = (pair_force(&m, &coeff(), &p), pair_force(&m, &coeff(), &q));
                for (u, w) in [(x.fc, y.fc), (x.fd, y.fd), (x.fr, y.fr), (x.fa, y.fa)] {
                    assert!(
                        (u - w).abs() <= 1e-12 * (1.0 + u.abs()),
                        "{f:?} {n:?}: {u} vs {w}"
                    );
                }
            }
        }
    }
}

/// The kernel sees only v_i − v_j: adding the same velocity to both changes nothing beyond the
/// round-off of forming the difference.
#[test]
fn galilean_invariance() {
    let m = model(Friction::Dot, Noise::TwoStep, 1e-3);
    for p in states(200) {
        let u = [3.7, -1.3, 0.25];
        let vi = [p.dv[0] + 0.1 + u[0], p.dv[1] - 0.2 + u[1], p.dv[2] + u[2]];
        let vj = [0.1 + u[0], -0.2 + u[1], u[2]];
        let q = PairInput {
            dv: [vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]],
            ..p
        };
        let (x, y) = (pair_force(&m, &coeff(), &p), pair_force(&m, &coeff(), &q));
        assert!((x.total() - y.total()).abs() <= 1e-12 * (1.0 + x.total().abs()));
    }
}

/// The cross estimator's correction vanishes (eq. 72): corrected == plain bit for bit.
#[test]
fn cross_correction_is_zero() {
    let plain = model(Friction::Cross, Noise::Plain, 1e-3);
    let corr = model(Friction::Cross, Noise::Corrected, 1e-3);
    for p in states(300) {
        let (a, b) = (
            pair_force(&plain, &coeff(), &p),
            pair_force(&corr, &coeff(), &p),
        );
        assert_eq!(b.fa, 0.0);
        assert_eq!(a, b);
    }
}

/// Plain noise amplitude: (F^R δt^(1/2) / (w_R ξ))² = σ² = 2 kT γ(S) with S at t (eq. 31).
#[test]
fn plain_amplitude_obeys_fdt() {
    for f in FRICTIONS {
        let m = model(f, Noise::Plain, 2.5e-3);
        for p in states(300) {
            let pf = pair_force(&m, &coeff(), &p);
            let r = p.dr.iter().map(|x| x * x).sum::<f64>().sqrt();
            let wr = 1.0 - r;
            let sigma2 = (pf.fr * 2.5e-3f64.sqrt() / (wr * p.xi)).powi(2);
            let gamma = f.gamma(&coeff(), f.rate(p.dr, p.dv));
            assert!(
                (sigma2 - 2.0 * 0.1 * gamma).abs() <= 1e-12 * sigma2,
                "{f:?}"
            );
            // and the dissipative part is −γ w_D (e·v)
            let ev = p.dr.iter().zip(p.dv).map(|(a, b)| a * b).sum::<f64>() / r;
            assert!((pf.fd + gamma * wr * wr * ev).abs() <= 1e-12 * (1.0 + pf.fd.abs()));
        }
    }
}

/// F^A = kT (1/m_i + 1/m_j) w_D (e · ∂γ/∂v) ξ² (eq. 32): check the analytic gradient against a
/// central finite difference of γ(S(r, v + h e)).
#[test]
fn correction_matches_finite_difference() {
    let m = model(Friction::Dot, Noise::Corrected, 1e-3);
    let c = coeff();
    for p in states(200) {
        let pf = pair_force(&m, &c, &p);
        let r = p.dr.iter().map(|x| x * x).sum::<f64>().sqrt();
        let e = p.dr.map(|x| x / r);
        // h = 1e-4: truncation error O(h²) ~ 1e-8 relative, cancellation ~ ε γ / h ~ 1e-11.
        let h = 1e-4;
        let g = |s: f64| {
            let v = [p.dv[0] + s * e[0], p.dv[1] + s * e[1], p.dv[2] + s * e[2]];
            Friction::Dot.gamma(&c, Friction::Dot.rate(p.dr, v))
        };
        let de_gamma = (g(h) - g(-h)) / (2.0 * h);
        let want = 0.1 * p.inv_mass_sum * (1.0 - r).powi(2) * de_gamma * p.xi * p.xi;
        assert!(
            (pf.fa - want).abs() <= 1e-6 * want.abs() + 1e-12,
            "{} vs {want}",
            pf.fa
        );
    }
}

fn slope(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Two-step equals corrected to O(δt) (eqs. 39–42): per step the random *impulses* differ by
/// O(δt^(3/2)), while plain and corrected differ by O(δt). Log–log slopes over δt = 1e-2..1e-6.
#[test]
fn twostep_converges_to_corrected() {
    let c = coeff();
    let dts: Vec<f64> = (0..9)
        .map(|k| 1e-2 * 10f64.powf(-0.5 * f64::from(k)))
        .collect();
    for p in states(40).into_iter().take(10) {
        let (mut d_ts, mut d_pl) = (Vec::new(), Vec::new());
        for &dt in &dts {
            let imp = |n: Noise| {
                let f = pair_force(&model(Friction::Dot, n, dt), &c, &p);
                (f.fr + f.fa) * dt
            };
            let corrected = imp(Noise::Corrected);
            d_ts.push((imp(Noise::TwoStep) - corrected).abs().ln());
            d_pl.push((imp(Noise::Plain) - corrected).abs().ln());
        }
        let x: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
        let (s_ts, s_pl) = (slope(&x, &d_ts), slope(&x, &d_pl));
        assert!(
            (s_ts - 1.5).abs() < 0.1,
            "two-step − corrected impulse slope {s_ts}"
        );
        assert!(
            (s_pl - 1.0).abs() < 0.02,
            "plain − corrected impulse slope {s_pl}"
        );
    }
}

/// Outside the cut-off and at r = 0 every part is zero; at r → r_c the weights vanish.
#[test]
fn cutoff_and_overlap() {
    let m = model(Friction::Dot, Noise::Corrected, 1e-3);
    let base = PairInput {
        dr: [1.0, 0.0, 0.0],
        dv: [0.3, 0.1, 0.0],
        inv_mass_sum: 2.0,
        xi: 1.3,
    };
    assert_eq!(pair_force(&m, &coeff(), &base), PairForce::default());
    let zero = PairInput {
        dr: [0.0; 3],
        ..base
    };
    assert_eq!(pair_force(&m, &coeff(), &zero), PairForce::default());
    let near = PairInput {
        dr: [1.0 - 1e-9, 0.0, 0.0],
        ..base
    };
    assert!(pair_force(&m, &coeff(), &near).total().abs() < 1e-6);
}

/// General weight exponent: w_D = (1 − r/r_c)^s and w_R² = w_D for any s > 0.
#[test]
fn weight_exponents() {
    for s in [0.07, 0.5, 1.0, 2.0, 3.3] {
        let w = Weight::new(s).expect("valid exponent");
        for q in [1e-3, 0.2, 0.5, 0.99, 1.0] {
            let (wd, wr) = w.wd_wr(q);
            assert!((wd - q.powf(s)).abs() <= 1e-14 * q.powf(s).max(1e-300));
            assert!((wr * wr - wd).abs() <= 1e-15);
        }
    }
    assert!(
        Weight::new(0.0).is_none()
            && Weight::new(-1.0).is_none()
            && Weight::new(f64::NAN).is_none()
    );
}

/// In 2-D (z = 0) the cross estimator is (x v_y − y v_x)².
#[test]
fn cross_estimator_in_2d() {
    let (x, y, vx, vy) = (0.3, -0.4, 0.7, 0.2);
    let s = Friction::Cross.rate([x, y, 0.0], [vx, vy, 0.0]);
    assert!((s - (x * vy - y * vx).powi(2)).abs() < 1e-15);
    let d = Friction::Dot.rate([x, y, 0.0], [vx, vy, 0.0]);
    assert!((d - (x * vx + y * vy).powi(2)).abs() < 1e-15);
}

#[test]
fn coefficient_validation() {
    let ok = coeff();
    assert!(ok.validate().is_ok());
    for (bad, word) in [
        (PairCoeff { gamma0: -1.0, ..ok }, "gamma0"),
        (PairCoeff { gamma1: -1.0, ..ok }, "gamma1"),
        (PairCoeff { rc: 0.0, ..ok }, "rc"),
        (PairCoeff { a: f64::NAN, ..ok }, "a"),
    ] {
        let e = bad.validate().expect_err("must be rejected");
        assert!(e.contains(word), "{e}");
    }
}

/// T = 0, as LAMMPS's `pair dpd` has it: in every friction × noise scheme the random part and
/// the correction are exactly 0 (σ = sqrt(2 kT γ) = 0; the two-step impulse vanishes, so
/// v'' = v and S'' = S; F^A ∝ kT), and the conservative and dissipative parts are those of
/// kT > 0, the friction kept: for constant friction a (1 − r/r_c) and −γ0 (1 − r/r_c)² (e·v)
/// written out here.
#[test]
fn zero_temperature_keeps_friction_without_noise() {
    let c = coeff();
    for f in FRICTIONS {
        for n in NOISES {
            let cold = PairModel::new(0.0, f, n, Weight::STANDARD, 1e-3);
            let warm = model(f, n, 1e-3);
            for p in states(300) {
                let a = pair_force(&cold, &c, &p);
                let b = pair_force(&warm, &c, &p);
                assert_eq!(a.fr, 0.0, "{f:?} {n:?}: random part {}", a.fr);
                assert_eq!(a.fa, 0.0, "{f:?} {n:?}: correction {}", a.fa);
                assert_eq!(a.fc.to_bits(), b.fc.to_bits(), "{f:?} {n:?}");
                assert_eq!(a.fd.to_bits(), b.fd.to_bits(), "{f:?} {n:?}");
                assert_eq!(a.total().to_bits(), (a.fc + a.fd).to_bits());
                if f == Friction::None {
                    let r = p.dr.iter().map(|x| x * x).sum::<f64>().sqrt();
                    let q = 1.0 - r / c.rc;
                    let ev = (0..3).map(|k| p.dr[k] * p.dv[k]).sum::<f64>() / r;
                    let (fc, fd) = (c.a * q, -c.gamma0 * q * q * ev);
                    assert!((a.fc - fc).abs() <= 1e-14 * c.a, "{n:?}: {} vs {fc}", a.fc);
                    assert!(
                        (a.fd - fd).abs() <= 1e-13 * fd.abs().max(1e-12),
                        "{n:?}: {} vs {fd}",
                        a.fd
                    );
                }
            }
        }
    }
}
