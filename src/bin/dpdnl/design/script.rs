//! `dpdnl theory SCRIPT`: the theory of every planned run of a script.

use super::*;
use dpdnl::engine::{Integrator, SetupNote};
use dpdnl::forces::{PairPlan, PlanPoint};
use dpdnl::input::{Collect, Interpreter, Options, PlannedRun};

/// `dpdnl theory SCRIPT`: set up every `run` of the script without running it and print, for
/// each, the state point, the kinetic theory of each type pair (ideal fluid, a = 0) and the Euler
/// finite-step temperature (or that velocity-Verlet has no closed form).
pub(super) fn theory_of_script(
    path: &std::path::Path,
    a: &TheoryArgs,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let runs = planned_runs(path, a)?;
    let mut out = String::new();
    let mut json_runs = Vec::new();
    for (k, r) in runs.iter().enumerate() {
        json_runs.push(run_theory(&mut out, k, runs.len(), r)?);
    }
    if a.json {
        let j = ScriptJson {
            command: "theory",
            script: path.display().to_string(),
            runs: json_runs,
        };
        println!("{}", to_line(&j)?);
    } else {
        print!("{out}");
    }
    Ok(ExitCode::SUCCESS)
}

/// The runs of the script at `path`, set up without running (an error when it has none).
fn planned_runs(
    path: &std::path::Path,
    a: &TheoryArgs,
) -> Result<Vec<PlannedRun>, Box<dyn std::error::Error>> {
    let vars = crate::var_pairs(&a.var);
    let opts = Options {
        vars,
        ..Options::default()
    };
    let mut console = Collect::default();
    let mut interp = Interpreter::new(&mut console, &opts)?;
    interp.set_dry_run(true);
    interp.run_file(path)?;
    let runs = interp.planned_runs().to_vec();
    drop(interp);
    if runs.is_empty() {
        return Err(format!("{}: the script has no 'run' command", path.display()).into());
    }
    Ok(runs)
}

/// The state point of one planned run, as the theory sees it.
struct RunPoint<'a> {
    r: &'a PlannedRun,
    /// n = N/V.
    density: f64,
    /// The lightest mass.
    m: f64,
    /// The run's unit style.
    units: dpdnl::Units,
    scheme: &'static str,
}

/// Run `k` of `nruns`: its lines in `out`, its JSON record.
fn run_theory(
    out: &mut String,
    k: usize,
    nruns: usize,
    r: &PlannedRun,
) -> Result<RunJson, Box<dyn std::error::Error>> {
    let density = r.natoms as f64 / r.volume;
    let masses: Vec<f64> = r.masses.iter().skip(1).copied().collect();
    let m = masses.iter().copied().fold(f64::INFINITY, f64::min);
    let scheme = match r.integrator {
        Some(Integrator::Euler) => "euler (fix nve/euler)",
        Some(Integrator::VelocityVerlet) => "velocity-Verlet (fix nve)",
        None => "none",
    };
    let p = RunPoint {
        r,
        density,
        m,
        units: r.units,
        scheme,
    };
    run_header(out, k, nruns, &p, &masses);
    let at = PlanPoint {
        dim: r.dim,
        density,
        mass: m,
        mvv2e: r.units.mvv2e,
    };
    let mut pairs_json = Vec::new();
    for pair in r.plan.pairs(&at)? {
        if let Some(json) = pair_theory(out, &p, &pair)? {
            pairs_json.push(json);
        }
    }
    Ok(RunJson {
        first_step: r.first_step,
        steps: r.steps,
        dim: r.dim,
        natoms: r.natoms,
        density,
        kt: r.plan.kt(),
        dt: r.dt,
        integrator: scheme.to_string(),
        s: r.plan.weight_exponent(),
        pairs: pairs_json,
    })
}

