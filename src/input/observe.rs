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

use super::expr::{AtomValue, RefKind};
use super::format::{ArgKind, FmtArg, conversion_kinds, sprintf};
use crate::engine::System;
use crate::engine::measure::{
    self, Beyond, Bin1d, BinOrigin, Discard, HistoBins, HistoSample, Msd,
};
use std::fs::File;
use std::io::{BufWriter, Write};

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

/// Names of the computes LAMMPS defines by itself.
pub const BUILTIN_COMPUTES: [&str; 3] = ["thermo_temp", "thermo_press", "thermo_pe"];

#[derive(Debug)]
enum ComputeKind {
    /// `temp`: scalar T (dof = dN − d), vector Σ m v_a v_b (xx yy zz xy xz yz).
    Temp,
    /// `temp/deform`: as `temp` with the streaming velocity of `fix deform` removed
    /// (`System::thermo_deform`).
    TempDeform,
    /// `pressure TEMP-ID`: scalar P, vector P_ab (kinetic part of TEMP-ID + virial of all pair
    /// forces).
    Pressure(String),
    /// `pe`: total pair energy.
    Pe,
    /// `ke`: total kinetic energy.
    Ke,
    /// `msd`: vector of 4.
    Msd(Msd),
    /// `chunk/atom bin/1d`: per-atom chunk index.
    Chunk(Bin1d),
}

impl ComputeKind {
    fn style(&self) -> &'static str {
        match self {
            ComputeKind::Temp => "temp",
            ComputeKind::TempDeform => "temp/deform",
            ComputeKind::Pressure(_) => "pressure",
            ComputeKind::Pe => "pe",
            ComputeKind::Ke => "ke",
            ComputeKind::Msd(_) => "msd",
            ComputeKind::Chunk(_) => "chunk/atom",
        }
    }

    fn has_scalar(&self) -> bool {
        matches!(
            self,
            ComputeKind::Temp
                | ComputeKind::TempDeform
                | ComputeKind::Pressure(_)
                | ComputeKind::Pe
                | ComputeKind::Ke
        )
    }

    fn vector_len(&self) -> Option<usize> {
        match self {
            ComputeKind::Temp | ComputeKind::TempDeform | ComputeKind::Pressure(_) => Some(6),
            ComputeKind::Msd(_) => Some(4),
            _ => None,
        }
    }

    fn extensive(&self) -> bool {
        matches!(self, ComputeKind::Pe | ComputeKind::Ke)
    }

    fn is_temperature(&self) -> bool {
        matches!(self, ComputeKind::Temp | ComputeKind::TempDeform)
    }
}

/// A compute: its ID and what it computes.
#[derive(Debug)]
pub struct ComputeDef {
    id: String,
    kind: ComputeKind,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ave {
    One,
    Running,
    Window(usize),
}

/// LAMMPS's `ave one|running|window M` over the per-Nfreq results, with the same add and
/// subtract operations (so the same round-off).
#[derive(Debug)]
struct Averager {
    ave: Ave,
    total: Vec<f64>,
    list: Vec<Vec<f64>>,
    iwindow: usize,
    full: bool,
    norm: usize,
}

impl Averager {
    fn new(ave: Ave) -> Averager {
        Averager {
            ave,
            total: Vec::new(),
            list: Vec::new(),
            iwindow: 0,
            full: false,
            norm: 0,
        }
    }

    fn push(&mut self, x: &[f64]) {
        if self.total.len() != x.len() {
            self.total = vec![0.0; x.len()];
            self.list.clear();
            self.iwindow = 0;
            self.full = false;
            self.norm = 0;
        }
        match self.ave {
            Ave::One => {
                self.total.copy_from_slice(x);
                self.norm = 1;
            }
            Ave::Running => {
                for (t, v) in self.total.iter_mut().zip(x) {
                    *t += v;
                }
                self.norm += 1;
            }
            Ave::Window(n) => {
                if self.list.len() < n {
                    self.list = vec![vec![0.0; x.len()]; n];
                }
                let slot = &mut self.list[self.iwindow];
                for ((t, v), old) in self.total.iter_mut().zip(x).zip(slot.iter_mut()) {
                    *t += v;
                    if self.full {
                        *t -= *old;
                    }
                    *old = *v;
                }
                self.iwindow += 1;
                if self.iwindow == n {
                    self.iwindow = 0;
                    self.full = true;
                }
                self.norm = if self.full { n } else { self.iwindow };
            }
        }
    }
}

/// LAMMPS's Nevery/Nrepeat/Nfreq schedule (`nextvalid`, `end_of_step`).
#[derive(Clone, Debug)]
struct Schedule {
    nevery: i64,
    nrepeat: i64,
    nfreq: i64,
    start: i64,
    nvalid: i64,
    nvalid_last: i64,
    irepeat: i64,
}

impl Schedule {
    fn next_valid(&self, step: i64) -> i64 {
        let mut nv = (step / self.nfreq) * self.nfreq + self.nfreq;
        while nv < self.start {
            nv += self.nfreq;
        }
        if nv - self.nfreq == step && self.nrepeat == 1 {
            nv = step;
        } else {
            nv -= (self.nrepeat - 1) * self.nevery;
        }
        if nv < step {
            nv += self.nfreq;
        }
        nv
    }

    /// At the start of every run (LAMMPS `init`).
    fn init(&mut self, step: i64) {
        if self.nvalid < step {
            self.irepeat = 0;
            self.nvalid = self.next_valid(step);
        }
    }

    fn due(&self, step: i64, style: &str) -> Result<bool, String> {
        if step < self.nvalid_last || step > self.nvalid {
            return Err(format!(
                "invalid timestep reset for fix {style} (step {step}, next sample {})",
                self.nvalid
            ));
        }
        Ok(step == self.nvalid)
    }

    /// Record a sample at `step`; true when it completes an Nfreq epoch.
    fn sampled(&mut self, step: i64) -> bool {
        self.nvalid_last = self.nvalid;
        self.irepeat += 1;
        if self.irepeat < self.nrepeat {
            self.nvalid += self.nevery;
            return false;
        }
        self.irepeat = 0;
        self.nvalid = step + self.nfreq - (self.nrepeat - 1) * self.nevery;
        true
    }
}

/// Where a global value comes from.
#[derive(Clone, Debug, PartialEq)]
enum Source {
    Compute(String),
    Fix(String),
    Var(String),
}

#[derive(Clone, Debug, PartialEq)]
struct ValueRef {
    text: String,
    source: Source,
    /// 1-based element; None: the scalar (or the whole vector in vector mode).
    index: Option<usize>,
}

#[derive(Debug)]
struct AveTime {
    values: Vec<ValueRef>,
    vector: bool,
    nrows: usize,
    sum: Vec<f64>,
    avg: Averager,
    format: String,
}

#[derive(Clone, Debug, PartialEq)]
enum ChunkValue {
    V(usize),
    F(usize),
    DensityNumber,
    DensityMass,
    Mass,
    Temp,
    Var(String),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Norm {
    All,
    Sample,
    None,
}

#[derive(Debug)]
struct AveChunk {
    chunk: String,
    values: Vec<ChunkValue>,
    norm: Norm,
    adof: f64,
    nchunk: usize,
    coord: Vec<f64>,
    count_many: Vec<f64>,
    values_many: Vec<f64>,
    count_sum: Vec<f64>,
    avg: Averager,
    format: String,
    lock_forever: bool,
}

#[derive(Clone, Debug, PartialEq)]
enum HistoInput {
    Atom(AtomValue),
    AtomVar(String),
    Global(ValueRef),
}

#[derive(Debug)]
struct AveHisto {
    inputs: Vec<HistoInput>,
    vector: bool,
    bins: HistoBins,
    acc: HistoSample,
    avg: Averager,
    minmax: Vec<[f64; 2]>,
    total_minmax: [f64; 2],
}

#[derive(Debug)]
enum AveKind {
    Time(AveTime),
    Chunk(AveChunk),
    Histo(AveHisto),
}

/// A time-averaging fix.
#[derive(Debug)]
pub struct AveFix {
    id: String,
    sched: Schedule,
    file: Option<(String, BufWriter<File>)>,
    kind: AveKind,
}

impl AveFix {
    fn style(&self) -> &'static str {
        match self.kind {
            AveKind::Time(_) => "ave/time",
            AveKind::Chunk(_) => "ave/chunk",
            AveKind::Histo(_) => "ave/histo",
        }
    }

