//! The interpreter of the LAMMPS-input subset (see `docs/input.md` for the full list).
//!
//! Every command is parsed and validated once, into the engine's typed values; every error names
//! the file, the line and the command. Output (what LAMMPS prints to the screen and the log) goes
//! to a [`Console`] supplied by the caller and to the log file.
//!
//! The rooms of this module, by command family:
//!
//! - this file: the [`Interpreter`] and its [`Options`], [`Console`] and [`ScriptError`]; reading
//!   scripts (`include`), variables and `$` substitution, the command dispatch;
//! - `setup`: the box and the atoms (`units`, `dimension`, `boundary`, `atom_style`, `region`,
//!   `create_box`, `create_atoms`, `mass`, `neighbor`, `timestep`, `change_box`,
//!   `reset_timestep`);
//! - `data`: `read_data`, `write_data`;
//! - `state`: crosscheck's run from LAMMPS's state ([`FromState`]);
//! - `velocity`: `velocity`;
//! - `pair`: `pair_style`, `pair_coeff` (parsed by [`crate::grammar`]);
//! - `fix`: `fix`, `unfix` and `fix deform`;
//! - `thermo`: `thermo_style`, `thermo_modify` and the thermo output;
//! - `output`: `dump`, `dump_modify`, `undump`, the dump files, `print`, `log`;
//! - `run`: `run`, the end-of-step fixes, dry runs and their [`PlannedRun`];
//! - `restart`: `write_restart`, `read_restart`, `restart N FILE` (the file format is
//!   [`crate::io::restart`]);
//! - `run_style verlet` is accepted in the dispatch (`run`).

mod bonded;
mod control;
mod data;
mod fix;
mod fix_group;
mod fix_print;
mod group;
mod output;
mod pair;
mod restart;
mod run;
mod setup;
mod state;
mod thermo;
mod variables;
use variables::Ctx;
mod velocity;

pub use run::PlannedRun;
pub use state::{CARRIED, FromState, StateReport, first_run_line, setup_groups};

use super::expr::{AtomBinder, ExprContext, eval_equal};
use super::format::{FmtArg, sprintf};
use super::lexer::{logical_lines, split_words, strip_comment};
use super::observe::{self, Observe, VarStyle};
use crate::engine::System;
use std::collections::BTreeMap;
use std::fmt;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Where the interpreter's screen output goes (the library never prints by itself), and how an
/// embedding stops a run.
///
/// Interrupting (a Python binding's Ctrl-C, a GUI's stop button): [`Console::interrupted`] is
/// asked at the start of every `run` (before its set-up) and after each of its steps (after the
/// step's fixes, thermo row and dumps). When it returns true the run stops at that step
/// boundary: the log is flushed as at the end of a run (dump and `fix ave/*` files are flushed
/// as they are written), no "Loop time" summary is printed, and the script stops with a
/// [`ScriptError`] of command `run` and message `interrupted at step N`, N the step reached
/// (with `restart N FILE` configured, the restart file of that step is written first and the
/// message goes on `; restart file F written`).
/// The interpreter stays usable: the system is left at step N and a later `run` continues from
/// it.
///
/// Consoles are `Send`, so that an [`Interpreter`] can be handed to another thread (e.g. a run
/// with Python's GIL released).
pub trait Console: Send {
    /// One line of output (no trailing newline).
    fn line(&mut self, text: &str);
    /// Progress of a run: `step` reached, run from `first` to `last`. Called about every second.
    fn progress(&mut self, _step: u64, _first: u64, _last: u64) {}
    /// True to stop the current run at this step boundary (see the trait's documentation).
    /// Called once per step, so it should be cheap (e.g. read a flag). Default: never.
    fn interrupted(&mut self) -> bool {
        false
    }
}

/// A console that collects lines in memory (tests, library users).
#[derive(Default, Debug)]
pub struct Collect(pub Vec<String>);

impl Console for Collect {
    fn line(&mut self, text: &str) {
        self.0.push(text.to_string());
    }
}

/// An input error: file, line, command and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptError {
    /// Input file (or `-var`/command line).
    pub file: String,
    /// 1-based line number (0 when not from a file).
    pub line: usize,
    /// The command word.
    pub command: String,
    /// The message.
    pub message: String,
}

impl fmt::Display for ScriptError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}: {}: {}",
            self.file, self.line, self.command, self.message
        )
    }
}

