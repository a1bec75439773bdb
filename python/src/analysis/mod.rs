//! `dpdnl analyze` from Python: the analyses of `dpdnl::report` (the same calls as the CLI in
//! `src/bin/dpdnl/analyze/`), returning the dict that the CLI writes to `PREFIX.json` plus
//! `"table"`: the columns of `PREFIX.csv` as arrays. No files are written and nothing is
//! plotted. Inputs are paths, or for time series a dict `{"Step": steps, column: values, …}`
//! (`read_series`, `Simulation.thermo[k]`). python/tests/test_analysis.py compares each result
//! with the CLI's JSON on the same input.

use crate::{AnalysisError, arr, json_to_py, read_text};
use dpdnl::analysis::formats::Series;
use dpdnl::report::{self, Table};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping, PyString};
use serde_json::Value;
use std::path::PathBuf;

mod maxwell;
mod pex;
mod shear;
mod transport;

use maxwell::{mb, mb_pdf};
use pex::nemd;
use shear::{couette, flowcurve};
use transport::{eh, msd};

fn aerr(e: String) -> PyErr {
    AnalysisError::new_err(e)
}

/// The result: the JSON object as a dict, with `table` (CSV columns as arrays) added.
fn result<'py>(py: Python<'py>, json: &Value, table: &Table) -> PyResult<Bound<'py, PyAny>> {
    let d = json_to_py(py, json)?;
    let t = PyDict::new(py);
    for (name, col) in table {
        t.set_item(*name, arr(py, col))?;
    }
    d.set_item("table", t)?;
    Ok(d)
}

/// A 1-D float64 vector from any array-like (NumPy array, list).
pub(crate) fn f64_vec(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let np = obj.py().import("numpy")?;
    let a = np
        .call_method1("ascontiguousarray", (obj, "float64"))
        .and_then(|a| a.extract::<PyReadonlyArray1<'_, f64>>())
        .map_err(|_| PyTypeError::new_err(format!("{what}: expected a 1-D array of numbers")))?;
    Ok(a.as_array().to_vec())
}

/// A time series given as a path or as a mapping name → 1-D array with a `Step` (or
/// `TimeStep`, `steps`) entry. Returns the series and its name for messages.
fn series_arg(obj: &Bound<'_, PyAny>) -> PyResult<(Series, String)> {
    if let Ok(m) = obj.cast::<PyMapping>() {
        let mut steps: Option<Vec<f64>> = None;
        let mut columns = Vec::new();
        let mut data = Vec::new();
        for item in m.items()?.iter() {
            let (k, v): (String, Bound<'_, PyAny>) = item.extract()?;
            let v = f64_vec(&v, &format!("series column '{k}'"))?;
            if steps.is_none() && matches!(k.as_str(), "Step" | "TimeStep" | "steps" | "step") {
                steps = Some(v);
            } else {
                columns.push(k);
                data.push(v);
            }
        }
        let steps = steps.ok_or_else(|| {
            aerr(format!(
                "<series>: no 'Step' entry (keys: {})",
                columns.join(" ")
            ))
        })?;
        if let Some((c, _)) = columns
            .iter()
            .zip(&data)
            .find(|(_, d)| d.len() != steps.len())
        {
            return Err(aerr(format!(
                "<series>: column '{c}' does not have one value per step ({} steps)",
                steps.len()
            )));
        }
        return Ok((
            Series {
                columns,
                steps,
                data,
            },
            "<series>".to_string(),
        ));
    }
    let p: PathBuf = obj.extract().map_err(|_| {
        PyTypeError::new_err("expected a path or a dict {'Step': steps, column: values, …}")
    })?;
    let name = p.display().to_string();
    let s = report::series_from_text(&name, &read_text(&p)?).map_err(aerr)?;
    Ok((s, name))
}

fn paths(obj: &Bound<'_, PyAny>) -> PyResult<Vec<PathBuf>> {
    if obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__")? {
        return Ok(vec![obj.extract()?]);
    }
    obj.try_iter()?
        .map(|p| p.and_then(|p| p.extract::<PathBuf>()))
        .collect()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(mb, m)?)?;
    m.add_function(wrap_pyfunction!(mb_pdf, m)?)?;
    m.add_function(wrap_pyfunction!(nemd, m)?)?;
    m.add_function(wrap_pyfunction!(eh, m)?)?;
    m.add_function(wrap_pyfunction!(msd, m)?)?;
    m.add_function(wrap_pyfunction!(couette, m)?)?;
    m.add_function(wrap_pyfunction!(flowcurve, m)?)?;
    Ok(())
}
