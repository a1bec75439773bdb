//! `dpdnl analyze <mb|nemd|eh|msd|couette|flowcurve> FILES… [--out PREFIX]`: turn run outputs
//! (LAMMPS's or this engine's, same formats) into the papers' numbers. Each subcommand prints
//! a short summary and writes `PREFIX.json` (the numbers), `PREFIX.csv` (the curve or profile)
//! and `PREFIX.png` / `PREFIX.svg` (the figure). See docs/analysis.md. Equation numbers ("eq. 55")
//! are the non-linear paper's, NL-55 … in docs/models.md.

use dpdnl::plot::{Figure, Legend, Panel, Series as Line};
use dpdnl::report::{self, Table};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod maxwell;
mod pex;
mod shear;
mod transport;

use maxwell::run_mb;
use pex::run_nemd;
use shear::{run_couette, run_flow};
use transport::{run_eh, run_msd};

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

fn write_json(prefix: &Path, v: &Value) -> Result<PathBuf, String> {
    let p = with_ext(prefix, "json");
    std::fs::write(&p, report::to_pretty(v)?).map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(p)
}

/// Writes a result's table as a CSV with a header; non-finite values are written as `nan`.
fn write_csv(prefix: &Path, table: &Table) -> Result<PathBuf, String> {
    let p = with_ext(prefix, "csv");
    let n = table.iter().map(|c| c.1.len()).max().unwrap_or(0);
    let header: Vec<&str> = table.iter().map(|c| c.0).collect();
    let mut s = header.join(",");
    s.push('\n');
    for i in 0..n {
        let row: Vec<String> = table
            .iter()
            .map(|(_, c)| match c.get(i) {
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

/// `block 25x16, n_eff 180` for a blocked estimate, and when the error is not to be trusted,
/// `…, n_eff 6: a lower bound (series short for its correlation time)`.
fn blocking(b: &dpdnl::stats::BlockEstimate) -> String {
    let head = format!("block {}x{}, n_eff {:.0}", b.n_blocks, b.block_len, b.n_eff);
    if b.converged {
        head
    } else {
        format!("{head}: error is a lower bound, the series is short for its correlation time")
    }
}

fn print_written(files: &[PathBuf]) {
    let names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    println!("wrote {}", names.join(", "));
}

// ---------------------------------------------------------------- mb
