//! Script control, as LAMMPS's `Input` does it: `if`/`then`/`elif`/`else`, `label`, `jump`,
//! `next`, and the values of `loop` variables.
//!
//! `jump` only records where to go ([`Flow::pending`]); the reading loop of
//! [`Interpreter::run_text`] rewinds the file (or opens another) and skips lines, without
//! substituting them, up to `label LABEL`. So a `jump` inside an `if` takes effect after the
//! `if`'s other commands, as in LAMMPS.

use super::{CmdResult, Interpreter, Var};
use crate::grammar::{need, parse_int, shown};
use crate::input::expr::eval_boolean;
use crate::input::lexer::{split_words, strip_comment};

/// A `jump` asked for by the last command.
#[derive(Clone, Debug)]
pub(super) struct Jump {
    /// The file to read from its start (None: `SELF`, the file being read).
    pub file: Option<String>,
    /// The label to skip to (None: the first line).
    pub label: Option<String>,
}

/// The state of `jump` and `next` between commands.
#[derive(Debug, Default)]
pub(super) struct Flow {
    /// The jump the last command asked for.
    pub pending: Option<Jump>,
    /// Skip the next `jump` (a `next` exhausted its variables: the loop ends).
    skip_jump: bool,
    /// Jumps taken (capped for untrusted scripts).
    jumps: u64,
}

/// The most jumps a script run with [`super::Options::max_steps`] (an untrusted script, e.g.
/// the fuzzer's) may take: a loop without end is an error there, not a hang.
const MAX_JUMPS_UNTRUSTED: u64 = 10_000;

impl Flow {
    /// Count a jump taken; an error past [`MAX_JUMPS_UNTRUSTED`] when `max_steps` is set.
    pub(super) fn count_jump(&mut self, max_steps: Option<u64>) -> Result<(), String> {
        self.jumps += 1;
        if max_steps.is_some() && self.jumps > MAX_JUMPS_UNTRUSTED {
            return Err(format!(
                "more than {MAX_JUMPS_UNTRUSTED} jumps (a loop without end?) in a script run \
                 with a step cap (Options::max_steps)"
            ));
        }
        Ok(())
    }
}

/// `label ID`: a place for `jump` to go; nothing to do when reached.
pub(super) fn cmd_label(args: &[String]) -> CmdResult {
    need(args, 1, "label ID")?;
    crate::grammar::at_most(args, 1, "label ID")
}

/// Whether the (comment-stripped, unsubstituted) line `body` is `label LABEL`.
pub(super) fn is_label(body: &str, label: &str) -> bool {
    split_words(strip_comment(body)).is_ok_and(|w| {
        w.first().is_some_and(|c| c == "label") && w.get(1).is_some_and(|l| l == label)
    })
}

/// The values of `variable NAME loop N [pad]` or `loop N1 N2 [pad]`: N1..=N2 (1..=N), as
/// strings; with `pad`, zero-padded to the width of the last.
pub(super) fn loop_values(args: &[String]) -> Result<Vec<String>, String> {
    const USAGE: &str = "variable NAME loop N [pad] or variable NAME loop N1 N2 [pad]";
    need(args, 1, USAGE)?;
    let pad = args.last().is_some_and(|a| a == "pad");
    let nums = &args[..args.len() - usize::from(pad)];
    let (lo, hi) = match nums {
        [n] => (1, parse_int::<i64>(n, "loop N")?),
        [a, b] => (
            parse_int::<i64>(a, "loop N1")?,
            parse_int::<i64>(b, "loop N2")?,
        ),
        [] => return Err(format!("missing arguments; usage: {USAGE}")),
        [_, _, extra, ..] => {
            return Err(format!(
                "unexpected argument '{}'; usage: {USAGE}",
                shown(extra)
            ));
        }
    };
    if hi < lo || (nums.len() == 1 && hi < 1) {
        return Err(format!(
            "loop variable from {lo} to {hi}: the last value must be >= the first"
        ));
    }
    if hi - lo >= 10_000_000 {
        return Err(format!(
            "loop variable from {lo} to {hi}: more than 10^7 values"
        ));
    }
    let width = hi.to_string().len();
    Ok((lo..=hi)
        .map(|v| {
            if pad {
                format!("{v:0width$}")
            } else {
                v.to_string()
            }
        })
        .collect())
}

