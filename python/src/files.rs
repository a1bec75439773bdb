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

/// The thermo blocks of a LAMMPS or dpdnl log.
///
/// Args:
///     path: the log file; give this or ``text``.
///     text: the log's text instead of a file.
///
/// Returns:
///     A list with one dict per run (per thermo header): column name as in the header
///     (``Step``, ``Temp``, …) → float array, in the units of the thermo keyword.
///
/// Raises:
///     FormatError: the text is not a log with thermo output (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> log = '''LAMMPS (22 Jul 2025)
///     ... Step Temp Press
///     ...        0   1.0   2.5
///     ...       10   0.98  2.4
///     ... Loop time of 0.01 on 1 procs for 10 steps with 500 atoms
///     ... '''
///     >>> runs = dpdnl.read_log(text=log)
///     >>> runs[0]["Temp"].tolist()
///     [1.0, 0.98]
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

/// The frames of a text dump (``dump custom`` or ``dump atom``) of either engine.
///
/// Args:
///     path: the dump file; give this or ``text``.
///     text: the dump's text instead of a file.
///
/// Returns:
///     A list with one dict per frame:
///
///     - ``step`` (int): the time step;
///     - ``box_bounds``: array (3, 2) of the lo and hi bounds (distance units);
///     - ``tilt``: ``(xy, xz, yz)`` for a triclinic box, else None;
///     - ``atoms``: dict column name (as in ``ITEM: ATOMS``) → float array, rows sorted by
///       id when there is an ``id`` column.
///
/// Raises:
///     FormatError: the text is not a dump (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> dump = '''ITEM: TIMESTEP
///     ... 100
///     ... ITEM: NUMBER OF ATOMS
///     ... 2
///     ... ITEM: BOX BOUNDS pp pp pp
///     ... 0 5
///     ... 0 5
///     ... 0 5
///     ... ITEM: ATOMS id type x y z vx vy vz
///     ... 2 1 1.0 1.0 1.0 0.1 0.0 0.0
///     ... 1 1 2.0 2.0 2.0 -0.1 0.0 0.0
///     ... '''
///     >>> frame = dpdnl.read_dump(text=dump)[0]
///     >>> frame["step"], frame["atoms"]["id"].tolist(), frame["atoms"]["vx"].tolist()
///     (100, [1.0, 2.0], [-0.1, 0.1])
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

/// A ``fix ave/time`` file, in scalar or vector mode.
///
/// Args:
///     path: the file; give this or ``text``.
///     text: the file's text instead of a file.
///
/// Returns:
///     A dict. Scalar mode: ``mode`` = ``"scalar"``, ``steps`` (int array), ``data`` (column
///     name → float array). Vector mode: ``mode`` = ``"vector"``, ``steps`` (int array),
///     ``blocks``: one dict per output with ``step``, ``header`` (the numbers of the output's
///     first line after the step) and ``data`` (``Row`` and each column → float array).
///     Values are in the units of the averaged quantities.
///
/// Raises:
///     FormatError: the text is not an ave/time file (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> text = '''# Time-averaged data for fix avg
///     ... # TimeStep c_msd[4] v_t
///     ... 100 0.52 1.01
///     ... 200 1.04 0.99
///     ... '''
///     >>> r = dpdnl.read_ave_time(text=text)
///     >>> r["mode"], r["steps"].tolist(), r["data"]["c_msd[4]"].tolist()
///     ('scalar', [100, 200], [0.52, 1.04])
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

/// A ``fix ave/chunk`` file (profiles).
///
/// Args:
///     path: the file; give this or ``text``.
///     text: the file's text instead of a file.
///
/// Returns:
///     A dict: ``columns`` (the names of the chunk lines: ``Chunk``, ``Coord1``, ``Ncount``,
///     the values), ``steps`` (int array), ``blocks``: one dict per output with ``step``,
///     ``header`` (the output line's numbers after the step), ``nchunks`` (int), ``total``
///     (the total count) and ``data`` (column → float array, one value per chunk; ``Coord1``
///     in distance units, or reduced with ``units reduced``).
///
/// Raises:
///     FormatError: the text is not an ave/chunk file (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> text = '''# Chunk-averaged data for fix prof and group all
///     ... # Timestep Number-of-chunks Total-count
///     ... # Chunk Coord1 Ncount vz
///     ... 1000 2 500
///     ...   1 0.25 250 0.1
///     ...   2 0.75 250 -0.1
///     ... '''
///     >>> block = dpdnl.read_ave_chunk(text=text)["blocks"][0]
///     >>> block["step"], block["nchunks"], block["data"]["vz"].tolist()
///     (1000, 2, [0.1, -0.1])
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

