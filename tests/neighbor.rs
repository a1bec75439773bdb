//! The pair loop of the standalone engine (src/engine/neighbor.rs): its forces, energy and
//! virial against a brute-force sum over all pairs with the kernel, and the same bits for every
//! thread count and instruction set (slab mode with 3-D and 2-D boxes, the serial small-box
//! mode, one and two atom types).

use dpdnl::engine::{ForceField, Integrator, NeighborList, SimBox, System};
use dpdnl::forces::Isa;
use dpdnl::forces::dpd::DpdPair;
use dpdnl::forces::dpd::kernel::{
    Friction, Noise, PairCoeff, PairInput, PairModel, Weight, pair_force,
};
use dpdnl::rng::{keyed_gaussian, keyed_uniform, pair_gaussian};

mod common;
use common::state_by_tag;

const SEED: u32 = 9898;

struct Spec {
    dim: usize,
    /// Box side (the 2-D box is l × l × 1).
    l: f64,
    /// Atoms per type (a second type only if the second number is > 0).
    n: [usize; 2],
    friction: Friction,
    noise: Noise,
    weight: f64,
}

fn fluid(s: &Spec, isa: Option<Isa>, working: Option<bool>) -> System {
    let (lo, hi) = if s.dim == 3 {
        ([0.0; 3], [s.l; 3])
    } else {
        ([0.0, 0.0, -0.5], [s.l, s.l, 0.5])
    };
    let ntypes = if s.n[1] > 0 { 2 } else { 1 };
    let mut sys = System::new(SimBox::new(s.dim, lo, hi).expect("box"), ntypes);
    sys.mass[1] = Some(1.0);
    if ntypes == 2 {
        sys.mass[2] = Some(2.5);
    }
    let mut tag = 0u32;
    for (t, &count) in s.n.iter().enumerate() {
        for _ in 0..count {
            tag += 1;
            let mut x = [0, 1, 2].map(|c| s.l * keyed_uniform(17, 3, 0, tag, c));
            let mut v = [0, 1, 2].map(|c| keyed_gaussian(17, 2, 0, tag, c));
            if s.dim == 2 {
                x[2] = 0.0;
                v[2] = 0.0;
            }
            sys.atoms.push(tag, t as u32 + 1, x, v, [0; 3]);
        }
    }
    let weight = Weight::new(s.weight).expect("s > 0");
    let model = PairModel::new(1.0, s.friction, s.noise, weight, 0.01);
    let mut ff = ForceField::new(model, SEED, 1.0, ntypes);
    let c = |a: f64, g1: f64, rc: f64| PairCoeff {
        a,
        gamma0: 4.5,
        gamma1: g1,
        rc,
    };
    ff.set(1, 1, c(25.0, 0.5, 1.0));
    if ntypes == 2 {
        ff.set(2, 2, c(30.0, 0.2, 0.9));
        ff.set(1, 2, c(20.0, 1.0, 0.8));
    }
    sys.set_pair(DpdPair::from_field(ff));
    sys.dt = 0.01;
    sys.integrator = Some(Integrator::VelocityVerlet);
    sys.neighbor = NeighborList::new(0.3);
    sys.neighbor.set_isa(isa);
    sys.neighbor.set_working_list(working);
    sys
}

fn specs() -> Vec<(&'static str, Spec)> {
    vec![
        (
            "3-D, 2 types, dot/twostep, 5 slabs",
            Spec {
                dim: 3,
                l: 7.0,
                n: [700, 330],
                friction: Friction::Dot,
                noise: Noise::TwoStep,
                weight: 2.0,
            },
        ),
        (
            "3-D, 1 type, none/plain, 6 slabs",
            Spec {
                dim: 3,
                l: 8.0,
                n: [1536, 0],
                friction: Friction::None,
                noise: Noise::Plain,
                weight: 2.0,
            },
        ),
        (
            "3-D, 1 type, cross/corrected, s = 1.5, serial (2 layers)",
            Spec {
                dim: 3,
                l: 3.5,
                n: [170, 0],
                friction: Friction::Cross,
                noise: Noise::Corrected,
                weight: 1.5,
            },
        ),
        (
            "2-D, 2 types, dot/corrected, 9 slabs along y",
            Spec {
                dim: 2,
                l: 12.0,
                n: [400, 176],
                friction: Friction::Dot,
                noise: Noise::Corrected,
                weight: 2.0,
            },
        ),
    ]
}

