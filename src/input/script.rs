//! The interpreter of the LAMMPS-input subset (see `docs/input.md` for the full list).
//!
//! Every command is parsed and validated once, into the engine's typed values; every error names
//! the file, the line and the command. Output (what LAMMPS prints to the screen and the log) goes
//! to a [`Console`] supplied by the caller and to the log file.

use super::expr::{AtomBinder, ExprContext, Formula, RefKind, eval_equal};
use super::format::{FmtArg, sprintf};
use super::lexer::{logical_lines, split_words, strip_comment};
use super::observe::{self, Observe, VarStyle};
use crate::engine::lees_edwards::{Deform, Triclinic};
use crate::engine::{ForceField, Integrator, PexPush, SetupNote, SimBox, System};
use crate::grammar;
use crate::io::data::{DataFile, format_data, parse_data};
use crate::kernel::{PairCoeff, PairModel};
use crate::rng::{STREAM_CREATE_ATOMS, STREAM_VELOCITY, keyed_gaussian, keyed_uniform};
use std::collections::BTreeMap;
use std::fmt;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where the interpreter's screen output goes (the library never prints by itself).
pub trait Console {
    /// One line of output (no trailing newline).
    fn line(&mut self, text: &str);
    /// Progress of a run: `step` reached, run from `first` to `last`. Called about every second.
    fn progress(&mut self, _step: u64, _first: u64, _last: u64) {}
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
    Index(String),
    Str(String),
    Equal(String),
    /// `variable NAME atom FORMULA` (per-atom values; see `observe`).
    Atom(String),
}

/// Commands accepted and ignored: they only matter to LAMMPS (communication, neighbour
/// bookkeeping, atom maps, Newton's third law flag, processor grids, echo).
pub const IGNORED_COMMANDS: &[&str] = &[
    "comm_modify",
    "neigh_modify",
    "atom_modify",
    "newton",
    "processors",
    "echo",
];

#[derive(Clone, Debug)]
struct ThermoSettings {
    every: u64,
    columns: Vec<String>,
    fmt_line: Option<Vec<String>>,
    fmt_int: Option<String>,
    fmt_float: Option<String>,
    fmt_col: BTreeMap<usize, String>,
    norm: bool,
    /// `thermo_modify temp ID` / `press ID` (None: thermo_temp / thermo_press).
    temp: Option<String>,
    press: Option<String>,
}

impl Default for ThermoSettings {
    fn default() -> Self {
        ThermoSettings {
            every: 0,
            columns: ["step", "temp", "epair", "emol", "etotal", "press"]
                .map(String::from)
                .to_vec(),
            fmt_line: None,
            fmt_int: None,
            fmt_float: None,
            fmt_col: BTreeMap::new(),
            norm: true,
            temp: None,
            press: None,
        }
    }
}

struct Dump {
    id: String,
    every: u64,
    path: String,
    columns: Vec<String>,
    fmt_line: Option<Vec<String>>,
    fmt_int: Option<String>,
    fmt_float: Option<String>,
    writer: BufWriter<File>,
    last: Option<u64>,
}

#[derive(Clone, Debug, PartialEq)]
enum FixKind {
    Nve,
    NveEuler,
    Enforce2d,
    Pex,
    /// `deform … xy erate R remap v` (Lees–Edwards, `engine::lees_edwards`).
    Deform,
    /// `ave/time`, `ave/chunk`, `ave/histo` (in `observe`).
    Observe,
}

/// Run-time options from the command line.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Log file (None: no log file).
    pub log: Option<PathBuf>,
    /// `-var NAME VALUE` definitions (index-style, as LAMMPS's `-var`).
    pub vars: Vec<(String, String)>,
    /// Number of threads the caller configured (printed in "Loop time").
    pub threads: usize,
}

/// The interpreter state.
pub struct Interpreter<'c> {
    console: &'c mut dyn Console,
    log: Option<BufWriter<File>>,
    vars: BTreeMap<String, Var>,
    dim: usize,
    regions: BTreeMap<String, [[f64; 2]; 3]>,
    /// Tilt factors (xy, xz, yz) of `region … prism` regions.
    prisms: BTreeMap<String, [f64; 3]>,
    sys: Option<System>,
    skin: f64,
    dry_run: bool,
    planned: Vec<PlannedRun>,
    dt: f64,
    thermo: ThermoSettings,
    dumps: Vec<Dump>,
    fixes: Vec<(String, FixKind)>,
    threads: usize,
    depth: usize,
    run_first: u64,
    obs: Observe,
}

type CmdResult = Result<(), String>;

/// What a `run` command would run, as seen by its set-up (for `dpdnl theory SCRIPT`): the
/// state point and every pair's resolved coefficients.
#[derive(Clone, Debug)]
pub struct PlannedRun {
    /// Step at which the run starts.
    pub first_step: u64,
    /// Number of steps.
    pub steps: u64,
    /// Dimension (2 or 3).
    pub dim: u32,
    /// Number of atoms.
    pub natoms: usize,
    /// Volume (area in 2-D).
    pub volume: f64,
    /// Per-type masses (index 0 unused).
    pub masses: Vec<f64>,
    /// The pair style's model (kT, friction, noise, weight; δt set).
    pub model: PairModel,
    /// Time step.
    pub dt: f64,
    /// The integrator, if any.
    pub integrator: Option<Integrator>,
    /// (i, j, coefficients) for i ≤ j, after (η, Sc) targets were resolved.
    pub coeffs: Vec<(usize, usize, PairCoeff)>,
    /// The set-up's log lines (resolved designs, warnings).
    pub notes: Vec<SetupNote>,
}

impl PlannedRun {
    fn of(sys: &mut System, steps: u64, notes: Vec<SetupNote>) -> Result<PlannedRun, String> {
        let ff = sys.ff.as_ref().ok_or("no pair style")?;
        let mut coeffs = Vec::new();
        for i in 1..=sys.ntypes {
            for j in i..=sys.ntypes {
                if let Some(c) = ff.get(i, j) {
                    coeffs.push((i, j, *c));
                }
            }
        }
        Ok(PlannedRun {
            first_step: sys.step,
            steps,
            dim: sys.bx.dim as u32,
            natoms: sys.atoms.len(),
            volume: sys.bx.volume(),
            masses: sys.mass.iter().map(|m| m.unwrap_or(0.0)).collect(),
            model: ff.model,
            dt: sys.dt,
            integrator: sys.integrator,
            coeffs,
            notes,
        })
    }
}

/// Commands a dry run ([`Interpreter::set_dry_run`]) skips: everything that writes a file or
/// only matters to the output of a real run.
fn dry_run_skips(cmd: &str, args: &[String]) -> bool {
    matches!(
        cmd,
        "dump" | "dump_modify" | "undump" | "write_data" | "log" | "print"
    ) || (cmd == "fix" && args.get(2).is_some_and(|s| s.starts_with("ave/")))
}

pub use crate::grammar::type_range;
use crate::grammar::{need, parse_f64, parse_int};

/// Rescale all velocities so that the kinetic temperature becomes `t` (current T must be > 0).
fn scale_to(sys: &mut System, t: f64) {
    let s = (t / sys.thermo().temp).sqrt();
    for v in sys.atoms.v.iter_mut() {
        for c in v.iter_mut() {
            *c *= s;
        }
    }
}

/// LAMMPS's header name of a thermo keyword.
fn thermo_header(kw: &str) -> String {
    match kw {
        "step" => "Step".into(),
        "elapsed" => "Elapsed".into(),
        "dt" => "Dt".into(),
        "time" => "Time".into(),
        "atoms" => "Atoms".into(),
        "temp" => "Temp".into(),
        "press" => "Press".into(),
        "ke" => "KinEng".into(),
        "pe" => "PotEng".into(),
        "epair" => "E_pair".into(),
        "evdwl" => "E_vdwl".into(),
        "emol" => "E_mol".into(),
        "etotal" => "TotEng".into(),
        "vol" => "Volume".into(),
        "density" => "Density".into(),
        "pxx" | "pyy" | "pzz" | "pxy" | "pxz" | "pyz" | "lx" | "ly" | "lz" | "xlo" | "xhi"
        | "ylo" | "yhi" | "zlo" | "zhi" | "xy" | "xz" | "yz" => {
            let mut c = kw.chars();
            match c.next() {
                Some(f) => f.to_uppercase().chain(c).collect(),
                None => String::new(),
            }
        }
        other => other.to_string(),
    }
}

