//! Identities of the sDPD kernels (`docs/models.md` §3.7): normalisation, F = −W'/r, the proposed
//! kernel at s = 2 is Lucy's, antisymmetric pair forces, and conservative forces that are the
//! gradient of the Tait energy.

use dpdnl::forces::sdpd::kernel::{
    KernelShape, SdpdAtom, SdpdCoeff, Smoothing, Tait, sdpd_pair_force,
};
use std::f64::consts::PI;

fn kernels() -> Vec<Smoothing> {
    let mut k = vec![Smoothing::Lucy, Smoothing::Quintic];
    for s in [0.07, 0.5, 1.0, 2.1113, 3.7] {
        k.push(Smoothing::proposed(s).unwrap());
    }
    k
}

/// ∫_0^rc f(r) S_d r^(d−1) dr by composite Simpson with `n` intervals.
fn radial_integral(dim: u32, rc: f64, n: usize, f: impl Fn(f64) -> f64) -> f64 {
    let sphere = if dim == 3 { 4.0 * PI } else { 2.0 * PI };
    let h = rc / n as f64;
    let g = |r: f64| f(r) * sphere * r.powi(dim as i32 - 1);
    let mut sum = g(0.0) + g(rc);
    for k in 1..n {
        let w = if k % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * g(k as f64 * h);
    }
    sum * h / 3.0
}

/// [W] = 1 (WF-7). Simpson with 2·10⁵ intervals: the error is ≲ h^(s+2) at the support's edge,
/// below 1e-9 for the smallest s used (0.07); tolerance 1e-8.
#[test]
fn kernels_are_normalised() {
    for dim in [2, 3] {
        for rc in [1.0, 2.5] {
            for k in kernels() {
                let w = KernelShape::new(k, dim, rc).unwrap();
                let total = radial_integral(dim, rc, 200_000, |r| w.w(r));
                assert!(
                    (total - 1.0).abs() < 1e-8,
                    "{k} {dim}-D rc {rc}: [W] = {total}"
                );
            }
        }
    }
}

/// F(r) = −W'(r)/r against a central difference (step 1e-6 r_c: truncation ~1e-12 relative,
/// rounding ~1e-10 relative; tolerance 1e-7). Points keep away from the support's edge, where
/// W'' is singular for s < 1.
#[test]
fn force_is_minus_w_prime_over_r() {
    for dim in [2, 3] {
        for rc in [1.0, 2.5] {
            for k in kernels() {
                let w = KernelShape::new(k, dim, rc).unwrap();
                for u in [0.01, 0.1, 0.2, 0.31, 0.5, 0.66, 0.8, 0.9] {
                    let r = u * rc;
                    let h = 1e-6 * rc;
                    let fd = -(w.w(r + h) - w.w(r - h)) / (2.0 * h) / r;
                    let f = w.f(r);
                    assert!(
                        (f - fd).abs() <= 1e-7 * f.abs().max(1e-12),
                        "{k} {dim}-D rc {rc} u {u}: F = {f}, −W'/r = {fd}"
                    );
                }
                assert_eq!(w.w(rc), 0.0);
                assert_eq!(w.f(rc), 0.0);
                assert_eq!(w.w(1.5 * rc), 0.0);
            }
        }
    }
}

