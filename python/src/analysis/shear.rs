//! `couette`, `flowcurve`: Couette viscosity and the flow curve (`dpdnl analyze couette`, `flowcurve`).

use super::*;
use dpdnl::report::shear::{self, CouetteParams, FlowCurve, FlowPoint};

/// The viscosity of Couette flow under Lees–Edwards boundaries (``fix deform … xy erate``),
/// as ``dpdnl analyze couette``: η* = −⟨P_xy⟩ / shear rate, the mean and its error from
/// block averaging.
///
/// Give the imposed ``rate``, or a velocity ``profile`` to measure it from.
///
/// Args:
///     source: a ``fix ave/time`` file or log with P_xy, or a series dict such as
///         ``Simulation.thermo[-1]``.
///     col: the P_xy column, pressure units (lj: ε/σ³); None: ``pxy``, else ``c_X[4]``.
///     rate: the imposed shear rate (``fix deform`` erate), 1/time (lj: 1/τ).
///     profile: instead of ``rate``, a ``fix ave/chunk`` profile of v_x along y, whose
///         block-averaged slope is the shear rate.
///     v_col: the profile's velocity column.
///     y_col: the profile's coordinate column.
///     y_scale: multiply the profile coordinate by this (L_y when the chunks use ``units
///         reduced``, which LAMMPS requires for triclinic boxes).
///     from_step: use only samples and outputs at or after this step.
///     label: the label of this result in :func:`flowcurve`; None: the file name without its
///         extension, or ``"couette"`` for a dict.
///
/// Returns:
///     The dict ``dpdnl analyze couette`` writes to ``PREFIX.json`` (units: lj):
///
///     - ``analysis`` (``"couette"``), ``label``, ``input``, ``column``, ``n_samples``,
///       ``from_step``;
///     - ``pxy``, ``pxy_err``: ⟨P_xy⟩ and its block error, pressure units; ``pxy_n_eff`` (the
///       effective number of independent samples behind the error) and ``pxy_converged``
///       (False: too few blocks at the chosen level, so the error is a lower bound;
///       docs/analysis.md, "How the errors are formed");
///     - ``shear_rate``, ``shear_rate_err`` (1/time), ``shear_rate_source`` (imposed or
///       measured), ``shear_rate_imposed`` (``rate``, or None);
///     - ``viscosity``, ``viscosity_err``: η*, mass/(distance·time) (lj: m/(σ τ); in 2-D
///       mass/time);
///     - ``table``: arrays ``step``, ``pxy``, ``pxy_running_mean``;
///     - ``profile`` (with ``profile`` only): arrays ``y``, ``v``, ``v_err``, ``v_fit``.
///
/// Raises:
///     AnalysisError: no P_xy column, neither rate nor profile, a series too short.
///     FormatError: a file is not in the expected format.
///     OSError: a file cannot be read.
///
/// Example:
///     >>> rng = np.random.default_rng(3)
///     >>> steps = np.arange(0, 20000, 10)
///     >>> s = {"Step": steps, "pxy": -0.5 + 0.05 * rng.standard_normal(steps.size)}
///     >>> r = dpdnl.couette(s, rate=0.25)
///     >>> round(r["viscosity"], 1), r["shear_rate_source"]
///     (2.0, 'imposed')
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

/// The viscosity against the shear rate, as ``dpdnl analyze flowcurve``: the points of
/// several results grouped by their label and sorted by rate.
///
/// Args:
///     results: results of :func:`nemd` or :func:`couette` (dicts, or their JSON files), or
///         CSV files with the columns ``label,rate,eta,eta_err``.
///
/// Returns:
///     A dict: ``analysis`` (``"flowcurve"``); ``groups``, one dict per label with ``label``
///     and the arrays ``rate`` (1/time), ``eta`` and ``eta_err`` (viscosity units); ``csv``,
///     the text of the CSV file the CLI writes.
///
/// Raises:
///     AnalysisError: a result without a shear rate or viscosity.
///     OSError: a file cannot be read.
///
/// Example:
///     >>> steps = np.arange(0, 2000, 10)
///     >>> a = dpdnl.couette({"Step": steps, "pxy": np.full(steps.size, -0.5)}, rate=0.25,
///     ...                   label="cross")
///     >>> b = dpdnl.couette({"Step": steps, "pxy": np.full(steps.size, -0.8)}, rate=0.5,
///     ...                   label="cross")
///     >>> g = dpdnl.flowcurve([b, a])["groups"][0]
///     >>> g["label"], g["rate"].tolist(), g["eta"].round(6).tolist()
///     ('cross', [0.25, 0.5], [2.0, 1.6])
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
