//! `dpdnl design` and `dpdnl theory`: the command-line face of [`dpdnl::theory`].
//!
//! Both print `key = value` lines (comments start with `#`) or, with `--json`, one JSON object.
//! Numbers are printed in Rust's shortest round-trip form, so pasting them back reproduces the
//! design bit for bit. Equation numbers are the papers' own: the weighting-function paper's
//! ("eqs. 52-53, 65", WF-52 … in `docs/models.md`) and the finite-step paper's (FS-22 …).

use dpdnl::fmtnum::fmt_g;
use dpdnl::report::theory::{
    self as rt, EulerBriefJson, InputLines, PairJson, RunJson, ScriptJson, fluid_in, neighbours,
    step_x,
};
use dpdnl::report::{short as num, to_line};
use dpdnl::theory::sdpd::Smoothing;
use dpdnl::theory::vv_measured::vv_verdict;
use dpdnl::theory::{
    Design, DesignMode, Dim, Fluid, STIFF_DT_C_FRACTION, StepScales, Transport, euler_critical_dt,
    euler_temperature_ratio, step_scales,
};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

mod script;

/// Choose γ and the weight exponent s from a target viscosity and Schmidt number.
///
/// By default the kinetic theory (ideal fluid, a = 0) is inverted exactly: the printed γ and s
/// give η and Sc. With `--paper-approx`, `--eta` is the dissipative viscosity η0 and `--sc` is Sc0
/// of the weighting-function paper, whose recipe assumes η ≈ η0 (eqs. 52–53, 65).
#[derive(clap::Args)]
pub struct DesignArgs {
    /// Target shear viscosity η (with --paper-approx: the paper's η0).
    #[arg(long, allow_negative_numbers = true)]
    eta: f64,
    /// Target Schmidt number Sc = η/(m n D) (with --paper-approx: the paper's Sc0).
    #[arg(long, allow_negative_numbers = true)]
    sc: f64,
    /// Number density n (particles per unit area in 2-D).
    #[arg(long, allow_negative_numbers = true)]
    density: f64,
    /// Cut-off radius r_c.
    #[arg(long, allow_negative_numbers = true)]
    rc: f64,
    /// Thermal energy kT.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    kt: f64,
    /// Unit style of the numbers (LAMMPS's `units`): lj, real, metal, si, cgs, micro or nano.
    /// Outside lj the mass
    /// is in the style's mass unit, viscosities in energy × time / volume (LAMMPS's native unit;
    /// −pxy/γ̇ of the thermo gives η × nktv2p), and T of the printed `pair_style` line is a
    /// temperature (kT = boltz T).
    #[arg(long, default_value = "lj")]
    units: String,
    /// Temperature T, instead of --kt: kT = boltz T of --units (T = kT in lj).
    #[arg(long, conflicts_with = "kt", allow_negative_numbers = true)]
    temp: Option<f64>,
    /// Particle mass m.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    mass: f64,
    /// Space dimension, 2 or 3.
    #[arg(long, default_value_t = 3, allow_negative_numbers = true)]
    dim: i64,
    /// Use the weighting-function paper's approximation η ≈ η0 (its Tables 4–5) instead of the
    /// exact inversion.
    #[arg(long)]
    paper_approx: bool,
    /// The seed written into the printed `pair_style` line.
    #[arg(long, default_value_t = 12345)]
    seed: u32,
    /// `dpd` (γ and the weight exponent of `pair_style dpd/nonlinear`) or `sdpd` (η0 and the
    /// proposed kernel's s of `pair_style sdpd`: the same kinetic theory, docs/models.md 3.7).
    #[arg(long, default_value = "dpd", value_parser = clap::builder::PossibleValuesParser::new(dpdnl::forces::design_methods()))]
    method: String,
    /// With --method sdpd: the sound speed c0 written into the printed `pair_coeff` line (the
    /// design does not choose it; without it the line holds the placeholder C0).
    #[arg(long, allow_negative_numbers = true)]
    c0: Option<f64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Print kinetic-theory predictions (and, with --dt, the Euler finite-step temperature).
#[derive(clap::Args)]
pub struct TheoryArgs {
    /// An input script: every `run` is set up (not run) and its parameters printed with the
    /// predictions (pair_coeff eta/sc targets resolved at the script's density).
    script: Option<PathBuf>,
    /// With SCRIPT: define an index-style variable NAME with VALUE (as LAMMPS's `-var`).
    #[arg(long = "var", num_args = 2, value_names = ["NAME", "VALUE"], action = clap::ArgAction::Append, allow_hyphen_values = true)]
    var: Vec<String>,
    /// Friction amplitude γ (`gamma0` of `pair_coeff`).
    #[arg(
        long,
        required_unless_present_any = ["script", "kernel"],
        allow_negative_numbers = true
    )]
    gamma: Option<f64>,
    /// Weight exponent s of w_D = (1 − r/r_c)^s (with --kernel proposed: the kernel's s).
    #[arg(
        long,
        required_unless_present_any = ["script", "kernel"],
        allow_negative_numbers = true
    )]
    s: Option<f64>,
    /// sDPD instead of DPD (`pair_style sdpd`): the kernel, lucy, quintic or proposed (with
    /// --s); give --eta0 instead of --gamma (docs/models.md 3.7, Table 1).
    #[arg(long)]
    kernel: Option<String>,
    /// With --kernel: the dissipative viscosity η0 (`eta0` of `pair_coeff … sdpd`).
    #[arg(long, allow_negative_numbers = true)]
    eta0: Option<f64>,
    /// Number density n (particles per unit area in 2-D).
    #[arg(
        long,
        required_unless_present = "script",
        allow_negative_numbers = true
    )]
    density: Option<f64>,
    /// Cut-off radius r_c.
    #[arg(
        long,
        required_unless_present = "script",
        allow_negative_numbers = true
    )]
    rc: Option<f64>,
    /// Thermal energy kT (the thermostat's kT0 for the Euler temperature).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    kt: f64,
    /// Unit style of the numbers (LAMMPS's `units`): lj (default), real, metal, si, cgs, micro
    /// or nano. Outside lj the mass is in the style's mass unit and viscosities in energy × time / volume (LAMMPS's
    /// native unit; −pxy/γ̇ of the thermo gives η × nktv2p). With SCRIPT the script's `units`
    /// decides (this option and --temp are refused).
    #[arg(long)]
    units: Option<String>,
    /// Temperature T, instead of --kt: kT = boltz T of --units (T = kT in lj).
    #[arg(long, conflicts_with = "kt", allow_negative_numbers = true)]
    temp: Option<f64>,
    /// Particle mass m.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    mass: f64,
    /// Space dimension, 2 or 3.
    #[arg(long, default_value_t = 3, allow_negative_numbers = true)]
    dim: i64,
    /// Time step δt: also print the Euler integrator's T_eq/T0, δt_c and n_c.
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// The unit style of `--units` (any of the standalone engine's), kT (from `--kt`, or boltz T with `--temp`)
/// and the T of a `pair_style` line.
fn units_kt(
    units: &str,
    kt: f64,
    temp: Option<f64>,
) -> Result<(dpdnl::Units, f64, f64), Box<dyn std::error::Error>> {
    let u = dpdnl::Units::standalone(units).map_err(|e| e.replace("units '", "--units '"))?;
    let kt = temp.map_or(kt, |t| u.kt(t));
    Ok((u, kt, temp.unwrap_or(kt / u.boltz)))
}

