//! LAMMPS log files: the thermo blocks, and column-by-column comparison of two logs or dumps.
//!
//! [`parse_log`] reads the thermo output that `thermo_style one/custom` prints (LAMMPS 2020 to
//! 2025 and this project's engine print the same shape): a header line whose first token is
//! `Step`, then one line of numbers per thermo step. A block ends at `Loop time of …` or at
//! the first other line that is not all numbers; `WARNING…` lines and blank lines inside a
//! block are skipped. A header followed by no rows is not a block. `thermo_style multi` and
//! `thermo_modify line yaml` output are not recognised.
//!
//! [`neighbor_summary`] reads LAMMPS's neighbour-list settings and "Dangerous builds" counts.
//!
//! The comparison functions ([`compare_exact`], [`compare_exact_logs`], [`compare_dumps_exact`],
//! [`compare_stats`]) return reports; the `dpdnl diff` command prints them, and other commands
//! (`crosscheck`) can use them directly.

use crate::io::dump_read::DumpFrame;
use crate::stats::{BlockEstimate, block_average};
use std::collections::BTreeMap;

/// One thermo block: the header's column names and the rows under it.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermoBlock {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl ThermoBlock {
    /// Index of column `name`: an exact match, else the only case-insensitive match
    /// (`temp` finds `Temp`).
    pub fn column_index(&self, name: &str) -> Option<usize> {
        column_index(&self.columns, name)
    }

    /// The values of column `name`, one per row.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.column_index(name)?;
        Some(
            self.rows
                .iter()
                .map(|r| r.get(i).copied().unwrap_or(f64::NAN))
                .collect(),
        )
    }
}

fn column_index(columns: &[String], name: &str) -> Option<usize> {
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

/// The values of a line whose tokens are all numbers, else `None`. `nan` and `inf` (any sign
/// and case) are read as such: LAMMPS prints them when a run blows up. A decimal literal beyond
/// the range of a double (`1e999`), which LAMMPS never prints, is an error: `(column, token)`.
fn parse_numbers(line: &str) -> Result<Option<Vec<f64>>, (usize, &str)> {
    let toks: Vec<&str> = line.split_whitespace().collect();
    let Some(values) = toks
        .iter()
        .map(|t| t.parse::<f64>().ok())
        .collect::<Option<Vec<f64>>>()
    else {
        return Ok(None);
    };
    match values
        .iter()
        .zip(&toks)
        .position(|(v, t)| v.is_infinite() && !super::spelled_infinity(t))
    {
        Some(i) => Err((i + 1, toks[i])),
        None => Ok(Some(values)),
    }
}

/// All thermo blocks of a log, in order.
///
/// Values `nan`, `inf` and `-inf` (as LAMMPS prints them after a blow-up) are read as NaN and
/// infinities, not refused: a log that blew up can still be read and compared (two NaNs compare
/// equal in [`differences`]).
///
/// Errors: a row whose number of values differs from its header (with the line number); a
/// number beyond the range of a double, such as `1e999` (with the line and column). The
/// last line of the text is exempt from the first check when it does not end in a newline (a
/// log still being written): it is dropped.
pub fn parse_log(text: &str) -> Result<Vec<ThermoBlock>, String> {
    let mut blocks = Vec::new();
    let mut current: Option<ThermoBlock> = None;
    let lines: Vec<&str> = text.lines().collect();
    let unterminated_last = !text.is_empty() && !text.ends_with('\n');
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim();
        if let Some(block) = current.as_mut() {
            if trimmed.is_empty() || trimmed.starts_with("WARNING") {
                continue;
            }
            let parsed = parse_numbers(trimmed).map_err(|(col, tok)| {
                format!(
                    "line {}: column {col}: {}; LAMMPS prints an infinite thermo value as 'inf'",
                    i + 1,
                    super::NumError::Overflow.describe(tok)
                )
            })?;
            if let Some(values) = parsed {
                if values.len() == block.columns.len() {
                    block.rows.push(values);
                    continue;
                }
                if unterminated_last && i + 1 == lines.len() {
                    continue;
                }
                return Err(format!(
                    "line {}: thermo row has {} values but the header has {} columns ({})",
                    i + 1,
                    values.len(),
                    block.columns.len(),
                    block.columns.join(" ")
                ));
            }
            if let Some(b) = current.take().filter(|b| !b.rows.is_empty()) {
                blocks.push(b);
            }
        }
        let mut tokens = trimmed.split_whitespace();
        if tokens.next() == Some("Step") {
            current = Some(ThermoBlock {
                columns: trimmed.split_whitespace().map(str::to_string).collect(),
                rows: Vec::new(),
            });
        }
    }
    if let Some(b) = current.filter(|b| !b.rows.is_empty()) {
        blocks.push(b);
    }
    Ok(blocks)
}