impl std::error::Error for ScriptError {}

#[derive(Clone, Debug)]
enum Var {
    /// `index` and `loop` variables: their values and the one `next` has reached.
    Index(Vec<String>, usize),
    Str(String),
    Equal(String),
    /// `variable NAME atom FORMULA` (per-atom values; see `observe`).
    Atom(String),
}

/// Commands accepted and ignored: they only matter to LAMMPS (neighbour
/// bookkeeping, atom maps, Newton's third law flag, processor grids, echo).
pub(crate) const IGNORED_COMMANDS: &[&str] = &[
    "neigh_modify",
    "atom_modify",
    "newton",
    "processors",
    "echo",
];

/// Run-time options from the command line.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Log file (None: no log file).
    pub log: Option<PathBuf>,
    /// `-var NAME VALUE` definitions (index-style, as LAMMPS's `-var`).
    pub vars: Vec<(String, String)>,
    /// Number of threads the caller configured (printed in "Loop time").
    pub threads: usize,
    /// Cap on the steps of one `run` (None: none). For scripts from an untrusted source, such
    /// as the fuzzer (`fuzz/`): a longer run is an error instead of a long computation.
    pub max_steps: Option<u64>,
    /// Cap on the number of atoms `create_atoms` may bring the system to (None: only the
    /// memory check). For untrusted scripts, as `max_steps`.
    pub max_atoms: Option<usize>,
    /// Take this sub-style's words from a `pair_style hybrid`/`hybrid/overlay` line instead of
    /// refusing it (`dpdnl verify`, which recomputes one dpdnl style of a LAMMPS run that
    /// overlays others): its words are the longest run after its name that it parses.
    pub substyle: Option<String>,
    /// Run from LAMMPS's state (`dpdnl crosscheck --from lammps`): see [`FromState`].
    pub from_state: Option<FromState>,
}

/// The interpreter state.
pub struct Interpreter<'c> {
    console: ConsoleSlot<'c>,
    log: Option<BufWriter<File>>,
    vars: BTreeMap<String, Var>,
    dim: usize,
    regions: BTreeMap<String, [[f64; 2]; 3]>,
    /// The same regions as atoms are matched against them (INF unbounded).
    region_match: BTreeMap<String, [[f64; 2]; 3]>,
    /// Tilt factors (xy, xz, yz) of `region … prism` regions.
    prisms: BTreeMap<String, [f64; 3]>,
    sys: Option<System>,
    /// `atom_style` (the columns `read_data` reads; molecular styles carry a topology).
    atom_style: crate::engine::topology::AtomStyle,
    /// The columns of `atom_style`'s data-file lines (`charge`, `mdpd`, `hybrid` …).
    atom_columns: crate::io::data::AtomColumns,
    /// The extra columns' values by atom id (read from a data file, written back by
    /// `write_data`; atoms made later get 0).
    atom_extra: BTreeMap<u32, crate::io::data::AtomExtra>,
    /// `bond_style`, `angle_style` words and `special_bonds` given before the box exists.
    pre_topo: bonded::PreTopology,
    /// `pair_style` words given before the box exists (the style is made with the box).
    pre_pair: Option<Vec<String>>,
    /// `comm_modify cutoff` (LAMMPS's user ghost cut-off; 0: none given).
    comm_cutoff: f64,
    skin: f64,
    /// `units` (lj until given; the box takes it when it is created).
    units: crate::units::Units,
    dry_run: bool,
    planned: Vec<PlannedRun>,
    dt: f64,
    thermo: ThermoSettings,
    dumps: Vec<Dump>,
    fixes: Vec<(String, FixKind)>,
    /// The files `write_dump` wrote (for [`Interpreter::dump_files`]).
    written_dumps: Vec<String>,
    /// The `fix print` fixes, by ID.
    prints: BTreeMap<String, fix_print::PrintFix>,
    /// The words of each fix's `fix` command, by ID (for restart files).
    fix_lines: BTreeMap<String, Vec<String>>,
    /// `restart N FILE`, when set.
    restart: Option<restart::RestartEvery>,
    /// Fix state read by `read_restart` that no re-defined fix has claimed yet.
    restart_fixes: Vec<restart::PendingFix>,
    threads: usize,
    /// [`Options::max_steps`] and [`Options::max_atoms`].
    max_steps: Option<u64>,
    max_atoms: Option<usize>,
    /// [`Options::substyle`].
    substyle: Option<String>,
    depth: usize,
    /// `jump` and `next`: the jump the last command asked for, and whether the next `jump` is
    /// skipped (a `next` that exhausted its variable).
    flow: control::Flow,
    run_first: u64,
    obs: Observe,
    /// The "from LAMMPS's state" mode, when [`Options::from_state`] is set.
    state: Option<state::StateMode>,
    /// The `run` commands started (a set-up error is one before the first).
    runs_started: u64,
}

