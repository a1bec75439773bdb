//! `analyze mb`: speed histograms (`fix ave/histo` files, dumps with velocities, or speeds)
//! against Maxwell–Boltzmann.

use super::{Table, in_name};
use crate::analysis::formats::{FileKind, detect, parse_ave_histo};
use crate::analysis::is_pos;
use crate::analysis::mb::{self, MbOptions, MbReport, SpeedHistogram};
use crate::io::dump_read::parse_dump;
use serde_json::{Value, json};

/// The inputs of one analysis, gathered one file at a time.
pub struct MbInput {
    hist: Option<SpeedHistogram>,
    speeds: Vec<Vec<f64>>,
    dim: Option<usize>,
    /// Dump frames read (0 for histogram files).
    pub dump_frames: usize,
    /// The names of the inputs (the `inputs` of the JSON).
    pub inputs: Vec<String>,
}

impl MbInput {
    /// `dim`: the dimension, or None for 3 with histograms and the dumps' own.
    pub fn new(dim: Option<usize>) -> MbInput {
        MbInput {
            hist: None,
            speeds: Vec::new(),
            dim,
            dump_frames: 0,
            inputs: Vec::new(),
        }
    }

    /// Adds a `fix ave/histo` file (summed with the earlier ones: same bins) or a dump with
    /// velocities (its frames at or after step `from`).
    pub fn add_text(&mut self, name: &str, text: &str, from: u64) -> Result<(), String> {
        self.inputs.push(name.to_string());
        match detect(text) {
            FileKind::AveHisto => {
                let h = in_name(name, parse_ave_histo(text))?;
                let h = in_name(name, SpeedHistogram::from_ave_histo(&h, from))?;
                self.hist = Some(match self.hist.take() {
                    None => h,
                    Some(mut acc) => {
                        if acc.edges != h.edges {
                            return Err(format!(
                                "{name}: bins differ from those of the first histogram file"
                            ));
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
                let frames = in_name(name, parse_dump(text))?;
                for fr in frames.iter().filter(|fr| fr.step >= from) {
                    let (v, d) = in_name(name, mb::frame_speeds(fr, self.dim))?;
                    self.dim.get_or_insert(d);
                    self.speeds.push(v);
                    self.dump_frames += 1;
                }
            }
            other => {
                return Err(format!(
                    "{name}: expected a fix ave/histo file or a dump, found {other:?}"
                ));
            }
        }
        Ok(())
    }

    /// Adds speeds given directly (one vector per frame or block), named `<speeds>`.
    pub fn add_speeds(&mut self, speeds: Vec<Vec<f64>>) {
        self.inputs.push("<speeds>".into());
        self.speeds.extend(speeds);
    }
}

/// The parameters of `analyze mb`.
pub struct MbParams {
    /// Set temperature kT.
    pub temp: f64,
    pub mass: f64,
    /// Samples (dumps, speeds): bins on [0, vmax] (default 2·sqrt(10 kT/m)).
    pub bins: usize,
    pub vmax: Option<f64>,
}

/// The result of `analyze mb`.
pub struct MbAnalysis {
    pub inputs: Vec<String>,
    pub dim: usize,
    pub mass: f64,
    pub temp: f64,
    pub dump_frames: usize,
    /// The histogram analysed.
    pub hist: SpeedHistogram,
    pub result: MbReport,
}

/// Histograms the samples if there are any and compares with Maxwell–Boltzmann.
pub fn analyze(input: MbInput, p: &MbParams) -> Result<MbAnalysis, String> {
    let dim = input.dim.unwrap_or(3);
    let vmax = p.vmax.unwrap_or(2.0 * (10.0 * p.temp / p.mass).sqrt());
    let mut hist = input.hist;
    if !input.speeds.is_empty() {
        if hist.is_some() {
            return Err("give either fix ave/histo files or dumps, not both".into());
        }
        if p.bins == 0 || !is_pos(vmax) {
            return Err("--bins and --vmax must be positive".into());
        }
        hist = Some(SpeedHistogram::from_samples(
            &input.speeds,
            mb::uniform_edges(0.0, vmax, p.bins),
        )?);
    }
    let hist = hist.ok_or("no histogram or dump frame to analyse")?;
    let o = MbOptions {
        kt: p.temp,
        mass: p.mass,
        dim,
        min_expected: 5.0,
    };
    let result = mb::analyze(&hist, &o)?;
    Ok(MbAnalysis {
        inputs: input.inputs,
        dim,
        mass: p.mass,
        temp: p.temp,
        dump_frames: input.dump_frames,
        hist,
        result,
    })
}

impl MbAnalysis {
    /// Lower and upper ends of the histogram.
    pub fn range(&self) -> (f64, f64) {
        let e = &self.hist.edges;
        (e[0], e[e.len() - 1])
    }

    /// The object of `PREFIX.json`.
    pub fn json(&self) -> Value {
        let r = &self.result;
        let (v_lo, v_hi) = self.range();
        json!({
            "analysis": "mb",
            "inputs": self.inputs,
            "dim": self.dim, "mass": self.mass, "kt_set": self.temp,
            "n_samples": r.n_total, "n_blocks": r.n_blocks, "source": self.hist.note,
            "v_lo": v_lo, "v_hi": v_hi, "bins": r.bins.len(),
            "outside": r.outside, "outside_expected": r.outside_expected,
            "kt_fit": r.kt_fit, "kt_fit_err_iid": r.kt_fit_err_iid,
            "kt_fit_err_blocks": r.kt_fit_err_blocks,
            "inefficiency": r.inefficiency,
            "chi2": r.chi2, "dof": r.dof, "p_value": r.p_value,
            "p_value_corrected": r.p_value_corrected,
            "chi2_fit": r.chi2_fit, "dof_fit": r.dof_fit, "p_value_fit": r.p_value_fit,
            "ks_d": r.ks_d, "ks_p": r.ks_p,
        })
    }

    /// The columns of `PREFIX.csv`: per bin its range, counts, densities and the residual
    /// (measured − MB at the set kT) / error.
    pub fn table(&self) -> Table {
        let b = &self.result.bins;
        let col = |f: &dyn Fn(&mb::MbBin) -> f64| b.iter().map(f).collect::<Vec<f64>>();
        let resid = col(&|b| {
            if b.pdf_err > 0.0 {
                (b.pdf - b.pdf_set) / b.pdf_err
            } else {
                f64::NAN
            }
        });
        vec![
            ("v_lo", col(&|b| b.lo)),
            ("v_hi", col(&|b| b.hi)),
            ("v_mid", col(&|b| 0.5 * (b.lo + b.hi))),
            ("count", col(&|b| b.count)),
            ("expected_count", col(&|b| b.expected)),
            ("pdf", col(&|b| b.pdf)),
            ("pdf_err", col(&|b| b.pdf_err)),
            ("pdf_mb_set", col(&|b| b.pdf_set)),
            ("pdf_mb_fit", col(&|b| b.pdf_fit)),
            ("residual_sigma", resid),
        ]
    }
}