fn is_int_keyword(kw: &str) -> bool {
    matches!(kw, "step" | "elapsed" | "atoms")
}

impl<'c> Interpreter<'c> {
    /// A fresh interpreter writing to `console` (and to `opts.log` when set).
    pub fn new(console: &'c mut dyn Console, opts: &Options) -> Result<Interpreter<'c>, String> {
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
            vars.insert(k.clone(), Var::Index(v.clone()));
        }
        Ok(Interpreter {
            console,
            log,
            vars,
            dim: 3,
            regions: BTreeMap::new(),
            prisms: BTreeMap::new(),
            sys: None,
            skin: 0.3,
            dry_run: false,
            planned: Vec::new(),
            dt: 0.005,
            thermo: ThermoSettings::default(),
            dumps: Vec::new(),
            fixes: Vec::new(),
            threads: opts.threads.max(1),
            depth: 0,
            run_first: 0,
            obs: Observe::new(),
        })
    }

    /// Dry run (for `dpdnl theory SCRIPT`): every `run` does its set-up (checks, (η, Sc)
    /// resolution, warnings) and is recorded in [`Interpreter::planned_runs`] instead of being
    /// run; commands that write files (`dump`, `write_data`, `log`, `print`, `fix ave/*`) are
    /// skipped.
    pub fn set_dry_run(&mut self, on: bool) {
        self.dry_run = on;
    }

    /// The runs a dry run recorded, in script order.
    pub fn planned_runs(&self) -> &[PlannedRun] {
        &self.planned
    }

    /// The system, once a box exists.
    pub fn system(&self) -> Option<&System> {
        self.sys.as_ref()
    }

    /// The file names of the dumps currently defined, as given to `dump` (after variable
    /// substitution), in the order they were defined.
    pub fn dump_files(&self) -> Vec<String> {
        self.dumps.iter().map(|d| d.path.clone()).collect()
    }

    fn out(&mut self, text: &str) {
        self.console.line(text);
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
        for raw in logical_lines(text) {
            let err = |command: &str, message: String| ScriptError {
                file: name.to_string(),
                line: raw.line,
                command: command.to_string(),
                message,
            };
            let body = strip_comment(&raw.text);
            if body.trim().is_empty() {
                continue;
            }
            let first = body.split_whitespace().next().unwrap_or("").to_string();
            let substituted = self.substitute(body).map_err(|m| err(&first, m))?;
            let words = split_words(strip_comment(&substituted)).map_err(|m| err(&first, m))?;
            let Some((cmd, args)) = words.split_first() else {
                continue;
            };
            if cmd == "include" {
                if args.len() != 1 {
                    return Err(err(cmd, "usage: include FILE".into()));
                }
                if self.depth > 16 {
                    return Err(err(cmd, "include nested more than 16 deep".into()));
                }
                self.depth += 1;
                let r = self.run_file(Path::new(&args[0]));
                self.depth -= 1;
                r?;
                continue;
            }
            self.command(cmd, args).map_err(|m| err(cmd, m))?;
        }
        if let Some(l) = self.log.as_mut() {
            let _ = l.flush();
        }
        Ok(())
    }

    // ------------------------------------------------------------------ variables