type CmdResult = Result<(), String>;

/// The console an interpreter writes to: borrowed from the caller ([`Interpreter::new`]) or
/// owned ([`Interpreter::with_console`], for embeddings that keep the interpreter alive).
enum ConsoleSlot<'c> {
    Borrowed(&'c mut dyn Console),
    Owned(Box<dyn Console>),
}

impl ConsoleSlot<'_> {
    fn get(&mut self) -> &mut dyn Console {
        match self {
            ConsoleSlot::Borrowed(c) => &mut **c,
            ConsoleSlot::Owned(c) => &mut **c,
        }
    }
}

pub(crate) use crate::grammar::type_range;
use crate::grammar::{need, parse_int};
use fix::FixKind;
use output::Dump;
use run::dry_run_skips;
use thermo::ThermoSettings;

impl Interpreter<'static> {
    /// A fresh interpreter that owns its console (embeddings: the interpreter can then live as
    /// long as its owner, and, consoles being `Send`, move between threads).
    pub fn with_console(
        console: Box<dyn Console>,
        opts: &Options,
    ) -> Result<Interpreter<'static>, String> {
        Self::with_slot(ConsoleSlot::Owned(console), opts)
    }
}

impl<'c> Interpreter<'c> {
    /// A fresh interpreter writing to `console` (and to `opts.log` when set).
    pub fn new(console: &'c mut dyn Console, opts: &Options) -> Result<Interpreter<'c>, String> {
        Self::with_slot(ConsoleSlot::Borrowed(console), opts)
    }

    fn with_slot(console: ConsoleSlot<'c>, opts: &Options) -> Result<Interpreter<'c>, String> {
        let log = match &opts.log {
            Some(p) => {
                Some(BufWriter::new(File::create(p).map_err(|e| {
                    format!("cannot open log file {}: {e}", p.display())
                })?))
            }
            None => None,
        };
        let mut vars = BTreeMap::new();
        for (k, v) in &opts.vars {
            vars.insert(k.clone(), Var::Index(vec![v.clone()], 0));
        }
        Ok(Interpreter {
            console,
            log,
            vars,
            dim: 3,
            regions: BTreeMap::new(),
            region_match: BTreeMap::new(),
            prisms: BTreeMap::new(),
            sys: None,
            atom_style: Default::default(),
            atom_columns: Default::default(),
            atom_extra: BTreeMap::new(),
            pre_topo: Default::default(),
            pre_pair: None,
            comm_cutoff: 0.0,
            skin: 0.3,
            units: crate::units::Units::LJ,
            dry_run: false,
            planned: Vec::new(),
            dt: 0.005,
            thermo: ThermoSettings::default(),
            dumps: Vec::new(),
            fixes: Vec::new(),
            prints: BTreeMap::new(),
            written_dumps: Vec::new(),
            fix_lines: BTreeMap::new(),
            restart: None,
            restart_fixes: Vec::new(),
            threads: opts.threads.max(1),
            max_steps: opts.max_steps,
            max_atoms: opts.max_atoms,
            substyle: opts.substyle.clone(),
            depth: 0,
            flow: Default::default(),
            run_first: 0,
            obs: Observe::new(),
            state: opts.from_state.clone().map(state::StateMode::new),
            runs_started: 0,
        })
    }

    /// The console, as [`Interpreter::with_console`] took it (or the caller's, borrowed).
    pub fn console(&mut self) -> &mut dyn Console {
        self.console.get()
    }

    /// The system, once a box exists.
    pub fn system(&self) -> Option<&System> {
        self.sys.as_ref()
    }

    /// The system, mutably, once a box exists (for embeddings that read or change the state
    /// between commands; the next `run` checks it and evaluates its forces again in its
    /// set-up).
    pub fn system_mut(&mut self) -> Option<&mut System> {
        self.sys.as_mut()
    }

    /// The number of `run` commands started so far (0: an error came from the set-up).
    pub fn runs_started(&self) -> u64 {
        self.runs_started
    }

    /// The file names of the dumps currently defined, as given to `dump` (after variable
    /// substitution), in the order they were defined; then those `write_dump` wrote, in the
    /// order written.
    pub fn dump_files(&self) -> Vec<String> {
        self.dumps
            .iter()
            .map(|d| d.path.clone())
            .chain(self.written_dumps.iter().cloned())
            .collect()
    }

    fn out(&mut self, text: &str) {
        self.console.get().line(text);
        if let Some(l) = self.log.as_mut() {
            let _ = writeln!(l, "{text}");
        }
    }

    fn warn(&mut self, text: &str) {
        self.out(&format!("WARNING: {text}"));
    }

    /// Run a script file.
    pub fn run_file(&mut self, path: &Path) -> Result<(), ScriptError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ScriptError {
            file: name.clone(),
            line: 0,
            command: "include".into(),
            message: format!("cannot read input file: {e}"),
        })?;
        self.run_text(&text, &name)
    }