    /// LAMMPS's `global_freq`: the fix's global values change on multiples of Nfreq.
    fn global_freq(&self) -> i64 {
        self.sched.nfreq
    }

    fn scalar(&self) -> Option<f64> {
        match &self.kind {
            AveKind::Time(t) if !t.vector && t.values.len() == 1 => Some(t.value(0, 0)),
            _ => None,
        }
    }

    fn vector_len(&self) -> Option<usize> {
        match &self.kind {
            AveKind::Time(t) if !t.vector && t.values.len() > 1 => Some(t.values.len()),
            AveKind::Time(t) if t.vector && t.values.len() == 1 => Some(t.nrows),
            AveKind::Histo(_) => Some(4),
            _ => None,
        }
    }

    /// Element `i` (0-based) of the global vector.
    fn vector(&self, i: usize) -> f64 {
        match &self.kind {
            AveKind::Time(t) if !t.vector => t.value(0, i),
            AveKind::Time(t) => t.value(i, 0),
            AveKind::Histo(h) => match i {
                0 | 1 => h.avg.total.get(i).copied().unwrap_or(0.0),
                2 => h.total_minmax[0],
                _ => h.total_minmax[1],
            },
            AveKind::Chunk(_) => 0.0,
        }
    }

    fn extensive(&self, obs: &Observe, index: Option<usize>) -> bool {
        match &self.kind {
            AveKind::Time(t) => {
                let k = if t.vector {
                    0
                } else {
                    index.map_or(0, |i| i - 1)
                };
                t.values.get(k).is_some_and(|v| obs.value_extensive(v))
            }
            _ => false,
        }
    }
}

impl AveTime {
    fn value(&self, row: usize, col: usize) -> f64 {
        let nv = self.values.len();
        if self.avg.norm == 0 {
            return 0.0;
        }
        self.avg
            .total
            .get(row * nv + col)
            .map_or(0.0, |t| t / self.avg.norm as f64)
    }
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

/// The lock a fix holds on a chunk compute, so that the chunks cannot change while it
/// averages (LAMMPS `ComputeChunkAtom::lock`): fix ID, first step, last step (−1: forever).
#[derive(Clone, Debug, PartialEq)]
struct ChunkLock {
    fix: String,
    start: i64,
    stop: i64,
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

    /// Lock chunk compute `chunk` for fix `fix` from `start` to `stop` (LAMMPS's rule: a second
    /// fix may only share the lock with the same steps).
    fn lock(&mut self, chunk: &str, fix: &str, start: i64, stop: i64) -> Result<(), String> {
        let new = ChunkLock {
            fix: fix.to_string(),
            start,
            stop,
        };
        match self.locks.iter_mut().find(|(c, _)| c == chunk) {
            None => self.locks.push((chunk.to_string(), new)),
            Some((_, l)) => {
                if l.start != start || l.stop != stop {
                    return Err(format!(
                        "two fix commands use compute chunk/atom '{chunk}' in incompatible ways: \
                         fix '{}' keeps its chunks fixed over steps {}..{}, fix '{fix}' over \
                         {start}..{} (LAMMPS refuses this too)",
                        l.fix,
                        l.start,
                        if l.stop < 0 {
                            "end".to_string()
                        } else {
                            l.stop.to_string()
                        },
                        if stop < 0 {
                            "end".to_string()
                        } else {
                            stop.to_string()
                        },
                    ));
                }
                l.fix = fix.to_string();
            }
        }
        Ok(())
    }

    fn unlock(&mut self, chunk: &str, fix: &str) {
        self.locks.retain(|(c, l)| !(c == chunk && l.fix == fix));
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

    // ------------------------------------------------------------------ computes

    /// Parse `compute ID all STYLE ARGS…` (checked against `env`, not yet added).
    pub fn parse_compute(args: &[String], env: &dyn Env) -> Result<ComputeDef, String> {
        let usage = "compute ID all temp | temp/deform | pressure TEMP-ID | pe | ke | msd [com yes|no] | chunk/atom bin/1d x|y|z lower|center|upper|COORD DELTA [units box|lattice|reduced] [discard mixed|yes|no] [bound x|y|z lo|lower hi|upper]";
        if args.len() < 3 {
            return Err(format!("missing arguments; usage: {usage}"));
        }
        let id = &args[0];
        if !id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(format!(
                "compute ID '{id}' must be alphanumeric, '_' or '-'"
            ));
        }
        if env.observe().compute(id).is_some() {
            return Err(format!("reuse of compute ID '{id}' (uncompute it first)"));
        }
        if args[1] != "all" {
            return Err(format!("group '{}' not supported: only 'all'", args[1]));
        }
        let sys = env
            .system()
            .ok_or("compute needs a simulation box (create_box or read_data) first")?;
        let extra = |n: usize| -> Result<(), String> {
            if args.len() > n {
                Err(format!(
                    "compute {} takes no argument '{}'; usage: {usage}",
                    args[2], args[n]
                ))
            } else {
                Ok(())
            }
        };
        let kind = match args[2].as_str() {
            "temp" => {
                extra(3)?;
                ComputeKind::Temp
            }
            "temp/deform" => {
                extra(3)?;
                ComputeKind::TempDeform
            }
            "pe" => {
                extra(3)?;
                ComputeKind::Pe
            }
            "ke" => {
                extra(3)?;
                ComputeKind::Ke
            }
            "pressure" => {
                let t = arg(args, 3, usage)?;
                match env.observe().compute(t) {
                    Some(c) if c.kind.is_temperature() => {}
                    Some(c) => {
                        return Err(format!(
                            "compute pressure: compute '{t}' is a {} compute, not a temperature",
                            c.kind.style()
                        ));
                    }
                    None => {
                        return Err(format!(
                            "compute pressure: temperature compute '{t}' does not exist"
                        ));
                    }
                }
                if args.len() > 4 {
                    return Err(format!(
                        "compute pressure keyword '{}' not supported: the pressure always \
                         includes the kinetic part and the virial of all pair forces",
                        args[4]
                    ));
                }
                ComputeKind::Pressure(t.to_string())
            }
            "msd" => {
                let mut com = false;
                let mut k = 3;
                while k < args.len() {
                    let v = arg(args, k + 1, usage)?;
                    let yes = match v {
                        "yes" => true,
                        "no" => false,
                        o => {
                            return Err(format!("compute msd {} '{o}' must be yes or no", args[k]));
                        }
                    };
                    match args[k].as_str() {
                        "com" => com = yes,
                        "average" if !yes => {}
                        "average" => {
                            return Err("compute msd average yes is not supported".into());
                        }
                        o => return Err(format!("unknown compute msd keyword '{o}'")),
                    }
                    k += 2;
                }
                ComputeKind::Msd(Msd::new(sys, com))
            }
            "chunk/atom" => ComputeKind::Chunk(Self::parse_chunk(args, sys)?),
            o => {
                return Err(format!("compute style '{o}' not supported; usage: {usage}"));
            }
        };
        Ok(ComputeDef {
            id: id.clone(),
            kind,
        })
    }

