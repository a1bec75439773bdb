//! Readers for the text files of LAMMPS's averaging fixes, as LAMMPS (2021–2025) writes them
//! and as this project's standalone engine writes them in the same format:
//!
//! - `fix ave/time … file F` in scalar mode (default): two comment lines
//!   (`# Time-averaged data for fix ID`, `# TimeStep c_a v_b …`), then one line per output step:
//!   `step value value …`.
//! - `fix ave/time … mode vector file F`: three comment lines (`# Time-averaged data for fix
//!   ID`, `# TimeStep Number-of-rows`, `# Row c_a …`), then per output step a line
//!   `step nrows` followed by `nrows` lines `row value …`.
//! - `fix ave/chunk … file F`: `# Chunk-averaged data for fix ID and group G`,
//!   `# Timestep Number-of-chunks Total-count`, `# Chunk Coord1 Ncount value …` (bin/1d; other
//!   chunk styles have other leading columns, `OrigID` with `compress yes`), then per output
//!   step `step nchunks total` followed by one line per chunk.
//! - `fix ave/histo … file F`: `# Histogrammed data for fix ID`,
//!   `# TimeStep Number-of-bins Total-counts Missing-counts Min-value Max-value`,
//!   `# Bin Coord Count Count/Total`, then per output step the six header values followed by
//!   one line per bin.
//!
//! Comment lines may reappear later in a file (a fix redefined with `append`, or several runs):
//! they must name the same columns. Titles changed with `title1/2/3` are accepted when the
//! data are unambiguous (see [`parse_ave_time`]). YAML output (file names ending in `.yaml`) is
//! refused with a message. Every value must be a finite number: `nan`, `inf` or `1e999` is an
//! error, as is any unreadable token. Errors name the line (1-based), the column and the
//! offending token; callers add the file name. (A [`parse_series`] of a log follows
//! [`parse_log`], which reads the `nan`/`inf` that LAMMPS prints after a blow-up.)

use crate::io::lammps_log::parse_log;

/// Which kind of file a text looks like (from its first non-blank line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    AveTime,
    AveChunk,
    AveHisto,
    Dump,
    /// Anything else: read as a LAMMPS log (thermo blocks).
    Log,
}

/// Guesses the kind of a file from its first non-blank line (LAMMPS's default titles).
pub fn detect(text: &str) -> FileKind {
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("");
    if first.starts_with("# Time-averaged data") {
        FileKind::AveTime
    } else if first.starts_with("# Chunk-averaged data") {
        FileKind::AveChunk
    } else if first.starts_with("# Histogrammed data") {
        FileKind::AveHisto
    } else if first.starts_with("ITEM: TIMESTEP") {
        FileKind::Dump
    } else {
        FileKind::Log
    }
}

/// `fix ave/time` output in scalar mode: one row of values per output step.
#[derive(Debug, Clone, PartialEq)]
pub struct AveTimeScalar {
    /// Value names as in the header (`c_thermo_press[4]`, `v_t`, …), without `TimeStep`.
    pub columns: Vec<String>,
    pub steps: Vec<u64>,
    /// `rows[k][j]`: value `j` at output `k`.
    pub rows: Vec<Vec<f64>>,
}

/// One output step of a blocked file (vector-mode ave/time, ave/chunk, ave/histo).
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    pub step: u64,
    /// The numbers of the block's first line after the step (`nrows`; `nchunks total`;
    /// `nbins total missing min max`).
    pub header: Vec<f64>,
    /// One row per line, all columns (including the leading row/chunk/bin index).
    pub rows: Vec<Vec<f64>>,
    /// 1-based line number of the block's first line.
    pub line: usize,
}

/// `fix ave/time` output in vector mode.
#[derive(Debug, Clone, PartialEq)]
pub struct AveTimeVector {
    /// Column names after `Row` (`c_msd`, …). Each row of a block is `[row, values…]`.
    pub columns: Vec<String>,
    pub blocks: Vec<Block>,
}

/// A `fix ave/time` file, in either mode.
#[derive(Debug, Clone, PartialEq)]
pub enum AveTime {
    Scalar(AveTimeScalar),
    Vector(AveTimeVector),
}

/// `fix ave/chunk` output.
#[derive(Debug, Clone, PartialEq)]
pub struct AveChunk {
    /// All column names of a chunk line, e.g. `Chunk Coord1 Ncount vz density/number`.
    pub columns: Vec<String>,
    /// `header` = `[nchunks, total_count]` (`[nchunks]` in old files).
    pub blocks: Vec<Block>,
}

