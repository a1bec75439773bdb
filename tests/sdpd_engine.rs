//! `pair_style sdpd` in the standalone engine: the same bits for any thread count (periodic
//! slab loop and Lees–Edwards loop), momentum conserved to round-off, the density pass against
//! a brute-force sum, the sampled temperature, and input errors.
#![allow(clippy::needless_range_loop)]

use dpdnl::engine::System;
use dpdnl::forces::sdpd::kernel::{KernelShape, Smoothing};

mod common;
use common::{run, state_by_tag};

/// A script for an sDPD fluid: `dim`-D, `n_atoms` atoms at number density 4, `kernel` words.
fn script(dim: u32, n_atoms: usize, kernel: &str, extra: &str, steps: u64) -> String {
    let l = if dim == 3 {
        (n_atoms as f64 / 4.0).cbrt()
    } else {
        (n_atoms as f64 / 4.0).sqrt()
    };
    let (zlo, zhi) = if dim == 3 { (0.0, l) } else { (-0.5, 0.5) };
    let enforce = if dim == 2 { "fix 2 all enforce2d" } else { "" };
    format!(
        "units lj\ndimension {dim}\nboundary p p p\natom_style atomic\n\
         region box block 0 {l} 0 {l} {zlo} {zhi}\ncreate_box 1 box\n\
         create_atoms 1 random {n_atoms} 8675 box\nmass 1 1.0\n\
         velocity all create 1.0 4928 mom yes dist gaussian\n\
         pair_style sdpd 1.0 2.0 34387 kernel {kernel}\npair_coeff 1 1 4 8 5\n\
         neighbor 0.3 bin\nneigh_modify delay 0 every 1 check yes\ntimestep 0.005\n\
         fix 1 all nve\n{enforce}\n{extra}\nthermo 0\nrun {steps}\n"
    )
}

fn run_threads(text: &str, threads: usize) -> System {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| run(text).expect("script runs").1.expect("a system"))
}

/// The same bits with 1, 2 and 3 threads: periodic 3-D (slab mode: the box holds ≥ 3 cells of
/// rc + skin along z), periodic 2-D, and a sheared 2-D box (Lees–Edwards).
#[test]
fn same_bits_for_any_thread_count() {
    let cases = [
        script(3, 1500, "lucy", "", 40),
        script(2, 900, "proposed 0.5", "", 40),
        script(2, 400, "quintic", "", 40),
        script(2, 900, "lucy", "", 40)
            .replace("region box block", "region box prism")
            .replace(" -0.5 0.5\n", " -0.5 0.5 0 0 0\n")
            .replace(
                "fix 1 all nve\n",
                "fix 1 all nve\nfix 3 all deform 1 xy erate 0.5 remap v\n",
            ),
    ];
    for text in &cases {
        let a = run_threads(text, 1);
        for t in [2, 3] {
            let b = run_threads(text, t);
            assert!(
                state_by_tag(&a) == state_by_tag(&b),
                "{t} threads differ from 1:\n{text}"
            );
        }
    }
}

/// Σ m v stays at its initial value (zero, `velocity … mom yes`) to round-off over 200 steps:
/// every pair force is applied ±, so only the rounding of the sums remains (tolerance 1e-10 per
/// atom, on velocities of order 1).
#[test]
fn momentum_is_conserved() {
    for text in [
        script(3, 1500, "lucy", "", 200),
        script(2, 900, "quintic", "", 200),
    ] {
        let sys = run(&text).expect("runs").1.expect("system");
        let n = sys.atoms.len() as f64;
        let mut p = [0.0f64; 3];
        for v in &sys.atoms.v {
            for k in 0..3 {
                p[k] += v[k];
            }
        }
        for k in 0..3 {
            assert!(p[k].abs() < 1e-10 * n, "P_{k} = {}", p[k]);
        }
    }
}

/// The density pass equals a brute-force O(N²) sum over minimum images with the self term.
#[test]
fn densities_match_brute_force() {
    for (dim, kernel, k) in [
        (3, "lucy", Smoothing::Lucy),
        (2, "quintic", Smoothing::Quintic),
        (2, "proposed 0.5", Smoothing::Proposed(0.5)),
    ] {
        let text = script(dim, 1200, kernel, "", 3);
        let sys = run(&text).expect("runs").1.expect("system");
        let sd = common::sdpd(&sys).expect("sdpd");
        let shape = KernelShape::new(k, dim, 2.0).unwrap();
        let a = &sys.atoms;
        let len = sys.bx.len();
        for i in (0..a.len()).step_by(37) {
            let mut d = shape.w0();
            for j in 0..a.len() {
                if j == i {
                    continue;
                }
                let mut r2 = 0.0;
                for q in 0..dim as usize {
                    let mut x = a.x[i][q] - a.x[j][q];
                    x -= len[q] * (x / len[q]).round();
                    r2 += x * x;
                }
                if r2 < 4.0 {
                    d += shape.w(r2.sqrt());
                }
            }
            let got = sd.density[i];
            assert!(
                (got - d).abs() < 1e-12 * d,
                "{kernel}: atom {} d = {got}, brute force {d}",
                a.tag[i]
            );
        }
    }
}

