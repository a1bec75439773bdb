//! What cannot be right is refused (issue 16): blow-ups stop the run naming step, atom and
//! quantity; a set-up that cannot fit in memory is refused before allocating; trailing words are
//! errors; `create_atoms single` outside the box creates nothing (as LAMMPS).

mod common;

use common::run;

const HEAD: &str =
    "units lj\natom_style atomic\nregion box block 0 4 0 4 0 4\ncreate_box 1 box\nmass 1 1.0\n";

/// The reproduction of the issue: a = 1000 with δt = 5 used to run to the end with T = 9e36.
#[test]
fn a_blow_up_stops_the_run_with_step_atom_and_quantity() {
    let script = format!(
        "{HEAD}create_atoms 1 random 256 7 box\nvelocity all create 1.0 5 mom yes\n\
         pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 1000 4.5 0\ntimestep 5\n\
         fix 1 all nve\nthermo 1000\nrun 1000\n"
    );
    let err = run(&script).expect_err("a blow-up must stop the run");
    assert_eq!(err.command, "run", "{err}");
    assert!(err.message.starts_with("blow-up at step "), "{err}");
    assert!(err.message.contains("atom "), "{err}");
    // It is caught long before the end: the first check after the set-up is step 100 at the
    // latest (here the set-up check itself or the first thermo/100-step check).
    let step: u64 = err.message["blow-up at step ".len()..]
        .split(':')
        .next()
        .and_then(|s| s.parse().ok())
        .expect("a step number");
    assert!(step <= 100, "{err}");
}

#[test]
fn a_healthy_run_passes_the_checks() {
    let script = format!(
        "{HEAD}create_atoms 1 random 256 7 box\nvelocity all create 1.0 5 mom yes\n\
         pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 25 4.5 0\ntimestep 0.01\n\
         fix 1 all nve\nthermo 50\nrun 250\n"
    );
    run(&script).expect("an ordinary fluid runs");
}

#[test]
fn a_set_up_too_large_for_memory_is_refused_before_allocating() {
    if std::fs::read_to_string("/proc/meminfo").is_err() {
        eprintln!("SKIPPED: no /proc/meminfo");
        return;
    }
    let script = format!("{HEAD}create_atoms 1 random 1000000000000 7 box\n");
    let err = run(&script).expect_err("10^12 atoms cannot fit");
    assert_eq!(err.command, "create_atoms");
    assert!(
        err.message.contains("atoms need at least") && err.message.contains("GB available"),
        "{err}"
    );
}

#[test]
fn trailing_words_are_errors() {
    let cases = [
        "timestep 0.01 0.02",
        "mass 1 1.0 2.0",
        "thermo 10 20",
        "neighbor 0.3 bin extra",
        "units lj extra",
        "reset_timestep 0 1",
        "create_atoms 1 single 1 1 1 extra",
    ];
    for c in cases {
        let err = run(&format!("{HEAD}{c}\n")).expect_err(c);
        assert!(
            err.message.contains("unexpected argument"),
            "{c}: {}",
            err.message
        );
    }
    let err = run("units lj\nregion box block 0 4 0 4 0 4\ncreate_box 1 box extra\n")
        .expect_err("create_box with a trailing word");
    assert!(err.message.contains("unexpected argument 'extra'"), "{err}");
}

#[test]
fn create_atoms_single_outside_the_box_creates_none() {
    let script = format!("{HEAD}create_atoms 1 single 5.0 1 1\ncreate_atoms 1 single 1 1 1\n");
    let (lines, sys) = run(&script).expect("runs");
    assert!(lines.iter().any(|l| l == "Created 0 atoms"), "{lines:?}");
    assert!(lines.iter().any(|l| l == "Created 1 atoms"), "{lines:?}");
    assert_eq!(sys.expect("system").atoms.len(), 1);
}

/// A missing `include` file is an error of the including line: its file and line number and the
/// missing name (was: the missing file's name at line 0).
#[test]
fn a_missing_include_names_the_including_line() {
    let Err(e) = run("units lj\n\ninclude no_such_file.in\n") else {
        panic!("accepted")
    };
    let e = e.to_string();
    assert!(
        e.starts_with("test.in:3: include:") && e.contains("cannot read 'no_such_file.in'"),
        "{e}"
    );
}
