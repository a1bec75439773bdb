//! `mb`, `mb_pdf`: the Maxwell–Boltzmann check (`dpdnl analyze mb`).

use super::*;

/// Speed distribution against Maxwell–Boltzmann (`dpdnl analyze mb`): from `fix ave/histo`
/// files or dumps with velocities (`files`), or from `speeds` (a list of 1-D arrays of
/// speeds, one per frame or block).
#[pyfunction]
#[pyo3(signature = (files = None, *, temp, mass = 1.0, dim = None, bins = 150, vmax = None, from_step = 0, speeds = None))]
#[allow(clippy::too_many_arguments)]
pub(super) fn mb<'py>(
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
                    let (v, d) = in_name(&name, amb::frame_speeds(fr, dim))?;
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
pub(super) fn mb_pdf<'py>(
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