/// Forces, energy and virial of the set-up against the direct double sum over all pairs
/// (minimum image, `pair_force` with the keyed ξ of step 0). Only the summation order
/// differs, so each force component agrees to 1e-12 of the sum of the magnitudes of its terms
/// (a few tens of terms, each rounding at 1.1e-16 relative), and so do energy and virial.
#[test]
fn forces_match_brute_force() {
    for (name, spec) in specs() {
        let mut sys = fluid(&spec, None, None);
        sys.setup().expect("setup");
        let a = &sys.atoms;
        let n = a.len();
        let ff = common::dpd(&sys).expect("ff");
        let inv_m = |t: u32| 1.0 / sys.mass[t as usize].expect("mass");
        let mut f = vec![[0.0; 3]; n];
        let mut scale = vec![[0.0; 3]; n];
        let (mut energy, mut virial) = (0.0, [0.0; 6]);
        let (mut e_scale, mut v_scale) = (0.0, [0.0; 6]);
        let mut pairs = 0;
        for i in 0..n {
            for j in i + 1..n {
                let xi = a.x[i];
                let xj = a.x[j];
                let dr = sys
                    .bx
                    .min_image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                let c = ff
                    .get(a.typ[i] as usize, a.typ[j] as usize)
                    .expect("coefficients");
                let input = PairInput {
                    dr,
                    dv: [0, 1, 2].map(|k| a.v[i][k] - a.v[j][k]),
                    inv_mass_sum: inv_m(a.typ[i]) + inv_m(a.typ[j]),
                    xi: pair_gaussian(SEED, 0, a.tag[i], a.tag[j]),
                };
                let pf = pair_force(&ff.model, c, &input);
                if pf.inv_r == 0.0 {
                    continue;
                }
                pairs += 1;
                let fv = pf.vector(dr);
                for k in 0..3 {
                    f[i][k] += fv[k];
                    f[j][k] -= fv[k];
                    scale[i][k] += fv[k].abs();
                    scale[j][k] += fv[k].abs();
                }
                energy += pf.energy;
                e_scale += pf.energy.abs();
                let w = [
                    dr[0] * fv[0],
                    dr[1] * fv[1],
                    dr[2] * fv[2],
                    dr[0] * fv[1],
                    dr[0] * fv[2],
                    dr[1] * fv[2],
                ];
                for k in 0..6 {
                    virial[k] += w[k];
                    v_scale[k] += w[k].abs();
                }
            }
        }
        // Density 2–3.6: about 4–7 pairs per atom in range.
        assert!(pairs > 2 * n, "{name}: only {pairs} pairs in range");
        for i in 0..n {
            for k in 0..3 {
                let d = (a.f[i][k] - f[i][k]).abs();
                assert!(
                    d <= 1e-12 * scale[i][k],
                    "{name}: atom tag {} component {k}: engine {} vs direct {}",
                    a.tag[i],
                    a.f[i][k],
                    f[i][k]
                );
            }
        }
        assert!(
            (sys.tally.energy - energy).abs() <= 1e-12 * e_scale,
            "{name}: energy {} vs {energy}",
            sys.tally.energy
        );
        for k in 0..6 {
            assert!(
                (sys.tally.virial[k] - virial[k]).abs() <= 1e-12 * v_scale[k],
                "{name}: virial[{k}] {} vs {}",
                sys.tally.virial[k],
                virial[k]
            );
        }
    }
}

/// 100 steps give the same bits with 1, 2 and 3 threads, with each instruction set of the
/// pair loop (the AVX-512 and AVX2 paths load x and v of 8 or 4 entries at once and keep the
/// in-range ones by a compress or a permutation table, the baseline does not), and
/// with the working list on or off; the list is rebuilt during the run.
#[test]
fn same_bits_for_threads_instruction_sets_and_working_list() {
    for (name, spec) in specs() {
        let mut reference = None;
        let mut configs = Vec::new();
        for isa in [Isa::Baseline, Isa::Avx2, Isa::Avx512] {
            for threads in [1, 2, 3] {
                configs.push((isa, threads, Some(false)));
            }
        }
        configs.push((Isa::Avx512, 2, Some(true)));
        configs.push((Isa::Avx2, 2, Some(true)));
        configs.push((Isa::Baseline, 1, Some(true)));
        for (isa, threads, working) in configs {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let (state, builds) = pool.install(|| {
                let mut sys = fluid(&spec, Some(isa), working);
                sys.setup().expect("setup");
                for _ in 0..100 {
                    sys.step_once();
                }
                (state_by_tag(&sys), sys.neighbor.builds)
            });
            assert!(builds > 1, "{name}: the list was never rebuilt");
            match &reference {
                None => reference = Some(state),
                Some(r) => assert!(
                    *r == state,
                    "{name}: {isa:?}, {threads} threads, working list {working:?} differs from the first run"
                ),
            }
        }
    }
}
