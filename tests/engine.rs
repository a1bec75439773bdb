//! Engine tests: conservation, determinism across thread counts, data round-trip, input errors.
#![allow(clippy::needless_range_loop)]

use dpdnl::engine::System;
use dpdnl::input::{Collect, Console, Interpreter, Options};

mod common;
use common::{run, state_by_tag};

fn tmp(name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("dpdnl-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name).display().to_string()
}

fn fluid(dim: u32, friction: &str, noise: &str, steps: u32) -> String {
    let (zlo, zhi, n) = if dim == 3 {
        ("0", "5", 500)
    } else {
        ("-0.5", "0.5", 400)
    };
    format!(
        "units lj\ndimension {dim}\nboundary p p p\natom_style atomic\n\
         region box block 0 5 0 5 {zlo} {zhi}\ncreate_box 2 box\n\
         create_atoms 1 random {n} 4242 box\ncreate_atoms 2 random {n} 4343 box\n\
         mass 1 1.0\nmass 2 2.5\nvelocity all create 1.0 87287 mom yes\n\
         comm_modify vel yes\n\
         pair_style dpd/nonlinear 1.0 1.0 9898 friction {friction} noise {noise}\n\
         pair_coeff * * 25.0 4.5 0.5\npair_coeff 1 2 30.0 3.0 0.2 0.9\n\
         neighbor 0.3 bin\ntimestep 0.01\nfix 1 all nve\nthermo 100\n\
         thermo_style custom step temp press pxy ke pe\nrun {steps}\n"
    )
}

fn momentum(sys: &System) -> [f64; 3] {
    sys.momentum()
}

/// Total momentum is conserved to round-off over 1000 steps, in 3-D and 2-D, with unequal
/// masses, per-pair cut-offs and the non-linear dot friction with two-step noise.
#[test]
fn momentum_conserved() {
    for dim in [3, 2] {
        for (f, n) in [("dot", "twostep"), ("dot", "corrected"), ("cross", "plain")] {
            let (_, sys) = run(&fluid(dim, f, n, 1000)).expect("runs");
            let sys = sys.expect("system");
            let p = momentum(&sys);
            // Scale: the momentum of one thermal particle is ~1; 1000 steps of round-off in
            // sums of ~10^3 forces of size ~10^2 stay far below 1e-9.
            for k in 0..3 {
                assert!(p[k].abs() < 1e-9, "{dim}-D {f}/{n}: P = {p:?}");
            }
            assert!(sys.thermo().temp > 0.5, "the fluid is alive");
        }
    }
}

/// The same bits with 1, 2 and 3 threads (fixed summation order, whatever the model).
#[test]
fn bit_identical_across_thread_counts() {
    let script = fluid(3, "dot", "twostep", 300);
    let states: Vec<_> = [1, 2, 3]
        .iter()
        .map(|&t| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("pool");
            pool.install(|| {
                let (lines, sys) = run(&script).expect("runs");
                (
                    lines
                        .into_iter()
                        .filter(|l| !l.starts_with("Loop") && !l.starts_with("Perf"))
                        .collect::<Vec<_>>(),
                    state_by_tag(&sys.expect("system")),
                )
            })
        })
        .collect();
    assert_eq!(states[0], states[1]);
    assert_eq!(states[0], states[2]);
}

/// write_data → read_data → write_data reproduces the file and the state exactly.
#[test]
fn data_round_trip() {
    let (a, b) = (tmp("rt_a.data"), tmp("rt_b.data"));
    let mut script = fluid(3, "dot", "corrected", 50);
    script.push_str(&format!("write_data {a}\n"));
    let (_, s1) = run(&script).expect("runs");
    let again = format!("units lj\natom_style atomic\nread_data {a}\nwrite_data {b}\n");
    let (_, s2) = run(&again).expect("reads");
    let (ta, tb) = (
        std::fs::read_to_string(&a).expect("a"),
        std::fs::read_to_string(&b).expect("b"),
    );
    let strip = |t: &str| t.lines().skip(1).collect::<Vec<_>>().join("\n");
    assert_eq!(strip(&ta), strip(&tb));
    let (s1, s2) = (s1.expect("s1"), s2.expect("s2"));
    let v1: Vec<_> = state_by_tag(&s1).into_iter().map(|e| (e.0, e.2)).collect();
    let v2: Vec<_> = state_by_tag(&s2).into_iter().map(|e| (e.0, e.2)).collect();
    assert_eq!(v1, v2, "velocities survive the round trip bit for bit");
    assert_eq!(s1.atoms.len(), 1000);
}

