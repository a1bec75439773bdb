//! Running one configuration (standalone in process, LAMMPS as a subprocess), its loop time,
//! CPU time and memory; the kernel micro-benchmark.

use super::*;

/// Memory and list figures of a standalone run.
#[derive(Clone, Copy, Debug)]
pub(super) struct MemoryUse {
    /// Bytes of the atom arrays (`System::bytes`).
    pub(super) atom: usize,
    /// Bytes of the neighbour structures (lists included).
    pub(super) neighbor: usize,
    /// Pairs in the list and in the working list (0 when off).
    pub(super) pairs: usize,
    pub(super) working_pairs: usize,
    /// List builds during the run (set-up included).
    pub(super) builds: u64,
}

pub(super) type Memory = Option<MemoryUse>;

/// Writes the LAMMPS input of `case` into `dir` (`in.SYSTEM[.native].VARIANT`; `native`:
/// LAMMPS's own styles): its file name.
fn write_lammps_input(dir: &Path, case: &Case, native: bool) -> Result<String, String> {
    let name = format!(
        "in.{}.{}{}",
        case.sys.key,
        if native { "native." } else { "" },
        case.variant.label().replace(['/', ',', ' '], "_")
    );
    let text = script(
        &case.sys,
        &data_name(&case.sys),
        case.variant,
        native,
        case.steps,
    );
    std::fs::write(dir.join(&name), text).map_err(|e| format!("{name}: {e}"))?;
    Ok(name)
}

/// Run one repeat of a case; returns the loop time in seconds (and memory for standalone runs).
pub(super) fn run_case(dir: &Path, case: &Case) -> Result<(LoopTime, Memory), String> {
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
            let name = write_lammps_input(dir, case, true)?;
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
        Engine::Shim(exe, t) => {
            let name = write_lammps_input(dir, case, false)?;
            let mut cmd = Command::new(exe);
            cmd.current_dir(dir)
                .args(["-in", &name, "-log", "none"])
                .env("OMP_NUM_THREADS", t.to_string());
            Ok((run_external(cmd, exe)?, None))
        }
    }
}

/// A run's loop time: wall seconds and, where known, the CPU seconds of all its threads.
#[derive(Clone, Copy, Debug)]
pub(super) struct LoopTime {
    pub(super) wall: f64,
    pub(super) cpu: Option<f64>,
}

/// CPU seconds (user + system) used so far by this process, threads that ended included, from
/// /proc/self/stat (Linux; clock ticks of 1/100 s, the fixed USER_HZ of the Linux ABI).
pub(super) fn process_cpu_seconds() -> Option<f64> {
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
pub(super) fn run_standalone(text: &str, threads: usize) -> Result<(LoopTime, Memory), String> {
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
            ..Options::default()
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

pub(super) fn run_external(mut cmd: Command, exe: &Path) -> Result<LoopTime, String> {
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
pub(super) fn loop_time<'a>(lines: impl Iterator<Item = &'a str>) -> Option<f64> {
    lines
        .filter_map(|l| l.trim().strip_prefix("Loop time of "))
        .filter_map(|r| r.split_whitespace().next()?.parse().ok())
        .last()
}

/// ns per pair of the batch kernel, for each friction/noise and instruction set: a fixed batch
/// of 64 in-range pairs (n = 16-like separations and velocities), evaluated 2000 times per
/// repeat; the minimum over 30 repeats.
pub(super) fn kernel_micro() -> Result<String, Box<dyn std::error::Error>> {
    use dpdnl::forces::dpd::kernel::{
        Friction, Noise, PairCoeff, PairModel, PairTable, Weight, pair_forces_batch_isa,
    };
    use dpdnl::forces::{BATCH, Isa, NoiseDist, PairBatch};
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
    // DPDNL_SIMD (see forces::Isa::detect) narrows the table to one instruction set.
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
    let (g, u) = (NoiseDist::Gaussian, NoiseDist::Uniform);
    for (f, n, d) in [
        (Friction::None, Noise::Plain, g),
        (Friction::Cross, Noise::Plain, g),
        (Friction::Dot, Noise::Plain, g),
        (Friction::Dot, Noise::Corrected, g),
        (Friction::Dot, Noise::TwoStep, g),
        (Friction::Cross, Noise::TwoStep, g),
        (Friction::None, Noise::Plain, u),
        (Friction::Cross, Noise::Plain, u),
        (Friction::Dot, Noise::TwoStep, u),
    ] {
        let model = PairModel::new(0.1, f, n, Weight::STANDARD, 1e-3).with_dist(d);
        let table = PairTable::new(&model, &coeff);
        let dist = if d == u { " (noise_dist uniform)" } else { "" };
        write!(out, "| {}/{}{dist} |", f.keyword(), n.keyword())?;
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
pub(super) fn resolve_exe(p: &Path) -> Result<PathBuf, String> {
    if p.components().count() <= 1 {
        return Ok(p.to_path_buf());
    }
    std::fs::canonicalize(p).map_err(|e| format!("{}: {e}", p.display()))
}
