//! LAMMPS's output computes and time-averaging fixes, the subset a DPD measurement needs
//! (`docs/models.md` §1.5 and §4.5–4.6; syntax and file formats of LAMMPS 29 Sep 2021, see
//! `docs/input.md`):
//!
//! - computes `temp`, `pressure`, `pe`, `ke`, `msd`, `chunk/atom bin/1d` and the built-in
//!   `thermo_temp`, `thermo_press`, `thermo_pe`;
//! - fixes `ave/time`, `ave/chunk`, `ave/histo`.
//!
//! The fixes follow LAMMPS's `end_of_step` rules exactly: a fix samples on the steps
//! `nvalid`, `nvalid + Nevery`, … (Nrepeat samples ending on a multiple of Nfreq; `nextvalid`),
//! also during the set-up of a run, and writes its file on the Nfreq steps with the same
//! header lines, columns and `%g` numbers as LAMMPS, so one reader parses both engines' files.
//! Measurement (what one sample is) lives in [`crate::engine::measure`]; this module parses
//! the commands, schedules the samples, averages them as LAMMPS does (same operations in the
//! same order) and writes the files.
//!
//! The rooms of this module:
//!
//! - `compute`: the computes (`compute`, `uncompute`, the thermo computes);
//! - `global`: global values of computes, fixes and variables (`c_ID[i]`, `f_ID`, `v_name`):
//!   references, checks, wildcard expansion;
//! - `average`: LAMMPS's Nevery/Nrepeat/Nfreq schedule and `ave one|running|window`;
//! - `fix`: the averaging fixes' common part (keywords, files, the two phases of
//!   `end_of_step`);
//! - `ave_args`: what `fix` hands to the style modules (the parsed common arguments, a
//!   sample's place in its epoch); a leaf, so `fix` → `ave_time`/`ave_chunk`/`ave_histo` runs
//!   one way;
//! - `ave_time`, `ave_chunk`, `ave_histo`: what is particular to each fix (each returns its
//!   own state; only `fix` knows all three, in `AveKind`);
//! - `per_atom`: per-atom values and atom-style formulas evaluated on a system.

mod ave_args;
mod ave_chunk;
mod ave_histo;
mod ave_time;
mod average;
mod compute;
mod fix;
mod global;
mod per_atom;
mod reduce;
mod stress_atom;

pub use compute::ComputeDef;
pub use fix::AveFix;
pub(crate) use per_atom::{atom_value, eval_atoms};

use super::expr::RefKind;
use super::format::{ArgKind, conversion_kinds};
use crate::engine::System;
use crate::engine::measure::HistoSample;
use ave_chunk::ChunkLock;
use average::Ave;
use compute::ComputeKind;

/// What the measurements need from the interpreter.
pub trait Env {
    /// The system, once a box exists.
    fn system(&self) -> Option<&System>;
    /// The computes and fixes defined so far.
    fn observe(&self) -> &Observe;
    /// The style of variable `name`.
    fn var_style(&self, name: &str) -> VarStyle;
    /// The value of equal-style variable `name`.
    fn equal_variable(&self, name: &str) -> Result<f64, String>;
    /// The values of atom-style variable `name`, one per atom in the atoms' internal order.
    fn atom_variable(&self, name: &str) -> Result<Vec<f64>, String>;
}

/// The style of a variable, as the fixes check it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarStyle {
    /// No such variable.
    Undefined,
    /// `equal`.
    Equal,
    /// `atom`.
    Atom,
    /// `index` or `string`.
    Other,
}

/// Where a global value comes from.
#[derive(Clone, Debug, PartialEq)]
enum Source {
    Compute(String),
    Fix(String),
    Var(String),
}

#[derive(Clone, Debug, PartialEq)]
pub(super) struct ValueRef {
    text: String,
    source: Source,
    /// 1-based element; None: the scalar (or the whole vector in vector mode).
    index: Option<usize>,
}

/// One sample of a fix, taken with shared access to everything (phase 1 of `end_of_step`).
#[derive(Debug)]
pub enum Sample {
    /// ave/time: rows × values, row-major (one row in scalar mode).
    Time(Vec<f64>),
    /// ave/chunk: bin centres, bin volume, atoms per chunk, chunk × value sums.
    Chunk {
        /// Bin centres.
        coord: Vec<f64>,
        /// Bin volume.
        volume: f64,
        /// Atoms per chunk.
        count: Vec<f64>,
        /// Sums per chunk and value (chunk-major).
        values: Vec<f64>,
    },
    /// ave/histo: this sample's histogram.
    Histo(HistoSample),
}

/// The computes and averaging fixes of an interpreter.
#[derive(Debug)]
pub struct Observe {
    computes: Vec<ComputeDef>,
    fixes: Vec<AveFix>,
    locks: Vec<(String, ChunkLock)>,
}

impl Default for Observe {
    fn default() -> Self {
        Observe::new()
    }
}

fn parse_i64(tok: &str, what: &str) -> Result<i64, String> {
    tok.parse()
        .map_err(|_| format!("expected an integer for {what}, found '{tok}'"))
}

