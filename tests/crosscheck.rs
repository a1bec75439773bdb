//! Cross-engine golden cases (`tests/data/crosscheck/in.*`): each script runs in the standalone
//! engine and in LAMMPS (`build/lmp_dpdnl`) through `dpdnl crosscheck`, which must report
//! agreement (thermo every 10 steps and dumps at step 0 and at the end, step 100 (60 or 40 for the mDPD
//! liquids, whose attraction amplifies round-off fast), within rtol 1e-9, atol 1e-9). On top of
//! that, the per-atom forces at step 0 (same state from read_data, same keyed noise) must agree
//! to 1e-12 relative.
//!
//! Without `build/lmp_dpdnl` (build: `bash lammps-plugin/build.sh`) the test prints a skip
//! message and passes, unless DPDNL_REQUIRE_LAMMPS is set, in which case it fails.

mod plugin_support;

use dpdnl::io::dump_read::parse_dump;
use dpdnl::io::lammps_log::{Tolerance, compare_dumps_exact, compare_exact_logs, parse_log};
use std::path::{Path, PathBuf};
use std::process::Command;

use plugin_support::{frames_at, golden_cases as cases, read, root, step0_forces};

fn lmp() -> Option<PathBuf> {
    plugin_support::lmp_dpdnl("cross-engine tests")
}

