//! Run set-up in the standalone engine (`dpdnl::init`): `pair_coeff … eta E sc S` resolved from
//! the current number density, and the Euler finite-step heating warning. The cross-engine twin
//! (same lines printed by the LAMMPS shim) is the golden case `in.design_euler_2d` in
//! `tests/crosscheck.rs`.

use dpdnl::engine::System;
use dpdnl::theory::{Fluid, Targets, design_from_targets, euler_critical_dt, kinetic_theory};

mod common;
use common::run;

/// A 2-D ideal fluid of `n_atoms` atoms in a 10 × 10 box, with the given pair lines, step and
/// integrator, run for `steps` steps.
fn script2d(n_atoms: usize, pair: &str, dt: f64, fix: &str, steps: u32) -> String {
    format!(
        "units lj\ndimension 2\nboundary p p p\natom_style atomic\ncomm_modify vel yes\n\
         region box block 0 10 0 10 -0.5 0.5\ncreate_box 2 box\n\
         create_atoms 1 random {n_atoms} 4321 box\nmass * 1.0\n\
         velocity all create 1.0 99 mom yes\n{pair}\ntimestep {dt}\n\
         fix 1 all {fix}\nfix 2 all enforce2d\nthermo 0\nrun {steps}\n"
    )
}

fn gamma0(sys: &System, i: usize, j: usize) -> f64 {
    common::dpd(sys).unwrap().get(i, j).unwrap().gamma0
}

/// γ0 and s are the exact kinetic-theory design at n = N/V, recomputed at every run: adding
/// atoms between runs changes n and so γ0 (γ ∝ 1/n² at fixed s, and s moves with n too).
#[test]
fn targets_resolve_from_the_current_density() {
    let pair = "pair_style dpd/nonlinear 1.0 1.0 555\npair_coeff * * 0.0 eta 3 sc 20";
    let mut text = script2d(400, pair, 0.005, "nve", 0);
    text.push_str("create_atoms 2 random 200 777 box\nrun 0\n");
    let (lines, sys) = run(&text).expect("script runs");
    let sys = sys.unwrap();
    let design = |n: f64| {
        let fluid = Fluid::new(2, n, 1.0, 1.0, 1.0).unwrap();
        let d = design_from_targets(&Targets {
            fluid,
            eta: 3.0,
            sc: 20.0,
        })
        .unwrap();
        let tr = kinetic_theory(&fluid, d.gamma, d.s).unwrap();
        assert!((tr.eta - 3.0).abs() < 1e-12 && (tr.schmidt - 20.0).abs() < 1e-10);
        d
    };
    let (d4, d6) = (design(4.0), design(6.0));
    // The last run's values (n = 600 / 100 = 6) are in the system, for every pair.
    for (i, j) in [(1, 1), (1, 2), (2, 2)] {
        let g = gamma0(&sys, i, j);
        assert!(
            (g - d6.gamma).abs() <= 1e-12 * d6.gamma,
            "{i} {j}: {g} vs {}",
            d6.gamma
        );
    }
    let s = common::dpd(&sys).unwrap().model.weight.exponent();
    assert!((s - d6.s).abs() <= 1e-12 * d6.s, "{s} vs {}", d6.s);
    // The first run logged the n = 4 design, the second the n = 6 one.
    let logged: Vec<&String> = lines
        .iter()
        .filter(|l| l.starts_with("pair_coeff 1 1:"))
        .collect();
    assert_eq!(logged.len(), 2, "{lines:#?}");
    assert!(
        logged[0].contains(&format!("gamma0 = {:.10}", d4.gamma)),
        "{}",
        logged[0]
    );
    assert!(
        logged[1].contains(&format!("gamma0 = {:.10}", d6.gamma)),
        "{}",
        logged[1]
    );
    assert!(logged[1].contains("n = 6.0000000000"), "{}", logged[1]);
    assert!(
        lines
            .iter()
            .any(|l| l.contains("weight exponent s =") && l.contains("replaces 2")),
        "{lines:#?}"
    );
}

