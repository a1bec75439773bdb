//! `dpdnl run SCRIPT`: run a LAMMPS-style input script in the standalone engine.

use dpdnl::input::{Console, Interpreter, Options};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Run a LAMMPS-style input script (the subset in docs/input.md).
#[derive(clap::Args)]
pub struct RunArgs {
    /// The input script (paths inside it are relative to the current directory, as in LAMMPS).
    pub script: PathBuf,
    /// Define an index-style variable NAME with VALUE (as LAMMPS's `-var`); repeatable.
    #[arg(long = "var", short = 'v', num_args = 2, value_names = ["NAME", "VALUE"], action = clap::ArgAction::Append, allow_hyphen_values = true)]
    pub var: Vec<String>,
    /// Log file; `none` for no log.
    #[arg(long, default_value = "log.dpdnl")]
    pub log: String,
    /// Worker threads (results are bit-identical for any number). 0: one per CPU available; a
    /// larger N than that is capped at the CPU count, with a warning.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64))]
    pub threads: u64,
    /// Do not echo thermo output to the screen (the log still gets it).
    #[arg(long)]
    pub quiet: bool,
}

struct Screen {
    lines: Vec<String>,
    quiet: bool,
    tty: bool,
    progress_shown: bool,
}

/// Set by SIGINT/SIGTERM (`ctrlc` handler); read by [`Screen::interrupted`] once per step.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Exit status of a run stopped by SIGINT/SIGTERM (128 + SIGINT, as shells report it).
const EXIT_INTERRUPTED: u8 = 130;

impl Console for Screen {
    fn interrupted(&mut self) -> bool {
        INTERRUPTED.load(Ordering::Relaxed)
    }

    fn line(&mut self, text: &str) {
        self.lines.push(text.to_string());
        if self.progress_shown {
            eprint!("\r\x1b[2K");
            self.progress_shown = false;
        }
        if !self.quiet {
            println!("{text}");
        }
    }
    fn progress(&mut self, step: u64, first: u64, last: u64) {
        if self.tty {
            let frac = (step - first) as f64 / (last - first).max(1) as f64;
            eprint!("\r  step {step} / {last} ({:.1}%)", 100.0 * frac);
            let _ = std::io::stderr().flush();
            self.progress_shown = true;
        }
    }
}

pub fn main(a: RunArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let threads = crate::thread_count(a.threads);
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .map_err(|e| format!("cannot start {threads} threads: {e}"))?;
    let vars = crate::var_pairs(&a.var);
    let opts = Options {
        log: (a.log != "none").then(|| PathBuf::from(&a.log)),
        vars,
        threads,
        ..Options::default()
    };
    let mut screen = Screen {
        lines: Vec::new(),
        quiet: a.quiet,
        tty: std::io::stderr().is_terminal(),
        progress_shown: false,
    };
    // The first SIGINT/SIGTERM stops the run at the next step boundary; a second one exits
    // at once.
    ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::Relaxed) {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
    })
    .map_err(|e| format!("cannot install the SIGINT/SIGTERM handler: {e}"))?;
    let mut interp = Interpreter::new(&mut screen, &opts)?;
    let result = interp.run_file(&a.script);
    // Dropping the interpreter flushes the log, dumps and averaging files (whole records).
    drop(interp);
    match result {
        Ok(()) => {
            summary(&screen.lines);
            Ok(ExitCode::SUCCESS)
        }
        Err(e) if INTERRUPTED.load(Ordering::Relaxed) => {
            eprintln!("dpdnl: {e}; outputs flushed");
            Ok(ExitCode::from(EXIT_INTERRUPTED))
        }
        Err(e) => Err(e.into()),
    }
}

/// A short summary of the last run: the mean of each thermo column over its second half, with a
/// block-averaged standard error (the first half is treated as equilibration).
fn summary(lines: &[String]) {
    let Ok(blocks) = dpdnl::io::lammps_log::parse_log(&lines.join("\n")) else {
        return;
    };
    let Some(b) = blocks.last() else { return };
    if b.rows.len() < 4 {
        return;
    }
    let half = &b.rows[b.rows.len() / 2..];
    println!(
        "Summary of the last run (second half: {} thermo rows, block-averaged errors):",
        half.len()
    );
    let mut lower_bound = false;
    for (k, name) in b.columns.iter().enumerate().skip(1) {
        let xs: Vec<f64> = half.iter().map(|r| r[k]).collect();
        let e = dpdnl::stats::block_average(&xs);
        lower_bound |= !e.converged;
        let mark = if e.converged { "" } else { " *" };
        println!("  {name:>8} = {:.6e} ± {:.1e}{mark}", e.mean, e.stderr);
    }
    if lower_bound {
        println!(
            "  * error is a lower bound: too few thermo rows for the correlation time (fewer \
             than 10 effective samples, or no plateau of the blocking); print thermo more often \
             or run longer"
        );
    }
}
