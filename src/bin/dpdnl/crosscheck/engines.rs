//! The two runs of a crosscheck: the standalone engine in-process, LAMMPS as a subprocess, and
//! their dumps moved into the work directory.

use super::{CannotRun, CrosscheckArgs};
use dpdnl::input::{Console, FromState, Interpreter, Options, StateReport};
use std::path::{Path, PathBuf};
use std::process::Command;

struct Quiet;

impl Console for Quiet {
    fn line(&mut self, _text: &str) {}
}
/// The LAMMPS executable, as an absolute path when given as a path.
pub(super) fn find_lmp(a: &CrosscheckArgs) -> Result<PathBuf, CannotRun> {
    let given = a
        .lmp
        .clone()
        .or_else(|| std::env::var_os("DPDNL_LMP").map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("build/lmp_dpdnl"));
    let hint = "build it with `bash lammps-plugin/build.sh` (from the repository root), or \
                point --lmp or $DPDNL_LMP at a LAMMPS with pair_style dpd/nonlinear";
    if given.components().count() == 1 && given.is_relative() && !given.exists() {
        // A bare name: look it up on PATH.
        if let Some(paths) = std::env::var_os("PATH") {
            for dir in std::env::split_paths(&paths) {
                let p = dir.join(&given);
                if p.is_file() {
                    return Ok(p);
                }
            }
        }
        return Err(CannotRun(format!(
            "LAMMPS executable '{}' not found on PATH; {hint}",
            given.display()
        )));
    }
    if !given.is_file() {
        return Err(CannotRun(format!(
            "LAMMPS executable {} not found; {hint}",
            given.display()
        )));
    }
    Ok(std::fs::canonicalize(&given)?)
}
/// Moves `from` (relative to the script directory, the current directory) to `dir/name`.
fn move_file(from: &Path, to: &Path) -> Result<(), CannotRun> {
    if std::fs::rename(from, to).is_err() {
        std::fs::copy(from, to).map_err(|e| {
            CannotRun(format!(
                "cannot move {} to {}: {e}",
                from.display(),
                to.display()
            ))
        })?;
        let _ = std::fs::remove_file(from);
    }
    Ok(())
}
/// Where a dump of the standalone engine or LAMMPS is moved: the work directory.
pub(super) fn moved(workdir: &Path, p: &Path, tag: &str) -> PathBuf {
    let name = p
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| tag.to_string());
    workdir.join(name)
}

/// What the standalone engine's run left: its log, the pairs (standalone dump, LAMMPS dump) of
/// the dumps whose names contain the engine name, and, from LAMMPS's state, what the state
/// carried.
pub(super) struct Standalone {
    pub(super) log: PathBuf,
    pub(super) dumps: Vec<(PathBuf, PathBuf)>,
    pub(super) state: Option<StateReport>,
}

/// Why the standalone engine did not run: the error, and whether it came from the set-up
/// (before the first `run`), where a crosscheck from LAMMPS's state may still go on.
pub(super) struct StandaloneFailed {
    pub(super) error: CannotRun,
    pub(super) in_setup: bool,
}

impl From<CannotRun> for StandaloneFailed {
    fn from(error: CannotRun) -> Self {
        StandaloneFailed {
            error,
            in_setup: false,
        }
    }
}

