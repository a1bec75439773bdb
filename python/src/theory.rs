//! `dpdnl::theory` from Python: kinetic theory, (η, Sc) design and the Euler finite-step
//! temperature. Each function returns the dict that `dpdnl design --json` / `dpdnl theory
//! --json` prints (the Python layer wraps them in dataclasses).

use crate::{TheoryError, json_to_py};
use dpdnl::theory::{
    Design, DesignMode, Dim, Fluid, Targets, TheoryError as CoreError, Transport,
    design_from_targets, design_paper_approx, euler_critical_density, euler_critical_dt,
    euler_temperature_ratio, kinetic_theory,
};
use pyo3::prelude::*;
use serde_json::{Value, json};

fn err(e: CoreError) -> PyErr {
    TheoryError::new_err(e.to_string())
}

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn fluid(dim: i64, density: f64, rc: f64, mass: f64, kt: f64) -> PyResult<Fluid> {
    let d = u32::try_from(dim)
        .map_err(|_| CoreError::Parameter {
            name: "dimension d",
            value: dim as f64,
            requirement: "2 or 3",
        })
        .and_then(Dim::new)
        .map_err(err)?;
    Fluid::new(d.get(), density, rc, mass, kt).map_err(err)
}

fn fluid_json(f: &Fluid) -> Value {
    json!({"dim": f.dim.get(), "density": num(f.density), "cutoff": num(f.cutoff),
           "mass": num(f.mass), "kt": num(f.kt)})
}

fn transport_json(t: &Transport) -> Value {
    json!({"eta_k": num(t.eta_k), "eta_d": num(t.eta_d), "eta": num(t.eta),
           "diffusion": num(t.diffusion), "schmidt": num(t.schmidt)})
}

/// Shortest round-trip decimal form, as the CLI prints numbers in the input lines.
fn short(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-5..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn design_json(f: &Fluid, d: &Design, eta: f64, sc: f64, seed: u32) -> Value {
    let (mode, targets) = match d.mode {
        DesignMode::Exact => ("exact", json!({"eta": num(eta), "sc": num(sc)})),
        DesignMode::PaperApprox => ("paper-approx", json!({"eta0": num(eta), "sc0": num(sc)})),
    };
    let lim = &d.limits;
    json!({
        "command": "design", "mode": mode, "fluid": fluid_json(f), "targets": targets,
        "design": {"eta0": num(d.eta0), "s": num(d.s), "gamma": num(d.gamma)},
        "limits": {"p": num(lim.p), "p0": num(lim.p0), "eta_max": num(lim.eta_max),
                   "sc_min": num(lim.sc_min), "sc_gas_max": lim.sc_gas_max.map_or(Value::Null, num),
                   "density_min": num(lim.density_min), "cutoff_min": num(lim.cutoff_min)},
        "pair_style": format!("pair_style dpd/nonlinear {} {} {seed} weight {}",
                              short(f.kt), short(f.cutoff), short(d.s)),
        "pair_coeff": format!("pair_coeff * * 0.0 {} 0.0", short(d.gamma)),
    })
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
    json_to_py(py, &transport_json(&t))
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
    let d = if paper_approx {
        design_paper_approx(&f, eta, sc)
    } else {
        design_from_targets(&Targets { fluid: f, eta, sc })
    }
    .map_err(err)?;
    let pred = kinetic_theory(&f, d.gamma, d.s).map_err(err)?;
    let mut v = design_json(&f, &d, eta, sc, seed);
    v["predicted"] = transport_json(&pred);
    json_to_py(py, &v)
}

/// The Euler integrator's finite-step temperature (finite-step paper eqs. 22-26) as `dpdnl
/// theory --dt` gives it: `{"dt", "stable", "t_ratio" (None when unstable), "dt_c", "n_c"
/// (None when no density is stable)}`.
fn euler_json(f: &Fluid, gamma: f64, s: f64, dt: f64) -> PyResult<Value> {
    let ratio = match euler_temperature_ratio(f, gamma, s, dt) {
        Ok(r) => Some(r),
        Err(CoreError::EulerUnstable { .. }) => None,
        Err(e) => return Err(err(e)),
    };
    let dt_c = euler_critical_dt(f, gamma, s).map_err(err)?;
    let n_c = match euler_critical_density(f, gamma, s, dt) {
        Ok(n) => Some(n),
        Err(CoreError::EulerNoStableDensity { .. }) => None,
        Err(e) => return Err(err(e)),
    };
    Ok(json!({"dt": num(dt), "stable": ratio.is_some(),
              "t_ratio": ratio.map_or(Value::Null, num), "dt_c": num(dt_c),
              "n_c": n_c.map_or(Value::Null, num)}))
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
    let t = kinetic_theory(&f, gamma, s).map_err(err)?;
    let euler = match dt {
        None => Value::Null,
        Some(dt) => euler_json(&f, gamma, s, dt)?,
    };
    let v = json!({"command": "theory", "fluid": fluid_json(&f), "gamma": num(gamma),
                   "s": num(s), "predicted": transport_json(&t), "euler": euler});
    json_to_py(py, &v)
}

/// The Euler finite-step temperature alone (see `_theory`).
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
    json_to_py(py, &euler_json(&f, gamma, s, dt)?)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_kinetic_theory, m)?)?;
    m.add_function(wrap_pyfunction!(_design, m)?)?;
    m.add_function(wrap_pyfunction!(_theory, m)?)?;
    m.add_function(wrap_pyfunction!(_euler_temperature, m)?)?;
    Ok(())
}
