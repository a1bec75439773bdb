//! `analyze nemd`: the PeX (reverse NEMD) viscosity from the profiles of a `fix ave/chunk` file
//! and the stress, nominal or measured from the pushed momentum.

use super::{Table, in_name, only_column};
use crate::analysis::formats::{Series, parse_ave_chunk};
use crate::analysis::nemd::{self, NemdColumns, NemdOptions, NemdReport, Profiles};
use serde_json::{Value, json};

/// The parameters of `analyze nemd`.
pub struct NemdParams {
    /// Box lengths Lx Ly Lz.
    pub r#box: [f64; 3],
    /// Lower x bound (default: from the bins, if they tile [xlo, xlo + Lx)).
    pub xlo: Option<f64>,
    pub dt: f64,
    /// Momentum per push (the nominal stress) and steps between pushes.
    pub dp: Option<f64>,
    pub every: u64,
    /// Column of the pushed total (default: the only one starting with f_).
    pub push_col: Option<String>,
    /// Only outputs at or after this step.
    pub from: u64,
    pub fit_fraction: f64,
    pub vz_col: String,
    pub density_col: String,
    pub td_col: String,
}

/// The profiles read and the box placed: the first half of the analysis, before the pushed
/// momentum is read.
pub struct NemdProfiles {
    pub name: String,
    pub profiles: Profiles,
    pub xlo: f64,
}

/// Reads the profiles of `text` (input `name`) and finds xlo.
pub fn profiles(name: &str, text: &str, p: &NemdParams) -> Result<NemdProfiles, String> {
    let chunk = in_name(name, parse_ave_chunk(text))?;
    let [lx, ly, lz] = p.r#box;
    let cols = NemdColumns {
        x: "Coord1".into(),
        vz: p.vz_col.clone(),
        density: p.density_col.clone(),
        td: p.td_col.clone(),
    };
    let prof = in_name(
        name,
        nemd::profiles_from_chunk(&chunk, &cols, p.from, ly * lz),
    )?;
    let xlo = match p.xlo {
        Some(x) => x,
        None => {
            let n = prof.x.len();
            let dx = (prof.x[n - 1] - prof.x[0]) / (n - 1) as f64;
            if ((n as f64) * dx - lx).abs() > 1e-4 * lx {
                return Err(format!(
                    "{name}: the {n} bins (width {dx}) do not tile Lx = {lx}; give --xlo"
                ));
            }
            prof.x[0] - 0.5 * dx
        }
    };
    Ok(NemdProfiles {
        name: name.to_string(),
        profiles: prof,
        xlo,
    })
}

/// The result of `analyze nemd`.
pub struct NemdAnalysis {
    pub label: String,
    pub input: String,
    pub r#box: [f64; 3],
    pub xlo: f64,
    pub dt: f64,
    pub from: u64,
    /// Π_xz used, its error and where it came from.
    pub stress: f64,
    pub stress_err: f64,
    pub stress_source: String,
    /// The nominal stress (with `dp`), and whether a pushed total was given too.
    pub stress_nominal: Option<f64>,
    pub measured: bool,
    pub density_source: String,
    pub td_source: Option<String>,
    pub result: NemdReport,
}