/// The line that says which units the numbers are in (nothing in lj).
fn units_text(out: &mut String, u: &dpdnl::Units, temp: f64) {
    if !u.is_lj() {
        let _ = writeln!(
            out,
            "# units {}: T = {} (kT = boltz T, boltz = {}), masses in the style's mass unit, \
             viscosities in energy x time / volume (the thermo's -pxy/rate is eta x nktv2p, \
             nktv2p = {}); mvv2e = {} converts m v^2 to energy",
            u.style,
            num(temp),
            num(u.boltz),
            num(u.nktv2p),
            num(u.mvv2e)
        );
    }
}

fn transport_text(out: &mut String, t: &Transport) {
    let _ = writeln!(out, "eta_K = {}", num(t.eta_k));
    let _ = writeln!(out, "eta_D = {}", num(t.eta_d));
    let _ = writeln!(out, "eta = {}", num(t.eta));
    let _ = writeln!(out, "D = {}", num(t.diffusion));
    let _ = writeln!(out, "Sc = {}", num(t.schmidt));
}

/// `dpdnl theory --kernel …`: the sDPD kinetic theory of one kernel and η0.
fn sdpd_theory(a: &TheoryArgs, name: &str) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let kernel = match name {
        "lucy" => Smoothing::Lucy,
        "quintic" => Smoothing::Quintic,
        "proposed" => {
            let s = a.s.ok_or("--kernel proposed needs --s")?;
            Smoothing::proposed(s).ok_or_else(|| format!("--s {s} must be > 0"))?
        }
        o => return Err(format!("--kernel '{o}' must be lucy, quintic or proposed").into()),
    };
    if a.gamma.is_some() {
        return Err("--gamma is DPD's: with --kernel give --eta0".into());
    }
    let eta0 = a.eta0.ok_or("--kernel needs --eta0")?;
    let density = a.density.ok_or("--density is required")?;
    let rc = a.rc.ok_or("--rc is required")?;
    let (u, kt, temp) = units_kt(a.units.as_deref().unwrap_or("lj"), a.kt, a.temp)?;
    let fluid = fluid_in(&u, a.dim, density, rc, a.mass, kt)?;
    let th = rt::sdpd_theory(fluid, kernel, eta0)?;
    if a.json {
        println!("{}", to_line(&th.json())?);
        return Ok(ExitCode::SUCCESS);
    }
    let (c, t, eta_min) = (th.c, &th.predicted, th.eta_min);
    let mut out = String::new();
    units_text(&mut out, &u, temp);
    let _ = writeln!(
        out,
        "# fluid: d = {}, n = {}, r_c = {}, m = {}, kT = {}; sDPD kernel {kernel}, eta0 = {}",
        fluid.dim.get(),
        num(fluid.density),
        num(fluid.cutoff),
        num(fluid.mass),
        num(fluid.kt),
        num(eta0)
    );
    let _ = writeln!(
        out,
        "# kinetic theory of sDPD (docs/models.md 3.7, Table 1): eta = c m kT n^2 r_c^2 / eta0 + eta0"
    );
    let _ = writeln!(out, "c = {}", num(c));
    transport_text(&mut out, t);
    let _ = writeln!(
        out,
        "# the smallest viscosity of this kernel here, 2 sqrt(c m kT n^2 r_c^2) (eqs. 31, 50, 64)"
    );
    let _ = writeln!(out, "eta_min = {}", num(eta_min));
    if a.dt.is_some() {
        let _ = writeln!(
            out,
            "# --dt: the Euler finite-step theory is DPD's (a pair friction without densities); none for sDPD"
        );
    }
    print!("{out}");
    Ok(ExitCode::SUCCESS)
}