    fn parse_chunk(args: &[String], sys: &System) -> Result<Bin1d, String> {
        let usage = "compute ID all chunk/atom bin/1d x|y|z lower|center|upper|COORD DELTA [units box|lattice|reduced] [discard mixed|yes|no] [bound x|y|z lo|lower hi|upper]";
        let style = arg(args, 3, usage)?;
        if style != "bin/1d" {
            return Err(format!(
                "compute chunk/atom style '{style}' not supported: only bin/1d"
            ));
        }
        let axis_of = |t: &str| -> Result<usize, String> {
            match t {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" => Ok(2),
                o => Err(format!("chunk/atom dimension '{o}' must be x, y or z")),
            }
        };
        let axis = axis_of(arg(args, 4, usage)?)?;
        if axis == 2 && sys.dim() == 2 {
            return Err("cannot use compute chunk/atom bin z for a 2-D model".into());
        }
        let origin = match arg(args, 5, usage)? {
            "lower" => BinOrigin::Lower,
            "center" => BinOrigin::Center,
            "upper" => BinOrigin::Upper,
            t => BinOrigin::Coord(parse_num(t, "bin origin")?),
        };
        let delta = parse_num(arg(args, 6, usage)?, "bin width")?;
        if delta <= 0.0 {
            return Err(format!("bin width {delta} must be > 0"));
        }
        let mut b = Bin1d {
            axis,
            origin,
            delta,
            reduced: false,
            min: None,
            max: None,
            discard: Discard::Mixed,
        };
        let mut k = 7;
        while k < args.len() {
            let v = arg(args, k + 1, usage)?;
            match args[k].as_str() {
                "units" => {
                    b.reduced = match v {
                        // No lattice command: lattice units are box units (LAMMPS's default
                        // lattice has spacing 1).
                        "box" | "lattice" => false,
                        "reduced" => true,
                        o => return Err(format!("units '{o}' must be box, lattice or reduced")),
                    }
                }
                "discard" => {
                    b.discard = match v {
                        "mixed" => Discard::Mixed,
                        "yes" => Discard::Yes,
                        "no" => Discard::No,
                        o => return Err(format!("discard '{o}' must be mixed, yes or no")),
                    }
                }
                "bound" => {
                    if axis_of(v)? != axis {
                        return Err(format!(
                            "bound {v}: only the binned dimension {} can be bounded",
                            ["x", "y", "z"][axis]
                        ));
                    }
                    let lo = arg(args, k + 2, usage)?;
                    let hi = arg(args, k + 3, usage)?;
                    b.min = if lo == "lower" {
                        None
                    } else {
                        Some(parse_num(lo, "bound lo")?)
                    };
                    b.max = if hi == "upper" {
                        None
                    } else {
                        Some(parse_num(hi, "bound hi")?)
                    };
                    k += 4;
                    continue;
                }
                "nchunk" | "ids" | "compress" | "limit" | "region" | "pbc" => {
                    return Err(format!(
                        "compute chunk/atom keyword '{}' not supported (units, discard, bound)",
                        args[k]
                    ));
                }
                o => return Err(format!("unknown compute chunk/atom keyword '{o}'")),
            }
            k += 2;
        }
        // Validate now (LAMMPS checks at the first use).
        b.layout(&sys.bx)?;
        Ok(b)
    }

    /// Add a parsed compute.
    pub fn add_compute(&mut self, c: ComputeDef) {
        self.computes.push(c);
    }

    /// The thermodynamic state (temperature, kinetic energy, and the pressure of a `compute
    /// pressure` that uses it) with the kinetic tensor of temperature compute `id`.
    pub fn thermo_of_temp(&self, id: &str, sys: &System) -> Result<crate::engine::Thermo, String> {
        match self.compute(id).map(|c| &c.kind) {
            Some(ComputeKind::Temp) => Ok(sys.thermo()),
            Some(ComputeKind::TempDeform) => Ok(sys.thermo_deform()),
            Some(k) => Err(format!(
                "compute '{id}' is a {} compute, not a temperature",
                k.style()
            )),
            None => Err(format!("temperature compute '{id}' does not exist")),
        }
    }

    /// The state of pressure compute `id` (its temperature's kinetic part + the virial).
    pub fn thermo_of_press(&self, id: &str, sys: &System) -> Result<crate::engine::Thermo, String> {
        match self.compute(id).map(|c| &c.kind) {
            Some(ComputeKind::Pressure(t)) => self.thermo_of_temp(t, sys),
            Some(k) => Err(format!(
                "compute '{id}' is a {} compute, not a pressure",
                k.style()
            )),
            None => Err(format!("pressure compute '{id}' does not exist")),
        }
    }

    /// `thermo_modify temp ID`: check `id` is a temperature and, as LAMMPS does, make the
    /// built-in `thermo_press` use it.
    pub fn set_thermo_temp(&mut self, id: &str) -> Result<(), String> {
        match self.compute(id).map(|c| c.kind.is_temperature()) {
            Some(true) => {}
            Some(false) => {
                return Err(format!(
                    "thermo_modify temp: compute '{id}' is not a temperature compute"
                ));
            }
            None => return Err(format!("thermo_modify temp: compute '{id}' does not exist")),
        }
        for c in &mut self.computes {
            if c.id == "thermo_press" {
                c.kind = ComputeKind::Pressure(id.to_string());
            }
        }
        Ok(())
    }

    /// True if `id` is a `compute pressure`.
    pub fn is_pressure(&self, id: &str) -> bool {
        matches!(
            self.compute(id).map(|c| &c.kind),
            Some(ComputeKind::Pressure(_))
        )
    }

    /// `uncompute ID`.
    pub fn uncompute(&mut self, id: &str) -> Result<(), String> {
        if BUILTIN_COMPUTES.contains(&id) {
            return Err(format!("the built-in compute '{id}' cannot be deleted"));
        }
        let pos = self
            .computes
            .iter()
            .position(|c| c.id == id)
            .ok_or_else(|| format!("no compute with ID '{id}'"))?;
        for f in &self.fixes {
            if f.uses_compute(id) {
                return Err(format!(
                    "compute '{id}' is used by fix '{}' (unfix it first)",
                    f.id
                ));
            }
        }
        for c in &self.computes {
            if c.id != id && matches!(&c.kind, ComputeKind::Pressure(t) if t == id) {
                return Err(format!("compute '{id}' is used by compute '{}'", c.id));
            }
        }
        self.computes.remove(pos);
        Ok(())
    }

    fn compute_scalar(&self, c: &ComputeDef, sys: &System) -> Result<f64, String> {
        Ok(match &c.kind {
            ComputeKind::Temp => sys.thermo().temp,
            ComputeKind::TempDeform => sys.thermo_deform().temp,
            ComputeKind::Pressure(t) => self.thermo_of_temp(t, sys)?.press,
            ComputeKind::Pe => sys.tally.energy,
            ComputeKind::Ke => sys.thermo().ke,
            k => {
                return Err(format!(
                    "compute {} '{}' does not calculate a global scalar",
                    k.style(),
                    c.id
                ));
            }
        })
    }

    fn compute_vector(&self, c: &ComputeDef, sys: &System) -> Result<Vec<f64>, String> {
        Ok(match &c.kind {
            ComputeKind::Temp => sys.thermo().ke_tensor.to_vec(),
            ComputeKind::TempDeform => sys.thermo_deform().ke_tensor.to_vec(),
            ComputeKind::Pressure(t) => self.thermo_of_temp(t, sys)?.p_tensor.to_vec(),
            ComputeKind::Msd(m) => m.compute(sys)?.to_vec(),
            k => {
                return Err(format!(
                    "compute {} '{}' does not calculate a global vector",
                    k.style(),
                    c.id
                ));
            }
        })
    }

