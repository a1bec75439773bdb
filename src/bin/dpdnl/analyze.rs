//! `dpdnl analyze <mb|nemd|eh|msd|couette|flowcurve> FILES… [--out PREFIX]`: turn run outputs
//! (LAMMPS's or this engine's, same formats) into the papers' numbers. Each subcommand prints
//! a short summary and writes `PREFIX.json` (the numbers), `PREFIX.csv` (the curve or profile)
//! and `PREFIX.png` / `PREFIX.svg` (the figure). See docs/analysis.md. Equation numbers ("eq. 55")
//! are the non-linear paper's, NL-55 … in docs/models.md.

use dpdnl::analysis::formats::{
    FileKind, Series, detect, parse_ave_chunk, parse_ave_histo, parse_series,
};
use dpdnl::analysis::{couette, eh, is_pos, mb, msd, nemd};
use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use dpdnl::plot::{Figure, Legend, Panel, Series as Line};
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Analyse run outputs: Maxwell–Boltzmann, NEMD viscosity, Einstein–Helfand, MSD, Couette.
#[derive(clap::Args)]
pub struct AnalyzeArgs {
    #[command(subcommand)]
    pub kind: Kind,
}

#[derive(clap::Args)]
pub struct OutArgs {
    /// Output prefix: writes PREFIX.json, PREFIX.csv, PREFIX.png, PREFIX.svg (default: the
    /// first input file's path followed by the subcommand name).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Skip the PNG/SVG figure.
    #[arg(long)]
    pub no_plot: bool,
}

#[derive(clap::Subcommand)]
pub enum Kind {
    /// Speed histogram against Maxwell–Boltzmann (fix ave/histo files or dumps with velocities).
    Mb(MbArgs),
    /// Reverse NEMD (PeX push): profiles, fits, Π_xz (eq. 55), viscosity (eq. 56), T_d (eq. 58).
    Nemd(NemdArgs),
    /// Einstein–Helfand viscosity (eq. 59) from off-diagonal pressure series.
    Eh(EhArgs),
    /// Self-diffusion from the MSD (compute msd series or unwrapped dumps); Schmidt number.
    Msd(MsdArgs),
    /// Couette flow under Lees–Edwards: η* = −⟨P_xy⟩ / shear rate.
    Couette(CouetteArgs),
    /// Viscosity against shear rate (log–log) from several nemd/couette results.
    Flowcurve(FlowArgs),
}

#[derive(clap::Args)]
pub struct MbArgs {
    /// fix ave/histo files (of the speed), or text dumps with vx vy [vz] columns.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Set temperature kT.
    #[arg(long)]
    pub temp: f64,
    #[arg(long, default_value_t = 1.0)]
    pub mass: f64,
    /// Dimension (default: 3 for histograms; for dumps 2 when there is no vz or it is all 0).
    #[arg(long)]
    pub dim: Option<usize>,
    /// Dumps: number of bins on [0, vmax] (the paper: 150).
    #[arg(long, default_value_t = 150)]
    pub bins: usize,
    /// Dumps: upper end of the histogram (default 2·sqrt(10 kT/m), i.e. the paper's 2 at kT = 0.1).
    #[arg(long)]
    pub vmax: Option<f64>,
    /// Skip dump frames and histogram outputs before this step.
    #[arg(long, default_value_t = 0)]
    pub from: u64,
    #[command(flatten)]
    pub out: OutArgs,
}

#[derive(clap::Args)]
pub struct NemdArgs {
    /// fix ave/chunk file of the profiles (bin/1d along x).
    pub profile: PathBuf,
    /// Box lengths Lx Ly Lz.
    #[arg(long, num_args = 3, value_names = ["LX", "LY", "LZ"], required = true)]
    pub r#box: Vec<f64>,
    /// Lower x bound of the box (default: from the bins, if they tile [xlo, xlo + Lx)).
    #[arg(long)]
    pub xlo: Option<f64>,
    /// Timestep δt.
    #[arg(long)]
    pub dt: f64,
    /// Momentum per push Δp_z (fix pex/push dp), for the nominal stress of eq. 55.
    #[arg(long)]
    pub dp: Option<f64>,
    /// Steps between pushes (fix pex/push every).
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Log or fix ave/time file holding the pushed momentum total (f_ID of fix pex/push); when
    /// given, Π_xz is measured from it (eq. 55 with ΣΔp_z over Δt).
    #[arg(long)]
    pub push: Option<PathBuf>,
    /// Column of the pushed total in --push (default: the only column starting with f_).
    #[arg(long)]
    pub push_col: Option<String>,
    /// Use only outputs at or after this step (steady state).
    #[arg(long, default_value_t = 0)]
    pub from: u64,
    /// Fraction of each half used for the fit, centred between the slabs.
    #[arg(long, default_value_t = 0.5)]
    pub fit_fraction: f64,
    #[arg(long, default_value = "vz")]
    pub vz_col: String,
    #[arg(long, default_value = "density/number")]
    pub density_col: String,
    /// Column with the per-particle mean of (px²+py²)/2m (k_B T_d of eq. 58).
    #[arg(long, default_value = "v_td")]
    pub td_col: String,
    /// Label of this result in flow curves.
    #[arg(long)]
    pub label: Option<String>,
    #[command(flatten)]
    pub out: OutArgs,
}