    fn var_string(&self, name: &str) -> Result<String, String> {
        match self.vars.get(name) {
            None => Err(format!("variable '{name}' is not defined")),
            Some(Var::Index(s)) | Some(Var::Str(s)) => Ok(s.clone()),
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
        let mut in_single = false;
        let mut in_triple = false;
        while i < b.len() {
            if !in_single && s[i..].starts_with("\"\"\"") {
                in_triple = !in_triple;
                out.push_str("\"\"\"");
                i += 3;
                continue;
            }
            let c = b[i];
            if c == b'\'' && !in_triple {
                in_single = !in_single;
            }
            if c != b'$' || in_single || in_triple || i + 1 >= b.len() {
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
                other => {
                    let name = (other as char).to_string();
                    out.push_str(&self.var_string(&name)?);
                    i += 2;
                }
            }
        }
        Ok(out)
    }

    // ------------------------------------------------------------------ thermo

    fn thermo_value(&self, kw: &str) -> Option<Result<f64, String>> {
        if let Some(name) = kw.strip_prefix("v_") {
            return Some(self.eval(&format!("v_{name}")));
        }
        if let Some(r) = observe::split_reference(kw) {
            return Some(r.and_then(|(kind, id, index)| {
                let v = self.obs.reference(kind, id, index, self)?;
                let n = self.sys.as_ref().map_or(0, |s| s.atoms.len());
                Ok(
                    if self.thermo.norm && n > 0 && self.obs.extensive(kind, id, index) {
                        v / n as f64
                    } else {
                        v
                    },
                )
            }));
        }
        let no_box = || Some(Err(format!("thermo keyword '{kw}' needs a simulation box")));
        let Some(sys) = self.sys.as_ref() else {
            return match kw {
                "step" | "elapsed" | "dt" | "time" | "atoms" | "temp" | "press" | "pxx" | "pyy"
                | "pzz" | "pxy" | "pxz" | "pyz" | "ke" | "pe" | "epair" | "evdwl" | "emol"
                | "etotal" | "vol" | "lx" | "ly" | "lz" | "density" => no_box(),
                _ => None,
            };
        };
        let n = sys.atoms.len() as f64;
        let norm = if self.thermo.norm && n > 0.0 {
            1.0 / n
        } else {
            1.0
        };
        // The temperature and pressure computes of thermo (LAMMPS: thermo_temp and
        // thermo_press unless thermo_modify temp/press; thermo_press uses thermo_modify's temp).
        let t = match &self.thermo.temp {
            None => sys.thermo(),
            Some(id) => match self.obs.thermo_of_temp(id, sys) {
                Ok(t) => t,
                Err(e) => return Some(Err(e)),
            },
        };
        let p = match self
            .obs
            .thermo_of_press(self.thermo.press.as_deref().unwrap_or("thermo_press"), sys)
        {
            Ok(p) => p,
            Err(e) => return Some(Err(e)),
        };
        let len = sys.bx.len();
        let v = match kw {
            "step" => sys.step as f64,
            "elapsed" => (sys.step - self.run_first) as f64,
            "dt" => self.dt,
            "time" => sys.step as f64 * self.dt,
            "atoms" => n,
            "temp" => t.temp,
            "press" => p.press,
            "pxx" => p.p_tensor[0],
            "pyy" => p.p_tensor[1],
            "pzz" => p.p_tensor[2],
            "pxy" => p.p_tensor[3],
            "pxz" => p.p_tensor[4],
            "pyz" => p.p_tensor[5],
            "xy" => sys.tri.as_ref().map_or(0.0, |tr| tr.reported_xy(&sys.bx)),
            "xz" | "yz" => 0.0,
            "ke" => t.ke * norm,
            "pe" | "epair" | "evdwl" => t.pe * norm,
            "emol" => 0.0,
            "etotal" => (t.ke + t.pe) * norm,
            "vol" => t.vol,
            "lx" => len[0],
            "ly" => len[1],
            "lz" => len[2],
            "xlo" => sys.bx.lo[0],
            "xhi" => sys.bx.hi[0],
            "ylo" => sys.bx.lo[1],
            "yhi" => sys.bx.hi[1],
            "zlo" => sys.bx.lo[2],
            "zhi" => sys.bx.hi[2],
            "density" => {
                let m: f64 = sys
                    .atoms
                    .typ
                    .iter()
                    .map(|&ty| sys.mass[ty as usize].unwrap_or(0.0))
                    .sum();
                m / t.vol
            }
            _ => return None,
        };
        Some(Ok(v))
    }

    fn thermo_header_line(&self) -> String {
        self.thermo
            .columns
            .iter()
            .map(|c| thermo_header(c))
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn thermo_row(&self) -> Result<String, String> {
        let mut fields = Vec::with_capacity(self.thermo.columns.len());
        for (k, kw) in self.thermo.columns.iter().enumerate() {
            let v = self
                .thermo_value(kw)
                .ok_or_else(|| format!("unknown thermo keyword '{kw}'"))??;
            let int = is_int_keyword(kw);
            let fmtstr = self
                .thermo
                .fmt_col
                .get(&(k + 1))
                .cloned()
                .or_else(|| {
                    self.thermo
                        .fmt_line
                        .as_ref()
                        .and_then(|l| l.get(k).cloned())
                })
                .or_else(|| {
                    if int {
                        self.thermo.fmt_int.clone()
                    } else {
                        self.thermo.fmt_float.clone()
                    }
                })
                .unwrap_or_else(|| if int { "%10d".into() } else { "%14.8g".into() });
            let arg = if int {
                FmtArg::Int(v as i64)
            } else {
                FmtArg::Float(v)
            };
            fields.push(sprintf(&fmtstr, &[arg])?);
        }
        Ok(fields.join(" "))
    }

    // ------------------------------------------------------------------ commands

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
            "units" => {
                need(args, 1, "units lj")?;
                if args[0] != "lj" {
                    return Err(format!("units '{}' not supported: only 'lj'", args[0]));
                }
                Ok(())
            }
            "dimension" => {
                need(args, 1, "dimension 2|3")?;
                if self.sys.is_some() {
                    return Err("dimension must be set before the box is created".into());
                }
                self.dim = match args[0].as_str() {
                    "2" => 2,
                    "3" => 3,
                    o => return Err(format!("dimension '{o}' must be 2 or 3")),
                };
                Ok(())
            }
            "boundary" => {
                need(args, 3, "boundary p p p")?;
                if args.iter().take(3).any(|a| a != "p") {
                    return Err(format!(
                        "boundary '{}': only fully periodic boxes ('p p p') are supported",
                        args.join(" ")
                    ));
                }
                Ok(())
            }
            "atom_style" => {
                need(args, 1, "atom_style atomic")?;
                if args[0] != "atomic" {
                    return Err(format!(
                        "atom_style '{}' not supported: only 'atomic'",
                        args[0]
                    ));
                }
                Ok(())
            }
            "variable" => self.cmd_variable(args),
            "region" => self.cmd_region(args),
            "create_box" => self.cmd_create_box(args),
            "create_atoms" => self.cmd_create_atoms(args),
            "read_data" => self.cmd_read_data(args),
            "write_data" => self.cmd_write_data(args),
            "mass" => {
                need(args, 2, "mass TYPE(S) VALUE")?;
                let m = parse_f64(&args[1], "mass")?;
                if m <= 0.0 {
                    return Err(format!("mass {m} must be > 0"));
                }
                let sys = self.sys_mut()?;
                let (lo, hi) = type_range(&args[0], sys.ntypes)?;
                for t in lo..=hi {
                    sys.mass[t] = Some(m);
                }
                Ok(())
            }
            "velocity" => self.cmd_velocity(args),
            "pair_style" => self.cmd_pair_style(args),
            "pair_coeff" => self.cmd_pair_coeff(args),
            "neighbor" => {
                need(args, 2, "neighbor SKIN bin")?;
                let skin = parse_f64(&args[0], "skin")?;
                if skin < 0.0 {
                    return Err(format!("skin {skin} must be >= 0"));
                }
                if !["bin", "nsq", "multi"].contains(&args[1].as_str()) {
                    return Err(format!("unknown neighbor style '{}'", args[1]));
                }
                self.skin = skin;
                if let Some(s) = self.sys.as_mut() {
                    s.neighbor = crate::engine::NeighborList::new(skin);
                }
                Ok(())
            }
            "timestep" => {
                need(args, 1, "timestep DT")?;
                let dt = parse_f64(&args[0], "timestep")?;
                if dt <= 0.0 {
                    return Err(format!("timestep {dt} must be > 0"));
                }
                self.dt = dt;
                if let Some(s) = self.sys.as_mut() {
                    s.dt = dt;
                }
                Ok(())
            }
            "fix" => self.cmd_fix(args),
            "unfix" => {
                need(args, 1, "unfix ID")?;
                let pos = self
                    .fixes
                    .iter()
                    .position(|(id, _)| id == &args[0])
                    .ok_or_else(|| format!("no fix with ID '{}'", args[0]))?;
                if let Some(user) = self.obs.fix_user(&args[0]) {
                    return Err(format!("fix '{}' is used by fix '{user}'", args[0]));
                }
                let (id, kind) = self.fixes.remove(pos);
                if let Some(sys) = self.sys.as_mut() {
                    match kind {
                        FixKind::Nve | FixKind::NveEuler => sys.integrator = None,
                        FixKind::Pex => sys.pex.retain(|p| p.id != id),
                        FixKind::Deform => {
                            if let Some(t) = sys.tri.as_mut() {
                                t.deform = None;
                            }
                        }
                        FixKind::Enforce2d => {}
                        FixKind::Observe => {
                            self.obs.unfix(&id);
                        }
                    }
                }
                Ok(())
            }
            "compute" => {
                let c = Observe::parse_compute(args, &*self)?;
                self.obs.add_compute(c);
                Ok(())
            }
            "uncompute" => {
                need(args, 1, "uncompute ID")?;
                self.obs.uncompute(&args[0])
            }
            "thermo" => {
                need(args, 1, "thermo N")?;
                self.thermo.every = parse_int(&args[0], "thermo interval")?;
                Ok(())
            }
            "thermo_style" => self.cmd_thermo_style(args),
            "thermo_modify" => self.cmd_thermo_modify(args),
            "dump" => self.cmd_dump(args),
            "dump_modify" => self.cmd_dump_modify(args),
            "undump" => {
                need(args, 1, "undump ID")?;
                let before = self.dumps.len();
                self.dumps.retain(|d| d.id != args[0]);
                if self.dumps.len() == before {
                    return Err(format!("no dump with ID '{}'", args[0]));
                }
                Ok(())
            }
            "run" => self.cmd_run(args),
            "change_box" => {
                need(args, 2, "change_box all triclinic")?;
                if args[0] != "all" {
                    return Err(format!("group '{}' not supported: only 'all'", args[0]));
                }
                if let Some(o) = args[1..].iter().find(|a| *a != "triclinic") {
                    return Err(format!(
                        "change_box keyword '{o}' not supported: only 'change_box all triclinic'"
                    ));
                }
                let sys = self.sys_mut()?;
                if sys.tri.is_none() {
                    sys.tri = Some(Triclinic::new(0.0));
                }
                Ok(())
            }
            "reset_timestep" => {
                need(args, 1, "reset_timestep N")?;
                let n: u64 = parse_int(&args[0], "timestep")?;
                self.sys_mut()?.step = n;
                Ok(())
            }
            "print" => {
                need(args, 1, "print TEXT [file F] [append F] [screen yes|no]")?;
                let mut screen = true;
                let mut file: Option<(String, bool)> = None;
                let mut k = 1;
                while k < args.len() {
                    need(
                        &args[k..],
                        2,
                        "print TEXT [file F] [append F] [screen yes|no]",
                    )?;
                    match args[k].as_str() {
                        "file" => file = Some((args[k + 1].clone(), false)),
                        "append" => file = Some((args[k + 1].clone(), true)),
                        "screen" => screen = args[k + 1] == "yes",
                        o => return Err(format!("unknown print keyword '{o}'")),
                    }
                    k += 2;
                }
                if let Some((path, append)) = file {
                    let mut f = std::fs::OpenOptions::new()
                        .create(true)
                        .write(true)
                        .append(append)
                        .truncate(!append)
                        .open(&path)
                        .map_err(|e| format!("cannot open {path}: {e}"))?;
                    writeln!(f, "{}", args[0]).map_err(|e| format!("cannot write {path}: {e}"))?;
                }
                if screen {
                    self.out(&args[0]);
                } else if let Some(l) = self.log.as_mut() {
                    let _ = writeln!(l, "{}", args[0]);
                }
                Ok(())
            }
            "log" => {
                need(args, 1, "log FILE [append]")?;
                let append = args.get(1).is_some_and(|a| a == "append");
                if let Some(mut l) = self.log.take() {
                    let _ = l.flush();
                }
                if args[0] != "none" {
                    let f = std::fs::OpenOptions::new()
                        .create(true)
                        .write(true)
                        .append(append)
                        .truncate(!append)
                        .open(&args[0])
                        .map_err(|e| format!("cannot open log file {}: {e}", args[0]))?;
                    self.log = Some(BufWriter::new(f));
                }
                Ok(())
            }
            "write_restart" | "read_restart" => Err(format!(
                "'{cmd}' is LAMMPS-only; in the standalone engine use write_data/read_data (state incl. velocities)"
            )),
            _ => Err(format!(
                "unknown command '{cmd}' (see docs/input.md for the supported subset)"
            )),
        }
    }

