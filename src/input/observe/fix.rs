//! The averaging fixes `ave/time`, `ave/chunk`, `ave/histo`: what they share (the common
//! arguments and keywords, the file and its header, the fix's global values, the two phases of
//! `end_of_step`); what is particular to each is in `ave_time`, `ave_chunk`, `ave_histo`.

use super::ave_args::{Epoch, FixArgs, Norm};
use super::ave_chunk::{self, AveChunk};
use super::ave_histo::{self, AveHisto, HistoInput};
use super::ave_time::{self, AveTime};
use super::average::{Ave, Schedule};
use super::{
    Env, Observe, Sample, Source, ValueRef, arg, check_format, io_err, parse_ave, parse_i64,
};
use crate::engine::measure::Beyond;
use std::fs::File;
use std::io::{BufWriter, Write};

#[derive(Debug)]
pub(super) enum AveKind {
    Time(AveTime),
    Chunk(AveChunk),
    Histo(AveHisto),
}

/// A time-averaging fix.
#[derive(Debug)]
pub struct AveFix {
    pub(super) id: String,
    pub(super) sched: Schedule,
    pub(super) file: Option<(String, BufWriter<File>)>,
    pub(super) kind: AveKind,
}

impl AveFix {
    pub(super) fn style(&self) -> &'static str {
        match self.kind {
            AveKind::Time(_) => "ave/time",
            AveKind::Chunk(_) => "ave/chunk",
            AveKind::Histo(_) => "ave/histo",
        }
    }

    /// LAMMPS's `global_freq`: the fix's global values change on multiples of Nfreq.
    pub(super) fn global_freq(&self) -> i64 {
        self.sched.nfreq
    }

    pub(super) fn scalar(&self) -> Option<f64> {
        match &self.kind {
            AveKind::Time(t) if !t.vector && t.values.len() == 1 => Some(t.value(0, 0)),
            _ => None,
        }
    }

    pub(super) fn vector_len(&self) -> Option<usize> {
        match &self.kind {
            AveKind::Time(t) if !t.vector && t.values.len() > 1 => Some(t.values.len()),
            AveKind::Time(t) if t.vector && t.values.len() == 1 => Some(t.nrows),
            AveKind::Histo(_) => Some(4),
            _ => None,
        }
    }

    /// Element `i` (0-based) of the global vector.
    pub(super) fn vector(&self, i: usize) -> f64 {
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

    pub(super) fn extensive(&self, obs: &Observe, index: Option<usize>) -> bool {
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

impl Observe {
    // ------------------------------------------------------------------ fixes

    /// Parse `fix ID all ave/time|ave/chunk|ave/histo …` (checked against `env`, not yet
    /// added). Writes the file header, as LAMMPS does when the fix is created.
    pub fn parse_fix(args: &[String], env: &dyn Env) -> Result<AveFix, String> {
        let sys = env
            .system()
            .ok_or("fix needs a simulation box (create_box or read_data) first")?;
        let style = args[2].as_str();
        let usage = fix_usage(style);
        let (nevery, nrepeat, nfreq) = parse_counts(args, style, usage)?;
        let (raw_values, k) = value_words(args, style, usage)?;
        let Keywords {
            file,
            ave,
            vector,
            start,
            format,
            titles,
            norm,
            beyond,
        } = Keywords::parse(args, k, style, usage)?;
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
        let f = FixArgs {
            args,
            id: &id,
            style,
            sys,
            raw_values,
            nevery,
            ave,
            vector,
            format,
            titles,
            norm,
            beyond,
        };
        let (kind, header) = match style {
            "ave/time" => {
                let (t, header) = ave_time::parse(f, env)?;
                (AveKind::Time(t), header)
            }
            "ave/chunk" => {
                let (c, header) = ave_chunk::parse(f, env)?;
                (AveKind::Chunk(c), header)
            }
            _ => {
                let (h, header) = ave_histo::parse(f, env)?;
                (AveKind::Histo(h), header)
            }
        };
        let file = match file {
            None => None,
            Some(path) => Some(open_file(path, style, &header)?),
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
            AveKind::Time(t) => self.sample_time(t, env)?,
            AveKind::Chunk(c) => self.sample_chunk(c, env, sys)?,
            AveKind::Histo(h) => self.sample_histo(h, env, sys)?,
        };
        Ok(Some(s))
    }

    /// Phase 2 of `end_of_step`: accumulate the sample of fix `id` taken at `step`; on the
    /// last sample of an Nfreq epoch, average and write the file.
    pub fn accumulate(&mut self, id: &str, sample: Sample, step: u64) -> Result<(), String> {
        let Some(k) = self.fixes.iter().position(|f| f.id == id) else {
            return Ok(());
        };
        let lock = match &self.fixes[k].kind {
            AveKind::Chunk(c) => Some(c.lock_request(&self.fixes[k].sched)),
            _ => None,
        };
        if let Some(r) = lock
            && self.lock_chunk(r, id, step)?
            && let AveKind::Chunk(c) = &mut self.fixes[k].kind
        {
            c.lock_forever = true;
        }
        let f = &mut self.fixes[k];
        let first = f.sched.irepeat == 0;
        let done = f.sched.sampled(step as i64);
        let nrepeat = f.sched.nrepeat as f64;
        let e = Epoch {
            id,
            step,
            first,
            done,
            nrepeat,
        };
        let text = match (&mut f.kind, sample) {
            (AveKind::Time(t), Sample::Time(x)) => ave_time::accumulate(t, x, e)?,
            (
                AveKind::Chunk(c),
                Sample::Chunk {
                    coord,
                    volume,
                    count,
                    values,
                },
            ) => ave_chunk::accumulate(c, coord, volume, count, values, e)?,
            (AveKind::Histo(h), Sample::Histo(s)) => ave_histo::accumulate(h, s, e)?,
            _ => return Err(format!("fix '{id}': sample of the wrong kind")),
        };
        let Some(text) = text else {
            return Ok(());
        };
        if let Some((path, w)) = f.file.as_mut() {
            w.write_all(text.as_bytes()).map_err(io_err(path))?;
            w.flush().map_err(io_err(path))?;
        }
        Ok(())
    }
}

impl AveFix {
    pub(super) fn uses_compute(&self, id: &str) -> bool {
        let v = |v: &ValueRef| v.source == Source::Compute(id.to_string());
        match &self.kind {
            AveKind::Time(t) => t.values.iter().any(v),
            AveKind::Chunk(c) => c.chunk == id || c.uses_value_compute(id),
            AveKind::Histo(h) => h.inputs.iter().any(|i| match i {
                HistoInput::Global(x) => v(x),
                _ => false,
            }),
        }
    }

    pub(super) fn uses_fix(&self, id: &str) -> bool {
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

/// The usage line of averaging fix `style`.
fn fix_usage(style: &str) -> &'static str {
    match style {
        "ave/time" => {
            "fix ID all ave/time Nevery Nrepeat Nfreq VALUES… [file F] [ave one|running|window M] [mode scalar|vector] [start S] [format FMT] [title1|title2|title3 T]"
        }
        "ave/chunk" => {
            "fix ID all ave/chunk Nevery Nrepeat Nfreq CHUNK-ID VALUES… [norm all|sample|none] [ave one|running|window M] [file F] [format FMT] [title1|title2|title3 T]"
        }
        _ => {
            "fix ID all ave/histo Nevery Nrepeat Nfreq LO HI NBINS VALUES… [mode scalar|vector] [beyond ignore|end|extra] [ave one|running|window M] [start S] [file F] [title1|title2|title3 T]"
        }
    }
}

/// Nevery, Nrepeat, Nfreq (arguments 3–5), checked against each other as LAMMPS does.
fn parse_counts(args: &[String], style: &str, usage: &str) -> Result<(i64, i64, i64), String> {
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
    Ok((nevery, nrepeat, nfreq))
}

/// True if `w` is a value (not a keyword) of averaging fix `style`.
fn is_value(style: &str, w: &str) -> bool {
    match style {
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
    }
}

/// The values: every word from the style's first value up to the first keyword; with the
/// index of that keyword.
fn value_words<'a>(
    args: &'a [String],
    style: &str,
    usage: &str,
) -> Result<(Vec<&'a str>, usize), String> {
    let first = match style {
        "ave/time" => 6,
        "ave/chunk" => 7,
        _ => 9,
    };
    if args.len() < first {
        return Err(format!("missing arguments; usage: {usage}"));
    }
    let mut k = first;
    while k < args.len() && is_value(style, &args[k]) {
        k += 1;
    }
    let raw_values: Vec<&str> = args[first..k].iter().map(String::as_str).collect();
    if raw_values.is_empty() {
        return Err(format!("no values in fix {style}; usage: {usage}"));
    }
    Ok((raw_values, k))
}

/// The keywords of an averaging fix, with their defaults.
struct Keywords {
    file: Option<String>,
    ave: Ave,
    vector: bool,
    start: i64,
    format: String,
    titles: [Option<String>; 3],
    norm: Norm,
    beyond: Beyond,
}

impl Keywords {
    /// The keywords from `args[k..]`.
    fn parse(args: &[String], mut k: usize, style: &str, usage: &str) -> Result<Self, String> {
        let mut kw = Keywords {
            file: None,
            ave: Ave::One,
            vector: false,
            start: 0i64,
            format: " %g".to_string(),
            titles: [None, None, None],
            norm: Norm::All,
            beyond: Beyond::Ignore,
        };
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
                ("file", _) => kw.file = Some(val.to_string()),
                ("ave", _) => {
                    let (a, n) = parse_ave(args, k, usage)?;
                    kw.ave = a;
                    step = n;
                }
                ("mode", "ave/time" | "ave/histo") => {
                    kw.vector = match val {
                        "scalar" => false,
                        "vector" => true,
                        o => return Err(format!("mode '{o}' must be scalar or vector")),
                    }
                }
                ("start", "ave/time" | "ave/histo") => {
                    kw.start = parse_i64(val, "start")?;
                }
                ("format", "ave/time" | "ave/chunk") => kw.format = check_format(val)?,
                ("title1", _) => kw.titles[0] = Some(val.to_string()),
                ("title2", _) => kw.titles[1] = Some(val.to_string()),
                ("title3", _) => kw.titles[2] = Some(val.to_string()),
                ("norm", "ave/chunk") => {
                    kw.norm = match val {
                        "all" => Norm::All,
                        "sample" => Norm::Sample,
                        "none" => Norm::None,
                        o => return Err(format!("norm '{o}' must be all, sample or none")),
                    }
                }
                ("beyond", "ave/histo") => {
                    kw.beyond = match val {
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
        Ok(kw)
    }
}

/// Create the fix's file at `path` and write its header, as LAMMPS does when the fix is
/// created.
fn open_file(
    path: String,
    style: &str,
    header: &[String],
) -> Result<(String, BufWriter<File>), String> {
    let f = File::create(&path).map_err(|e| format!("cannot open fix {style} file {path}: {e}"))?;
    let mut w = BufWriter::new(f);
    for line in header {
        writeln!(w, "{line}").map_err(io_err(&path))?;
    }
    w.flush().map_err(io_err(&path))?;
    Ok((path, w))
}
