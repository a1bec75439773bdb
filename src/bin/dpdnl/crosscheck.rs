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
//! ([`neighbor_summary`]): with dangerous builds (its lists missed pairs, e.g. under the
//! `neigh_modify delay 10` default of older LAMMPS) a DIFFER verdict says so and names the fix,
//! `neigh_modify delay 0 every 1 check yes`. The standalone engine checks every step.

use crate::report::{TableStyle, c, write_exact_table};
use dpdnl::input::{Console, Interpreter, Options};
use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use dpdnl::io::growth::{
    Growth, MAX_RATE, Point, classify, merged, printed_digits, resolution, table_rows, timeline,
};
use dpdnl::io::lammps_log::{
    ExactReport, NeighborSummary, StepMax, Tolerance, compare_dumps_exact, compare_exact_logs,
    neighbor_summary, parse_log,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

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
}

/// An error that means "cannot run" (exit 2).
struct CannotRun(String);

impl<E: std::fmt::Display> From<E> for CannotRun {
    fn from(e: E) -> Self {
        CannotRun(e.to_string())
    }
}

struct Quiet;

impl Console for Quiet {
    fn line(&mut self, _text: &str) {}
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

/// The LAMMPS executable, as an absolute path when given as a path.
fn find_lmp(a: &CrosscheckArgs) -> Result<PathBuf, CannotRun> {
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

fn run(a: &CrosscheckArgs) -> Result<bool, CannotRun> {
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

    let (log_s, dumps) = run_standalone(&script, &workdir, &mut vars, threads)?;
    let log_l = run_lammps(&lmp, &script, &workdir, &vars, &dumps)?;
    compare(a, &lmp, &script, &workdir, &log_s, &log_l, &dumps)
}

/// Where a dump of the standalone engine or LAMMPS is moved: the work directory.
fn moved(workdir: &Path, p: &Path, tag: &str) -> PathBuf {
    let name = p
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| tag.to_string());
    workdir.join(name)
}

/// Step 1: the standalone engine, in-process (`-var engine standalone`); its log and the pairs
/// (standalone dump, LAMMPS dump) of the dumps whose names contain the engine name, the
/// standalone ones moved to the work directory.
fn run_standalone(
    script: &Path,
    workdir: &Path,
    vars: &mut Vec<(String, String)>,
    threads: usize,
) -> Result<(PathBuf, Vec<(PathBuf, PathBuf)>), CannotRun> {
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
        ..Options::default()
    };
    vars.pop();
    let mut quiet = Quiet;
    let dump_files = {
        let mut interp = Interpreter::new(&mut quiet, &opts)?;
        interp
            .run_file(script)
            .map_err(|e| CannotRun(format!("the standalone engine failed: {e}")))?;
        interp.dump_files()
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
    Ok((log_s, dumps))
}

/// Step 2: LAMMPS, a subprocess (`-var engine lammps`); its log, its dumps moved to the work
/// directory.
fn run_lammps(
    lmp: &Path,
    script: &Path,
    workdir: &Path,
    vars: &[(String, String)],
    dumps: &[(PathBuf, PathBuf)],
) -> Result<PathBuf, CannotRun> {
    // 2. LAMMPS, a subprocess.
    let log_l = workdir.join("lammps.log");
    let mut cmd = Command::new(lmp);
    cmd.arg("-in")
        .arg(script)
        .arg("-log")
        .arg(&log_l)
        .args(["-screen", "none"]);
    for (k, v) in vars {
        cmd.args(["-var", k, v]);
    }
    cmd.args(["-var", "engine", "lammps"]);
    let out = cmd
        .output()
        .map_err(|e| CannotRun(format!("cannot start {}: {e}", lmp.display())))?;
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

/// Step 3: compare the thermo logs and the dumps exactly (to `--rtol`) and print the report;
/// true when they agree.
fn compare(
    a: &CrosscheckArgs,
    lmp: &Path,
    script: &Path,
    workdir: &Path,
    log_s: &Path,
    log_l: &Path,
    dumps: &[(PathBuf, PathBuf)],
) -> Result<bool, CannotRun> {
    // 3. Compare.
    let tol = Tolerance {
        rtol: a.rtol,
        atol: 0.0,
    };
    let read = |p: &Path| {
        std::fs::read_to_string(p)
            .map_err(|e| CannotRun(format!("cannot read {}: {e}", p.display())))
    };
    let text_s = read(log_s)?;
    let blocks_s = parse_log(&text_s).map_err(|e| format!("{}: {e}", log_s.display()))?;
    let text_l = read(log_l)?;
    let blocks_l = parse_log(&text_l).map_err(|e| format!("{}: {e}", log_l.display()))?;
    let neigh = neighbor_summary(&text_l);
    if blocks_s.is_empty() || blocks_l.is_empty() {
        return Err(CannotRun(
            "a log has no thermo block (does the script run any steps?)".into(),
        ));
    }
    println!("script: {}", script.display());
    println!("lammps: {}", lmp.display());
    println!("workdir: {}", workdir.display());
    if let Some(line) = neighbor_line(&neigh) {
        println!("{line}");
    }
    let mut notes = shear_notes(&text_l, &neigh);
    notes.extend(flip_leak_notes(&text_s, &text_l));
    for n in &notes {
        println!("note: {n}");
    }
    let r = compare_exact_logs(&blocks_s, &blocks_l, None, tol)
        .map_err(|e| format!("comparing thermo logs: {e}"))?;
    let mut pass = print_report("thermo (A = standalone.log, B = lammps.log)", &r);
    // The coarsest printed precision of the compared files bounds what the comparison resolves.
    let mut digits: Vec<usize> = [&text_s, &text_l]
        .iter()
        .filter_map(|t| printed_digits(t))
        .collect();
    let mut dump_steps: Vec<(String, Vec<StepMax>)> = Vec::new();
    let mut n_dump_rows = 0;
    for (s, l) in dumps {
        let (ps, pl) = (
            moved(workdir, s, "dump.standalone"),
            moved(workdir, l, "dump.lammps"),
        );
        let (ts, tl) = (read(&ps)?, read(&pl)?);
        digits.extend(printed_digits(&ts));
        digits.extend(printed_digits(&tl));
        let fs = parse_dump(&ts).map_err(|e| format!("{}: {e}", ps.display()))?;
        let mut fl = parse_dump(&tl).map_err(|e| format!("{}: {e}", pl.display()))?;
        let shifted = minimum_image(&fs, &mut fl);
        let r = compare_dumps_exact(&fs, &fl, None, tol)
            .map_err(|e| format!("comparing dumps {} and {}: {e}", ps.display(), pl.display()))?;
        n_dump_rows += r.n_matched;
        let name = ps.file_name().unwrap_or_default().to_string_lossy();
        let title = format!(
            "dump (A = {name}, B = {})",
            pl.file_name().unwrap_or_default().to_string_lossy()
        );
        pass &= print_report(&title, &r);
        dump_steps.push((name.replace("standalone", "${engine}"), r.steps.clone()));
        if shifted > 0 {
            println!(
                "({shifted} LAMMPS atom position(s) moved by lattice vectors to the standalone \
                 image: LAMMPS wraps atoms back into the box only when it re-neighbours, and \
                 into the tilted cell of a tilted box)"
            );
        }
    }
    let what = if dumps.is_empty() {
        "thermo log".to_string()
    } else {
        format!(
            "thermo log and {} dump(s), {n_dump_rows} atom rows",
            dumps.len()
        )
    };
    if pass {
        println!("CROSSCHECK AGREE: {what} within rtol {}", c("%g", a.rtol));
    } else {
        let points = timeline(&r.steps, &dump_steps);
        let res = digits.iter().min().map_or(0.0, |&d| resolution(d));
        let growth = classify(&points, a.rtol, res);
        print!("{}", growth_table(&merged(&points), a.rtol));
        let mut v = differ_verdict(&what, a.rtol, &neigh, &growth);
        for n in &notes {
            let _ = write!(v, "; {n}");
        }
        println!("{v}");
    }
    Ok(pass)
}

/// `lammps neighbor lists: neigh_modify every 1 delay 10 check yes; Dangerous builds = 2`, from
/// the LAMMPS log (None when it has neither line).
fn neighbor_line(n: &NeighborSummary) -> Option<String> {
    if n.settings.is_empty() && n.dangerous.is_empty() {
        return None;
    }
    let settings = n
        .settings
        .last()
        .map_or("settings not logged".to_string(), |s| {
            format!("neigh_modify {}", s.keywords())
        });
    let builds = if n.dangerous.is_empty() {
        String::new()
    } else if n.unchecked_runs() == n.dangerous.len() {
        "; Dangerous builds not checked".to_string()
    } else {
        format!("; Dangerous builds = {}", dangerous_counts(n))
    };
    Some(format!("lammps neighbor lists: {settings}{builds}"))
}

/// `2`, or per run `0, 2, not checked`.
fn dangerous_counts(n: &NeighborSummary) -> String {
    if n.dangerous.len() == 1 {
        return n.dangerous_total().to_string();
    }
    let runs: Vec<String> = n
        .dangerous
        .iter()
        .map(|d| d.map_or("not checked".to_string(), |k| k.to_string()))
        .collect();
    format!("{} (per run: {})", n.dangerous_total(), runs.join(", "))
}

/// The momentum leak at box flips (issue 41), as the end-of-run warnings of the two logs report
/// it: plain `fix deform … remap v` puts atoms through y at flips without the velocity jump, so
/// the mean velocity relative to the shear profile, V, is not 0; both engines do the same and
/// agree, but neither is right. One note per engine that reports it, with the cure.
fn flip_leak_notes(text_s: &str, text_l: &str) -> Vec<String> {
    let leak = |text: &str| -> Option<(u64, String)> {
        let mut atoms = 0;
        let mut v = String::new();
        for line in text
            .lines()
            .filter(|l| l.contains("without remap v's velocity jump"))
        {
            let n = line
                .split("box flips put ")
                .nth(1)
                .and_then(|r| r.split_whitespace().next())
                .and_then(|w| w.parse::<u64>().ok())?;
            atoms += n;
            if let Some(rest) = line.split("mean velocity V = ").nth(1) {
                v = rest.split(')').next().unwrap_or_default().to_string();
            }
        }
        (atoms > 0).then_some((atoms, v))
    };
    [("standalone engine", text_s), ("LAMMPS", text_l)]
        .iter()
        .filter_map(|(who, text)| {
            let (atoms, v) = leak(text)?;
            Some(format!(
                "{who}: box flips put {atoms} atom(s) through y without remap v's velocity jump \
                 (V = {v} in its last run): the momentum relative to the shear profile leaked, \
                 as LAMMPS's fix deform leaks it; add `fix ID all flip/momentum` \
                 (docs/manual/styles/fix_flip_momentum.md)"
            ))
        })
        .collect()
}

/// The differences by design of a sheared run (a `fix … deform` in LAMMPS's echo of the
/// script), each with the agreement to expect: LAMMPS wraps atoms back into a tilted box, and
/// `remap v` changes their v_x by the box's velocity jump, only when it re-neighbours (and, with
/// no jump, in `write_restart`, whose `init` sets the jump to 0 outside a run); the standalone
/// engine re-neighbours by LAMMPS's rule for `neigh_modify delay 0 every 1 check yes` (and on
/// the steps `restart N` writes, as LAMMPS), so another `neigh_modify` schedule or a
/// `write_restart` between runs wraps atoms on other steps in LAMMPS.
fn shear_notes(text_l: &str, n: &NeighborSummary) -> Vec<String> {
    let words = |l: &str| l.split_whitespace().map(str::to_string).collect::<Vec<_>>();
    let lines: Vec<Vec<String>> = text_l.lines().map(words).collect();
    let sheared = lines
        .iter()
        .any(|w| w.len() > 3 && w[0] == "fix" && w[3] == "deform");
    if !sheared {
        return Vec::new();
    }
    let mut why = Vec::new();
    if let Some(st) = n
        .settings
        .last()
        .filter(|s| !(s.every == 1 && s.delay == 0 && s.check))
    {
        why.push(format!(
            "LAMMPS re-neighbours by `neigh_modify {}`, the standalone engine by LAMMPS's \
             rule for `neigh_modify delay 0 every 1 check yes` only",
            st.keywords()
        ));
    }
    if lines
        .iter()
        .any(|w| w.first().is_some_and(|c| c == "write_restart"))
    {
        why.push(
            "LAMMPS's `write_restart` wraps the atoms outside the box without the velocity \
             jump (its `fix deform` has h_rate 0 outside a run), the standalone engine's \
             leaves them"
                .to_string(),
        );
    }
    why.into_iter()
        .map(|w| {
            format!(
                "sheared box (fix deform): {w}, and LAMMPS wraps atoms into the tilted box \
                 (with the `remap v` velocity jump) only when it re-neighbours, so an atom can \
                 wait outside the box in one engine and not in the other: expect `temp`, `ke`, \
                 `etotal`, the thermo pressure and dumped x, vx to differ (by about \
                 m (R L_y)^2 / (d N) in temp per such atom); pe, forces, `temp/deform` and its \
                 pressure, and xu agree to round-off only until the first box flip (LAMMPS puts \
                 the atoms outside the box at a flip back without their velocity jump, and \
                 which atoms those are depends on its schedule), after it they differ too; for \
                 the same numbers use `neigh_modify delay 0 every 1 check yes` and no \
                 `write_restart` between runs"
            )
        })
        .collect()
}

/// The DIFFER verdict line, with the reason LAMMPS's own log gives when it gives one: dangerous
/// builds (its neighbour lists missed pairs, unless they were checked every step), or lists it
/// rebuilt every N > 1 steps unchecked.
fn differ_verdict(what: &str, rtol: f64, n: &NeighborSummary, growth: &Growth) -> String {
    let mut v = format!(
        "CROSSCHECK DIFFER{}: {what} not within rtol {} (see the table(s) above)",
        growth_reason(growth),
        c("%g", rtol)
    );
    if let Growth::Chaotic {
        reaches_rtol: Some(t),
        start,
        ..
    } = growth
    {
        let _ = write!(
            v,
            "; the fitted growth reaches rtol {} about {} steps after step {}: compare \
             shorter runs, or loosen --rtol",
            c("%g", rtol),
            (t - start.elapsed as f64).max(0.0).round(),
            start.step
        );
    }
    let settings = n.settings.last().map_or(String::new(), |s| {
        format!(" (neigh_modify {})", s.keywords())
    });
    let fix = "add `neigh_modify delay 0 every 1 check yes` to the script and run again to see \
               what difference remains (the standalone engine checks its lists every step)";
    let every_step = n.settings.last().is_some_and(|s| s.checks_every_step());
    if n.dangerous_total() > 0 && every_step {
        // LAMMPS counts a build as dangerous when it comes at the first step it could
        // (ago == max(every, delay)): with every 1 delay 0 that is any build one step after the
        // previous, e.g. every build under fast shear. The lists were checked before every
        // force evaluation, so no pair was missed: the count explains nothing here.
        let _ = write!(
            v,
            "; LAMMPS logged Dangerous builds = {}{settings}: with lists checked every step \
             that only counts rebuilds on consecutive steps (fast shear or fast atoms), not \
             missed pairs, so the difference has another cause",
            dangerous_counts(n)
        );
    } else if n.dangerous_total() > 0 {
        let _ = write!(
            v,
            "; LAMMPS logged Dangerous builds = {}{settings}: some atom had moved more than half \
             the skin before LAMMPS rebuilt its neighbor lists, so it missed pairs, enough by \
             itself to make the engines differ; {fix}",
            dangerous_counts(n)
        );
    } else if n.unchecked_runs() > 0 && n.settings.last().is_none_or(|s| s.every > 1) {
        let _ = write!(
            v,
            "; LAMMPS did not check its neighbor lists (Dangerous builds not checked{settings}), \
             so missed pairs cannot be ruled out; {fix}"
        );
    }
    v
}

/// `3.1e-13`, or `0 (identical to the printed digits)`.
fn small(x: f64) -> String {
    if x == 0.0 {
        "0 (identical to the printed digits)".to_string()
    } else {
        c("%.1e", x)
    }
}

/// ` (chaotic growth of round-off: …)`, the parenthesis of the DIFFER verdict that says which
/// case the user is in ([`Growth`]).
fn growth_reason(g: &Growth) -> String {
    match g {
        Growth::Agree => String::new(),
        Growth::AtStart { start, floor } => format!(
            " (model difference: already {} at step {} ({}), where round-off leaves at most {})",
            c("%.1e", start.diff),
            start.step,
            start.what,
            c("%.0e", *floor)
        ),
        Growth::Chaotic { start, rate, .. } => format!(
            " (chaotic growth of round-off: step-{} agreement {}, growth rate {} per step, x10 \
             every {} steps; this is not a model difference)",
            start.step,
            small(start.diff),
            c("%.3g", *rate),
            c("%.0f", std::f64::consts::LN_10 / rate)
        ),
        Growth::NotRoundoff {
            start,
            at,
            needed_rate,
            line_start,
            ..
        } => {
            let why = if *needed_rate > MAX_RATE {
                format!(
                    "growing from round-off that needs a rate of at least {} per step, x10 every \
                     {} steps, too fast for chaos at a time step that resolves the dynamics",
                    c("%.3g", *needed_rate),
                    c("%.2g", std::f64::consts::LN_10 / needed_rate)
                )
            } else {
                format!(
                    "not a constant exponential growth from round-off{}",
                    line_start.map_or(String::new(), |l| format!(
                        " (the growth taken back to step {} gives {})",
                        start.step,
                        c("%.1e", l)
                    ))
                )
            };
            format!(
                " (model difference after step {s}: step-{s} agreement {}, then {} at step {} \
                 ({}); {why})",
                small(start.diff),
                c("%.1e", at.diff),
                at.step,
                at.what,
                s = start.step,
            )
        }
        Growth::Unresolved {
            start,
            at,
            needed_rate,
            ..
        } => format!(
            " (round-off growth or model difference, cannot tell: step-{} agreement {}, then {} \
             at step {} ({}), too few output steps in between to measure the growth; from \
             round-off that needs a rate of at least {} per step, x10 every {} steps; print \
             thermo more often)",
            start.step,
            small(start.diff),
            c("%.1e", at.diff),
            at.step,
            at.what,
            c("%.3g", *needed_rate),
            c("%.2g", std::f64::consts::LN_10 / needed_rate)
        ),
        Growth::RoundoffOnly { largest, floor } => format!(
            " (round-off only: every difference is at most {} (round-off, or the printed \
             digits), the largest {} at step {}; --rtol is tighter than that)",
            c("%.0e", *floor),
            c("%.1e", largest.diff),
            largest.step
        ),
    }
}

/// The short table of the largest difference per output step, from the first.
fn growth_table(points: &[Point], rtol: f64) -> String {
    let mut out = String::from(
        "\ngrowth of the largest difference from the first step (|A - B| / the largest |value| \
         of its column: thermo over the run, dump in the frame):\n",
    );
    let _ = writeln!(out, "{:>10}  {:>10}  where", "step", "difference");
    for i in table_rows(points, rtol, 12) {
        let p = &points[i];
        let _ = writeln!(
            out,
            "{:>10}  {:>10}  {}",
            p.step,
            c("%.2e", p.diff),
            if p.diff > 0.0 { p.what.as_str() } else { "" }
        );
    }
    out
}

/// Prints one comparison table; true when it passes (values and rows).
fn print_report(title: &str, r: &ExactReport) -> bool {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\n{title}: {} row(s) matched by {}",
        r.n_matched, r.key
    );
    write_exact_table(
        &mut out,
        r,
        &TableStyle {
            labels: ["standalone", "lammps"],
            value_fmt: "%.15g",
            value_width: 22,
            blank_before_header: false,
        },
    );
    print!("{out}");
    r.values_pass() && r.rows_match()
}

/// The box of a dump frame as (lo, edge lengths, xy): for a triclinic frame the bounds are
/// LAMMPS's bounding box (`xlo_bound = xlo + min(0, xy, xz, xy + xz)`, …), undone here.
fn frame_box(f: &DumpFrame) -> Option<([f64; 3], [f64; 3], f64)> {
    if f.box_bounds.len() < 3 {
        return None;
    }
    let [xy, xz, yz] = f.tilt.unwrap_or([0.0; 3]);
    let b = &f.box_bounds;
    let lo = [
        b[0][0] - 0f64.min(xy).min(xz).min(xy + xz),
        b[1][0] - 0f64.min(yz),
        b[2][0],
    ];
    let hi = [
        b[0][1] - 0f64.max(xy).max(xz).max(xy + xz),
        b[1][1] - 0f64.max(yz),
        b[2][1],
    ];
    let len = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    if xz != 0.0 || yz != 0.0 || len.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
        return None;
    }
    Some((lo, len, xy))
}