impl AveChunk {
    /// Index of a column: exact name, else the only case-insensitive match.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        column_index(&self.columns, name)
    }
}

/// One output of `fix ave/histo`.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoBlock {
    pub step: u64,
    /// Counts inside `[lo, hi]` over all samples of the output (`Total-counts`).
    pub total: f64,
    /// Counts outside `[lo, hi]` (`Missing-counts`; 0 with `beyond end|extra`).
    pub missing: f64,
    /// Smallest and largest value seen (`Min-value`, `Max-value`).
    pub min: f64,
    pub max: f64,
    /// Bin centres (`Coord`), counts (`Count`) and fractions (`Count/Total`).
    pub coord: Vec<f64>,
    pub count: Vec<f64>,
    pub fraction: Vec<f64>,
    pub line: usize,
}

/// `fix ave/histo` output.
#[derive(Debug, Clone, PartialEq)]
pub struct AveHisto {
    pub blocks: Vec<HistoBlock>,
}

/// A table of named columns against the time step, from an ave/time scalar file or a log.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub columns: Vec<String>,
    pub steps: Vec<f64>,
    /// Column-major: `data[j][k]` is column `j` at row `k`.
    pub data: Vec<Vec<f64>>,
}

/// The uniform step spacing of a series' steps (an error when there are fewer than two, when
/// they are not equally spaced or do not increase).
pub(crate) fn step_spacing(steps: &[f64]) -> Result<f64, String> {
    if steps.len() < 2 {
        return Err("fewer than two samples".into());
    }
    let d = steps[1] - steps[0];
    if let Some(k) = steps.windows(2).position(|w| w[1] - w[0] != d) {
        return Err(format!(
            "samples are not equally spaced (step {} after {}, spacing {d} before)",
            steps[k + 1],
            steps[k]
        ));
    }
    if d <= 0.0 {
        return Err("steps do not increase".into());
    }
    Ok(d)
}

impl Series {
    /// The rows at or after step `from`.
    pub fn from_step(self, from: u64) -> Series {
        let keep: Vec<bool> = self.steps.iter().map(|&k| k >= from as f64).collect();
        let pick = |v: &Vec<f64>| -> Vec<f64> {
            v.iter()
                .zip(&keep)
                .filter(|(_, k)| **k)
                .map(|(x, _)| *x)
                .collect()
        };
        Series {
            steps: pick(&self.steps),
            data: self.data.iter().map(pick).collect(),
            columns: self.columns,
        }
    }

    /// Columns `c_X[i]` for the given indices, for one X that has them all.
    pub fn indexed_columns(&self, idx: &[usize]) -> Option<Vec<String>> {
        for c in &self.columns {
            if let Some(base) = c.strip_suffix(&format!("[{}]", idx[0])) {
                let names: Vec<String> = idx.iter().map(|i| format!("{base}[{i}]")).collect();
                if names.iter().all(|n| self.column_index(n).is_some()) {
                    return Some(names);
                }
            }
        }
        None
    }

    /// Index of a column: exact name, else the only case-insensitive match.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        column_index(&self.columns, name)
    }
    /// The values of a column, or an error listing the available names.
    pub fn column(&self, name: &str) -> Result<&[f64], String> {
        self.column_index(name)
            .map(|j| self.data[j].as_slice())
            .ok_or_else(|| format!("no column '{name}' (columns: {})", self.columns.join(" ")))
    }
}

pub(crate) fn column_index(columns: &[String], name: &str) -> Option<usize> {
    if let Some(i) = columns.iter().position(|c| c == name) {
        return Some(i);
    }
    let mut it = columns
        .iter()
        .enumerate()
        .filter(|(_, c)| c.eq_ignore_ascii_case(name));
    match (it.next(), it.next()) {
        (Some((i, _)), None) => Some(i),
        _ => None,
    }
}

/// The values of a data line, each a finite number: NaN and infinities (`nan`, `inf`, `1e999`)
/// are refused with the line and column.
fn numbers(line: &str, ln: usize) -> Result<Vec<f64>, String> {
    line.split_whitespace()
        .enumerate()
        .map(|(i, t)| {
            crate::io::finite_f64(t)
                .map_err(|e| format!("line {ln}: column {}: {}", i + 1, e.describe(t)))
        })
        .collect()
}

