//! `mb`, `mb_pdf`: the Maxwell–Boltzmann check (`dpdnl analyze mb`).

use super::*;
use dpdnl::report::mb::{self as rmb, MbInput, MbParams};

/// The speed distribution against Maxwell–Boltzmann, as ``dpdnl analyze mb``
/// (non-linear paper eq. 53, in d dimensions).
///
/// Each ``fix ave/histo`` output, dump frame or array of ``speeds`` is one block of the error
/// analysis. Expected counts are the exact integrals of the Maxwell–Boltzmann density over the
/// bins; the χ² test merges bins until each expects ≥ 5 counts.
///
/// Args:
///     files: ``fix ave/histo`` files of the speed, or text dumps with ``vx vy [vz]``
///         columns (a path or a list of paths); None: give ``speeds``.
///     temp: the set temperature kT, an energy (lj: ε).
///     mass: the particle mass, mass units (lj: m).
///     dim: the dimension; None: 3 for histograms, for dumps 2 when there is no ``vz`` or
///         it is all 0, 3 for ``speeds``.
///     bins: dumps and ``speeds``: the number of bins on [0, vmax] (the paper: 150).
///     vmax: dumps and ``speeds``: upper end of the histogram, velocity units (lj: σ/τ);
///         None: 2·sqrt(10 kT/m), the paper's 2 at kT = 0.1.
///     from_step: skip dump frames and histogram outputs before this step.
///     speeds: instead of files, a list of 1-D arrays of speeds (velocity units), one per
///         frame or block.
///
/// Returns:
///     The dict ``dpdnl analyze mb`` writes to ``PREFIX.json``; energies in ε, speeds in σ/τ
///     (lj):
///
///     - ``analysis`` (``"mb"``), ``inputs`` (names of the inputs), ``source`` (what the
///       histogram came from), ``dim``, ``mass``, ``kt_set`` (= ``temp``);
///     - ``n_samples`` (speeds counted), ``n_blocks``, ``bins``, ``v_lo`` and ``v_hi``
///       (range of the histogram), ``outside`` and ``outside_expected`` (counts beyond it,
///       measured and expected);
///     - ``kt_fit``: maximum-likelihood kT of the counts; ``kt_fit_err_iid`` its error for
///       independent samples, ``kt_fit_err_blocks`` from the spread between blocks;
///       ``inefficiency`` = (err_blocks/err_iid)², correlated samples per independent one;
///     - ``chi2``, ``dof``, ``p_value``: Pearson χ² against ``temp``; ``p_value_corrected``
///       with χ² divided by the inefficiency; ``chi2_fit``, ``dof_fit``, ``p_value_fit``:
///       against ``kt_fit``;
///     - ``ks_d``, ``ks_p``: Kolmogorov–Smirnov distance of the cumulative distributions and
///       its probability for the independent samples;
///     - ``table``: per bin, arrays ``v_lo``, ``v_hi``, ``v_mid``, ``count``,
///       ``expected_count``, ``pdf`` and ``pdf_err`` (measured density, 1/velocity),
///       ``pdf_mb_set`` and ``pdf_mb_fit`` (Maxwell–Boltzmann at ``temp`` and at
///       ``kt_fit``), ``residual_sigma`` ((pdf − pdf_mb_set)/pdf_err).
///
/// Raises:
///     AnalysisError: no histogram or frame, both files and speeds, a bad parameter.
///     FormatError: an input is not an ave/histo file or a dump.
///     OSError: a file cannot be read.
///
/// Example:
///     >>> rng = np.random.default_rng(1)
///     >>> v = np.linalg.norm(rng.normal(0.0, 1.0, (20000, 3)), axis=1)  # kT = m = 1
///     >>> r = dpdnl.mb(speeds=[v[:10000], v[10000:]], temp=1.0)
///     >>> round(r["kt_fit"], 2), r["n_blocks"], len(r["table"]["pdf"])
///     (0.99, 2, 150)
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
    let mut input = MbInput::new(dim);
    for f in &files {
        let text = read_text(f)?;
        input
            .add_text(&f.display().to_string(), &text, from_step)
            .map_err(aerr)?;
    }
    if let Some(sp) = &speeds {
        if !files.is_empty() {
            return Err(aerr("give either files or speeds, not both".into()));
        }
        let samples = sp
            .iter()
            .map(|a| f64_vec(a, "speeds"))
            .collect::<PyResult<_>>()?;
        input.add_speeds(samples);
    }
    let p = MbParams {
        temp,
        mass,
        bins,
        vmax,
    };
    let m = rmb::analyze(input, &p).map_err(aerr)?;
    result(py, &m.json(), &m.table())
}

/// The Maxwell–Boltzmann speed density P(v) in d dimensions, the curve ``dpdnl analyze mb``
/// draws: P(v) = 2 (m/2kT)^(d/2) / Γ(d/2) · v^(d−1) exp(−m v²/2kT).
///
/// Args:
///     v: speeds, velocity units (lj: σ/τ), a 1-D float array.
///     temp: kT, an energy (lj: ε).
///     mass: the particle mass, mass units (lj: m).
///     dim: the dimension, 2 or 3.
///
/// Returns:
///     P at each speed of ``v``, 1/velocity units (lj: τ/σ); its integral over v ≥ 0 is 1.
///
/// Example:
///     >>> v = np.linspace(0.0, 10.0, 100001)
///     >>> p = dpdnl.mb_pdf(v, 1.0)
///     >>> round(float(np.sum(p) * (v[1] - v[0])), 6)
///     1.0
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
        .map(|&x| dpdnl::analysis::mb::mb_pdf(x, temp, mass, dim))
        .collect();
    arr(py, &out)
}
