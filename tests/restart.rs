//! Exact restart (issue 16, "Build"): `run 50` + `run 50` in one interpreter gives the same bits
//! as `run 50` + `write_restart`, then `read_restart` + `run 50` in a fresh one, for
//! velocity-Verlet and Euler, periodic and Lees–Edwards boxes, a bonded polymer solution
//! (topology, molecule ids, FENE and cosine styles, fractional special_bonds), 1 and 2 threads,
//! with `fix pex/push`; periodic `restart N FILE` (names with `*`, two alternating files) and the
//! file written at an interrupt; and refusals of corrupted, truncated, foreign and newer files with the file, line and command.

use dpdnl::engine::System;
use dpdnl::input::{Collect, Interpreter, Options, ScriptError};
use dpdnl::io::restart;
use std::path::{Path, PathBuf};

mod common;
use common::state_by_tag;

/// A scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("dpdnl-restart-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// One test system: `system` builds the box, atoms and pair style (what a restart file holds);
/// `settings` are the fixes, computes and thermo lines a script re-issues after `read_restart`.
struct Case {
    name: &'static str,
    system: String,
    settings: String,
}

/// A 3-D periodic fluid of two types (unequal masses, two cut-offs, dot friction with two-step
/// noise), skin 0.5 (not the default: the restart must carry it), PeX pushes every 5 steps.
fn periodic(integrator: &str) -> Case {
    Case {
        name: if integrator == "nve" {
            "periodic nve"
        } else {
            "periodic nve/euler"
        },
        system: "units lj\natom_style atomic\nregion box block 0 7 0 7 0 7\ncreate_box 2 box\n\
                 create_atoms 1 random 700 4242 box\ncreate_atoms 2 random 330 4343 box\n\
                 mass 1 1.0\nmass 2 2.5\nvelocity all create 1.0 87287 mom yes\n\
                 pair_style dpd/nonlinear 1.0 1.0 9898 friction dot noise twostep\n\
                 pair_coeff * * 25.0 4.5 0.5\npair_coeff 1 2 30.0 3.0 0.2 0.9\n\
                 neighbor 0.5 bin\ntimestep 0.01\n"
            .into(),
        settings: format!(
            "fix 1 all {integrator}\nfix push all pex/push 0.05 every 5\nthermo 10\n\
             thermo_style custom step temp press pxy ke pe f_push\n\
             thermo_modify format float %.17g\n"
        ),
    }
}

/// A Lees–Edwards (triclinic, `fix deform … remap v`) fluid; 2-D or 3-D (the 3-D pair
/// coefficients from (η, Sc) targets, resolved again at every set-up).
fn lees_edwards(integrator: &str, dim: u32) -> Case {
    let (name, z, n, coeff, extra) = match (integrator, dim) {
        ("nve", 2) => (
            "Lees-Edwards 2-D nve",
            "-0.5 0.5",
            400,
            "10.0 4.5 0.3",
            "fix 2 all enforce2d\n",
        ),
        _ => (
            "Lees-Edwards 3-D nve/euler",
            "0 5",
            500,
            "10.0 eta 0.3 sc 1.5 gamma1 0.3",
            "",
        ),
    };
    Case {
        name,
        system: format!(
            "units lj\ndimension {dim}\natom_style atomic\n\
             region box prism 0 10 0 10 {z} 0 0 0\ncreate_box 1 box\n\
             create_atoms 1 random {n} 8675 box\nmass 1 1.0\n\
             velocity all create 1.0 4928 mom yes dist gaussian\n\
             pair_style dpd/nonlinear 1.0 1.0 34387 friction cross\n\
             pair_coeff 1 1 {coeff}\n\
             timestep 0.01\nvelocity all ramp vx 0.0 5.0 y 0 10 sum yes units box\n"
        ),
        settings: format!(
            "fix 1 all {integrator}\n{extra}fix 3 all deform 1 xy erate 0.5 remap v\n\
             compute tdef all temp/deform\ncompute pdef all pressure tdef\nthermo 10\n\
             thermo_style custom step temp press pxy xy\nthermo_modify temp tdef\n\
             thermo_modify format float %.17g\n"
        ),
    }
}

