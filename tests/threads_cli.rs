//! `--threads N` of `dpdnl run` and `dpdnl crosscheck` (issue 16, item 4): N above the CPU count
//! (`std::thread::available_parallelism`) is capped at it with a warning naming both numbers,
//! instead of trying to spawn N threads (`--threads 99999999999` used to hang); 0 means one
//! thread per CPU; a count beyond u64 is refused by the argument parser.
//!
//! Each command runs as a child process with a deadline, so a regression fails instead of
//! hanging the test run.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const SCRIPT: &str = "\
units           lj
atom_style      atomic
dimension       2
boundary        p p p
region          box block 0 5 0 5 -0.5 0.5
create_box      1 box
create_atoms    1 random 50 4711 box
mass            1 1.0
pair_style      dpd/nonlinear 1.0 1.0 7919
pair_coeff      1 1 25.0 4.5 0.0
timestep        0.01
fix             1 all nve
thermo          5
run             10
";

struct Out {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs `dpdnl ARGS` in `dir`; panics (after killing it) if it takes longer than 60 s.
fn dpdnl(dir: &Path, args: &[&str]) -> Out {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start dpdnl");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait for dpdnl") {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("dpdnl {args:?} still running after 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stdout = String::new();
    let mut stderr = String::new();
    if let Some(mut o) = child.stdout.take() {
        o.read_to_string(&mut stdout).expect("stdout");
    }
    if let Some(mut e) = child.stderr.take() {
        e.read_to_string(&mut stderr).expect("stderr");
    }
    Out {
        code: status.code(),
        stdout,
        stderr,
    }
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("threads_cli")
        .join(name);
    std::fs::create_dir_all(&d).expect("scratch dir");
    std::fs::write(d.join("in.tiny"), SCRIPT).expect("write script");
    d
}

fn cpus() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The `Loop time of T on P procs` line of a run names the thread count used.
fn procs(stdout: &str) -> usize {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix("Loop time of "))
        .and_then(|l| l.split(" on ").nth(1))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no 'Loop time of … on P procs' line in\n{stdout}"))
}

#[test]
fn run_caps_threads_at_the_cpu_count_with_a_warning() {
    let dir = scratch("run");
    let n = cpus();
    let warning = format!(
        "WARNING: --threads 99999999999 is more than the {n} CPU(s) available to this process; \
         using {n} thread(s)"
    );
    let o = dpdnl(
        &dir,
        &[
            "run",
            "in.tiny",
            "--log",
            "none",
            "--threads",
            "99999999999",
        ],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert!(o.stderr.contains(&warning), "{}", o.stderr);
    assert_eq!(procs(&o.stdout), n);

    let above = (n + 1).to_string();
    let o = dpdnl(
        &dir,
        &["run", "in.tiny", "--log", "none", "--threads", &above],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert!(
        o.stderr
            .contains(&format!("--threads {above} is more than the {n} CPU(s)")),
        "{}",
        o.stderr
    );
    assert_eq!(procs(&o.stdout), n);

    // 0 (the default) is one thread per CPU, 1 is 1: no warning.
    for (arg, want) in [("0", n), ("1", 1)] {
        let o = dpdnl(&dir, &["run", "in.tiny", "--log", "none", "--threads", arg]);
        assert_eq!(o.code, Some(0), "{}", o.stderr);
        assert!(!o.stderr.contains("WARNING"), "{}", o.stderr);
        assert_eq!(procs(&o.stdout), want, "--threads {arg}");
    }

    // Beyond u64 and negative counts are refused by the argument parser (exit 2), at once.
    for bad in ["99999999999999999999999", "-1", "two"] {
        let o = dpdnl(&dir, &["run", "in.tiny", "--log", "none", "--threads", bad]);
        assert_eq!(o.code, Some(2), "{bad}: {}", o.stderr);
        assert!(
            o.stderr
                .contains(&format!("invalid value '{bad}' for '--threads"))
                || o.stderr.contains("unexpected argument"),
            "{bad}: {}",
            o.stderr
        );
    }
}

/// crosscheck reads --threads before it looks for LAMMPS, so this needs no LAMMPS.
#[test]
fn crosscheck_caps_threads_too() {
    let dir = scratch("crosscheck");
    let o = dpdnl(
        &dir,
        &[
            "crosscheck",
            "in.tiny",
            "--lmp",
            "/nonexistent/lmp_dpdnl",
            "--threads",
            "99999999999",
        ],
    );
    assert_eq!(o.code, Some(2), "{}", o.stderr);
    let n = cpus();
    assert!(
        o.stderr.contains(&format!(
            "WARNING: --threads 99999999999 is more than the {n} CPU(s) available"
        )),
        "{}",
        o.stderr
    );
    assert!(o.stderr.contains("not found"), "{}", o.stderr);
}