/// The first lines of a run: its state point, a note when the masses differ, its set-up notes.
fn run_header(out: &mut String, k: usize, nruns: usize, p: &RunPoint<'_>, masses: &[f64]) {
    let RunPoint {
        r,
        density,
        m,
        units,
        scheme,
    } = *p;
    let _ = writeln!(
        out,
        "# run {} of {}: steps {}..{}, d = {}, N = {}, n = N/V = {}, kT = {}, dt = {}, \
         integrator {scheme}, {}",
        k + 1,
        nruns,
        r.first_step,
        r.first_step + r.steps,
        r.dim,
        r.natoms,
        num(density),
        r.plan.kt().map_or("none".to_string(), num),
        num(r.dt),
        r.plan
            .summary()
            .unwrap_or_else(|| format!("pair_style {}", r.style))
    );
    if !units.is_lj() {
        let _ = writeln!(
            out,
            "# units {}: kT = boltz T (an energy), masses in the style's mass unit, viscosities in \
             energy x time / volume (the thermo's -pxy/rate is eta x nktv2p, nktv2p = {}); the \
             theory takes m mvv2e, mvv2e = {}",
            units.style,
            num(units.nktv2p),
            num(units.mvv2e)
        );
    }
    if masses.iter().any(|&x| x != m) {
        let _ = writeln!(
            out,
            "# masses differ between types; the one-mass kinetic theory below uses the lightest, m = {}",
            num(m)
        );
    }
    for note in &r.notes {
        match note {
            SetupNote::Info(t) => {
                let _ = writeln!(out, "# {t}");
            }
            SetupNote::Warning(t) => {
                let _ = writeln!(out, "# WARNING: {t}");
            }
        }
    }
}

/// One type pair of a run's plan: its lines in `out`, its JSON record (None without a
/// prediction).
fn pair_theory(
    out: &mut String,
    p: &RunPoint<'_>,
    pair: &PairPlan,
) -> Result<Option<PairJson>, Box<dyn std::error::Error>> {
    let coeffs: Vec<String> = pair
        .coeffs
        .iter()
        .map(|(k, v)| format!("{k} = {}", num(*v)))
        .collect();
    let _ = writeln!(
        out,
        "# pair {} {}{}: {}",
        pair.i,
        pair.j,
        pair.label
            .as_ref()
            .map_or(String::new(), |l| format!(" ({l})")),
        coeffs.join(", ")
    );
    let theory = match &pair.theory {
        Ok(t) => t,
        Err(why) => {
            let _ = writeln!(out, "# {why}");
            return Ok(None);
        }
    };
    let _ = writeln!(out, "# {}", theory.title);
    transport_text(out, &theory.predicted);
    let finite_step = match theory.finite_step {
        Some((gamma0, s)) => Some(finite_step(out, p, &theory.fluid, gamma0, s)?),
        None => None,
    };
    Ok(Some(PairJson::new(pair, theory, finite_step)))
}

/// The finite-step part of a pair whose friction is DPD's γ0 w_D (w_D = (1 − r/r_c)^s): the
/// Euler temperature under `fix nve/euler`, the measured heating under velocity-Verlet.
fn finite_step(
    out: &mut String,
    p: &RunPoint<'_>,
    fluid: &Fluid,
    gamma0: f64,
    s: f64,
) -> Result<(Option<EulerBriefJson>, Option<rt::VvJson>), Box<dyn std::error::Error>> {
    let r = p.r;
    let dt_c = euler_critical_dt(fluid, gamma0, s)?;
    if r.integrator == Some(Integrator::Euler) {
        let ratio = euler_temperature_ratio(fluid, gamma0, s, r.dt).ok();
        let _ = writeln!(
            out,
            "# Euler integrator, ideal fluid (finite-step paper eqs. 22, 25)"
        );
        match ratio {
            Some(x) => {
                let _ = writeln!(out, "T_eq/T0 = {}", num(x));
            }
            None => {
                let _ = writeln!(out, "T_eq/T0 = unstable");
            }
        }
        let _ = writeln!(out, "dt_c = {}", num(dt_c));
        let _ = writeln!(out, "dt/dt_c = {}", num(r.dt / dt_c));
        Ok((
            Some(EulerBriefJson {
                t_ratio: ratio,
                dt_c,
            }),
            None,
        ))
    } else {
        vv_text(out, fluid, s, gamma0, r.dt, dt_c);
        Ok((None, Some(rt::vv_json(fluid, s, r.dt, dt_c))))
    }
}
