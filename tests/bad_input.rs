//! Bad input next to its message, in both engines (`tests/data/bad_input/cases.txt`): every case
//! runs in the standalone engine (in process) and in LAMMPS (`build/lmp_dpdnl`, and LAMMPS
//! 22 Jul 2025 with `build/dpdnlplugin.so` when the plugin is built). Both must give the same
//! verdict, and a refusal must carry the case's expected text in both engines' messages.
//!
//! Without `build/lmp_dpdnl` only the standalone half runs (with a SKIPPED note) unless
//! DPDNL_REQUIRE_LAMMPS is set, in which case the test fails; likewise DPDNL_REQUIRE_PLUGIN.

mod common;
mod plugin_support;

use std::path::Path;
use std::process::Command;

struct Case {
    label: String,
    /// None: the script must run.
    expect: Option<String>,
    /// LAMMPS's own text, for a command LAMMPS implements itself (`lammps:` line); else the
    /// same text as `expect` (this project's styles: one message for both engines).
    lammps: Option<String>,
    /// `data: FILE STYLE [KEYWORDS…]`: read this file of `tests/data/bad_input/` with this atom
    /// style (and these `read_data` keywords) instead of the prelude's `atomic` dpd3d.data.
    data: Option<(String, String)>,
    /// `before: LINE` lines: commands placed before the prelude's `read_data` (a `pair_style`
    /// or `bond_style` for the data file's coefficient sections).
    before: String,
    body: String,
}

fn cases() -> Vec<Case> {
    let path = plugin_support::root().join("tests/data/bad_input/cases.txt");
    let text = std::fs::read_to_string(&path).expect("tests/data/bad_input/cases.txt");
    let mut out: Vec<Case> = Vec::new();
    for line in text.lines() {
        if let Some(label) = line.strip_prefix("== ") {
            out.push(Case {
                label: label.to_string(),
                expect: None,
                lammps: None,
                data: None,
                before: String::new(),
                body: String::new(),
            });
        } else if let Some(c) = out.last_mut() {
            if let Some(e) = line.strip_prefix("expect: ") {
                c.expect = (e != "ok").then(|| e.to_string());
            } else if let Some(e) = line.strip_prefix("lammps: ") {
                c.lammps = Some(e.to_string());
            } else if let Some(e) = line.strip_prefix("before: ") {
                c.before.push_str(e);
                c.before.push('\n');
            } else if let Some(e) = line.strip_prefix("data: ") {
                let (file, style) = e.split_once(' ').expect("data: FILE STYLE [KEYWORDS]");
                c.data = Some((file.to_string(), style.to_string()));
            } else if !line.trim().is_empty() {
                c.body.push_str(line);
                c.body.push('\n');
            }
        }
    }
    out
}

fn script(case: &Case, data: &Path) -> String {
    let (data, style) = match &case.data {
        Some((file, style)) => (
            plugin_support::root()
                .join("tests/data/bad_input")
                .join(file),
            style.as_str(),
        ),
        None => (data.to_path_buf(), "atomic"),
    };
    let (style, keywords) = style.split_once(' ').unwrap_or((style, ""));
    format!(
        "units lj\natom_style {style}\ncomm_modify vel yes\n{}read_data {} {keywords}\nmass * 1.0\n{}",
        case.before,
        data.display(),
        case.body
    )
}

/// The verdict of one engine: Ok, or Err with the error text.
type Verdict = Result<(), String>;

fn standalone(text: &str) -> Verdict {
    common::run(text).map(|_| ()).map_err(|e| e.to_string())
}

/// Run `text` with `cmd` (a LAMMPS) in `dir`; its ERROR line on failure.
fn lammps(mut cmd: Command, dir: &Path, name: &str, text: &str) -> Verdict {
    std::fs::create_dir_all(dir).expect("work dir");
    let input = dir.join(format!("{name}.in"));
    std::fs::write(&input, text).expect("write input");
    let out = cmd
        .current_dir(dir)
        .arg("-in")
        .arg(&input)
        .arg("-log")
        .arg("none")
        .output();
    let out = out.expect("LAMMPS starts");
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    match all.lines().find(|l| l.contains("ERROR")) {
        Some(e) => Err(e.to_string()),
        None if out.status.success() => Ok(()),
        None => Err(format!(
            "exit {:?} without an ERROR line: {all}",
            out.status
        )),
    }
}

fn check(label: &str, engine: &str, v: &Verdict, expect: &Option<String>, bad: &mut Vec<String>) {
    match (v, expect) {
        (Ok(()), None) => {}
        (Err(e), Some(want)) if e.contains(want.as_str()) => {}
        (Ok(()), Some(want)) => bad.push(format!("{label}: {engine} accepted it (want '{want}')")),
        (Err(e), Some(want)) => bad.push(format!("{label}: {engine} said '{e}', want '{want}'")),
        (Err(e), None) => bad.push(format!("{label}: {engine} refused it: {e}")),
    }
}

#[test]
fn same_verdict_and_message_in_both_engines() {
    let root = plugin_support::root();
    let data = root.join("tests/data/crosscheck/dpd3d.data");
    let cases = cases();
    assert!(
        cases.len() >= 20,
        "expected the table, found {}",
        cases.len()
    );
    let tmp = std::env::temp_dir().join(format!("dpdnl-bad-input-{}", std::process::id()));
    let shim = plugin_support::lmp_dpdnl("the LAMMPS half of the bad-input table");
    let plugin = plugin_support::find();
    let mut bad = Vec::new();
    let (mut refused, mut accepted) = (0, 0);
    for (k, c) in cases.iter().enumerate() {
        let text = script(c, &data);
        let v = standalone(&text);
        check(&c.label, "standalone", &v, &c.expect, &mut bad);
        // `lammps: ok`: LAMMPS runs what this engine refuses (documented in the case).
        let lammps_expect = match c.lammps.as_deref() {
            Some("ok") => None,
            Some(t) => Some(t.to_string()),
            None => c.expect.clone(),
        };
        if let Some(lmp) = &shim {
            let mut cmd = Command::new(lmp);
            cmd.env("OMP_NUM_THREADS", "1");
            let w = lammps(cmd, &tmp.join("shim"), &format!("case{k}"), &text);
            check(&c.label, "LAMMPS (lmp_dpdnl)", &w, &lammps_expect, &mut bad);
        }
        if let Some(p) = &plugin {
            let w = lammps(p.command(), &tmp.join("plugin"), &format!("case{k}"), &text);
            check(
                &c.label,
                "LAMMPS 22Jul2025 + plugin",
                &w,
                &lammps_expect,
                &mut bad,
            );
        }
        if c.expect.is_some() {
            refused += 1;
        } else {
            accepted += 1;
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    eprintln!(
        "bad-input table: {refused} refused and {accepted} accepted cases, engines: standalone{}{}",
        if shim.is_some() { ", lmp_dpdnl" } else { "" },
        if plugin.is_some() { ", plugin" } else { "" }
    );
    assert!(
        bad.is_empty(),
        "{} disagreements:\n{}",
        bad.len(),
        bad.join("\n")
    );
}