    /// Run script text; `name` is used in error messages.
    pub fn run_text(&mut self, text: &str, name: &str) -> Result<(), ScriptError> {
        let mut name = name.to_string();
        let mut lines = logical_lines(text);
        let mut k = 0;
        // `jump FILE LABEL`: the label searched for (lines are skipped, unsubstituted, until
        // `label LABEL`), and the line of that jump.
        let mut seeking: Option<(String, usize)> = None;
        while k < lines.len() {
            let raw = &lines[k];
            k += 1;
            let line = raw.line;
            let err = |command: &str, message: String| ScriptError {
                file: name.clone(),
                line,
                command: command.to_string(),
                message,
            };
            let body = strip_comment(&raw.text);
            if body.trim().is_empty() {
                continue;
            }
            if let Some((label, _)) = &seeking {
                if control::is_label(body, label) {
                    seeking = None;
                }
                continue;
            }
            let first = body.split_whitespace().next().unwrap_or("").to_string();
            let substituted = self.substitute(body).map_err(|m| err(&first, m))?;
            let words = split_words(strip_comment(&substituted)).map_err(|m| err(&first, m))?;
            let Some((cmd, args)) = words.split_first() else {
                continue;
            };
            if let Some(r) = self.state_command(raw.line, cmd, args) {
                r.map_err(|m| err(cmd, m))?;
                continue;
            }
            if cmd == "include" {
                self.include(args)
                    .map_err(|e| e.unwrap_or_else(|m| err(cmd, m)))?;
                continue;
            }
            self.command(cmd, args).map_err(|m| err(cmd, m))?;
            if let Some(jump) = self.flow.pending.take() {
                self.flow
                    .count_jump(self.max_steps)
                    .map_err(|m| err("jump", m))?;
                if let Some(file) = jump.file {
                    let text = std::fs::read_to_string(&file).map_err(|e| {
                        err(
                            "jump",
                            format!("cannot read '{}': {e}", crate::grammar::shown(&file)),
                        )
                    })?;
                    lines = logical_lines(&text);
                    name = file;
                }
                k = 0;
                seeking = jump.label.map(|l| (l, line));
            }
        }
        if let Some((label, line)) = seeking {
            let message = format!(
                "label '{label}' not found in {}",
                crate::grammar::shown(&name)
            );
            return Err(ScriptError {
                file: name,
                line,
                command: "jump".into(),
                message,
            });
        }
        self.flush_outputs();
        Ok(())
    }

    /// `include FILE`: its errors are the included file's (`Err(Ok(e))`), or this line's
    /// (`Err(Err(message))`: a missing file, too deep).
    fn include(&mut self, args: &[String]) -> Result<(), Result<ScriptError, String>> {
        if args.len() != 1 {
            return Err(Err("usage: include FILE".into()));
        }
        if self.depth > 16 {
            return Err(Err("include nested more than 16 deep".into()));
        }
        // A missing file is an error of this line (file and line of the `include`).
        let text = std::fs::read_to_string(&args[0]).map_err(|e| {
            Err(format!(
                "cannot read '{}': {e}",
                crate::grammar::shown(&args[0])
            ))
        })?;
        self.depth += 1;
        let r = self.run_text(&text, &args[0]);
        self.depth -= 1;
        r.map_err(Ok)
    }