/// A 2-D `pair_style sdpd` fluid (proposed kernel designed from (η, Sc) targets, resolved again
/// at every set-up): the density pass and the per-atom state of a many-body style.
fn sdpd() -> Case {
    Case {
        name: "sdpd 2-D nve",
        system: "units lj\ndimension 2\natom_style atomic\n\
                 region box block 0 12 0 12 -0.5 0.5\ncreate_box 1 box\n\
                 create_atoms 1 random 576 8675 box\nmass 1 1.0\n\
                 velocity all create 1.0 4928 mom yes dist gaussian\n\
                 pair_style sdpd 1.0 2.0 34387 kernel proposed 1\n\
                 pair_coeff 1 1 4.0 8.0 eta 8 sc 60\ntimestep 0.005\n"
            .into(),
        settings: "fix 1 all nve\nfix 2 all enforce2d\nthermo 10\n\
                   thermo_style custom step temp press pxy ke pe\n\
                   thermo_modify format float %.17g\n"
            .into(),
    }
}

/// The polymer solution of the bonded golden cases: bonds and angles through the periodic
/// boundaries, molecule ids, fractional special_bonds (scaled coefficient blocks) and FENE
/// bonds with cosine angles: everything of the topology the restart file carries.
fn bonded() -> Case {
    Case {
        name: "bonded 3-D nve",
        system: format!(
            "units lj\natom_style angle\nbond_style fene\nangle_style cosine\n\
             special_bonds lj 0.5 0.75 1 angle yes\nread_data {}/tests/data/crosscheck/polymer3d.data\n\
             mass 1 1.0\nmass 2 1.5\n\
             pair_style dpd/nonlinear 1.0 1.0 7919 friction dot noise twostep\n\
             pair_coeff * * 25.0 4.5 0.5\nbond_coeff 1 30.0 1.5 1.0 1.0\nangle_coeff 1 2.0\n\
             timestep 0.01\n",
            env!("CARGO_MANIFEST_DIR")
        ),
        settings: "fix 1 all nve\nthermo 10\n\
                   thermo_style custom step temp press pxy pe ebond eangle\n\
                   thermo_modify format float %.17g\n"
            .into(),
    }
}

fn cases() -> Vec<Case> {
    vec![
        bonded(),
        periodic("nve"),
        periodic("nve/euler"),
        lees_edwards("nve", 2),
        lees_edwards("nve/euler", 3),
        sdpd(),
    ]
}

/// Run `text` in a fresh interpreter on a pool of `threads` threads: console lines and system.
fn run_on(threads: usize, text: &str) -> Result<(Vec<String>, System), ScriptError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let (lines, sys) = common::run(text)?;
        Ok((lines, sys.expect("a system")))
    })
}

/// The thermo rows of the last run in `lines` (header to "Loop time").
fn last_run_rows(lines: &[String]) -> Vec<String> {
    let start = lines
        .iter()
        .rposition(|l| l.split_whitespace().next() == Some("Step"))
        .expect("a thermo header");
    lines[start..]
        .iter()
        .take_while(|l| !l.starts_with("Loop time"))
        .cloned()
        .collect()
}

/// What must agree bit for bit: atoms by tag (x, v bits), image flags, step, PeX totals, tilt,
/// and the last run's thermo rows (printed with %.17g).
#[derive(Debug, PartialEq)]
struct Outcome {
    atoms: Vec<(u32, [u64; 3], [u64; 3])>,
    images: Vec<(u32, [i32; 3])>,
    step: u64,
    pex: Vec<u64>,
    xy: Option<u64>,
    rows: Vec<String>,
}

fn outcome(lines: &[String], sys: &System) -> Outcome {
    let mut images: Vec<_> = (0..sys.atoms.len())
        .map(|i| (sys.atoms.tag[i], sys.atoms.image[i]))
        .collect();
    images.sort();
    Outcome {
        atoms: state_by_tag(sys),
        images,
        step: sys.step,
        pex: sys.pex.iter().map(|p| p.total.to_bits()).collect(),
        xy: sys.tri.as_ref().map(|t| t.xy.to_bits()),
        rows: last_run_rows(lines),
    }
}

/// One process: `run 50` twice.
fn continuous(c: &Case, threads: usize) -> Outcome {
    let text = format!("{}{}run 50\nrun 50\n", c.system, c.settings);
    let (lines, sys) = run_on(threads, &text).expect("continuous run");
    outcome(&lines, &sys)
}

/// Two interpreters: `run 50` + `write_restart`, then `read_restart` + the settings + `run 50`.
fn restarted(c: &Case, file: &Path, write_threads: usize, read_threads: usize) -> Outcome {
    let f = file.display();
    let first = format!("{}{}run 50\nwrite_restart {f}\n", c.system, c.settings);
    run_on(write_threads, &first).expect("first half");
    let second = format!("read_restart {f}\n{}run 50\n", c.settings);
    let (lines, sys) = run_on(read_threads, &second).expect("second half");
    outcome(&lines, &sys)
}

