//! Exact comparison of two logs or two dumps: columns chosen, rows matched by step (and atom
//! id), and every difference measured.

use super::ThermoBlock;
use super::report::{ColumnDiff, ExactReport, StepMax, Tolerance, differences};
use super::thermo::column_index;
use crate::io::dump_read::DumpFrame;
use std::collections::BTreeMap;

/// Columns left out of comparisons unless asked for by name: wall-clock timings, which differ
/// between any two runs.
pub(crate) const TIMING_COLUMNS: [&str; 7] = [
    "CPU", "T/CPU", "S/CPU", "CPULeft", "TPCPU", "SPCPU", "Elapsed",
];

fn is_timing(name: &str) -> bool {
    TIMING_COLUMNS.iter().any(|t| t.eq_ignore_ascii_case(name))
}

/// The columns to compare: `wanted` if given (each must exist in both), else all columns of
/// `a` except `keys` and timings, which must then be the same set as `b`'s.
pub(super) fn select_columns(
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
pub(super) fn check_shape<'a>(
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