    // ------------------------------------------------------------------ global values

    /// The value of `c_ID`, `c_ID[i]`, `f_ID`, `f_ID[i]` (for formulas and thermo output).
    pub fn reference(
        &self,
        kind: RefKind,
        id: &str,
        index: Option<usize>,
        env: &dyn Env,
    ) -> Result<f64, String> {
        let sys = env.system().ok_or("needs a simulation box")?;
        match kind {
            RefKind::Compute => {
                let c = self
                    .compute(id)
                    .ok_or_else(|| format!("compute '{id}' does not exist"))?;
                match index {
                    None => self.compute_scalar(c, sys),
                    Some(i) => {
                        let n = c.kind.vector_len().ok_or_else(|| {
                            format!(
                                "compute {} '{id}' does not calculate a global vector",
                                c.kind.style()
                            )
                        })?;
                        if i > n {
                            return Err(format!(
                                "compute '{id}' vector has {n} elements, [{i}] is out of range"
                            ));
                        }
                        Ok(self.compute_vector(c, sys)?[i - 1])
                    }
                }
            }
            RefKind::Fix => {
                if let Some(p) = sys.pex.iter().find(|p| p.id == id) {
                    return match index {
                        None => Ok(p.total),
                        Some(_) => Err(format!(
                            "fix pex/push '{id}' has a global scalar only (f_{id})"
                        )),
                    };
                }
                let f = self
                    .fix(id)
                    .ok_or_else(|| format!("fix '{id}' does not exist or has no global values"))?;
                match index {
                    None => f.scalar().ok_or_else(|| {
                        format!(
                            "fix {} '{id}' does not calculate a global scalar",
                            f.style()
                        )
                    }),
                    Some(i) => {
                        let n = f.vector_len().ok_or_else(|| {
                            format!(
                                "fix {} '{id}' does not calculate a global vector",
                                f.style()
                            )
                        })?;
                        if i > n {
                            return Err(format!(
                                "fix '{id}' vector has {n} elements, [{i}] is out of range"
                            ));
                        }
                        Ok(f.vector(i - 1))
                    }
                }
            }
        }
    }

    /// True if `c_ID…`/`f_ID…` is extensive (thermo output divides it by the atom count with
    /// `thermo_modify norm yes`, as LAMMPS).
    pub fn extensive(&self, kind: RefKind, id: &str, index: Option<usize>) -> bool {
        match kind {
            RefKind::Compute => self.compute(id).is_some_and(|c| c.kind.extensive()),
            RefKind::Fix => self.fix(id).is_some_and(|f| f.extensive(self, index)),
        }
    }

    fn value_extensive(&self, v: &ValueRef) -> bool {
        match &v.source {
            Source::Compute(id) => self.extensive(RefKind::Compute, id, v.index),
            Source::Fix(id) => self.extensive(RefKind::Fix, id, v.index),
            Source::Var(_) => false,
        }
    }

    fn global(&self, v: &ValueRef, env: &dyn Env) -> Result<f64, String> {
        match &v.source {
            Source::Compute(id) => self.reference(RefKind::Compute, id, v.index, env),
            Source::Fix(id) => self.reference(RefKind::Fix, id, v.index, env),
            Source::Var(name) => env.equal_variable(name),
        }
    }

    fn global_vector(&self, v: &ValueRef, env: &dyn Env) -> Result<Vec<f64>, String> {
        let sys = env.system().ok_or("needs a simulation box")?;
        match &v.source {
            Source::Compute(id) => {
                let c = self
                    .compute(id)
                    .ok_or_else(|| format!("compute '{id}' does not exist"))?;
                self.compute_vector(c, sys)
            }
            Source::Fix(id) => {
                let f = self
                    .fix(id)
                    .ok_or_else(|| format!("fix '{id}' does not exist"))?;
                let n = f.vector_len().ok_or_else(|| {
                    format!(
                        "fix {} '{id}' does not calculate a global vector",
                        f.style()
                    )
                })?;
                Ok((0..n).map(|i| f.vector(i)).collect())
            }
            Source::Var(name) => Err(format!(
                "v_{name}: vector-style variables are not supported"
            )),
        }
    }

    /// Check a global value for `style` in scalar or vector mode; returns the vector length in
    /// vector mode.
    fn check_global(
        &self,
        v: &ValueRef,
        vector: bool,
        nevery: i64,
        style: &str,
        env: &dyn Env,
    ) -> Result<Option<usize>, String> {
        let t = &v.text;
        match &v.source {
            Source::Compute(id) => {
                let c = self
                    .compute(id)
                    .ok_or_else(|| format!("{t}: compute ID '{id}' does not exist"))?;
                let name = c.kind.style();
                match (vector, v.index) {
                    (false, None) if !c.kind.has_scalar() => Err(format!(
                        "{t}: compute {name} does not calculate a global scalar"
                    )),
                    (false, Some(i)) => match c.kind.vector_len() {
                        None => Err(format!(
                            "{t}: compute {name} does not calculate a global vector"
                        )),
                        Some(n) if i > n => Err(format!(
                            "{t}: compute vector is accessed out of range ({n})"
                        )),
                        _ => Ok(None),
                    },
                    (true, None) => match c.kind.vector_len() {
                        None => Err(format!(
                            "{t}: compute {name} does not calculate a global vector"
                        )),
                        n => Ok(n),
                    },
                    (true, Some(_)) => Err(format!(
                        "{t}: compute {name} does not calculate a global array"
                    )),
                    _ => Ok(None),
                }
            }
            Source::Fix(id) => {
                let sys = env.system().ok_or("needs a simulation box")?;
                let (has_scalar, vlen, freq, name) = if sys.pex.iter().any(|p| &p.id == id) {
                    (true, None, 1, "pex/push")
                } else if let Some(f) = self.fix(id) {
                    (
                        f.scalar().is_some(),
                        f.vector_len(),
                        f.global_freq(),
                        f.style(),
                    )
                } else {
                    return Err(format!(
                        "{t}: fix ID '{id}' does not exist or has no global values"
                    ));
                };
                if nevery % freq != 0 {
                    return Err(format!(
                        "{t}: fix {name} is not computed at compatible times (its values change \
                         every {freq} steps; Nevery = {nevery})"
                    ));
                }
                match (vector, v.index) {
                    (false, None) if !has_scalar => Err(format!(
                        "{t}: fix {name} does not calculate a global scalar"
                    )),
                    (false, Some(i)) => match vlen {
                        None => Err(format!(
                            "{t}: fix {name} does not calculate a global vector"
                        )),
                        Some(n) if i > n => {
                            Err(format!("{t}: fix vector is accessed out of range ({n})"))
                        }
                        _ => Ok(None),
                    },
                    (true, None) => match vlen {
                        None => Err(format!(
                            "{t}: fix {name} does not calculate a global vector"
                        )),
                        n => Ok(n),
                    },
                    (true, Some(_)) => {
                        Err(format!("{t}: fix {name} global arrays are not supported"))
                    }
                    _ => Ok(None),
                }
            }
            Source::Var(name) => {
                if vector {
                    return Err(format!(
                        "{t}: fix {style} cannot use a variable in vector mode"
                    ));
                }
                if v.index.is_some() {
                    return Err(format!("{t}: vector-style variables are not supported"));
                }
                match env.var_style(name) {
                    VarStyle::Equal => Ok(None),
                    VarStyle::Undefined => Err(format!(
                        "{t}: variable '{name}' for fix {style} does not exist"
                    )),
                    _ => Err(format!(
                        "{t}: fix {style} variable '{name}' is not an equal-style variable"
                    )),
                }
            }
        }
    }