/// Lucy's closed forms (WF-25 and its 2-D form) to round-off (1e-14 of W(0), F(0)), and the proposed kernel at s = 2
/// is the same function to the bit.
#[test]
fn proposed_two_is_lucy() {
    let s2 = Smoothing::proposed(2.0).unwrap();
    for dim in [2u32, 3] {
        for rc in [1.0, 2.5] {
            let lucy = KernelShape::new(Smoothing::Lucy, dim, rc).unwrap();
            let prop = KernelShape::new(s2, dim, rc).unwrap();
            for k in 0..=100 {
                let r = rc * k as f64 / 100.0;
                let q = r / rc;
                let (w, f) = if dim == 3 {
                    (
                        105.0 / (16.0 * PI * rc.powi(3)) * (1.0 + 3.0 * q) * (1.0 - q).powi(3),
                        315.0 / (4.0 * PI * rc.powi(5)) * (1.0 - q).powi(2),
                    )
                } else {
                    (
                        5.0 / (PI * rc * rc) * (1.0 + 3.0 * q) * (1.0 - q).powi(3),
                        60.0 / (PI * rc.powi(4)) * (1.0 - q).powi(2),
                    )
                };
                // Relative to the values at r = 0: 1 − r/r_c is formed differently near r_c.
                assert!((lucy.w(r) - w).abs() <= 1e-14 * lucy.w0(), "W({r})");
                assert!((lucy.f(r) - f).abs() <= 1e-14 * lucy.f(0.0), "F({r})");
                assert_eq!(lucy.w(r).to_bits(), prop.w(r).to_bits());
                assert_eq!(lucy.f(r).to_bits(), prop.f(r).to_bits());
            }
        }
    }
}

/// A small deterministic generator for the test inputs.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn sym(&mut self) -> f64 {
        2.0 * self.next() - 1.0
    }
}

/// F_ji = −F_ij for every part, to the bit: swapping i and j flips r_ij and v_ij exactly and
/// leaves the symmetric factors (P_i/d_i² + P_j/d_j², d_i d_j, ξ_ij) unchanged.
#[test]
fn pair_force_is_antisymmetric_to_the_bit() {
    let mut g = Lcg(7);
    for k in kernels() {
        for dim in [2u32, 3] {
            let shape = KernelShape::new(k, dim, 2.5).unwrap();
            let c = SdpdCoeff::new(shape, 10.0, 1.0, 0.01).unwrap();
            for _ in 0..200 {
                let mut dr = [2.0 * g.sym(), 2.0 * g.sym(), 2.0 * g.sym()];
                let mut dv = [g.sym(), g.sym(), g.sym()];
                if dim == 2 {
                    dr[2] = 0.0;
                    dv[2] = 0.0;
                }
                let ai = SdpdAtom {
                    inv_d: 1.0 / (3.0 + g.next()),
                    pterm: g.sym(),
                };
                let aj = SdpdAtom {
                    inv_d: 1.0 / (3.0 + g.next()),
                    pterm: g.sym(),
                };
                let xi = g.sym();
                let fij = sdpd_pair_force(&c, dr, dv, xi, ai, aj);
                let neg = |v: [f64; 3]| [-v[0], -v[1], -v[2]];
                let fji = sdpd_pair_force(&c, neg(dr), neg(dv), xi, aj, ai);
                // Along e_ji = −e_ij: the projections are equal, the vectors opposite.
                assert_eq!(fij.fc.to_bits(), fji.fc.to_bits());
                assert_eq!(fij.fd.to_bits(), fji.fd.to_bits());
                assert_eq!(fij.fr.to_bits(), fji.fr.to_bits());
            }
        }
    }
}

/// The Tait energy: u(d0) = 0, P(d0) = 0, du/dd = P/d² (central difference, step 1e-6 d0,
/// tolerance 1e-7 relative to P0/d0²).
#[test]
fn tait_energy_derivative_is_pressure_term() {
    let t = Tait::new(4.0, 10.0, 1.0).unwrap();
    assert!((t.p0 - 100.0 * 4.0 / 7.0).abs() < 1e-12);
    assert_eq!(t.energy(t.d0), 0.0);
    assert_eq!(t.pressure(t.d0), 0.0);
    for x in [0.5, 0.9, 0.99, 1.0, 1.01, 1.2, 2.0] {
        let d = x * t.d0;
        let h = 1e-6 * t.d0;
        let fd = (t.energy(d + h) - t.energy(d - h)) / (2.0 * h);
        let scale = t.p0 / (t.d0 * t.d0);
        assert!(
            (fd - t.pressure_term(d)).abs() < 1e-7 * scale * (1.0 + x.powi(5)),
            "x = {x}: du/dd = {fd}, P/d^2 = {}",
            t.pressure_term(d)
        );
    }
    assert!(Tait::new(0.0, 1.0, 1.0).is_err());
    assert!(Tait::new(1.0, -1.0, 1.0).is_err());
    assert!(Tait::new(1.0, 1e300, 1e300).is_err());
}