const IF_USAGE: &str = "if BOOLEAN then CMD… [elif BOOLEAN CMD…]… [else CMD…]";

impl Interpreter<'_> {
    /// `if BOOLEAN then "CMD" … [elif BOOLEAN "CMD" …]… [else "CMD" …]` (LAMMPS's
    /// `Input::ifthenelse`): the commands of the first true branch run in order, each as an
    /// input line of its own (its `$` variables substituted when it runs).
    pub(super) fn cmd_if(&mut self, args: &[String]) -> CmdResult {
        need(args, 3, IF_USAGE)?;
        if args[1] != "then" {
            return Err(format!(
                "expected 'then' after the Boolean, found '{}'; usage: {IF_USAGE}",
                shown(&args[1])
            ));
        }
        let is_branch = |w: &String| w == "elif" || w == "else";
        // As LAMMPS: the branches are read as they are reached, so a malformed branch after
        // the one that runs is not looked at.
        let mut cond = Some(args[0].as_str());
        let mut k = 2;
        loop {
            let end = args[k..]
                .iter()
                .position(is_branch)
                .map_or(args.len(), |p| k + p);
            let truth = match cond {
                Some(c) => eval_boolean(&self.substitute(c)?)? != 0.0,
                None => true,
            };
            if truth {
                if end == k {
                    return Err(format!(
                        "a branch of the if command has no command; usage: {IF_USAGE}"
                    ));
                }
                for c in &args[k..end] {
                    if c.trim().is_empty() {
                        return Err("a command of the if command is empty".into());
                    }
                    self.one(c)?;
                }
                return Ok(());
            }
            if end == args.len() {
                return Ok(());
            }
            if end + 2 > args.len() {
                return Err(format!(
                    "'{}' needs {}; usage: {IF_USAGE}",
                    args[end],
                    if args[end] == "elif" {
                        "a Boolean and commands"
                    } else {
                        "commands"
                    }
                ));
            }
            if args[end] == "elif" {
                cond = Some(args[end + 1].as_str());
                k = end + 2;
            } else {
                cond = None;
                k = end + 1;
            }
        }
    }

    /// One command given as text (a command of `if`): substituted, split and run as an input
    /// line (`include` too; its errors then name the included file's line).
    pub(super) fn one(&mut self, text: &str) -> CmdResult {
        let substituted = self.substitute(strip_comment(text))?;
        let words = split_words(strip_comment(&substituted))?;
        let Some((cmd, args)) = words.split_first() else {
            return Ok(());
        };
        if cmd == "include" {
            return self
                .include(args)
                .map_err(|e| e.map_or_else(|m| m, |e| e.to_string()));
        }
        self.command(cmd, args).map_err(|m| format!("{cmd}: {m}"))
    }

    /// `jump FILE [LABEL]`: read FILE (`SELF`: the file being read) from its start, or from
    /// `label LABEL`; skipped once after a `next` that ended its loop.
    pub(super) fn cmd_jump(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "jump FILE [LABEL]")?;
        crate::grammar::at_most(args, 2, "jump FILE [LABEL]")?;
        if std::mem::take(&mut self.flow.skip_jump) {
            return Ok(());
        }
        self.flow.pending = Some(Jump {
            file: (args[0] != "SELF").then(|| args[0].clone()),
            label: args.get(1).cloned(),
        });
        Ok(())
    }

    /// `next NAME…`: each `index` or `loop` variable takes its next value; one that has no
    /// more is deleted, and the next `jump` is skipped (LAMMPS's `Variable::next`).
    pub(super) fn cmd_next(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "next NAME…")?;
        for name in args {
            match self.vars.get(name) {
                Some(Var::Index(..)) => {}
                Some(_) => {
                    return Err(format!(
                        "variable '{name}' is not an index or loop variable: next \
                         advances those only"
                    ));
                }
                None => return Err(format!("variable '{name}' is not defined")),
            }
        }
        for name in args {
            if let Some(Var::Index(values, at)) = self.vars.get_mut(name) {
                *at += 1;
                if *at >= values.len() {
                    self.vars.remove(name);
                    self.flow.skip_jump = true;
                }
            }
        }
        Ok(())
    }
}