/// The weight exponent is one for all pairs: targets needing different s are refused, naming
/// both pairs; unreachable targets name the bound.
#[test]
fn inconsistent_or_unreachable_targets_are_errors() {
    let pair = "pair_style dpd/nonlinear 1.0 1.0 555\npair_coeff 1 1 0.0 eta 3 sc 20\n\
                pair_coeff 1 2 0.0 eta 3 sc 30\npair_coeff 2 2 0.0 eta 3 sc 20";
    let err = run(&script2d(400, pair, 0.005, "nve", 0)).unwrap_err();
    assert!(
        err.message.contains("1 1")
            && err.message.contains("1 2")
            && err.message.contains("weight"),
        "{err}"
    );
    // eta far above the bound for Sc = 20 at n = 4 (eta_max = 4.53).
    let pair = "pair_style dpd/nonlinear 1.0 1.0 555\npair_coeff * * 0.0 eta 50 sc 20";
    let err = run(&script2d(400, pair, 0.005, "nve", 0)).unwrap_err();
    assert!(err.message.contains("pair_coeff 1 1 eta 50 sc 20"), "{err}");
    for bad in [
        "pair_coeff * * 0.0 eta 3 sc 0.4",
        "pair_coeff * * 0.0 eta -1 sc 20",
        "pair_coeff * * 0.0 eta 3 Sc 20",
        "pair_coeff * * 0.0 eta 3 sc 20 gamma1",
        "pair_coeff * * 0.0 eta 3 sc 20 gamma1 1",
        "pair_coeff * * 0.0 eta 3 sc 20 rho 1",
    ] {
        let pair = format!("pair_style dpd/nonlinear 1.0 1.0 555\n{bad}");
        let err = run(&script2d(400, &pair, 0.005, "nve", 0)).unwrap_err();
        assert_eq!(err.command, "pair_coeff", "{bad}: {err}");
    }
    // Different masses: the design's kinetic theory is for one mass.
    let pair = "pair_style dpd/nonlinear 1.0 1.0 555\npair_coeff * * 0.0 eta 3 sc 20\nmass 2 2.0";
    let err = run(&script2d(400, pair, 0.005, "nve", 0)).unwrap_err();
    assert!(err.message.contains("different masses"), "{err}");
}

/// The Euler warning: silent for δt ≤ 0.1 δt_c with ≤ 1 % predicted heating, a warning with
/// eq. 22's number above, an "unstable" warning at δt ≥ δt_c; never for velocity-Verlet.
#[test]
fn euler_heating_warning_thresholds() {
    let fluid = Fluid::new(2, 4.0, 1.0, 1.0, 1.0).unwrap();
    let dt_c = euler_critical_dt(&fluid, 4.5, 2.0).unwrap();
    let pair = "pair_style dpd/nonlinear 1.0 1.0 555\npair_coeff * * 0.0 4.5 0.0";
    let warnings = |dt: f64, fix: &str| {
        let (lines, _) = run(&script2d(400, pair, dt, fix, 0)).expect("runs");
        lines
            .into_iter()
            .filter(|l| l.starts_with("WARNING: Euler"))
            .collect::<Vec<_>>()
    };
    // 1/(1 − 0.005) − 1 = 0.5 % < 1 % and 0.005 < 0.1: silent.
    assert!(warnings(0.005 * dt_c, "nve/euler").is_empty());
    let w = warnings(0.3 * dt_c, "nve/euler");
    assert_eq!(w.len(), 1, "{w:?}");
    let predicted = 1.0 / (1.0 - 0.3);
    assert!(
        w[0].contains(&format!("T_eq/T0 = {predicted:.4}")),
        "{}",
        w[0]
    );
    assert!(w[0].contains("is 0.300 dt_c"), "{}", w[0]);
    let w = warnings(1.2 * dt_c, "nve/euler");
    assert!(w[0].contains("no equilibrium temperature"), "{}", w[0]);
    assert!(warnings(0.3 * dt_c, "nve").is_empty());
}

