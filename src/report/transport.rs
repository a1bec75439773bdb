//! `analyze eh` and `analyze msd`: the Einstein–Helfand viscosity and self-diffusion (with the
//! Schmidt number).

use super::{Table, in_name, line_at, only_column};
use crate::analysis::formats::{FileKind, Series, detect, parse_series, step_spacing};
use crate::analysis::{eh, msd};
use crate::io::dump_read::{DumpFrame, parse_dump};
use serde_json::{Value, json};

// ---------------------------------------------------------------- eh

/// The parameters of `analyze eh`.
pub struct EhParams {
    pub dt: f64,
    /// Box lengths: 2 in 2-D, 3 in 3-D.
    pub r#box: Vec<f64>,
    pub temp: f64,
    /// Number density n (ρ = n m).
    pub density: f64,
    pub mass: f64,
    /// Stress columns (default: pxy,pxz,pyz or c_X[4],c_X[5],c_X[6]; only xy in 2-D).
    pub cols: Option<Vec<String>>,
    pub from: u64,
    pub window_factor: f64,
    pub tmin: Option<f64>,
    pub tmax: Option<f64>,
    pub blocks: usize,
}

impl EhParams {
    /// The box must have 2 or 3 lengths.
    pub fn check(&self) -> Result<(), String> {
        if (2..=3).contains(&self.r#box.len()) {
            Ok(())
        } else {
            Err("box: give 2 (2-D) or 3 (3-D) lengths".into())
        }
    }
}

/// The result of `analyze eh`.
pub struct EhAnalysis {
    pub input: String,
    /// The stress columns used.
    pub components: Vec<String>,
    /// Steps between samples.
    pub spacing: f64,
    pub dt: f64,
    pub from: u64,
    pub temp: f64,
    pub options: eh::EhOptions,
    pub volume: f64,
    pub box_len: f64,
    /// The running viscosity drifts over the window by more than 3 standard errors.
    pub not_linear: bool,
    pub result: eh::EhReport,
}

/// The Einstein–Helfand viscosity of the stress columns of `s` (input `name`).
pub fn eh(name: &str, s: Series, p: &EhParams) -> Result<EhAnalysis, String> {
    p.check()?;
    let s = s.from_step(p.from);
    let dim = p.r#box.len();
    let names: Vec<String> = match &p.cols {
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
                return Err(format!(
                    "{name}: cannot find the off-diagonal pressure columns (columns: {}); give --cols",
                    s.columns.join(" ")
                ));
            }
        }
    };
    let comps: Vec<&[f64]> = names
        .iter()
        .map(|n| in_name(name, s.column(n)))
        .collect::<Result<_, _>>()?;
    let spacing = in_name(name, step_spacing(&s.steps))?;
    let volume: f64 = p.r#box.iter().product();
    let box_len = p.r#box.iter().copied().fold(f64::INFINITY, f64::min);
    let mut o = eh::EhOptions::new(spacing * p.dt, volume, p.temp, box_len, p.density * p.mass);
    o.window_factor = p.window_factor;
    o.t_min = p.tmin;
    o.t_max = p.tmax;
    o.n_blocks = p.blocks;
    let r = in_name(name, eh::analyze(&comps, &o))?;
    // Significant at 3 standard errors: the fitted slope is then biased beyond its error.
    let not_linear =
        r.drift.is_finite() && r.drift_err.is_finite() && r.drift.abs() > 3.0 * r.drift_err;
    Ok(EhAnalysis {
        input: name.to_string(),
        components: names,
        spacing,
        dt: p.dt,
        from: p.from,
        temp: p.temp,
        options: o,
        volume,
        box_len,
        not_linear,
        result: r,
    })
}

impl EhAnalysis {
    /// The object of `PREFIX.json`.
    pub fn json(&self) -> Value {
        let r = &self.result;
        json!({
            "analysis": "eh", "input": self.input, "components": self.components,
            "dt": self.dt, "sample_interval": self.options.dt_sample, "n_samples": r.n_samples,
            "from_step": self.from,
            "volume": self.volume, "kt": self.temp, "box_len": self.box_len,
            "mass_density": self.options.mass_density,
            "t_min": r.t_min, "t_max": r.t_max, "tau_l": r.tau_l,
            "window_source": r.window_source, "window_capped": r.capped,
            "viscosity": r.viscosity, "viscosity_err": r.viscosity_err,
            "per_component": r.per_component, "blocks": r.blocks,
            "window_drift": r.drift, "window_drift_err": r.drift_err,
            "window_not_linear": self.not_linear,
            "slope": r.fit.slope, "intercept": r.fit.intercept,
        })
    }

    /// The fitted line at every lag.
    pub fn fit_line(&self) -> Vec<f64> {
        let r = &self.result;
        line_at(&r.t, r.fit.slope, r.fit.intercept)
    }

    /// The columns of `PREFIX.csv`.
    pub fn table(&self) -> Table {
        let r = &self.result;
        vec![
            ("t", r.t.clone()),
            ("msd_integral", r.msd.clone()),
            ("mu_running", r.running.clone()),
            ("msd_fit", self.fit_line()),
        ]
    }
}

// ---------------------------------------------------------------- msd

/// What `analyze msd` reads: dump frames with unwrapped positions, or a series with an MSD
/// column.
pub enum MsdSource {
    Dump(Vec<DumpFrame>),
    Series(Series),
}