/// Why a design whose γ needs an impractically small step cannot be run ([`StepScales::stiff`]).
fn stiff_warning(gamma: f64, s: f64, t: &StepScales) -> String {
    format!(
        "gamma = {} (s = {}) is huge: it needs a time step below dt_c = {}, where the Euler \
         integrator goes unstable (finite-step paper eq. 25; velocity-Verlet has no closed form \
         but treats the friction explicitly too), and below the velocity relaxation time \
         m D/kT = {}, against r_c sqrt(m/kT) = {} for a particle to cross the cut-off at \
         thermal speed: over {} steps per crossing. Raise eta (at fixed Sc, gamma falls as eta \
         grows) for a design that can be run (this warning: dt_c < {} r_c sqrt(m/kT))",
        fmt_g(gamma),
        fmt_g(s),
        fmt_g(t.dt_c),
        fmt_g(t.tau),
        fmt_g(t.t0),
        fmt_g((t.t0 / t.dt_c).floor()),
        fmt_g(STIFF_DT_C_FRACTION)
    )
}

/// `dpdnl design`.
pub fn design_main(a: DesignArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let (u, kt, temp) = units_kt(&a.units, a.kt, a.temp)?;
    let fluid = fluid_in(&u, a.dim, a.density, a.rc, a.mass, kt)?;
    let lines = InputLines::of(&a.method, a.c0)
        .ok_or_else(|| format!("--method '{}' designs no pair style", a.method))?;
    let res = rt::design_at(fluid, temp, a.eta, a.sc, a.paper_approx, a.seed, lines)?;
    let design = &res.design;
    let scales = step_scales(&fluid, design.gamma, design.s)?;
    if scales.stiff() {
        eprintln!(
            "WARNING: {}",
            stiff_warning(design.gamma, design.s, &scales)
        );
    }
    let (style, coeff) = (&res.pair_style, &res.pair_coeff);
    let d = fluid.dim.get();
    let eqs = match fluid.dim {
        Dim::Three => "eqs. 54-55",
        Dim::Two => "eqs. 63-64",
    };
    let mut out = String::new();
    if a.json {
        println!("{}", to_line(&res.json())?);
        return Ok(ExitCode::SUCCESS);
    }
    units_text(&mut out, &u, temp);
    let _ = writeln!(
        out,
        "# fluid: d = {d}, n = {}, r_c = {}, m = {}, kT = {} (ideal fluid, a = 0)",
        num(fluid.density),
        num(fluid.cutoff),
        num(fluid.mass),
        num(fluid.kt)
    );
    match design.mode {
        DesignMode::Exact => {
            let _ = writeln!(
                out,
                "# design: exact inversion of the kinetic theory (docs/models.md 3.4) for eta = {}, Sc = {}",
                num(a.eta),
                num(a.sc)
            );
        }
        DesignMode::PaperApprox => {
            let _ = writeln!(
                out,
                "# design: the weighting-function paper's APPROXIMATION eta ~ eta0 (eqs. 52-53, 65)\n\
                 # for eta0 = {}, Sc0 = {}; kinetic theory then gives eta = eta0 (1 + 1/(2 Sc0)) and\n\
                 # Sc = Sc0 + 1/2 (see the check below); drop --paper-approx for the exact inversion",
                num(a.eta),
                num(a.sc)
            );
        }
    }
    let _ = writeln!(out, "eta0 = {}", num(design.eta0));
    let _ = writeln!(out, "s = {}", num(design.s));
    let check = lines.method.check(design, &fluid)?;
    for (k, v) in &check.values {
        let _ = writeln!(out, "{k} = {}", num(*v));
    }
    let _ = writeln!(out, "# {}", check.title);
    transport_text(&mut out, &check.predicted);
    limits_text(&mut out, design, d, eqs);
    let _ = writeln!(out, "# {}", lines.method.lines_note());
    let _ = writeln!(out, "{style}");
    let _ = writeln!(out, "{coeff}");
    print!("{out}");
    Ok(ExitCode::SUCCESS)
}

