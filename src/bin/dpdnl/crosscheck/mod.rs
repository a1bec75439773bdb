//! `dpdnl crosscheck SCRIPT`: run one script in the standalone engine (in-process) and in LAMMPS
//! (`build/lmp_dpdnl`, a subprocess), then compare the thermo logs, and the dumps whose file
//! names contain `${engine}`, value by value.
//!
//! Both engines run with the current directory set to the script's directory (scripts use
//! relative paths, as in LAMMPS) and with `-var engine standalone` / `-var engine lammps`, so a
//! dump written to `dump.${engine}` gets one file per engine. The dumps are moved into the work
//! directory after each run. Exit status: 0 agree, 1 differ, 2 cannot run.
//!
//! LAMMPS's neighbour-list settings and its "Dangerous builds = N" count are read from its log
//! ([`neighbor_summary`](dpdnl::io::lammps_log::neighbor_summary)): with dangerous builds (its
//! lists missed pairs, e.g. under the `neigh_modify delay 10` default of older LAMMPS) a DIFFER
//! verdict says so and names the fix, `neigh_modify delay 0 every 1 check yes`. The standalone
//! engine checks every step.
//!
//! `--from lammps` (and `--from auto`, the default, when the standalone engine cannot build the
//! system: an error before the first `run`) starts both engines from LAMMPS's state: LAMMPS
//! runs the script's set-up (its lines before the first top-level `run`) and writes its state,
//! which the standalone engine installs at `create_box`/`read_data` (see [`state`]).

mod compare;
mod engines;
mod state;
mod verdict;

use compare::compare;
use engines::{Standalone, find_lmp, run_lammps, run_standalone};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Run one script in the standalone engine and in LAMMPS and compare thermo logs and dumps.
///
/// Exit status: 0 when both engines agree within --rtol, 1 when they differ, 2 when the script
/// cannot be run in one of them (or LAMMPS is missing).
#[derive(clap::Args)]
pub struct CrosscheckArgs {
    /// The input script (run with its own directory as the current directory, in both engines).
    pub script: PathBuf,
    /// The LAMMPS executable with `pair_style dpd/nonlinear` (default: $DPDNL_LMP, else
    /// build/lmp_dpdnl; build it with `bash lammps-plugin/build.sh`).
    #[arg(long)]
    pub lmp: Option<PathBuf>,
    /// Relative tolerance: |A−B| / max(|A|, |B|).
    #[arg(long, default_value_t = 1e-9)]
    pub rtol: f64,
    /// Absolute tolerance: a value differs only if both tolerances are exceeded (an atom's net
    /// force can be a near-cancellation of O(10) pair forces, which two summation orders leave
    /// ~1e-13 apart in absolute terms).
    #[arg(long, default_value_t = 0.0)]
    pub atol: f64,
    /// Define an index-style variable NAME with VALUE in both engines; repeatable.
    #[arg(long = "var", short = 'v', num_args = 2, value_names = ["NAME", "VALUE"], action = clap::ArgAction::Append, allow_hyphen_values = true)]
    pub var: Vec<String>,
    /// Where the logs (standalone.log, lammps.log) and dumps go (default: a new directory
    /// under the system's temporary directory).
    #[arg(long)]
    pub workdir: Option<PathBuf>,
    /// Worker threads of the standalone engine (results are bit-identical for any number). 0:
    /// one per CPU available; a larger N than that is capped at the CPU count, with a warning.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64))]
    pub threads: u64,
    /// Where the standalone engine's run starts. `script`: both engines run the whole script
    /// (start from `read_data` for the same state: `create_atoms random` and `velocity create`
    /// draw differently in the two engines). `lammps`: LAMMPS runs the set-up (the script's
    /// lines before its first top-level `run`: lattice, create_atoms, velocity create, region
    /// shapes, set, delete_atoms, minimize, …) and writes its state (write_data: box, tilt,
    /// atoms, image flags, velocities, masses, topology, step; group memberships); the
    /// standalone engine installs it at `create_box`/`read_data`, skips the set-up commands the
    /// state carries (logged), and both run the rest of the script; the verdict names what
    /// was not carried. `auto`: `script`, then `lammps` when the standalone engine cannot build
    /// the system (an error before the first run).
    #[arg(long, value_enum, default_value_t = StartFrom::Auto)]
    pub from: StartFrom,
}