/// All cases in one test: they share the script directory, where the engines write their
/// dumps before crosscheck moves them away.
#[test]
fn golden_cases_agree_between_engines() {
    let Some(lmp) = lmp() else { return };
    let cases = cases();
    assert!(
        cases.len() >= 8,
        "expected the golden cases, found {cases:?}"
    );
    let tmp = std::env::temp_dir().join(format!("dpdnl-crosscheck-test-{}", std::process::id()));
    let mut failures = Vec::new();
    let mut summary = Vec::new();
    for script in &cases {
        let name = script.file_name().unwrap().to_string_lossy().into_owned();
        let work = tmp.join(&name);
        let out = plugin_support::golden_crosscheck(script, &lmp, &work)
            .output()
            .expect("run dpdnl crosscheck");
        let stdout = String::from_utf8_lossy(&out.stdout);
        if out.status.code() != Some(0) {
            failures.push(format!(
                "{name}: crosscheck exit {:?}\n{stdout}\n{}",
                out.status.code(),
                String::from_utf8_lossy(&out.stderr)
            ));
            continue;
        }
        // Step-0 forces, 1e-12 relative.
        let case = name.trim_start_matches("in.");
        let ds = parse_dump(&read(&work.join(format!("dump.{case}.standalone")))).unwrap();
        let dl = parse_dump(&read(&work.join(format!("dump.{case}.lammps")))).unwrap();
        // Per-value relative differences |Δf| / max(|f_A|, |f_B|) are reported; the check is
        // against the force scale of the frame, max |Δf| / max_i |f_i| <= 1e-12, because an
        // atom's net force can be a near-cancellation of pair forces of O(10-30), and the two
        // engines sum the pairs in different orders (round-off ~1e-13 absolute).
        let step0 = step0_forces(&ds, &dl);
        let (f0, d0, scale, s0) = (step0.max_rel, step0.max_abs, step0.scale, step0.relative());
        if s0 > 1e-12 {
            failures.push(format!(
                "{name}: step-0 forces differ: max |Δf| {d0:.3e} / max |f| {scale:.3e} = {s0:.3e} > 1e-12"
            ));
        }
        // Set-up lines from the shared Rust code (dpdnl::init): the resolved (eta, sc) design
        // and the Euler heating warning must read the same in both logs (LAMMPS appends the
        // source location to a WARNING line, so the standalone text must be contained in it);
        // so must LAMMPS's "Inconsistent image flags" of a generator-style data file.
        let (text_s, text_l) = (
            read(&work.join("standalone.log")),
            read(&work.join("lammps.log")),
        );
        let setup_lines: Vec<&str> = text_s
            .lines()
            .filter(|l| {
                l.starts_with("WARNING: Euler")
                    || l.starts_with("WARNING: Inconsistent image flags")
                    || l.contains("from the (eta, sc) design")
                    || (l.starts_with("pair_coeff ")
                        && (l.contains(" -> gamma0 = ") || l.contains(": eta0 = ")))
            })
            .collect();
        for line in &setup_lines {
            if !text_l.lines().any(|m| m.starts_with(line)) {
                failures.push(format!(
                    "{name}: LAMMPS log lacks the set-up line\n  {line}"
                ));
            }
        }
        if name.contains("design") && setup_lines.len() < 3 {
            failures.push(format!(
                "{name}: expected design and warning lines, got {setup_lines:?}"
            ));
        }
        let image_warning = |text: &str| {
            text.lines()
                .filter(|l| l.starts_with("WARNING: Inconsistent image flags"))
                .count()
        };
        let (ws, wl) = (image_warning(&text_s), image_warning(&text_l));
        if ws != wl || (ws > 0) != name.contains("wrapped") {
            failures.push(format!(
                "{name}: \"Inconsistent image flags\" warned {ws} time(s) by the standalone \
                 engine, {wl} by LAMMPS (expected once in each for the wrapped data file only)"
            ));
        }
        // Thermo at the last dumped step (100, or fewer steps for the chaotic mDPD liquids;
        // reported: crosscheck already judged all rows at 1e-9).
        let end = ds.iter().map(|f| f.step).max().unwrap_or(0);
        let ls = parse_log(&text_s).unwrap();
        let ll = parse_log(&text_l).unwrap();
        // (The block of the last run: a script with several runs ends its dump there.)
        let last = |b: &[dpdnl::io::lammps_log::ThermoBlock]| {
            let mut b = b.last().expect("a thermo block").clone();
            b.rows.retain(|r| r[0] == end as f64);
            b
        };
        let rt =
            compare_exact_logs(&[last(&ls)], &[last(&ll)], None, Tolerance::default()).unwrap();
        let (tcol, t100) = rt
            .columns
            .iter()
            .map(|c| (c.column.clone(), c.max_rel))
            .fold((String::new(), 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let cols: Vec<String> = ["fx", "fy", "fz"].iter().map(|s| s.to_string()).collect();
        let tol = Tolerance {
            rtol: 1e-12,
            atol: 0.0,
        };
        let r100 =
            compare_dumps_exact(&frames_at(&ds, end), &frames_at(&dl, end), Some(&cols), tol)
                .unwrap();
        let f100 = r100.columns.iter().map(|c| c.max_rel).fold(0.0, f64::max);
        summary.push(format!(
            "{case:<26} step-0 forces: max |Δf|/max|f| {s0:.2e}, per-value max rel {f0:.2e}; step-{end} thermo max rel {t100:.2e} ({tcol}); step-{end} forces max rel {f100:.2e}"
        ));
    }
    eprintln!("cross-engine agreement:\n{}", summary.join("\n"));
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// A missing LAMMPS executable is "cannot run" (exit 2) with a hint on how to build it.
#[test]
fn missing_lammps_is_exit_2_with_a_hint() {
    let script = root().join("tests/data/crosscheck/in.none_plain_3d");
    let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("crosscheck")
        .arg(&script)
        .arg("--lmp")
        .arg(root().join("build/no_such_lmp"))
        .output()
        .expect("run dpdnl crosscheck");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("lammps-plugin/build.sh"), "{err}");
}

/// A stand-in for LAMMPS: a shell script that copies `log` to the file after `-log`, as a
/// LAMMPS that differs from the standalone engine and logged `dangerous` would.
#[cfg(unix)]
fn fake_lammps(dir: &Path, name: &str, dangerous: &str) -> PathBuf {
    let log = dir.join(format!("{name}.log"));
    std::fs::write(
        &log,
        format!(
            "LAMMPS (29 Sep 2021 - Update 2)\n\
             Neighbor list info ...\n  update every 1 steps, delay 10 steps, check yes\n  \
             max neighbors/atom: 2000, page size: 100000\n\
             Step Temp E_pair E_mol TotEng Press\n\
             0 0 1 0 1 1\n5 0.5 1 0 1.5 1\n10 1 1 0 2 1\n\
             Loop time of 0.01 on 1 procs for 10 steps with 50 atoms\n\n\
             Total # of neighbors = 123\nAve neighs/atom = 2.46\n\
             Neighbor list builds = 3\n{dangerous}\nTotal wall time: 0:00:00\n"
        ),
    )
    .expect("write the fake log");
    stand_in(
        dir,
        name,
        &format!(
            "#!/bin/sh\nwhile [ $# -gt 0 ]; do\n  if [ \"$1\" = \"-log\" ]; then cp '{}' \"$2\"; fi\n  \
             shift\ndone\n",
            log.display()
        ),
    )
}

/// The executable shell script `dir/name` with the text `script`: a stand-in for LAMMPS.
#[cfg(unix)]
fn stand_in(dir: &Path, name: &str, script: &str) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let exe = dir.join(name);
    std::fs::write(&exe, script).expect("write the fake LAMMPS");
    std::fs::set_permissions(&exe, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    exe
}

/// With "Dangerous builds = 2" in LAMMPS's log, the DIFFER verdict names them, LAMMPS's
/// neighbour settings and the fix (issue 16, item 11); without dangerous builds it does not.
/// Runs without LAMMPS: the LAMMPS side is a stand-in that writes a fixed, different log.
#[cfg(unix)]
#[test]
fn differ_verdict_names_dangerous_builds_and_the_fix() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("crosscheck_dangerous");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let script = dir.join("in.tiny");
    std::fs::write(
        &script,
        "units lj\natom_style atomic\ndimension 2\nboundary p p p\n\
         region box block 0 5 0 5 -0.5 0.5\ncreate_box 1 box\n\
         create_atoms 1 random 50 4711 box\nmass 1 1.0\n\
         pair_style dpd/nonlinear 1.0 1.0 7919\npair_coeff 1 1 25.0 4.5 0.0\n\
         timestep 0.01\nfix 1 all nve\nthermo 5\nrun 10\n",
    )
    .expect("write the script");
    let crosscheck = |lmp: &Path, work: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(&script)
            .arg("--lmp")
            .arg(lmp)
            .arg("--workdir")
            .arg(dir.join(work))
            .output()
            .expect("run dpdnl crosscheck");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
        stdout
    };
    let out = crosscheck(
        &fake_lammps(&dir, "lmp_dangerous", "Dangerous builds = 2"),
        "w1",
    );
    assert!(
        out.contains(
            "lammps neighbor lists: neigh_modify every 1 delay 10 check yes; Dangerous builds = 2"
        ),
        "{out}"
    );
    let verdict = out.lines().last().unwrap_or("");
    for part in [
        "CROSSCHECK DIFFER (",
        "): thermo log not within rtol 1e-09",
        "LAMMPS logged Dangerous builds = 2 (neigh_modify every 1 delay 10 check yes)",
        "missed pairs",
        "add `neigh_modify delay 0 every 1 check yes` to the script",
        "the standalone engine checks its lists every step",
    ] {
        assert!(
            verdict.contains(part),
            "'{part}' not in the verdict: {verdict}"
        );
    }
    let out = crosscheck(
        &fake_lammps(&dir, "lmp_clean", "Dangerous builds = 0"),
        "w2",
    );
    let verdict = out.lines().last().unwrap_or("");
    assert!(
        verdict.starts_with("CROSSCHECK DIFFER") && !verdict.contains("neigh_modify"),
        "{verdict}"
    );
}

