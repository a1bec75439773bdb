//! `dpdnl diff` end to end: exit status 0 (same), 1 (different), 2 (cannot compare), and what
//! it names.
//!
//! Fixed logs live in tests/data/diff_cli: `log_a.lammps` (LAMMPS 2022 layout),
//! `log_engine.txt` (the same numbers in this engine's compact layout), `log_perturbed.txt`
//! (E_pair at step 500 changed by 3e-7 relative), `log_extra_column.txt` (an extra Volume
//! column). Long logs for the stats mode and the dumps are generated under
//! CARGO_TARGET_TMPDIR.

use dpdnl::rng::keyed_gaussian;
use std::path::{Path, PathBuf};
use std::process::Command;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/diff_cli");

fn data(name: &str) -> String {
    format!("{DATA}/{name}")
}

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn diff(args: &[&str]) -> Out {
    let o = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("diff")
        .args(args)
        .output()
        .expect("run dpdnl");
    Out {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

fn last_line(s: &str) -> &str {
    s.trim_end().lines().last().unwrap_or("")
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("diff_cli");
    std::fs::create_dir_all(&dir).expect("create tmp dir");
    dir.join(name)
}

fn write_tmp(name: &str, text: &str) -> String {
    let p = tmp(name);
    std::fs::write(&p, text).expect("write tmp file");
    p.to_string_lossy().into_owned()
}

#[test]
fn identical_values_in_different_layouts() {
    let o = diff(&[&data("log_a.lammps"), &data("log_engine.txt")]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(
        last_line(&o.stdout).starts_with("verdict: SAME"),
        "{}",
        o.stdout
    );
    assert!(
        o.stdout.contains("11 row(s) matched by Step"),
        "{}",
        o.stdout
    );
}

#[test]
fn perturbed_value_is_found_and_named() {
    let o = diff(&[&data("log_a.lammps"), &data("log_perturbed.txt")]);
    assert_eq!(o.code, 1, "{}{}", o.stdout, o.stderr);
    let verdict = last_line(&o.stdout);
    assert!(
        verdict.starts_with("verdict: DIFFERENT") && verdict.contains("E_pair"),
        "{verdict}"
    );
    let row = o
        .stdout
        .lines()
        .find(|l| l.starts_with("E_pair"))
        .expect("an E_pair row");
    assert!(row.contains("step 500") && row.contains("DIFFERS"), "{row}");
    for other in ["Temp", "E_mol", "TotEng", "Press"] {
        let row = o.stdout.lines().find(|l| l.starts_with(other)).unwrap();
        assert!(!row.contains("DIFFERS"), "{row}");
    }
}

#[test]
fn tolerances_and_column_choice() {
    let (a, p) = (data("log_a.lammps"), data("log_perturbed.txt"));
    assert_eq!(diff(&[&a, &p, "--rtol", "1e-6"]).code, 0);
    assert_eq!(diff(&[&a, &p, "--atol", "1e-5"]).code, 0);
    assert_eq!(diff(&[&a, &p, "--rtol", "1e-6", "--atol", "1e-7"]).code, 0);
    assert_eq!(diff(&[&a, &p, "--columns", "Temp,Press"]).code, 0);
    assert_eq!(diff(&[&a, &p, "--columns", "temp,e_pair"]).code, 1);
    let o = diff(&[&a, &p, "--rtol=-1"]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("--rtol"), "{}", o.stderr);
}

#[test]
fn json_output() {
    let o = diff(&[&data("log_a.lammps"), &data("log_perturbed.txt"), "--json"]);
    assert_eq!(o.code, 1);
    let j = o.stdout.trim();
    assert!(j.starts_with('{') && j.ends_with('}'), "{j}");
    assert!(j.contains(r#""mode":"exact""#), "{j}");
    assert!(j.contains(r#""pass":false"#), "{j}");
    assert!(
        j.contains(r#""column":"E_pair""#) && j.contains(r#""at":"step 500""#),
        "{j}"
    );
    let o = diff(&[&data("log_a.lammps"), &data("log_engine.txt"), "--json"]);
    assert_eq!(o.code, 0);
    assert!(
        o.stdout.trim().ends_with(
            r#""pass":true,"verdict":"SAME: 5 column(s) over 11 row(s) within rtol 1e-09, atol 0"}"#
        ),
        "{}",
        o.stdout
    );
}

#[test]
fn errors_name_the_file() {
    let o = diff(&[&data("log_a.lammps"), &data("log_extra_column.txt")]);
    assert_eq!(o.code, 2, "{}", o.stdout);
    assert!(
        o.stderr.contains("log_extra_column.txt") && o.stderr.contains("Volume"),
        "{}",
        o.stderr
    );
    assert_eq!(
        diff(&[
            &data("log_a.lammps"),
            &data("log_extra_column.txt"),
            "--columns",
            "Temp"
        ])
        .code,
        0
    );

    let missing = data("no_such_log.lammps");
    let o = diff(&[&missing, &data("log_a.lammps")]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("no_such_log.lammps"), "{}", o.stderr);

    let empty = write_tmp(
        "no_thermo.log",
        "LAMMPS (2 Apr 2025)\nunits lj\nTotal wall time: 0:00:00\n",
    );
    let o = diff(&[&data("log_a.lammps"), &empty]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("no_thermo.log") && o.stderr.contains("no thermo block"),
        "{}",
        o.stderr
    );

    let bad_row = write_tmp("bad_row.log", "Step Temp\n0 1\n10 1 2\n");
    let o = diff(&[&bad_row, &data("log_a.lammps")]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("bad_row.log: line 3"), "{}", o.stderr);

    let o = diff(&[
        &data("log_a.lammps"),
        &data("log_engine.txt"),
        "--block",
        "2",
    ]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("--block 2"), "{}", o.stderr);
}

#[test]
fn missing_rows_make_a_difference_unless_allowed() {
    let text = std::fs::read_to_string(data("log_engine.txt")).unwrap();
    let short: String = text
        .lines()
        .filter(|l| !l.starts_with("1000 "))
        .map(|l| format!("{l}\n"))
        .collect();
    let short = write_tmp("short.log", &short);
    let o = diff(&[&data("log_a.lammps"), &short]);
    assert_eq!(o.code, 1, "{}", o.stdout);
    assert!(
        o.stdout.contains("rows only in A: 1 (step 1000)"),
        "{}",
        o.stdout
    );
    assert!(
        last_line(&o.stdout).contains("rows only in A: 1"),
        "{}",
        o.stdout
    );
    assert_eq!(
        diff(&[&data("log_a.lammps"), &short, "--allow-missing"]).code,
        0
    );
}

/// A long log of `n` rows: Temp is an AR(1) series (φ = 0.8) of unit variance around `1 +
/// shift`, Press independent Gaussian noise around 5, Volume constant.
fn long_log(name: &str, seed: u32, n: usize, shift: f64) -> String {
    let phi: f64 = 0.8;
    let mut t = keyed_gaussian(seed, 1, 0, 0, 0);
    let mut text = String::from("Step Temp Press Volume\n");
    for i in 0..n {
        if i > 0 {
            t = phi * t + (1.0 - phi * phi).sqrt() * keyed_gaussian(seed, 1, i as u64, 0, 0);
        }
        let p = 5.0 + keyed_gaussian(seed, 2, i as u64, 0, 0);
        text.push_str(&format!(
            "{} {:.10} {:.10} 1000\n",
            10 * i,
            1.0 + shift + 0.1 * t,
            p
        ));
    }
    write_tmp(name, &text)
}

#[test]
fn stats_mode() {
    // Independent runs of the same process: the means agree within a few standard errors.
    // Error of the Temp mean: 0.1 sqrt((1 + φ)/((1 − φ) N)) = 0.1 · 3 / 100 = 0.003 for
    // N = 10^4; a shift of 0.03 is 10 of those per run, |z| ≈ 7, far beyond --zmax 3.
    let n = 10_000;
    let a = long_log("stats_a.log", 11, n, 0.0);
    let b = long_log("stats_b.log", 12, n, 0.0);
    let c = long_log("stats_c.log", 13, n, 0.03);
    let o = diff(&["--mode", "stats", "--skip", "100", &a, &b]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(
        o.stdout.contains("9900 rows after skipping 100"),
        "{}",
        o.stdout
    );
    assert!(
        last_line(&o.stdout).starts_with("verdict: SAME"),
        "{}",
        o.stdout
    );
    let o = diff(&["--mode", "stats", &a, &c]);
    assert_eq!(o.code, 1, "{}", o.stdout);
    let verdict = last_line(&o.stdout);
    assert!(
        verdict.contains("Temp") && !verdict.contains("Press"),
        "{verdict}"
    );
    assert_eq!(
        diff(&["--mode", "stats", &a, &c, "--columns", "Press,Volume"]).code,
        0
    );
    let o = diff(&["--mode", "stats", &a, &c, "--json"]);
    assert_eq!(o.code, 1);
    assert!(o.stdout.contains(r#""mode":"stats""#) && o.stdout.contains(r#""column":"Temp""#));
}

/// Two frames of four atoms; `reverse` lists the atoms in another order, `perturb` moves one
/// velocity by 1e-6.
fn dump_text(perturb: bool, reverse: bool) -> String {
    let mut s = String::new();
    for step in [0u64, 10] {
        s.push_str(&format!(
            "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n4\nITEM: BOX BOUNDS pp pp pp\n\
             0 5\n0 5\n0 5\nITEM: ATOMS id type x y z vx\n"
        ));
        // Atom order depends on the step, as with several MPI ranks.
        let mut ids: [u32; 4] = if step == 0 {
            [3, 1, 4, 2]
        } else {
            [2, 4, 1, 3]
        };
        if reverse {
            ids.reverse();
        }
        for id in ids {
            let mut vx = 0.25 * id as f64 - 0.5 + step as f64 * 0.01;
            if perturb && step == 10 && id == 4 {
                vx += 1e-6;
            }
            s.push_str(&format!("{id} 1 {} 1.5 2.5 {vx}\n", id as f64 * 0.5));
        }
    }
    s
}

#[test]
fn dumps_match_by_step_and_id() {
    let a = write_tmp("a.dump", &dump_text(false, false));
    let b = write_tmp("b.dump", &dump_text(false, true));
    let c = write_tmp("c.dump", &dump_text(true, true));
    let o = diff(&[&a, &b]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(o.stdout.contains("matched by (step, id)"), "{}", o.stdout);
    let o = diff(&[&a, &c]);
    assert_eq!(o.code, 1, "{}", o.stdout);
    let row = o
        .stdout
        .lines()
        .find(|l| l.starts_with("vx"))
        .expect("vx row");
    assert!(
        row.contains("step 10 id 4") && row.contains("DIFFERS"),
        "{row}"
    );
    let o = diff(&[&a, &data("log_a.lammps")]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("A is a dump but B is a log"),
        "{}",
        o.stderr
    );
    let o = diff(&["--mode", "stats", &a, &c]);
    assert_eq!(o.code, 2);
}
