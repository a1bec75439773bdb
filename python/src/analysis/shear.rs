//! `couette`, `flowcurve`: Couette viscosity and the flow curve (`dpdnl analyze couette`, `flowcurve`).

use super::*;
use dpdnl::report::shear::{self, CouetteParams, FlowCurve, FlowPoint};

/// Couette flow under Lees–Edwards, as `dpdnl analyze couette`: η* = −⟨P_xy⟩ / shear rate,
/// the rate imposed (`rate`) or measured from a `fix ave/chunk` velocity profile (`profile`).
#[pyfunction]
#[pyo3(signature = (source, *, col = None, rate = None, profile = None, v_col = "vx", y_col = "Coord1", y_scale = 1.0, from_step = 0, label = None))]
#[allow(clippy::too_many_arguments)]
pub(super) fn couette<'py>(
    py: Python<'py>,
    source: Bound<'py, PyAny>,
    col: Option<String>,
    rate: Option<f64>,
    profile: Option<PathBuf>,
    v_col: &str,
    y_col: &str,
    y_scale: f64,
    from_step: u64,
    label: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let (s, name) = series_arg(&source)?;
    let p = CouetteParams {
        col,
        rate,
        v_col: v_col.into(),
        y_col: y_col.into(),
        y_scale,
        from: from_step,
    };
    let s = shear::series(&name, s, &p).map_err(aerr)?;
    let prof = match &profile {
        Some(f) => Some((f.display().to_string(), read_text(f)?)),
        None => None,
    };
    let label = label.unwrap_or_else(|| match source.extract::<PathBuf>() {
        Ok(p) if source.cast::<PyMapping>().is_err() => report::stem(&p, "couette"),
        _ => "couette".into(),
    });
    let c = shear::analyze(
        s,
        prof.as_ref().map(|(n, t)| (n.as_str(), t.as_str())),
        &p,
        label,
    )
    .map_err(aerr)?;
    let out = result(py, &c.json(), &c.table())?;
    if let (Some(p), Some(fit)) = (&c.profile, c.profile_fit()) {
        let d = PyDict::new(py);
        d.set_item("y", arr(py, &p.y))?;
        d.set_item("v", arr(py, &p.v_mean))?;
        d.set_item("v_err", arr(py, &p.v_err))?;
        d.set_item("v_fit", arr(py, &fit))?;
        out.set_item("profile", d)?;
    }
    Ok(out)
}

// ---------------------------------------------------------------- flow curve

/// Viscosity against shear rate (`dpdnl analyze flowcurve`) from results of `nemd`/`couette`
/// (dicts, or their JSON files) or CSV files with columns label,rate,eta,eta_err: the points
/// grouped by label and sorted by rate, and the CSV text the CLI writes.
#[pyfunction]
pub(super) fn flowcurve<'py>(
    py: Python<'py>,
    results: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let mut curve = FlowCurve::default();
    for item in results.try_iter()? {
        let item = item?;
        if let Ok(d) = item.cast::<PyDict>() {
            let get = |k: &str| -> PyResult<f64> {
                d.get_item(k)?
                    .and_then(|x| x.extract::<f64>().ok())
                    .ok_or_else(|| aerr(format!("<result>: no number '{k}'")))
            };
            let label: String = d
                .get_item("label")?
                .and_then(|x| x.extract().ok())
                .unwrap_or_else(|| "result".into());
            let err = d
                .get_item("viscosity_err")?
                .and_then(|x| x.extract::<f64>().ok())
                .unwrap_or(0.0);
            curve.add(label, (get("shear_rate")?.abs(), get("viscosity")?, err));
            continue;
        }
        let f: PathBuf = item.extract()?;
        let text = read_text(&f)?;
        curve
            .add_text(&f.display().to_string(), &text)
            .map_err(aerr)?;
    }
    let curve = curve.sorted();
    let out_groups = pyo3::types::PyList::empty(py);
    for (label, pts) in &curve.groups {
        let g = PyDict::new(py);
        g.set_item("label", label.as_str())?;
        let col = |f: fn(&FlowPoint) -> f64| -> Vec<f64> { pts.iter().map(f).collect() };
        g.set_item("rate", arr(py, &col(|p| p.0)))?;
        g.set_item("eta", arr(py, &col(|p| p.1)))?;
        g.set_item("eta_err", arr(py, &col(|p| p.2)))?;
        out_groups.append(g)?;
    }
    let d = PyDict::new(py);
    d.set_item("analysis", "flowcurve")?;
    d.set_item("groups", out_groups)?;
    d.set_item("csv", curve.csv())?;
    Ok(d.into_any())
}