/// The `# limits` part of `dpdnl design`: P, P0 and the bounds that keep s > 0.
fn limits_text(out: &mut String, design: &Design, d: u32, eqs: &str) {
    let lim = &design.limits;
    let _ = writeln!(
        out,
        "# limits: s > 0 <=> P_{d}(s) > P_{d}(0) ({}{eqs}); P is the paper's C",
        if design.mode == DesignMode::Exact {
            "exact form of "
        } else {
            ""
        }
    );
    let _ = writeln!(out, "P = {}", num(lim.p));
    let _ = writeln!(out, "P0 = {}", num(lim.p0));
    match design.mode {
        DesignMode::Exact => {
            let _ = writeln!(out, "# largest eta for this Sc; smallest Sc for this eta");
            let _ = writeln!(out, "eta_max = {}", num(lim.eta_max));
            let _ = writeln!(out, "Sc_min = {}", num(lim.sc_min));
            if let Some(gas) = lim.sc_gas_max {
                let _ = writeln!(
                    out,
                    "# a gas-like design (eta_K > eta_D) also exists for 0.5 < Sc < Sc_gas_max"
                );
                let _ = writeln!(out, "Sc_gas_max = {}", num(gas));
            }
        }
        DesignMode::PaperApprox => {
            let _ = writeln!(
                out,
                "# largest eta0 for this Sc0; smallest Sc0 for this eta0"
            );
            let _ = writeln!(out, "eta0_max = {}", num(lim.eta_max));
            let _ = writeln!(out, "Sc0_min = {}", num(lim.sc_min));
        }
    }
    let _ = writeln!(
        out,
        "# smallest density and cut-off with the other inputs fixed"
    );
    let _ = writeln!(out, "n_min = {}", num(lim.density_min));
    let _ = writeln!(out, "rc_min = {}", num(lim.cutoff_min));
}

