//! `dpdnl analyze` from Python: the same steps as `src/bin/dpdnl/analyze/` (which file kind,
//! which columns, which window), calling the same `dpdnl::analysis` functions, returning the
//! dict that the CLI writes to `PREFIX.json` plus `"table"`: the columns of `PREFIX.csv` as
//! arrays. No files are written and nothing is plotted. Inputs are paths, or for time series
//! a dict `{"Step": steps, column: values, …}` (`read_series`, `Simulation.thermo[k]`).
//!
//! Keep in step with the CLI (`run_mb` in maxwell.rs, `run_nemd` in pex.rs, `run_eh` and
//! `run_msd` in transport.rs, `run_couette` and `run_flow` in shear.rs, the helpers in
//! mod.rs): python/tests/test_analysis.py compares each result with the
//! CLI's JSON on the same input.

use crate::{AnalysisError, arr, json_to_py, read_text};
use dpdnl::analysis::formats::{
    FileKind, Series, detect, parse_ave_chunk, parse_ave_histo, parse_series,
};
use dpdnl::analysis::is_pos;
use dpdnl::analysis::{couette as acouette, eh as aeh, mb as amb, msd as amsd, nemd as anemd};
use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping, PyString};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn aerr(e: String) -> PyErr {
    AnalysisError::new_err(e)
}

/// A number for JSON: non-finite values become null (as the CLI's `num`).
fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn nums(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|x| num(*x)).collect())
}

/// The result: the JSON object as a dict, with `table` (CSV columns as arrays) added.
fn result<'py>(
    py: Python<'py>,
    json: &Value,
    table: &[(&str, &[f64])],
) -> PyResult<Bound<'py, PyAny>> {
    let d = json_to_py(py, json)?;
    let t = PyDict::new(py);
    for (name, col) in table {
        t.set_item(*name, arr(py, col))?;
    }
    d.set_item("table", t)?;
    Ok(d)
}

/// A 1-D float64 vector from any array-like (NumPy array, list).
pub(crate) fn f64_vec(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let np = obj.py().import("numpy")?;
    let a = np
        .call_method1("ascontiguousarray", (obj, "float64"))
        .and_then(|a| a.extract::<PyReadonlyArray1<'_, f64>>())
        .map_err(|_| PyTypeError::new_err(format!("{what}: expected a 1-D array of numbers")))?;
    Ok(a.as_array().to_vec())
}

/// A time series given as a path or as a mapping name → 1-D array with a `Step` (or
/// `TimeStep`, `steps`) entry. Returns the series and its name for messages.
fn series_arg(obj: &Bound<'_, PyAny>) -> PyResult<(Series, String)> {
    if let Ok(m) = obj.cast::<PyMapping>() {
        let mut steps: Option<Vec<f64>> = None;
        let mut columns = Vec::new();
        let mut data = Vec::new();
        for item in m.items()?.iter() {
            let (k, v): (String, Bound<'_, PyAny>) = item.extract()?;
            let v = f64_vec(&v, &format!("series column '{k}'"))?;
            if steps.is_none() && matches!(k.as_str(), "Step" | "TimeStep" | "steps" | "step") {
                steps = Some(v);
            } else {
                columns.push(k);
                data.push(v);
            }
        }
        let steps = steps.ok_or_else(|| {
            aerr(format!(
                "<series>: no 'Step' entry (keys: {})",
                columns.join(" ")
            ))
        })?;
        if let Some((c, _)) = columns
            .iter()
            .zip(&data)
            .find(|(_, d)| d.len() != steps.len())
        {
            return Err(aerr(format!(
                "<series>: column '{c}' does not have one value per step ({} steps)",
                steps.len()
            )));
        }
        return Ok((
            Series {
                columns,
                steps,
                data,
            },
            "<series>".to_string(),
        ));
    }
    let p: PathBuf = obj.extract().map_err(|_| {
        PyTypeError::new_err("expected a path or a dict {'Step': steps, column: values, …}")
    })?;
    let name = p.display().to_string();
    let s = in_name(&name, parse_series(&read_text(&p)?))?;
    Ok((s, name))
}

fn in_name<T>(name: &str, r: Result<T, String>) -> PyResult<T> {
    r.map_err(|e| aerr(format!("{name}: {e}")))
}

/// Keeps the rows of a series at or after `from` (analyze/mod.rs `series_from`).
fn series_from(s: Series, from: u64) -> Series {
    let keep: Vec<bool> = s.steps.iter().map(|&k| k >= from as f64).collect();
    let pick = |v: &Vec<f64>| -> Vec<f64> {
        v.iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(x, _)| *x)
            .collect()
    };
    Series {
        steps: pick(&s.steps),
        data: s.data.iter().map(pick).collect(),
        columns: s.columns,
    }
}

/// The uniform step spacing of a series (analyze/mod.rs `step_spacing`).
fn step_spacing(steps: &[f64], name: &str) -> PyResult<f64> {
    if steps.len() < 2 {
        return Err(aerr(format!("{name}: fewer than two samples")));
    }
    let d = steps[1] - steps[0];
    if let Some(k) = steps.windows(2).position(|w| w[1] - w[0] != d) {
        return Err(aerr(format!(
            "{name}: samples are not equally spaced (step {} after {}, spacing {d} before)",
            steps[k + 1],
            steps[k]
        )));
    }
    if d <= 0.0 {
        return Err(aerr(format!("{name}: steps do not increase")));
    }
    Ok(d)
}

/// Columns `c_X[i]` for the given indices, for one X that has them all.
fn indexed_columns(s: &Series, idx: &[usize]) -> Option<Vec<String>> {
    for c in &s.columns {
        if let Some(base) = c.strip_suffix(&format!("[{}]", idx[0])) {
            let names: Vec<String> = idx.iter().map(|i| format!("{base}[{i}]")).collect();
            if names.iter().all(|n| s.column_index(n).is_some()) {
                return Some(names);
            }
        }
    }
    None
}

fn paths(obj: &Bound<'_, PyAny>) -> PyResult<Vec<PathBuf>> {
    if obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__")? {
        return Ok(vec![obj.extract()?]);
    }
    obj.try_iter()?
        .map(|p| p.and_then(|p| p.extract::<PathBuf>()))
        .collect()
}