    // ------------------------------------------------------------------ variables

    fn var_string(&self, name: &str) -> Result<String, String> {
        match self.vars.get(name) {
            None => Err(format!("variable '{name}' is not defined")),
            Some(Var::Index(v, at)) => Ok(v[*at].clone()),
            Some(Var::Str(s)) => Ok(s.clone()),
            Some(Var::Equal(e)) => {
                let v = self.eval(e)?;
                sprintf("%.15g", &[FmtArg::Float(v)])
            }
            Some(Var::Atom(_)) => Err(format!(
                "variable '{name}' is atom-style: it has no single value to substitute"
            )),
        }
    }

    fn eval(&self, expr: &str) -> Result<f64, String> {
        eval_equal(expr, &Ctx(self, 0))
    }

    fn substitute(&self, s: &str) -> Result<String, String> {
        if !s.contains('$') {
            return Ok(s.to_string());
        }
        let mut out = String::with_capacity(s.len());
        let mut i = 0;
        let b = s.as_bytes();
        while i < b.len() {
            // As LAMMPS's `Input::substitute`: text in single, double or triple quotes is
            // copied as it is (the commands that take such text, `print`, `if`, `fix print`,
            // `run every`, substitute it themselves when they use it). An unmatched quote
            // copies the rest (the word split reports it).
            let quote = if s[i..].starts_with("\"\"\"") {
                Some("\"\"\"")
            } else if b[i] == b'"' {
                Some("\"")
            } else if b[i] == b'\'' {
                Some("'")
            } else {
                None
            };
            if let Some(q) = quote {
                let end = s[i + q.len()..]
                    .find(q)
                    .map_or(s.len(), |e| i + q.len() + e + q.len());
                out.push_str(&s[i..end]);
                i = end;
                continue;
            }
            let c = b[i];
            if c != b'$' || i + 1 >= b.len() {
                let ch = s[i..].chars().next().unwrap_or(' ');
                out.push(ch);
                i += ch.len_utf8();
                continue;
            }
            match b[i + 1] {
                b'{' => {
                    let end = s[i + 2..]
                        .find('}')
                        .ok_or_else(|| format!("unterminated ${{ in: {s}"))?;
                    let name = &s[i + 2..i + 2 + end];
                    out.push_str(&self.var_string(name)?);
                    i += end + 3;
                }
                b'(' => {
                    let mut level = 0;
                    let mut end = None;
                    for (k, ch) in s[i + 1..].char_indices() {
                        match ch {
                            '(' => level += 1,
                            ')' => {
                                level -= 1;
                                if level == 0 {
                                    end = Some(i + 1 + k);
                                    break;
                                }
                            }
                            _ => {}
                        }
                    }
                    let end = end.ok_or_else(|| format!("unterminated $( in: {s}"))?;
                    let inner = &s[i + 2..end];
                    let (expr, fmtstr) = match inner.rsplit_once(":%") {
                        Some((e, f)) => (e, format!("%{f}")),
                        None => (inner, "%.20g".to_string()),
                    };
                    let v = self.eval(expr)?;
                    out.push_str(&sprintf(&fmtstr, &[FmtArg::Float(v)])?);
                    i = end + 1;
                }
                _ => {
                    // A one-character name ($x); the character, not its first byte (`$é`
                    // names 'é').
                    let ch = s[i + 1..].chars().next().unwrap_or(' ');
                    out.push_str(&self.var_string(&ch.to_string())?);
                    i += 1 + ch.len_utf8();
                }
            }
        }
        Ok(out)
    }

    // ------------------------------------------------------------------ commands

    /// The per-atom virial tally on while a `compute stress/atom` is defined (LAMMPS's
    /// `vflag_atom`; off, the force loop is as without it).
    fn sync_virial_atom(&mut self) {
        let on = self.obs.wants_virial_atom();
        if let Some(s) = self.system_mut() {
            s.set_virial_atom(on);
        }
    }

    fn sys_mut(&mut self) -> Result<&mut System, String> {
        self.sys
            .as_mut()
            .ok_or_else(|| "needs a simulation box (create_box or read_data) first".to_string())
    }