/// `dpdnl theory`.
pub fn theory_main(a: TheoryArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    if let Some(p) = &a.script {
        if a.units.is_some() || a.temp.is_some() {
            return Err(
                "with SCRIPT the script's `units` line sets the units: give no --units or \
                        --temp"
                    .into(),
            );
        }
        return script::theory_of_script(p, &a);
    }
    if let Some(k) = a.kernel.clone() {
        return sdpd_theory(&a, &k);
    }
    let gamma = a.gamma.ok_or("--gamma is required")?;
    let s = a.s.ok_or("--s is required")?;
    let density = a.density.ok_or("--density is required")?;
    let rc = a.rc.ok_or("--rc is required")?;
    let (u, kt, temp) = units_kt(a.units.as_deref().unwrap_or("lj"), a.kt, a.temp)?;
    let fluid = fluid_in(&u, a.dim, density, rc, a.mass, kt)?;
    let th = rt::theory(fluid, gamma, s, a.dt)?;
    if a.json {
        println!("{}", to_line(&th.json())?);
        return Ok(ExitCode::SUCCESS);
    }
    let t = &th.predicted;
    let mut out = String::new();
    units_text(&mut out, &u, temp);
    let _ = writeln!(
        out,
        "# fluid: d = {}, n = {}, r_c = {}, m = {}, kT = {}; gamma = {}, s = {}",
        fluid.dim.get(),
        num(fluid.density),
        num(fluid.cutoff),
        num(fluid.mass),
        num(fluid.kt),
        num(gamma),
        num(s)
    );
    let _ = writeln!(
        out,
        "# kinetic theory of the ideal fluid (a = 0), w_D = (1 - r/r_c)^s (docs/models.md 3.2)"
    );
    transport_text(&mut out, t);
    if let Some(rt::Euler {
        dt,
        t_ratio: ratio,
        dt_c,
        n_c,
        ..
    }) = th.euler
    {
        let _ = writeln!(
            out,
            "# Euler integrator, ideal fluid (finite-step paper eqs. 22-26; sigma^2 = 2 gamma kT, w_R^2 = w_D)"
        );
        let _ = writeln!(out, "dt = {}", num(dt));
        match ratio {
            Some(r) => {
                let _ = writeln!(out, "T_eq/T0 = {}", num(r));
            }
            None => {
                let _ = writeln!(out, "# dt >= dt_c: no finite equilibrium temperature");
                let _ = writeln!(out, "T_eq/T0 = unstable");
            }
        }
        let _ = writeln!(out, "dt_c = {}", num(dt_c));
        match n_c {
            Some(n) => {
                let _ = writeln!(out, "n_c = {}", num(n));
            }
            None => {
                let _ = writeln!(out, "# dt >= 2 A1/A2: no density is stable at this dt");
                let _ = writeln!(out, "n_c = none");
            }
        }
        let _ = writeln!(
            out,
            "# velocity-Verlet: the finite-step paper gives no closed form; none is computed"
        );
    }
    print!("{out}");
    Ok(ExitCode::SUCCESS)
}