fn stem(p: &Path, default: &str) -> String {
    p.file_stem()
        .map_or(default.into(), |s| s.to_string_lossy().into_owned())
}

// ---------------------------------------------------------------- mb

/// Speeds of one dump frame, and the dimension (given, or 2 when vz is absent or all 0).
fn frame_speeds(f: &DumpFrame, dim: Option<usize>) -> Result<(Vec<f64>, usize), String> {
    let col = |n: &str| f.columns.iter().position(|c| c == n);
    let (jx, jy) = match (col("vx"), col("vy")) {
        (Some(x), Some(y)) => (x, y),
        _ => {
            return Err(format!(
                "step {}: the dump needs vx vy [vz] columns (has {})",
                f.step,
                f.columns.join(" ")
            ));
        }
    };
    let jz = col("vz");
    let d = dim.unwrap_or(match jz {
        Some(j) if f.rows.iter().any(|r| r[j] != 0.0) => 3,
        _ => 2,
    });
    if d == 3 && jz.is_none() {
        return Err(format!("step {}: --dim 3 needs a vz column", f.step));
    }
    Ok((
        f.rows
            .iter()
            .map(|r| {
                let mut s = r[jx] * r[jx] + r[jy] * r[jy];
                if d == 3
                    && let Some(j) = jz
                {
                    s += r[j] * r[j];
                }
                s.sqrt()
            })
            .collect(),
        d,
    ))
}

