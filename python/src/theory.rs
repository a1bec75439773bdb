//! `dpdnl::theory` from Python: kinetic theory, (η, Sc) design and the Euler finite-step
//! temperature. Each function returns the dict that `dpdnl design --json` / `dpdnl theory
//! --json` prints (the Python layer wraps them in dataclasses).

use crate::{TheoryError, json_to_py};
use dpdnl::report::theory::{self as rt, InputLines, TransportJson};
use dpdnl::report::to_value;
use dpdnl::theory::{Fluid, TheoryError as CoreError, kinetic_theory};
use pyo3::prelude::*;
use serde_json::Value;

fn err(e: CoreError) -> PyErr {
    TheoryError::new_err(e.to_string())
}

fn fluid(dim: i64, density: f64, rc: f64, mass: f64, kt: f64) -> PyResult<Fluid> {
    rt::fluid_of(dim, density, rc, mass, kt).map_err(err)
}

/// A result as the dict `json.loads` gives for the CLI's `--json` output.
fn to_py(py: Python<'_>, v: Result<Value, String>) -> PyResult<Bound<'_, PyAny>> {
    json_to_py(py, &v.map_err(TheoryError::new_err)?)
}

/// Kinetic theory of the ideal DPD fluid (a = 0) with w_D = (1 − r/r_c)^s: `{"eta_k",
/// "eta_d", "eta", "diffusion", "schmidt"}` (`dpdnl theory`'s "predicted").
#[pyfunction]
#[pyo3(signature = (gamma, s, density, rc, *, kt = 1.0, mass = 1.0, dim = 3))]
#[allow(clippy::too_many_arguments)]
fn _kinetic_theory<'py>(
    py: Python<'py>,
    gamma: f64,
    s: f64,
    density: f64,
    rc: f64,
    kt: f64,
    mass: f64,
    dim: i64,
) -> PyResult<Bound<'py, PyAny>> {
    let f = fluid(dim, density, rc, mass, kt)?;
    let t = kinetic_theory(&f, gamma, s).map_err(err)?;
    to_py(py, to_value(&TransportJson::from(&t)))
}

/// `dpdnl design --json`: γ and s from the target η and Sc (exact inversion, or the
/// weighting-function paper's approximation), the check by kinetic theory, the limits and the
/// two input lines.
#[pyfunction]
#[pyo3(signature = (eta, sc, density, rc, *, kt = 1.0, mass = 1.0, dim = 3, paper_approx = false, seed = 12345))]
#[allow(clippy::too_many_arguments)]
fn _design<'py>(
    py: Python<'py>,
    eta: f64,
    sc: f64,
    density: f64,
    rc: f64,
    kt: f64,
    mass: f64,
    dim: i64,
    paper_approx: bool,
    seed: u32,
) -> PyResult<Bound<'py, PyAny>> {
    let f = fluid(dim, density, rc, mass, kt)?;
    let lines = InputLines::of("dpd", None)
        .ok_or_else(|| pyo3::exceptions::PyValueError::new_err("no design method 'dpd'"))?;
    let d = rt::design(f, eta, sc, paper_approx, seed, lines).map_err(err)?;
    to_py(py, to_value(&d.json()))
}

/// `dpdnl theory --json` (without a script): the fluid, the kinetic theory of (γ, s) and,
/// with `dt`, the Euler finite-step temperature.
#[pyfunction]
#[pyo3(signature = (gamma, s, density, rc, *, kt = 1.0, mass = 1.0, dim = 3, dt = None))]
#[allow(clippy::too_many_arguments)]
fn _theory<'py>(
    py: Python<'py>,
    gamma: f64,
    s: f64,
    density: f64,
    rc: f64,
    kt: f64,
    mass: f64,
    dim: i64,
    dt: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let f = fluid(dim, density, rc, mass, kt)?;
    let t = rt::theory(f, gamma, s, dt).map_err(err)?;
    to_py(py, to_value(&t.json()))
}

/// The Euler integrator's finite-step temperature (finite-step paper eqs. 22-26) as `dpdnl
/// theory --dt` gives it: `{"dt", "stable", "t_ratio" (None when unstable), "dt_c", "n_c"
/// (None when no density is stable)}`.
#[pyfunction]
#[pyo3(signature = (gamma, s, density, rc, dt, *, kt = 1.0, mass = 1.0, dim = 3))]
#[allow(clippy::too_many_arguments)]
fn _euler_temperature<'py>(
    py: Python<'py>,
    gamma: f64,
    s: f64,
    density: f64,
    rc: f64,
    dt: f64,
    kt: f64,
    mass: f64,
    dim: i64,
) -> PyResult<Bound<'py, PyAny>> {
    let f = fluid(dim, density, rc, mass, kt)?;
    to_py(py, to_value(&rt::euler(&f, gamma, s, dt).map_err(err)?))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_kinetic_theory, m)?)?;
    m.add_function(wrap_pyfunction!(_design, m)?)?;
    m.add_function(wrap_pyfunction!(_theory, m)?)?;
    m.add_function(wrap_pyfunction!(_euler_temperature, m)?)?;
    Ok(())
}
