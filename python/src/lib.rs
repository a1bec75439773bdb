//! `dpdnl._dpdnl`: the Rust half of the `dpdnl` Python package (PyO3). Everything that computes
//! a number is the `dpdnl` crate's; this crate only moves data between it and Python:
//!
//! - [`sim`]: `Simulation`, the standalone engine's script interpreter driven from Python;
//! - [`files`]: readers of LAMMPS-format logs, dumps and `fix ave/*` files (either engine);
//! - [`theory`]: kinetic theory, (η, Sc) design, the Euler finite-step temperature;
//! - [`analysis`]: `mb`, `nemd`, `eh`, `msd`, `couette`, `flowcurve`, returning what
//!   `dpdnl analyze` writes to its JSON file (plus the CSV columns as arrays).
//!
//! Errors become Python exceptions with the CLI's messages: `ScriptError` (a `RuntimeError`
//! with `file`, `line`, `command`, `message`), `FormatError`, `AnalysisError` and `TheoryError`
//! (all `ValueError`s), and `OSError`s for files that cannot be read.

mod analysis;
mod files;
mod sim;
mod theory;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;
use std::path::Path;

create_exception!(
    dpdnl,
    ScriptError,
    PyRuntimeError,
    "An error in a script or command: ``str(e)`` is the CLI's ``file:line: command: message``.

Example:
    >>> sim = dpdnl.Simulation()
    >>> try:
    ...     sim.commands([\"units lj\", \"frobnicate 1 2\"])
    ... except dpdnl.ScriptError as e:
    ...     print(e.file, e.line, e.command)
    <commands> 2 frobnicate"
);
create_exception!(
    dpdnl,
    FormatError,
    PyValueError,
    "A file that is not in the format it was read as; the message names the file, the line
and the offending token, as the CLI's.

Example:
    >>> try:
    ...     dpdnl.read_ave_chunk(text=\"# Chunk Coord1 Ncount vz\\n1000 2 x\\n\")
    ... except dpdnl.FormatError:
    ...     print(\"not an ave/chunk file\")
    not an ave/chunk file"
);
create_exception!(
    dpdnl,
    AnalysisError,
    PyValueError,
    "An analysis that cannot be done on the given data (the message is the CLI's).

Example:
    >>> try:
    ...     dpdnl.couette({\"Step\": [0, 10], \"temp\": [1.0, 1.0]}, rate=0.1)
    ... except dpdnl.AnalysisError:
    ...     print(\"no pxy column\")
    no pxy column"
);
create_exception!(
    dpdnl,
    TheoryError,
    PyValueError,
    "Parameters outside the kinetic theory's domain, or a design target that cannot be met
(the message says which bound to move, as the CLI's).

Example:
    >>> try:
    ...     dpdnl.design(eta=3.0, sc=0.4, density=4.0, rc=1.0)
    ... except dpdnl.TheoryError:
    ...     print(\"Sc <= 1/2 is impossible\")
    Sc <= 1/2 is impossible"
);

/// A `ScriptError` with its attributes set from the interpreter's error.
pub(crate) fn script_error(py: Python<'_>, e: &dpdnl::input::ScriptError) -> PyErr {
    let err = ScriptError::new_err(e.to_string());
    let v = err.value(py);
    let _ = v.setattr("file", &e.file);
    let _ = v.setattr("line", e.line);
    let _ = v.setattr("command", &e.command);
    let _ = v.setattr("message", &e.message);
    err
}

/// Reads a text file; errors are `OSError`s (`FileNotFoundError`, `PermissionError`) whose text
/// is the CLI's (`PATH: reason`).
pub(crate) fn read_text(path: &Path) -> PyResult<String> {
    std::fs::read_to_string(path).map_err(|e| {
        let msg = format!("{}: {e}", path.display());
        match e.kind() {
            std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(msg),
            std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(msg),
            _ => PyOSError::new_err(msg),
        }
    })
}

/// A float array from a slice.
pub(crate) fn arr<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

/// An (n, k) float array from rows of equal length `k`.
pub(crate) fn arr2<'py>(
    py: Python<'py>,
    rows: &[Vec<f64>],
    k: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    if flat.len() != rows.len() * k {
        return Err(FormatError::new_err("rows of unequal length"));
    }
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows.len(), k])?
        .into_any())
}

/// A JSON value as the Python object `json.loads` would give (dict, list, int, float, str,
/// bool, None).
pub(crate) fn json_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(json_to_py(py, x)?)?;
            }
            l.into_any()
        }
        Value::Object(o) => {
            let d = PyDict::new(py);
            for (k, x) in o {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// The directory of the repository this extension was built from (for finding
/// `build/dpdnlplugin.so`).
const SOURCE_ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

#[pymodule(gil_used = true)]
fn _dpdnl(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ScriptError", py.get_type::<ScriptError>())?;
    m.add("FormatError", py.get_type::<FormatError>())?;
    m.add("AnalysisError", py.get_type::<AnalysisError>())?;
    m.add("TheoryError", py.get_type::<TheoryError>())?;
    m.add("_source_root", SOURCE_ROOT)?;
    sim::register(m)?;
    files::register(m)?;
    theory::register(m)?;
    analysis::register(m)?;
    Ok(())
}