/// The conservative pair forces are −∇ Σ_i u(d_i) (d_i with the self term): a cluster of 12
/// particles in an open box, gradient by central differences (step 1e-6: tolerance 1e-6 relative
/// to the largest force component).
#[test]
fn conservative_force_is_gradient_of_tait_energy() {
    for k in kernels() {
        for dim in [2u32, 3] {
            let rc = 1.5;
            let shape = KernelShape::new(k, dim, rc).unwrap();
            let c = SdpdCoeff::new(shape, 1.0, 1.0, 0.01).unwrap();
            let tait = Tait::new(2.0, 3.0, 1.3).unwrap();
            let mut g = Lcg(11 + dim as u64);
            let n = 12;
            let mut x: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    [
                        1.2 * g.next(),
                        1.2 * g.next(),
                        if dim == 3 { 1.2 * g.next() } else { 0.0 },
                    ]
                })
                .collect();
            let density = |x: &[[f64; 3]]| -> Vec<f64> {
                (0..n)
                    .map(|i| {
                        let mut d = shape.w0();
                        for j in 0..n {
                            if j != i {
                                let r = dist(x[i], x[j]);
                                d += shape.w(r);
                            }
                        }
                        d
                    })
                    .collect()
            };
            let energy =
                |x: &[[f64; 3]]| -> f64 { density(x).iter().map(|&d| tait.energy(d)).sum() };
            let d = density(&x);
            let atoms: Vec<SdpdAtom> = d
                .iter()
                .map(|&d| SdpdAtom {
                    inv_d: 1.0 / d,
                    pterm: tait.pressure_term(d),
                })
                .collect();
            let mut force = vec![[0.0f64; 3]; n];
            for i in 0..n {
                for j in 0..n {
                    if i == j {
                        continue;
                    }
                    let dr = sub(x[i], x[j]);
                    let r = dist(x[i], x[j]);
                    let p = sdpd_pair_force(&c, dr, [0.0; 3], 0.0, atoms[i], atoms[j]);
                    assert_eq!(p.fd, 0.0);
                    for a in 0..3 {
                        force[i][a] += p.fc * dr[a] / r.max(1e-300);
                    }
                }
            }
            let fmax = force
                .iter()
                .flat_map(|f| f.iter())
                .fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(fmax > 0.0, "{k}: no forces");
            let h = 1e-6;
            for i in 0..n {
                for a in 0..dim as usize {
                    let x0 = x[i][a];
                    x[i][a] = x0 + h;
                    let ep = energy(&x);
                    x[i][a] = x0 - h;
                    let em = energy(&x);
                    x[i][a] = x0;
                    let grad = -(ep - em) / (2.0 * h);
                    assert!(
                        (grad - force[i][a]).abs() < 1e-6 * fmax,
                        "{k} {dim}-D atom {i} axis {a}: −dE/dx = {grad}, F = {}",
                        force[i][a]
                    );
                }
            }
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Bad kernel parameters are refused with a message naming them.
#[test]
fn bad_kernel_parameters_are_refused() {
    assert!(Smoothing::proposed(0.0).is_none());
    assert!(Smoothing::proposed(-1.0).is_none());
    assert!(Smoothing::proposed(f64::NAN).is_none());
    let e = KernelShape::new(Smoothing::Lucy, 3, 0.0).unwrap_err();
    assert!(e.contains("rc"), "{e}");
    let e = KernelShape::new(Smoothing::Lucy, 4, 1.0).unwrap_err();
    assert!(e.contains("dimension"), "{e}");
    let shape = KernelShape::new(Smoothing::Lucy, 3, 1.0).unwrap();
    let e = SdpdCoeff::new(shape, 0.0, 1.0, 0.01).unwrap_err();
    assert!(e.contains("eta0"), "{e}");
}

/// The batch loop equals the scalar pair force to the bit, with every instruction set, for
/// every kernel family (the specialised s = 1, s = 2 and quintic loops and the general one),
/// with lanes in and out of range, mixed coefficient indices and a lane at r < 1e-10.
#[test]
fn batch_equals_scalar_to_the_bit() {
    use dpdnl::forces::sdpd::kernel::sdpd_forces_batch;
    use dpdnl::forces::{BATCH, Isa, PairBatch};
    use dpdnl::rng::pair_gaussian;
    let mut g = Lcg(99);
    for k in [
        Smoothing::Lucy,
        Smoothing::Quintic,
        Smoothing::proposed(1.0).unwrap(),
        Smoothing::proposed(0.37).unwrap(),
    ] {
        for dim in [2u32, 3] {
            let coeff: Vec<SdpdCoeff> = [1.0, 1.3]
                .iter()
                .enumerate()
                .map(|(m, &rc)| {
                    let shape = KernelShape::new(k, dim, rc).unwrap();
                    SdpdCoeff::new(shape, 3.0 + m as f64, 1.2, 0.004).unwrap()
                })
                .collect();
            let atoms: Vec<SdpdAtom> = (0..50)
                .map(|_| SdpdAtom {
                    inv_d: 1.0 / (2.0 + g.next()),
                    pterm: g.sym(),
                })
                .collect();
            let mut b = PairBatch::default();
            let (mut iv, mut jv) = (vec![0u32; BATCH], vec![0u32; BATCH]);
            for l in 0..BATCH {
                for c in 0..3 {
                    b.dr[c][l] = if c == 2 && dim == 2 {
                        0.0
                    } else {
                        0.9 * g.sym()
                    };
                    b.dv[c][l] = g.sym();
                }
                if l == 5 {
                    b.dr = b.dr.map(|mut a| {
                        a[5] = 1e-12;
                        a
                    });
                }
                b.coeff[l] = (l % 3 == 0) as u32;
                b.tag_i[l] = 1 + (g.next() * 1000.0) as u32;
                b.tag_j[l] = 1001 + (g.next() * 1000.0) as u32;
                iv[l] = (g.next() * 50.0) as u32;
                jv[l] = (g.next() * 50.0) as u32;
            }
            for isa in [Isa::Baseline, Isa::Avx2, Isa::Avx512] {
                for n in [BATCH, 17] {
                    let mut bb = b.clone();
                    bb.len = n;
                    sdpd_forces_batch(isa, &coeff, &atoms, 7, 42, &mut bb, &iv[..n], &jv[..n]);
                    for l in 0..n {
                        let dr = [b.dr[0][l], b.dr[1][l], b.dr[2][l]];
                        let dv = [b.dv[0][l], b.dv[1][l], b.dv[2][l]];
                        let xi = pair_gaussian(7, 42, b.tag_i[l], b.tag_j[l]);
                        let c = &coeff[b.coeff[l] as usize];
                        let f = sdpd_pair_force(
                            c,
                            dr,
                            dv,
                            xi,
                            atoms[iv[l] as usize],
                            atoms[jv[l] as usize],
                        );
                        let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
                        let want = if f == Default::default() {
                            0.0
                        } else {
                            f.total() / rsq.sqrt()
                        };
                        assert_eq!(
                            bb.fpair[l].to_bits(),
                            want.to_bits(),
                            "{k} {dim}-D {isa:?} lane {l}: {} vs {want}",
                            bb.fpair[l]
                        );
                    }
                }
            }
        }
    }
}