/// One `Neighbor list info` settings line of a LAMMPS log: `update every 1 steps, delay 10
/// steps, check yes` (LAMMPS up to 2022) or `update: every = 1 steps, delay = 0 steps, check =
/// yes` (later), the values of `neigh_modify every/delay/check`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NeighborSettings {
    pub every: u64,
    pub delay: u64,
    pub check: bool,
}

impl NeighborSettings {
    /// `every 1 delay 10 check yes`, as `neigh_modify` spells it.
    pub fn keywords(&self) -> String {
        format!(
            "every {} delay {} check {}",
            self.every,
            self.delay,
            if self.check { "yes" } else { "no" }
        )
    }

    /// `every 1 delay 0 check yes`: the lists are checked every step, so no build is late.
    pub fn checks_every_step(&self) -> bool {
        self.every == 1 && self.delay == 0 && self.check
    }

    fn parse(line: &str) -> Option<NeighborSettings> {
        let rest = line.trim().strip_prefix("update")?;
        let toks: Vec<&str> = rest
            .split(|c: char| c.is_whitespace() || matches!(c, ':' | '=' | ','))
            .filter(|t| !t.is_empty())
            .collect();
        let after = |key: &str| {
            toks.iter()
                .position(|t| *t == key)
                .and_then(|i| toks.get(i + 1))
        };
        Some(NeighborSettings {
            every: after("every")?.parse().ok()?,
            delay: after("delay")?.parse().ok()?,
            check: match *after("check")? {
                "yes" => true,
                "no" => false,
                _ => return None,
            },
        })
    }
}

/// What a LAMMPS log says about its neighbour lists: the settings printed under `Neighbor list
/// info ...` at a run's set-up, and the `Dangerous builds = N` line of each run's summary (a
/// build is dangerous when some atom had moved more than half the skin since the previous one:
/// pairs may have been missed in between).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NeighborSummary {
    /// Each settings line, in log order.
    pub settings: Vec<NeighborSettings>,
    /// Each run's dangerous-build count, in log order; `None` where LAMMPS printed `Dangerous
    /// builds not checked` (`check no`).
    pub dangerous: Vec<Option<u64>>,
}

impl NeighborSummary {
    /// Dangerous builds over all runs.
    pub fn dangerous_total(&self) -> u64 {
        self.dangerous.iter().flatten().sum()
    }

    /// Runs whose dangerous builds LAMMPS did not count.
    pub fn unchecked_runs(&self) -> usize {
        self.dangerous.iter().filter(|d| d.is_none()).count()
    }
}

/// Reads the neighbour-list settings and dangerous-build counts from a LAMMPS log's text
/// (empty when there are none, e.g. a log of this project's engine).
pub fn neighbor_summary(text: &str) -> NeighborSummary {
    let mut out = NeighborSummary::default();
    for line in text.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("Dangerous builds") {
            let rest = rest.trim();
            if let Some(n) = rest.strip_prefix('=').and_then(|n| n.trim().parse().ok()) {
                out.dangerous.push(Some(n));
            } else if rest == "not checked" {
                out.dangerous.push(None);
            }
        } else if t.starts_with("update")
            && let Some(s) = NeighborSettings::parse(t)
        {
            out.settings.push(s);
        }
    }
    out
}

/// Whether `text` looks like a LAMMPS text dump (its first non-blank line is `ITEM: TIMESTEP`)
/// rather than a log.
pub fn looks_like_dump(text: &str) -> bool {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .is_some_and(|l| l.starts_with("ITEM: TIMESTEP"))
}

