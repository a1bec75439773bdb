//! `nemd`: reverse NEMD with the PeX push (`dpdnl analyze nemd`).

use super::*;

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
    let chunk = in_name(&pname, parse_ave_chunk(&read_text(&profile)?))?;
    let [lx, ly, lz] = r#box;
    let cols = anemd::NemdColumns {
        x: "Coord1".into(),
        vz: vz_col.into(),
        density: density_col.into(),
        td: td_col.into(),
    };
    let prof = in_name(
        &pname,
        anemd::profiles_from_chunk(&chunk, &cols, from_step, ly * lz),
    )?;
    let xlo = match xlo {
        Some(x) => x,
        None => {
            let n = prof.x.len();
            let dx = (prof.x[n - 1] - prof.x[0]) / (n - 1) as f64;
            if ((n as f64) * dx - lx).abs() > 1e-4 * lx {
                return Err(aerr(format!(
                    "{pname}: the {n} bins (width {dx}) do not tile Lx = {lx}; give --xlo"
                )));
            }
            prof.x[0] - 0.5 * dx
        }
    };
    let nominal = dp.map(|dp| anemd::pex_stress_nominal(dp, every, dt, ly, lz));
    let measured = match &push {
        Some(p) => {
            let (s, name) = series_arg(p)?;
            let s = s.from_step(from_step);
            let col = match &push_col {
                Some(c) => c.clone(),
                None => {
                    let f: Vec<&String> =
                        s.columns.iter().filter(|c| c.starts_with("f_")).collect();
                    match f.as_slice() {
                        [one] => (*one).clone(),
                        _ => {
                            return Err(aerr(format!(
                                "{name}: cannot tell the pushed-momentum column (columns: {}); give --push-col",
                                s.columns.join(" ")
                            )));
                        }
                    }
                }
            };
            let values = in_name(&name, s.column(&col))?;
            let last_step = prof.steps[prof.steps.len() - 1] as f64;
            let (last, steps): (Vec<f64>, Vec<f64>) = values
                .iter()
                .zip(&s.steps)
                .filter(|(_, k)| **k <= last_step)
                .map(|(v, k)| (*v, *k))
                .unzip();
            Some((
                in_name(
                    &name,
                    anemd::pex_stress_from_total(&steps, &last, dt, ly, lz),
                )?,
                col,
            ))
        }
        None => None,
    };
    let (stress, stress_err, stress_source) = match (&measured, nominal) {
        (Some(((s, e), name)), _) => (*s, *e, format!("measured from {name}")),
        (None, Some(s)) => (s, 0.0, "nominal dp/(2 Ly Lz every dt)".to_string()),
        (None, None) => {
            return Err(aerr(
                "give --dp (nominal stress) or --push (measured)".into(),
            ));
        }
    };
    let o = anemd::NemdOptions {
        xlo,
        lx,
        stress,
        stress_err,
        fit_fraction,
    };
    let r = anemd::analyze(&prof, &o).map_err(aerr)?;
    let label = label.unwrap_or_else(|| stem(&profile, "nemd"));
    let nan = vec![f64::NAN; r.x.len()];
    let fitline: Vec<f64> = (0..r.x.len())
        .map(|i| {
            r.halves
                .iter()
                .find_map(|h| {
                    h.bins
                        .iter()
                        .position(|&b| b == i)
                        .map(|k| h.fit.slope * h.x[k] + h.fit.intercept)
                })
                .unwrap_or(f64::NAN)
        })
        .collect();
    let (td_m, td_e) = r.td.as_ref().map_or((nan.clone(), nan.clone()), |t| {
        (t.mean.clone(), t.err.clone())
    });
    let halves: Vec<Value> = r
        .halves
        .iter()
        .map(|h| {
            json!({
                "name": h.name, "window": [num(h.window.0), num(h.window.1)], "bins": h.bins.len(),
                "slope": num(h.slope.mean), "slope_err": num(h.slope.stderr),
                "slope_fit_mean_profile": num(h.fit.slope), "slope_fit_err_regression": num(h.fit.slope_err),
                "intercept": num(h.fit.intercept), "r2": num(h.fit.r2),
            })
        })
        .collect();
    let json = json!({
        "analysis": "nemd", "label": label, "input": pname,
        "box": [lx, ly, lz], "xlo": xlo, "dt": dt, "from_step": from_step,
        "n_outputs": r.n_outputs, "first_step": r.first_step, "last_step": r.last_step,
        "fit_fraction": r.fit_fraction, "halves": halves,
        "stress": num(stress), "stress_err": num(stress_err), "stress_source": stress_source,
        "stress_nominal": nominal.map_or(Value::Null, num),
        "shear_rate": num(r.shear_rate.mean), "shear_rate_err": num(r.shear_rate.stderr),
        "shear_rate_blocks": r.shear_rate.n_blocks, "shear_rate_converged": r.shear_rate.converged,
        "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
        "density_centre": num(r.density_centre.mean), "density_centre_err": num(r.density_centre.stderr),
        "td_centre": r.td_centre.map_or(Value::Null, |t| num(t.mean)),
        "td_centre_err": r.td_centre.map_or(Value::Null, |t| num(t.stderr)),
        "density_source": prof.density_source, "td_source": prof.td_source,
    });
    result(
        py,
        &json,
        &[
            ("x", &r.x),
            ("vz", &r.vz.mean),
            ("vz_err", &r.vz.err),
            ("vz_fit", &fitline),
            ("td", &td_m),
            ("td_err", &td_e),
            ("density", &r.density.mean),
            ("density_err", &r.density.err),
        ],
    )
}