fn step_of(v: f64, tok: &str, ln: usize) -> Result<u64, String> {
    if v >= 0.0 && v.fract() == 0.0 && v < 9.0e15 {
        Ok(v as u64)
    } else {
        Err(format!(
            "line {ln}: '{tok}' is not a time step (a non-negative integer)"
        ))
    }
}

fn count_of(v: f64, tok: &str, ln: usize, what: &str) -> Result<usize, String> {
    if v >= 0.0 && v.fract() == 0.0 && v < 1.0e9 {
        Ok(v as usize)
    } else {
        Err(format!("line {ln}: '{tok}' is not a valid {what}"))
    }
}

fn refuse_yaml(text: &str) -> Result<(), String> {
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("");
    if first == "---" || first.starts_with("keywords:") {
        return Err(
            "line 1: YAML output of an averaging fix is not supported; name the file without \
             .yaml/.yml to get the text format"
                .into(),
        );
    }
    Ok(())
}

/// Comment lines (`#`, text after it, trimmed) and data lines, both with 1-based numbers.
enum Line<'a> {
    Comment(usize, &'a str),
    Data(usize, &'a str),
}

fn lines(text: &str) -> Vec<Line<'_>> {
    text.lines()
        .enumerate()
        .filter_map(|(i, l)| {
            let t = l.trim();
            if t.is_empty() {
                None
            } else if let Some(c) = t.strip_prefix('#') {
                Some(Line::Comment(i + 1, c.trim()))
            } else {
                Some(Line::Data(i + 1, t))
            }
        })
        .collect()
}

/// Reads a blocked file: block lines of `header_lens` values (step first, row count second),
/// each followed by that many rows of `row_len` values (if given; else all rows of the file
/// must have the same length). Comment lines between blocks are passed to `on_comment`.
fn parse_blocked(
    text: &str,
    what: &str,
    header_lens: &[usize],
    row_len: Option<usize>,
    mut on_comment: impl FnMut(usize, &str) -> Result<(), String>,
) -> Result<Vec<Block>, String> {
    let all = lines(text);
    let mut blocks = Vec::new();
    let mut i = 0;
    let mut width = row_len;
    while i < all.len() {
        match all[i] {
            Line::Comment(ln, c) => {
                on_comment(ln, c)?;
                i += 1;
            }
            Line::Data(ln, l) => {
                let h = numbers(l, ln)?;
                if !header_lens.contains(&h.len()) {
                    return Err(format!(
                        "line {ln}: expected a {what} block line of {} values (step, count, …), \
                         found {} in '{l}'",
                        header_lens
                            .iter()
                            .map(|n| n.to_string())
                            .collect::<Vec<_>>()
                            .join(" or "),
                        h.len()
                    ));
                }
                let toks: Vec<&str> = l.split_whitespace().collect();
                let step = step_of(h[0], toks[0], ln)?;
                let n = count_of(h[1], toks[1], ln, "row count")?;
                let mut rows = Vec::with_capacity(n);
                i += 1;
                while rows.len() < n {
                    let Some(next) = all.get(i) else {
                        return Err(format!(
                            "line {ln}: {what} block of step {step} announces {n} rows, the \
                             file ends after {}",
                            rows.len()
                        ));
                    };
                    let (rl, r) = match *next {
                        Line::Data(rl, r) => (rl, r),
                        Line::Comment(rl, _) => {
                            return Err(format!(
                                "line {rl}: comment inside the {what} block of step {step} \
                                 ({} of {n} rows read)",
                                rows.len()
                            ));
                        }
                    };
                    let v = numbers(r, rl)?;
                    match width {
                        Some(w) if v.len() != w => {
                            return Err(format!(
                                "line {rl}: {what} row has {} values, expected {w}: '{r}'",
                                v.len()
                            ));
                        }
                        None => width = Some(v.len()),
                        _ => {}
                    }
                    rows.push(v);
                    i += 1;
                }
                blocks.push(Block {
                    step,
                    header: h[1..].to_vec(),
                    rows,
                    line: ln,
                });
            }
        }
    }
    Ok(blocks)
}

/// Remembers the column names from a header comment and checks later repeats against them.
fn set_columns(
    slot: &mut Option<Vec<String>>,
    names: Vec<String>,
    ln: usize,
) -> Result<(), String> {
    match slot {
        Some(old) if *old != names => Err(format!(
            "line {ln}: columns changed within the file ('{}' after '{}')",
            names.join(" "),
            old.join(" ")
        )),
        _ => {
            *slot = Some(names);
            Ok(())
        }
    }
}

