//! The measurement subset (`compute temp|pressure|pe|ke|msd|chunk/atom`, `fix ave/time`,
//! `fix ave/chunk`, `fix ave/histo`, atom-style variables): exact checks against values worked
//! out by hand from LAMMPS's definitions, and a cross-engine check (the same script run by
//! `dpdnl run` and by LAMMPS through `build/lmp_dpdnl` writes the same files).
//!
//! Most exact cases use an ideal gas with a = γ = 0: no forces, so positions move ballistically
//! and velocities stay as set, and every expected number follows from the input alone.
#![allow(clippy::needless_range_loop)]

use dpdnl::input::{Collect, Interpreter, Options, ScriptError};
use std::path::{Path, PathBuf};
use std::process::Command;

fn run(text: &str) -> Result<Vec<String>, ScriptError> {
    let mut console = Collect::default();
    let opts = Options::default();
    let mut interp = Interpreter::new(&mut console, &opts).expect("no log file");
    interp.run_text(text, "test.in")?;
    drop(interp);
    Ok(console.0)
}

fn tmpdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dpdnl-observe-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()))
}

/// Data lines (not comments) of an output file, split into numbers.
fn rows(p: &Path) -> Vec<Vec<f64>> {
    read(p)
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            l.split_whitespace()
                .map(|t| {
                    t.parse()
                        .unwrap_or_else(|_| panic!("{}: bad number {t}", p.display()))
                })
                .collect()
        })
        .collect()
}

fn comments(p: &Path) -> Vec<String> {
    read(p)
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(String::from)
        .collect()
}

fn close(a: f64, b: f64, rtol: f64) -> bool {
    (a - b).abs() <= rtol * a.abs().max(b.abs()).max(1e-300)
}

/// An ideal gas (no forces) of `n` atoms in a `l`³ box with velocities set by `velocity`.
fn ideal(n: usize, l: f64, velocity: &str) -> String {
    format!(
        "units lj\natom_style atomic\nregion b block 0 {l} 0 {l} 0 {l}\ncreate_box 1 b\n\
         create_atoms 1 random {n} 4711 b\nmass 1 1.0\n{velocity}\n\
         pair_style dpd/nonlinear 1.0 1.0 1234\npair_coeff 1 1 0 0 0\ntimestep 0.1\n\
         fix 1 all nve\n"
    )
}

/// `ave/time` of `v_s = step²`: which steps are sampled (Nevery/Nrepeat/Nfreq, the set-up of
/// each run included), the averages, and `ave running|window`, all from the definitions.
#[test]
fn ave_time_samples_the_documented_steps() {
    let dir = tmpdir("avetime");
    let f = |n: &str| dir.join(n).display().to_string();
    let script = format!(
        "{}variable s equal step*step\n\
         fix a all ave/time 2 3 10 v_s file {} format \" %.17g\"\n\
         fix b all ave/time 1 1 5 v_s file {} ave running format \" %.17g\"\n\
         fix c all ave/time 5 2 10 v_s v_s file {} ave window 2 format \" %.17g\"\n\
         run 20\nrun 10\n",
        ideal(10, 5.0, "velocity all set 0.1 0 0"),
        f("a"),
        f("b"),
        f("c")
    );
    run(&script).expect("runs");
    let sq = |s: u64| (s * s) as f64;
    // a: samples at n-4, n-2, n on multiples of 10 (none at step 0: the set-up step is not
    // the last of a 3-sample window).
    let a = rows(&dir.join("a"));
    let want: Vec<(u64, f64)> = [10u64, 20, 30]
        .iter()
        .map(|&n| (n, (sq(n - 4) + sq(n - 2) + sq(n)) / 3.0))
        .collect();
    assert_eq!(a.len(), want.len(), "{a:?}");
    for (r, (n, v)) in a.iter().zip(&want) {
        assert_eq!(r[0], *n as f64);
        assert!(close(r[1], *v, 1e-15), "step {n}: {} vs {v}", r[1]);
    }
    // b: every 5 steps from the set-up of the first run (step 0), running mean; the second
    // run's set-up at step 20 does not sample again.
    let b = rows(&dir.join("b"));
    let steps: Vec<u64> = b.iter().map(|r| r[0] as u64).collect();
    assert_eq!(steps, vec![0, 5, 10, 15, 20, 25, 30]);
    for (k, r) in b.iter().enumerate() {
        let mean = (0..=k).map(|j| sq(5 * j as u64)).sum::<f64>() / (k + 1) as f64;
        assert!(
            close(r[1], mean, 1e-15),
            "step {}: {} vs {mean}",
            r[0],
            r[1]
        );
    }
    // c: epochs (5,10), (15,20), (25,30); window of the last two epoch means; two columns.
    let c = rows(&dir.join("c"));
    let epoch = |n: u64| (sq(n - 5) + sq(n)) / 2.0;
    let want = [
        epoch(10),
        (epoch(10) + epoch(20)) / 2.0,
        (epoch(20) + epoch(30)) / 2.0,
    ];
    assert_eq!(c.len(), 3);
    for (r, w) in c.iter().zip(want) {
        assert!(close(r[1], w, 1e-15) && r[1] == r[2], "{r:?} vs {w}");
    }
    assert_eq!(
        comments(&dir.join("c")),
        vec!["# Time-averaged data for fix c", "# TimeStep v_s v_s"]
    );
}