    fn cmd_variable(&mut self, args: &[String]) -> CmdResult {
        need(args, 2, "variable NAME STYLE ARGS…")?;
        let name = args[0].clone();
        if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("variable name '{name}' must be alphanumeric or _"));
        }
        match args[1].as_str() {
            "delete" => {
                self.vars.remove(&name);
            }
            "index" => {
                need(args, 3, "variable NAME index VALUE…")?;
                if args.len() > 3 {
                    return Err(
                        "index variables with several values (loops with next) are not supported"
                            .into(),
                    );
                }
                // As LAMMPS: an index variable already defined (e.g. by -var) is kept.
                self.vars.entry(name).or_insert(Var::Index(args[2].clone()));
            }
            "string" => {
                need(args, 3, "variable NAME string VALUE")?;
                self.vars.insert(name, Var::Str(args[2].clone()));
            }
            "equal" => {
                need(args, 3, "variable NAME equal FORMULA")?;
                self.vars.insert(name, Var::Equal(args[2..].join(" ")));
            }
            "atom" => {
                need(args, 3, "variable NAME atom FORMULA")?;
                let f = args[2..].join(" ");
                Formula::parse(&f)?;
                self.vars.insert(name, Var::Atom(f));
            }
            o => {
                return Err(format!(
                    "variable style '{o}' not supported (index, string, equal, atom, delete)"
                ));
            }
        }
        Ok(())
    }

    fn cmd_region(&mut self, args: &[String]) -> CmdResult {
        let usage = "region ID block xlo xhi ylo yhi zlo zhi [units box|lattice] | region ID prism xlo xhi ylo yhi zlo zhi xy xz yz [units box|lattice]";
        need(args, 8, usage)?;
        let prism = match args[1].as_str() {
            "block" => None,
            "prism" => {
                need(args, 11, usage)?;
                let mut t = [0.0; 3];
                for (k, name) in ["xy", "xz", "yz"].iter().enumerate() {
                    t[k] = parse_f64(&args[8 + k], name)?;
                }
                if t[1] != 0.0 || t[2] != 0.0 {
                    return Err(format!(
                        "region prism: tilt xz '{}' yz '{}' not supported: only xy (Lees–Edwards Couette flow)",
                        args[9], args[10]
                    ));
                }
                Some(t)
            }
            o => {
                return Err(format!(
                    "region style '{o}' not supported: only 'block' and 'prism'"
                ));
            }
        };
        let mut k = if prism.is_some() { 11 } else { 8 };
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            match (args[k].as_str(), args[k + 1].as_str()) {
                ("units", "box") | ("units", "lattice") => {}
                ("side", "in") => {}
                (a, b) => return Err(format!("unsupported region keyword '{a} {b}'")),
            }
            k += 2;
        }
        let mut b = [[0.0; 2]; 3];
        for d in 0..3 {
            for s in 0..2 {
                let tok = &args[2 + 2 * d + s];
                b[d][s] = match tok.as_str() {
                    "INF" | "EDGE" => {
                        let sys = self
                            .sys
                            .as_ref()
                            .ok_or_else(|| format!("'{tok}' in a region needs an existing box"))?;
                        if s == 0 { sys.bx.lo[d] } else { sys.bx.hi[d] }
                    }
                    _ => parse_f64(tok, "region bound")?,
                };
            }
            if b[d][0] >= b[d][1] {
                return Err(format!(
                    "region {} bounds in {}: lo {} >= hi {}",
                    args[0],
                    ["x", "y", "z"][d],
                    b[d][0],
                    b[d][1]
                ));
            }
        }
        self.regions.insert(args[0].clone(), b);
        match prism {
            Some(t) => {
                self.prisms.insert(args[0].clone(), t);
            }
            None => {
                self.prisms.remove(&args[0]);
            }
        }
        Ok(())
    }

    fn region(&self, id: &str) -> Result<[[f64; 2]; 3], String> {
        self.regions
            .get(id)
            .copied()
            .ok_or_else(|| format!("no region with ID '{id}'"))
    }

    fn new_system(&mut self, ntypes: usize, lo: [f64; 3], hi: [f64; 3]) -> CmdResult {
        if self.sys.is_some() {
            return Err("a simulation box already exists".into());
        }
        if ntypes == 0 {
            return Err("the number of atom types must be >= 1".into());
        }
        let bx = SimBox::new(self.dim, lo, hi)?;
        let mut sys = System::new(bx, ntypes);
        sys.dt = self.dt;
        sys.neighbor = crate::engine::NeighborList::new(self.skin);
        self.sys = Some(sys);
        Ok(())
    }

    fn cmd_create_box(&mut self, args: &[String]) -> CmdResult {
        need(args, 2, "create_box NTYPES REGION-ID")?;
        let ntypes: usize = parse_int(&args[0], "number of atom types")?;
        let r = self.region(&args[1])?;
        self.new_system(
            ntypes,
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
        )?;
        let d = self.dim;
        if let Some(t) = self.prisms.get(&args[1]).copied() {
            let sys = self.sys_mut()?;
            sys.tri = Some(Triclinic::new(t[0]));
            self.out(&format!(
                "Created triclinic box = ({} {} {}) to ({} {} {}) with tilt ({} {} {}) in {d}-D",
                r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], t[0], t[1], t[2]
            ));
            return Ok(());
        }
        self.out(&format!(
            "Created orthogonal box = ({} {} {}) to ({} {} {}) in {d}-D",
            r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1]
        ));
        Ok(())
    }

    fn cmd_create_atoms(&mut self, args: &[String]) -> CmdResult {
        let usage = "create_atoms TYPE random N SEED REGION-ID | create_atoms TYPE single X Y Z";
        need(args, 2, usage)?;
        let dim = self.dim;
        let regions = self.regions.clone();
        let sys = self.sys_mut()?;
        let t: u32 = parse_int(&args[0], "atom type")?;
        if t == 0 || t as usize > sys.ntypes {
            return Err(format!("atom type {t} out of range 1..{}", sys.ntypes));
        }
        let mut next = sys.atoms.max_tag();
        let mut created = 0usize;
        match args[1].as_str() {
            "random" => {
                need(args, 5, usage)?;
                if args.len() > 5 {
                    return Err(format!(
                        "create_atoms random keyword '{}' not supported",
                        args[5]
                    ));
                }
                let n: usize = parse_int(&args[2], "number of atoms")?;
                let seed: u32 = parse_int(&args[3], "seed")?;
                if seed == 0 {
                    return Err("seed must be > 0".into());
                }
                let r = if args[4] == "NULL" {
                    [
                        [sys.bx.lo[0], sys.bx.hi[0]],
                        [sys.bx.lo[1], sys.bx.hi[1]],
                        [sys.bx.lo[2], sys.bx.hi[2]],
                    ]
                } else {
                    *regions
                        .get(&args[4])
                        .ok_or_else(|| format!("no region with ID '{}'", args[4]))?
                };
                let mut lo = [0.0; 3];
                let mut hi = [0.0; 3];
                for d in 0..3 {
                    lo[d] = r[d][0].max(sys.bx.lo[d]);
                    hi[d] = r[d][1].min(sys.bx.hi[d]);
                    if lo[d] >= hi[d] {
                        return Err(format!("region {} does not overlap the box", args[4]));
                    }
                }
                for _ in 0..n {
                    next = next
                        .checked_add(1)
                        .ok_or("atom ids would exceed 2^32 - 1")?;
                    let mut x = [0.0; 3];
                    for d in 0..dim {
                        let u = keyed_uniform(seed, STREAM_CREATE_ATOMS, 0, next, d as u32);
                        x[d] = lo[d] + u * (hi[d] - lo[d]);
                    }
                    sys.atoms.push(next, t, x, [0.0; 3], [0; 3]);
                    created += 1;
                }
            }
            "single" => {
                need(args, 5, usage)?;
                let mut x = [0.0; 3];
                for d in 0..3 {
                    x[d] = parse_f64(&args[2 + d], "coordinate")?;
                }
                if dim == 2 {
                    x[2] = 0.0;
                }
                next = next
                    .checked_add(1)
                    .ok_or("atom ids would exceed 2^32 - 1")?;
                let mut im = [0; 3];
                sys.bx.wrap(&mut x, &mut im);
                sys.atoms.push(next, t, x, [0.0; 3], [0; 3]);
                created = 1;
            }
            o => {
                return Err(format!(
                    "create_atoms style '{o}' not supported (random, single)"
                ));
            }
        }
        self.out(&format!("Created {created} atoms"));
        Ok(())
    }

    fn cmd_read_data(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "read_data FILE")?;
        if args.len() > 1 {
            return Err(format!("read_data keyword '{}' not supported", args[1]));
        }
        let text = std::fs::read_to_string(&args[0])
            .map_err(|e| format!("cannot read data file {}: {e}", args[0]))?;
        let d = parse_data(&text, &args[0])?;
        if self.dim == 2 && d.atoms.iter().any(|a| a.2[2] != 0.0) {
            return Err(format!(
                "{}: a 2-D system needs z = 0 for every atom",
                args[0]
            ));
        }
        self.new_system(d.ntypes, d.lo, d.hi)?;
        let sys = self.sys_mut()?;
        let mut index = BTreeMap::new();
        for (k, &(tag, t, x, im)) in d.atoms.iter().enumerate() {
            sys.atoms.push(tag, t, x, [0.0; 3], im);
            index.insert(tag, k);
        }
        for (tag, v) in &d.velocities {
            let k = index
                .get(tag)
                .ok_or_else(|| format!("{}: Velocities for unknown atom id {tag}", args[0]))?;
            sys.atoms.v[*k] = *v;
        }
        for (t, m) in d.masses.iter().enumerate() {
            if m.is_some() {
                sys.mass[t] = *m;
            }
        }
        let n = d.atoms.len();
        self.out(&format!(
            "Read data file {}: {n} atoms, {} atom types",
            args[0], d.ntypes
        ));
        Ok(())
    }

    fn cmd_write_data(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "write_data FILE [nocoeff]")?;
        for a in &args[1..] {
            if a != "nocoeff" {
                return Err(format!("write_data keyword '{a}' not supported"));
            }
        }
        let sys = self.sys.as_ref().ok_or("needs a simulation box first")?;
        if sys.is_triclinic() {
            return Err(
                "write_data of a triclinic (Lees–Edwards) box is not supported: read_data could not read its tilt back"
                    .into(),
            );
        }
        let mut order: Vec<usize> = (0..sys.atoms.len()).collect();
        order.sort_by_key(|&i| sys.atoms.tag[i]);
        let mut atoms = Vec::with_capacity(order.len());
        let mut vels = Vec::with_capacity(order.len());
        for &i in &order {
            let mut x = sys.atoms.x[i];
            let mut im = sys.atoms.image[i];
            sys.bx.wrap(&mut x, &mut im);
            atoms.push((sys.atoms.tag[i], sys.atoms.typ[i], x, im));
            vels.push((sys.atoms.tag[i], sys.atoms.v[i]));
        }
        let d = DataFile {
            ntypes: sys.ntypes,
            lo: sys.bx.lo,
            hi: sys.bx.hi,
            masses: sys.mass.clone(),
            atoms,
            velocities: vels,
        };
        let title = format!(
            "LAMMPS data file via write_data (dpdnl), timestep = {}",
            sys.step
        );
        std::fs::write(&args[0], format_data(&d, &title))
            .map_err(|e| format!("cannot write {}: {e}", args[0]))
    }

    fn cmd_velocity(&mut self, args: &[String]) -> CmdResult {
        let usage = "velocity all create T SEED [dist uniform|gaussian] [mom yes|no] [rot no] [loop all|local|geom] | velocity all set VX VY VZ [sum yes|no] | velocity all zero linear | velocity all scale T";
        need(args, 2, usage)?;
        if args[0] != "all" {
            return Err(format!("group '{}' not supported: only 'all'", args[0]));
        }
        let dim = self.dim;
        let sys = self.sys_mut()?;
        if sys.mass.iter().skip(1).any(|m| m.is_none()) {
            return Err("all masses must be set before velocity".into());
        }
        let n = sys.atoms.len();
        let mass = |sys: &System, i: usize| sys.mass[sys.atoms.typ[i] as usize].unwrap_or(1.0);
        let zero_momentum = |sys: &mut System| {
            let p = sys.momentum();
            let mtot: f64 = (0..sys.atoms.len()).map(|i| mass(sys, i)).sum();
            for v in sys.atoms.v.iter_mut() {
                for k in 0..3 {
                    v[k] -= p[k] / mtot;
                }
            }
        };
        match args[1].as_str() {
            "create" => {
                need(args, 4, usage)?;
                let t = parse_f64(&args[2], "temperature")?;
                if t < 0.0 {
                    return Err(format!("temperature {t} must be >= 0"));
                }
                let seed: u32 = parse_int(&args[3], "seed")?;
                if seed == 0 {
                    return Err("seed must be > 0".into());
                }
                let mut gaussian = false;
                let mut mom = true;
                let mut k = 4;
                while k < args.len() {
                    need(&args[k..], 2, usage)?;
                    let val = args[k + 1].as_str();
                    match args[k].as_str() {
                        "dist" => {
                            gaussian = match val {
                                "uniform" => false,
                                "gaussian" => true,
                                o => return Err(format!("dist '{o}' must be uniform or gaussian")),
                            }
                        }
                        "mom" => mom = val == "yes",
                        "rot" => {
                            if val != "no" {
                                return Err("rot yes is not supported (periodic systems)".into());
                            }
                        }
                        "loop" | "sum" => {}
                        o => return Err(format!("unknown velocity keyword '{o}'")),
                    }
                    k += 2;
                }
                for i in 0..n {
                    let tag = sys.atoms.tag[i];
                    let f = 1.0 / mass(sys, i).sqrt();
                    let mut v = [0.0; 3];
                    for (d, vd) in v.iter_mut().enumerate().take(dim) {
                        *vd = f * if gaussian {
                            keyed_gaussian(seed, STREAM_VELOCITY, 0, tag, d as u32)
                        } else {
                            keyed_uniform(seed, STREAM_VELOCITY, 0, tag, d as u32) - 0.5
                        };
                    }
                    sys.atoms.v[i] = v;
                }
                if mom {
                    zero_momentum(sys);
                }
                if sys.thermo().temp > 0.0 {
                    scale_to(sys, t);
                }
            }
            "set" => {
                need(args, 5, usage)?;
                let mut val = [None; 3];
                for d in 0..3 {
                    if args[2 + d] != "NULL" {
                        val[d] = Some(parse_f64(&args[2 + d], "velocity")?);
                    }
                }
                let mut sum = false;
                let mut k = 5;
                while k < args.len() {
                    need(&args[k..], 2, usage)?;
                    match (args[k].as_str(), args[k + 1].as_str()) {
                        ("sum", v) => sum = v == "yes",
                        ("units", "box") | ("units", "lattice") => {}
                        (o, _) => return Err(format!("unknown velocity set keyword '{o}'")),
                    }
                    k += 2;
                }
                for v in sys.atoms.v.iter_mut() {
                    for d in 0..dim {
                        if let Some(x) = val[d] {
                            v[d] = if sum { v[d] + x } else { x };
                        }
                    }
                }
            }
            "ramp" => {
                // LAMMPS: v_a = vlo + f (vhi − vlo), f = (x_d − clo)/(chi − clo) clamped to
                // [0, 1]; `sum yes` adds it to the current velocity.
                let usage = "velocity all ramp vx|vy|vz VLO VHI x|y|z CLO CHI [sum yes|no] [units box|lattice]";
                need(args, 8, usage)?;
                let comp = |t: &str, names: [&str; 3]| {
                    names
                        .iter()
                        .position(|n| *n == t)
                        .ok_or_else(|| format!("velocity ramp: '{t}' must be one of {names:?}"))
                };
                let a = comp(&args[2], ["vx", "vy", "vz"])?;
                let (vlo, vhi) = (
                    parse_f64(&args[3], "velocity")?,
                    parse_f64(&args[4], "velocity")?,
                );
                let c = comp(&args[5], ["x", "y", "z"])?;
                let (clo, chi) = (
                    parse_f64(&args[6], "coordinate")?,
                    parse_f64(&args[7], "coordinate")?,
                );
                if chi <= clo {
                    return Err(format!(
                        "velocity ramp: coordinate range {clo} {chi} is empty"
                    ));
                }
                if a >= dim || c >= dim {
                    return Err("velocity ramp: a z component in a 2-D model".into());
                }
                let mut sum = false;
                let mut k = 8;
                while k < args.len() {
                    need(&args[k..], 2, usage)?;
                    match (args[k].as_str(), args[k + 1].as_str()) {
                        ("sum", v) => sum = v == "yes",
                        ("units", "box") | ("units", "lattice") => {}
                        (o, _) => return Err(format!("unknown velocity ramp keyword '{o}'")),
                    }
                    k += 2;
                }
                for (v, x) in sys.atoms.v.iter_mut().zip(&sys.atoms.x) {
                    let f = ((x[c] - clo) / (chi - clo)).clamp(0.0, 1.0);
                    let u = vlo + f * (vhi - vlo);
                    v[a] = if sum { v[a] + u } else { u };
                }
            }
            "zero" => {
                need(args, 3, usage)?;
                if args[2] != "linear" {
                    return Err(format!("velocity zero '{}': only 'linear'", args[2]));
                }
                zero_momentum(sys);
            }
            "scale" => {
                need(args, 3, usage)?;
                let t = parse_f64(&args[2], "temperature")?;
                if sys.thermo().temp <= 0.0 {
                    return Err("cannot scale a zero temperature".into());
                }
                scale_to(sys, t);
            }
            o => {
                return Err(format!(
                    "velocity style '{o}' not supported (create, set, ramp, zero, scale)"
                ));
            }
        }
        Ok(())
    }

    fn cmd_pair_style(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, grammar::pair::PAIR_STYLE.usage)?;
        if args[0] != "dpd/nonlinear" {
            return Err(format!(
                "pair style '{}' not supported: only dpd/nonlinear",
                grammar::shown(&args[0])
            ));
        }
        let style = grammar::pair::pair_style(&args[1..])?;
        let dt = self.dt;
        let sys = self.sys_mut()?;
        sys.ff = Some(ForceField::new(
            style.model(dt),
            style.seed,
            style.rc,
            sys.ntypes,
        ));
        Ok(())
    }

    /// `pair_coeff I J a gamma0 gamma1 [rc]` or `I J a eta E sc S [gamma1 G] [rc R]` (γ0 and
    /// the weight exponent then come from the targets η and Sc at every run's set-up,
    /// `crate::init::resolve_design`).
    fn cmd_pair_coeff(&mut self, args: &[String]) -> CmdResult {
        let sys = self.sys_mut()?;
        let ntypes = sys.ntypes;
        let ff = sys.ff.as_mut().ok_or("pair_coeff before pair_style")?;
        let line = grammar::pair::pair_coeff(args, ntypes, ff.model.friction, ff.rc_global)?;
        for (i, j) in line.pairs() {
            match line.targets {
                Some((eta, sc)) => ff.set_targets(i, j, line.coeff, eta, sc),
                None => ff.set(i, j, line.coeff),
            }
        }
        Ok(())
    }

    fn cmd_fix(&mut self, args: &[String]) -> CmdResult {
        let usage = "fix ID all nve | nve/euler | enforce2d | pex/push DP [width W] [every N] | ave/time … | ave/chunk … | ave/histo …";
        need(args, 3, usage)?;
        if args[1] != "all" {
            return Err(format!("group '{}' not supported: only 'all'", args[1]));
        }
        let id = args[0].clone();
        if self.fixes.iter().any(|(i, _)| i == &id) {
            return Err(format!("fix ID '{id}' already exists (unfix it first)"));
        }
        if matches!(args[2].as_str(), "ave/time" | "ave/chunk" | "ave/histo") {
            let f = Observe::parse_fix(args, &*self)?;
            self.obs.add_fix(f);
            self.fixes.push((id, FixKind::Observe));
            return Ok(());
        }
        let dim = self.dim;
        let sys = self.sys_mut()?;
        let kind = match args[2].as_str() {
            s @ ("nve" | "nve/euler") => {
                grammar::fix::integrator(s, &args[3..])?;
                if sys.integrator.is_some() {
                    return Err(
                        "only one time-integration fix (nve or nve/euler) is allowed".into(),
                    );
                }
                if s == "nve" {
                    sys.integrator = Some(Integrator::VelocityVerlet);
                    FixKind::Nve
                } else {
                    sys.integrator = Some(Integrator::Euler);
                    FixKind::NveEuler
                }
            }
            "enforce2d" => {
                if dim != 2 {
                    return Err("fix enforce2d needs dimension 2".into());
                }
                FixKind::Enforce2d
            }
            "pex/push" => {
                let p = grammar::fix::pex_push(&args[3..], dim)?;
                sys.pex.push(PexPush {
                    id: id.clone(),
                    dp: p.dp,
                    width: p.width,
                    every: p.every,
                    total: 0.0,
                });
                FixKind::Pex
            }
            "deform" => {
                Self::fix_deform(sys, &id, args)?;
                FixKind::Deform
            }
            o => return Err(format!("fix style '{o}' not supported; {usage}")),
        };
        self.fixes.push((id, kind));
        Ok(())
    }

    /// `fix ID all deform N xy erate R remap v [flip yes|no] [units box|lattice]`: the only
    /// form Couette flow needs (Lees–Edwards, `engine::lees_edwards`).
    fn fix_deform(sys: &mut System, id: &str, args: &[String]) -> CmdResult {
        let usage = "fix ID all deform N xy erate R remap v [flip yes|no] [units box|lattice]";
        need(args, 7, usage)?;
        let every: u64 = parse_int(&args[3], "deform interval N")?;
        if every == 0 {
            return Err("fix deform: N must be >= 1".into());
        }
        if args[4] != "xy" {
            return Err(format!(
                "fix deform parameter '{}' not supported: only 'xy erate R remap v' (Couette flow)",
                args[4]
            ));
        }
        if args[5] != "erate" {
            return Err(format!(
                "fix deform xy style '{}' not supported: only 'erate'",
                args[5]
            ));
        }
        let erate = parse_f64(&args[6], "erate")?;
        if !erate.is_finite() {
            return Err(format!("fix deform: erate '{}' must be finite", args[6]));
        }
        let (mut remap_v, mut flip) = (false, true);
        let mut k = 7;
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            let val = args[k + 1].as_str();
            match (args[k].as_str(), val) {
                ("remap", "v") => remap_v = true,
                ("remap", o) => {
                    return Err(format!(
                        "fix deform remap '{o}' not supported: only 'remap v' (Lees–Edwards)"
                    ));
                }
                ("flip", "yes") => flip = true,
                ("flip", "no") => flip = false,
                ("flip", o) => return Err(format!("fix deform flip '{o}' must be yes or no")),
                ("units", "box" | "lattice") => {}
                (o, _) => {
                    return Err(format!(
                        "fix deform keyword '{o}' not supported; usage: {usage}"
                    ));
                }
            }
            k += 2;
        }
        if !remap_v {
            return Err(
                "fix deform needs 'remap v' here (LAMMPS's default 'remap x' is not supported)"
                    .into(),
            );
        }
        let Some(tri) = sys.tri.as_mut() else {
            return Err(
                "fix deform xy needs a triclinic box (region … prism … or change_box all triclinic)"
                    .into(),
            );
        };
        if tri.deform.is_some() {
            return Err("only one fix deform is allowed".into());
        }
        tri.deform = Some(Deform::new(id.to_string(), every, erate, flip));
        Ok(())
    }

    fn cmd_thermo_style(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "thermo_style custom KEYWORDS… | thermo_style one")?;
        match args[0].as_str() {
            "one" => self.thermo.columns = ThermoSettings::default().columns,
            "custom" => {
                need(args, 2, "thermo_style custom KEYWORDS…")?;
                for kw in &args[1..] {
                    let known = kw.starts_with("v_")
                        || kw.starts_with("f_")
                        || kw.starts_with("c_")
                        || matches!(
                            kw.as_str(),
                            "step"
                                | "elapsed"
                                | "dt"
                                | "time"
                                | "atoms"
                                | "temp"
                                | "press"
                                | "pxx"
                                | "pyy"
                                | "pzz"
                                | "pxy"
                                | "pxz"
                                | "pyz"
                                | "ke"
                                | "pe"
                                | "epair"
                                | "evdwl"
                                | "emol"
                                | "etotal"
                                | "vol"
                                | "lx"
                                | "ly"
                                | "lz"
                                | "xlo"
                                | "xhi"
                                | "ylo"
                                | "yhi"
                                | "zlo"
                                | "zhi"
                                | "xy"
                                | "xz"
                                | "yz"
                                | "density"
                        );
                    if !known {
                        return Err(format!("unknown thermo keyword '{kw}'"));
                    }
                }
                self.thermo.columns = args[1..].to_vec();
            }
            o => return Err(format!("thermo_style '{o}' not supported (one, custom)")),
        }
        self.thermo.fmt_line = None;
        self.thermo.fmt_col.clear();
        // As LAMMPS: a new thermo_style drops thermo_modify's temp and press (thermo_press
        // keeps the temperature thermo_modify gave it).
        if self.thermo.temp.is_some() || self.thermo.press.is_some() {
            self.thermo.temp = None;
            self.thermo.press = None;
            self.warn("New thermo_style command, previous thermo_modify settings will be lost");
        }
        Ok(())
    }

    fn cmd_thermo_modify(&mut self, args: &[String]) -> CmdResult {
        let usage = "thermo_modify norm yes|no | format line|int|float|N FORMAT | flush yes|no | temp ID | press ID";
        need(args, 2, usage)?;
        let mut k = 0;
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            match args[k].as_str() {
                "norm" => self.thermo.norm = args[k + 1] == "yes",
                "flush" | "lost" | "lost/bond" | "warn" => {}
                "temp" => {
                    let id = &args[k + 1];
                    self.obs.set_thermo_temp(id)?;
                    self.thermo.temp = Some(id.clone());
                }
                "press" => {
                    let id = &args[k + 1];
                    if !self.obs.is_pressure(id) {
                        return Err(format!(
                            "thermo_modify press: '{id}' is not a pressure compute"
                        ));
                    }
                    self.thermo.press = Some(id.clone());
                }
                "format" => {
                    need(&args[k..], 3, usage)?;
                    let what = args[k + 1].as_str();
                    let f = args[k + 2].clone();
                    match what {
                        "line" => {
                            self.thermo.fmt_line =
                                Some(f.split_whitespace().map(String::from).collect())
                        }
                        "int" => self.thermo.fmt_int = Some(f),
                        "float" => self.thermo.fmt_float = Some(f),
                        "none" => {
                            self.thermo.fmt_line = None;
                            self.thermo.fmt_int = None;
                            self.thermo.fmt_float = None;
                            self.thermo.fmt_col.clear();
                            k += 2;
                            continue;
                        }
                        n => {
                            let col: usize = parse_int(n, "thermo column")?;
                            if col == 0 || col > self.thermo.columns.len() {
                                return Err(format!("thermo column {col} out of range"));
                            }
                            self.thermo.fmt_col.insert(col, f);
                        }
                    }
                    k += 3;
                    continue;
                }
                o => return Err(format!("unknown thermo_modify keyword '{o}'")),
            }
            k += 2;
        }
        Ok(())
    }

    fn cmd_dump(&mut self, args: &[String]) -> CmdResult {
        let usage = "dump ID all custom N FILE COLUMNS…";
        need(args, 6, usage)?;
        if args[1] != "all" {
            return Err(format!("group '{}' not supported: only 'all'", args[1]));
        }
        if args[2] != "custom" {
            return Err(format!(
                "dump style '{}' not supported: only custom",
                args[2]
            ));
        }
        if self.dumps.iter().any(|d| d.id == args[0]) {
            return Err(format!("dump ID '{}' already exists", args[0]));
        }
        let every: u64 = parse_int(&args[3], "dump interval")?;
        if every == 0 {
            return Err("dump interval must be >= 1".into());
        }
        let columns = args[5..].to_vec();
        for c in &columns {
            if !matches!(
                c.as_str(),
                "id" | "type"
                    | "mass"
                    | "x"
                    | "y"
                    | "z"
                    | "xu"
                    | "yu"
                    | "zu"
                    | "ix"
                    | "iy"
                    | "iz"
                    | "vx"
                    | "vy"
                    | "vz"
                    | "fx"
                    | "fy"
                    | "fz"
            ) {
                return Err(format!("unknown dump column '{c}'"));
            }
        }
        let f = File::create(&args[4])
            .map_err(|e| format!("cannot open dump file {}: {e}", args[4]))?;
        self.dumps.push(Dump {
            id: args[0].clone(),
            every,
            path: args[4].clone(),
            columns,
            fmt_line: None,
            fmt_int: None,
            fmt_float: None,
            writer: BufWriter::new(f),
            last: None,
        });
        Ok(())
    }

    fn cmd_dump_modify(&mut self, args: &[String]) -> CmdResult {
        let usage = "dump_modify ID sort id|off | format line|int|float FORMAT";
        need(args, 3, usage)?;
        let d = self
            .dumps
            .iter_mut()
            .find(|d| d.id == args[0])
            .ok_or_else(|| format!("no dump with ID '{}'", args[0]))?;
        let mut k = 1;
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            match args[k].as_str() {
                // Output is always sorted by id (the engine reorders atoms for locality).
                "sort" => k += 2,
                "flush" => k += 2,
                "format" => {
                    need(&args[k..], 3, usage)?;
                    let f = args[k + 2].clone();
                    match args[k + 1].as_str() {
                        "line" => {
                            d.fmt_line = Some(f.split_whitespace().map(String::from).collect())
                        }
                        "int" => d.fmt_int = Some(f),
                        "float" => d.fmt_float = Some(f),
                        o => {
                            return Err(format!(
                                "dump_modify format '{o}' not supported (line, int, float)"
                            ));
                        }
                    }
                    k += 3;
                }
                o => return Err(format!("unknown dump_modify keyword '{o}'")),
            }
        }
        Ok(())
    }

    fn write_dumps(&mut self, setup: bool) -> CmdResult {
        let Some(sys) = self.sys.as_ref() else {
            return Ok(());
        };
        let step = sys.step;
        for d in self.dumps.iter_mut() {
            if step % d.every != 0 || d.last == Some(step) {
                continue;
            }
            let _ = setup;
            d.last = Some(step);
            let n = sys.atoms.len();
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by_key(|&i| sys.atoms.tag[i]);
            let w = &mut d.writer;
            let io = |e: std::io::Error| format!("cannot write dump file: {e}");
            writeln!(
                w,
                "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS pp pp pp"
            )
            .map_err(io)?;
            for a in 0..3 {
                writeln!(w, "{:.16e} {:.16e}", sys.bx.lo[a], sys.bx.hi[a]).map_err(io)?;
            }
            writeln!(w, "ITEM: ATOMS {}", d.columns.join(" ")).map_err(io)?;
            let mut line = String::new();
            for &i in &order {
                line.clear();
                let mut x = sys.atoms.x[i];
                let mut im = sys.atoms.image[i];
                sys.bx.wrap(&mut x, &mut im);
                let xu = sys.bx.unwrap(x, im);
                for (k, c) in d.columns.iter().enumerate() {
                    let (int, val) = match c.as_str() {
                        "id" => (true, f64::from(sys.atoms.tag[i])),
                        "type" => (true, f64::from(sys.atoms.typ[i])),
                        "ix" => (true, f64::from(im[0])),
                        "iy" => (true, f64::from(im[1])),
                        "iz" => (true, f64::from(im[2])),
                        "mass" => (false, sys.mass[sys.atoms.typ[i] as usize].unwrap_or(0.0)),
                        "x" => (false, x[0]),
                        "y" => (false, x[1]),
                        "z" => (false, x[2]),
                        "xu" => (false, xu[0]),
                        "yu" => (false, xu[1]),
                        "zu" => (false, xu[2]),
                        "vx" => (false, sys.atoms.v[i][0]),
                        "vy" => (false, sys.atoms.v[i][1]),
                        "vz" => (false, sys.atoms.v[i][2]),
                        "fx" => (false, sys.atoms.f[i][0]),
                        "fy" => (false, sys.atoms.f[i][1]),
                        _ => (false, sys.atoms.f[i][2]),
                    };
                    let fmtstr = d
                        .fmt_line
                        .as_ref()
                        .and_then(|l| l.get(k).map(String::as_str))
                        .or(if int {
                            d.fmt_int.as_deref()
                        } else {
                            d.fmt_float.as_deref()
                        })
                        .unwrap_or(if int { "%d" } else { "%g" });
                    let arg = if int {
                        FmtArg::Int(val as i64)
                    } else {
                        FmtArg::Float(val)
                    };
                    if k > 0 {
                        line.push(' ');
                    }
                    line.push_str(&sprintf(fmtstr, &[arg])?);
                }
                writeln!(w, "{line}").map_err(io)?;
            }
            w.flush().map_err(io)?;
            let _ = &d.path;
        }
        Ok(())
    }

    /// LAMMPS `end_of_step` (and, at `setup`, the fixes' set-up call): PeX pushes and
    /// measurements in the order the fixes were defined.
    fn end_of_step(&mut self, setup: bool) -> CmdResult {
        for k in 0..self.fixes.len() {
            let (id, kind) = &self.fixes[k];
            match kind {
                FixKind::Pex if !setup => {
                    let id = id.clone();
                    let sys = self.sys_mut()?;
                    if let Some(p) = sys.pex.iter().position(|p| p.id == id) {
                        sys.apply_pex_push(p);
                    }
                }
                FixKind::Observe => {
                    if let Some(sample) = self.obs.sample(id, &*self)? {
                        let (id, step) = (id.clone(), self.sys_mut()?.step);
                        self.obs.accumulate(&id, sample, step)?;
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn cmd_run(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "run N [upto] [pre yes|no] [post yes|no]")?;
        let mut n: u64 = parse_int(&args[0], "number of steps")?;
        let mut upto = false;
        let mut k = 1;
        while k < args.len() {
            match args[k].as_str() {
                "upto" => {
                    upto = true;
                    k += 1;
                }
                "pre" | "post" => k += 2,
                o => return Err(format!("run keyword '{o}' not supported (upto, pre, post)")),
            }
        }
        let threads = self.threads;
        let sys = self.sys_mut()?;
        if upto {
            n = n
                .checked_sub(sys.step)
                .ok_or("run upto: target step is in the past")?;
        }
        sys.setup()?;
        let notes = std::mem::take(&mut sys.setup_notes);
        let integ = sys.integrator;
        let first = sys.step;
        let last = first + n;
        let natoms = sys.atoms.len();
        let dt = sys.dt;
        self.run_first = first;
        if self.dry_run {
            let plan = PlannedRun::of(self.sys_mut()?, n, notes)?;
            self.planned.push(plan);
            return Ok(());
        }
        for note in notes {
            match note {
                SetupNote::Info(text) => self.out(&text),
                SetupNote::Warning(text) => self.warn(&text),
            }
        }
        if integ.is_none() {
            self.warn("No fixes with time integration, atoms won't move");
        }
        let scheme = match integ {
            Some(Integrator::Euler) => "Euler (nve/euler)",
            _ => "velocity-Verlet (nve)",
        };
        self.out(&format!("Setting up {scheme} run ...\n  Unit style    : lj\n  Current step  : {first}\n  Time step     : {dt}"));
        self.obs.init(first);
        self.end_of_step(true)?;
        let header = self.thermo_header_line();
        self.out(&header);
        let row = self.thermo_row()?;
        self.out(&row);
        self.write_dumps(true)?;
        let every = self.thermo.every;
        let start = Instant::now();
        let mut last_progress = Instant::now();
        let measuring = self.obs.has_fixes();
        for _ in 0..n {
            let sys = self.sys_mut()?;
            if measuring {
                sys.advance();
            } else {
                sys.step_once();
            }
            let step = sys.step;
            if measuring {
                self.end_of_step(false)?;
            }
            if (every > 0 && step % every == 0) || step == last {
                let row = self.thermo_row()?;
                self.out(&row);
            }
            if !self.dumps.is_empty() {
                self.write_dumps(false)?;
            }
            if last_progress.elapsed().as_secs_f64() > 1.0 {
                last_progress = Instant::now();
                self.console.progress(step, first, last);
                if let Some(l) = self.log.as_mut() {
                    let _ = l.flush();
                }
            }
        }
        let secs = start.elapsed().as_secs_f64();
        self.out(&format!(
            "Loop time of {secs:.6} on {threads} procs for {n} steps with {natoms} atoms\n"
        ));
        if secs > 0.0 && n > 0 {
            let steps_per_s = n as f64 / secs;
            self.out(&format!(
                "Performance: {:.3} tau/day, {:.3} timesteps/s, {:.3} katom-step/s",
                86400.0 * steps_per_s * dt,
                steps_per_s,
                steps_per_s * natoms as f64 / 1000.0
            ));
        }
        if let Some(l) = self.log.as_mut() {
            let _ = l.flush();
        }
        Ok(())
    }
}

impl Interpreter<'_> {
    /// Consume the interpreter, returning the system (if a box was created).
    pub fn into_system(self) -> Option<System> {
        self.sys
    }
}

/// The formula context of an interpreter: variables, thermo keywords, computes and fixes;
/// the depth guards against variables that refer to themselves.
struct Ctx<'a, 'b>(&'a Interpreter<'b>, usize);

impl ExprContext for Ctx<'_, '_> {
    fn variable(&self, name: &str) -> Result<f64, String> {
        if self.1 > 64 {
            return Err(format!("variable '{name}' refers to itself"));
        }
        match self.0.vars.get(name) {
            None => Err(format!("variable '{name}' is not defined")),
            Some(Var::Index(s)) | Some(Var::Str(s)) => s
                .trim()
                .parse::<f64>()
                .map_err(|_| format!("variable '{name}' = '{s}' is not a number")),
            Some(Var::Equal(e)) => eval_equal(e, &Ctx(self.0, self.1 + 1)),
            Some(Var::Atom(_)) => Err(format!(
                "variable '{name}' is atom-style: not usable in an equal-style formula"
            )),
        }
    }
    fn thermo(&self, keyword: &str) -> Option<Result<f64, String>> {
        self.0.thermo_value(keyword)
    }
    fn reference(
        &self,
        kind: RefKind,
        id: &str,
        index: Option<usize>,
    ) -> Option<Result<f64, String>> {
        Some(self.0.obs.reference(kind, id, index, self.0))
    }
}

impl AtomBinder for Ctx<'_, '_> {
    fn atom_variable(&self, name: &str) -> Option<Result<Formula, String>> {
        let Some(Var::Atom(src)) = self.0.vars.get(name) else {
            return None;
        };
        if self.1 > 64 {
            return Some(Err(format!("variable '{name}' refers to itself")));
        }
        let inner = Ctx(self.0, self.1 + 1);
        Some(Formula::parse(src).and_then(|f| f.bind_atoms(&inner, &inner)))
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