/// Reads a `fix ave/time` file in scalar or vector mode.
///
/// The mode comes from the header (`# TimeStep Number-of-rows` or a `# Row …` line means
/// vector mode). With custom titles, a file whose data lines form consistent blocks
/// (`step n` followed by `n` lines numbered 1…n) is read as vector mode, else as scalar mode;
/// columns without a header are named `col1`, `col2`, ….
pub fn parse_ave_time(text: &str) -> Result<AveTime, String> {
    refuse_yaml(text)?;
    let mut vector_header = false;
    let mut scalar_cols: Option<Vec<String>> = None;
    for l in lines(text) {
        match l {
            Line::Comment(_, c) => {
                let toks: Vec<&str> = c.split_whitespace().collect();
                if toks.first() == Some(&"Row")
                    || (toks.len() == 2 && toks[0] == "TimeStep" && toks[1] == "Number-of-rows")
                {
                    vector_header = true;
                } else if toks.first() == Some(&"TimeStep") && scalar_cols.is_none() {
                    scalar_cols = Some(toks[1..].iter().map(|s| s.to_string()).collect());
                }
            }
            Line::Data(..) => break,
        }
    }
    if vector_header {
        return parse_ave_time_vector(text, true).map(AveTime::Vector);
    }
    if scalar_cols.is_none()
        && let Ok(v) = parse_ave_time_vector(text, false)
        && !v.blocks.is_empty()
    {
        return Ok(AveTime::Vector(v));
    }
    parse_ave_time_scalar(text).map(AveTime::Scalar)
}

fn parse_ave_time_vector(text: &str, strict: bool) -> Result<AveTimeVector, String> {
    let mut cols: Option<Vec<String>> = None;
    let blocks = parse_blocked(text, "fix ave/time (vector mode)", &[2], None, |ln, c| {
        let toks: Vec<&str> = c.split_whitespace().collect();
        if toks.first() == Some(&"Row") {
            set_columns(
                &mut cols,
                toks[1..].iter().map(|s| s.to_string()).collect(),
                ln,
            )?;
        }
        Ok(())
    })?;
    for b in &blocks {
        for (k, r) in b.rows.iter().enumerate() {
            if r.first().copied() != Some((k + 1) as f64) {
                return Err(format!(
                    "fix ave/time (vector mode), step {} (line {}): row {} is numbered {:?}",
                    b.step,
                    b.line,
                    k + 1,
                    r.first()
                ));
            }
        }
    }
    let width = blocks
        .iter()
        .find_map(|b| b.rows.first().map(Vec::len))
        .unwrap_or(1);
    let columns = match cols {
        Some(c) => {
            if width != c.len() + 1 {
                return Err(format!(
                    "fix ave/time (vector mode): the header names {} columns after 'Row' but \
                     the rows have {} values after the row number",
                    c.len(),
                    width - 1
                ));
            }
            c
        }
        None if strict => {
            return Err("fix ave/time (vector mode): no '# Row …' header line".into());
        }
        None => (1..width).map(|j| format!("col{j}")).collect(),
    };
    Ok(AveTimeVector { columns, blocks })
}

fn parse_ave_time_scalar(text: &str) -> Result<AveTimeScalar, String> {
    let mut cols: Option<Vec<String>> = None;
    let mut steps = Vec::new();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for l in lines(text) {
        match l {
            Line::Comment(ln, c) => {
                let toks: Vec<&str> = c.split_whitespace().collect();
                if toks.first() == Some(&"TimeStep") {
                    set_columns(
                        &mut cols,
                        toks[1..].iter().map(|s| s.to_string()).collect(),
                        ln,
                    )?;
                }
            }
            Line::Data(ln, d) => {
                let v = numbers(d, ln)?;
                let toks: Vec<&str> = d.split_whitespace().collect();
                let step = step_of(v[0], toks[0], ln)?;
                let width = cols
                    .as_ref()
                    .map(|c| c.len())
                    .or_else(|| rows.first().map(Vec::len))
                    .unwrap_or(v.len() - 1);
                if v.len() != width + 1 {
                    return Err(format!(
                        "line {ln}: fix ave/time row has {} values after the step, expected \
                         {width}: '{d}'",
                        v.len() - 1
                    ));
                }
                steps.push(step);
                rows.push(v[1..].to_vec());
            }
        }
    }
    let width = rows.first().map_or(0, Vec::len);
    let columns = cols.unwrap_or_else(|| (1..=width).map(|j| format!("col{j}")).collect());
    Ok(AveTimeScalar {
        columns,
        steps,
        rows,
    })
}