    /// Expand `c_ID[*]`, `c_ID[n*]`, `c_ID[*m]`, `c_ID[n*m]` (and `f_`) in scalar mode into
    /// single elements, as LAMMPS's `expand_args`.
    fn expand(&self, word: &str, vector: bool) -> Result<Vec<String>, String> {
        let Some((head, rest)) = word.split_once('[') else {
            return Ok(vec![word.to_string()]);
        };
        let Some(range) = rest.strip_suffix(']') else {
            return Ok(vec![word.to_string()]);
        };
        let Some((a, b)) = range.split_once('*') else {
            return Ok(vec![word.to_string()]);
        };
        if vector {
            return Err(format!(
                "'{word}': wildcards in vector mode would select array columns (not supported)"
            ));
        }
        let len = match (&word[..2], &head[2..]) {
            ("c_", id) => self.compute(id).and_then(|c| c.kind.vector_len()),
            ("f_", id) => self.fix(id).and_then(|f| f.vector_len()),
            _ => None,
        }
        .ok_or_else(|| format!("'{word}': wildcard on something without a global vector"))?;
        let lo = if a.is_empty() {
            1
        } else {
            a.parse()
                .map_err(|_| format!("'{word}': bad wildcard range"))?
        };
        let hi = if b.is_empty() {
            len
        } else {
            b.parse()
                .map_err(|_| format!("'{word}': bad wildcard range"))?
        };
        if lo < 1 || hi > len || lo > hi {
            return Err(format!("'{word}': wildcard range out of 1..{len}"));
        }
        Ok((lo..=hi).map(|i| format!("{head}[{i}]")).collect())
    }

    // ------------------------------------------------------------------ fixes