/// A ``fix ave/histo`` file (histograms).
///
/// Args:
///     path: the file; give this or ``text``.
///     text: the file's text instead of a file.
///
/// Returns:
///     A dict: ``steps`` (int array) and ``blocks``, one dict per output with ``step``,
///     ``total`` (counts), ``missing`` (counts outside the range), ``min`` and ``max`` (the
///     extreme values seen, units of the histogrammed quantity), ``coord`` (bin centres,
///     same units), ``count`` and ``fraction`` (float arrays, one per bin).
///
/// Raises:
///     FormatError: the text is not an ave/histo file (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> text = '''# Histogrammed data for fix h
///     ... # TimeStep Number-of-bins Total-counts Missing-counts Min-value Max-value
///     ... # Bin Coord Count Count/Total
///     ... 1000 2 100 0 0.01 1.9
///     ... 1 0.5 60 0.6
///     ... 2 1.5 40 0.4
///     ... '''
///     >>> block = dpdnl.read_ave_histo(text=text)["blocks"][0]
///     >>> block["total"], block["coord"].tolist(), block["fraction"].tolist()
///     (100.0, [0.5, 1.5], [0.6, 0.4])
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

/// A time series from a scalar-mode ``fix ave/time`` file or a log, the input the analyses
/// take.
///
/// A log's runs are joined with the last run's columns, repeated steps dropped.
///
/// Args:
///     path: the file; give this or ``text``.
///     text: the file's text instead of a file.
///
/// Returns:
///     ``{"Step": steps, column: values, …}``, float arrays of equal length.
///
/// Raises:
///     FormatError: neither a scalar ave/time file nor a log (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> text = '''# Time-averaged data for fix avg
///     ... # TimeStep c_msd[4]
///     ... 100 0.52
///     ... 200 1.04
///     ... '''
///     >>> s = dpdnl.read_series(text=text)
///     >>> list(s), s["Step"].tolist()
///     (['Step', 'c_msd[4]'], [100.0, 200.0])
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

/// The kind of a file, from its first lines.
///
/// Args:
///     path: the file; give this or ``text``.
///     text: the file's text instead of a file.
///
/// Returns:
///     ``"ave/time"``, ``"ave/chunk"``, ``"ave/histo"``, ``"dump"`` or ``"log"``.
///
/// Raises:
///     OSError: the file cannot be read.
///
/// Example:
///     >>> dpdnl.detect_kind(text="ITEM: TIMESTEP\n0\n")
///     'dump'
#[pyfunction]
#[pyo3(signature = (path = None, *, text = None))]
fn detect_kind(path: Option<PathBuf>, text: Option<String>) -> PyResult<&'static str> {
    let (_, text) = source(path, text)?;
    Ok(kind_name(detect(&text)))
}

/// Reads any of the above by its kind (:func:`detect_kind`).
///
/// Args:
///     path: the file; give this or ``text``.
///     text: the file's text instead of a file.
///
/// Returns:
///     A log gives :func:`read_log`'s list, a dump :func:`read_dump`'s list, the others
///     their reader's dict.
///
/// Raises:
///     FormatError: the text is not in the format of its kind (file, line, token).
///     OSError: the file cannot be read.
///
/// Example:
///     >>> r = dpdnl.read(text="# Time-averaged data\n# TimeStep v_a\n0 1.5\n10 2.5\n")
///     >>> r["mode"], r["data"]["v_a"].tolist()
///     ('scalar', [1.5, 2.5])
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
