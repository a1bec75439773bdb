//! Text output shared by `dpdnl diff` and `dpdnl crosscheck`.

use dpdnl::input::format::{FmtArg, sprintf};
use dpdnl::io::lammps_log::ExactReport;
use std::fmt::Write as _;

/// `%` formatting through the project's printf (same look as LAMMPS output).
pub fn c(fmt: &str, v: f64) -> String {
    sprintf(fmt, &[FmtArg::Float(v)]).unwrap_or_else(|_| v.to_string())
}

/// How the two sides of an exact comparison are labelled and printed.
pub struct TableStyle<'a> {
    /// Names of side A and side B.
    pub labels: [&'a str; 2],
    /// printf format of the worst values.
    pub value_fmt: &'a str,
    /// Width of the value columns.
    pub value_width: usize,
    /// A blank line before the column header.
    pub blank_before_header: bool,
}

/// The rows present on one side only, then one line per column: max |A−B|, max relative
/// difference, number of failing values, where the worst one is, and its two values.
pub fn write_exact_table(out: &mut String, r: &ExactReport, s: &TableStyle) {
    for (label, n, keys) in [
        (s.labels[0], r.n_only_in_a, &r.only_in_a),
        (s.labels[1], r.n_only_in_b, &r.only_in_b),
    ] {
        if n > 0 {
            let more = if n > keys.len() { ", …" } else { "" };
            let _ = writeln!(out, "rows only in {label}: {n} ({}{more})", keys.join(", "));
        }
    }
    let w = r
        .columns
        .iter()
        .map(|c| c.column.chars().count())
        .max()
        .unwrap_or(0)
        .max(6);
    let wa = r
        .columns
        .iter()
        .filter_map(|c| c.worst.as_ref().map(|w| w.0.chars().count()))
        .max()
        .unwrap_or(0)
        .max(8);
    let wv = s.value_width;
    let _ = writeln!(
        out,
        "{}{:<w$}  {:>10}  {:>10}  {:>5}  {:<wa$}  {:>wv$}  {:>wv$}",
        if s.blank_before_header { "\n" } else { "" },
        "column",
        "max |A-B|",
        "max rel",
        "fail",
        "worst at",
        s.labels[0],
        s.labels[1]
    );
    for cd in &r.columns {
        let (at, va, vb) = match &cd.worst {
            Some((at, va, vb)) => (at.as_str(), c(s.value_fmt, *va), c(s.value_fmt, *vb)),
            None => ("-", String::new(), String::new()),
        };
        let line = format!(
            "{:<w$}  {:>10}  {:>10}  {:>5}  {:<wa$}  {:>wv$}  {:>wv$}{}",
            cd.column,
            c("%.3e", cd.max_abs),
            c("%.3e", cd.max_rel),
            cd.n_fail,
            at,
            va,
            vb,
            if cd.pass() { "" } else { "  <- DIFFERS" }
        );
        let _ = writeln!(out, "{}", line.trim_end());
    }
}