/// A stand-in for LAMMPS that writes, as its log, the standalone engine's log (which crosscheck
/// writes first, into the directory of the LAMMPS log) with every thermo value v except the
/// step replaced by v (1 + f), `f` an awk expression of the step `s`, printed with 15 digits:
/// a synthetic log whose difference from the standalone one is known.
#[cfg(unix)]
fn perturbing_lammps(dir: &Path, name: &str, f: &str) -> PathBuf {
    stand_in(
        dir,
        name,
        &format!(
            "#!/bin/sh
while [ $# -gt 0 ]; do
  if [ \"$1\" = \"-log\" ]; then out=\"$2\"; fi
  \
             shift
done
\
             awk '$1 == \"Step\" {{ n = NF; print; next }}
\
             n > 0 && NF == n && $1 ~ /^[0-9]+$/ {{ s = $1; line = $1
\
               for (i = 2; i <= NF; i++) line = line \" \" sprintf(\"%.15g\", $i * (1 + ({f})))
\
               print line; next }}
\
             {{ n = 0; print }}' \"$(dirname \"$out\")/standalone.log\" > \"$out\"
"
        ),
    )
}

/// The DIFFER verdict tells chaotic growth of round-off from a model difference (issue 41):
/// the LAMMPS side is the standalone log with each thermo value multiplied by 1 + f(step).
/// f = 3e-13 e^{0.046 s} is issue 41's sheared polymer (3e-13 at step 0, 1e-5 at step 400):
/// chaotic growth, at the rate put in; f = 1e-5 is a model difference at step 0; f = 1e-4
/// from step 1 on is a model difference after step 0 (from round-off in 20 steps would need
/// a rate of 0.9 per step, ×10 in 2.5 steps). Runs without LAMMPS.
#[cfg(unix)]
#[test]
fn differ_verdict_tells_round_off_growth_from_a_model_difference() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("crosscheck_growth");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let script = dir.join("in.tiny");
    std::fs::write(
        &script,
        "units lj\natom_style atomic\ndimension 2\nboundary p p p\n\
         region box block 0 5 0 5 -0.5 0.5\ncreate_box 1 box\n\
         create_atoms 1 random 50 4711 box\nmass 1 1.0\nvelocity all create 1.0 87287\n\
         pair_style dpd/nonlinear 1.0 1.0 7919\npair_coeff 1 1 25.0 4.5 0.0\n\
         timestep 0.01\nfix 1 all nve\nthermo 20\n\
         thermo_modify format float %20.15g\nrun 400\n",
    )
    .expect("write the script");
    let crosscheck = |f: &str, name: &str| {
        let lmp = perturbing_lammps(&dir, name, f);
        let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(&script)
            .arg("--lmp")
            .arg(&lmp)
            .arg("--rtol")
            .arg("1e-6")
            .arg("--workdir")
            .arg(dir.join(format!("w.{name}")))
            .output()
            .expect("run dpdnl crosscheck");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
        stdout
    };
    let number_after = |text: &str, key: &str| -> f64 {
        let i = text
            .find(key)
            .unwrap_or_else(|| panic!("'{key}' not in: {text}"))
            + key.len();
        text[i..]
            .split([' ', ','])
            .next()
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("no number after '{key}' in: {text}"))
    };

    let out = crosscheck("3e-13 * exp(0.046 * s)", "lmp_chaotic");
    assert!(
        out.contains("growth of the largest difference from the first step"),
        "{out}"
    );
    let verdict = out.lines().last().unwrap_or("");
    assert!(
        verdict.starts_with("CROSSCHECK DIFFER (chaotic growth of round-off: step-0 agreement "),
        "{verdict}"
    );
    assert!(
        verdict.contains("this is not a model difference"),
        "{verdict}"
    );
    // The largest scaled difference of a step is f times |v_s| / max_t |v_t| of the column
    // that gives it, between 0.9 and 1 for these columns: the rate within 5 % of 0.046, the
    // step-0 agreement between 2e-13 and 3e-13.
    let rate = number_after(verdict, "growth rate ");
    assert!((rate / 0.046 - 1.0).abs() < 0.05, "rate {rate}: {verdict}");
    let start = number_after(verdict, "step-0 agreement ");
    assert!(
        (2e-13..=3.0001e-13).contains(&start),
        "start {start}: {verdict}"
    );
    // f reaches 1e-6 at s = ln(1e-6 / 3e-13) / 0.046 = 327.
    let reach = number_after(verdict, "reaches rtol 1e-06 about ");
    assert!((reach - 327.0).abs() < 20.0, "{reach}: {verdict}");

    // A difference at step 0. The script draws its positions and velocities from each
    // engine's own generator (`create_atoms … random`, `velocity … create`), so the verdict
    // names that set-up instead of calling it a model difference (the plain model-difference
    // wording is the unit test's in src/bin/dpdnl/crosscheck/verdict.rs).
    let out = crosscheck("1e-5", "lmp_model");
    let verdict = out.lines().last().unwrap_or("");
    assert!(
        verdict.starts_with("CROSSCHECK DIFFER (the engines start from different states: already "),
        "{verdict}"
    );
    assert!(
        verdict.contains("line 7, `create_atoms 1 random 50 4711 box`"),
        "{verdict}"
    );
    assert!(verdict.contains(" at step 0 "), "{verdict}");
    let start = number_after(verdict, "already ");
    assert!((0.9e-5..=1.0e-5).contains(&start), "{verdict}");

    let out = crosscheck("(s == 0 ? 0 : 1e-4)", "lmp_later");
    let verdict = out.lines().last().unwrap_or("");
    for part in [
        "CROSSCHECK DIFFER (model difference after step 0: step-0 agreement 0 (identical to the printed digits), then ",
        " at step 20 ",
        "too fast for chaos",
    ] {
        assert!(verdict.contains(part), "'{part}' not in: {verdict}");
    }
}

