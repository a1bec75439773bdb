//! SIGINT during `dpdnl run` (issue 16, "interrupt without loss"): the run stops at the next
//! step boundary, the log and the dump end with whole lines of the step reached, the restart
//! file of `restart N FILE` is written at that step, and the exit status is 130.

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn sigint_stops_the_run_at_a_step_with_whole_output_files() {
    let dir = std::env::temp_dir().join(format!("dpdnl-sigint-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let script = dir.join("in.long");
    let setup = "units lj\natom_style atomic\nregion box block 0 6 0 6 0 6\ncreate_box 1 box\n\
                 create_atoms 1 random 2000 7 box\nmass 1 1.0\nvelocity all create 1.0 5 mom yes\n\
                 pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 25 4.5 0\ntimestep 0.01\n\
                 fix 1 all nve\nthermo 10\n";
    std::fs::write(
        &script,
        format!(
            "{setup}dump d all custom 10 dump.long id x y z\nrestart 1000000000 int.*.restart\n\
             run 100000000\n"
        ),
    )
    .expect("script");
    let mut child = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .current_dir(&dir)
        .args(["run", "in.long", "--threads", "1", "--log", "log.long"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("dpdnl starts");
    // Wait until the run is under way (a thermo row past step 0 in the dump's wake).
    let dump = dir.join("dump.long");
    let start = Instant::now();
    while std::fs::read_to_string(&dump).map_or(0, |d| d.matches("ITEM: TIMESTEP").count()) < 3 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the run did not start"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "no stop after SIGINT"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    child
        .stderr
        .take()
        .expect("stderr")
        .read_to_string(&mut err)
        .expect("read stderr");
    assert_eq!(status.code(), Some(130), "stderr: {err}");
    assert!(err.contains("interrupted at step "), "{err}");
    let step: u64 = err
        .split("interrupted at step ")
        .nth(1)
        .and_then(|s| s.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|s| s.parse().ok())
        .expect("a step in the message");
    // The log ends with a newline, its last thermo row is at or before the step reached; the
    // dump ends with a whole frame.
    let log = std::fs::read_to_string(dir.join("log.long")).expect("log");
    assert!(log.ends_with('\n'), "log ends mid-line");
    let last_row = log
        .lines()
        .rev()
        .find_map(|l| l.split_whitespace().next()?.parse::<u64>().ok())
        .expect("thermo rows");
    assert!(
        last_row <= step && step - last_row < 10,
        "{last_row} vs {step}"
    );
    let d = std::fs::read_to_string(&dump).expect("dump");
    assert!(d.ends_with('\n'));
    let frames = d.matches("ITEM: TIMESTEP").count();
    let atom_lines = d
        .lines()
        .filter(|l| l.split_whitespace().count() == 4 && !l.starts_with("ITEM"))
        .count();
    assert_eq!(atom_lines, 2000 * frames, "a partial frame in the dump");
    // The restart file of the step reached: named after it, announced, and the state of a run
    // of exactly that many steps, bit for bit and in the same atom order.
    let name = format!("int.{step}.restart");
    assert!(
        err.contains(&format!("; restart file {name} written")),
        "{err}"
    );
    let saved = dpdnl::io::restart::read(&dir.join(&name)).expect("a whole restart file");
    assert_eq!(saved.step, step);
    let mut console = dpdnl::input::Collect::default();
    let opts = dpdnl::input::Options::default();
    let mut interp = dpdnl::input::Interpreter::new(&mut console, &opts).expect("interpreter");
    interp
        .run_text(&format!("{setup}run {step}\n"), "in.reference")
        .expect("reference run");
    let reference = interp.into_system().expect("system");
    assert!(
        saved.atoms == reference.atoms,
        "restart file != state at step {step}"
    );
    // The file continues in a new process.
    std::fs::write(
        dir.join("in.more"),
        format!("read_restart {name}\nfix 1 all nve\nrun 10\n"),
    )
    .expect("script");
    let more = Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .current_dir(&dir)
        .args(["run", "in.more", "--threads", "1", "--log", "none"])
        .output()
        .expect("dpdnl runs");
    assert!(
        more.status.success(),
        "{}",
        String::from_utf8_lossy(&more.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