/// Reads a `fix ave/chunk` file.
pub fn parse_ave_chunk(text: &str) -> Result<AveChunk, String> {
    refuse_yaml(text)?;
    let mut cols: Option<Vec<String>> = None;
    let blocks = parse_blocked(text, "fix ave/chunk", &[2, 3], None, |ln, c| {
        let toks: Vec<&str> = c.split_whitespace().collect();
        if toks.first() == Some(&"Chunk") {
            set_columns(&mut cols, toks.iter().map(|s| s.to_string()).collect(), ln)?;
        }
        Ok(())
    })?;
    let columns = cols.ok_or("fix ave/chunk: no '# Chunk …' header line naming the columns")?;
    if let Some(b) = blocks
        .iter()
        .find(|b| b.rows.first().is_some_and(|r| r.len() != columns.len()))
    {
        return Err(format!(
            "line {}: fix ave/chunk rows have {} values, the header names {} columns ({})",
            b.line + 1,
            b.rows[0].len(),
            columns.len(),
            columns.join(" ")
        ));
    }
    Ok(AveChunk { columns, blocks })
}

/// Reads a `fix ave/histo` file (any `mode`; the bins must be the four standard columns).
pub fn parse_ave_histo(text: &str) -> Result<AveHisto, String> {
    refuse_yaml(text)?;
    let raw = parse_blocked(text, "fix ave/histo", &[6], Some(4), |_, _| Ok(()))?;
    let blocks = raw
        .into_iter()
        .map(|b| HistoBlock {
            step: b.step,
            total: b.header[1],
            missing: b.header[2],
            min: b.header[3],
            max: b.header[4],
            coord: b.rows.iter().map(|r| r[1]).collect(),
            count: b.rows.iter().map(|r| r[2]).collect(),
            fraction: b.rows.iter().map(|r| r[3]).collect(),
            line: b.line,
        })
        .collect();
    Ok(AveHisto { blocks })
}

/// A [`Series`] from a `fix ave/time` scalar-mode file or from the thermo output of a log.
///
/// Logs: the thermo blocks that have the same columns as the last block are joined in order;
/// a row whose step equals the previous row's (the first row of a `run` repeats the last row
/// of the one before) is dropped. The step column (`Step`) is taken out of the columns.
pub fn parse_series(text: &str) -> Result<Series, String> {
    match detect(text) {
        FileKind::AveTime => match parse_ave_time(text)? {
            AveTime::Scalar(s) => {
                let ncol = s.columns.len();
                let data = (0..ncol)
                    .map(|j| s.rows.iter().map(|r| r[j]).collect())
                    .collect();
                Ok(Series {
                    columns: s.columns,
                    steps: s.steps.iter().map(|&k| k as f64).collect(),
                    data,
                })
            }
            AveTime::Vector(_) => Err(
                "this fix ave/time file is in vector mode; a time series needs scalar mode \
                 (values like c_ID[1] c_ID[2] …)"
                    .into(),
            ),
        },
        FileKind::Log => {
            let blocks = parse_log(text)?;
            let last = blocks
                .last()
                .ok_or("no thermo block (a 'Step …' header followed by rows) in this log")?;
            let cols = last.columns.clone();
            let step_j =
                column_index(&cols, "Step").ok_or("the thermo header has no 'Step' column")?;
            let mut steps: Vec<f64> = Vec::new();
            let mut data: Vec<Vec<f64>> = vec![Vec::new(); cols.len() - 1];
            for b in blocks.iter().filter(|b| b.columns == cols) {
                for r in &b.rows {
                    if steps.last() == Some(&r[step_j]) {
                        continue;
                    }
                    steps.push(r[step_j]);
                    let mut j2 = 0;
                    for (j, v) in r.iter().enumerate() {
                        if j != step_j {
                            data[j2].push(*v);
                            j2 += 1;
                        }
                    }
                }
            }
            let columns = cols
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != step_j)
                .map(|(_, c)| c.clone())
                .collect();
            Ok(Series {
                columns,
                steps,
                data,
            })
        }
        other => Err(format!(
            "expected a fix ave/time file (scalar mode) or a log, found a {other:?} file"
        )),
    }
}