    /// Parse `fix ID all ave/time|ave/chunk|ave/histo …` (checked against `env`, not yet
    /// added). Writes the file header, as LAMMPS does when the fix is created.
    pub fn parse_fix(args: &[String], env: &dyn Env) -> Result<AveFix, String> {
        let obs = env.observe();
        let sys = env
            .system()
            .ok_or("fix needs a simulation box (create_box or read_data) first")?;
        let style = args[2].as_str();
        let usage = match style {
            "ave/time" => {
                "fix ID all ave/time Nevery Nrepeat Nfreq VALUES… [file F] [ave one|running|window M] [mode scalar|vector] [start S] [format FMT] [title1|title2|title3 T]"
            }
            "ave/chunk" => {
                "fix ID all ave/chunk Nevery Nrepeat Nfreq CHUNK-ID VALUES… [norm all|sample|none] [ave one|running|window M] [file F] [format FMT] [title1|title2|title3 T]"
            }
            _ => {
                "fix ID all ave/histo Nevery Nrepeat Nfreq LO HI NBINS VALUES… [mode scalar|vector] [beyond ignore|end|extra] [ave one|running|window M] [start S] [file F] [title1|title2|title3 T]"
            }
        };
        let nevery = parse_i64(arg(args, 3, usage)?, "Nevery")?;
        let nrepeat = parse_i64(arg(args, 4, usage)?, "Nrepeat")?;
        let nfreq = parse_i64(arg(args, 5, usage)?, "Nfreq")?;
        if nevery <= 0 || nrepeat <= 0 || nfreq <= 0 {
            return Err(format!(
                "illegal fix {style}: Nevery, Nrepeat, Nfreq must be > 0 (got {nevery} {nrepeat} {nfreq})"
            ));
        }
        if nfreq % nevery != 0 || nrepeat * nevery > nfreq {
            return Err(format!(
                "illegal fix {style}: Nfreq ({nfreq}) must be a multiple of Nevery ({nevery}) and \
                 Nrepeat*Nevery ({}) must not exceed Nfreq",
                nrepeat * nevery
            ));
        }
        // Values: everything up to the first keyword.
        let first = match style {
            "ave/time" => 6,
            "ave/chunk" => 7,
            _ => 9,
        };
        if args.len() < first {
            return Err(format!("missing arguments; usage: {usage}"));
        }
        let is_value = |w: &str| match style {
            "ave/time" => w.starts_with("c_") || w.starts_with("f_") || w.starts_with("v_"),
            "ave/chunk" => {
                w.starts_with("c_")
                    || w.starts_with("f_")
                    || w.starts_with("v_")
                    || matches!(
                        w,
                        "vx" | "vy"
                            | "vz"
                            | "fx"
                            | "fy"
                            | "fz"
                            | "density/number"
                            | "density/mass"
                            | "mass"
                            | "temp"
                    )
            }
            _ => {
                w.starts_with("c_")
                    || w.starts_with("f_")
                    || w.starts_with("v_")
                    || matches!(w, "x" | "y" | "z" | "vx" | "vy" | "vz" | "fx" | "fy" | "fz")
            }
        };
        let mut k = first;
        while k < args.len() && is_value(&args[k]) {
            k += 1;
        }
        let raw_values: Vec<&str> = args[first..k].iter().map(String::as_str).collect();
        if raw_values.is_empty() {
            return Err(format!("no values in fix {style}; usage: {usage}"));
        }
        // Keywords.
        let mut file = None;
        let mut ave = Ave::One;
        let mut vector = false;
        let mut start = 0i64;
        let mut format = " %g".to_string();
        let mut titles: [Option<String>; 3] = [None, None, None];
        let mut norm = Norm::All;
        let mut beyond = Beyond::Ignore;
        while k < args.len() {
            let key = args[k].as_str();
            if matches!(
                key,
                "off" | "overwrite" | "bias" | "adof" | "cdof" | "scale"
            ) {
                return Err(format!("fix {style} keyword '{key}' is not supported"));
            }
            let val = arg(args, k + 1, usage)?;
            let mut step = 2;
            match (key, style) {
                ("file", _) => file = Some(val.to_string()),
                ("ave", _) => {
                    let (a, n) = parse_ave(args, k, usage)?;
                    ave = a;
                    step = n;
                }
                ("mode", "ave/time" | "ave/histo") => {
                    vector = match val {
                        "scalar" => false,
                        "vector" => true,
                        o => return Err(format!("mode '{o}' must be scalar or vector")),
                    }
                }
                ("start", "ave/time" | "ave/histo") => {
                    start = parse_i64(val, "start")?;
                }
                ("format", "ave/time" | "ave/chunk") => format = check_format(val)?,
                ("title1", _) => titles[0] = Some(val.to_string()),
                ("title2", _) => titles[1] = Some(val.to_string()),
                ("title3", _) => titles[2] = Some(val.to_string()),
                ("norm", "ave/chunk") => {
                    norm = match val {
                        "all" => Norm::All,
                        "sample" => Norm::Sample,
                        "none" => Norm::None,
                        o => return Err(format!("norm '{o}' must be all, sample or none")),
                    }
                }
                ("beyond", "ave/histo") => {
                    beyond = match val {
                        "ignore" => Beyond::Ignore,
                        "end" => Beyond::End,
                        "extra" => Beyond::Extra,
                        o => return Err(format!("beyond '{o}' must be ignore, end or extra")),
                    }
                }
                _ => {
                    return Err(format!(
                        "unknown fix {style} keyword or value '{key}'; usage: {usage}"
                    ));
                }
            }
            k += step;
        }
        let sched = {
            let mut s = Schedule {
                nevery,
                nrepeat,
                nfreq,
                start,
                nvalid: 0,
                nvalid_last: -1,
                irepeat: 0,
            };
            s.nvalid = s.next_valid(sys.step as i64);
            s
        };
        let id = args[0].clone();
        let (kind, header) = match style {
            "ave/time" => {
                let mut values = Vec::new();
                for w in &raw_values {
                    for e in obs.expand(w, vector)? {
                        let (source, index) = parse_ref(&e)?
                            .ok_or_else(|| format!("'{e}' is not c_ID, f_ID or v_name"))?;
                        values.push(ValueRef {
                            text: e,
                            source,
                            index,
                        });
                    }
                }
                let mut nrows = 1;
                for (n, v) in values.iter().enumerate() {
                    let len = obs.check_global(v, vector, nevery, style, env)?;
                    if vector {
                        let len = len.unwrap_or(0);
                        if n == 0 {
                            nrows = len;
                        } else if len != nrows {
                            return Err(format!(
                                "fix ave/time columns have inconsistent lengths ({} has {len}, \
                                 {} has {nrows})",
                                v.text, values[0].text
                            ));
                        }
                    }
                }
                let names: Vec<&str> = values.iter().map(|v| v.text.as_str()).collect();
                let mut header = vec![
                    titles[0]
                        .clone()
                        .unwrap_or_else(|| format!("# Time-averaged data for fix {id}")),
                ];
                if vector {
                    header.push(
                        titles[1]
                            .clone()
                            .unwrap_or_else(|| "# TimeStep Number-of-rows".into()),
                    );
                    header.push(
                        titles[2]
                            .clone()
                            .unwrap_or_else(|| format!("# Row {}", names.join(" "))),
                    );
                } else {
                    header.push(
                        titles[1]
                            .clone()
                            .unwrap_or_else(|| format!("# TimeStep {}", names.join(" "))),
                    );
                }
                (
                    AveKind::Time(AveTime {
                        values,
                        vector,
                        nrows,
                        sum: Vec::new(),
                        avg: Averager::new(ave),
                        format,
                    }),
                    header,
                )
            }
            "ave/chunk" => {
                let cid = &args[6];
                match obs.compute(cid) {
                    Some(c) if matches!(c.kind, ComputeKind::Chunk(_)) => {}
                    Some(_) => {
                        return Err(format!(
                            "fix ave/chunk: compute '{cid}' is not a chunk/atom compute"
                        ));
                    }
                    None => {
                        return Err(format!(
                            "fix ave/chunk: chunk/atom compute '{cid}' does not exist"
                        ));
                    }
                }
                let mut values = Vec::new();
                for w in &raw_values {
                    values.push(match *w {
                        "vx" => ChunkValue::V(0),
                        "vy" => ChunkValue::V(1),
                        "vz" => ChunkValue::V(2),
                        "fx" => ChunkValue::F(0),
                        "fy" => ChunkValue::F(1),
                        "fz" => ChunkValue::F(2),
                        "density/number" => ChunkValue::DensityNumber,
                        "density/mass" => ChunkValue::DensityMass,
                        "mass" => ChunkValue::Mass,
                        "temp" => ChunkValue::Temp,
                        w => match parse_ref(w)? {
                            Some((Source::Var(name), None)) => match env.var_style(&name) {
                                VarStyle::Atom => ChunkValue::Var(name),
                                VarStyle::Undefined => {
                                    return Err(format!(
                                        "{w}: variable '{name}' for fix ave/chunk does not exist"
                                    ));
                                }
                                _ => {
                                    return Err(format!(
                                        "{w}: fix ave/chunk variable '{name}' is not an \
                                         atom-style variable"
                                    ));
                                }
                            },
                            _ => {
                                return Err(format!(
                                    "fix ave/chunk value '{w}' not supported (vx vy vz fx fy fz \
                                     density/number density/mass mass temp v_NAME)"
                                ));
                            }
                        },
                    });
                }
                let header = vec![
                    titles[0].clone().unwrap_or_else(|| {
                        format!("# Chunk-averaged data for fix {id} and group all")
                    }),
                    titles[1]
                        .clone()
                        .unwrap_or_else(|| "# Timestep Number-of-chunks Total-count".into()),
                    titles[2].clone().unwrap_or_else(|| {
                        format!("# Chunk Coord1 Ncount {}", raw_values.join(" "))
                    }),
                ];
                (
                    AveKind::Chunk(AveChunk {
                        chunk: cid.clone(),
                        values,
                        norm,
                        adof: sys.dim() as f64,
                        nchunk: 0,
                        coord: Vec::new(),
                        count_many: Vec::new(),
                        values_many: Vec::new(),
                        count_sum: Vec::new(),
                        avg: Averager::new(ave),
                        format,
                        lock_forever: false,
                    }),
                    header,
                )
            }
            _ => {
                let lo = parse_num(&args[6], "histogram lo")?;
                let hi = parse_num(&args[7], "histogram hi")?;
                let nbins = parse_i64(&args[8], "number of bins")?;
                if lo >= hi {
                    return Err(format!("illegal fix ave/histo: lo {lo} >= hi {hi}"));
                }
                if nbins <= 0 {
                    return Err(format!("illegal fix ave/histo: {nbins} bins"));
                }
                let mut inputs = Vec::new();
                for w in &raw_values {
                    if let Some(a) = AtomValue::from_word(w) {
                        inputs.push(HistoInput::Atom(a));
                        continue;
                    }
                    for e in obs.expand(w, vector)? {
                        let (source, index) = parse_ref(&e)?
                            .ok_or_else(|| format!("'{e}' is not c_ID, f_ID or v_name"))?;
                        if let Source::Var(name) = &source
                            && env.var_style(name) == VarStyle::Atom
                        {
                            if index.is_some() {
                                return Err(format!("{e}: atom-style variables take no index"));
                            }
                            inputs.push(HistoInput::AtomVar(name.clone()));
                            continue;
                        }
                        if let Source::Compute(cid) = &source
                            && obs
                                .compute(cid)
                                .is_some_and(|c| matches!(c.kind, ComputeKind::Chunk(_)))
                        {
                            return Err(format!(
                                "{e}: per-atom computes are not supported in fix ave/histo"
                            ));
                        }
                        let v = ValueRef {
                            text: e,
                            source,
                            index,
                        };
                        obs.check_global(&v, vector, nevery, style, env)?;
                        inputs.push(HistoInput::Global(v));
                    }
                }
                let peratom = matches!(inputs[0], HistoInput::Atom(_) | HistoInput::AtomVar(_));
                if inputs
                    .iter()
                    .any(|i| matches!(i, HistoInput::Global(_)) == peratom)
                {
                    return Err("fix ave/histo inputs are not all global or all per-atom".into());
                }
                if peratom && !vector {
                    return Err("fix ave/histo cannot input per-atom values in scalar mode \
                                (add 'mode vector')"
                        .into());
                }
                let bins = HistoBins::new(lo, hi, nbins as usize, beyond);
                let header = vec![
                    titles[0]
                        .clone()
                        .unwrap_or_else(|| format!("# Histogrammed data for fix {id}")),
                    titles[1].clone().unwrap_or_else(|| {
                        "# TimeStep Number-of-bins Total-counts Missing-counts Min-value Max-value"
                            .into()
                    }),
                    titles[2]
                        .clone()
                        .unwrap_or_else(|| "# Bin Coord Count Count/Total".into()),
                ];
                (
                    AveKind::Histo(AveHisto {
                        inputs,
                        vector,
                        acc: bins.empty(),
                        bins,
                        avg: Averager::new(ave),
                        minmax: Vec::new(),
                        total_minmax: [0.0, 0.0],
                    }),
                    header,
                )
            }
        };
        let file = match file {
            None => None,
            Some(path) => {
                let f = File::create(&path)
                    .map_err(|e| format!("cannot open fix {style} file {path}: {e}"))?;
                let mut w = BufWriter::new(f);
                for line in &header {
                    writeln!(w, "{line}").map_err(io_err(&path))?;
                }
                w.flush().map_err(io_err(&path))?;
                Some((path, w))
            }
        };
        Ok(AveFix {
            id,
            sched,
            file,
            kind,
        })
    }

