//! Analysis of run outputs: what the papers measure, from the files LAMMPS's averaging fixes
//! (and this project's engine, in the same formats) write. Pure functions: text in, numbers
//! out; the `dpdnl analyze` command reads files, prints summaries, writes CSV/JSON and plots.
//!
//! - [`formats`]: readers for `fix ave/time` (scalar and vector mode), `fix ave/chunk`,
//!   `fix ave/histo`, and time series from ave/time files or log thermo output.
//! - [`mb`]: speed histograms against Maxwell–Boltzmann in d = 2, 3 (non-linear paper eq. 53):
//!   χ², Kolmogorov distance, fitted temperature.
//! - [`nemd`]: reverse NEMD with the modified PeX push: profiles, fits in the middle of each
//!   half, Π_xz (eq. 55), viscosity (eq. 56), T_d (eq. 58).
//! - [`eh`]: Einstein–Helfand viscosity (eq. 59) with its fit window and block error.
//! - [`msd`]: self-diffusion from the MSD and the Schmidt number.
//! - [`couette`]: Lees–Edwards Couette flow, η* = −⟨P_xy⟩/γ̇.
//! - [`special`], [`corr`]: incomplete gamma, χ² and Kolmogorov tails; all-origin MSD by FFT.
//!
//! Equations are numbered as in the papers ("eq. 55" is the non-linear paper's unless stated:
//! NL-55 in `docs/models.md`); `docs/analysis.md` describes the command line, defaults and output
//! columns.

pub mod corr;
pub mod couette;
pub mod eh;
pub mod formats;
pub mod mb;
pub mod msd;
pub mod nemd;
pub mod special;

/// `x > 0`, false for NaN: the check on every positive parameter.
pub(crate) fn is_pos(x: f64) -> bool {
    x > 0.0
}
