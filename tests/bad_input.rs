//! Bad input next to its message, in both engines (`tests/data/bad_input/cases.txt`): every case
//! runs in the standalone engine (in process) and in LAMMPS (`build/lmp_dpdnl`, and LAMMPS
//! 22 Jul 2025 with `build/dpdnlplugin.so` when the plugin is built). Both must give the same
//! verdict, and a refusal must carry the case's expected text in both engines' messages.
//!
//! Without `build/lmp_dpdnl` only the standalone half runs (with a SKIPPED note) unless
//! DPDNL_REQUIRE_LAMMPS is set, in which case the test fails; likewise DPDNL_REQUIRE_PLUGIN.
//!
//! The manual's troubleshooting page, `docs/manual/troubleshooting.md`, is generated from the
//! same table: every refused case with its class, the standalone engine's message (run here),
//! its `cause:` and `cure:`. `troubleshooting_page_is_the_table` fails when the committed page
//! differs from what the table and the code give now; `DPDNL_BLESS=1` rewrites it.

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
    /// The troubleshooting page's annotations (`class:`, `cause:`, `cure:`; every refused case
    /// has them): the section it goes in, why the input is refused, what to do.
    class: Option<String>,
    cause: Option<String>,
    cure: Option<String>,
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
                class: None,
                cause: None,
                cure: None,
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
            } else if let Some(e) = line.strip_prefix("class: ") {
                c.class = Some(e.to_string());
            } else if let Some(e) = line.strip_prefix("cause: ") {
                c.cause = Some(e.to_string());
            } else if let Some(e) = line.strip_prefix("cure: ") {
                c.cure = Some(e.to_string());
            } else if !line.trim().is_empty() && !line.starts_with('#') {
                // ('#' lines are the table's comments, between cases.)
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

/// The standalone engine's message for a refused case, as `dpdnl run` prints it, with the
/// script's name and line as placeholders and the repository's test-data folders left out of
/// file names.
fn message(case: &Case, data: &Path) -> String {
    let e = common::run(&script(case, data)).expect_err("a refused case");
    let root = plugin_support::root();
    let mut m = format!("ERROR: SCRIPT:LINE: {}: {}", e.command, e.message);
    for dir in ["tests/data/bad_input", "tests/data/crosscheck"] {
        m = m.replace(&format!("{}/", root.join(dir).display()), "");
    }
    m
}

/// mdBook's id of a heading (`normalize_id`): alphanumerics, `_` and `-` kept (ASCII lower
/// case), white space to `-`, the rest dropped.
fn anchor(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c.to_ascii_lowercase())
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// The troubleshooting page, from the table.
fn troubleshooting_page(cases: &[Case], data: &Path) -> String {
    let mut classes: Vec<&str> = Vec::new();
    for c in cases.iter().filter(|c| c.expect.is_some()) {
        let class = c.class.as_deref().unwrap();
        if !classes.contains(&class) {
            classes.push(class);
        }
    }
    let mut p = String::from(
        "# Troubleshooting\n\n\
         <!-- Generated by tests/bad_input.rs from tests/data/bad_input/cases.txt: do not edit; \
         `DPDNL_BLESS=1 cargo test --test bad_input troubleshooting` rewrites it. -->\n\n\
         Each error below is a case of the test suite's bad-input table \
         (`tests/data/bad_input/cases.txt`), which `tests/bad_input.rs` runs in the standalone \
         engine and in LAMMPS with this project's styles (`build/lmp_dpdnl`, and the plugin in \
         LAMMPS 22 Jul 2025): both engines must refuse it, and with the same message (one Rust \
         function words it for both). This page is generated from that table, and the test \
         fails when the page differs from what the table and the code give, so a message here \
         is the one the code prints.\n\n\
         A case is the lines it adds to a script that begins\n\n\
         ```lammps\n\
         units           lj\n\
         atom_style      atomic\n\
         comm_modify     vel yes\n\
         read_data       dpd3d.data\n\
         mass            * 1.0\n\
         ```\n\n\
         (500 atoms of 2 types in a box from −2.5 to 2.5 along x, y and z; the bonded cases read \
         their own data file). The standalone engine prints `ERROR: SCRIPT:LINE: COMMAND: \
         MESSAGE`, naming your script and its line; LAMMPS prints the same message after its \
         own words (`ERROR: Illegal pair_style dpd/nonlinear command: MESSAGE`), except for \
         LAMMPS's own commands, whose wording the case gives.\n\n",
    );
    for class in &classes {
        p += &format!("- [{class}](#{})\n", anchor(class));
    }
    for class in &classes {
        p += &format!("\n## {class}\n");
        for c in cases
            .iter()
            .filter(|c| c.expect.is_some() && c.class.as_deref() == Some(*class))
        {
            p += &format!("\n### {}\n\n", c.label);
            if let Some((file, style)) = &c.data {
                p += &format!(
                    "With `atom_style {style}` and `read_data {file}` instead of the lines \
                     above{}:\n\n",
                    if c.body.is_empty() {
                        ", nothing more"
                    } else {
                        ", then"
                    }
                );
            }
            if !c.body.is_empty() {
                p += &format!("```lammps\n{}```\n\n", c.body);
            }
            p += &format!("```text\n{}\n```\n\n", message(c, data));
            match c.lammps.as_deref() {
                Some("ok") => {
                    p += "LAMMPS runs this one (see the heading); the standalone engine refuses \
                          it.\n\n"
                }
                Some(t) => {
                    let words: Vec<String> = t.split(" || ").map(|w| format!("`{w}`")).collect();
                    p += &format!("LAMMPS's words: {}.\n\n", words.join(" or "))
                }
                None => {}
            }
            p += &format!(
                "**Cause.** {}\n\n**Cure.** {}\n",
                c.cause.as_deref().unwrap(),
                c.cure.as_deref().unwrap()
            );
        }
    }
    let ok: Vec<&Case> = cases.iter().filter(|c| c.expect.is_none()).collect();
    p += "\n## Borderline input that runs\n\nThe table also holds input near a limit that \
          both engines accept:\n\n";
    for c in ok {
        p += &format!("- {}\n", c.label);
    }
    p
}

#[test]
fn troubleshooting_page_is_the_table() {
    let root = plugin_support::root();
    let data = root.join("tests/data/crosscheck/dpd3d.data");
    let cases = cases();
    for c in &cases {
        let annotated = [&c.class, &c.cause, &c.cure].iter().all(|a| a.is_some());
        if c.expect.is_some() {
            assert!(
                annotated,
                "case '{}': a refused case needs class:, cause: and cure: lines (the \
                 troubleshooting page shows them)",
                c.label
            );
        }
    }
    let page = troubleshooting_page(&cases, &data);
    let path = root.join("docs/manual/troubleshooting.md");
    if std::env::var_os("DPDNL_BLESS").is_some() {
        std::fs::write(&path, &page).expect("write the troubleshooting page");
        eprintln!("wrote {}", path.display());
        return;
    }
    let old = std::fs::read_to_string(&path).unwrap_or_default();
    if old != page {
        let line = old
            .lines()
            .zip(page.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(old.lines().count().min(page.lines().count()));
        panic!(
            "docs/manual/troubleshooting.md is not what tests/data/bad_input/cases.txt and the \
             code give now (first difference at line {}); regenerate it: DPDNL_BLESS=1 cargo test \
             --test bad_input troubleshooting",
            line + 1
        );
    }
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
        // `A || B`: LAMMPS's builds word it differently (Debian's lacks some packages).
        (Err(e), Some(want)) if want.split(" || ").any(|w| e.contains(w)) => {}
        (Ok(()), Some(want)) => bad.push(format!("{label}: {engine} accepted it (want '{want}')")),
        (Err(e), Some(want)) => bad.push(format!("{label}: {engine} said '{e}', want '{want}'")),
        (Err(e), None) => bad.push(format!("{label}: {engine} refused it: {e}")),
    }
}

/// One case through every engine: its disagreements, engine by engine (standalone, lmp_dpdnl,
/// plugin). `k` numbers the case's input files in the work directories.
fn case_disagreements(
    k: usize,
    c: &Case,
    data: &Path,
    tmp: &Path,
    shim: Option<&Path>,
    plugin: Option<&plugin_support::PluginLammps>,
) -> Vec<String> {
    let mut bad = Vec::new();
    let text = script(c, data);
    let v = standalone(&text);
    check(&c.label, "standalone", &v, &c.expect, &mut bad);
    // `lammps: ok`: LAMMPS runs what this engine refuses (documented in the case).
    let lammps_expect = match c.lammps.as_deref() {
        Some("ok") => None,
        Some(t) => Some(t.to_string()),
        None => c.expect.clone(),
    };
    if let Some(lmp) = shim {
        let mut cmd = Command::new(lmp);
        cmd.env("OMP_NUM_THREADS", "1");
        let w = lammps(cmd, &tmp.join("shim"), &format!("case{k}"), &text);
        check(&c.label, "LAMMPS (lmp_dpdnl)", &w, &lammps_expect, &mut bad);
    }
    if let Some(p) = plugin {
        let w = lammps(p.command(), &tmp.join("plugin"), &format!("case{k}"), &text);
        check(
            &c.label,
            "LAMMPS 22Jul2025 + plugin",
            &w,
            &lammps_expect,
            &mut bad,
        );
    }
    bad
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
    // Each case is three short runs, and most of their time is LAMMPS starting, which waits more
    // than it computes (MPI's start-up: about 0.2 s of CPU in 0.5 s per case in CI): the cases
    // are shared out over two workers per core, and the disagreements reported in the table's
    // order whatever the order the cases finished in.
    let workers = 2 * std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut per_case: Vec<Vec<String>> = vec![Vec::new(); cases.len()];
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(c) = cases.get(k) else { break done };
                        let bad =
                            case_disagreements(k, c, &data, &tmp, shim.as_deref(), plugin.as_ref());
                        done.push((k, bad));
                    }
                })
            })
            .collect();
        for h in handles {
            for (k, bad) in h.join().expect("a bad-input worker") {
                per_case[k] = bad;
            }
        }
    });
    let bad: Vec<String> = per_case.into_iter().flatten().collect();
    let refused = cases.iter().filter(|c| c.expect.is_some()).count();
    let accepted = cases.len() - refused;
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