/// Galilean invariance of the whole engine: after a uniform velocity shift u, the peculiar
/// velocities v − u follow the unshifted run to round-off (chaos over 100 steps amplifies the
/// different summation orders, hence 1e-8 rather than bits).
#[test]
fn galilean_invariance_engine() {
    let base = fluid(3, "dot", "twostep", 100);
    let u = [0.7, -0.3, 0.2];
    let shifted = base.replace(
        "velocity all create 1.0 87287 mom yes\n",
        "velocity all create 1.0 87287 mom yes\nvelocity all set 0.7 -0.3 0.2 sum yes\n",
    );
    let (_, s0) = run(&base).expect("runs");
    let (_, s1) = run(&shifted).expect("runs");
    let (s0, s1) = (s0.expect("system"), s1.expect("system"));
    let (a, b) = (state_by_tag(&s0), state_by_tag(&s1));
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.0, y.0);
        for k in 0..3 {
            let (v0, v1) = (f64::from_bits(x.2[k]), f64::from_bits(y.2[k]) - u[k]);
            assert!((v0 - v1).abs() < 1e-8, "atom {}: {v0} vs {v1}", x.0);
        }
    }
}

/// Each bad script gives a ScriptError naming the line and the command, never a panic.
#[test]
fn bad_scripts_give_clear_errors() {
    let head = "units lj\natom_style atomic\nregion box block 0 5 0 5 0 5\ncreate_box 1 box\ncreate_atoms 1 random 100 1 box\nmass 1 1.0\n";
    let cases: &[(&str, &str, &str)] = &[
        ("frobnicate 3\n", "frobnicate", "unknown command"),
        (
            "pair_style dpd/nonlinear 1.0 1.0\n",
            "pair_style",
            "missing arguments",
        ),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 0 -4.5 0\n",
            "pair_coeff",
            "gamma0",
        ),
        ("pair_style dpd/nonlinear 1.0 0.0 5\n", "pair_style", "rc"),
        ("pair_style dpd/nonlinear 1.0 -1 5\n", "pair_style", "rc"),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5 frction dot\n",
            "pair_style",
            "unknown pair_style dpd/nonlinear keyword 'frction'",
        ),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5 noise fancy\n",
            "pair_style",
            "noise 'fancy'",
        ),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5 weight 0\n",
            "pair_style",
            "weight exponent",
        ),
        (
            "pair_style dpd/nonlinear 1.0 6.0 5\npair_coeff 1 1 0 4.5 0\nfix 1 all nve\nrun 1\n",
            "run",
            "shorter than the largest cut-off rc = 6",
        ),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 1 0 4.5 0 x\n",
            "pair_coeff",
            "'x'",
        ),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5\npair_coeff 1 2 0 4.5 0\n",
            "pair_coeff",
            "type",
        ),
        (
            "pair_style dpd/nonlinear 1.0 1.0 5\nfix 1 all nve\nrun 1\n",
            "run",
            "pair coefficients",
        ),
        ("variable x equal 1/(\n print ${x}\n", "print", ""),
        ("thermo_style custom step bogus\n", "thermo_style", "bogus"),
        (
            "read_data /nonexistent/file.data\n",
            "read_data",
            "cannot read",
        ),
        ("fix 1 all nve extra\n", "fix", "no arguments"),
    ];
    for (tail, command, needle) in cases {
        let script = format!("{head}{tail}");
        let err = run(&script).expect_err(&format!("script should fail: {tail}"));
        assert_eq!(&err.command, command, "{err}");
        assert!(
            err.message.contains(needle),
            "'{}' lacks '{needle}'",
            err.message
        );
        assert!(err.line > 6, "line number points into the tail: {err}");
        assert_eq!(err.file, "test.in");
    }
}

