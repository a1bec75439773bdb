//! `couette`, `flowcurve`: Couette viscosity and the flow curve (`dpdnl analyze couette`, `flowcurve`).

use super::*;

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
    let s = s.from_step(from_step);
    let cname = match &col {
        Some(c) => c.clone(),
        None if s.column_index("pxy").is_some() => "pxy".into(),
        None => s
            .indexed_columns(&[4])
            .map(|v| v[0].clone())
            .ok_or_else(|| {
                aerr(format!(
                    "{name}: no pxy column (columns: {}); give --col",
                    s.columns.join(" ")
                ))
            })?,
    };
    let pxy = in_name(&name, s.column(&cname))?;
    let prof = match &profile {
        Some(p) => {
            let pname = p.display().to_string();
            let chunk = in_name(&pname, parse_ave_chunk(&read_text(p)?))?;
            if !is_pos(y_scale) {
                return Err(aerr(format!("--y-scale must be positive (got {y_scale})")));
            }
            let mut r = in_name(
                &pname,
                acouette::rate_from_profile(&chunk, y_col, v_col, from_step),
            )?;
            r.y.iter_mut().for_each(|y| *y *= y_scale);
            r.rate.mean /= y_scale;
            r.rate.stderr /= y_scale;
            Some(r)
        }
        None => None,
    };
    let (g, g_err, g_source) = match (&prof, rate) {
        (Some(p), _) => (
            p.rate.mean,
            p.rate.stderr,
            "measured from the profile".to_string(),
        ),
        (None, Some(g)) => (g, 0.0, "imposed".to_string()),
        (None, None) => {
            return Err(aerr("give --rate (imposed) or --profile (measured)".into()));
        }
    };
    let r = acouette::analyze(pxy, g, g_err).map_err(aerr)?;
    let label = label.unwrap_or_else(|| match source.extract::<PathBuf>() {
        Ok(p) if source.cast::<PyMapping>().is_err() => stem(&p, "couette"),
        _ => "couette".into(),
    });
    let mut running = Vec::with_capacity(pxy.len());
    let mut acc = 0.0;
    for (k, v) in pxy.iter().enumerate() {
        acc += v;
        running.push(acc / (k + 1) as f64);
    }
    let json = json!({
        "analysis": "couette", "label": label, "input": name, "column": cname,
        "n_samples": r.n_samples, "from_step": from_step,
        "pxy": num(r.pxy.mean), "pxy_err": num(r.pxy.stderr),
        "shear_rate": num(g), "shear_rate_err": num(g_err), "shear_rate_source": g_source,
        "shear_rate_imposed": rate.map_or(Value::Null, num),
        "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
    });
    let steps = s.steps.clone();
    let out = result(
        py,
        &json,
        &[
            ("step", &steps),
            ("pxy", pxy),
            ("pxy_running_mean", &running),
        ],
    )?;
    if let Some(p) = &prof {
        let fit: Vec<f64> = p.y.iter().map(|y| p.rate.mean * y + p.intercept).collect();
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

/// (shear rate, viscosity, its error).
type FlowPoint = (f64, f64, f64);

/// Viscosity against shear rate (`dpdnl analyze flowcurve`) from results of `nemd`/`couette`
/// (dicts, or their JSON files) or CSV files with columns label,rate,eta,eta_err: the points
/// grouped by label and sorted by rate, and the CSV text the CLI writes.
#[pyfunction]
pub(super) fn flowcurve<'py>(
    py: Python<'py>,
    results: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let mut groups: Vec<(String, Vec<FlowPoint>)> = Vec::new();
    let mut add = |label: String, p: FlowPoint| match groups.iter_mut().find(|g| g.0 == label) {
        Some(g) => g.1.push(p),
        None => groups.push((label, vec![p])),
    };
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
            add(label, (get("shear_rate")?.abs(), get("viscosity")?, err));
            continue;
        }
        let f: PathBuf = item.extract()?;
        let name = f.display().to_string();
        let text = read_text(&f)?;
        if text.trim_start().starts_with('{') {
            let v: Value = serde_json::from_str(&text).map_err(|e| aerr(format!("{name}: {e}")))?;
            let get = |k: &str| {
                v[k].as_f64()
                    .ok_or_else(|| aerr(format!("{name}: no number '{k}'")))
            };
            let label = v["label"].as_str().unwrap_or("result").to_string();
            add(
                label,
                (
                    get("shear_rate")?.abs(),
                    get("viscosity")?,
                    v["viscosity_err"].as_f64().unwrap_or(0.0),
                ),
            );
        } else {
            let mut lines = text
                .lines()
                .enumerate()
                .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
            let (_, header) = lines
                .next()
                .ok_or_else(|| aerr(format!("{name}: empty CSV")))?;
            let cols: Vec<&str> = header.split(',').map(str::trim).collect();
            let idx = |n: &str| {
                cols.iter().position(|c| *c == n).ok_or_else(|| {
                    aerr(format!(
                        "{name}: line 1: the CSV header has no '{n}' column"
                    ))
                })
            };
            let (jl, jr, je, jerr) = (
                idx("label")?,
                idx("rate")?,
                idx("eta")?,
                idx("eta_err").ok(),
            );
            for (i, l) in lines {
                let t: Vec<&str> = l.split(',').map(str::trim).collect();
                let val = |j: usize| -> PyResult<f64> {
                    let tok = t.get(j).copied().unwrap_or("");
                    tok.parse().map_err(|_| {
                        aerr(format!(
                            "{name}: line {}: cannot read '{tok}' as a number",
                            i + 1
                        ))
                    })
                };
                let label = t.get(jl).copied().unwrap_or("").to_string();
                let e = match jerr {
                    Some(j) => val(j)?,
                    None => 0.0,
                };
                add(label, (val(jr)?.abs(), val(je)?, e));
            }
        }
    }
    let mut csv = String::from("label,rate,eta,eta_err\n");
    let out_groups = pyo3::types::PyList::empty(py);
    for (label, pts) in &mut groups {
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (r, e, err) in pts.iter() {
            csv.push_str(&format!("{label},{r},{e},{err}\n"));
        }
        let g = PyDict::new(py);
        g.set_item("label", label.as_str())?;
        let col = |k: usize| -> Vec<f64> {
            pts.iter()
                .map(|p| match k {
                    0 => p.0,
                    1 => p.1,
                    _ => p.2,
                })
                .collect()
        };
        g.set_item("rate", arr(py, &col(0)))?;
        g.set_item("eta", arr(py, &col(1)))?;
        g.set_item("eta_err", arr(py, &col(2)))?;
        out_groups.append(g)?;
    }
    let d = PyDict::new(py);
    d.set_item("analysis", "flowcurve")?;
    d.set_item("groups", out_groups)?;
    d.set_item("csv", csv)?;
    Ok(d.into_any())
}
