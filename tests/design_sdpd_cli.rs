//! `dpdnl design --method sdpd` and `dpdnl theory --kernel …` / `dpdnl theory SCRIPT` for
//! `pair_style sdpd`: the printed design, run through a script, gives back the paper's η̄.

mod common;
use common::{TABLE4_DESIGN, dpdnl_cli as dpdnl, value};

/// Table 4's first row (Sc0 = 400, η0 = 49 → s = 0.0700, η̄ = 49.0613, exactly 49.06125 = η0 (1 + 1/(2 Sc0))): the design's two lines,
/// put in a script, give the same kinetic theory through `dpdnl theory SCRIPT`.
#[test]
fn sdpd_design_round_trip() {
    let (code, out, err) = dpdnl(
        &[
            &["design", "--method", "sdpd", "--paper-approx"][..],
            &TABLE4_DESIGN,
            &["--c0", "20"],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    assert!((value(&out, "s") - 0.0700).abs() < 5e-5, "{out}");
    assert!((value(&out, "eta") - 49.06125).abs() < 1e-9, "{out}");
    let style = out
        .lines()
        .find(|l| l.starts_with("pair_style sdpd"))
        .expect(&out);
    let coeff = out
        .lines()
        .find(|l| l.starts_with("pair_coeff"))
        .expect(&out);
    assert!(
        style.contains("kernel proposed 0.0699") && coeff == "pair_coeff * * 4 20 49",
        "{out}"
    );
    let dir = std::env::temp_dir().join(format!("dpdnl-sdpd-design-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = dir.join("in.design");
    std::fs::write(
        &script,
        format!(
            "units lj\ndimension 2\nregion box block 0 20 0 20 -0.5 0.5\ncreate_box 1 box\n\
             create_atoms 1 random 1600 8675 box\nmass 1 1.0\n{style}\n{coeff}\n\
             timestep 0.005\nfix 1 all nve\nrun 10\n"
        ),
    )
    .unwrap();
    let (code, out, err) = dpdnl(&["theory", script.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!((value(&out, "eta") - 49.06125).abs() < 1e-9, "{out}");
    assert!(out.contains("kernel proposed (s = 0.0699"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Table 2's quintic row: η̄ = 10.0718 at η0 = 10, r_c = 2.5; bad kernel words are refused.
#[test]
fn sdpd_theory_of_a_kernel() {
    let (code, out, err) = dpdnl(&[
        "theory",
        "--kernel",
        "quintic",
        "--eta0",
        "10",
        "--density",
        "4",
        "--rc",
        "2.5",
        "--dim",
        "2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!((value(&out, "eta") - 10.0718).abs() < 5e-5, "{out}");
    assert!((value(&out, "c") - 239.0 / 33264.0).abs() < 1e-15, "{out}");
    let (code, _, err) = dpdnl(&[
        "theory",
        "--kernel",
        "gauss",
        "--eta0",
        "10",
        "--density",
        "4",
        "--rc",
        "2.5",
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("lucy, quintic or proposed"), "{err}");
    let (code, _, err) = dpdnl(&[
        "theory",
        "--kernel",
        "proposed",
        "--eta0",
        "10",
        "--density",
        "4",
        "--rc",
        "2.5",
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("needs --s"), "{err}");
}