/// `write_data` of a sheared box (issue 32), both directions: after the same sheared run (the
/// mixture of `in.shear_flip_3d` at erate 1, N = 2, 113 steps: a flip behind it, tilt 0.6), the
/// standalone engine writes the data file LAMMPS writes (the `xy xz yz` line, atoms in LAMMPS's
/// tilted cell, image flags equal, positions and velocities to 1e-9), and a run continued from
/// the standalone engine's file agrees between the engines (`in.shear_data_3d` continues from
/// LAMMPS's file).
#[test]
fn sheared_write_data_matches_lammps_and_continues() {
    let Some(lmp) = lmp() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("shear_write_data");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let cases = root().join("tests/data/crosscheck");
    std::fs::copy(cases.join("dpd3d.data"), dir.join("dpd3d.data")).expect("copy data");
    let script = read(&cases.join("in.shear_flip_3d"))
        .replace("erate 2.0", "erate 1.0")
        .replace(
            "run             100",
            "run             113\nwrite_data      out.${engine}.data nocoeff",
        );
    assert!(script.contains("write_data"), "the script changed");
    std::fs::write(dir.join("in.write"), script).expect("write the script");
    let crosscheck = |script: &Path, extra: &[&str], work: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(script)
            .arg("--lmp")
            .arg(&lmp)
            .arg("--workdir")
            .arg(dir.join(work))
            .args(extra)
            .output()
            .expect("run dpdnl crosscheck");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert_eq!(out.status.code(), Some(0), "{stdout}");
        stdout
    };
    crosscheck(&dir.join("in.write"), &[], "w");
    let data = |engine: &str| {
        let p = dir.join(format!("out.{engine}.data"));
        dpdnl::io::data::parse_data(&read(&p), &p.display().to_string()).expect("parse")
    };
    let (s, l) = (data("standalone"), data("lammps"));
    let (ts, tl) = (
        s.tilt.expect("standalone tilt"),
        l.tilt.expect("lammps tilt"),
    );
    assert!(
        (ts[0] - 0.6).abs() < 1e-9 && (ts[0] - tl[0]).abs() < 1e-12,
        "{ts:?} {tl:?}"
    );
    assert_eq!(s.atoms.len(), 500);
    let by_tag = |d: &dpdnl::io::data::DataFile| {
        let mut a = d.atoms.clone();
        a.sort_by_key(|a| a.0);
        let mut v = d.velocities.clone();
        v.sort_by_key(|v| v.0);
        (a, v)
    };
    let ((sa, sv), (la, lv)) = (by_tag(&s), by_tag(&l));
    let mut crossed = 0;
    for (a, b) in sa.iter().zip(&la) {
        assert_eq!(
            (a.0, a.1, a.3),
            (b.0, b.1, b.3),
            "atom {} (id type image)",
            a.0
        );
        for k in 0..3 {
            assert!(
                (a.2[k] - b.2[k]).abs() < 1e-9,
                "atom {}: {:?} {:?}",
                a.0,
                a.2,
                b.2
            );
        }
        crossed += usize::from(a.3 != [0; 3]);
    }
    assert!(
        crossed > 50,
        "only {crossed} atoms with image flags: test too weak"
    );
    for (a, b) in sv.iter().zip(&lv) {
        for k in 0..3 {
            assert!(
                (a.1[k] - b.1[k]).abs() < 1e-9,
                "atom {}: {:?} {:?}",
                a.0,
                a.1,
                b.1
            );
        }
    }
    // LAMMPS continues from the standalone engine's file as the standalone engine does.
    let src = dir.join("out.standalone.data");
    let src = src.to_string_lossy();
    crosscheck(
        &cases.join("in.shear_data_3d"),
        &["--var", "src", &src],
        "c",
    );
}

