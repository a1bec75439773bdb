//! Statistical comparison of two independent runs: block-averaged means and their z-scores.

use super::ThermoBlock;
use super::exact::{check_shape, select_columns};
use crate::stats::{BlockEstimate, block_average};

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
/// Columns as in [`compare_exact`](super::compare_exact). Errors: fewer than 2 rows left after skipping, or a
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
