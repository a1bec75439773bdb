//! The test-only pair style `test/spring` (cargo feature `test-style`, src/forces/spring/): a
//! new pair style is its folder and two lines of the registry, and then runs in the standalone
//! engine with nothing else changed: its forces are the analytic F = k (1 − r/r_c) summed over
//! pairs, momentum is conserved, a restart gives back its lines and continues bit for bit, and
//! `dpdnl theory` reports it with the defaults of a style without kinetic theory.
//!
//! Run with `cargo test --features test-style --test new_style`.
#![cfg(feature = "test-style")]

use dpdnl::engine::System;

mod common;
use common::{run, state_by_tag};

/// Two types in a periodic 3-D box, two cut-offs, velocity-Verlet.
const SYSTEM: &str = "units lj\natom_style atomic\nregion box block 0 6 0 6 0 6\n\
    create_box 2 box\ncreate_atoms 1 random 300 4242 box\ncreate_atoms 2 random 200 4343 box\n\
    mass 1 1.0\nmass 2 2.0\nvelocity all create 1.0 87287 mom yes\n\
    pair_style test/spring 1.0\npair_coeff * * 10.0\npair_coeff 1 2 5.0 0.8\n\
    timestep 0.005\nfix 1 all nve\nthermo 0\n";

/// k and r_c of type pair (ti, tj), as the script sets them.
fn coeff(ti: u32, tj: u32) -> (f64, f64) {
    if ti != tj { (5.0, 0.8) } else { (10.0, 1.0) }
}

fn system(extra: &str) -> System {
    let (_, sys) = run(&format!("{SYSTEM}{extra}")).expect("the script runs");
    sys.expect("a system")
}

fn momentum(sys: &System) -> [f64; 3] {
    let a = &sys.atoms;
    let mut p = [0.0; 3];
    for i in 0..a.len() {
        let m = sys.mass[a.typ[i] as usize].expect("mass");
        for (k, pk) in p.iter_mut().enumerate() {
            *pk += m * a.v[i][k];
        }
    }
    p
}

