//! `eh`, `msd`: Einstein–Helfand viscosity and self-diffusion (`dpdnl analyze eh`, `msd`).

use super::*;

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
    if !(2..=3).contains(&r#box.len()) {
        return Err(aerr("box: give 2 (2-D) or 3 (3-D) lengths".into()));
    }
    let (s, name) = series_arg(&source)?;
    let s = s.from_step(from_step);
    let dim = r#box.len();
    let names: Vec<String> = match &cols {
        Some(c) => c.clone(),
        None => {
            let want: &[&str] = if dim == 2 {
                &["pxy"]
            } else {
                &["pxy", "pxz", "pyz"]
            };
            if want.iter().all(|n| s.column_index(n).is_some()) {
                want.iter().map(|n| n.to_string()).collect()
            } else if let Some(v) = s.indexed_columns(if dim == 2 { &[4] } else { &[4, 5, 6] }) {
                v
            } else {
                return Err(aerr(format!(
                    "{name}: cannot find the off-diagonal pressure columns (columns: {}); give --cols",
                    s.columns.join(" ")
                )));
            }
        }
    };
    let comps: Vec<&[f64]> = names
        .iter()
        .map(|n| in_name(&name, s.column(n)))
        .collect::<Result<_, _>>()?;
    let spacing = in_name(&name, step_spacing(&s.steps))?;
    let volume: f64 = r#box.iter().product();
    let box_len = r#box.iter().copied().fold(f64::INFINITY, f64::min);
    let mut o = aeh::EhOptions::new(spacing * dt, volume, temp, box_len, density * mass);
    o.window_factor = window_factor;
    o.t_min = tmin;
    o.t_max = tmax;
    o.n_blocks = blocks;
    let r = in_name(&name, aeh::analyze(&comps, &o))?;
    let drifting =
        r.drift.is_finite() && r.drift_err.is_finite() && r.drift.abs() > 3.0 * r.drift_err;
    let fitline: Vec<f64> =
        r.t.iter()
            .map(|t| r.fit.slope * t + r.fit.intercept)
            .collect();
    let json = json!({
        "analysis": "eh", "input": name, "components": names,
        "dt": dt, "sample_interval": o.dt_sample, "n_samples": r.n_samples, "from_step": from_step,
        "volume": volume, "kt": temp, "box_len": box_len, "mass_density": o.mass_density,
        "t_min": num(r.t_min), "t_max": num(r.t_max), "tau_l": num(r.tau_l),
        "window_source": r.window_source, "window_capped": r.capped,
        "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
        "per_component": nums(&r.per_component), "blocks": nums(&r.blocks),
        "window_drift": num(r.drift), "window_drift_err": num(r.drift_err), "window_not_linear": drifting,
        "slope": num(r.fit.slope), "intercept": num(r.fit.intercept),
    });
    result(
        py,
        &json,
        &[
            ("t", &r.t),
            ("msd_integral", &r.msd),
            ("mu_running", &r.running),
            ("msd_fit", &fitline),
        ],
    )
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
    let mut o = amsd::MsdOptions::new(dim);
    o.t_min = tmin;
    o.t_max = tmax;
    // A dump (by its first line) is read as trajectories, anything else as a series.
    let dump = if source.cast::<PyMapping>().is_err() {
        let p: PathBuf = source.extract().map_err(|_| {
            PyTypeError::new_err("expected a path or a dict {'Step': steps, column: values, …}")
        })?;
        let text = read_text(&p)?;
        (detect(&text) == FileKind::Dump).then_some((p, text))
    } else {
        None
    };
    let (r, name) = if let Some((p, text)) = dump {
        let name = p.display().to_string();
        let frames: Vec<DumpFrame> = in_name(&name, parse_dump(&text))?
            .into_iter()
            .filter(|f| f.step >= from_step)
            .collect();
        let (steps, series, note) = in_name(&name, amsd::unwrapped_series(&frames, dim))?;
        let st: Vec<f64> = steps.iter().map(|&k| k as f64).collect();
        let spacing = in_name(&name, step_spacing(&st))?;
        let mut r = in_name(
            &name,
            amsd::from_trajectories(&series, dim, spacing * dt, &o),
        )?;
        r.method = format!("{} ({note})", r.method);
        (r, name)
    } else {
        let (s, name) = series_arg(&source)?;
        let s = s.from_step(from_step);
        let c = match &col {
            Some(c) => c.clone(),
            None => {
                let c: Vec<&String> = s
                    .columns
                    .iter()
                    .filter(|c| c.ends_with("[4]") || c.eq_ignore_ascii_case("msd"))
                    .collect();
                match c.as_slice() {
                    [one] => (*one).clone(),
                    _ => {
                        return Err(aerr(format!(
                            "{name}: cannot tell the MSD column (columns: {}); give --col",
                            s.columns.join(" ")
                        )));
                    }
                }
            }
        };
        let m = in_name(&name, s.column(&c))?;
        let t: Vec<f64> = s.steps.iter().map(|k| k * dt).collect();
        (in_name(&name, amsd::from_series(&t, m, &o, atoms))?, name)
    };
    let eta = match (&eta_from, eta) {
        (Some(src), _) => {
            let (v, from): (Value, String) = if let Ok(d) = src.cast::<PyDict>() {
                let mu: Option<f64> = d.get_item("viscosity")?.and_then(|x| x.extract().ok());
                let e: Option<f64> = d.get_item("viscosity_err")?.and_then(|x| x.extract().ok());
                (
                    json!({"viscosity": mu, "viscosity_err": e}),
                    "<result>".to_string(),
                )
            } else {
                let p: PathBuf = src.extract()?;
                let v = serde_json::from_str(&read_text(&p)?)
                    .map_err(|e| aerr(format!("{}: {e}", p.display())))?;
                (v, p.display().to_string())
            };
            let mu = v["viscosity"]
                .as_f64()
                .ok_or_else(|| aerr(format!("{from}: no 'viscosity' number")))?;
            Some((mu, v["viscosity_err"].as_f64().unwrap_or(0.0), from))
        }
        (None, Some(mu)) => Some((mu, eta_err, "--eta".to_string())),
        _ => None,
    };
    let sc = match (eta.as_ref(), density) {
        (Some((mu, mu_err, _)), Some(n)) => {
            Some(amsd::schmidt(*mu, *mu_err, n * mass, r.d, r.d_err))
        }
        (Some(_), None) => return Err(aerr("the Schmidt number needs --density".into())),
        _ => None,
    };
    let fitline: Vec<f64> =
        r.t.iter()
            .map(|t| r.fit.slope * t + r.fit.intercept)
            .collect();
    let err = r
        .msd_err
        .clone()
        .unwrap_or_else(|| vec![f64::NAN; r.t.len()]);
    let json = json!({
        "analysis": "msd", "input": name, "dim": dim, "dt": dt,
        "method": r.method, "t_min": num(r.t_min), "t_max": num(r.t_max),
        "diffusion": num(r.d), "diffusion_err": num(r.d_err), "diffusion_err_method": r.d_err_method,
        "diffusion_groups": nums(&r.d_groups),
        "viscosity": eta.as_ref().map_or(Value::Null, |e| num(e.0)),
        "viscosity_source": eta.as_ref().map(|e| e.2.clone()),
        "schmidt": sc.map_or(Value::Null, |s| num(s.0)), "schmidt_err": sc.map_or(Value::Null, |s| num(s.1)),
    });
    result(
        py,
        &json,
        &[
            ("t", &r.t),
            ("msd", &r.msd),
            ("msd_err", &err),
            ("msd_fit", &fitline),
        ],
    )
}
