//! `nemd`: reverse NEMD with the PeX push (`dpdnl analyze nemd`).

use super::*;
use dpdnl::report::nemd::{self as rnemd, NemdParams};

/// Reverse NEMD (PeX push), as `dpdnl analyze nemd`: profiles from a `fix ave/chunk` file,
/// fits, Π_xz (eq. 55; nominal from `dp`, or measured from the pushed total in `push`),
/// viscosity (eq. 56) and T_d (eq. 58).
#[pyfunction]
#[pyo3(signature = (profile, *, r#box, dt, xlo = None, dp = None, every = 1, push = None, push_col = None, from_step = 0, fit_fraction = 0.5, vz_col = "vz", density_col = "density/number", td_col = "v_td", label = None))]
#[allow(clippy::too_many_arguments)]
pub(super) fn nemd<'py>(
    py: Python<'py>,
    profile: PathBuf,
    r#box: [f64; 3],
    dt: f64,
    xlo: Option<f64>,
    dp: Option<f64>,
    every: u64,
    push: Option<Bound<'py, PyAny>>,
    push_col: Option<String>,
    from_step: u64,
    fit_fraction: f64,
    vz_col: &str,
    density_col: &str,
    td_col: &str,
    label: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let pname = profile.display().to_string();
    let text = read_text(&profile)?;
    let p = NemdParams {
        r#box,
        xlo,
        dt,
        dp,
        every,
        push_col,
        from: from_step,
        fit_fraction,
        vz_col: vz_col.into(),
        density_col: density_col.into(),
        td_col: td_col.into(),
    };
    let prof = rnemd::profiles(&pname, &text, &p).map_err(aerr)?;
    let push = match &push {
        Some(s) => {
            let (s, name) = series_arg(s)?;
            Some((name, s))
        }
        None => None,
    };
    let label = label.unwrap_or_else(|| report::stem(&profile, "nemd"));
    let n = rnemd::analyze(prof, push, &p, label).map_err(aerr)?;
    result(py, &n.json(), &n.table())
}
