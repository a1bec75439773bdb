//! `analyze couette` and `analyze flowcurve`: the Couette viscosity and viscosity against shear
//! rate.

use super::{Table, in_name};
use crate::analysis::couette::{self, CouetteReport, RateProfile};
use crate::analysis::formats::{Series, parse_ave_chunk};
use crate::analysis::is_pos;
use serde_json::{Value, json};
use std::fmt::Write as _;

// ---------------------------------------------------------------- couette

/// The parameters of `analyze couette`.
pub struct CouetteParams {
    /// P_xy column (default pxy, else c_X[4]).
    pub col: Option<String>,
    /// Imposed shear rate; or measured from a profile.
    pub rate: Option<f64>,
    pub v_col: String,
    pub y_col: String,
    /// Factor on the profile coordinate (L_y for `units reduced` chunks).
    pub y_scale: f64,
    pub from: u64,
}

/// The stress series with its P_xy column chosen: the first half of the analysis, before the
/// profile is read.
pub struct CouetteSeries {
    pub input: String,
    pub column: String,
    pub series: Series,
}

/// Chooses the P_xy column of `s` (input `name`).
pub fn series(name: &str, s: Series, p: &CouetteParams) -> Result<CouetteSeries, String> {
    let s = s.from_step(p.from);
    let column = match &p.col {
        Some(c) => c.clone(),
        None if s.column_index("pxy").is_some() => "pxy".into(),
        None => s
            .indexed_columns(&[4])
            .map(|v| v[0].clone())
            .ok_or_else(|| {
                format!(
                    "{name}: no pxy column (columns: {}); give --col",
                    s.columns.join(" ")
                )
            })?,
    };
    in_name(name, s.column(&column))?;
    Ok(CouetteSeries {
        input: name.to_string(),
        column,
        series: s,
    })
}

/// The result of `analyze couette`.
pub struct CouetteAnalysis {
    pub label: String,
    pub input: String,
    pub column: String,
    pub from: u64,
    pub steps: Vec<f64>,
    pub pxy: Vec<f64>,
    /// The measured profile (with a profile file).
    pub profile: Option<RateProfile>,
    /// The shear rate used, its error and where it came from; the imposed one if given.
    pub rate: f64,
    pub rate_err: f64,
    pub rate_source: String,
    pub rate_imposed: Option<f64>,
    pub result: CouetteReport,
}

/// η* = −⟨P_xy⟩ / γ̇, γ̇ measured from `profile` (input name, text of a `fix ave/chunk` file) or
/// imposed.
pub fn analyze(
    s: CouetteSeries,
    profile: Option<(&str, &str)>,
    p: &CouetteParams,
    label: String,
) -> Result<CouetteAnalysis, String> {
    let pxy = in_name(&s.input, s.series.column(&s.column))?.to_vec();
    let profile = match profile {
        Some((name, text)) => {
            let chunk = in_name(name, parse_ave_chunk(text))?;
            if !is_pos(p.y_scale) {
                return Err(format!("--y-scale must be positive (got {})", p.y_scale));
            }
            let mut r = in_name(
                name,
                couette::rate_from_profile(&chunk, &p.y_col, &p.v_col, p.from),
            )?;
            r.y.iter_mut().for_each(|y| *y *= p.y_scale);
            r.rate.mean /= p.y_scale;
            r.rate.stderr /= p.y_scale;
            Some(r)
        }
        None => None,
    };
    let (rate, rate_err, rate_source) = match (&profile, p.rate) {
        (Some(pr), _) => (
            pr.rate.mean,
            pr.rate.stderr,
            "measured from the profile".to_string(),
        ),
        (None, Some(g)) => (g, 0.0, "imposed".to_string()),
        (None, None) => return Err("give --rate (imposed) or --profile (measured)".into()),
    };
    let result = couette::analyze(&pxy, rate, rate_err)?;
    Ok(CouetteAnalysis {
        label,
        input: s.input,
        column: s.column,
        from: p.from,
        steps: s.series.steps,
        pxy,
        profile,
        rate,
        rate_err,
        rate_source,
        rate_imposed: p.rate,
        result,
    })
}