/// The sampled temperature is kT: 2-D, 400 atoms, Lucy, 6000 steps after 1000, T every 10 steps
/// in 20 blocks. The block error is ~0.004; tolerance 4 block errors plus 0.5 % for the finite
/// step (velocity Verlet at δt = 0.005; measured bias here is below the block error).
#[test]
fn temperature_is_sampled() {
    let text = script(2, 400, "lucy", "", 1000);
    let mut sys = run(&text).expect("runs").1.expect("system");
    sys.setup().expect("setup");
    let mut t = Vec::new();
    for k in 0..6000 {
        sys.step_once();
        if k % 10 == 9 {
            t.push(sys.thermo().temp);
        }
    }
    let nb = 20;
    let per = t.len() / nb;
    let blocks: Vec<f64> = (0..nb)
        .map(|b| t[b * per..(b + 1) * per].iter().sum::<f64>() / per as f64)
        .collect();
    let mean = blocks.iter().sum::<f64>() / nb as f64;
    let var = blocks.iter().map(|b| (b - mean).powi(2)).sum::<f64>() / (nb - 1) as f64;
    let err = (var / nb as f64).sqrt();
    assert!(
        (mean - 1.0).abs() < 4.0 * err + 0.005,
        "<T> = {mean} ± {err}, want 1"
    );
}

/// Bad `pair_style sdpd` / `pair_coeff` words stop the script at their line.
#[test]
fn bad_input_is_refused() {
    for (bad, want) in [
        ("gauss", "kernel 'gauss'"),
        ("proposed 0", "must be > 0"),
        ("proposed -1", "must be > 0"),
        ("proposed", "needs its exponent"),
        ("lucy 2", "unexpected argument '2'"),
    ] {
        let text = script(2, 100, bad, "", 1);
        let Err(e) = run(&text) else {
            panic!("accepted:\n{text}")
        };
        let e = e.to_string();
        assert!(e.contains(want) && e.contains("test.in:10:"), "{bad}: {e}");
    }
    for (coeff, want) in [
        ("pair_coeff 1 1 0 8 5", "rho0"),
        ("pair_coeff 1 1 4 0 5", "c0"),
        ("pair_coeff 1 1 4 8 -5", "eta0"),
        ("pair_coeff 1 1 4 8 eta 10 sc 100", "kernel proposed"),
    ] {
        let text = script(2, 100, "lucy", "", 1).replace("pair_coeff 1 1 4 8 5", coeff);
        let Err(e) = run(&text) else {
            panic!("accepted:\n{text}")
        };
        let e = e.to_string();
        assert!(
            e.contains(want) && e.contains("test.in:11:"),
            "{coeff}: {e}"
        );
    }
}

/// `compute sdpd/density`: its vector is [mean d, rms(d − mean)/mean] of the per-atom densities
/// (thermo), its per-atom values feed `fix ave/chunk` (the bin averages of d, printed with 6
/// digits, count-weight-average to the mean within 1e-5), and it needs `pair_style sdpd`.
#[test]
fn density_compute() {
    let dir = std::env::temp_dir().join(format!("dpdnl-sdpd-compute-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let prof = dir.join("d.chunk");
    let extra = format!(
        "compute d all sdpd/density\ncompute layer all chunk/atom bin/1d y lower 0.25 units reduced\n\
         fix prof all ave/chunk 1 1 10 layer c_d density/number file {}\n\
         thermo_style custom step c_d[1] c_d[2]\nthermo_modify format float %.17g\nthermo 10",
        prof.display()
    );
    let text = script(2, 900, "lucy", &extra, 10).replace("thermo 0\n", "");
    let (lines, sys) = run(&text).expect("runs");
    let sys = sys.unwrap();
    let d = &common::sdpd(&sys).unwrap().density;
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let rms = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt() / mean;
    let row = lines
        .iter()
        .find(|l| l.trim_start().starts_with("10 "))
        .expect("thermo row at step 10");
    let v: Vec<f64> = row.split_whitespace().map(|w| w.parse().unwrap()).collect();
    assert_eq!(v[1], mean, "{row}");
    assert!((v[2] - rms).abs() <= 1e-15 * rms.max(1.0), "{row} vs {rms}");
    assert!(
        rms > 0.0 && rms < 0.5 && (mean - 4.2).abs() < 0.5,
        "{mean} {rms}"
    );
    // The chunk file: 4 bins, the count-weighted mean of c_d is the mean density.
    let text = std::fs::read_to_string(&prof).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .filter(|r: &Vec<f64>| r.len() == 5)
        .collect();
    // Frames at steps 0 and 10, 4 bins each; the values are printed with 6 digits.
    assert_eq!(rows.len(), 8, "{text}");
    let (mut sum, mut count) = (0.0, 0.0);
    for r in &rows[4..] {
        sum += r[2] * r[3];
        count += r[2];
    }
    assert_eq!(count, n);
    assert!(
        (sum / count - mean).abs() < 1e-5 * mean,
        "{sum} {count} {mean}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    // Without pair_style sdpd.
    let bad = "units lj\nregion box block 0 5 0 5 0 5\ncreate_box 1 box\n\
               pair_style dpd/nonlinear 1.0 1.0 5\ncompute d all sdpd/density\n";
    let Err(e) = run(bad) else { panic!("accepted") };
    assert!(e.to_string().contains("needs pair_style sdpd"), "{e}");
}