/// `dpdnl theory SCRIPT` sets the script's runs up without running them: it reports the
/// resolved design (the targets come back from the kinetic theory), the Euler temperature of
/// eq. 22, and writes no dump.
#[test]
fn theory_of_a_script() {
    let dir = std::env::temp_dir().join(format!("dpdnl-theory-script-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/crosscheck");
    for f in ["in.design_euler_2d", "dpd2d.data"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .current_dir(&dir)
        .args(["theory", "in.design_euler_2d"])
        .output()
        .expect("run dpdnl theory");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let value = |key: &str| -> Vec<f64> {
        text.lines()
            .filter_map(|l| l.strip_prefix(&format!("{key} = ")))
            .map(|v| v.parse::<f64>().unwrap())
            .collect()
    };
    // Three type pairs, each with the targets eta = 3, Sc = 20.
    assert_eq!(value("eta").len(), 3, "{text}");
    assert!(
        value("eta").iter().all(|e| (e - 3.0).abs() < 1e-12),
        "{text}"
    );
    assert!(
        value("Sc").iter().all(|e| (e - 20.0).abs() < 1e-10),
        "{text}"
    );
    // Eq. 22 in the form 1/(1 − δt/δt_c).
    let (t, dtc) = (value("T_eq/T0"), value("dt_c"));
    assert!((t[0] - 1.0 / (1.0 - 0.01 / dtc[0])).abs() < 1e-12, "{text}");
    assert!(text.contains("# WARNING: Euler step dt = 0.01"), "{text}");
    assert!(!dir.join("dump.design_euler_2d.standalone").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `dpdnl theory SCRIPT` with `fix nve` (issue 14 section 4): the velocity-Verlet heating is
/// reported as a MEASUREMENT of the nearest measured fluid, never as theory. The finite-step
/// paper's 2-D fluid at n = 4 (13 neighbours, the measured family itself) at δt = 0.03 δt_c
/// (x = δt √(kT/m)/r_c = 0.023): the interpolated T/T0 lies between the family's measured
/// points around that x, and the verdict says where the family reaches 1 % heating; the JSON
/// carries the same verdict.
#[test]
fn theory_of_a_velocity_verlet_script_is_labelled_measured() {
    use dpdnl::theory::vv_measured::vv_verdict;
    let dir = std::env::temp_dir().join(format!("dpdnl-theory-vv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // δt_c of this fluid (eq. 25) from the library, then a script at 0.03 δt_c.
    let fluid = dpdnl::theory::Fluid::new(2, 4.0, 1.0, 1.0, 0.5).unwrap();
    let dt_c = dpdnl::theory::euler_critical_dt(&fluid, 1.0, 2.0).unwrap();
    let dt = 0.03 * dt_c;
    let script = format!(
        "units lj\ndimension 2\natom_style atomic\nregion box block 0 20 0 20 -0.5 0.5\n\
         create_box 1 box\ncreate_atoms 1 random 1600 2468 box\nmass 1 1.0\n\
         pair_style dpd/nonlinear 0.5 1.0 97531\npair_coeff 1 1 0.0 1.0 0.0\n\
         timestep {dt}\nfix 1 all nve\nfix 2 all enforce2d\nrun 100\n"
    );
    std::fs::write(dir.join("in.vv"), script).unwrap();
    let run = |json: bool| {
        let mut args = vec!["theory", "in.vv"];
        if json {
            args.push("--json");
        }
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .current_dir(&dir)
            .args(&args)
            .output()
            .expect("run dpdnl theory");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let text = run(false);
    assert!(text.contains("MEASURED, not theory"), "{text}");
    assert!(text.contains("measured family: 2d-ideal (n = 4,"), "{text}");
    let t: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("T/T0 (velocity-Verlet, measured, interpolated) = "))
        .expect("T/T0 line")
        .parse()
        .unwrap();
    let x = dt * 0.5f64.sqrt();
    let v = vv_verdict(2, 4.0 * std::f64::consts::PI, 2.0, x).expect("2-D family");
    assert_eq!(v.family, "2d-ideal");
    let below = v
        .points
        .iter()
        .rev()
        .find(|p| p.0 <= x)
        .expect("a point below");
    let above = v.points.iter().find(|p| p.0 > x).expect("a point above");
    assert!(
        t >= below.1.min(above.1) - 1e-4 && t <= below.1.max(above.1) + 1e-4,
        "{t} not between the measured points {below:?} {above:?}"
    );
    let verdict = text
        .lines()
        .find(|l| l.starts_with("velocity-Verlet verdict (measured, not theory): "))
        .expect("verdict line");
    let one = v.one_percent_at.expect("the family reaches 1 %");
    assert!(
        verdict.contains(if x >= one {
            "heating >= 1 %"
        } else {
            "heating < 1 %"
        }),
        "{verdict}"
    );
    let json: serde_json::Value = serde_json::from_str(run(true).trim()).expect("JSON");
    let pair = &json["runs"][0]["pairs"][0];
    assert!(pair["euler"].is_null(), "{pair}");
    assert_eq!(pair["vv_measured"]["verdict"]["family"], "2d-ideal");
    let _ = std::fs::remove_dir_all(&dir);
}