/// LAMMPS's argument rules for Nevery/Nrepeat/Nfreq and values give errors, not silent output.
#[test]
fn invalid_averaging_arguments_are_errors() {
    let base = ideal(10, 5.0, "velocity all set 0.1 0 0");
    let cases: &[(&str, &str)] = &[
        ("fix a all ave/time 0 1 10 c_thermo_temp", "must be > 0"),
        (
            "fix a all ave/time 3 1 10 c_thermo_temp",
            "multiple of Nevery",
        ),
        (
            "fix a all ave/time 2 6 10 c_thermo_temp",
            "must not exceed Nfreq",
        ),
        ("fix a all ave/time 1 1 1 c_nope", "does not exist"),
        ("fix a all ave/time 1 1 1 c_thermo_temp[7]", "out of range"),
        (
            "fix a all ave/time 1 1 1 c_thermo_press v_x mode vector",
            "variable",
        ),
        (
            "variable q atom vx\nfix a all ave/time 1 1 1 v_q",
            "not an equal-style",
        ),
        ("fix a all ave/histo 1 1 1 0 2 10 vx", "mode vector"),
        (
            "fix a all ave/histo 1 1 1 2 0 10 vx mode vector",
            "lo 2 >= hi 0",
        ),
        (
            "compute c all chunk/atom bin/1d x lower 0.5\nfix a all ave/chunk 1 1 1 c v_nope",
            "does not exist",
        ),
        (
            "compute c all chunk/atom bin/2d x lower 0.5 y lower 0.5",
            "only bin/1d",
        ),
        ("compute m all msd average yes", "not supported"),
        (
            "fix a all ave/time 1 1 1 c_thermo_temp overwrite",
            "not supported",
        ),
        (
            "fix a all ave/time 1 1 1 c_thermo_temp ave window 0",
            "M must be >= 1",
        ),
        (
            "fix a all ave/time 1 1 1 c_thermo_temp format %d",
            "floating-point",
        ),
        ("variable q atom vx +", "expected a value"),
        (
            "variable q atom vx\nvariable e equal v_q+1\nprint ${e}",
            "atom-style",
        ),
    ];
    for (extra, needle) in cases {
        let e = run(&format!("{base}{extra}\nrun 1\n")).expect_err(extra);
        assert!(
            e.message.contains(needle),
            "{extra:?}: error lacks {needle:?}: {e}"
        );
    }
    // Two fixes that need the same chunks over different windows: LAMMPS refuses, so do we.
    let e = run(&format!(
        "{base}compute c all chunk/atom bin/1d x lower 1.0\n\
         fix a all ave/chunk 2 2 10 c vx\nfix b all ave/chunk 1 2 4 c vx ave running\nrun 10\n"
    ))
    .expect_err("incompatible locks");
    assert!(e.message.contains("incompatible"), "{e}");
}

