//! `dpdnl theory SCRIPT`: the theory of every planned run of a script.

use super::*;
use dpdnl::engine::{Integrator, SetupNote};
use dpdnl::forces::dpd::kernel::PairCoeff;
use dpdnl::input::script::PlannedSdpd;
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
    /// The weight exponent.
    s: f64,
    kt: f64,
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
    let s = r.model.weight.exponent();
    let kt = r.model.kt;
    let scheme = match r.integrator {
        Some(Integrator::Euler) => "euler (fix nve/euler)",
        Some(Integrator::VelocityVerlet) => "velocity-Verlet (fix nve)",
        None => "none",
    };
    let p = RunPoint {
        r,
        density,
        m,
        s,
        kt,
        units: r.units,
        scheme,
    };
    run_header(out, k, nruns, &p, &masses);
    let mut pairs_json = Vec::new();
    if let Some(sd) = &r.sdpd {
        sdpd_pairs(out, &p, sd, &mut pairs_json)?;
    }
    for (i, j, c) in &r.coeffs {
        if let Some(pair) = dpd_pair(out, &p, (*i, *j, c))? {
            pairs_json.push(pair);
        }
    }
    Ok(RunJson {
        first_step: r.first_step,
        steps: r.steps,
        dim: r.dim,
        natoms: r.natoms,
        density,
        kt,
        dt: r.dt,
        integrator: scheme.to_string(),
        s,
        pairs: pairs_json,
    })
}

/// The first lines of a run: its state point, a note when the masses differ, its set-up notes.
fn run_header(out: &mut String, k: usize, nruns: usize, p: &RunPoint<'_>, masses: &[f64]) {
    let RunPoint {
        r,
        density,
        m,
        s,
        kt,
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
        num(kt),
        num(r.dt),
        match &r.sdpd {
            Some(sd) => format!("pair_style sdpd, kernel {}", sd.kernel),
            None => format!(
                "friction {}, noise {}, weight s = {}",
                r.model.friction.keyword(),
                r.model.noise.keyword(),
                num(s)
            ),
        }
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

/// The sDPD type pairs of a run: their lines in `out`, their JSON records in `pairs_json`.
fn sdpd_pairs(
    out: &mut String,
    pt: &RunPoint<'_>,
    sd: &PlannedSdpd,
    pairs_json: &mut Vec<PairJson>,
) -> Result<(), Box<dyn std::error::Error>> {
    let RunPoint {
        r,
        density,
        m,
        units,
        ..
    } = *pt;
    for (i, j, p) in &sd.pairs {
        let _ = writeln!(
            out,
            "# pair {i} {j} (sdpd, kernel {}): rho0 = {}, c0 = {}, eta0 = {}, rc = {}",
            sd.kernel,
            num(p.rho0),
            num(p.c0),
            num(p.eta0),
            num(p.rc)
        );
        let fluid = Fluid::new(r.dim, density, p.rc, m, sd.kt)?.with_mvv2e(units.mvv2e)?;
        let t = sdpd::kinetic_theory(&fluid, sd.kernel, p.eta0)?;
        let _ = writeln!(
            out,
            "# kinetic theory of sDPD (docs/models.md 3.7, Table 1; the Tait pressure adds a \
             conservative viscosity not in it)"
        );
        transport_text(out, &t);
        pairs_json.push(PairJson::Sdpd {
            i: *i,
            j: *j,
            rho0: p.rho0,
            c0: p.c0,
            eta0: p.eta0,
            rc: p.rc,
            kernel: sd.kernel.keyword(),
            fluid: (&fluid).into(),
            predicted: (&t).into(),
        });
    }
    Ok(())
}

/// One DPD type pair of a run: its lines in `out`, its JSON record (None without
/// dissipation, γ0 = 0).
fn dpd_pair(
    out: &mut String,
    p: &RunPoint<'_>,
    (i, j, c): (usize, usize, &PairCoeff),
) -> Result<Option<PairJson>, Box<dyn std::error::Error>> {
    let RunPoint {
        r,
        density,
        m,
        s,
        kt,
        units,
        ..
    } = *p;
    let _ = writeln!(
        out,
        "# pair {i} {j}: a = {}, gamma0 = {}, gamma1 = {}, rc = {}",
        num(c.a),
        num(c.gamma0),
        num(c.gamma1),
        num(c.rc)
    );
    if c.gamma0 <= 0.0 {
        let _ = writeln!(out, "# gamma0 = 0: no dissipation, no kinetic theory");
        return Ok(None);
    }
    let fluid = Fluid::new(r.dim, density, c.rc, m, kt)?.with_mvv2e(units.mvv2e)?;
    let t = kinetic_theory(&fluid, c.gamma0, s)?;
    let _ = writeln!(
        out,
        "# kinetic theory of the ideal fluid, w_D = (1 - r/r_c)^s (docs/models.md 3.2){}{}",
        if c.a != 0.0 {
            "; a != 0 adds a conservative viscosity not in it"
        } else {
            ""
        },
        if c.gamma1 != 0.0 {
            "; gamma0 only: the zero-shear limit of the non-linear friction"
        } else {
            ""
        }
    );
    transport_text(out, &t);
    let (euler_json, vv_json_text) = match r.integrator {
        Some(Integrator::Euler) => {
            let dt_c = euler_critical_dt(&fluid, c.gamma0, s)?;
            let ratio = euler_temperature_ratio(&fluid, c.gamma0, s, r.dt).ok();
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
            (
                Some(EulerBriefJson {
                    t_ratio: ratio,
                    dt_c,
                }),
                None,
            )
        }
        _ => {
            let dt_c = euler_critical_dt(&fluid, c.gamma0, s)?;
            vv_text(out, &fluid, s, c.gamma0, r.dt, dt_c);
            (None, Some(rt::vv_json(&fluid, s, r.dt, dt_c)))
        }
    };
    Ok(Some(PairJson::Dpd {
        i,
        j,
        a: c.a,
        gamma0: c.gamma0,
        gamma1: c.gamma1,
        rc: c.rc,
        fluid: (&fluid).into(),
        predicted: (&t).into(),
        euler: euler_json,
        vv_measured: vv_json_text,
    }))
}