fn parse_num(tok: &str, what: &str) -> Result<f64, String> {
    let v: f64 = tok
        .parse()
        .map_err(|_| format!("expected a number for {what}, found '{tok}'"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what} = '{tok}' is not finite"))
    }
}

fn arg<'a>(args: &'a [String], k: usize, usage: &str) -> Result<&'a str, String> {
    args.get(k)
        .map(String::as_str)
        .ok_or_else(|| format!("missing argument; usage: {usage}"))
}

fn parse_ave(args: &[String], k: usize, usage: &str) -> Result<(Ave, usize), String> {
    match arg(args, k + 1, usage)? {
        "one" => Ok((Ave::One, 2)),
        "running" => Ok((Ave::Running, 2)),
        "window" => {
            let n = parse_i64(arg(args, k + 2, usage)?, "ave window M")?;
            if n <= 0 {
                return Err(format!("ave window {n}: M must be >= 1"));
            }
            Ok((Ave::Window(n as usize), 3))
        }
        o => Err(format!("ave '{o}' must be one, running or window M")),
    }
}

fn check_format(f: &str) -> Result<String, String> {
    if conversion_kinds(f)? != [ArgKind::Float] {
        return Err(format!(
            "format '{f}' must hold exactly one floating-point conversion (e.g. %g, %.15g)"
        ));
    }
    Ok(f.to_string())
}

/// `c_ID`, `c_ID[3]`, `f_ID[2]`, `v_name` → (source, index); `[*]`, `[n*m]` wildcards are
/// expanded by the caller.
fn parse_ref(word: &str) -> Result<Option<(Source, Option<usize>)>, String> {
    let (kind, body) = match word.get(..2) {
        Some("c_") => ('c', &word[2..]),
        Some("f_") => ('f', &word[2..]),
        Some("v_") => ('v', &word[2..]),
        _ => return Ok(None),
    };
    let (id, index) = match body.split_once('[') {
        Some((id, rest)) => {
            let idx = rest
                .strip_suffix(']')
                .ok_or_else(|| format!("'{word}': missing ']'"))?;
            let n: usize = idx
                .parse()
                .map_err(|_| format!("'{word}': index '{idx}' must be an integer >= 1"))?;
            if n == 0 {
                return Err(format!("'{word}': index must be >= 1"));
            }
            (id, Some(n))
        }
        None => (body, None),
    };
    if id.is_empty() {
        return Err(format!("'{word}': missing ID"));
    }
    Ok(Some((
        match kind {
            'c' => Source::Compute(id.to_string()),
            'f' => Source::Fix(id.to_string()),
            _ => Source::Var(id.to_string()),
        },
        index,
    )))
}

fn io_err(path: &str) -> impl Fn(std::io::Error) -> String + '_ {
    move |e| format!("cannot write {path}: {e}")
}

impl Observe {
    /// The built-in computes only.
    pub fn new() -> Observe {
        Observe {
            computes: vec![
                ComputeDef {
                    id: "thermo_temp".into(),
                    kind: ComputeKind::Temp,
                },
                ComputeDef {
                    id: "thermo_press".into(),
                    kind: ComputeKind::Pressure("thermo_temp".into()),
                },
                ComputeDef {
                    id: "thermo_pe".into(),
                    kind: ComputeKind::Pe,
                },
            ],
            fixes: Vec::new(),
            locks: Vec::new(),
        }
    }

    fn compute(&self, id: &str) -> Option<&ComputeDef> {
        self.computes.iter().find(|c| c.id == id)
    }

    fn fix(&self, id: &str) -> Option<&AveFix> {
        self.fixes.iter().find(|f| f.id == id)
    }

    /// True if `id` is one of these averaging fixes.
    pub fn is_fix(&self, id: &str) -> bool {
        self.fix(id).is_some()
    }

    /// True if any averaging fix is defined (the run loop then calls the end-of-step hooks).
    pub fn has_fixes(&self) -> bool {
        !self.fixes.is_empty()
    }
}

/// A compute or fix reference: kind, ID, 1-based index (None: the scalar).
pub(crate) type Reference<'a> = (RefKind, &'a str, Option<usize>);

/// Split a thermo keyword `c_ID`, `c_ID[i]`, `f_ID`, `f_ID[i]`; None for other keywords.
pub(crate) fn split_reference(kw: &str) -> Option<Result<Reference<'_>, String>> {
    let kind = match kw.get(..2)? {
        "c_" => RefKind::Compute,
        "f_" => RefKind::Fix,
        _ => return None,
    };
    let body = &kw[2..];
    Some(match body.split_once('[') {
        None => Ok((kind, body, None)),
        Some((id, rest)) => match rest.strip_suffix(']').and_then(|i| i.parse::<usize>().ok()) {
            Some(i) if i >= 1 => Ok((kind, id, Some(i))),
            _ => Err(format!("'{kw}': index must be an integer >= 1 in [ ]")),
        },
    })
}