/// Speed distribution against Maxwell–Boltzmann (`dpdnl analyze mb`): from `fix ave/histo`
/// files or dumps with velocities (`files`), or from `speeds` (a list of 1-D arrays of
/// speeds, one per frame or block).
#[pyfunction]
#[pyo3(signature = (files = None, *, temp, mass = 1.0, dim = None, bins = 150, vmax = None, from_step = 0, speeds = None))]
#[allow(clippy::too_many_arguments)]
fn mb<'py>(
    py: Python<'py>,
    files: Option<Bound<'py, PyAny>>,
    temp: f64,
    mass: f64,
    dim: Option<usize>,
    bins: usize,
    vmax: Option<f64>,
    from_step: u64,
    speeds: Option<Vec<Bound<'py, PyAny>>>,
) -> PyResult<Bound<'py, PyAny>> {
    let files = match &files {
        Some(f) => paths(f)?,
        None => Vec::new(),
    };
    let mut hist: Option<amb::SpeedHistogram> = None;
    let mut dim = dim;
    let mut samples: Vec<Vec<f64>> = Vec::new();
    for f in &files {
        let name = f.display().to_string();
        let text = read_text(f)?;
        match detect(&text) {
            FileKind::AveHisto => {
                let h = in_name(&name, parse_ave_histo(&text))?;
                let h = in_name(&name, amb::SpeedHistogram::from_ave_histo(&h, from_step))?;
                hist = Some(match hist {
                    None => h,
                    Some(mut acc) => {
                        if acc.edges != h.edges {
                            return Err(aerr(format!(
                                "{name}: bins differ from those of the first histogram file"
                            )));
                        }
                        for (x, y) in acc.counts.iter_mut().zip(&h.counts) {
                            *x += y;
                        }
                        acc.outside += h.outside;
                        acc.blocks.extend(h.blocks);
                        acc.note = format!("{}; + {}", acc.note, h.note);
                        acc
                    }
                });
            }
            FileKind::Dump => {
                let frames = in_name(&name, parse_dump(&text))?;
                for fr in frames.iter().filter(|fr| fr.step >= from_step) {
                    let (v, d) = in_name(&name, frame_speeds(fr, dim))?;
                    dim.get_or_insert(d);
                    samples.push(v);
                }
            }
            other => {
                return Err(aerr(format!(
                    "{name}: expected a fix ave/histo file or a dump, found {other:?}"
                )));
            }
        }
    }
    let mut inputs: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    if let Some(sp) = &speeds {
        if !files.is_empty() {
            return Err(aerr("give either files or speeds, not both".into()));
        }
        samples = sp
            .iter()
            .map(|a| f64_vec(a, "speeds"))
            .collect::<PyResult<_>>()?;
        inputs.push("<speeds>".into());
    }
    let dim = dim.unwrap_or(3);
    let vmax = vmax.unwrap_or(2.0 * (10.0 * temp / mass).sqrt());
    if !samples.is_empty() {
        if hist.is_some() {
            return Err(aerr(
                "give either fix ave/histo files or dumps, not both".into(),
            ));
        }
        if bins == 0 || !is_pos(vmax) {
            return Err(aerr("--bins and --vmax must be positive".into()));
        }
        hist = Some(
            amb::SpeedHistogram::from_samples(&samples, amb::uniform_edges(0.0, vmax, bins))
                .map_err(aerr)?,
        );
    }
    let h = hist.ok_or_else(|| aerr("no histogram or dump frame to analyse".into()))?;
    let o = amb::MbOptions {
        kt: temp,
        mass,
        dim,
        min_expected: 5.0,
    };
    let r = amb::analyze(&h, &o).map_err(aerr)?;
    let col = |f: &dyn Fn(&amb::MbBin) -> f64| r.bins.iter().map(f).collect::<Vec<f64>>();
    let lo = col(&|b| b.lo);
    let hi = col(&|b| b.hi);
    let mid = col(&|b| 0.5 * (b.lo + b.hi));
    let count = col(&|b| b.count);
    let pdf = col(&|b| b.pdf);
    let err = col(&|b| b.pdf_err);
    let set = col(&|b| b.pdf_set);
    let fit = col(&|b| b.pdf_fit);
    let expected = col(&|b| b.expected);
    let resid: Vec<f64> = (0..r.bins.len())
        .map(|i| {
            if err[i] > 0.0 {
                (pdf[i] - set[i]) / err[i]
            } else {
                f64::NAN
            }
        })
        .collect();
    let json = json!({
        "analysis": "mb",
        "inputs": inputs,
        "dim": dim, "mass": mass, "kt_set": temp,
        "n_samples": num(r.n_total), "n_blocks": r.n_blocks, "source": h.note,
        "v_lo": num(h.edges[0]), "v_hi": num(h.edges[h.edges.len() - 1]), "bins": r.bins.len(),
        "outside": num(r.outside), "outside_expected": num(r.outside_expected),
        "kt_fit": num(r.kt_fit), "kt_fit_err_iid": num(r.kt_fit_err_iid),
        "kt_fit_err_blocks": r.kt_fit_err_blocks.map_or(Value::Null, num),
        "inefficiency": r.inefficiency.map_or(Value::Null, num),
        "chi2": num(r.chi2), "dof": r.dof, "p_value": num(r.p_value),
        "p_value_corrected": r.p_value_corrected.map_or(Value::Null, num),
        "chi2_fit": num(r.chi2_fit), "dof_fit": r.dof_fit, "p_value_fit": num(r.p_value_fit),
        "ks_d": num(r.ks_d), "ks_p": num(r.ks_p),
    });
    result(
        py,
        &json,
        &[
            ("v_lo", &lo),
            ("v_hi", &hi),
            ("v_mid", &mid),
            ("count", &count),
            ("expected_count", &expected),
            ("pdf", &pdf),
            ("pdf_err", &err),
            ("pdf_mb_set", &set),
            ("pdf_mb_fit", &fit),
            ("residual_sigma", &resid),
        ],
    )
}