// ---------------------------------------------------------------------------------------------
// Comparison
// ---------------------------------------------------------------------------------------------

/// Columns left out of comparisons unless asked for by name: wall-clock timings, which differ
/// between any two runs.
pub(crate) const TIMING_COLUMNS: [&str; 7] = [
    "CPU", "T/CPU", "S/CPU", "CPULeft", "TPCPU", "SPCPU", "Elapsed",
];

fn is_timing(name: &str) -> bool {
    TIMING_COLUMNS.iter().any(|t| t.eq_ignore_ascii_case(name))
}

/// When two values count as different: relative difference above `rtol` **and** absolute
/// difference above `atol`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    pub rtol: f64,
    pub atol: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            rtol: 1e-9,
            atol: 0.0,
        }
    }
}

/// Absolute and relative difference of two values. The relative difference is
/// `|a − b| / max(|a|, |b|)` (0 when both are 0). Two NaNs, or two equal infinities, count as
/// equal; one NaN or infinity against anything else is an infinite difference.
pub fn differences(a: f64, b: f64) -> (f64, f64) {
    if a == b || (a.is_nan() && b.is_nan()) {
        return (0.0, 0.0);
    }
    if !a.is_finite() || !b.is_finite() {
        return (f64::INFINITY, f64::INFINITY);
    }
    let d = (a - b).abs();
    (d, d / a.abs().max(b.abs()))
}

/// The comparison of one column.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnDiff {
    pub column: String,
    pub max_abs: f64,
    pub max_rel: f64,
    /// Rows whose values differ beyond the tolerance.
    pub n_fail: usize,
    /// Where the largest relative difference is (`step 100`, `block 2 step 100`,
    /// `step 100 id 17`), with the two values there; `None` if the column is identical.
    pub worst: Option<(String, f64, f64)>,
}

impl ColumnDiff {
    pub fn pass(&self) -> bool {
        self.n_fail == 0
    }
}

/// The largest difference at one output step of an exact comparison (for
/// [`crate::io::growth`]: how a difference grows from the first step).
#[derive(Debug, Clone, PartialEq)]
pub struct StepMax {
    /// Thermo block (0-based; 0 for a dump) and step.
    pub block: usize,
    pub step: i64,
    /// The largest scaled difference at this step, `|A − B| / scale` with the scale of the
    /// value's column: for a thermo log the largest `|value|` of the column over all matched
    /// rows of both inputs, for a dump the largest `|value|` of the column in the frame (an
    /// atom's net force can be a near-cancellation of large pair forces, and a thermo value
    /// such as `pxy` can pass through 0, where a plain relative difference means nothing).
    /// 0 when every value is equal; infinite for a non-finite value against a finite one.
    pub max_scaled: f64,
    /// The column of that largest difference (empty when all are equal).
    pub column: String,
    /// The atom id of that largest difference (dumps).
    pub id: Option<i64>,
}

/// The result of an exact (short-run) comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactReport {
    /// What rows are matched by (`Step`, or `(step, id)`).
    pub key: String,
    pub columns: Vec<ColumnDiff>,
    pub n_matched: usize,
    /// Keys of rows present in only one input (at most the first 5 of each are kept).
    pub only_in_a: Vec<String>,
    pub only_in_b: Vec<String>,
    pub n_only_in_a: usize,
    pub n_only_in_b: usize,
    pub tolerance: Tolerance,
    /// The largest scaled difference per output step of the matched rows, in step order
    /// (logs: block, then step).
    pub steps: Vec<StepMax>,
}

impl ExactReport {
    /// No column differs beyond the tolerance (rows present in only one input are not judged
    /// here; see [`ExactReport::rows_match`]).
    pub fn values_pass(&self) -> bool {
        self.columns.iter().all(ColumnDiff::pass)
    }

    /// Both inputs have the same row keys.
    pub fn rows_match(&self) -> bool {
        self.n_only_in_a == 0 && self.n_only_in_b == 0
    }

    /// Names of the columns that differ beyond the tolerance.
    pub fn failing_columns(&self) -> Vec<&str> {
        self.columns
            .iter()
            .filter(|c| !c.pass())
            .map(|c| c.column.as_str())
            .collect()
    }
}

