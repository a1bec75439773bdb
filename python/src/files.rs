//! Readers of LAMMPS-format files of either engine, with the crate's parsers
//! (`dpdnl::io::{lammps_log, dump_read}`, `dpdnl::analysis::formats`), into dicts of NumPy
//! arrays. Every reader takes a path, or the file's text as `text=`.

use crate::{FormatError, arr, read_text};
use dpdnl::analysis::formats::{
    AveTime, Block, FileKind, Series, detect, parse_ave_chunk, parse_ave_histo, parse_ave_time,
    parse_series,
};
use dpdnl::io::dump_read::parse_dump;
use dpdnl::io::lammps_log::parse_log;
use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// The name (for messages) and text of a `path` or a `text=` argument.
pub(crate) fn source(path: Option<PathBuf>, text: Option<String>) -> PyResult<(String, String)> {
    match (path, text) {
        (Some(p), None) => Ok((p.display().to_string(), read_text(&p)?)),
        (None, Some(t)) => Ok(("<text>".to_string(), t)),
        _ => Err(PyTypeError::new_err("give a path or text=, not both")),
    }
}

/// A parser's error, prefixed with the file name as the CLI does.
pub(crate) fn in_file<T>(name: &str, r: Result<T, String>) -> PyResult<T> {
    r.map_err(|e| FormatError::new_err(format!("{name}: {e}")))
}

/// Columns `names` of `rows` as a dict name → array.
fn columns_dict<'py>(
    py: Python<'py>,
    names: &[String],
    rows: &[Vec<f64>],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (j, n) in names.iter().enumerate() {
        let col: Vec<f64> = rows
            .iter()
            .map(|r| r.get(j).copied().unwrap_or(f64::NAN))
            .collect();
        d.set_item(n, arr(py, &col))?;
    }
    Ok(d)
}

/// A [`Series`] as a dict: `Step` → steps, then each column.
pub(crate) fn series_dict<'py>(py: Python<'py>, s: &Series) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("Step", arr(py, &s.steps))?;
    for (c, v) in s.columns.iter().zip(&s.data) {
        d.set_item(c, arr(py, v))?;
    }
    Ok(d)
}

fn steps_array<'py>(
    py: Python<'py>,
    steps: impl Iterator<Item = u64>,
) -> Bound<'py, PyArray1<i64>> {
    PyArray1::from_vec(py, steps.map(|s| s as i64).collect())
}

fn log_blocks<'py>(py: Python<'py>, name: &str, text: &str) -> PyResult<Bound<'py, PyList>> {
    let blocks = in_file(name, parse_log(text))?;
    let out = PyList::empty(py);
    for b in &blocks {
        out.append(columns_dict(py, &b.columns, &b.rows)?)?;
    }
    Ok(out)
}

fn dump_frames<'py>(py: Python<'py>, name: &str, text: &str) -> PyResult<Bound<'py, PyList>> {
    let frames = in_file(name, parse_dump(text))?;
    let out = PyList::empty(py);
    for f in &frames {
        let d = PyDict::new(py);
        d.set_item("step", f.step)?;
        let bounds: Vec<Vec<f64>> = f.box_bounds.iter().map(|b| b.to_vec()).collect();
        d.set_item("box_bounds", crate::arr2(py, &bounds, 2)?)?;
        d.set_item("tilt", f.tilt.map(|t| (t[0], t[1], t[2])))?;
        d.set_item("atoms", columns_dict(py, &f.columns, &f.rows)?)?;
        out.append(d)?;
    }
    Ok(out)
}

fn block_dict<'py>(py: Python<'py>, b: &Block, names: &[String]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("step", b.step)?;
    d.set_item("header", b.header.clone())?;
    d.set_item("data", columns_dict(py, names, &b.rows)?)?;
    Ok(d)
}

fn ave_time<'py>(py: Python<'py>, name: &str, text: &str) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match in_file(name, parse_ave_time(text))? {
        AveTime::Scalar(s) => {
            d.set_item("mode", "scalar")?;
            d.set_item("steps", steps_array(py, s.steps.iter().copied()))?;
            d.set_item("data", columns_dict(py, &s.columns, &s.rows)?)?;
        }
        AveTime::Vector(v) => {
            d.set_item("mode", "vector")?;
            d.set_item("steps", steps_array(py, v.blocks.iter().map(|b| b.step)))?;
            let mut names = vec!["Row".to_string()];
            names.extend(v.columns.iter().cloned());
            let blocks = PyList::empty(py);
            for b in &v.blocks {
                blocks.append(block_dict(py, b, &names)?)?;
            }
            d.set_item("blocks", blocks)?;
        }
    }
    Ok(d)
}