impl MsdSource {
    /// A dump (by its first line) or else a series, from the text of input `name`.
    pub fn from_text(name: &str, text: &str) -> Result<MsdSource, String> {
        if detect(text) == FileKind::Dump {
            Ok(MsdSource::Dump(in_name(name, parse_dump(text))?))
        } else {
            Ok(MsdSource::Series(in_name(name, parse_series(text))?))
        }
    }
}

/// The parameters of `analyze msd`.
pub struct MsdParams {
    pub dt: f64,
    pub dim: usize,
    /// MSD column of a series (default: the only one named like c_*[4] or msd).
    pub col: Option<String>,
    /// Number of atoms (series): the Brownian error estimate.
    pub atoms: Option<usize>,
    pub tmin: Option<f64>,
    pub tmax: Option<f64>,
    pub from: u64,
}

/// A viscosity for the Schmidt number: value, error and where it came from.
pub type Viscosity = (f64, f64, String);

/// The viscosity of a result of `analyze eh`/`nemd` (input `name`): its `viscosity` (required)
/// and `viscosity_err` (default 0).
pub fn viscosity_of(name: &str, v: &Value) -> Result<Viscosity, String> {
    let mu = v["viscosity"]
        .as_f64()
        .ok_or_else(|| format!("{name}: no 'viscosity' number"))?;
    Ok((
        mu,
        v["viscosity_err"].as_f64().unwrap_or(0.0),
        name.to_string(),
    ))
}

/// The same from the JSON text of such a result.
pub fn viscosity_from_text(name: &str, text: &str) -> Result<Viscosity, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("{name}: {e}"))?;
    viscosity_of(name, &v)
}

/// The result of `analyze msd`.
pub struct MsdAnalysis {
    pub input: String,
    pub dim: usize,
    pub dt: f64,
    pub result: msd::MsdReport,
    /// The viscosity given and the Schmidt number with its error ([`MsdAnalysis::schmidt`]).
    pub viscosity: Option<Viscosity>,
    pub schmidt: Option<(f64, f64)>,
}

/// The diffusion coefficient from `src` (input `name`).
pub fn msd(name: &str, src: MsdSource, p: &MsdParams) -> Result<MsdAnalysis, String> {
    let mut o = msd::MsdOptions::new(p.dim);
    o.t_min = p.tmin;
    o.t_max = p.tmax;
    let r = match src {
        MsdSource::Dump(frames) => {
            let frames: Vec<DumpFrame> = frames.into_iter().filter(|f| f.step >= p.from).collect();
            let (steps, series, note) = in_name(name, msd::unwrapped_series(&frames, p.dim))?;
            let st: Vec<f64> = steps.iter().map(|&k| k as f64).collect();
            let spacing = in_name(name, step_spacing(&st))?;
            let mut r = in_name(
                name,
                msd::from_trajectories(&series, p.dim, spacing * p.dt, &o),
            )?;
            r.method = format!("{} ({note})", r.method);
            r
        }
        MsdSource::Series(s) => {
            let s = s.from_step(p.from);
            let c = match &p.col {
                Some(c) => c.clone(),
                None => only_column(name, &s, "the MSD column", "--col", |c| {
                    c.ends_with("[4]") || c.eq_ignore_ascii_case("msd")
                })?,
            };
            let m = in_name(name, s.column(&c))?;
            let t: Vec<f64> = s.steps.iter().map(|k| k * p.dt).collect();
            in_name(name, msd::from_series(&t, m, &o, p.atoms))?
        }
    };
    Ok(MsdAnalysis {
        input: name.to_string(),
        dim: p.dim,
        dt: p.dt,
        result: r,
        viscosity: None,
        schmidt: None,
    })
}

impl MsdAnalysis {
    /// Sc = μ/(ρ D) with ρ = n m, when a viscosity is given (which then needs the density).
    pub fn schmidt(
        &mut self,
        eta: Option<Viscosity>,
        density: Option<f64>,
        mass: f64,
    ) -> Result<(), String> {
        let r = &self.result;
        self.schmidt = match (eta.as_ref(), density) {
            (Some((mu, mu_err, _)), Some(n)) => {
                Some(msd::schmidt(*mu, *mu_err, n * mass, r.d, r.d_err))
            }
            (Some(_), None) => return Err("the Schmidt number needs --density".into()),
            _ => None,
        };
        self.viscosity = eta;
        Ok(())
    }

    /// The object of `PREFIX.json`.
    pub fn json(&self) -> Value {
        let r = &self.result;
        let eta = self.viscosity.as_ref();
        json!({
            "analysis": "msd", "input": self.input, "dim": self.dim, "dt": self.dt,
            "method": r.method, "t_min": r.t_min, "t_max": r.t_max,
            "diffusion": r.d, "diffusion_err": r.d_err, "diffusion_err_method": r.d_err_method,
            "diffusion_groups": r.d_groups,
            "viscosity": eta.map(|e| e.0),
            "viscosity_source": eta.map(|e| e.2.clone()),
            "schmidt": self.schmidt.map(|s| s.0), "schmidt_err": self.schmidt.map(|s| s.1),
        })
    }

    /// The fitted line at every lag.
    pub fn fit_line(&self) -> Vec<f64> {
        let r = &self.result;
        line_at(&r.t, r.fit.slope, r.fit.intercept)
    }

    /// The columns of `PREFIX.csv` (the error NaN where there is none).
    pub fn table(&self) -> Table {
        let r = &self.result;
        let err = r
            .msd_err
            .clone()
            .unwrap_or_else(|| vec![f64::NAN; r.t.len()]);
        vec![
            ("t", r.t.clone()),
            ("msd", r.msd.clone()),
            ("msd_err", err),
            ("msd_fit", self.fit_line()),
        ]
    }
}