    /// Add a parsed fix.
    pub fn add_fix(&mut self, f: AveFix) {
        self.fixes.push(f);
    }

    /// `unfix ID`: true if it was one of these fixes.
    pub fn unfix(&mut self, id: &str) -> bool {
        self.locks.retain(|(_, l)| l.fix != id);
        let before = self.fixes.len();
        self.fixes.retain(|f| f.id != id);
        self.fixes.len() != before
    }

    /// The ID of a fix of this module that reads fix `id`, if any.
    pub fn fix_user(&self, id: &str) -> Option<&str> {
        self.fixes
            .iter()
            .find(|f| f.uses_fix(id))
            .map(|f| f.id.as_str())
    }

    /// At the start of every run: LAMMPS `init` (re-schedules fixes whose next sample is past).
    pub fn init(&mut self, step: u64) {
        for f in self.fixes.iter_mut() {
            f.sched.init(step as i64);
        }
    }

    /// Phase 1 of `end_of_step` for fix `id`: the sample, if this step is one of its sampling
    /// steps.
    pub fn sample(&self, id: &str, env: &dyn Env) -> Result<Option<Sample>, String> {
        let Some(f) = self.fix(id) else {
            return Ok(None);
        };
        let sys = env.system().ok_or("needs a simulation box")?;
        if !f.sched.due(sys.step as i64, f.style())? {
            return Ok(None);
        }
        let s = match &f.kind {
            AveKind::Time(t) => {
                let mut out = Vec::with_capacity(t.nrows * t.values.len());
                if t.vector {
                    let cols = t
                        .values
                        .iter()
                        .map(|v| self.global_vector(v, env))
                        .collect::<Result<Vec<_>, _>>()?;
                    for r in 0..t.nrows {
                        for c in &cols {
                            out.push(c.get(r).copied().unwrap_or(0.0));
                        }
                    }
                } else {
                    for v in &t.values {
                        out.push(self.global(v, env)?);
                    }
                }
                Sample::Time(out)
            }
            AveKind::Chunk(c) => self.sample_chunk(c, env, sys)?,
            AveKind::Histo(h) => {
                let mut s = h.bins.empty();
                for input in &h.inputs {
                    match input {
                        HistoInput::Atom(a) => {
                            for i in 0..sys.atoms.len() {
                                h.bins.add(&mut s, measure::atom_value(sys, i, *a));
                            }
                        }
                        HistoInput::AtomVar(name) => {
                            for v in env.atom_variable(name)? {
                                h.bins.add(&mut s, v);
                            }
                        }
                        HistoInput::Global(v) if h.vector => {
                            for x in self.global_vector(v, env)? {
                                h.bins.add(&mut s, x);
                            }
                        }
                        HistoInput::Global(v) => h.bins.add(&mut s, self.global(v, env)?),
                    }
                }
                Sample::Histo(s)
            }
        };
        Ok(Some(s))
    }

    fn sample_chunk(&self, c: &AveChunk, env: &dyn Env, sys: &System) -> Result<Sample, String> {
        let Some(ComputeKind::Chunk(b)) = self.compute(&c.chunk).map(|d| &d.kind) else {
            return Err(format!(
                "chunk/atom compute '{}' for fix ave/chunk does not exist",
                c.chunk
            ));
        };
        let layout = b.layout(&sys.bx)?;
        let bins = layout.assign(sys);
        let n = layout.len();
        let nv = c.values.len();
        let mut count = vec![0.0; n];
        let mut values = vec![0.0; n * nv];
        for b in bins.iter().flatten() {
            count[*b] += 1.0;
        }
        for (m, v) in c.values.iter().enumerate() {
            let per_atom: Vec<f64> = match v {
                ChunkValue::V(d) => sys.atoms.v.iter().map(|v| v[*d]).collect(),
                ChunkValue::F(d) => sys.atoms.f.iter().map(|f| f[*d]).collect(),
                ChunkValue::DensityNumber => vec![1.0; sys.atoms.len()],
                ChunkValue::DensityMass | ChunkValue::Mass => (0..sys.atoms.len())
                    .map(|i| measure::mass_of(sys, i))
                    .collect(),
                ChunkValue::Temp => (0..sys.atoms.len())
                    .map(|i| {
                        let v = sys.atoms.v[i];
                        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * measure::mass_of(sys, i)
                    })
                    .collect(),
                ChunkValue::Var(name) => env.atom_variable(name)?,
            };
            for (i, b) in bins.iter().enumerate() {
                if let Some(b) = b {
                    values[b * nv + m] += per_atom[i];
                }
            }
        }
        Ok(Sample::Chunk {
            coord: layout.coord,
            volume: layout.volume,
            count,
            values,
        })
    }