#[derive(clap::Args)]
pub struct EhArgs {
    /// fix ave/time file (scalar mode) or log with the off-diagonal pressure components.
    pub file: PathBuf,
    /// Timestep δt (the sample interval is δt times the step spacing of the file).
    #[arg(long)]
    pub dt: f64,
    /// Box lengths (2 in 2-D, 3 in 3-D): volume and the smallest length L of the window rule.
    #[arg(long, num_args = 2..=3, required = true)]
    pub r#box: Vec<f64>,
    /// k_B T.
    #[arg(long)]
    pub temp: f64,
    /// Number density n (ρ = n m for ν = μ/ρ in the window rule).
    #[arg(long)]
    pub density: f64,
    #[arg(long, default_value_t = 1.0)]
    pub mass: f64,
    /// Comma-separated stress columns (default: pxy,pxz,pyz or c_X[4],c_X[5],c_X[6]; only xy in 2-D).
    #[arg(long, value_delimiter = ',')]
    pub cols: Option<Vec<String>>,
    /// Use only samples at or after this step.
    #[arg(long, default_value_t = 0)]
    pub from: u64,
    /// t_max = FACTOR · L²/(4π²ν) (automatic window).
    #[arg(long, default_value_t = 0.1)]
    pub window_factor: f64,
    /// Fit window [tmin, tmax] in time units (overrides the automatic window).
    #[arg(long)]
    pub tmin: Option<f64>,
    #[arg(long)]
    pub tmax: Option<f64>,
    /// Blocks for the error.
    #[arg(long, default_value_t = 10)]
    pub blocks: usize,
    #[command(flatten)]
    pub out: OutArgs,
}

#[derive(clap::Args)]
pub struct MsdArgs {
    /// fix ave/time file or log with a compute msd column, or a dump with unwrapped positions.
    pub file: PathBuf,
    /// Timestep δt.
    #[arg(long)]
    pub dt: f64,
    #[arg(long, default_value_t = 3)]
    pub dim: usize,
    /// MSD column (series files; default: the only column named like c_*[4] or msd).
    #[arg(long)]
    pub col: Option<String>,
    /// Number of atoms (series files): gives the Brownian error estimate.
    #[arg(long)]
    pub atoms: Option<usize>,
    /// Fit window in time units.
    #[arg(long)]
    pub tmin: Option<f64>,
    #[arg(long)]
    pub tmax: Option<f64>,
    /// Use only samples/frames at or after this step.
    #[arg(long, default_value_t = 0)]
    pub from: u64,
    /// Shear viscosity μ for the Schmidt number Sc = μ/(ρD) (or --eta-from).
    #[arg(long)]
    pub eta: Option<f64>,
    #[arg(long, default_value_t = 0.0)]
    pub eta_err: f64,
    /// JSON result of `analyze eh` or `analyze nemd` to take μ from.
    #[arg(long)]
    pub eta_from: Option<PathBuf>,
    /// Number density n (ρ = n m) for the Schmidt number.
    #[arg(long)]
    pub density: Option<f64>,
    #[arg(long, default_value_t = 1.0)]
    pub mass: f64,
    #[command(flatten)]
    pub out: OutArgs,
}

#[derive(clap::Args)]
pub struct CouetteArgs {
    /// fix ave/time file or log with P_xy.
    pub file: PathBuf,
    /// P_xy column (default pxy, else c_X[4]).
    #[arg(long)]
    pub col: Option<String>,
    /// Imposed shear rate (fix deform erate); or measure it with --profile.
    #[arg(long)]
    pub rate: Option<f64>,
    /// fix ave/chunk profile along the gradient direction to measure the shear rate.
    #[arg(long)]
    pub profile: Option<PathBuf>,
    #[arg(long, default_value = "vx")]
    pub v_col: String,
    #[arg(long, default_value = "Coord1")]
    pub y_col: String,
    /// Multiply the profile coordinate by this (the box length L_y when the chunks use
    /// `units reduced`, which LAMMPS requires for triclinic boxes).
    #[arg(long, default_value_t = 1.0)]
    pub y_scale: f64,
    /// Use only samples/outputs at or after this step.
    #[arg(long, default_value_t = 0)]
    pub from: u64,
    #[arg(long)]
    pub label: Option<String>,
    #[command(flatten)]
    pub out: OutArgs,
}

#[derive(clap::Args)]
pub struct FlowArgs {
    /// JSON results of `analyze nemd`/`analyze couette`, or CSV files with columns
    /// label,rate,eta,eta_err.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Output prefix (default: flowcurve).
    #[arg(long, default_value = "flowcurve")]
    pub out: PathBuf,
    #[arg(long)]
    pub no_plot: bool,
}

pub fn main(a: AnalyzeArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    match a.kind {
        Kind::Mb(a) => run_mb(a),
        Kind::Nemd(a) => run_nemd(a),
        Kind::Eh(a) => run_eh(a),
        Kind::Msd(a) => run_msd(a),
        Kind::Couette(a) => run_couette(a),
        Kind::Flowcurve(a) => run_flow(a),
    }
    .map(|()| ExitCode::SUCCESS)
    .map_err(Into::into)
}

// ---------------------------------------------------------------- helpers

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Prefixes an error with the file it came from.
fn in_file<T>(path: &Path, r: Result<T, String>) -> Result<T, String> {
    r.map_err(|e| format!("{}: {e}", path.display()))
}

fn prefix(out: &OutArgs, first: &Path, kind: &str) -> Result<PathBuf, String> {
    let p = match &out.out {
        Some(p) => p.clone(),
        None => {
            let mut s = first.as_os_str().to_os_string();
            s.push(format!(".{kind}"));
            PathBuf::from(s)
        }
    };
    if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    Ok(p)
}

