//! `fix ID GROUP print N TEXT [file F | append F] [screen yes|no] [title T]`, as LAMMPS's
//! `FixPrint`: at the set-up of every run (when its step is a multiple of N) and at the end of
//! every N-th step, TEXT with its `$` variables and `$(…)` formulas substituted then goes to the
//! screen and log and to the file (which starts with the title line, by default
//! `# Fix print output for fix ID`). It reads no atom, so its group does not matter to it.

use super::{CmdResult, Interpreter};
use crate::grammar::{need, parse_int, shown};
use std::fs::File;
use std::io::{BufWriter, Write};

const USAGE: &str = "fix ID GROUP print N TEXT [file F | append F] [screen yes|no] [title T]";

/// One `fix print`.
pub(super) struct PrintFix {
    every: u64,
    text: String,
    screen: bool,
    file: Option<(String, BufWriter<File>)>,
    /// The next step it prints at (set at each run's set-up).
    next: u64,
}

impl PrintFix {
    /// Parse `args` (the whole `fix` command) and open the file, writing its title line.
    pub(super) fn parse(args: &[String]) -> Result<PrintFix, String> {
        need(args, 5, USAGE)?;
        if args[3].starts_with("v_") {
            return Err(format!(
                "fix print with a variable interval ('{}') is not supported: give N, a number \
                 of steps",
                shown(&args[3])
            ));
        }
        let every: u64 = parse_int(&args[3], "fix print N")?;
        if every == 0 {
            return Err(format!("fix print N = 0 must be > 0; usage: {USAGE}"));
        }
        let mut screen = true;
        let mut title = None;
        let mut path: Option<(String, bool)> = None;
        let mut k = 5;
        while k < args.len() {
            let word = args[k].as_str();
            let value = args
                .get(k + 1)
                .ok_or_else(|| format!("fix print {word} needs a value; usage: {USAGE}"))?;
            match word {
                "file" => path = Some((value.clone(), false)),
                "append" => path = Some((value.clone(), true)),
                "screen" => {
                    screen = match value.as_str() {
                        "yes" => true,
                        "no" => false,
                        o => {
                            return Err(format!(
                                "fix print screen takes yes or no, not '{}'",
                                shown(o)
                            ));
                        }
                    }
                }
                "title" => title = Some(value.clone()),
                o => {
                    return Err(format!(
                        "unknown fix print keyword '{}'; usage: {USAGE}",
                        shown(o)
                    ));
                }
            }
            k += 2;
        }
        let file = match path {
            None => None,
            Some((p, append)) => {
                let f = std::fs::OpenOptions::new()
                    .create(true)
                    .write(true)
                    .append(append)
                    .truncate(!append)
                    .open(&p)
                    .map_err(|e| format!("cannot open fix print file {}: {e}", shown(&p)))?;
                let mut w = BufWriter::new(f);
                let head =
                    title.unwrap_or_else(|| format!("# Fix print output for fix {}", args[0]));
                writeln!(w, "{head}")
                    .and_then(|_| w.flush())
                    .map_err(|e| format!("cannot write {}: {e}", shown(&p)))?;
                Some((p, w))
            }
        };
        Ok(PrintFix {
            every,
            text: args[4].clone(),
            screen,
            file,
            next: 0,
        })
    }
}

impl Interpreter<'_> {
    /// `fix print` at the set-up of a run (`setup`: its first print step is this step when a
    /// multiple of N, else the next multiple) or at the end of a step.
    pub(super) fn fix_print_step(&mut self, id: &str, setup: bool) -> CmdResult {
        let step = self.sys_mut()?.step;
        let Some(p) = self.prints.get_mut(id) else {
            return Ok(());
        };
        if setup {
            p.next = step.div_ceil(p.every) * p.every;
        }
        if step != p.next {
            return Ok(());
        }
        p.next = (step / p.every + 1) * p.every;
        let (text, screen) = (p.text.clone(), p.screen);
        let line = self.substitute(&text)?;
        if screen {
            self.out(&line);
        }
        if let Some(p) = self.prints.get_mut(id)
            && let Some((path, w)) = p.file.as_mut()
        {
            writeln!(w, "{line}")
                .and_then(|_| w.flush())
                .map_err(|e| format!("fix print: cannot write {}: {e}", shown(path)))?;
        }
        Ok(())
    }
}