/// Π_xz from the pushed total of `push` (input name, series), or nominal; then the fits.
pub fn analyze(
    prof: NemdProfiles,
    push: Option<(String, Series)>,
    p: &NemdParams,
    label: String,
) -> Result<NemdAnalysis, String> {
    let [_, ly, lz] = p.r#box;
    let nominal =
        p.dp.map(|dp| nemd::pex_stress_nominal(dp, p.every, p.dt, ly, lz));
    let pr = &prof.profiles;
    let measured = match push {
        Some((name, s)) => {
            let name = name.as_str();
            let s = s.from_step(p.from);
            let col = match &p.push_col {
                Some(c) => c.clone(),
                None => only_column(name, &s, "the pushed-momentum column", "--push-col", |c| {
                    c.starts_with("f_")
                })?,
            };
            let values = in_name(name, s.column(&col))?;
            let last_step = pr.steps[pr.steps.len() - 1] as f64;
            let (last, steps): (Vec<f64>, Vec<f64>) = values
                .iter()
                .zip(&s.steps)
                .filter(|(_, k)| **k <= last_step)
                .map(|(v, k)| (*v, *k))
                .unzip();
            let st = nemd::pex_stress_from_total(&steps, &last, p.dt, ly, lz);
            Some((in_name(name, st)?, col))
        }
        None => None,
    };
    let (stress, stress_err, stress_source) = match (&measured, nominal) {
        (Some(((s, e), name)), _) => (*s, *e, format!("measured from {name}")),
        (None, Some(s)) => (s, 0.0, "nominal dp/(2 Ly Lz every dt)".to_string()),
        (None, None) => return Err("give --dp (nominal stress) or --push (measured)".into()),
    };
    let o = NemdOptions {
        xlo: prof.xlo,
        lx: p.r#box[0],
        stress,
        stress_err,
        fit_fraction: p.fit_fraction,
    };
    let result = nemd::analyze(pr, &o)?;
    Ok(NemdAnalysis {
        label,
        input: prof.name,
        r#box: p.r#box,
        xlo: prof.xlo,
        dt: p.dt,
        from: p.from,
        stress,
        stress_err,
        stress_source,
        stress_nominal: nominal,
        measured: measured.is_some(),
        density_source: prof.profiles.density_source,
        td_source: prof.profiles.td_source,
        result,
    })
}

impl NemdAnalysis {
    /// The object of `PREFIX.json`.
    pub fn json(&self) -> Value {
        let r = &self.result;
        let halves: Vec<Value> = r
            .halves
            .iter()
            .map(|h| {
                json!({
                    "name": h.name, "window": [h.window.0, h.window.1], "bins": h.bins.len(),
                    "slope": h.slope.mean, "slope_err": h.slope.stderr,
                    "slope_fit_mean_profile": h.fit.slope, "slope_fit_err_regression": h.fit.slope_err,
                    "intercept": h.fit.intercept, "r2": h.fit.r2,
                })
            })
            .collect();
        json!({
            "analysis": "nemd", "label": self.label, "input": self.input,
            "box": self.r#box, "xlo": self.xlo, "dt": self.dt, "from_step": self.from,
            "n_outputs": r.n_outputs, "first_step": r.first_step, "last_step": r.last_step,
            "fit_fraction": r.fit_fraction, "halves": halves,
            "stress": self.stress, "stress_err": self.stress_err, "stress_source": self.stress_source,
            "stress_nominal": self.stress_nominal,
            "shear_rate": r.shear_rate.mean, "shear_rate_err": r.shear_rate.stderr,
            "shear_rate_blocks": r.shear_rate.n_blocks, "shear_rate_converged": r.shear_rate.converged,
            "shear_rate_n_eff": r.shear_rate.n_eff,
            "viscosity": r.viscosity, "viscosity_err": r.viscosity_err,
            "density_centre": r.density_centre.mean, "density_centre_err": r.density_centre.stderr,
            "td_centre": r.td_centre.map(|t| t.mean),
            "td_centre_err": r.td_centre.map(|t| t.stderr),
            "density_source": self.density_source, "td_source": self.td_source,
        })
    }

    /// The fitted line of each half at its bins, NaN elsewhere.
    pub fn fit_line(&self) -> Vec<f64> {
        let r = &self.result;
        (0..r.x.len())
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
            .collect()
    }

    /// The columns of `PREFIX.csv` (T_d as NaN without its column).
    pub fn table(&self) -> Table {
        let r = &self.result;
        let nan = vec![f64::NAN; r.x.len()];
        let (td_m, td_e) =
            r.td.as_ref()
                .map_or((nan.clone(), nan), |t| (t.mean.clone(), t.err.clone()));
        vec![
            ("x", r.x.clone()),
            ("vz", r.vz.mean.clone()),
            ("vz_err", r.vz.err.clone()),
            ("vz_fit", self.fit_line()),
            ("td", td_m),
            ("td_err", td_e),
            ("density", r.density.mean.clone()),
            ("density_err", r.density.err.clone()),
        ]
    }
}