    fn command(&mut self, cmd: &str, args: &[String]) -> CmdResult {
        if self.dry_run && dry_run_skips(cmd, args) {
            return Ok(());
        }
        match cmd {
            c if IGNORED_COMMANDS.contains(&c) => Ok(()),
            "comm_modify" => self.cmd_comm_modify(args),
            "units" => self.cmd_units(args),
            "dimension" => self.cmd_dimension(args),
            "boundary" => Self::cmd_boundary(args),
            "atom_style" => self.cmd_atom_style(args),
            "variable" => self.cmd_variable(args),
            "region" => self.cmd_region(args),
            "group" => self.cmd_group(args),
            "create_box" => self.cmd_create_box(args),
            "create_atoms" => self.cmd_create_atoms(args),
            "read_data" => self.cmd_read_data(args),
            "bond_style" => self.cmd_bond_style(args),
            "bond_coeff" => self.cmd_bond_coeff(args),
            "angle_style" => self.cmd_angle_style(args),
            "angle_coeff" => self.cmd_angle_coeff(args),
            "special_bonds" => self.cmd_special_bonds(args),
            "write_data" => self.cmd_write_data(args),
            "mass" => self.cmd_mass(args),
            "velocity" => self.cmd_velocity(args),
            "pair_style" => self.cmd_pair_style(args),
            "pair_coeff" => self.cmd_pair_coeff(args),
            "neighbor" => self.cmd_neighbor(args),
            "timestep" => self.cmd_timestep(args),
            "fix" => self.cmd_fix(args),
            "unfix" => self.cmd_unfix(args),
            "compute" => {
                let c = Observe::parse_compute(args, &*self)?;
                self.obs.add_compute(c);
                self.sync_virial_atom();
                Ok(())
            }
            "uncompute" => {
                need(args, 1, "uncompute ID")?;
                crate::grammar::at_most(args, 1, "uncompute ID")?;
                self.obs.uncompute(&args[0])?;
                self.sync_virial_atom();
                Ok(())
            }
            "thermo" => {
                need(args, 1, "thermo N")?;
                crate::grammar::at_most(args, 1, "thermo N")?;
                self.thermo.every = parse_int(&args[0], "thermo interval")?;
                Ok(())
            }
            "thermo_style" => self.cmd_thermo_style(args),
            "thermo_modify" => self.cmd_thermo_modify(args),
            "dump" => self.cmd_dump(args),
            "dump_modify" => self.cmd_dump_modify(args),
            "undump" => self.cmd_undump(args),
            "run" => {
                self.runs_started += 1;
                self.cmd_run(args)
            }
            "run_style" => run::cmd_run_style(args),
            "write_dump" => self.cmd_write_dump(args),
            "if" => self.cmd_if(args),
            "label" => control::cmd_label(args),
            "jump" => self.cmd_jump(args),
            "next" => self.cmd_next(args),
            "change_box" => self.cmd_change_box(args),
            "reset_timestep" => self.cmd_reset_timestep(args),
            "print" => self.cmd_print(args),
            "log" => self.cmd_log(args),
            "write_restart" => self.cmd_write_restart(args),
            "read_restart" => self.cmd_read_restart(args),
            "restart" => self.cmd_restart(args),
            _ => Err(format!(
                "unknown command '{cmd}' (see docs/input.md for the supported subset)"
            )),
        }
    }
}

impl Interpreter<'_> {
    /// Consume the interpreter, returning the system (if a box was created).
    pub fn into_system(self) -> Option<System> {
        self.sys
    }
}

impl observe::Env for Interpreter<'_> {
    fn system(&self) -> Option<&System> {
        self.sys.as_ref()
    }
    fn observe(&self) -> &Observe {
        &self.obs
    }
    fn var_style(&self, name: &str) -> VarStyle {
        match self.vars.get(name) {
            None => VarStyle::Undefined,
            Some(Var::Equal(_)) => VarStyle::Equal,
            Some(Var::Atom(_)) => VarStyle::Atom,
            Some(_) => VarStyle::Other,
        }
    }
    fn equal_variable(&self, name: &str) -> Result<f64, String> {
        Ctx(self, 0).variable(name)
    }
    fn atom_variable(&self, name: &str) -> Result<Vec<f64>, String> {
        let sys = self.sys.as_ref().ok_or("needs a simulation box")?;
        let f = Ctx(self, 0)
            .atom_variable(name)
            .ok_or_else(|| format!("variable '{name}' is not an atom-style variable"))??;
        observe::eval_atoms(&f, sys).map_err(|e| format!("atom-style variable '{name}': {e}"))
    }
}