/// Maps the `x`, `y`, `z` values of `b` to the periodic image nearest `a`'s value for the same
/// atom and step, since the engines wrap atoms at different times (LAMMPS only when it
/// re-neighbours) and, in a tilted box, into different cells (LAMMPS the tilted cell, the
/// standalone engine the orthogonal one): the image is moved by whole lattice vectors
/// (L_x, 0, 0), (xy, L_y, 0), (0, 0, L_z), y first. A value is changed only when it is more than
/// half a box length away; image flags `ix iy iz`, when dumped, change with it (the unwrapped
/// position is kept). Returns how many atoms were shifted.
fn minimum_image(a: &[DumpFrame], b: &mut [DumpFrame]) -> usize {
    let mut shifted = 0;
    for fb in b.iter_mut() {
        let Some(fa) = a.iter().find(|f| f.step == fb.step) else {
            continue;
        };
        let Some((_, len, xy)) = frame_box(fb) else {
            continue;
        };
        let col = |f: &DumpFrame, name: &str| f.columns.iter().position(|c| c == name);
        let (Some(ida), Some(idb)) = (col(fa, "id"), col(fb, "id")) else {
            continue;
        };
        let by_id: std::collections::HashMap<i64, &Vec<f64>> =
            fa.rows.iter().map(|r| (r[ida] as i64, r)).collect();
        let ka: Vec<Option<usize>> = ["x", "y", "z"].iter().map(|n| col(fa, n)).collect();
        let kb: Vec<Option<usize>> = ["x", "y", "z"].iter().map(|n| col(fb, n)).collect();
        let kimg: Vec<Option<usize>> = ["ix", "iy", "iz"].iter().map(|n| col(fb, n)).collect();
        for rb in fb.rows.iter_mut() {
            let Some(ra) = by_id.get(&(rb[idb] as i64)) else {
                continue;
            };
            let nb = rb.len();
            let pair = |d: usize| match (ka[d], kb[d]) {
                (Some(i), Some(j)) if i < ra.len() && j < nb => Some((i, j)),
                _ => None,
            };
            let mut moved = false;
            // A move by n lattice vectors along d changes the image flag by +n (the unwrapped
            // position is kept).
            let flag = |rb: &mut Vec<f64>, d: usize, n: f64| {
                if let Some(k) = kimg[d].filter(|&k| k < nb) {
                    rb[k] += n;
                }
            };
            // y first: a y image also moves x by the tilt.
            if let Some((i, j)) = pair(1) {
                let n = ((rb[j] - ra[i]) / len[1]).round();
                if n != 0.0 && n.is_finite() {
                    rb[j] -= n * len[1];
                    if let Some((_, jx)) = pair(0) {
                        rb[jx] -= n * xy;
                    }
                    flag(rb, 1, n);
                    moved = true;
                }
            }
            for d in [0, 2] {
                if let Some((i, j)) = pair(d) {
                    let n = ((rb[j] - ra[i]) / len[d]).round();
                    if n != 0.0 && n.is_finite() {
                        rb[j] -= n * len[d];
                        flag(rb, d, n);
                        moved = true;
                    }
                }
            }
            shifted += usize::from(moved);
        }
    }
    shifted
}