/// Step 1: the standalone engine, in-process (`-var engine standalone`), from its own set-up or
/// from LAMMPS's state (`from`); the standalone dumps moved to the work directory.
pub(super) fn run_standalone(
    script: &Path,
    workdir: &Path,
    vars: &mut Vec<(String, String)>,
    threads: usize,
    from: Option<&FromState>,
) -> Result<Standalone, StandaloneFailed> {
    // 1. Standalone engine, in-process.
    // A global pool may already exist (e.g. when called twice in one process); that is fine.
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global();
    let log_s = workdir.join("standalone.log");
    vars.push(("engine".into(), "standalone".into()));
    let opts = Options {
        log: Some(log_s.clone()),
        vars: vars.clone(),
        threads,
        from_state: from.cloned(),
        ..Options::default()
    };
    vars.pop();
    let mut quiet = Quiet;
    let (dump_files, state) = {
        let mut interp = Interpreter::new(&mut quiet, &opts).map_err(CannotRun)?;
        if let Err(e) = interp.run_file(script) {
            return Err(StandaloneFailed {
                error: CannotRun(format!("the standalone engine failed: {e}")),
                in_setup: interp.runs_started() == 0,
            });
        }
        (interp.dump_files(), interp.state_report().cloned())
    };
    // Dumps whose names contain the engine name: (standalone file, lammps file).
    let mut dumps: Vec<(PathBuf, PathBuf)> = Vec::new();
    for f in &dump_files {
        if let Some(k) = f.rfind("standalone") {
            let other = format!("{}lammps{}", &f[..k], &f[k + "standalone".len()..]);
            dumps.push((PathBuf::from(f), PathBuf::from(other)));
        }
    }
    for (s, _) in &dumps {
        move_file(s, &moved(workdir, s, "dump.standalone"))?;
    }
    Ok(Standalone {
        log: log_s,
        dumps,
        state,
    })
}

/// Step 2: LAMMPS, a subprocess (`-var engine lammps`); its log, its dumps moved to the work
/// directory.
pub(super) fn run_lammps(
    lmp: &Path,
    script: &Path,
    workdir: &Path,
    vars: &[(String, String)],
    dumps: &[(PathBuf, PathBuf)],
) -> Result<PathBuf, CannotRun> {
    // 2. LAMMPS, a subprocess.
    let log_l = workdir.join("lammps.log");
    let out = run_lmp(lmp, script, &log_l, vars)?;
    if !out.status.success() {
        let log = std::fs::read_to_string(&log_l).unwrap_or_default();
        let tail: Vec<&str> = log.lines().rev().take(8).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let script_text = std::fs::read_to_string(script).unwrap_or_default();
        let hint = if script_text.lines().any(|l| {
            let w: Vec<&str> = l
                .split('#')
                .next()
                .unwrap_or("")
                .split_whitespace()
                .collect();
            w.len() > 3
                && w[0] == "fix"
                && w[3] == "deform"
                && w.windows(2).any(|p| p[0] == "order")
        }) {
            "\n(`fix deform … order lammps|current` is a keyword of the standalone engine only; \
             LAMMPS refuses it. Drop it to compare: LAMMPS's order is the standalone engine's \
             default, and `order current` gives other numbers by design: step n's forces in the \
             box of step n instead of n − 1, atoms wrapped every step)"
        } else {
            ""
        };
        return Err(CannotRun(format!(
            "LAMMPS ({}) failed ({}); end of {}:\n{}\n{}{hint}",
            lmp.display(),
            out.status,
            log_l.display(),
            tail.join("\n"),
            stderr.trim_end()
        )));
    }
    for (_, l) in dumps {
        if !l.is_file() {
            return Err(CannotRun(format!(
                "LAMMPS did not write {} (the standalone engine wrote its dump with \
                 'standalone' in the name; use ${{engine}} in the dump file name)",
                l.display()
            )));
        }
        move_file(l, &moved(workdir, l, "dump.lammps"))?;
    }
    Ok(log_l)
}

/// Run LAMMPS `lmp` on `input`, logging to `log`, screen off, with the `-var` pairs `vars` and
/// `-var engine lammps`; its output once it has exited.
pub(super) fn run_lmp(
    lmp: &Path,
    input: &Path,
    log: &Path,
    vars: &[(String, String)],
) -> Result<std::process::Output, CannotRun> {
    let mut cmd = Command::new(lmp);
    cmd.arg("-in")
        .arg(input)
        .arg("-log")
        .arg(log)
        .args(["-screen", "none"]);
    for (k, v) in vars {
        cmd.args(["-var", k, v]);
    }
    cmd.args(["-var", "engine", "lammps"]);
    cmd.output()
        .map_err(|e| CannotRun(format!("cannot start {}: {e}", lmp.display())))
}