/// The columns to compare: `wanted` if given (each must exist in both), else all columns of
/// `a` except `keys` and timings, which must then be the same set as `b`'s.
fn select_columns(
    a_cols: &[String],
    b_cols: &[String],
    wanted: Option<&[String]>,
    keys: &[&str],
) -> Result<Vec<(String, usize, usize)>, String> {
    let skip = |c: &str| keys.iter().any(|k| k.eq_ignore_ascii_case(c)) || is_timing(c);
    match wanted {
        Some(names) => names
            .iter()
            .map(
                |n| match (column_index(a_cols, n), column_index(b_cols, n)) {
                    (Some(i), Some(j)) => Ok((a_cols[i].clone(), i, j)),
                    (None, _) => Err(format!(
                        "column '{n}' is not in A (A has: {})",
                        a_cols.join(" ")
                    )),
                    (_, None) => Err(format!(
                        "column '{n}' is not in B (B has: {})",
                        b_cols.join(" ")
                    )),
                },
            )
            .collect(),
        None => {
            let only_a: Vec<&str> = a_cols
                .iter()
                .filter(|c| !skip(c) && !b_cols.contains(c))
                .map(String::as_str)
                .collect();
            let only_b: Vec<&str> = b_cols
                .iter()
                .filter(|c| !skip(c) && !a_cols.contains(c))
                .map(String::as_str)
                .collect();
            if !only_a.is_empty() || !only_b.is_empty() {
                let mut parts = Vec::new();
                if !only_a.is_empty() {
                    parts.push(format!("only in A: {}", only_a.join(" ")));
                }
                if !only_b.is_empty() {
                    parts.push(format!("only in B: {}", only_b.join(" ")));
                }
                return Err(format!(
                    "column mismatch ({}); choose common columns with --columns",
                    parts.join("; ")
                ));
            }
            Ok(a_cols
                .iter()
                .enumerate()
                .filter(|(_, c)| !skip(c))
                .filter_map(|(i, c)| {
                    b_cols
                        .iter()
                        .position(|d| d == c)
                        .map(|j| (c.clone(), i, j))
                })
                .collect())
        }
    }
}

/// An integer key from a float column value (steps and atom ids are printed as integers).
fn int_key(v: f64, what: &str) -> Result<i64, String> {
    if v.is_finite() && v.fract() == 0.0 && v.abs() < 9.0e15 {
        Ok(v as i64)
    } else {
        Err(format!("{what} value {v} is not an integer"))
    }
}

type Key = (i64, i64, i64);

struct Keyed<'a> {
    rows: BTreeMap<Key, &'a [f64]>,
}

fn keyed<'a>(
    rows: impl Iterator<Item = Result<(Key, &'a [f64]), String>>,
    label: &str,
    describe: &dyn Fn(Key) -> String,
) -> Result<Keyed<'a>, String> {
    let mut map = BTreeMap::new();
    for r in rows {
        let (k, row) = r?;
        if map.insert(k, row).is_some() {
            return Err(format!("{label}: {} appears twice", describe(k)));
        }
    }
    Ok(Keyed { rows: map })
}

/// What the rows of a comparison are: thermo rows keyed by (block, step, 0), or dump rows
/// keyed by (step, id, 0).
#[derive(Clone, Copy, PartialEq)]
enum Rows {
    Log,
    Dump,
}