impl CouetteAnalysis {
    /// The object of `PREFIX.json`.
    pub fn json(&self) -> Value {
        let r = &self.result;
        json!({
            "analysis": "couette", "label": self.label, "input": self.input, "column": self.column,
            "n_samples": r.n_samples, "from_step": self.from,
            "pxy": r.pxy.mean, "pxy_err": r.pxy.stderr,
            "pxy_n_eff": r.pxy.n_eff, "pxy_converged": r.pxy.converged,
            "shear_rate": self.rate, "shear_rate_err": self.rate_err,
            "shear_rate_source": self.rate_source,
            "shear_rate_imposed": self.rate_imposed,
            "viscosity": r.viscosity, "viscosity_err": r.viscosity_err,
        })
    }

    /// The running mean of P_xy.
    pub fn running_mean(&self) -> Vec<f64> {
        let mut acc = 0.0;
        self.pxy
            .iter()
            .enumerate()
            .map(|(k, v)| {
                acc += v;
                acc / (k + 1) as f64
            })
            .collect()
    }

    /// The columns of `PREFIX.csv`.
    pub fn table(&self) -> Table {
        vec![
            ("step", self.steps.clone()),
            ("pxy", self.pxy.clone()),
            ("pxy_running_mean", self.running_mean()),
        ]
    }

    /// The fitted line of the measured profile at its coordinates.
    pub fn profile_fit(&self) -> Option<Vec<f64>> {
        self.profile
            .as_ref()
            .map(|p| p.y.iter().map(|y| p.rate.mean * y + p.intercept).collect())
    }
}

// ---------------------------------------------------------------- flow curve

/// (shear rate, viscosity, its error).
pub type FlowPoint = (f64, f64, f64);

/// Points of viscosity against |shear rate|, grouped by label in the order first seen.
#[derive(Default)]
pub struct FlowCurve {
    pub groups: Vec<(String, Vec<FlowPoint>)>,
}

impl FlowCurve {
    pub fn add(&mut self, label: String, p: FlowPoint) {
        match self.groups.iter_mut().find(|g| g.0 == label) {
            Some(g) => g.1.push(p),
            None => self.groups.push((label, vec![p])),
        }
    }

    /// Adds the text of input `name`: a JSON result of `analyze nemd`/`couette` (one point)
    /// or a CSV with columns label,rate,eta[,eta_err].
    pub fn add_text(&mut self, name: &str, text: &str) -> Result<(), String> {
        if text.trim_start().starts_with('{') {
            let v: Value = serde_json::from_str(text).map_err(|e| format!("{name}: {e}"))?;
            let get = |k: &str| v[k].as_f64().ok_or(format!("{name}: no number '{k}'"));
            let label = v["label"].as_str().unwrap_or("result").to_string();
            let err = v["viscosity_err"].as_f64().unwrap_or(0.0);
            self.add(label, (get("shear_rate")?.abs(), get("viscosity")?, err));
            return Ok(());
        }
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
        let (_, header) = lines.next().ok_or(format!("{name}: empty CSV"))?;
        let cols: Vec<&str> = header.split(',').map(str::trim).collect();
        let idx = |n: &str| {
            cols.iter().position(|c| *c == n).ok_or(format!(
                "{name}: line 1: the CSV header has no '{n}' column"
            ))
        };
        let (jl, jr, je, jerr) = (
            idx("label")?,
            idx("rate")?,
            idx("eta")?,
            idx("eta_err").ok(),
        );
        for (i, l) in lines {
            let t: Vec<&str> = l.split(',').map(str::trim).collect();
            let val = |j: usize| -> Result<f64, String> {
                let tok = t.get(j).copied().unwrap_or("");
                tok.parse()
                    .map_err(|_| format!("{name}: line {}: cannot read '{tok}' as a number", i + 1))
            };
            let label = t.get(jl).copied().unwrap_or("").to_string();
            let rate = val(jr)?.abs();
            let eta = val(je)?;
            let err = match jerr {
                Some(j) => val(j)?,
                None => 0.0,
            };
            self.add(label, (rate, eta, err));
        }
        Ok(())
    }

    /// Each group's points sorted by rate.
    pub fn sorted(mut self) -> FlowCurve {
        for (_, pts) in &mut self.groups {
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        self
    }

    /// The CSV `label,rate,eta,eta_err`, one row per point.
    pub fn csv(&self) -> String {
        let mut csv = String::from("label,rate,eta,eta_err\n");
        for (label, pts) in &self.groups {
            for (r, e, err) in pts {
                let _ = writeln!(csv, "{label},{r},{e},{err}");
            }
        }
        csv
    }
}