fn with_ext(prefix: &Path, ext: &str) -> PathBuf {
    dpdnl::plot::with_suffix(prefix, ext)
}

/// A number for JSON: non-finite values become null.
fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn nums(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|x| num(*x)).collect())
}

fn write_json(prefix: &Path, v: &Value) -> Result<PathBuf, String> {
    let p = with_ext(prefix, "json");
    let s = serde_json::to_string_pretty(v).map_err(|e| e.to_string())?;
    std::fs::write(&p, s + "\n").map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(p)
}

/// Writes a CSV with a header; non-finite values are written as `nan`.
fn write_csv(prefix: &Path, header: &[&str], cols: &[&[f64]]) -> Result<PathBuf, String> {
    let p = with_ext(prefix, "csv");
    let n = cols.iter().map(|c| c.len()).max().unwrap_or(0);
    let mut s = header.join(",");
    s.push('\n');
    for i in 0..n {
        let row: Vec<String> = cols
            .iter()
            .map(|c| match c.get(i) {
                Some(v) if v.is_finite() => format!("{v}"),
                _ => "nan".into(),
            })
            .collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    std::fs::write(&p, s).map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(p)
}

fn save_plot(
    out: &OutArgs,
    prefix: &Path,
    fig: Figure,
    written: &mut Vec<PathBuf>,
) -> Result<(), String> {
    if !out.no_plot {
        written.extend(fig.save(prefix)?);
    }
    Ok(())
}

fn pm(v: f64, e: f64) -> String {
    if e.is_finite() && e > 1e-9 * v.abs() {
        // Two significant digits of the error.
        let digits = (1 - e.log10().floor() as i32).clamp(0, 12) as usize;
        format!("{v:.digits$} ± {e:.digits$}")
    } else {
        format!("{v:.6}")
    }
}

fn print_written(files: &[PathBuf]) {
    let names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    println!("wrote {}", names.join(", "));
}

/// Keeps the rows of a series at or after `from`.
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

/// The uniform step spacing of a series.
fn step_spacing(steps: &[f64], path: &Path) -> Result<f64, String> {
    if steps.len() < 2 {
        return Err(format!("{}: fewer than two samples", path.display()));
    }
    let d = steps[1] - steps[0];
    if let Some(k) = steps.windows(2).position(|w| w[1] - w[0] != d) {
        return Err(format!(
            "{}: samples are not equally spaced (step {} after {}, spacing {d} before)",
            path.display(),
            steps[k + 1],
            steps[k]
        ));
    }
    if d <= 0.0 {
        return Err(format!("{}: steps do not increase", path.display()));
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

// ---------------------------------------------------------------- mb

fn run_mb(a: MbArgs) -> Result<(), String> {
    let mut hist: Option<mb::SpeedHistogram> = None;
    let mut dim = a.dim;
    let mut speeds: Vec<Vec<f64>> = Vec::new();
    let mut dump_frames = 0;
    for f in &a.files {
        let text = read(f)?;
        match detect(&text) {
            FileKind::AveHisto => {
                let h = in_file(f, parse_ave_histo(&text))?;
                let h = in_file(f, mb::SpeedHistogram::from_ave_histo(&h, a.from))?;
                hist = Some(match hist {
                    None => h,
                    Some(mut acc) => {
                        if acc.edges != h.edges {
                            return Err(format!(
                                "{}: bins differ from those of the first histogram file",
                                f.display()
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
                let frames = in_file(f, parse_dump(&text))?;
                for fr in frames.iter().filter(|fr| fr.step >= a.from) {
                    let (v, d) = in_file(f, frame_speeds(fr, dim))?;
                    dim.get_or_insert(d);
                    speeds.push(v);
                    dump_frames += 1;
                }
            }
            other => {
                return Err(format!(
                    "{}: expected a fix ave/histo file or a dump, found {other:?}",
                    f.display()
                ));
            }
        }
    }
    let dim = dim.unwrap_or(3);
    let vmax = a.vmax.unwrap_or(2.0 * (10.0 * a.temp / a.mass).sqrt());
    if !speeds.is_empty() {
        if hist.is_some() {
            return Err("give either fix ave/histo files or dumps, not both".into());
        }
        if a.bins == 0 || !is_pos(vmax) {
            return Err("--bins and --vmax must be positive".into());
        }
        hist = Some(mb::SpeedHistogram::from_samples(
            &speeds,
            mb::uniform_edges(0.0, vmax, a.bins),
        )?);
    }
    let h = hist.ok_or("no histogram or dump frame to analyse")?;
    let o = mb::MbOptions {
        kt: a.temp,
        mass: a.mass,
        dim,
        min_expected: 5.0,
    };
    let r = mb::analyze(&h, &o)?;
    let prefix = prefix(&a.out, &a.files[0], "mb")?;

    let kt_err = r.kt_fit_err_blocks.unwrap_or(r.kt_fit_err_iid);
    println!(
        "Maxwell–Boltzmann, d = {dim}: {} samples ({}; {} blocks), {} bins on [{}, {}]",
        r.n_total,
        if dump_frames > 0 {
            format!("{dump_frames} dump frames")
        } else {
            h.note.clone()
        },
        r.n_blocks,
        r.bins.len(),
        h.edges[0],
        h.edges[h.edges.len() - 1]
    );
    println!(
        "  kT fitted {} (set {}; error {}), outside range {} (expected {:.1})",
        pm(r.kt_fit, kt_err),
        a.temp,
        if r.kt_fit_err_blocks.is_some() {
            "from blocks"
        } else {
            "iid"
        },
        r.outside,
        r.outside_expected
    );
    println!(
        "  chi2 = {:.2} for {} dof (p = {:.3e}{}); KS D = {:.3e} (p = {:.3e})",
        r.chi2,
        r.dof,
        r.p_value,
        match (r.inefficiency, r.p_value_corrected) {
            (Some(g), Some(p)) => format!("; inefficiency g = {g:.2}, corrected p = {p:.3e}"),
            _ => String::new(),
        },
        r.ks_d,
        r.ks_p
    );

    let lo: Vec<f64> = r.bins.iter().map(|b| b.lo).collect();
    let hi: Vec<f64> = r.bins.iter().map(|b| b.hi).collect();
    let mid: Vec<f64> = r.bins.iter().map(|b| 0.5 * (b.lo + b.hi)).collect();
    let count: Vec<f64> = r.bins.iter().map(|b| b.count).collect();
    let pdf: Vec<f64> = r.bins.iter().map(|b| b.pdf).collect();
    let err: Vec<f64> = r.bins.iter().map(|b| b.pdf_err).collect();
    let set: Vec<f64> = r.bins.iter().map(|b| b.pdf_set).collect();
    let fit: Vec<f64> = r.bins.iter().map(|b| b.pdf_fit).collect();
    let expected: Vec<f64> = r.bins.iter().map(|b| b.expected).collect();
    let resid: Vec<f64> = (0..r.bins.len())
        .map(|i| {
            if err[i] > 0.0 {
                (pdf[i] - set[i]) / err[i]
            } else {
                f64::NAN
            }
        })
        .collect();
    let mut written = vec![write_csv(
        &prefix,
        &[
            "v_lo",
            "v_hi",
            "v_mid",
            "count",
            "expected_count",
            "pdf",
            "pdf_err",
            "pdf_mb_set",
            "pdf_mb_fit",
            "residual_sigma",
        ],
        &[
            &lo, &hi, &mid, &count, &expected, &pdf, &err, &set, &fit, &resid,
        ],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "mb",
            "inputs": a.files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            "dim": dim, "mass": a.mass, "kt_set": a.temp,
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
        }),
    )?);
    // Smooth MB curves for the figure.
    let vmax_plot = h.edges[h.edges.len() - 1];
    let vs: Vec<f64> = (0..=400).map(|i| vmax_plot * i as f64 / 400.0).collect();
    let curve = |kt: f64| {
        vs.iter()
            .map(|&v| mb::mb_pdf(v, kt, a.mass, dim))
            .collect::<Vec<_>>()
    };
    let p1 = Panel::new(&format!("Speed distribution, d = {dim}"), "speed v", "P(v)")
        .with(Line::points("measured", mid.clone(), pdf).errors(err))
        .with(Line::dashed(
            &format!("Maxwell–Boltzmann, kT = {}", a.temp),
            vs.clone(),
            curve(a.temp),
        ))
        .with(Line::line(
            &format!("MB at fitted kT = {:.5}", r.kt_fit),
            vs.clone(),
            curve(r.kt_fit),
        ));
    let p2 = Panel::new(
        &match r.p_value_corrected {
            Some(pc) => format!(
                "χ² = {:.1} / {} dof, p = {:.2e} (corrected for correlation: {:.2e})",
                r.chi2, r.dof, r.p_value, pc
            ),
            None => format!("χ² = {:.1} / {} dof, p = {:.2e}", r.chi2, r.dof, r.p_value),
        },
        "speed v",
        "(measured − MB) / error",
    )
    .with(Line::points("", mid.clone(), resid))
    .with(Line::dashed("±2σ", vec![0.0, vmax_plot], vec![2.0, 2.0]).color(6))
    .with(Line::dashed("", vec![0.0, vmax_plot], vec![-2.0, -2.0]).color(6));
    save_plot(&a.out, &prefix, Figure::grid(vec![p1, p2], 2), &mut written)?;
    print_written(&written);
    Ok(())
}

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

// ---------------------------------------------------------------- nemd

fn run_nemd(a: NemdArgs) -> Result<(), String> {
    let text = read(&a.profile)?;
    let chunk = in_file(&a.profile, parse_ave_chunk(&text))?;
    let (lx, ly, lz) = (a.r#box[0], a.r#box[1], a.r#box[2]);
    let cols = nemd::NemdColumns {
        x: "Coord1".into(),
        vz: a.vz_col.clone(),
        density: a.density_col.clone(),
        td: a.td_col.clone(),
    };
    let prof = in_file(
        &a.profile,
        nemd::profiles_from_chunk(&chunk, &cols, a.from, ly * lz),
    )?;
    let xlo = match a.xlo {
        Some(x) => x,
        None => {
            let n = prof.x.len();
            let dx = (prof.x[n - 1] - prof.x[0]) / (n - 1) as f64;
            if ((n as f64) * dx - lx).abs() > 1e-4 * lx {
                return Err(format!(
                    "{}: the {n} bins (width {dx}) do not tile Lx = {lx}; give --xlo",
                    a.profile.display()
                ));
            }
            prof.x[0] - 0.5 * dx
        }
    };
    let nominal =
        a.dp.map(|dp| nemd::pex_stress_nominal(dp, a.every, a.dt, ly, lz));
    let measured = match &a.push {
        Some(p) => {
            let s = series_from(in_file(p, parse_series(&read(p)?))?, a.from);
            let name = match &a.push_col {
                Some(c) => c.clone(),
                None => {
                    let f: Vec<&String> =
                        s.columns.iter().filter(|c| c.starts_with("f_")).collect();
                    match f.as_slice() {
                        [one] => (*one).clone(),
                        _ => {
                            return Err(format!(
                                "{}: cannot tell the pushed-momentum column (columns: {}); give --push-col",
                                p.display(),
                                s.columns.join(" ")
                            ));
                        }
                    }
                }
            };
            let col = in_file(p, s.column(&name))?;
            let (last, steps): (Vec<f64>, Vec<f64>) = col
                .iter()
                .zip(&s.steps)
                .filter(|(_, k)| **k <= prof.steps[prof.steps.len() - 1] as f64)
                .map(|(v, k)| (*v, *k))
                .unzip();
            Some((
                in_file(p, nemd::pex_stress_from_total(&steps, &last, a.dt, ly, lz))?,
                name,
            ))
        }
        None => None,
    };
    let (stress, stress_err, stress_source) = match (&measured, nominal) {
        (Some(((s, e), name)), _) => (*s, *e, format!("measured from {name}")),
        (None, Some(s)) => (s, 0.0, "nominal dp/(2 Ly Lz every dt)".to_string()),
        (None, None) => return Err("give --dp (nominal stress) or --push (measured)".into()),
    };
    let o = nemd::NemdOptions {
        xlo,
        lx,
        stress,
        stress_err,
        fit_fraction: a.fit_fraction,
    };
    let r = nemd::analyze(&prof, &o)?;
    let prefix = prefix(&a.out, &a.profile, "nemd")?;
    let label = a.label.clone().unwrap_or_else(|| {
        a.profile
            .file_stem()
            .map_or("nemd".into(), |s| s.to_string_lossy().into_owned())
    });

    println!(
        "NEMD (PeX): {} profiles, steps {}..{}, {} bins, xlo = {xlo}, Lx = {lx}",
        r.n_outputs,
        r.first_step,
        r.last_step,
        r.x.len()
    );
    println!(
        "  Pi_xz = {} ({stress_source}){}",
        pm(stress, stress_err),
        match (nominal, &measured) {
            (Some(n), Some(_)) => format!("; nominal {n:.6}"),
            _ => String::new(),
        }
    );
    for h in &r.halves {
        println!(
            "  {:7} half: window [{:.4}, {:.4}] ({} bins), slope {}",
            h.name,
            h.window.0,
            h.window.1,
            h.bins.len(),
            pm(h.slope.mean, h.slope.stderr)
        );
    }
    println!(
        "  shear rate {} (block {}x{}{}), viscosity mu = {}",
        pm(r.shear_rate.mean, r.shear_rate.stderr),
        r.shear_rate.n_blocks,
        r.shear_rate.block_len,
        if r.shear_rate.converged {
            ""
        } else {
            ", not converged"
        },
        pm(r.viscosity, r.viscosity_err)
    );
    println!(
        "  centre: density {}{}",
        pm(r.density_centre.mean, r.density_centre.stderr),
        r.td_centre
            .map_or(" (no T_d column)".to_string(), |t| format!(
                ", T_d {}",
                pm(t.mean, t.stderr)
            ))
    );

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
    let mut written = vec![write_csv(
        &prefix,
        &[
            "x",
            "vz",
            "vz_err",
            "vz_fit",
            "td",
            "td_err",
            "density",
            "density_err",
        ],
        &[
            &r.x,
            &r.vz.mean,
            &r.vz.err,
            &fitline,
            &td_m,
            &td_e,
            &r.density.mean,
            &r.density.err,
        ],
    )?];
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
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "nemd", "label": label, "input": a.profile.display().to_string(),
            "box": [lx, ly, lz], "xlo": xlo, "dt": a.dt, "from_step": a.from,
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
        }),
    )?);

    let mut pv = Panel::new(
        &format!("v_z profile: μ = {}", pm(r.viscosity, r.viscosity_err)),
        "x",
        "v_z",
    )
    .with(Line::points("⟨v_z⟩", r.x.clone(), r.vz.mean.clone()).errors(r.vz.err.clone()));
    for (k, h) in r.halves.iter().enumerate() {
        let xs = vec![h.window.0, h.window.1];
        let ys: Vec<f64> = xs
            .iter()
            .map(|x| h.fit.slope * x + h.fit.intercept)
            .collect();
        // The outer window straddles the boundary: draw its fit on both ends of the box.
        if h.name == "outer" {
            let xlo_p = xlo;
            let xhi_p = xlo + lx;
            let y_at = |x: f64| h.fit.slope * x + h.fit.intercept;
            let left = (xlo_p, h.window.1);
            let right = (h.window.0 + lx, xhi_p);
            pv = pv
                .with(
                    Line::line(
                        "linear fit",
                        vec![left.0, left.1],
                        vec![y_at(left.0), y_at(left.1)],
                    )
                    .color(1),
                )
                .with(
                    Line::line(
                        "",
                        vec![right.0, right.1],
                        vec![y_at(right.0 - lx), y_at(right.1 - lx)],
                    )
                    .color(1),
                )
                .band(left.0, left.1, "")
                .band(right.0, right.1, "");
        } else {
            pv = pv
                .with(Line::line(if k == 0 { "" } else { "linear fit" }, xs.clone(), ys).color(1))
                .band(xs[0], xs[1], "fit window");
        }
    }
    let mut panels = vec![pv];
    if let Some(t) = &r.td {
        panels.push(
            Panel::new("Dynamic temperature (eq. 58)", "x", "k_B T_d")
                .with(Line::points("T_d", r.x.clone(), t.mean.clone()).errors(t.err.clone())),
        );
    }
    panels.push(
        Panel::new("Density", "x", "n")
            .with(
                Line::points("density", r.x.clone(), r.density.mean.clone())
                    .errors(r.density.err.clone()),
            )
            .legend(Legend::LowerRight),
    );
    let cols = panels.len();
    save_plot(&a.out, &prefix, Figure::grid(panels, cols), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- eh

fn run_eh(a: EhArgs) -> Result<(), String> {
    let s = series_from(in_file(&a.file, parse_series(&read(&a.file)?))?, a.from);
    let dim = a.r#box.len();
    let names: Vec<String> = match &a.cols {
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
                return Err(format!(
                    "{}: cannot find the off-diagonal pressure columns (columns: {}); give --cols",
                    a.file.display(),
                    s.columns.join(" ")
                ));
            }
        }
    };
    let comps: Vec<&[f64]> = names
        .iter()
        .map(|n| in_file(&a.file, s.column(n)))
        .collect::<Result<_, _>>()?;
    let spacing = step_spacing(&s.steps, &a.file)?;
    let volume: f64 = a.r#box.iter().product();
    let box_len = a.r#box.iter().copied().fold(f64::INFINITY, f64::min);
    let mut o = eh::EhOptions::new(spacing * a.dt, volume, a.temp, box_len, a.density * a.mass);
    o.window_factor = a.window_factor;
    o.t_min = a.tmin;
    o.t_max = a.tmax;
    o.n_blocks = a.blocks;
    let r = in_file(&a.file, eh::analyze(&comps, &o))?;
    let prefix = prefix(&a.out, &a.file, "eh")?;

    println!(
        "Einstein–Helfand (eq. 59): {} samples every {} steps (Δ = {}), components {}",
        r.n_samples,
        spacing,
        o.dt_sample,
        names.join(" ")
    );
    println!(
        "  window [{:.4}, {:.4}] ({}); L²/(4π²ν) = {:.4}{}",
        r.t_min,
        r.t_max,
        r.window_source,
        r.tau_l,
        if r.capped {
            "; CAPPED by the run length (run longer for this window)"
        } else {
            ""
        }
    );
    println!(
        "  viscosity mu = {} ({} blocks); per component {}",
        pm(r.viscosity, r.viscosity_err),
        r.blocks.len(),
        r.per_component
            .iter()
            .map(|v| format!("{v:.5}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    // Significant at 3 standard errors: the fitted slope is then biased beyond its error.
    let drifting =
        r.drift.is_finite() && r.drift_err.is_finite() && r.drift.abs() > 3.0 * r.drift_err;
    println!(
        "  linearity: mu(second half of window) - mu(first half) = {}{}",
        pm(r.drift, r.drift_err),
        if drifting {
            "  WARNING: not linear over the window (still in the transient); try a larger \
             --window-factor or a larger box"
        } else {
            ""
        }
    );
    let fitline: Vec<f64> =
        r.t.iter()
            .map(|t| r.fit.slope * t + r.fit.intercept)
            .collect();
    let mut written = vec![write_csv(
        &prefix,
        &["t", "msd_integral", "mu_running", "msd_fit"],
        &[&r.t, &r.msd, &r.running, &fitline],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "eh", "input": a.file.display().to_string(), "components": names,
            "dt": a.dt, "sample_interval": o.dt_sample, "n_samples": r.n_samples, "from_step": a.from,
            "volume": volume, "kt": a.temp, "box_len": box_len, "mass_density": o.mass_density,
            "t_min": num(r.t_min), "t_max": num(r.t_max), "tau_l": num(r.tau_l),
            "window_source": r.window_source, "window_capped": r.capped,
            "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
            "per_component": nums(&r.per_component), "blocks": nums(&r.blocks),
            "window_drift": num(r.drift), "window_drift_err": num(r.drift_err), "window_not_linear": drifting,
            "slope": num(r.fit.slope), "intercept": num(r.fit.intercept),
        }),
    )?);
    let show =
        r.t.iter()
            .position(|&t| t > 3.0 * r.t_max)
            .unwrap_or(r.t.len());
    let t = r.t[1..show].to_vec();
    let p1 = Panel::new(
        &format!(
            "EH running viscosity: μ = {}",
            pm(r.viscosity, r.viscosity_err)
        ),
        "t",
        "V ⟨(∫Π dt)²⟩ / (2 kT t)",
    )
    .with(Line::line("μ(t)", t.clone(), r.running[1..show].to_vec()))
    .with(Line::dashed("fitted μ", vec![t[0], t[t.len() - 1]], vec![r.viscosity; 2]).color(1))
    .band(r.t_min, r.t_max, "fit window")
    .legend(Legend::LowerRight);
    let p2 = Panel::new("Integrated stress", "t", "⟨(∫Π dt)²⟩")
        .with(Line::line(
            "all origins",
            t.clone(),
            r.msd[1..show].to_vec(),
        ))
        .with(Line::dashed("linear fit", t, fitline[1..show].to_vec()).color(1))
        .band(r.t_min, r.t_max, "fit window")
        .legend(Legend::UpperLeft);
    save_plot(&a.out, &prefix, Figure::grid(vec![p1, p2], 2), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- msd

fn run_msd(a: MsdArgs) -> Result<(), String> {
    let text = read(&a.file)?;
    let mut o = msd::MsdOptions::new(a.dim);
    o.t_min = a.tmin;
    o.t_max = a.tmax;
    let r = if detect(&text) == FileKind::Dump {
        let frames: Vec<DumpFrame> = in_file(&a.file, parse_dump(&text))?
            .into_iter()
            .filter(|f| f.step >= a.from)
            .collect();
        let (steps, series, note) = in_file(&a.file, msd::unwrapped_series(&frames, a.dim))?;
        let st: Vec<f64> = steps.iter().map(|&k| k as f64).collect();
        let spacing = step_spacing(&st, &a.file)?;
        let mut r = in_file(
            &a.file,
            msd::from_trajectories(&series, a.dim, spacing * a.dt, &o),
        )?;
        r.method = format!("{} ({note})", r.method);
        r
    } else {
        let s = series_from(in_file(&a.file, parse_series(&text))?, a.from);
        let name = match &a.col {
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
                        return Err(format!(
                            "{}: cannot tell the MSD column (columns: {}); give --col",
                            a.file.display(),
                            s.columns.join(" ")
                        ));
                    }
                }
            }
        };
        let m = in_file(&a.file, s.column(&name))?;
        let t: Vec<f64> = s.steps.iter().map(|k| k * a.dt).collect();
        in_file(&a.file, msd::from_series(&t, m, &o, a.atoms))?
    };
    let eta = match (&a.eta_from, a.eta) {
        (Some(p), _) => {
            let v: Value =
                serde_json::from_str(&read(p)?).map_err(|e| format!("{}: {e}", p.display()))?;
            let mu = v["viscosity"]
                .as_f64()
                .ok_or(format!("{}: no 'viscosity' number", p.display()))?;
            Some((
                mu,
                v["viscosity_err"].as_f64().unwrap_or(0.0),
                p.display().to_string(),
            ))
        }
        (None, Some(mu)) => Some((mu, a.eta_err, "--eta".to_string())),
        _ => None,
    };
    let sc = match (eta.as_ref(), a.density) {
        (Some((mu, mu_err, _)), Some(n)) => {
            Some(msd::schmidt(*mu, *mu_err, n * a.mass, r.d, r.d_err))
        }
        (Some(_), None) => return Err("the Schmidt number needs --density".into()),
        _ => None,
    };
    let prefix = prefix(&a.out, &a.file, "msd")?;
    println!(
        "MSD, d = {}: {}; window [{:.4}, {:.4}]",
        a.dim, r.method, r.t_min, r.t_max
    );
    println!("  D = {} ({})", pm(r.d, r.d_err), r.d_err_method);
    if let Some((s, e)) = sc {
        println!("  Sc = mu/(rho D) = {}", pm(s, e));
    }
    let fitline: Vec<f64> =
        r.t.iter()
            .map(|t| r.fit.slope * t + r.fit.intercept)
            .collect();
    let err = r
        .msd_err
        .clone()
        .unwrap_or_else(|| vec![f64::NAN; r.t.len()]);
    let mut written = vec![write_csv(
        &prefix,
        &["t", "msd", "msd_err", "msd_fit"],
        &[&r.t, &r.msd, &err, &fitline],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "msd", "input": a.file.display().to_string(), "dim": a.dim, "dt": a.dt,
            "method": r.method, "t_min": num(r.t_min), "t_max": num(r.t_max),
            "diffusion": num(r.d), "diffusion_err": num(r.d_err), "diffusion_err_method": r.d_err_method,
            "diffusion_groups": nums(&r.d_groups),
            "viscosity": eta.as_ref().map_or(Value::Null, |e| num(e.0)),
            "viscosity_source": eta.as_ref().map(|e| e.2.clone()),
            "schmidt": sc.map_or(Value::Null, |s| num(s.0)), "schmidt_err": sc.map_or(Value::Null, |s| num(s.1)),
        }),
    )?);
    let mut line = Line::points("MSD", r.t.clone(), r.msd.clone());
    if let Some(e) = &r.msd_err {
        line = line.errors(e.clone());
    }
    let p = Panel::new(&format!("MSD: D = {}", pm(r.d, r.d_err)), "t", "MSD")
        .with(line)
        .with(Line::dashed("linear fit", r.t.clone(), fitline).color(1))
        .band(r.t_min, r.t_max, "fit window")
        .legend(Legend::UpperLeft);
    save_plot(&a.out, &prefix, Figure::single(p), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- couette

fn run_couette(a: CouetteArgs) -> Result<(), String> {
    let s = series_from(in_file(&a.file, parse_series(&read(&a.file)?))?, a.from);
    let name = match &a.col {
        Some(c) => c.clone(),
        None if s.column_index("pxy").is_some() => "pxy".into(),
        None => indexed_columns(&s, &[4])
            .map(|v| v[0].clone())
            .ok_or(format!(
                "{}: no pxy column (columns: {}); give --col",
                a.file.display(),
                s.columns.join(" ")
            ))?,
    };
    let pxy = in_file(&a.file, s.column(&name))?;
    let profile = match &a.profile {
        Some(p) => {
            let chunk = in_file(p, parse_ave_chunk(&read(p)?))?;
            if !is_pos(a.y_scale) {
                return Err(format!("--y-scale must be positive (got {})", a.y_scale));
            }
            let mut r = in_file(
                p,
                couette::rate_from_profile(&chunk, &a.y_col, &a.v_col, a.from),
            )?;
            r.y.iter_mut().for_each(|y| *y *= a.y_scale);
            r.rate.mean /= a.y_scale;
            r.rate.stderr /= a.y_scale;
            Some(r)
        }
        None => None,
    };
    let (rate, rate_err, rate_source) = match (&profile, a.rate) {
        (Some(p), _) => (
            p.rate.mean,
            p.rate.stderr,
            "measured from the profile".to_string(),
        ),
        (None, Some(g)) => (g, 0.0, "imposed".to_string()),
        (None, None) => return Err("give --rate (imposed) or --profile (measured)".into()),
    };
    let r = couette::analyze(pxy, rate, rate_err)?;
    let prefix = prefix(&a.out, &a.file, "couette")?;
    let label = a.label.clone().unwrap_or_else(|| {
        a.file
            .file_stem()
            .map_or("couette".into(), |s| s.to_string_lossy().into_owned())
    });
    println!(
        "Couette: {} samples of {name}; <P_xy> = {} (block {}x{}{})",
        r.n_samples,
        pm(r.pxy.mean, r.pxy.stderr),
        r.pxy.n_blocks,
        r.pxy.block_len,
        if r.pxy.converged {
            ""
        } else {
            ", not converged"
        }
    );
    let mut msg = String::new();
    if let (Some(p), Some(g)) = (&profile, a.rate) {
        let _ = write!(
            msg,
            " (imposed {g}, profile {})",
            pm(p.rate.mean, p.rate.stderr)
        );
    }
    println!(
        "  shear rate {} ({rate_source}){msg}; eta* = -<P_xy>/rate = {}",
        pm(rate, rate_err),
        pm(r.viscosity, r.viscosity_err)
    );
    let steps = s.steps.clone();
    let mut running = Vec::with_capacity(pxy.len());
    let mut acc = 0.0;
    for (k, v) in pxy.iter().enumerate() {
        acc += v;
        running.push(acc / (k + 1) as f64);
    }
    let mut written = vec![write_csv(
        &prefix,
        &["step", "pxy", "pxy_running_mean"],
        &[&steps, pxy, &running],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "couette", "label": label, "input": a.file.display().to_string(), "column": name,
            "n_samples": r.n_samples, "from_step": a.from,
            "pxy": num(r.pxy.mean), "pxy_err": num(r.pxy.stderr),
            "shear_rate": num(rate), "shear_rate_err": num(rate_err), "shear_rate_source": rate_source,
            "shear_rate_imposed": a.rate.map_or(Value::Null, num),
            "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
        }),
    )?);
    let mut panels = vec![
        Panel::new(
            &format!("P_xy: η* = {}", pm(r.viscosity, r.viscosity_err)),
            "step",
            "P_xy",
        )
        .with(Line::line("P_xy", steps.clone(), pxy.to_vec()).color(5))
        .with(Line::line("running mean", steps, running).color(1)),
    ];
    if let Some(p) = &profile {
        let fit: Vec<f64> = p.y.iter().map(|y| p.rate.mean * y + p.intercept).collect();
        panels.push(
            Panel::new("Streaming velocity", "y", &a.v_col)
                .with(
                    Line::points("measured", p.y.clone(), p.v_mean.clone()).errors(p.v_err.clone()),
                )
                .with(Line::dashed("linear fit", p.y.clone(), fit).color(1))
                .legend(Legend::UpperLeft),
        );
    }
    let cols = panels.len();
    save_plot(&a.out, &prefix, Figure::grid(panels, cols), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- flow curve

/// (shear rate, viscosity, its error).
type FlowPoint = (f64, f64, f64);

fn run_flow(a: FlowArgs) -> Result<(), String> {
    let mut groups: Vec<(String, Vec<FlowPoint>)> = Vec::new();
    let mut add = |label: String, p: (f64, f64, f64)| match groups.iter_mut().find(|g| g.0 == label)
    {
        Some(g) => g.1.push(p),
        None => groups.push((label, vec![p])),
    };
    for f in &a.files {
        let text = read(f)?;
        if text.trim_start().starts_with('{') {
            let v: Value =
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", f.display()))?;
            let get = |k: &str| {
                v[k].as_f64()
                    .ok_or(format!("{}: no number '{k}'", f.display()))
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
            let (_, header) = lines.next().ok_or(format!("{}: empty CSV", f.display()))?;
            let cols: Vec<&str> = header.split(',').map(str::trim).collect();
            let idx = |n: &str| {
                cols.iter().position(|c| *c == n).ok_or(format!(
                    "{}: line 1: the CSV header has no '{n}' column",
                    f.display()
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
                    tok.parse().map_err(|_| {
                        format!(
                            "{}: line {}: cannot read '{tok}' as a number",
                            f.display(),
                            i + 1
                        )
                    })
                };
                let label = t.get(jl).copied().unwrap_or("").to_string();
                add(
                    label,
                    (
                        val(jr)?.abs(),
                        val(je)?,
                        match jerr {
                            Some(j) => val(j)?,
                            None => 0.0,
                        },
                    ),
                );
            }
        }
    }
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let mut panel = Panel::new("Viscosity against shear rate", "shear rate", "viscosity")
        .log_x()
        .log_y()
        .legend(Legend::LowerLeft);
    let mut csv = String::from("label,rate,eta,eta_err\n");
    for (label, pts) in &mut groups {
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        println!("{label}:");
        for (r, e, err) in pts.iter() {
            println!("  rate {r:.5}  eta {}", pm(*e, *err));
            let _ = writeln!(csv, "{label},{r},{e},{err}");
        }
        panel = panel.with(
            Line::points_line(
                label,
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
            )
            .errors(pts.iter().map(|p| p.2).collect()),
        );
    }
    let csv_path = with_ext(&a.out, "csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let mut written = vec![csv_path];
    if !a.no_plot {
        written.extend(Figure::single(panel).save(&a.out)?);
    }
    print_written(&written);
    Ok(())
}