/// The measured velocity-Verlet heating (issue 14 section 4; `dpdnl::theory::vv_measured`) of
/// the family nearest to `fluid` (weight exponent `s`, friction `gamma`) at step `dt`: labelled
/// as a measurement, never as theory.
fn vv_text(out: &mut String, fluid: &Fluid, s: f64, gamma: f64, dt: f64, dt_c: f64) {
    let dim = match fluid.dim {
        Dim::Two => 2,
        Dim::Three => 3,
    };
    let x = step_x(fluid, dt);
    let _ = writeln!(
        out,
        "# velocity-Verlet (fix nve): no closed form; MEASURED, not theory (validation/finite_step, \
         velocity-Verlet section), on the measured fluid nearest to this one, against \
         x = dt sqrt(kT/m)/r_c (a thermal particle's step in cut-offs)"
    );
    let Some(v) = vv_verdict(dim, neighbours(fluid), s, x) else {
        let _ = writeln!(out, "# no measurement of a {dim}-D fluid");
        return;
    };
    let _ = writeln!(
        out,
        "# measured family: {} (n = {}, {} neighbours within r_c, s = {}, gamma = {}; this \
         fluid: {} neighbours, s = {}, gamma = {})",
        v.family,
        num(v.density),
        num((v.neighbours * 10.0).round() / 10.0),
        num(v.s),
        fmt_g(v.gamma),
        num((neighbours(fluid) * 10.0).round() / 10.0),
        num(s),
        fmt_g(gamma)
    );
    if v.s != s {
        let _ = writeln!(
            out,
            "# CAUTION: this fluid's weight exponent differs from the family's: a rough indication \
             only; measure this fluid (validation/finite_step/README.md)"
        );
    }
    let pts: Vec<String> = v
        .points
        .iter()
        .map(|(x, y, e)| format!("{}: {} +- {}", fmt_g(*x), num(*y), num(*e)))
        .collect();
    let _ = writeln!(out, "# measured T/T0 at x = {}", pts.join("; "));
    let _ = writeln!(out, "x = {}", num(x));
    let _ = writeln!(out, "dt/dt_c = {}", num(dt / dt_c));
    match v.t_ratio {
        Some(t) => {
            let _ = writeln!(
                out,
                "T/T0 (velocity-Verlet, measured, interpolated) = {}",
                num((t * 1e4).round() / 1e4)
            );
        }
        None => {
            let _ = writeln!(
                out,
                "T/T0 (velocity-Verlet, measured) = beyond the measured range"
            );
        }
    }
    let dt_of = |x1: f64| x1 * fluid.cutoff / (fluid.kt / fluid.inertia()).sqrt();
    let verdict = match (v.one_percent_at, v.t_ratio) {
        (Some(x1), _) if x >= x1 => format!(
            "heating >= 1 % (measured: the family reaches 1 % at x = {}, i.e. dt = {} here; take a \
             smaller dt)",
            fmt_g(x1),
            fmt_g(dt_of(x1))
        ),
        (Some(x1), _) => format!(
            "heating < 1 % (measured: the family reaches 1 % at x = {}, i.e. dt = {} here)",
            fmt_g(x1),
            fmt_g(dt_of(x1))
        ),
        (None, Some(_)) => "heating < 1 % over the whole measured range (measured)".to_string(),
        (None, None) => "beyond the measured range: no verdict".to_string(),
    };
    let _ = writeln!(
        out,
        "velocity-Verlet verdict (measured, not theory): {verdict}"
    );
}