/// [`StepMax`] for every output step of the matched rows of `a` and `b`.
fn step_maxima(a: &Keyed, b: &Keyed, cols: &[(String, usize, usize)], kind: Rows) -> Vec<StepMax> {
    // (block, step) of a key; the scale of a log column is over all rows, of a dump column
    // over its frame.
    let group = |k: &Key| match kind {
        Rows::Log => (k.0, k.1),
        Rows::Dump => (0, k.0),
    };
    let scale_key = |k: &Key| match kind {
        Rows::Log => (0, 0),
        Rows::Dump => (0, k.0),
    };
    let matched: Vec<(Key, &[f64], &[f64])> = a
        .rows
        .iter()
        .filter_map(|(k, ra)| b.rows.get(k).map(|rb| (*k, *ra, *rb)))
        .collect();
    let mut scales: BTreeMap<(i64, i64), Vec<f64>> = BTreeMap::new();
    for (k, ra, rb) in &matched {
        let s = scales
            .entry(scale_key(k))
            .or_insert_with(|| vec![0.0; cols.len()]);
        for (c, (_, i, j)) in cols.iter().enumerate() {
            for v in [ra[*i], rb[*j]] {
                if v.is_finite() {
                    s[c] = s[c].max(v.abs());
                }
            }
        }
    }
    let mut out: Vec<StepMax> = Vec::new();
    for (k, ra, rb) in &matched {
        let (blk, step) = group(k);
        if out
            .last()
            .is_none_or(|m| (m.block as i64, m.step) != (blk, step))
        {
            out.push(StepMax {
                block: blk as usize,
                step,
                max_scaled: 0.0,
                column: String::new(),
                id: None,
            });
        }
        let Some(cur) = out.last_mut() else { continue };
        let s = &scales[&scale_key(k)];
        for (c, (name, i, j)) in cols.iter().enumerate() {
            let (d, _) = differences(ra[*i], rb[*j]);
            let x = if d == 0.0 {
                0.0
            } else if s[c] > 0.0 {
                d / s[c]
            } else {
                f64::INFINITY
            };
            if x > cur.max_scaled {
                cur.max_scaled = x;
                cur.column = name.clone();
                cur.id = (kind == Rows::Dump).then_some(k.1);
            }
        }
    }
    out
}

fn compare_keyed(
    a: &Keyed,
    b: &Keyed,
    cols: &[(String, usize, usize)],
    tol: Tolerance,
    key_name: &str,
    describe: &dyn Fn(Key) -> String,
    kind: Rows,
) -> ExactReport {
    let mut columns: Vec<ColumnDiff> = cols
        .iter()
        .map(|(name, _, _)| ColumnDiff {
            column: name.clone(),
            max_abs: 0.0,
            max_rel: 0.0,
            n_fail: 0,
            worst: None,
        })
        .collect();
    let mut n_matched = 0;
    for (k, ra) in &a.rows {
        let Some(rb) = b.rows.get(k) else { continue };
        n_matched += 1;
        for (cd, (_, i, j)) in columns.iter_mut().zip(cols) {
            let (va, vb) = (ra[*i], rb[*j]);
            let (d, r) = differences(va, vb);
            if r > tol.rtol && d > tol.atol {
                cd.n_fail += 1;
            }
            cd.max_abs = cd.max_abs.max(d);
            if r > cd.max_rel || (cd.worst.is_none() && d > 0.0) {
                cd.max_rel = cd.max_rel.max(r);
                cd.worst = Some((describe(*k), va, vb));
            }
        }
    }
    let only = |x: &Keyed, y: &Keyed| -> (Vec<String>, usize) {
        let keys: Vec<&Key> = x.rows.keys().filter(|k| !y.rows.contains_key(k)).collect();
        (
            keys.iter().take(5).map(|k| describe(**k)).collect(),
            keys.len(),
        )
    };
    let (only_in_a, n_only_in_a) = only(a, b);
    let (only_in_b, n_only_in_b) = only(b, a);
    ExactReport {
        key: key_name.to_string(),
        columns,
        n_matched,
        only_in_a,
        only_in_b,
        n_only_in_a,
        n_only_in_b,
        tolerance: tol,
        steps: step_maxima(a, b, cols, kind),
    }
}

/// Every row has one value per column (the fields are public, so a block may have been built
/// by hand).
fn check_shape<'a>(
    label: &str,
    columns: &[String],
    rows: impl IntoIterator<Item = &'a Vec<f64>>,
) -> Result<(), String> {
    match rows.into_iter().position(|r| r.len() != columns.len()) {
        Some(i) => Err(format!(
            "{label}: row {} has a different number of values than the {} columns",
            i + 1,
            columns.len()
        )),
        None => Ok(()),
    }
}

fn step_index(block: &ThermoBlock, label: &str) -> Result<usize, String> {
    block
        .column_index("Step")
        .ok_or_else(|| format!("{label}: thermo block has no Step column"))
}