#[test]
fn restart_continues_bit_for_bit() {
    let dir = scratch("bits");
    for c in cases() {
        let reference = continuous(&c, 1);
        assert_eq!(reference.step, 100);
        assert!(
            reference.rows.len() >= 6,
            "{}: {:?}",
            c.name,
            reference.rows
        );
        if c.name.starts_with("periodic") {
            assert!(reference.pex[0] != 0f64.to_bits(), "{}: PeX pushed", c.name);
        } else if c.name.starts_with("Lees") {
            assert!(reference.xy.is_some_and(|b| f64::from_bits(b) > 4.0));
        }
        for (w, r) in [(1, 1), (2, 2), (1, 2)] {
            let file = dir.join(format!(
                "{}.{w}{r}.restart",
                c.name.replace([' ', '/'], "_")
            ));
            let got = restarted(&c, &file, w, r);
            assert_eq!(
                got, reference,
                "{}: written on {w} thread(s), continued on {r}",
                c.name
            );
        }
        assert_eq!(continuous(&c, 2), reference, "{}: 2 threads", c.name);
    }
}

/// `restart N FILE*` writes at multiples of N during a run; continuing from the file of step 40
/// is the run split at step 40.
#[test]
fn periodic_restart_files_continue_exactly() {
    let dir = scratch("periodic");
    let c = periodic("nve");
    let pattern = dir.join("state.*.restart");
    let text = format!(
        "{}{}restart 20 {}\nrun 50\n",
        c.system,
        c.settings,
        pattern.display()
    );
    run_on(2, &text).expect("run with restart files");
    let mut written: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(
        written,
        ["state.20.restart", "state.40.restart"],
        "one file per multiple of 20, no temporary file left behind"
    );
    let second = format!(
        "read_restart {}\n{}run 10\n",
        dir.join("state.40.restart").display(),
        c.settings
    );
    let (lines, sys) = run_on(1, &second).expect("continued");
    let split = format!("{}{}run 40\nrun 10\n", c.system, c.settings);
    let (ref_lines, ref_sys) = run_on(1, &split).expect("split run");
    assert_eq!(outcome(&lines, &sys), outcome(&ref_lines, &ref_sys));
}

/// `restart N A B` alternates between A and B (no `*`: each is overwritten); `restart 0` stops.
#[test]
fn two_restart_files_alternate() {
    let dir = scratch("toggle");
    let c = periodic("nve");
    let (a, b) = (dir.join("a.restart"), dir.join("b.restart"));
    let text = format!(
        "{}{}restart 10 {} {}\nrun 30\nrestart 0\nrun 20\n",
        c.system,
        c.settings,
        a.display(),
        b.display()
    );
    run_on(1, &text).expect("runs");
    let step = |p: &Path| restart::read(p).expect("a restart file").step;
    assert_eq!((step(&a), step(&b)), (30, 20));
}

/// The state of a fix is restored only into a fix of the same ID and style; unclaimed state is
/// dropped with a warning at the next run.
#[test]
fn fix_state_needs_the_same_id_and_style() {
    let dir = scratch("fixstate");
    let c = periodic("nve");
    let file = dir.join("s.restart");
    let first = format!(
        "{}{}run 20\nwrite_restart {}\n",
        c.system,
        c.settings,
        file.display()
    );
    let (_, before) = run_on(1, &first).expect("first");
    let total = before.pex[0].total;
    assert!(total > 0.0);
    let f = file.display();
    let (lines, sys) = run_on(
        1,
        &format!("read_restart {f}\nfix 1 all nve\nfix push all pex/push 0.05 every 5\nrun 0\n"),
    )
    .expect("same id and style");
    assert_eq!(sys.pex[0].total.to_bits(), total.to_bits());
    assert!(
        lines
            .iter()
            .any(|l| l.contains("fix push pex/push: state restored"))
    );
    let (lines, sys) = run_on(
        1,
        &format!("read_restart {f}\nfix 1 all nve\nfix other all pex/push 0.05\nrun 0\n"),
    )
    .expect("another id");
    assert_eq!(sys.pex[0].total, 0.0);
    assert!(
        lines.iter().any(|l| l.starts_with("WARNING:")
            && l.contains("the state of fix push pex/push is not used")),
        "{lines:?}"
    );
}

