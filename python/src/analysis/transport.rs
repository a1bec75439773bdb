//! `eh`, `msd`: Einstein–Helfand viscosity and self-diffusion (`dpdnl analyze eh`, `msd`).

use super::*;
use dpdnl::report::transport::{self, EhParams, MsdParams, MsdSource};
use serde_json::json;

/// The Einstein–Helfand viscosity (non-linear paper eq. 59), as ``dpdnl analyze eh``:
/// μ = V/(2 kT t) ⟨(∫_0^t Π_ab dt')²⟩, averaged over time origins and the off-diagonal
/// components, from the slope over a fit window.
///
/// Sample the stress every step (or average it over every step of the interval): the
/// random stress is uncorrelated between steps. The default window follows the paper's
/// condition t ≪ L²/(4π² ν): t_max = ``window_factor`` · L²/(4π² ν), t_min = t_max/4.
///
/// Args:
///     source: a scalar ``fix ave/time`` file or a log with the off-diagonal pressure
///         components, or a series dict such as ``Simulation.thermo[-1]``.
///     dt: the time step, time units (lj: τ); the sample interval is dt times the step
///         spacing of the series.
///     box: the box lengths (2 in 2-D, 3 in 3-D), distance units (lj: σ): the volume, and
///         the smallest length L of the window rule.
///     temp: kT, an energy (lj: ε).
///     density: the number density n, 1/volume (lj: σ⁻³; σ⁻² in 2-D), for ν = μ/(n m) in the
///         window rule.
///     mass: the particle mass, mass units (lj: m).
///     cols: the stress columns; None: ``pxy pxz pyz`` or ``c_X[4] c_X[5] c_X[6]`` (only xy
///         in 2-D). Pressure units (lj: ε/σ³).
///     from_step: use only samples at or after this step.
///     window_factor: t_max = factor · L²/(4π² ν) (automatic window).
///     tmin: the start of the fit window, time units; with ``tmax``, overrides the automatic
///         window.
///     tmax: the end of the fit window, time units.
///     blocks: the number of consecutive blocks for the error (fewer when a block would be
///         shorter than 4 t_max).
///
/// Returns:
///     The dict ``dpdnl analyze eh`` writes to ``PREFIX.json`` (units: lj):
///
///     - ``analysis`` (``"eh"``), ``input``, ``components`` (the columns used), ``dt``,
///       ``sample_interval`` (time), ``n_samples``, ``from_step``, ``volume``, ``kt``,
///       ``box_len`` (L), ``mass_density`` (n m);
///     - ``viscosity``, ``viscosity_err``: μ, mass/(distance·time) (lj: m/(σ τ); in 2-D
///       mass/time); ``per_component``: μ of each component; ``blocks``: μ of each block
///       (the error is their standard error);
///     - ``t_min``, ``t_max`` (the fit window, time), ``tau_l`` (L²/(4π² ν), time),
///       ``window_source`` (how the window was set), ``window_capped`` (True: the run was too
///       short for the window);
///     - ``slope``, ``intercept``: the fit of ⟨(∫Π dt)²⟩ against t;
///     - ``window_drift``, ``window_drift_err``, ``window_not_linear``: μ on the second half
///       of the window minus μ on the first, its error, and whether it is significant (more
///       than 3 errors: the window is still in the transient);
///     - ``table``: arrays ``t`` (lags), ``msd_integral`` (⟨(∫Π dt)²⟩), ``mu_running``
///       (V⟨(∫Π)²⟩/(2kT t)), ``msd_fit``.
///
/// Raises:
///     AnalysisError: a missing column, a series too short, a bad parameter.
///     FormatError: the file is not an ave/time file or a log.
///     OSError: the file cannot be read.
///
/// Example:
///     >>> rng = np.random.default_rng(2)
///     >>> n = 20000           # white-noise stress: mu = V var(P) dt / (2 kT) = 5
///     >>> p = {"Step": np.arange(n), "pxy": rng.standard_normal(n),
///     ...      "pxz": rng.standard_normal(n), "pyz": rng.standard_normal(n)}
///     >>> r = dpdnl.eh(p, dt=0.01, box=[10, 10, 10], temp=1.0, density=3.0)
///     >>> abs(r["viscosity"] - 5.0) < 3 * r["viscosity_err"]
///     True
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

/// The self-diffusion coefficient D = MSD/(2 d t) from the slope of the mean-squared
/// displacement, as ``dpdnl analyze msd``; with a viscosity and the density, the Schmidt
/// number Sc = μ/(n m D).
///
/// From a series (a ``compute msd`` column): one time origin, default window the last 80 %.
/// From a dump with unwrapped positions (``xu yu zu``, or ``x y z ix iy iz``): all time
/// origins and atoms, lags up to half the trajectory, default window 20–100 % of that, the
/// error from 8 groups of atoms.
///
/// Args:
///     source: a ``fix ave/time`` file or log with a ``compute msd`` column, a dump with
///         unwrapped positions (a path), or a series dict.
///     dt: the time step, time units (lj: τ).
///     dim: the dimension d, 2 or 3.
///     col: the MSD column of a series; None: the only column named like ``c_*[4]`` or
///         ``msd``. Squared distance units (lj: σ²).
///     atoms: the number of atoms (series only): gives the Brownian error estimate; None:
///         the regression error only (an underestimate).
///     tmin: the start of the fit window, time units; None: the default window.
///     tmax: the end of the fit window, time units; None: the default window.
///     from_step: use only samples or frames at or after this step.
///     eta: the shear viscosity μ for the Schmidt number, mass/(distance·time) (lj:
///         m/(σ τ)); needs ``density``.
///     eta_err: the error of ``eta``, same units.
///     eta_from: instead of ``eta``, a result of :func:`eh` or :func:`nemd` (a dict, or its
///         JSON file) to take μ and its error from.
///     density: the number density n, 1/volume (lj: σ⁻³), for ρ = n m.
///     mass: the particle mass, mass units (lj: m).
///
/// Returns:
///     The dict ``dpdnl analyze msd`` writes to ``PREFIX.json`` (units: lj):
///
///     - ``analysis`` (``"msd"``), ``input``, ``dim``, ``dt``, ``method`` (one origin or all
///       origins), ``t_min``, ``t_max`` (the fit window, time);
///     - ``diffusion``, ``diffusion_err``: D, distance²/time (lj: σ²/τ);
///       ``diffusion_err_method`` (how the error was estimated); ``diffusion_groups`` (D of
///       each group of atoms, dumps only);
///     - ``viscosity``, ``viscosity_source`` (the μ used, or None); ``schmidt``,
///       ``schmidt_err`` (a pure number, or None without a viscosity);
///     - ``table``: arrays ``t``, ``msd`` (σ²), ``msd_err`` (NaN where there is none),
///       ``msd_fit``.
///
/// Raises:
///     AnalysisError: no MSD column, a window outside the data, a viscosity without a density.
///     FormatError: the file is not a series or a dump.
///     OSError: a file cannot be read.
///
/// Example:
///     >>> t = np.arange(0, 5000, 50)            # steps; D = 0.05 at dt = 0.01
///     >>> r = dpdnl.msd({"Step": t, "c_msd[4]": 6 * 0.05 * t * 0.01}, dt=0.01,
///     ...               eta=1.0, density=3.0)
///     >>> round(r["diffusion"], 6), round(r["schmidt"], 6)
///     (0.05, 6.666667)
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