#[test]
fn forces_are_the_analytic_spring_sum() {
    let sys = system("run 0\n");
    let a = &sys.atoms;
    let n = a.len();
    let mut f = vec![[0.0; 3]; n];
    let mut pairs = 0;
    for i in 0..n {
        for j in i + 1..n {
            let d = sys
                .bx
                .min_image(std::array::from_fn(|k| a.x[i][k] - a.x[j][k]));
            let r = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            let (k, rc) = coeff(a.typ[i], a.typ[j]);
            if r >= rc {
                continue;
            }
            pairs += 1;
            let mag = k * (1.0 - r / rc);
            for c in 0..3 {
                f[i][c] += mag * d[c] / r;
                f[j][c] -= mag * d[c] / r;
            }
        }
    }
    assert!(pairs > 1000, "{pairs} pairs in range");
    for (i, want) in f.iter().enumerate() {
        for (c, &want) in want.iter().enumerate() {
            let got = a.f[i][c];
            assert!(
                (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                "atom {} component {c}: {got} vs {want}",
                a.tag[i]
            );
        }
    }
}

#[test]
fn momentum_is_conserved() {
    let p0 = momentum(&system("run 0\n"));
    let p1 = momentum(&system("run 200\n"));
    for k in 0..3 {
        assert!(
            (p1[k] - p0[k]).abs() < 1e-11,
            "component {k}: {} then {}",
            p0[k],
            p1[k]
        );
    }
}

#[test]
fn a_restart_gives_back_the_lines_and_continues_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("dpdnl-new-style-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let file = dir.join("spring.restart");
    let written = system(&format!("run 20\nwrite_restart {}\n", file.display()));
    let settings = "timestep 0.005\nfix 1 all nve\nthermo 0\n";
    let (_, back) = run(&format!("read_restart {}\n{settings}", file.display())).expect("reads");
    let back = back.expect("a system");
    let lines = |s: &System| s.pair.as_deref().expect("pair style").restart_lines();
    assert_eq!(lines(&back), lines(&written));
    assert_eq!(lines(&back)[0][..2], ["pair_style", "test/spring"]);
    assert_eq!(
        lines(&back).len(),
        4,
        "pair_style and three pair_coeff lines"
    );
    let (_, cont) = run(&format!(
        "read_restart {}\n{settings}run 30\n",
        file.display()
    ))
    .expect("continues");
    // The same two runs in one interpreter (a run's set-up re-sorts the atoms, so the
    // comparison keeps the run boundary, as tests/restart.rs does).
    assert!(
        state_by_tag(&cont.expect("a system")) == state_by_tag(&system("run 20\nrun 30\n")),
        "the restarted run differs from the continuous one"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn theory_reports_a_style_without_kinetic_theory() {
    let dir = std::env::temp_dir().join(format!("dpdnl-new-style-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let script = dir.join("in.spring");
    std::fs::write(&script, format!("{SYSTEM}run 10\n")).expect("script");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("theory")
        .arg(&script)
        .output()
        .expect("dpdnl runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    let first = text.lines().next().expect("a heading");
    assert!(first.contains("kT = none"), "{first}");
    assert!(
        first.ends_with("integrator velocity-Verlet (fix nve), pair_style test/spring"),
        "{first}"
    );
    assert!(
        !text.lines().any(|l| l.starts_with("# pair")),
        "no pair has a prediction: {text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The test-only bonded forms `bond_style test/quartic` (E = K (r − r0)⁴) and `angle_style
/// test/square` (E = K (1 − cos θ)²), each one file in src/forces/bonded/ and its two lines in
/// that folder's `mod.rs`: the forms give −∇E (central differences, h = 1e-6: truncation
/// ~h² E''' and round-off ~ε E/h, far below the 1e-6 relative tolerance), and the engine runs
/// the polymer solution of the golden cases with them, momentum conserved to round-off.
#[test]
fn a_new_bond_and_angle_style_are_one_file_each() {
    use dpdnl::forces::bonded::{AngleStyle, BondStyle};
    let w = |s: &str| s.split_whitespace().map(String::from).collect::<Vec<_>>();
    let diff = |e: &dyn Fn(f64) -> f64, x: f64| (e(x + 1e-6) - e(x - 1e-6)) / 2e-6;
    let mut bond = BondStyle::new(&w("test/quartic"), 1).expect("a registered bond style");
    bond.set_coeff(&w("1 40.0 0.9")).expect("coefficients");
    for r in [0.5, 0.8, 0.9, 1.1, 1.4] {
        let (fbond, e, _) = bond.eval(1, r * r);
        assert!(
            (e - 40.0 * (r - 0.9f64).powi(4)).abs() < 1e-12,
            "E at r = {r}"
        );
        let want = -diff(&|r| bond.eval(1, r * r).1, r) / r;
        assert!(
            (fbond - want).abs() <= 1e-6 * want.abs() + 1e-8,
            "r = {r}: {fbond} {want}"
        );
    }
    let mut angle = AngleStyle::new(&w("test/square"), 1).expect("a registered angle style");
    angle.set_coeff(&w("1 3.0")).expect("coefficients");
    let x = [[0.9, 0.1, -0.2], [0.0, 0.0, 0.0], [-0.3, 0.8, 0.4]];
    let energy = |x: &[[f64; 3]; 3]| {
        let d1 = [0, 1, 2].map(|c| x[0][c] - x[1][c]);
        let d2 = [0, 1, 2].map(|c| x[2][c] - x[1][c]);
        angle.eval(1, d1, d2).2
    };
    let d1 = [0, 1, 2].map(|c| x[0][c] - x[1][c]);
    let d2 = [0, 1, 2].map(|c| x[2][c] - x[1][c]);
    let (f1, f3, _) = angle.eval(1, d1, d2);
    for (atom, f) in [(0, f1), (2, f3)] {
        for c in 0..3 {
            let e = |h: f64| {
                let mut y = x;
                y[atom][c] += h;
                energy(&y)
            };
            let want = -diff(&e, 0.0);
            assert!(
                (f[c] - want).abs() <= 1e-6 * want.abs() + 1e-8,
                "atom {atom} {c}"
            );
        }
    }
    let data = format!(
        "{}/tests/data/crosscheck/polymer3d.data",
        env!("CARGO_MANIFEST_DIR")
    );
    let (_, sys) = run(&format!(
        "units lj\natom_style angle\nbond_style test/quartic\nangle_style test/square\n\
         read_data {data}\nmass 1 1.0\nmass 2 1.5\n\
         pair_style dpd/nonlinear 1.0 1.0 7919 friction cross\npair_coeff * * 25.0 4.5 0.0\n\
         bond_coeff 1 200.0 0.85\nangle_coeff 1 5.0\nneighbor 0.5 bin\ntimestep 0.005\n\
         fix 1 all nve\nthermo 0\nrun 0\n"
    ))
    .expect("the polymer runs with the test styles");
    let mut sys = sys.expect("a system");
    let p0 = sys.momentum();
    let (_, sys2) = run(&format!(
        "units lj\natom_style angle\nbond_style test/quartic\nangle_style test/square\n\
         read_data {data}\nmass 1 1.0\nmass 2 1.5\n\
         pair_style dpd/nonlinear 1.0 1.0 7919 friction cross\npair_coeff * * 25.0 4.5 0.0\n\
         bond_coeff 1 200.0 0.85\nangle_coeff 1 5.0\nneighbor 0.5 bin\ntimestep 0.005\n\
         fix 1 all nve\nthermo 0\nrun 200\n"
    ))
    .expect("200 steps");
    sys = sys2.expect("a system");
    let p1 = sys.momentum();
    for k in 0..3 {
        assert!(
            (p1[k] - p0[k]).abs() < 1e-10,
            "momentum {k}: {} -> {}",
            p0[k],
            p1[k]
        );
    }
}
