//! The reports of an exact comparison: the tolerance, per-column differences and their growth
//! step by step.

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