/// The log has LAMMPS's shape: a `Step …` header, rows, then `Loop time of`.
#[test]
fn log_shape() {
    let (lines, _) = run(&fluid(2, "none", "plain", 200).replace(
        "0.5\npair_coeff 1 2 30.0 3.0 0.2 0.9",
        "0.0\npair_coeff 1 2 30.0 3.0 0.0 0.9",
    ))
    .expect("runs");
    let h = lines
        .iter()
        .position(|l| l.starts_with("Step"))
        .expect("header");
    assert_eq!(
        lines[h].split_whitespace().collect::<Vec<_>>(),
        ["Step", "Temp", "Press", "Pxy", "KinEng", "PotEng"]
    );
    let rows: Vec<_> = lines[h + 1..]
        .iter()
        .take_while(|l| !l.starts_with("Loop time of"))
        .collect();
    assert_eq!(rows.len(), 3, "steps 0, 100, 200");
    assert!(lines.iter().any(|l| l.starts_with("Loop time of")));
}

/// A console whose `interrupted` returns true from call `after + 1` on, while `*limit` is not
/// raised (an embedding's Ctrl-C).
struct StopAfter {
    lines: Vec<String>,
    calls: usize,
    limit: std::sync::Arc<std::sync::atomic::AtomicUsize>,
}

