//! `nemd`: reverse NEMD with the PeX push (`dpdnl analyze nemd`).

use super::*;
use dpdnl::report::nemd::{self as rnemd, NemdParams};

/// The viscosity of reverse NEMD with the PeX push (``fix pex/push``), as ``dpdnl analyze
/// nemd``: profiles, the fits of v_z(x) in the middle of each half, the stress Π_xz (non-linear
/// paper eq. 55), the viscosity μ = Π_xz / shear rate (eq. 56) and T_d (eq. 58).
///
/// The stress is nominal, dp / (2 Ly Lz every dt), with ``dp``, or measured from the pushed
/// total with ``push`` (then skipped exchanges are accounted for); give one of the two.
///
/// Args:
///     profile: the ``fix ave/chunk`` file of the profiles (``bin/1d`` along x, ``units box``),
///         with a v_z column and, optionally, the number density and T_d.
///     box: the box lengths (Lx, Ly, Lz), distance units (lj: σ).
///     dt: the time step, time units (lj: τ).
///     xlo: the lower x bound of the box, distance units; None: from the bins, when they
///         tile [xlo, xlo + Lx).
///     dp: the momentum of one push (``fix pex/push`` dp), mass·velocity (lj: m σ/τ), for the
///         nominal stress.
///     every: steps between pushes (``fix pex/push`` every).
///     push: a log or ``fix ave/time`` file, or a series dict, holding the pushed total
///         ``f_ID``; the stress is then the fitted rate of that total.
///     push_col: the column of the total in ``push``; None: the only column starting with
///         ``f_``.
///     from_step: use only outputs at or after this step (the steady state).
///     fit_fraction: the fraction of each half, centred between the slabs, that the fit uses.
///     vz_col: the profile's v_z column.
///     density_col: the profile's number-density column (if absent: Ncount per bin volume).
///     td_col: the profile's column of the per-particle mean of (p_x² + p_y²)/2m, k_B T_d
///         (eq. 58); if absent, no T_d.
///     label: the label of this result in :func:`flowcurve`; None: the profile's file name
///         without its extension.
///
/// Returns:
///     The dict ``dpdnl analyze nemd`` writes to ``PREFIX.json`` (units: lj):
///
///     - ``analysis`` (``"nemd"``), ``label``, ``input``, ``box``, ``xlo``, ``dt``,
///       ``from_step``, ``n_outputs``, ``first_step``, ``last_step``, ``fit_fraction``;
///     - ``stress``, ``stress_err``: Π_xz, momentum per area and time (lj: ε/σ³);
///       ``stress_source`` (nominal or measured from which column), ``stress_nominal``
///       (dp/(2 Ly Lz every dt), or None without ``dp``);
///     - ``shear_rate``, ``shear_rate_err`` (1/time), ``shear_rate_blocks``,
///       ``shear_rate_converged`` (False: too few blocks at the chosen level, so the error is a
///       lower bound; docs/analysis.md, "How the errors are formed"), ``shear_rate_n_eff``
///       (the effective number of independent samples behind the error);
///     - ``viscosity``, ``viscosity_err``: μ, mass/(distance·time) (lj: m/(σ τ));
///     - ``density_centre``, ``density_centre_err`` (1/volume) and ``td_centre``,
///       ``td_centre_err`` (energy; None without T_d): averaged over the fit windows;
///       ``density_source``, ``td_source``: the columns used;
///     - ``halves``: for ``central`` and ``outer``, ``name``, ``window`` ([lo, hi], distance),
///       ``bins`` (count), ``slope`` and ``slope_err`` (block-averaged, 1/time),
///       ``slope_fit_mean_profile``, ``slope_fit_err_regression``, ``intercept``, ``r2``
///       (the fit of the mean profile);
///     - ``table``: per bin, arrays ``x``, ``vz``, ``vz_err``, ``vz_fit`` (NaN outside the
///       windows), ``td``, ``td_err``, ``density``, ``density_err``.
///
/// Raises:
///     AnalysisError: neither ``dp`` nor ``push``, a missing column, too few outputs.
///     FormatError: the profile is not an ave/chunk file.
///     OSError: a file cannot be read.
///
/// Example:
///     >>> sim = dpdnl.Simulation()
///     >>> sim.commands([
///     ...     "region box block 0 8 0 4 0 4", "create_box 1 box",
///     ...     "create_atoms 1 random 384 8675 box", "mass 1 1.0",
///     ...     "velocity all create 1.0 4928 mom yes",
///     ...     "pair_style dpd/nonlinear 1.0 1.0 7919", "pair_coeff * * 0.0 4.5 0.0",
///     ...     "fix 1 all nve", "timestep 0.01",
///     ...     "fix push all pex/push 0.05",
///     ...     "compute slab all chunk/atom bin/1d x lower 0.4 units box",
///     ...     "fix prof all ave/chunk 10 10 100 slab vz density/number file prof.chunk",
///     ...     "thermo 100", "thermo_style custom step temp f_push",
///     ... ])
///     >>> sim.run(2000)
///     >>> r = dpdnl.nemd("prof.chunk", box=(8, 4, 4), dt=0.01, dp=0.05, from_step=500)
///     >>> r["stress"], r["n_outputs"], [h["name"] for h in r["halves"]]
///     (0.15625, 16, ['central', 'outer'])
///     >>> m = dpdnl.nemd("prof.chunk", box=(8, 4, 4), dt=0.01, push=sim.thermo[-1],
///     ...                from_step=500)
///     >>> m["stress_source"].startswith("measured")
///     True
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
    let text = read_text(&profile)?;
    let p = NemdParams {
        r#box,
        xlo,
        dt,
        dp,
        every,
        push_col,
        from: from_step,
        fit_fraction,
        vz_col: vz_col.into(),
        density_col: density_col.into(),
        td_col: td_col.into(),
    };
    let prof = rnemd::profiles(&pname, &text, &p).map_err(aerr)?;
    let push = match &push {
        Some(s) => {
            let (s, name) = series_arg(s)?;
            Some((name, s))
        }
        None => None,
    };
    let label = label.unwrap_or_else(|| report::stem(&profile, "nemd"));
    let n = rnemd::analyze(prof, push, &p, label).map_err(aerr)?;
    result(py, &n.json(), &n.table())
}
