//! `eh`, `msd`: Einstein–Helfand viscosity and self-diffusion (`dpdnl analyze eh`, `msd`).

use super::*;
use dpdnl::report::transport::{self, EhParams, MsdParams, MsdSource};
use serde_json::json;

/// Einstein–Helfand viscosity (eq. 59), as `dpdnl analyze eh`, from off-diagonal pressure
/// series: a scalar-mode `fix ave/time` file, a log, or a series dict (e.g.
/// `Simulation.thermo[-1]`).
#[pyfunction]
#[pyo3(signature = (source, *, dt, r#box, temp, density, mass = 1.0, cols = None, from_step = 0, window_factor = 0.1, tmin = None, tmax = None, blocks = 10))]
#[allow(clippy::too_many_arguments)]
pub(super) fn eh<'py>(
    py: Python<'py>,
    source: Bound<'py, PyAny>,
    dt: f64,
    r#box: Vec<f64>,
    temp: f64,
    density: f64,
    mass: f64,
    cols: Option<Vec<String>>,
    from_step: u64,
    window_factor: f64,
    tmin: Option<f64>,
    tmax: Option<f64>,
    blocks: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let p = EhParams {
        dt,
        r#box,
        temp,
        density,
        mass,
        cols,
        from: from_step,
        window_factor,
        tmin,
        tmax,
        blocks,
    };
    p.check().map_err(aerr)?;
    let (s, name) = series_arg(&source)?;
    let e = transport::eh(&name, s, &p).map_err(aerr)?;
    result(py, &e.json(), &e.table())
}

// ---------------------------------------------------------------- msd

/// Self-diffusion from the MSD, as `dpdnl analyze msd`: a series with a compute msd column
/// (file or dict), or a dump with unwrapped positions or image flags; with `eta` (or
/// `eta_from`, a result dict or JSON file of `eh`/`nemd`) and `density`, the Schmidt number.
#[pyfunction]
#[pyo3(signature = (source, *, dt, dim = 3, col = None, atoms = None, tmin = None, tmax = None, from_step = 0, eta = None, eta_err = 0.0, eta_from = None, density = None, mass = 1.0))]
#[allow(clippy::too_many_arguments)]
pub(super) fn msd<'py>(
    py: Python<'py>,
    source: Bound<'py, PyAny>,
    dt: f64,
    dim: usize,
    col: Option<String>,
    atoms: Option<usize>,
    tmin: Option<f64>,
    tmax: Option<f64>,
    from_step: u64,
    eta: Option<f64>,
    eta_err: f64,
    eta_from: Option<Bound<'py, PyAny>>,
    density: Option<f64>,
    mass: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let p = MsdParams {
        dt,
        dim,
        col,
        atoms,
        tmin,
        tmax,
        from: from_step,
    };
    // A dump (by its first line) is read as trajectories, anything else as a series.
    let (src, name) = if source.cast::<PyMapping>().is_err() {
        let p: PathBuf = source.extract().map_err(|_| {
            PyTypeError::new_err("expected a path or a dict {'Step': steps, column: values, …}")
        })?;
        let name = p.display().to_string();
        let src = MsdSource::from_text(&name, &read_text(&p)?).map_err(aerr)?;
        (src, name)
    } else {
        let (s, name) = series_arg(&source)?;
        (MsdSource::Series(s), name)
    };
    let mut m = transport::msd(&name, src, &p).map_err(aerr)?;
    let eta = match (&eta_from, eta) {
        (Some(src), _) => Some(if let Ok(d) = src.cast::<PyDict>() {
            let mu: Option<f64> = d.get_item("viscosity")?.and_then(|x| x.extract().ok());
            let e: Option<f64> = d.get_item("viscosity_err")?.and_then(|x| x.extract().ok());
            let v = json!({"viscosity": mu, "viscosity_err": e});
            transport::viscosity_of("<result>", &v).map_err(aerr)?
        } else {
            let p: PathBuf = src.extract()?;
            transport::viscosity_from_text(&p.display().to_string(), &read_text(&p)?)
                .map_err(aerr)?
        }),
        (None, Some(mu)) => Some((mu, eta_err, "--eta".to_string())),
        _ => None,
    };
    m.schmidt(eta, density, mass).map_err(aerr)?;
    result(py, &m.json(), &m.table())
}