#[cfg(test)]
mod tests {
    use super::*;
    use dpdnl::io::lammps_log::NeighborSettings;

    fn summary(every: u64, delay: u64, dangerous: u64) -> NeighborSummary {
        NeighborSummary {
            settings: vec![NeighborSettings {
                every,
                delay,
                check: true,
            }],
            dangerous: vec![Some(dangerous)],
        }
    }

    /// Late builds (delay 10) may miss pairs and the verdict says so; with lists checked every
    /// step LAMMPS's count only means consecutive rebuilds, and the verdict must not blame it.
    #[test]
    fn dangerous_builds_blamed_only_when_lists_were_not_checked_every_step() {
        let late = differ_verdict("thermo", 1e-9, &summary(1, 10, 2), &Growth::Agree);
        assert!(late.contains("so it missed pairs"), "{late}");
        let checked = differ_verdict("thermo", 1e-9, &summary(1, 0, 290), &Growth::Agree);
        assert!(checked.contains("not missed pairs"), "{checked}");
        assert!(!checked.contains("so it missed pairs"), "{checked}");
    }

    /// The leak notes come from the engines' own end-of-run warnings (the words of
    /// `dpdnl::engine::lees_edwards::flip_leak_warning`), summed over runs, with the last V;
    /// nothing without a warning, and nothing for `fix flip/momentum`'s own line.
    #[test]
    fn flip_leak_notes_read_the_warnings() {
        use dpdnl::engine::lees_edwards::{FlipLeak, flip_jump_note, flip_leak_warning};
        let w = |atoms, momentum| {
            let leak = FlipLeak {
                atoms,
                momentum,
                conserved: false,
            };
            format!("WARNING: {}", flip_leak_warning(&leak, 400.0).unwrap())
        };
        let jumped = flip_jump_note(&FlipLeak {
            atoms: 3,
            momentum: 0.0,
            conserved: true,
        })
        .unwrap();
        let lmp = format!(
            "Step Temp\n{}\nLoop time\n{} (src/fix.cpp:12)\n",
            w(2, -60.0),
            w(1, 30.0)
        );
        let notes = flip_leak_notes(&jumped, &lmp);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(
            notes[0].starts_with("LAMMPS: box flips put 3 atom(s)"),
            "{notes:?}"
        );
        assert!(
            notes[0].contains("(V = 0.075 in its last run)"),
            "{notes:?}"
        );
        assert!(flip_leak_notes("", &jumped).is_empty());
    }
}