fn keyed_log<'a>(
    blocks: &'a [ThermoBlock],
    label: &str,
    describe: &dyn Fn(Key) -> String,
) -> Result<BTreeMap<Key, &'a [f64]>, String> {
    let mut all = BTreeMap::new();
    for (bi, block) in blocks.iter().enumerate() {
        let s = step_index(block, label)?;
        let rows = block.rows.iter().map(|r| {
            int_key(r[s], &format!("{label}: Step")).map(|st| ((bi as i64, st, 0), r.as_slice()))
        });
        all.extend(keyed(rows, label, describe)?.rows);
    }
    Ok(all)
}

fn keyed_dump<'a>(
    frames: &'a [DumpFrame],
    label: &str,
    describe: &dyn Fn(Key) -> String,
) -> Result<BTreeMap<Key, &'a [f64]>, String> {
    let first = frames.first().map(|f| f.columns.as_slice()).unwrap_or(&[]);
    let id =
        column_index(first, "id").ok_or_else(|| format!("{label}: the dump has no id column"))?;
    let mut all = BTreeMap::new();
    for f in frames {
        if f.columns != first {
            return Err(format!(
                "{label}: dump columns change at step {} ({} instead of {})",
                f.step,
                f.columns.join(" "),
                first.join(" ")
            ));
        }
        let step =
            i64::try_from(f.step).map_err(|_| format!("{label}: step {} is too large", f.step))?;
        let rows = f.rows.iter().map(|r| {
            Ok((
                (step, int_key(r[id], &format!("{label}: id"))?, 0),
                r.as_slice(),
            ))
        });
        all.extend(keyed(rows, label, describe)?.rows);
    }
    Ok(all)
}

/// Compares two thermo blocks row by row, matching rows by `Step`.
///
/// `columns`: the columns to compare (default: all but `Step` and [`TIMING_COLUMNS`], which
/// must then be the same in both). Errors: no `Step` column, a missing or mismatched column,
/// a repeated or non-integer step, or no common step.
pub fn compare_exact(
    a: &ThermoBlock,
    b: &ThermoBlock,
    columns: Option<&[String]>,
    tol: Tolerance,
) -> Result<ExactReport, String> {
    compare_exact_logs(
        std::slice::from_ref(a),
        std::slice::from_ref(b),
        columns,
        tol,
    )
}

/// Compares two logs block by block (block i of A with block i of B; the counts must agree),
/// matching rows by (block, `Step`).
pub fn compare_exact_logs(
    a: &[ThermoBlock],
    b: &[ThermoBlock],
    columns: Option<&[String]>,
    tol: Tolerance,
) -> Result<ExactReport, String> {
    if a.len() != b.len() {
        return Err(format!(
            "A has {} thermo block(s) but B has {} (compare one with --block)",
            a.len(),
            b.len()
        ));
    }
    let (Some(a0), Some(b0)) = (a.first(), b.first()) else {
        return Err("no thermo block to compare".to_string());
    };
    for (label, blocks) in [("A", a), ("B", b)] {
        for blk in blocks {
            check_shape(label, &blk.columns, &blk.rows)?;
        }
    }
    let cols = select_columns(&a0.columns, &b0.columns, columns, &["Step"])?;
    for (k, (ba, bb)) in a.iter().zip(b).enumerate().skip(1) {
        let ck = select_columns(&ba.columns, &bb.columns, columns, &["Step"])?;
        if ck != cols {
            return Err(format!(
                "thermo block {} has different columns from block 1 (compare blocks one at a \
                 time with --block)",
                k + 1
            ));
        }
    }
    let multi = a.len() > 1;
    let describe = move |k: Key| {
        if multi {
            format!("block {} step {}", k.0 + 1, k.1)
        } else {
            format!("step {}", k.1)
        }
    };
    let ka = Keyed {
        rows: keyed_log(a, "A", &describe)?,
    };
    let kb = Keyed {
        rows: keyed_log(b, "B", &describe)?,
    };
    let report = compare_keyed(&ka, &kb, &cols, tol, "Step", &describe, Rows::Log);
    if report.n_matched == 0 {
        return Err("A and B have no Step in common".to_string());
    }
    Ok(report)
}