/// `read_restart` restores the pair style and coefficients without the script re-issuing them,
/// and the file keeps atoms in their storage order (not sorted by id).
#[test]
fn the_file_holds_the_system_in_storage_order() {
    let dir = scratch("order");
    let c = periodic("nve");
    let file = dir.join("o.restart");
    let text = format!(
        "{}{}run 30\nwrite_restart {}\n",
        c.system,
        c.settings,
        file.display()
    );
    let (_, sys) = run_on(1, &text).expect("runs");
    let r = restart::read(&file).expect("reads");
    assert_eq!(
        r.atoms, sys.atoms,
        "every atom array, in storage order, bit for bit"
    );
    assert!(
        r.atoms.tag.windows(2).any(|w| w[0] > w[1]),
        "the neighbour sort has reordered the atoms"
    );
    assert_eq!((r.step, r.dt, r.skin, r.ntypes), (30, 0.01, 0.5, 2));
    assert_eq!(r.masses, vec![None, Some(1.0), Some(2.5)]);
    // The style's restart lines (`PairStyle::restart_lines`, the same as LAMMPS's restart of
    // the style): `pair_style` and one `pair_coeff` per type pair of the two types.
    assert_eq!(r.pair.len(), 4);
    assert_eq!(r.pair[0][..2], ["pair_style", "dpd/nonlinear"]);
    assert!(r.pair[1..].iter().all(|l| l[0] == "pair_coeff"));
    assert_eq!(r.fixes.len(), 2);
    assert_eq!(r.fixes[1].words[..3], ["push", "all", "pex/push"]);
    let (_, back) = run_on(1, &format!("read_restart {}\n", file.display())).expect("reads");
    let ff = common::dpd(&back).expect("pair style restored");
    assert_eq!(ff.seed, 9898);
    assert_eq!(ff.get(1, 2).map(|p| p.rc), Some(0.9));
    assert_eq!(back.neighbor.skin, 0.5);
}

/// A console that answers `interrupted` with true from call `after + 1` on.
struct StopAfter {
    calls: usize,
    after: usize,
}

impl dpdnl::input::Console for StopAfter {
    fn line(&mut self, _: &str) {}
    fn interrupted(&mut self) -> bool {
        self.calls += 1;
        self.calls > self.after
    }
}

/// An interrupt writes the restart file of the step reached (the next of two alternating
/// files), unless that step's periodic file was just written; the message names the file.
#[test]
fn an_interrupt_writes_the_restart_file() {
    let dir = scratch("interrupt");
    let c = periodic("nve");
    let (a, b) = (dir.join("a.restart"), dir.join("b.restart"));
    let text = format!(
        "{}{}restart 10 {} {}\nrun 100\n",
        c.system,
        c.settings,
        a.display(),
        b.display()
    );
    // Asked once before the set-up, then after every step: call K + 1 is after step K.
    for (stop, file, other_step) in [(20u64, &b, 10), (25, &a, 20)] {
        let _ = std::fs::remove_file(&a);
        let _ = std::fs::remove_file(&b);
        let mut console = StopAfter {
            calls: 0,
            after: stop as usize,
        };
        let mut interp = Interpreter::new(&mut console, &Options::default()).expect("interp");
        let err = interp.run_text(&text, "in.stop").expect_err("interrupted");
        assert_eq!(
            err.message,
            format!(
                "interrupted at step {stop}; restart file {} written",
                file.display()
            )
        );
        let other = if file == &a { &b } else { &a };
        assert_eq!(restart::read(file).expect("written").step, stop);
        assert_eq!(restart::read(other).expect("written").step, other_step);
    }
}

// ------------------------------------------------------------------------------- refusals

/// `read_restart` of `bytes` (written to a file in `dir`): the error.
fn read_error(dir: &Path, name: &str, bytes: &[u8]) -> ScriptError {
    let file = dir.join(name);
    std::fs::write(&file, bytes).expect("write");
    let mut console = Collect::default();
    let mut interp = Interpreter::new(&mut console, &Options::default()).expect("interpreter");
    let text = format!("read_restart {}\n", file.display());
    let err = interp.run_text(&text, "in.read").expect_err("refused");
    assert_eq!(
        (err.file.as_str(), err.line, err.command.as_str()),
        ("in.read", 1, "read_restart")
    );
    assert!(
        err.message
            .starts_with(&format!("restart file {}: ", file.display())),
        "{err}"
    );
    assert!(interp.system().is_none(), "no half-read system is left");
    err
}