/// The differences by design of a sheared run are named (issue 32): with another LAMMPS
/// neighbour schedule (`neigh_modify every 2 delay 4`) LAMMPS wraps atoms, with the `remap v`
/// velocity jump, on other steps, so `temp` differs: the DIFFER verdict says so and what agrees;
/// `restart N`, on whose steps LAMMPS re-neighbours too, is mirrored (AGREE); `fix deform …
/// order current` (standalone only) makes LAMMPS fail, and crosscheck's message says why.
#[test]
fn sheared_verdicts_name_the_differences_by_design() {
    let Some(lmp) = lmp() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("shear_verdicts");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let cases = root().join("tests/data/crosscheck");
    std::fs::copy(cases.join("dpd3d.data"), dir.join("dpd3d.data")).expect("copy data");
    let golden = read(&cases.join("in.shear_dot_twostep_3d"));
    let run = |name: &str, script: String| {
        std::fs::write(dir.join(name), script).expect("write the script");
        Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(dir.join(name))
            .arg("--lmp")
            .arg(&lmp)
            .arg("--workdir")
            .arg(dir.join(format!("w.{name}")))
            .output()
            .expect("run dpdnl crosscheck")
    };
    let delayed = golden.replace(
        "neigh_modify    delay 0 every 1 check yes",
        "neigh_modify    delay 4 every 2 check yes",
    );
    assert_ne!(delayed, golden, "the golden script changed");
    let out = run("in.delayed", delayed);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let verdict = stdout.lines().last().unwrap_or("");
    for part in [
        "CROSSCHECK DIFFER",
        "sheared box (fix deform): LAMMPS re-neighbours by `neigh_modify every 2 delay 4 check yes`",
        "expect `temp`, `ke`, `etotal`",
        "`temp/deform` and its pressure",
        "use `neigh_modify delay 0 every 1 check yes`",
    ] {
        assert!(
            verdict.contains(part),
            "'{part}' not in the verdict: {verdict}"
        );
    }
    // `restart N` makes LAMMPS re-neighbour (and so wrap atoms, with the velocity jump) on the
    // steps it writes; the standalone engine does the same, so the numbers agree.
    let with_restart = golden.replace("run             100", "restart 40 rst.*\nrun 100");
    assert_ne!(with_restart, golden, "the golden script changed");
    let out = run("in.restart", with_restart);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let current = golden.replace("remap v", "remap v order current");
    let out = run("in.current", current);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("is a keyword of the standalone engine only"),
        "{stderr}"
    );
}