fn write_data(path: &Path, atoms: &[(u32, u32, [f64; 3], [f64; 3])], masses: &[f64]) {
    let mut s = format!(
        "test data\n\n{} atoms\n{} atom types\n\n0 10 xlo xhi\n0 4 ylo yhi\n0 5 zlo zhi\n\nMasses\n\n",
        atoms.len(),
        masses.len()
    );
    for (t, m) in masses.iter().enumerate() {
        s.push_str(&format!("{} {m}\n", t + 1));
    }
    s.push_str("\nAtoms # atomic\n\n");
    for (id, t, x, _) in atoms {
        s.push_str(&format!("{id} {t} {} {} {}\n", x[0], x[1], x[2]));
    }
    s.push_str("\nVelocities\n\n");
    for (id, _, _, v) in atoms {
        s.push_str(&format!("{id} {} {} {}\n", v[0], v[1], v[2]));
    }
    std::fs::write(path, s).expect("write data");
}

/// `compute chunk/atom bin/1d` + `fix ave/chunk` on atoms at known places: counts, bin
/// centres, the velocity average, number and mass density (bin volume V δ/Lx), per-chunk
/// temperature Σ m v² / (d N), mean mass and an atom-style variable, as LAMMPS defines them.
#[test]
fn ave_chunk_of_known_atoms() {
    let dir = tmpdir("chunk");
    let data = dir.join("atoms.data");
    // (id, type, x, v); bins of width 2.5 along x in [0, 10): [0,2.5) [2.5,5) [5,7.5) [7.5,10)
    let atoms = [
        (1, 1, [0.5, 1.0, 1.0], [1.0, 0.0, 0.0]),
        (2, 1, [1.0, 2.0, 2.0], [2.0, 1.0, 0.0]),
        (3, 2, [3.0, 3.0, 3.0], [4.0, 0.0, -1.0]),
        (4, 1, [9.9, 1.0, 4.0], [-1.0, 0.0, 0.0]),
    ];
    write_data(&data, &atoms, &[1.0, 2.0]);
    let out = dir.join("chunks");
    let script = format!(
        "units lj\natom_style atomic\nread_data {}\n\
         pair_style dpd/nonlinear 1.0 1.0 99\npair_coeff * * 0 0 0\n\
         variable e atom id*10+vx\n\
         compute c all chunk/atom bin/1d x lower 2.5\n\
         fix a all ave/chunk 1 1 1 c vx density/number density/mass temp mass v_e file {} format \" %.17g\"\n\
         run 0\n",
        data.display(),
        out.display()
    );
    run(&script).expect("runs");
    assert_eq!(
        comments(&out),
        vec![
            "# Chunk-averaged data for fix a and group all",
            "# Timestep Number-of-chunks Total-count",
            "# Chunk Coord1 Ncount vx density/number density/mass temp mass v_e",
        ]
    );
    let r = rows(&out);
    assert_eq!(r[0], vec![0.0, 4.0, 4.0]);
    let vol = 10.0 * 4.0 * 5.0 * 2.5 / 10.0;
    // bin 1: atoms 1, 2 (mass 1); Σ m v² = 1 + 5
    let want1 = [
        1.0,
        1.25,
        2.0,
        1.5,
        2.0 / vol,
        2.0 / vol,
        6.0 / 6.0,
        1.0,
        (11.0 + 22.0) / 2.0,
    ];
    // bin 2: atom 3 (mass 2); Σ m v² = 2 · 17
    let want2 = [
        2.0,
        3.75,
        1.0,
        4.0,
        1.0 / vol,
        2.0 / vol,
        34.0 / 3.0,
        2.0,
        34.0,
    ];
    let want3 = [3.0, 6.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let want4 = [
        4.0,
        8.75,
        1.0,
        -1.0,
        1.0 / vol,
        1.0 / vol,
        1.0 / 3.0,
        1.0,
        39.0,
    ];
    for (row, want) in r[1..].iter().zip([want1, want2, want3, want4]) {
        for (k, (g, w)) in row.iter().zip(want).enumerate() {
            assert!(close(*g, w, 1e-15), "column {k}: {g} vs {w} in {row:?}");
        }
    }
}

/// `compute msd` of a prescribed ballistic motion across periodic boundaries: ⟨dx²⟩ = (v t)²
/// per component; with `com yes` the common drift cancels; usable in ave/time, in thermo and
/// in an equal-style formula.
#[test]
fn msd_of_a_prescribed_displacement() {
    let dir = tmpdir("msd");
    let out = dir.join("msd");
    let script = format!(
        "{}compute m all msd\ncompute mc all msd com yes\n\
         variable D equal c_m[4]/(6*(step*dt+1e-300))\n\
         fix a all ave/time 100 1 100 c_m[1] c_m[2] c_m[3] c_m[4] c_mc[4] v_D file {} format \" %.17g\"\n\
         thermo_style custom step c_m[4] v_D\nthermo_modify format float %.17g\nrun 100\n",
        ideal(30, 6.0, "velocity all set 1.0 0.5 0"),
        out.display()
    );
    let log = run(&script).expect("runs");
    let r = rows(&out);
    // Nrepeat 1 and step 0 a multiple of Nfreq: the set-up samples too (all zero).
    assert_eq!(r.len(), 2);
    assert!(r[0][1..].iter().all(|&x| x.abs() < 1e-20), "{:?}", r[0]);
    let t = 100.0 * 0.1;
    let want = [
        100.0,
        t * t,
        0.25 * t * t,
        0.0,
        1.25 * t * t,
        0.0,
        1.25 * t * t / (6.0 * t),
    ];
    for (k, (g, w)) in r[1].iter().zip(want).enumerate() {
        // 100 steps of x += v dt accumulate ~1e-14 relative round-off; com yes leaves a
        // difference of near-equal numbers ~1e-12 absolute.
        assert!(
            (g - w).abs() <= 1e-10 * w.abs().max(1.0),
            "column {k}: {g} vs {w}"
        );
    }
    let last = log
        .iter()
        .rev()
        .find(|l| l.trim_start().starts_with("100 "))
        .expect("thermo row at step 100");
    let cols: Vec<f64> = last
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(
        close(cols[1], 125.0, 1e-10) && close(cols[2], 125.0 / 60.0, 1e-10),
        "{last}"
    );
}

/// The speed histogram of a gas whose atoms all have speed 0.625 (`v_speed` atom-style,
/// `mode vector`), and the pressure tensor of that gas in vector-mode ave/time:
/// P_ab = N m v_a v_b / V exactly (no virial), and `ave/histo` counts over Nrepeat samples.
#[test]
fn histogram_and_pressure_of_a_uniform_gas() {
    let dir = tmpdir("histo");
    let (h, p) = (dir.join("h"), dir.join("p"));
    let n = 40;
    let script = format!(
        "{}variable speed atom sqrt(vx*vx+vy*vy+vz*vz)\n\
         fix h all ave/histo 1 2 2 0 2 4 v_speed mode vector file {}\n\
         fix p all ave/time 1 1 1 c_thermo_press mode vector file {} format \" %.17g\"\n\
         run 2\n",
        ideal(n, 4.0, "velocity all set 0.375 0.5 0"),
        h.display(),
        p.display()
    );
    run(&script).expect("runs");
    assert_eq!(
        comments(&h),
        vec![
            "# Histogrammed data for fix h",
            "# TimeStep Number-of-bins Total-counts Missing-counts Min-value Max-value",
            "# Bin Coord Count Count/Total",
        ]
    );
    let r = rows(&h);
    // samples at steps 1 and 2; the speed (exactly 0.625 in binary) lies in bin 2, [0.5, 1)
    assert_eq!(r[0], vec![2.0, 4.0, 2.0 * n as f64, 0.0, 0.625, 0.625]);
    assert_eq!(r[1], vec![1.0, 0.25, 0.0, 0.0]);
    assert_eq!(r[2], vec![2.0, 0.75, 2.0 * n as f64, 1.0]);
    let p = rows(&p);
    // blocks of 7 lines (step nrows, 6 rows) at steps 0, 1, 2
    assert_eq!(p.len(), 21);
    let v = [0.375, 0.5, 0.0];
    let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    for b in 0..3 {
        assert_eq!(p[7 * b], vec![b as f64, 6.0]);
        for (k, (i, j)) in pairs.iter().enumerate() {
            let want = n as f64 * v[*i] * v[*j] / 64.0;
            let got = p[7 * b + 1 + k][1];
            assert_eq!(
                got, want,
                "P[{k}]: every product and sum is exact in binary"
            );
        }
    }
}

/// Fixes act in the order they are defined, as LAMMPS's end_of_step: a temperature averaged
/// by a fix defined before `pex/push` sees the velocities before the push, one defined after
/// sees them after it. With no forces the velocities change only by pushes, so the "after"
/// value of step n is the "before" value of step n + 1.
#[test]
fn end_of_step_follows_fix_order() {
    let dir = tmpdir("order");
    let (a, b) = (dir.join("before"), dir.join("after"));
    let script = format!(
        "{}fix before all ave/time 1 1 1 c_thermo_temp file {} format \" %.17g\"\n\
         fix p all pex/push 0.5 width 2.0\n\
         fix after all ave/time 1 1 1 c_thermo_temp f_p file {} format \" %.17g\"\n\
         run 10\n",
        ideal(200, 8.0, "velocity all create 1.0 5 dist gaussian"),
        a.display(),
        b.display()
    );
    run(&script).expect("runs");
    let (ra, rb) = (rows(&a), rows(&b));
    assert_eq!(ra.len(), 11);
    let mut pushed = 0;
    for n in 0..10 {
        // Same velocities; the sum may run in another atom order after a re-sort.
        assert!(
            close(rb[n][1], ra[n + 1][1], 1e-13),
            "step {n}: T after push vs T before the next push"
        );
        if rb[n + 1][2] > rb[n][2] {
            pushed += 1;
            assert_ne!(
                ra[n + 1][1],
                rb[n + 1][1],
                "a push changes the kinetic energy"
            );
        }
    }
    assert!(
        pushed > 5,
        "the slabs should hold atoms on most steps ({pushed})"
    );
}

// ---------------------------------------------------------------------- cross-engine

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `build/lmp_dpdnl`, or `$DPDNL_LMP`; None (skip) unless DPDNL_REQUIRE_LAMMPS is set.
fn lmp() -> Option<PathBuf> {
    let p = std::env::var_os("DPDNL_LMP")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("build/lmp_dpdnl"));
    if p.is_file() {
        return Some(p);
    }
    let msg = format!(
        "{} not found (build it with `bash lammps-plugin/build.sh`)",
        p.display()
    );
    if std::env::var_os("DPDNL_REQUIRE_LAMMPS").is_some() {
        panic!("DPDNL_REQUIRE_LAMMPS is set but {msg}");
    }
    eprintln!("SKIPPED: cross-engine measurement test: {msg}");
    None
}