/// `--from`: where the standalone engine's run starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum StartFrom {
    /// `script`, then `lammps` when the standalone engine cannot build the system.
    Auto,
    /// Both engines run the whole script.
    Script,
    /// The standalone engine starts from LAMMPS's state after the set-up.
    Lammps,
}

/// An error that means "cannot run" (exit 2).
struct CannotRun(String);

impl<E: std::fmt::Display> From<E> for CannotRun {
    fn from(e: E) -> Self {
        CannotRun(e.to_string())
    }
}

pub fn main(a: CrosscheckArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    match run(&a) {
        Ok(true) => Ok(ExitCode::SUCCESS),
        Ok(false) => Ok(ExitCode::from(1)),
        Err(CannotRun(e)) => {
            eprintln!("ERROR: dpdnl crosscheck: {e}");
            Ok(ExitCode::from(2))
        }
    }
}

fn default_workdir(script: &Path) -> PathBuf {
    let stem = script
        .file_name()
        .map(|s| {
            s.to_string_lossy()
                .replace(|c: char| !c.is_ascii_alphanumeric(), "_")
        })
        .unwrap_or_default();
    std::env::temp_dir().join(format!("dpdnl-crosscheck-{stem}-{}", std::process::id()))
}

fn run(a: &CrosscheckArgs) -> Result<bool, CannotRun> {
    if a.atol.is_nan() || a.atol < 0.0 {
        return Err(CannotRun(format!(
            "--atol must be a non-negative number, got {}",
            a.atol
        )));
    }
    if a.rtol.is_nan() || a.rtol < 0.0 {
        return Err(CannotRun(format!(
            "--rtol must be a non-negative number, got {}",
            a.rtol
        )));
    }
    let threads = crate::thread_count(a.threads);
    let lmp = find_lmp(a)?;
    let script = std::fs::canonicalize(&a.script)
        .map_err(|e| CannotRun(format!("cannot open script {}: {e}", a.script.display())))?;
    let script_dir = script
        .parent()
        .map(Path::to_path_buf)
        .ok_or_else(|| CannotRun(format!("{} has no directory", script.display())))?;
    let workdir = a
        .workdir
        .clone()
        .unwrap_or_else(|| default_workdir(&script));
    std::fs::create_dir_all(&workdir)
        .map_err(|e| CannotRun(format!("cannot create {}: {e}", workdir.display())))?;
    let workdir = std::fs::canonicalize(&workdir)?;
    let mut vars = crate::var_pairs(&a.var);
    let engine_given = vars.iter().any(|(k, _)| k == "engine");
    vars.retain(|(k, _)| k != "engine");
    if engine_given {
        eprintln!("WARNING: -var engine is set by crosscheck itself; the given value is ignored");
    }
    std::env::set_current_dir(&script_dir)
        .map_err(|e| CannotRun(format!("cannot enter {}: {e}", script_dir.display())))?;

    let mut from_state = None;
    if a.from == StartFrom::Lammps {
        from_state = Some(state::lammps_state(&lmp, &script, &workdir, &vars)?);
    }
    let standalone =
        match run_standalone(&script, &workdir, &mut vars, threads, from_state.as_ref()) {
            Ok(s) => s,
            Err(f) if a.from == StartFrom::Auto && f.in_setup => {
                println!(
                    "note: the standalone engine cannot build this system ({}); crosschecking \
                 from LAMMPS's state (--from lammps)",
                    f.error
                        .0
                        .trim_start_matches("the standalone engine failed: ")
                );
                let st = state::lammps_state(&lmp, &script, &workdir, &vars)?;
                let s = run_standalone(&script, &workdir, &mut vars, threads, Some(&st))
                    .map_err(|f| f.error)?;
                from_state = Some(st);
                s
            }
            Err(f) => return Err(f.error),
        };
    let Standalone { log, dumps, state } = standalone;
    let log_l = run_lammps(&lmp, &script, &workdir, &vars, &dumps)?;
    let from = from_state.as_ref().zip(state.as_ref());
    compare(a, &lmp, &script, &workdir, (&log, &log_l), &dumps, from)
}