#[test]
fn bad_files_are_refused_with_the_reason() {
    let dir = scratch("bad");
    let c = periodic("nve");
    let good = dir.join("good.restart");
    run_on(
        1,
        &format!(
            "{}{}run 5\nwrite_restart {}\n",
            c.system,
            c.settings,
            good.display()
        ),
    )
    .expect("writes");
    let bytes = std::fs::read(&good).expect("read");

    let mut flipped = bytes.clone();
    flipped[bytes.len() / 2] ^= 0x04;
    let e = read_error(&dir, "flipped.restart", &flipped);
    assert!(e.message.contains("corrupted: checksum mismatch"), "{e}");

    let e = read_error(&dir, "cut.restart", &bytes[..bytes.len() * 2 / 3]);
    assert!(e.message.contains("truncated"), "{e}");
    let e = read_error(&dir, "tiny.restart", &bytes[..5]);
    assert!(e.message.contains("truncated"), "{e}");
    let e = read_error(&dir, "empty.restart", b"");
    assert!(e.message.contains("truncated"), "{e}");

    let e = read_error(&dir, "text.restart", b"LAMMPS data file\n\n10 atoms\n");
    assert!(e.message.contains("not a dpdnl restart file"), "{e}");
    let e = read_error(&dir, "lammps.restart", b"LammpS RestartT\x00\x01\x02\x03");
    assert!(e.message.contains("this is a LAMMPS restart file"), "{e}");

    let mut newer = bytes.clone();
    newer[8..12].copy_from_slice(&7u32.to_le_bytes());
    let e = read_error(&dir, "newer.restart", &newer);
    assert!(
        e.message
            .contains("format version 7 is newer than this dpdnl reads"),
        "{e}"
    );

    // A checksum that matches contents no writer produces.
    let mut odd = restart::decode(&bytes).expect("decodes");
    odd.atoms.typ[3] = 9;
    let e = read_error(&dir, "odd.restart", &restart::encode(&odd));
    assert!(
        e.message.contains("malformed contents: atom ")
            && e.message.contains("has type 9 (types are 1..2)"),
        "{e}"
    );

    let missing = dir.join("missing.restart");
    let mut console = Collect::default();
    let mut interp = Interpreter::new(&mut console, &Options::default()).expect("interpreter");
    let err = interp
        .run_text(&format!("read_restart {}\n", missing.display()), "in.read")
        .expect_err("refused");
    assert!(err.message.contains("cannot read"), "{err}");
}

#[test]
fn commands_are_checked() {
    let dir = scratch("commands");
    let c = periodic("nve");
    let cases = [
        (
            "write_restart\n",
            "missing arguments; usage: write_restart FILE",
        ),
        ("write_restart a b\n", "unexpected argument 'b'"),
        (
            "restart 10\n",
            "missing arguments; usage: restart 0 | restart N FILE [FILE2]",
        ),
        ("restart 0 a\n", "unexpected argument 'a'"),
        (
            "restart x a\n",
            "expected an integer for restart interval N, found 'x'",
        ),
        ("restart 10 a b c\n", "unexpected argument 'c'"),
        (
            "restart 10 a fileper\n",
            "restart keyword 'fileper' not supported",
        ),
        (
            "read_restart x\n",
            "cannot read_restart after the simulation box is defined",
        ),
    ];
    for (line, want) in cases {
        let err = common::run(&format!("{}{line}", c.system)).expect_err(line);
        assert!(err.message.contains(want), "{line}: {err}");
    }
    let nowhere = dir.join("no/such/dir/x.restart");
    let err = common::run(&format!(
        "{}write_restart {}\n",
        c.system,
        nowhere.display()
    ))
    .expect_err("no directory");
    assert!(
        err.message
            .starts_with(&format!("cannot write restart file {}", nowhere.display())),
        "{err}"
    );
}

// ------------------------------------------------------------------------------- the CLI

fn dpdnl(dir: &Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("dpdnl runs")
}