impl Console for StopAfter {
    fn line(&mut self, text: &str) {
        self.lines.push(text.to_string());
    }
    fn interrupted(&mut self) -> bool {
        self.calls += 1;
        self.calls > self.limit.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// `Console::interrupted` stops a run at a step boundary: asked at the start of the run and
/// after every step, so true on call K + 1 stops at step K with `interrupted at step K`; dump
/// and log hold that step; the interpreter can run on from it.
#[test]
fn interrupted_run_stops_at_the_step_boundary() {
    let dump = tmp("interrupt.dump");
    let log = tmp("interrupt.log");
    let script = fluid(3, "dot", "twostep", 100)
        .replace("thermo 100\n", "thermo 10\n")
        .replace(
            "run 100\n",
            &format!("dump d all custom 5 {dump} id x\nrun 100\n"),
        );
    let nlines = script.lines().count();
    let limit = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(37));
    let mut console = StopAfter {
        lines: Vec::new(),
        calls: 0,
        limit: limit.clone(),
    };
    let opts = Options {
        log: Some(log.clone().into()),
        ..Options::default()
    };
    let mut interp = Interpreter::new(&mut console, &opts).expect("log file");
    let err = interp
        .run_text(&script, "test.in")
        .expect_err("interrupted");
    assert_eq!(err.message, "interrupted at step 37");
    assert_eq!(err.command, "run");
    assert_eq!((err.file.as_str(), err.line), ("test.in", nlines));
    assert_eq!(interp.system().expect("system").step, 37);
    // The files hold every step written before the interruption (dumps 0, 5, …, 35; thermo
    // 0, 10, 20, 30) and no end-of-run summary.
    let dumped = std::fs::read_to_string(&dump).expect("dump");
    assert_eq!(dumped.matches("ITEM: TIMESTEP").count(), 8);
    let logged = std::fs::read_to_string(&log).expect("log");
    assert!(
        logged
            .lines()
            .any(|l| l.split_whitespace().next() == Some("30"))
    );
    assert!(!logged.contains("Loop time of"));
    // Running on: the next run continues from step 37.
    limit.store(usize::MAX, std::sync::atomic::Ordering::Relaxed);
    interp.run_text("run 10\n", "more.in").expect("runs on");
    assert_eq!(interp.system().expect("system").step, 47);
    // Interrupted before the set-up of a run (call 1): nothing is run or printed.
    limit.store(0, std::sync::atomic::Ordering::Relaxed);
    let err = interp
        .run_text("run 10\n", "more.in")
        .expect_err("interrupted");
    assert_eq!(err.message, "interrupted at step 47");
    assert_eq!(err.line, 1);
    drop(interp);
    assert_eq!(
        console.calls,
        38 + 11 + 1,
        "asked at the start of every run and after every step"
    );
    let setups = console
        .lines
        .iter()
        .filter(|l| l.starts_with("Setting up"))
        .count();
    assert_eq!(setups, 2, "the last run stopped before its set-up");
    assert!(console.lines.iter().any(|l| l.starts_with("Loop time of")));
}

/// An interpreter can own its console and move to another thread (embeddings release a GIL
/// around a run): `Interpreter<'static>` is `Send`.
#[test]
fn an_interpreter_owning_its_console_is_send() {
    fn assert_send<T: Send>(_: &T) {}
    let opts = Options::default();
    let mut interp =
        Interpreter::with_console(Box::new(Collect::default()), &opts).expect("no log file");
    assert_send(&interp);
    let handle = std::thread::spawn(move || {
        interp
            .run_text(
                "units lj\nregion b block 0 3 0 3 0 3\ncreate_box 1 b\n",
                "t.in",
            )
            .map(|_| interp.system().map(|s| s.ntypes))
    });
    assert_eq!(handle.join().expect("thread").expect("runs"), Some(1));
}

/// `dump ID all atom N FILE` is LAMMPS's default atom dump: the columns id type xs ys zs,
/// scaled positions (x − lo)/L of the positions `dump custom … x y z` writes, in an orthogonal
/// box and in a sheared one (LAMMPS's lamda coordinates: the tilt taken out of x).
#[test]
fn dump_atom_writes_scaled_positions() {
    for (k, region) in [
        "region box block 0 5 0 5 0 5",
        "region box prism 0 5 0 5 0 5 1.5 0 0",
    ]
    .iter()
    .enumerate()
    {
        let (atom, custom) = (
            tmp(&format!("atom{k}.dump")),
            tmp(&format!("custom{k}.dump")),
        );
        let script = fluid(3, "dot", "plain", 20)
            .replace("region box block 0 5 0 5 0 5", region)
            .replace(
                "run 20\n",
                &format!(
                    "dump a all atom 10 {atom}\ndump c all custom 10 {custom} id type x y z \
                     xs ys zs\ndump_modify c format float %.17g\nrun 20\n"
                ),
            );
        let (_, sys) = common::run(&script).expect("runs");
        let sys = sys.expect("system");
        let (lo, hi) = (sys.bx.lo, sys.bx.hi);
        let xy = if k == 1 { 1.5 } else { 0.0 };
        let atom = std::fs::read_to_string(&atom).expect("atom dump");
        let custom = std::fs::read_to_string(&custom).expect("custom dump");
        assert!(atom.contains("ITEM: ATOMS id type xs ys zs\n"), "{atom}");
        let rows = |t: &str| -> Vec<Vec<f64>> {
            t.lines()
                .filter(|l| l.split_whitespace().count() >= 5 && !l.starts_with("ITEM"))
                .map(|l| {
                    l.split_whitespace()
                        .map(|w| w.parse().expect("number"))
                        .collect()
                })
                .collect()
        };
        let (a, c) = (rows(&atom), rows(&custom));
        assert_eq!(a.len(), 3 * 1000, "three frames of 1000 atoms");
        assert_eq!(a.len(), c.len());
        for (ra, rc) in a.iter().zip(&c) {
            assert_eq!(ra[..2], rc[..2], "id and type");
            let sy = (rc[3] - lo[1]) / (hi[1] - lo[1]);
            let want = [
                (rc[2] - lo[0] - xy * sy) / (hi[0] - lo[0]),
                sy,
                (rc[4] - lo[2]) / (hi[2] - lo[2]),
            ];
            for d in 0..3 {
                // The custom dump's xs ys zs at full precision are the same numbers.
                assert_eq!(rc[5 + d], want[d], "custom xs/ys/zs column {d}");
                // The atom dump prints them with %g (six digits).
                assert!(
                    (ra[2 + d] - want[d]).abs() <= 5e-6 * want[d].abs().max(1e-3),
                    "{ra:?} {want:?}"
                );
                assert!(
                    (-0.5..1.5).contains(&want[d]),
                    "scaled coordinate {}",
                    want[d]
                );
            }
        }
    }
}
