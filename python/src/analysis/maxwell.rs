//! `mb`, `mb_pdf`: the Maxwell–Boltzmann check (`dpdnl analyze mb`).

use super::*;
use dpdnl::report::mb::{self as rmb, MbInput, MbParams};

/// Speed distribution against Maxwell–Boltzmann (`dpdnl analyze mb`): from `fix ave/histo`
/// files or dumps with velocities (`files`), or from `speeds` (a list of 1-D arrays of
/// speeds, one per frame or block).
#[pyfunction]
#[pyo3(signature = (files = None, *, temp, mass = 1.0, dim = None, bins = 150, vmax = None, from_step = 0, speeds = None))]
#[allow(clippy::too_many_arguments)]
pub(super) fn mb<'py>(
    py: Python<'py>,
    files: Option<Bound<'py, PyAny>>,
    temp: f64,
    mass: f64,
    dim: Option<usize>,
    bins: usize,
    vmax: Option<f64>,
    from_step: u64,
    speeds: Option<Vec<Bound<'py, PyAny>>>,
) -> PyResult<Bound<'py, PyAny>> {
    let files = match &files {
        Some(f) => paths(f)?,
        None => Vec::new(),
    };
    let mut input = MbInput::new(dim);
    for f in &files {
        let text = read_text(f)?;
        input
            .add_text(&f.display().to_string(), &text, from_step)
            .map_err(aerr)?;
    }
    if let Some(sp) = &speeds {
        if !files.is_empty() {
            return Err(aerr("give either files or speeds, not both".into()));
        }
        let samples = sp
            .iter()
            .map(|a| f64_vec(a, "speeds"))
            .collect::<PyResult<_>>()?;
        input.add_speeds(samples);
    }
    let p = MbParams {
        temp,
        mass,
        bins,
        vmax,
    };
    let m = rmb::analyze(input, &p).map_err(aerr)?;
    result(py, &m.json(), &m.table())
}

/// The Maxwell–Boltzmann speed density P(v) in d dimensions at kT and mass m (the curve the
/// CLI's figure draws), at each speed of `v`.
#[pyfunction]
#[pyo3(signature = (v, temp, *, mass = 1.0, dim = 3))]
pub(super) fn mb_pdf<'py>(
    py: Python<'py>,
    v: PyReadonlyArray1<'py, f64>,
    temp: f64,
    mass: f64,
    dim: usize,
) -> Bound<'py, numpy::PyArray1<f64>> {
    let out: Vec<f64> = v
        .as_array()
        .iter()
        .map(|&x| dpdnl::analysis::mb::mb_pdf(x, temp, mass, dim))
        .collect();
    arr(py, &out)
}