/// Compare two output files of the same fix value by value. Comment lines must be equal;
/// numbers agree within `rtol` relative to the larger of the two, with a floor of 1e-3 of
/// the column's largest magnitude (a value that should be 0, e.g. an MSD at step 0 with
/// `com yes`, is round-off in both engines). Returns the worst relative difference.
fn compare_files(a: &Path, b: &Path, rtol: f64) -> Result<f64, String> {
    let (ta, tb) = (read(a), read(b));
    let (la, lb): (Vec<&str>, Vec<&str>) = (ta.lines().collect(), tb.lines().collect());
    if la.len() != lb.len() {
        return Err(format!("{} lines vs {}", la.len(), lb.len()));
    }
    let mut pairs = Vec::new();
    let mut colmax = std::collections::HashMap::new();
    for (i, (x, y)) in la.iter().zip(&lb).enumerate() {
        if x.starts_with('#') || y.starts_with('#') {
            if x != y {
                return Err(format!("line {}: '{x}' vs '{y}'", i + 1));
            }
            continue;
        }
        let (wx, wy): (Vec<&str>, Vec<&str>) = (
            x.split_whitespace().collect(),
            y.split_whitespace().collect(),
        );
        if wx.len() != wy.len() {
            return Err(format!("line {}: '{x}' vs '{y}'", i + 1));
        }
        for (k, (p, q)) in wx.iter().zip(&wy).enumerate() {
            let (p, q): (f64, f64) = match (p.parse(), q.parse()) {
                (Ok(p), Ok(q)) => (p, q),
                _ => return Err(format!("line {}: not numbers: '{x}' vs '{y}'", i + 1)),
            };
            let key = (wx.len(), k);
            let m = colmax.entry(key).or_insert(0.0f64);
            *m = m.max(p.abs()).max(q.abs());
            pairs.push((i + 1, key, p, q));
        }
    }
    let mut worst = 0.0f64;
    for (line, key, p, q) in pairs {
        let scale = p.abs().max(q.abs()) + 1e-3 * colmax[&key];
        let rel = if scale > 0.0 {
            (p - q).abs() / scale
        } else {
            0.0
        };
        if rel > rtol {
            return Err(format!("line {line}: {p} vs {q} (relative {rel:.2e})"));
        }
        worst = worst.max(rel);
    }
    Ok(worst)
}