/// Data files as LAMMPS's `write_data` writes them (issue 42): LAMMPS (`build/lmp_dpdnl`) runs
/// 30 steps and writes its state with its coefficient sections (`Pair Coeffs`, or `PairIJ
/// Coeffs` with `pair ij`; `Bond Coeffs`, `Angle Coeffs`), for `dpd/nonlinear` (3-D), `sdpd`
/// (2-D) and the bonded polymer solution; a continuation with `pair_style` (and the bonded
/// styles) before `read_data` and no coefficient commands (only the cross pair a `Pair Coeffs`
/// section lacks) runs in both engines through `dpdnl crosscheck`, which must agree (thermo
/// and the dumped positions and velocities; a force near zero, a near-cancellation of pair
/// forces summed in another order, can miss the per-value 1e-9 on its own). For
/// `dpd/nonlinear`, the standalone engine's continuation from the coefficient section is the
/// same, bit for bit, as the one from `write_data … nocoeff` with the `pair_coeff` lines given.
#[test]
fn lammps_write_data_continues_with_pair_style_before_read_data() {
    let Some(lmp) = lmp() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("lammps_write_data");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let cases = root().join("tests/data/crosscheck");
    for f in ["dpd3d.data", "dpd2d.data", "polymer3d.data"] {
        std::fs::copy(cases.join(f), dir.join(f)).expect("copy data");
    }
    struct Case {
        name: &'static str,
        /// units … atom_style … comm_modify (before the styles).
        head: &'static str,
        /// The style lines, before read_data in the continuation.
        styles: &'static str,
        source: &'static str,
        /// The coefficient commands of the writing run.
        coeffs: &'static str,
        /// write_data's keywords.
        write: &'static str,
        /// What the continuation gives after read_data (the cross pair of `Pair Coeffs`).
        after: &'static str,
        /// Fixes and thermo keywords.
        fixes: &'static str,
    }
    let all = [
        Case {
            name: "dpd",
            head: "units lj\ndimension 3\natom_style atomic\ncomm_modify vel yes\n",
            styles: "pair_style dpd/nonlinear 1.0 1.0 7919 friction dot noise twostep\n",
            source: "dpd3d.data\nmass 1 1.0\nmass 2 1.5",
            coeffs: "pair_coeff 1 1 8.0 4.5 0.5\npair_coeff 1 2 10.0 4.0 0.5 0.9\n\
                     pair_coeff 2 2 6.0 3.0 0.5 0.8\n",
            write: "",
            after: "pair_coeff 1 2 10.0 4.0 0.5 0.9\n",
            fixes: "fix 1 all nve\nthermo_style custom step temp press pxx pyy pxy pe etotal\n",
        },
        Case {
            name: "sdpd",
            head: "units lj\ndimension 2\natom_style atomic\ncomm_modify vel yes\n",
            styles: "pair_style sdpd 1.0 2.5 7919 kernel lucy\n",
            source: "dpd2d.data\nmass 1 1.0\nmass 2 1.5",
            coeffs: "pair_coeff 1 1 4.0 10.0 10.0\npair_coeff 2 2 6.0 10.0 10.0\n\
                     pair_coeff 1 2 4.0 10.0 8.0 2.2\n",
            write: " pair ij",
            after: "",
            fixes: "fix 1 all nve\nfix 2 all enforce2d\n\
                    thermo_style custom step temp press pxx pyy pxy pe etotal\n",
        },
        Case {
            name: "bonded",
            head: "units lj\ndimension 3\natom_style angle\ncomm_modify vel yes cutoff 3.0\n",
            styles: "pair_style dpd/nonlinear 1.0 1.0 7919 friction cross\nbond_style harmonic\n\
                     angle_style harmonic\nspecial_bonds lj 0 1 1\n",
            source: "polymer3d.data\nmass 1 1.0\nmass 2 1.5",
            coeffs: "pair_coeff 1 1 25.0 4.5 0.5\npair_coeff 1 2 30.0 4.0 0.5\n\
                     pair_coeff 2 2 25.0 3.0 0.5\nbond_coeff 1 50.0 0.85\nangle_coeff 1 5.0 150.0\n",
            write: " pair ij",
            after: "",
            fixes: "fix 1 all nve\n\
                    thermo_style custom step temp press pxy pe ebond eangle etotal\n",
        },
    ];
    let settings = "neighbor 1.0 bin\nneigh_modify delay 0 every 1 check yes\ntimestep 0.01\n";
    let crosscheck = |script: &Path, work: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(script)
            .arg("--lmp")
            .arg(&lmp)
            .arg("--workdir")
            .arg(dir.join(work))
            .output()
            .expect("run dpdnl crosscheck");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {stdout}\n{}",
            script.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        read(&dir.join(work).join("standalone.log"))
    };
    for c in &all {
        // LAMMPS writes the state, with and without its coefficient sections.
        let write = format!(
            "{}{}read_data {}\n{}{settings}{}run 30\nwrite_data state.{}.data{}\n\
             write_data state.{}.nocoeff.data nocoeff\n",
            c.head, c.styles, c.source, c.coeffs, c.fixes, c.name, c.write, c.name
        );
        std::fs::write(dir.join(format!("in.write_{}", c.name)), &write).expect("write");
        let out = Command::new(&lmp)
            .current_dir(&dir)
            .env("OMP_NUM_THREADS", "1")
            .args(["-in", &format!("in.write_{}", c.name), "-log", "none"])
            .output()
            .expect("run LAMMPS");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && !stdout.contains("ERROR"),
            "{}: {stdout}",
            c.name
        );
        let data = read(&dir.join(format!("state.{}.data", c.name)));
        let section = if c.write.is_empty() {
            "\nPair Coeffs # "
        } else {
            "\nPairIJ Coeffs # "
        };
        assert!(
            data.contains(section),
            "{}: no '{section}' in\n{data}",
            c.name
        );
        if c.name == "bonded" {
            for s in ["\nBond Coeffs # harmonic", "\nAngle Coeffs # harmonic"] {
                assert!(data.contains(s), "bonded: no '{s}'");
            }
        }
        // Both engines continue from it with the styles before read_data.
        let tail = format!(
            "{settings}{}thermo 10\nthermo_modify format float %20.15g\n\
             dump 1 all custom 50 dump.{}.${{engine}} id type x y z vx vy vz\n\
             dump_modify 1 sort id format float %20.15g\nrun 50\n",
            c.fixes, c.name
        );
        let cont = format!(
            "variable engine index standalone\n{}{}read_data state.{}.data\n{}{tail}",
            c.head, c.styles, c.name, c.after
        );
        let script = dir.join(format!("in.cont_{}", c.name));
        std::fs::write(&script, cont).expect("write");
        let log = crosscheck(&script, &format!("w.{}", c.name));
        if c.name == "dpd" {
            // The same continuation from the nocoeff file with the coefficients given.
            let nocoeff = format!(
                "variable engine index standalone\n{}read_data state.dpd.nocoeff.data\n{}{}{tail}",
                c.head, c.styles, c.coeffs
            );
            let script = dir.join("in.cont_dpd_nocoeff");
            std::fs::write(&script, nocoeff).expect("write");
            let log2 = crosscheck(&script, "w.dpd_nocoeff");
            let rows = |log: &str| {
                let b = parse_log(log).unwrap();
                assert_eq!(b[0].rows.len(), 6, "thermo rows 0..50");
                b[0].rows.clone()
            };
            assert_eq!(
                rows(&log),
                rows(&log2),
                "Pair Coeffs and pair_coeff lines differ"
            );
        }
    }
}

