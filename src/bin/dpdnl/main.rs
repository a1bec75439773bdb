//! `dpdnl`: the command-line front end of the standalone DPD engine and its tools.

mod analyze;
mod bench;
mod crosscheck;
mod design;
mod diff;
mod report;
mod run;
mod verify;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Dissipative particle dynamics with non-linear friction.
///
/// The engine reads a documented subset of the LAMMPS input language, so the same script runs in
/// LAMMPS (with this project's `pair_style dpd/nonlinear`) and here, and the two logs can be diffed.
#[derive(Parser)]
#[command(name = "dpdnl", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a LAMMPS-style input script in the standalone engine.
    Run(run::RunArgs),
    /// Choose γ and the weight exponent s from a target viscosity and Schmidt number.
    Design(design::DesignArgs),
    /// Print kinetic-theory predictions and the finite-step temperature for a parameter set.
    Theory(design::TheoryArgs),
    /// Compare two LAMMPS-format logs or dumps column by column.
    Diff(diff::DiffArgs),
    /// Run one script in both engines (standalone and LAMMPS) and compare the results.
    Crosscheck(crosscheck::CrosscheckArgs),
    /// Check a LAMMPS run frame by frame: recompute the force of this project's pair style in
    /// every frame of `fix dpdnl/frames` and compare it per atom.
    Verify(verify::VerifyArgs),
    /// Turn run outputs into the papers' numbers (MB, NEMD, Einstein–Helfand, MSD, Couette).
    Analyze(analyze::AnalyzeArgs),
    /// Measure atom-steps per second on the reference systems, against LAMMPS (`--lmp`).
    Bench(bench::BenchArgs),
}

/// The `-var NAME VALUE` words of a command line as (name, value) pairs, as LAMMPS's `-var`
/// (a trailing name without a value gets "").
pub(crate) fn var_pairs(words: &[String]) -> Vec<(String, String)> {
    words
        .chunks(2)
        .map(|c| (c[0].clone(), c.get(1).cloned().unwrap_or_default()))
        .collect()
}

/// The number of worker threads for `--threads N` (`run`, `crosscheck`, `bench`): 0 means one per
/// CPU available to this process (`std::thread::available_parallelism`, which honours CPU
/// affinity and cgroup quotas); N above that count is capped at it, with a warning on stderr
/// naming both numbers. More threads than CPUs only add overhead (1000 threads ran 190 times
/// slower than 2 on 2 CPUs), and a huge N would try to spawn that many threads. N is parsed as a
/// u64 (`value_parser!(u64)`), so any count that fits is read and capped, never truncated.
pub(crate) fn thread_count(requested: u64) -> usize {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    if requested == 0 {
        return cpus;
    }
    match usize::try_from(requested) {
        Ok(n) if n <= cpus => n,
        _ => {
            eprintln!(
                "WARNING: --threads {requested} is more than the {cpus} CPU(s) available to this \
                 process; using {cpus} thread(s)"
            );
            cpus
        }
    }
}

/// `dpdnl … | head` closes the pipe early; Rust's `println!` then panics on EPIPE. Leave quietly
/// with the shell's status for SIGPIPE (128 + 13) instead of printing a panic.
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let text = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if text.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    quiet_on_broken_pipe();
    // Accept LAMMPS's single-dash spelling `-var NAME VALUE` (and `-log`, `-in`-free forms).
    let args = std::env::args_os().map(|a| match a.to_str() {
        Some("-var") => "--var".into(),
        Some("-log") => "--log".into(),
        _ => a,
    });
    let cli = Cli::parse_from(args);
    let result = match cli.command {
        Command::Run(a) => run::main(a),
        Command::Design(a) => design::design_main(a),
        Command::Theory(a) => design::theory_main(a),
        Command::Diff(a) => diff::main(a),
        Command::Crosscheck(a) => crosscheck::main(a),
        Command::Verify(a) => verify::main(a),
        Command::Analyze(a) => analyze::main(a),
        Command::Bench(a) => bench::main(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("ERROR: {e}");
            ExitCode::FAILURE
        }
    }
}