/// The same script (every compute and averaging fix, PeX push, two runs) through both engines
/// from the same data file: all output files agree. Both engines call the same pair kernel with
/// the same keyed noise; over 100 steps the trajectories agree to ~1e-12 (thermo, dumps:
/// tests/crosscheck.rs), so 1e-9 leaves a margin of ~100 for the chaotic growth.
#[test]
fn measurement_files_agree_between_engines() {
    let Some(lmp) = lmp() else { return };
    let files = [
        "t1", "t2", "t3", "t4", "t5", "c1", "c2", "c3", "h1", "h2", "h3",
    ];
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for dim in [3, 2] {
        let script = root().join(format!("tests/data/observe/in.measure_{dim}d"));
        let data = root().join(format!("tests/data/crosscheck/dpd{dim}d.data"));
        let work = tmpdir(&format!("cross{dim}"));
        for (engine, exe, sub) in [
            (
                "standalone",
                PathBuf::from(env!("CARGO_BIN_EXE_dpdnl")),
                "run",
            ),
            ("lammps", lmp.clone(), "-in"),
        ] {
            let mut cmd = Command::new(&exe);
            if engine == "standalone" {
                cmd.arg(sub).arg(&script);
            } else {
                cmd.arg(sub).arg(&script).arg("-log").arg("none");
            }
            let out = cmd
                .arg("-var")
                .arg("engine")
                .arg(engine)
                .arg("-var")
                .arg("data")
                .arg(&data)
                .current_dir(&work)
                .output()
                .expect("run engine");
            let text = String::from_utf8_lossy(&out.stdout).to_string()
                + &String::from_utf8_lossy(&out.stderr);
            assert!(
                out.status.success() && !text.contains("ERROR"),
                "{engine} {dim}-D failed:\n{text}"
            );
        }
        for f in files {
            let a = work.join(format!("{f}.standalone"));
            let b = work.join(format!("{f}.lammps"));
            match compare_files(&a, &b, 1e-9) {
                Ok(w) => report.push(format!("{dim}-D {f}: worst relative difference {w:.1e}")),
                Err(e) => failures.push(format!("{dim}-D {f}: {e}")),
            }
        }
    }
    eprintln!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