fn ave_chunk<'py>(py: Python<'py>, name: &str, text: &str) -> PyResult<Bound<'py, PyDict>> {
    let c = in_file(name, parse_ave_chunk(text))?;
    let d = PyDict::new(py);
    d.set_item("columns", c.columns.clone())?;
    d.set_item("steps", steps_array(py, c.blocks.iter().map(|b| b.step)))?;
    let blocks = PyList::empty(py);
    for b in &c.blocks {
        let bd = block_dict(py, b, &c.columns)?;
        bd.set_item("nchunks", b.header.first().map(|n| *n as i64))?;
        bd.set_item("total", b.header.get(1).copied())?;
        blocks.append(bd)?;
    }
    d.set_item("blocks", blocks)?;
    Ok(d)
}

fn ave_histo<'py>(py: Python<'py>, name: &str, text: &str) -> PyResult<Bound<'py, PyDict>> {
    let h = in_file(name, parse_ave_histo(text))?;
    let d = PyDict::new(py);
    d.set_item("steps", steps_array(py, h.blocks.iter().map(|b| b.step)))?;
    let blocks = PyList::empty(py);
    for b in &h.blocks {
        let bd = PyDict::new(py);
        bd.set_item("step", b.step)?;
        bd.set_item("total", b.total)?;
        bd.set_item("missing", b.missing)?;
        bd.set_item("min", b.min)?;
        bd.set_item("max", b.max)?;
        bd.set_item("coord", arr(py, &b.coord))?;
        bd.set_item("count", arr(py, &b.count))?;
        bd.set_item("fraction", arr(py, &b.fraction))?;
        blocks.append(bd)?;
    }
    d.set_item("blocks", blocks)?;
    Ok(d)
}

fn kind_name(k: FileKind) -> &'static str {
    match k {
        FileKind::AveTime => "ave/time",
        FileKind::AveChunk => "ave/chunk",
        FileKind::AveHisto => "ave/histo",
        FileKind::Dump => "dump",
        FileKind::Log => "log",
    }
}

/// The thermo blocks of a LAMMPS or dpdnl log: a list (one per run) of dicts column → array.
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read_log<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyList>> {
    let (name, text) = source(path, text)?;
    log_blocks(py, &name, &text)
}

/// The frames of a text dump (`dump custom`/`atom`): a list of dicts with `step`,
/// `box_bounds` (array (3, 2) of lo, hi), `tilt` ((xy, xz, yz) or None) and `atoms` (column
/// name → array, rows sorted by id when there is an id column).
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read_dump<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyList>> {
    let (name, text) = source(path, text)?;
    dump_frames(py, &name, &text)
}

/// A `fix ave/time` file. Scalar mode: `{"mode": "scalar", "steps", "data": {name: array}}`;
/// vector mode: `{"mode": "vector", "steps", "blocks": [{"step", "header", "data": {"Row",
/// name: array}}]}`.
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read_ave_time<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let (name, text) = source(path, text)?;
    ave_time(py, &name, &text)
}

/// A `fix ave/chunk` file: `{"columns", "steps", "blocks": [{"step", "header", "nchunks",
/// "total", "data": {column: array}}]}`.
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read_ave_chunk<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let (name, text) = source(path, text)?;
    ave_chunk(py, &name, &text)
}

/// A `fix ave/histo` file: `{"steps", "blocks": [{"step", "total", "missing", "min", "max",
/// "coord", "count", "fraction"}]}`.
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read_ave_histo<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let (name, text) = source(path, text)?;
    ave_histo(py, &name, &text)
}

/// A time series from a scalar-mode `fix ave/time` file or a log (runs with the last run's
/// columns joined, repeated steps dropped): `{"Step": array, column: array, …}`, the input the
/// analyses take.
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read_series<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let (name, text) = source(path, text)?;
    let s = in_file(&name, parse_series(&text))?;
    series_dict(py, &s)
}

/// The kind of a file, from its first line: "ave/time", "ave/chunk", "ave/histo", "dump" or
/// "log".
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn detect_kind(path: Option<PathBuf>, text: Option<String>) -> PyResult<&'static str> {
    let (_, text) = source(path, text)?;
    Ok(kind_name(detect(&text)))
}

/// Reads any of the above by its kind (see `detect_kind`): a log gives `read_log`'s list, the
/// others their reader's dict.
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn read<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let (name, text) = source(path, text)?;
    Ok(match detect(&text) {
        FileKind::AveTime => ave_time(py, &name, &text)?.into_any(),
        FileKind::AveChunk => ave_chunk(py, &name, &text)?.into_any(),
        FileKind::AveHisto => ave_histo(py, &name, &text)?.into_any(),
        FileKind::Dump => dump_frames(py, &name, &text)?.into_any(),
        FileKind::Log => log_blocks(py, &name, &text)?.into_any(),
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_log, m)?)?;
    m.add_function(wrap_pyfunction!(read_dump, m)?)?;
    m.add_function(wrap_pyfunction!(read_ave_time, m)?)?;
    m.add_function(wrap_pyfunction!(read_ave_chunk, m)?)?;
    m.add_function(wrap_pyfunction!(read_ave_histo, m)?)?;
    m.add_function(wrap_pyfunction!(read_series, m)?)?;
    m.add_function(wrap_pyfunction!(detect_kind, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    Ok(())
}