/// The verdict example of the crosscheck page (docs/manual/cli/crosscheck.md) is this run's
/// verdict: the sheared golden case `in.shear_dot_twostep_2d` run to 1500 steps instead of 150
/// (chaotic growth of round-off, then the engines' different box flips). The test fails when
/// the page's line is not the current code's; `DPDNL_BLESS=1 cargo test --test crosscheck
/// manual_verdict` rewrites it.
#[test]
fn manual_verdict_example_is_the_current_verdict() {
    let Some(lmp) = lmp() else { return };
    let src = root().join("tests/data/crosscheck");
    let dir = std::env::temp_dir().join(format!("dpdnl-verdict-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("work dir");
    let script = read(&src.join("in.shear_dot_twostep_2d"));
    assert_eq!(script.matches("\nrun             150\n").count(), 1);
    let script = script.replace("\nrun             150\n", "\nrun             1500\n");
    std::fs::write(dir.join("in.shear_dot_twostep_2d"), script).expect("script");
    std::fs::copy(src.join("dpd2d.data"), dir.join("dpd2d.data")).expect("data file");
    let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .arg("crosscheck")
        .arg(dir.join("in.shear_dot_twostep_2d"))
        .arg("--lmp")
        .arg(&lmp)
        .arg("--workdir")
        .arg(dir.join("w"))
        .output()
        .expect("run dpdnl crosscheck");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let verdict = stdout.lines().last().unwrap_or("").to_string();
    assert!(
        verdict.starts_with("CROSSCHECK DIFFER (chaotic growth of round-off"),
        "{verdict}"
    );
    let page = root().join("docs/manual/cli/crosscheck.md");
    let text = read(&page);
    let marker = "<!-- verdict: tests/crosscheck.rs manual_verdict_example_is_the_current_verdict -->\n```text\n";
    let at = text.find(marker).expect("the page's verdict marker") + marker.len();
    let end = at + text[at..].find("\n```").expect("the block's end");
    if std::env::var_os("DPDNL_BLESS").is_some() {
        let new = format!("{}{verdict}{}", &text[..at], &text[end..]);
        std::fs::write(&page, new).expect("rewrite the page");
    } else {
        assert_eq!(
            &text[at..end],
            verdict,
            "{}: the verdict example is not the current one; `DPDNL_BLESS=1 cargo test --test \
             crosscheck manual_verdict` rewrites it",
            page.display()
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