/// Two `dpdnl run` invocations (1 thread, then 2) give the dump of one invocation, at %.17g.
#[test]
fn two_cli_invocations_equal_one() {
    let dir = scratch("cli");
    let c = lees_edwards("nve", 2);
    let dump = "dump d all custom 50 DUMP id type x y vx vy ix iy\n\
                dump_modify d format float %.17g\n";
    let whole = format!(
        "{}{}run 50\n{}run 50\n",
        c.system,
        c.settings,
        dump.replace("DUMP", "whole.dump")
    );
    let first = format!(
        "{}{}run 50\nwrite_restart cli.restart\n",
        c.system, c.settings
    );
    let second = format!(
        "read_restart cli.restart\n{}{}run 50\n",
        c.settings,
        dump.replace("DUMP", "split.dump")
    );
    for (name, text) in [
        ("in.whole", &whole),
        ("in.first", &first),
        ("in.second", &second),
    ] {
        std::fs::write(dir.join(name), text).expect("script");
    }
    for (script, threads) in [("in.whole", "2"), ("in.first", "1"), ("in.second", "2")] {
        let o = dpdnl(
            &dir,
            &["run", script, "--log", "none", "--threads", threads],
        );
        assert!(
            o.status.success(),
            "{script}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let read = |n: &str| std::fs::read_to_string(dir.join(n)).expect("dump");
    let (w, s) = (read("whole.dump"), read("split.dump"));
    assert_eq!(w.matches("ITEM: TIMESTEP").count(), 2);
    assert_eq!(w, s);
}

/// What a restart stores of `pair_coeff … eta E sc S` (issue 42, the pair style's page): the
/// targets, not the γ0 and s resolved from them, in both engines. After `read_restart` and
/// `create_atoms` (density 3 → 4) the next set-up resolves the targets again at the new
/// density: the standalone engine logs γ0 = 429.34… (not the 140.81… of the run that wrote the
/// file), and LAMMPS (`build/lmp_dpdnl`, when built) logs the same line.
#[test]
fn eta_sc_targets_are_stored_and_resolved_again() {
    let dir = scratch("eta_sc_targets");
    let file = dir.join("designed.restart");
    let write = format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\nregion box block 0 6 0 6 0 6\n\
         create_box 1 box\ncreate_atoms 1 random 648 8675 box\nmass 1 1.0\n\
         pair_style dpd/nonlinear 1.0 1.0 34387 friction cross\n\
         pair_coeff 1 1 10.0 eta 0.5 sc 1.5 gamma1 0.3\ntimestep 0.01\nrun 0\n\
         write_restart {}\n",
        file.display()
    );
    let read = format!(
        "units lj\ncomm_modify vel yes\nread_restart {}\ncreate_atoms 1 random 216 99 NULL\nrun 0\n",
        file.display()
    );
    let design = |lines: &[String]| -> Vec<String> {
        lines
            .iter()
            .filter(|l| l.starts_with("pair_coeff 1 1: eta 0.5 sc 1.5 at n = "))
            .cloned()
            .collect()
    };
    let (first, _) = run_on(1, &write).expect("first script");
    let (second, _) = run_on(1, &read).expect("second script");
    let (d1, d2) = (design(&first), design(&second));
    assert_eq!(d1.len(), 1, "{first:#?}");
    assert_eq!(d2.len(), 1, "{second:#?}");
    assert!(
        d1[0].contains("n = 3.0000000000") && d1[0].contains("-> gamma0 = 140.81"),
        "{}",
        d1[0]
    );
    assert!(
        d2[0].contains("n = 4.0000000000") && d2[0].contains("-> gamma0 = 429.34"),
        "{}",
        d2[0]
    );
    let lmp = Path::new(env!("CARGO_MANIFEST_DIR")).join("build/lmp_dpdnl");
    if !lmp.is_file() {
        assert!(
            std::env::var_os("DPDNL_REQUIRE_LAMMPS").is_none(),
            "DPDNL_REQUIRE_LAMMPS is set but {} is missing",
            lmp.display()
        );
        eprintln!("SKIPPED: LAMMPS half: {} not built", lmp.display());
        return;
    }
    let lammps = |name: &str, text: &str| -> Vec<String> {
        std::fs::write(
            dir.join(name),
            text.replace(&*file.to_string_lossy(), "lmp.restart"),
        )
        .expect("write the input");
        let out = std::process::Command::new(&lmp)
            .current_dir(&dir)
            .env("OMP_NUM_THREADS", "1")
            .args(["-in", name, "-log", "none"])
            .output()
            .expect("LAMMPS starts");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success() && !stdout.contains("ERROR"),
            "{stdout}"
        );
        stdout.lines().map(String::from).collect()
    };
    lammps("in.write", &write);
    let l2 = design(&lammps("in.read", &read));
    assert!(
        !l2.is_empty(),
        "no design line from LAMMPS after read_restart"
    );
    assert!(
        l2.iter().all(|l| *l == d2[0]),
        "LAMMPS {l2:?}\nstandalone {d2:?}"
    );
}
