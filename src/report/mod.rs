//! The results of `dpdnl analyze`, `dpdnl design` and `dpdnl theory` as typed values, and their
//! JSON: one place for what the CLI writes to `PREFIX.json` / prints with `--json` and what the
//! Python package returns as dicts. The front ends only read files (or take Python objects),
//! call these functions and present the result (text, CSV, figures; dicts).
//!
//! - [`mb`], [`nemd`], [`transport`] (`eh`, `msd`), [`shear`] (`couette`, `flowcurve`): the
//!   analyses: which file kind, which columns, which window, the checks between the inputs;
//!   each result has `json()` (the object of `PREFIX.json`) and `table()` (the columns of
//!   `PREFIX.csv`).
//! - [`theory`]: `design` and `theory` results with serde-derived JSON (keys in the order the CLI
//!   has always printed them).
//!
//! Errors are the CLI's messages (`NAME: …` for a problem in one input).

pub mod mb;
pub mod nemd;
pub mod shear;
pub mod theory;
pub mod transport;

use crate::analysis::formats::{Series, parse_series};
use serde::Serialize;
use serde_json::Value;
use std::io;
use std::path::Path;

/// Named columns of equal length (those of `PREFIX.csv`, in order).
pub type Table = Vec<(&'static str, Vec<f64>)>;

/// Prefixes an error with the input it came from.
pub(crate) fn in_name<T>(name: &str, r: Result<T, String>) -> Result<T, String> {
    r.map_err(|e| format!("{name}: {e}"))
}

/// A time series from the text of a `fix ave/time` file or a log; errors name the input.
pub fn series_from_text(name: &str, text: &str) -> Result<Series, String> {
    in_name(name, parse_series(text))
}

/// The file name without its extension: the default label of a result.
pub fn stem(path: &Path, default: &str) -> String {
    path.file_stem()
        .map_or(default.into(), |s| s.to_string_lossy().into_owned())
}

/// An analysis result as the text of `PREFIX.json`: pretty-printed, keys sorted, a final newline.
pub fn to_pretty(v: &Value) -> Result<String, String> {
    serde_json::to_string_pretty(v)
        .map(|s| s + "\n")
        .map_err(|e| e.to_string())
}

/// A value as JSON (for the Python package's dicts): keys sorted.
pub fn to_value<T: Serialize>(v: &T) -> Result<Value, String> {
    serde_json::to_value(v).map_err(|e| e.to_string())
}

/// One line of compact JSON as `dpdnl design/theory --json` prints it: keys in declaration order,
/// numbers in [`short`] form (so `3`, not `3.0`), non-finite numbers as `null`, and every
/// control character escaped as `\u00XX`.
pub fn to_line<T: Serialize>(v: &T) -> Result<String, String> {
    let mut out = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut out, LineFormatter);
    v.serialize(&mut ser).map_err(|e| e.to_string())?;
    String::from_utf8(out).map_err(|e| e.to_string())
}

pub use crate::fmtnum::short;

/// serde_json's compact output with the CLI's number and escape forms.
struct LineFormatter;

impl serde_json::ser::Formatter for LineFormatter {
    fn write_f64<W: ?Sized + io::Write>(&mut self, w: &mut W, value: f64) -> io::Result<()> {
        w.write_all(short(value).as_bytes())
    }

    fn write_char_escape<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        escape: serde_json::ser::CharEscape,
    ) -> io::Result<()> {
        use serde_json::ser::CharEscape::*;
        let byte = match escape {
            Quote => return w.write_all(b"\\\""),
            ReverseSolidus => return w.write_all(b"\\\\"),
            Solidus => b'/',
            Backspace => 0x08,
            FormFeed => 0x0c,
            LineFeed => b'\n',
            CarriageReturn => b'\r',
            Tab => b'\t',
            AsciiControl(b) => b,
        };
        write!(w, "\\u{byte:04x}")
    }
}

/// The fitted line `slope · t + intercept` at each `t`.
pub(crate) fn line_at(t: &[f64], slope: f64, intercept: f64) -> Vec<f64> {
    t.iter().map(|t| slope * t + intercept).collect()
}

/// The one column of `s` that `pick` accepts, or an error naming the input, the columns and
/// the option that chooses one (`what`: e.g. "the MSD column"; `option`: "--col").
pub(crate) fn only_column(
    name: &str,
    s: &Series,
    what: &str,
    option: &str,
    pick: impl Fn(&str) -> bool,
) -> Result<String, String> {
    let c: Vec<&String> = s.columns.iter().filter(|c| pick(c)).collect();
    match c.as_slice() {
        [one] => Ok((*one).clone()),
        _ => Err(format!(
            "{name}: cannot tell {what} (columns: {}); give {option}",
            s.columns.join(" ")
        )),
    }
}