/// The Maxwell–Boltzmann speed density P(v) in d dimensions at kT and mass m (the curve the
/// CLI's figure draws), at each speed of `v`.
#[pyfunction]
#[pyo3(signature = (v, temp, *, mass = 1.0, dim = 3))]
fn mb_pdf<'py>(
    py: Python<'py>,
    v: PyReadonlyArray1<'py, f64>,
    temp: f64,
    mass: f64,
    dim: usize,
) -> Bound<'py, numpy::PyArray1<f64>> {
    let out: Vec<f64> = v
        .as_array()
        .iter()
        .map(|&x| amb::mb_pdf(x, temp, mass, dim))
        .collect();
    arr(py, &out)
}

// ---------------------------------------------------------------- nemd

/// Reverse NEMD (PeX push), as `dpdnl analyze nemd`: profiles from a `fix ave/chunk` file,
/// fits, Π_xz (eq. 55; nominal from `dp`, or measured from the pushed total in `push`),
/// viscosity (eq. 56) and T_d (eq. 58).
#[pyfunction]
#[pyo3(signature = (profile, *, r#box, dt, xlo = None, dp = None, every = 1, push = None, push_col = None, from_step = 0, fit_fraction = 0.5, vz_col = "vz", density_col = "density/number", td_col = "v_td", label = None))]
#[allow(clippy::too_many_arguments)]
fn nemd<'py>(
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
            let s = series_from(s, from_step);
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

// ---------------------------------------------------------------- eh

/// Einstein–Helfand viscosity (eq. 59), as `dpdnl analyze eh`, from off-diagonal pressure
/// series: a scalar-mode `fix ave/time` file, a log, or a series dict (e.g.
/// `Simulation.thermo[-1]`).
#[pyfunction]
#[pyo3(signature = (source, *, dt, r#box, temp, density, mass = 1.0, cols = None, from_step = 0, window_factor = 0.1, tmin = None, tmax = None, blocks = 10))]
#[allow(clippy::too_many_arguments)]
fn eh<'py>(
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
    let s = series_from(s, from_step);
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
            } else if let Some(v) = indexed_columns(&s, if dim == 2 { &[4] } else { &[4, 5, 6] }) {
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
    let spacing = step_spacing(&s.steps, &name)?;
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
fn msd<'py>(
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
        let spacing = step_spacing(&st, &name)?;
        let mut r = in_name(
            &name,
            amsd::from_trajectories(&series, dim, spacing * dt, &o),
        )?;
        r.method = format!("{} ({note})", r.method);
        (r, name)
    } else {
        let (s, name) = series_arg(&source)?;
        let s = series_from(s, from_step);
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

// ---------------------------------------------------------------- couette

/// Couette flow under Lees–Edwards, as `dpdnl analyze couette`: η* = −⟨P_xy⟩ / shear rate,
/// the rate imposed (`rate`) or measured from a `fix ave/chunk` velocity profile (`profile`).
#[pyfunction]
#[pyo3(signature = (source, *, col = None, rate = None, profile = None, v_col = "vx", y_col = "Coord1", y_scale = 1.0, from_step = 0, label = None))]
#[allow(clippy::too_many_arguments)]
fn couette<'py>(
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
    let s = series_from(s, from_step);
    let cname = match &col {
        Some(c) => c.clone(),
        None if s.column_index("pxy").is_some() => "pxy".into(),
        None => indexed_columns(&s, &[4])
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
fn flowcurve<'py>(py: Python<'py>, results: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
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

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(mb, m)?)?;
    m.add_function(wrap_pyfunction!(mb_pdf, m)?)?;
    m.add_function(wrap_pyfunction!(nemd, m)?)?;
    m.add_function(wrap_pyfunction!(eh, m)?)?;
    m.add_function(wrap_pyfunction!(msd, m)?)?;
    m.add_function(wrap_pyfunction!(couette, m)?)?;
    m.add_function(wrap_pyfunction!(flowcurve, m)?)?;
    Ok(())
}