    /// Phase 2 of `end_of_step`: accumulate the sample of fix `id` taken at `step`; on the
    /// last sample of an Nfreq epoch, average and write the file.
    pub fn accumulate(&mut self, id: &str, sample: Sample, step: u64) -> Result<(), String> {
        let Some(k) = self.fixes.iter().position(|f| f.id == id) else {
            return Ok(());
        };
        if let AveKind::Chunk(c) = &self.fixes[k].kind {
            // LAMMPS locks the chunk compute on the first sample of an epoch.
            let s = &self.fixes[k].sched;
            let (chunk, ave, forever) = (c.chunk.clone(), c.avg.ave, c.lock_forever);
            let step = step as i64;
            if s.irepeat == 0 {
                if s.nrepeat > 1 && ave == Ave::One {
                    let stop = step + (s.nrepeat - 1) * s.nevery;
                    self.lock(&chunk, id, step, stop)?;
                } else if ave != Ave::One && !forever {
                    self.lock(&chunk, id, step, -1)?;
                    if let AveKind::Chunk(c) = &mut self.fixes[k].kind {
                        c.lock_forever = true;
                    }
                }
            } else if s.irepeat + 1 == s.nrepeat && s.nrepeat > 1 && ave == Ave::One {
                self.unlock(&chunk, id);
            }
        }
        let f = &mut self.fixes[k];
        let first = f.sched.irepeat == 0;
        let done = f.sched.sampled(step as i64);
        let nrepeat = f.sched.nrepeat as f64;
        let mut text = String::new();
        match (&mut f.kind, sample) {
            (AveKind::Time(t), Sample::Time(x)) => {
                if first {
                    t.sum = vec![0.0; x.len()];
                }
                for (s, v) in t.sum.iter_mut().zip(&x) {
                    *s += v;
                }
                if !done {
                    return Ok(());
                }
                for s in t.sum.iter_mut() {
                    *s /= nrepeat;
                }
                t.avg.push(&t.sum);
                let nv = t.values.len();
                let norm = t.avg.norm as f64;
                if t.vector {
                    text.push_str(&format!("{step} {}\n", t.nrows));
                    for r in 0..t.nrows {
                        text.push_str(&(r + 1).to_string());
                        for c in 0..nv {
                            let v = t.avg.total[r * nv + c] / norm;
                            text.push_str(&sprintf(&t.format, &[FmtArg::Float(v)])?);
                        }
                        text.push('\n');
                    }
                } else {
                    text.push_str(&step.to_string());
                    for c in 0..nv {
                        let v = t.avg.total[c] / norm;
                        text.push_str(&sprintf(&t.format, &[FmtArg::Float(v)])?);
                    }
                    text.push('\n');
                }
            }
            (
                AveKind::Chunk(c),
                Sample::Chunk {
                    coord,
                    volume,
                    count,
                    values,
                },
            ) => {
                let nv = c.values.len();
                if first {
                    c.nchunk = coord.len();
                    c.coord = coord;
                    c.count_many = vec![0.0; c.nchunk];
                    c.values_many = vec![0.0; c.nchunk * nv];
                    c.count_sum = vec![0.0; c.nchunk];
                } else if coord.len() != c.nchunk {
                    return Err(format!(
                        "fix ave/chunk '{id}': the number of chunks changed within an Nfreq epoch"
                    ));
                }
                let n = c.nchunk;
                match c.norm {
                    Norm::All => {
                        for m in 0..n {
                            c.count_many[m] += count[m];
                            for j in 0..nv {
                                c.values_many[m * nv + j] += values[m * nv + j];
                            }
                        }
                    }
                    Norm::Sample | Norm::None => {
                        c.count_many.copy_from_slice(&count);
                        for m in 0..n {
                            let cm = c.count_many[m];
                            if cm > 0.0 {
                                for j in 0..nv {
                                    let v = values[m * nv + j];
                                    c.values_many[m * nv + j] += match c.values[j] {
                                        ChunkValue::Temp => v / (c.adof * cm),
                                        ChunkValue::DensityNumber | ChunkValue::DensityMass => v,
                                        _ if c.norm == Norm::None => v,
                                        _ => v / cm,
                                    };
                                }
                            }
                            c.count_sum[m] += cm;
                        }
                    }
                }
                if !done {
                    return Ok(());
                }
                // Time average across the Nrepeat samples (LAMMPS's operations, in order).
                let mut count_sum = vec![0.0; n];
                let mut values_sum = vec![0.0; n * nv];
                match c.norm {
                    Norm::All => {
                        count_sum.copy_from_slice(&c.count_many);
                        values_sum.copy_from_slice(&c.values_many);
                        for m in 0..n {
                            if count_sum[m] > 0.0 {
                                for j in 0..nv {
                                    let v = &mut values_sum[m * nv + j];
                                    match c.values[j] {
                                        ChunkValue::Temp => *v *= 1.0 / (c.adof * count_sum[m]),
                                        ChunkValue::DensityMass => *v *= 1.0 / nrepeat,
                                        ChunkValue::DensityNumber => *v /= nrepeat,
                                        _ => *v /= count_sum[m],
                                    }
                                }
                            }
                            count_sum[m] /= nrepeat;
                        }
                    }
                    Norm::Sample | Norm::None => {
                        for m in 0..n {
                            for j in 0..nv {
                                values_sum[m * nv + j] = c.values_many[m * nv + j] / nrepeat;
                            }
                            count_sum[m] = c.count_sum[m] / nrepeat;
                        }
                    }
                }
                for j in 0..nv {
                    if matches!(
                        c.values[j],
                        ChunkValue::DensityNumber | ChunkValue::DensityMass
                    ) {
                        for m in 0..n {
                            values_sum[m * nv + j] /= volume;
                        }
                    }
                }
                let mut flat = count_sum;
                flat.extend_from_slice(&values_sum);
                c.avg.push(&flat);
                let norm = c.avg.norm as f64;
                let total: f64 = c.avg.total[..n].iter().sum();
                text.push_str(&format!(
                    "{step} {n} {}\n",
                    sprintf("%g", &[FmtArg::Float(total)])?
                ));
                for m in 0..n {
                    text.push_str(&format!(
                        "  {} {} {}",
                        m + 1,
                        sprintf("%g", &[FmtArg::Float(c.coord[m])])?,
                        sprintf("%g", &[FmtArg::Float(c.avg.total[m] / norm)])?
                    ));
                    for j in 0..nv {
                        let v = c.avg.total[n + m * nv + j] / norm;
                        text.push_str(&sprintf(&c.format, &[FmtArg::Float(v)])?);
                    }
                    text.push('\n');
                }
            }
            (AveKind::Histo(h), Sample::Histo(s)) => {
                if first {
                    h.acc = h.bins.empty();
                }
                for (a, b) in h.acc.bins.iter_mut().zip(&s.bins) {
                    *a += b;
                }
                h.acc.stats[0] += s.stats[0];
                h.acc.stats[1] += s.stats[1];
                h.acc.stats[2] = h.acc.stats[2].min(s.stats[2]);
                h.acc.stats[3] = h.acc.stats[3].max(s.stats[3]);
                if !done {
                    return Ok(());
                }
                let mut flat = vec![h.acc.stats[0], h.acc.stats[1]];
                flat.extend_from_slice(&h.acc.bins);
                h.avg.push(&flat);
                let (mn, mx) = (h.acc.stats[2], h.acc.stats[3]);
                h.total_minmax = match h.avg.ave {
                    Ave::One => [mn, mx],
                    // LAMMPS starts the running min and max from 0, not from ±BIG.
                    Ave::Running => [h.total_minmax[0].min(mn), h.total_minmax[1].max(mx)],
                    Ave::Window(nw) => {
                        // avg.push already advanced its slot: the one just filled is before it.
                        let slot = (h.avg.iwindow + nw - 1) % nw;
                        if h.minmax.len() < nw {
                            h.minmax = vec![[0.0, 0.0]; nw];
                        }
                        h.minmax[slot] = [mn, mx];
                        let m = if h.avg.full { nw } else { slot + 1 };
                        let mut t = h.minmax[0];
                        for e in &h.minmax[1..m] {
                            t = [t[0].min(e[0]), t[1].max(e[1])];
                        }
                        t
                    }
                };
                let tot = &h.avg.total;
                let g = |v: f64| sprintf("%g", &[FmtArg::Float(v)]);
                text.push_str(&format!(
                    "{step} {} {} {} {} {}\n",
                    h.bins.nbins,
                    g(tot[0])?,
                    g(tot[1])?,
                    g(h.total_minmax[0])?,
                    g(h.total_minmax[1])?
                ));
                for i in 0..h.bins.nbins {
                    let (count, frac) = if tot[0] != 0.0 {
                        (tot[2 + i], tot[2 + i] / tot[0])
                    } else {
                        (0.0, 0.0)
                    };
                    text.push_str(&format!(
                        "{} {} {} {}\n",
                        i + 1,
                        g(h.bins.coord[i])?,
                        g(count)?,
                        g(frac)?
                    ));
                }
            }
            _ => return Err(format!("fix '{id}': sample of the wrong kind")),
        }
        if let Some((path, w)) = f.file.as_mut() {
            w.write_all(text.as_bytes()).map_err(io_err(path))?;
            w.flush().map_err(io_err(path))?;
        }
        Ok(())
    }
}

impl AveFix {
    fn uses_compute(&self, id: &str) -> bool {
        let v = |v: &ValueRef| v.source == Source::Compute(id.to_string());
        match &self.kind {
            AveKind::Time(t) => t.values.iter().any(v),
            AveKind::Chunk(c) => c.chunk == id,
            AveKind::Histo(h) => h.inputs.iter().any(|i| match i {
                HistoInput::Global(x) => v(x),
                _ => false,
            }),
        }
    }

    fn uses_fix(&self, id: &str) -> bool {
        let v = |v: &ValueRef| v.source == Source::Fix(id.to_string());
        match &self.kind {
            AveKind::Time(t) => t.values.iter().any(v),
            AveKind::Chunk(_) => false,
            AveKind::Histo(h) => h.inputs.iter().any(|i| match i {
                HistoInput::Global(x) => v(x),
                _ => false,
            }),
        }
    }
}

/// A compute or fix reference: kind, ID, 1-based index (None: the scalar).
pub type Reference<'a> = (RefKind, &'a str, Option<usize>);

/// Split a thermo keyword `c_ID`, `c_ID[i]`, `f_ID`, `f_ID[i]`; None for other keywords.
pub fn split_reference(kw: &str) -> Option<Result<Reference<'_>, String>> {
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