/// Compares two dumps, matching rows by (timestep, atom id). Both must have an `id` column.
pub fn compare_dumps_exact(
    a: &[DumpFrame],
    b: &[DumpFrame],
    columns: Option<&[String]>,
    tol: Tolerance,
) -> Result<ExactReport, String> {
    let (Some(a0), Some(b0)) = (a.first(), b.first()) else {
        return Err("a dump has no frames".to_string());
    };
    for (label, frames) in [("A", a), ("B", b)] {
        for f in frames {
            check_shape(&format!("{label} step {}", f.step), &f.columns, &f.rows)?;
        }
    }
    let cols = select_columns(&a0.columns, &b0.columns, columns, &["id"])?;
    let describe = |k: Key| format!("step {} id {}", k.0, k.1);
    let ka = Keyed {
        rows: keyed_dump(a, "A", &describe)?,
    };
    let kb = Keyed {
        rows: keyed_dump(b, "B", &describe)?,
    };
    let report = compare_keyed(&ka, &kb, &cols, tol, "(step, id)", &describe, Rows::Dump);
    if report.n_matched == 0 {
        return Err("A and B have no (step, id) in common".to_string());
    }
    Ok(report)
}

/// One column of a statistical comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnStats {
    pub column: String,
    pub a: BlockEstimate,
    pub b: BlockEstimate,
    /// `(mean_A − mean_B) / sqrt(err_A² + err_B²)`; 0 when both means are equal, ±∞ when they
    /// differ with zero errors, NaN when an error is undefined.
    pub z: f64,
}

/// The result of a statistical (long-run) comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct StatsReport {
    pub columns: Vec<ColumnStats>,
    /// Rows used from A and B (after skipping).
    pub n_a: usize,
    pub n_b: usize,
    pub zmax: f64,
}

impl ColumnStats {
    /// `|z| ≤ zmax` (a NaN z fails).
    pub fn pass(&self, zmax: f64) -> bool {
        self.z.abs() <= zmax
    }
}

impl StatsReport {
    pub fn pass(&self) -> bool {
        self.columns.iter().all(|c| c.pass(self.zmax))
    }

    pub fn failing_columns(&self) -> Vec<&str> {
        self.columns
            .iter()
            .filter(|c| !c.pass(self.zmax))
            .map(|c| c.column.as_str())
            .collect()
    }
}

/// z-score of the difference of two independent estimates.
pub fn z_score(a: &BlockEstimate, b: &BlockEstimate) -> f64 {
    let d = a.mean - b.mean;
    if d == 0.0 {
        return 0.0;
    }
    d / (a.stderr * a.stderr + b.stderr * b.stderr).sqrt()
}

/// Compares the means of each column of two thermo blocks (independent runs), after skipping
/// the first `skip` rows of each, with block-averaged errors ([`block_average`]).
///
/// Columns as in [`compare_exact`]. Errors: fewer than 2 rows left after skipping, or a
/// missing or mismatched column.
pub fn compare_stats(
    a: &ThermoBlock,
    b: &ThermoBlock,
    columns: Option<&[String]>,
    skip: usize,
    zmax: f64,
) -> Result<StatsReport, String> {
    check_shape("A", &a.columns, &a.rows)?;
    check_shape("B", &b.columns, &b.rows)?;
    let cols = select_columns(&a.columns, &b.columns, columns, &["Step"])?;
    for (label, blk) in [("A", a), ("B", b)] {
        if blk.rows.len() < skip + 2 {
            return Err(format!(
                "{label}: {} rows, fewer than 2 left after skipping {skip}",
                blk.rows.len()
            ));
        }
    }
    let series = |blk: &ThermoBlock, i: usize| -> Vec<f64> {
        blk.rows[skip..].iter().map(|r| r[i]).collect()
    };
    let columns = cols
        .iter()
        .map(|(name, i, j)| {
            let ea = block_average(&series(a, *i));
            let eb = block_average(&series(b, *j));
            ColumnStats {
                column: name.clone(),
                z: z_score(&ea, &eb),
                a: ea,
                b: eb,
            }
        })
        .collect();
    Ok(StatsReport {
        columns,
        n_a: a.rows.len() - skip,
        n_b: b.rows.len() - skip,
        zmax,
    })
}
