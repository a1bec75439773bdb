//! `velocity`: `create` (random draws keyed by atom tag), `set`, `ramp`, `zero`, `scale`.

use super::{CmdResult, Interpreter};
use crate::engine::System;
use crate::grammar::{need, parse_f64, parse_int};
use crate::rng::{STREAM_VELOCITY, keyed_gaussian, keyed_uniform};

/// The kinetic temperature of the atoms of mask `bit` (LAMMPS's `compute temp` on the group:
/// dof = d N_g − d); the thermo temperature for `all`.
fn group_temp(sys: &System, bit: u32) -> f64 {
    if bit == 1 {
        return sys.thermo().temp;
    }
    let a = &sys.atoms;
    let d = sys.dim();
    let (mut mv2, mut n) = (0.0, 0usize);
    for i in (0..a.len()).filter(|&i| a.mask_of(i) & bit != 0) {
        let v = a.v[i];
        mv2 += atom_mass(sys, i) * (0..d).map(|k| v[k] * v[k]).sum::<f64>();
        n += 1;
    }
    let dof = (d * n) as f64 - d as f64;
    if dof > 0.0 {
        sys.units.mvv2e * mv2 / (dof * sys.units.boltz)
    } else {
        0.0
    }
}

/// Rescale the velocities of the atoms of mask `bit` so that their kinetic temperature becomes
/// `t` (their current T must be > 0).
fn scale_to(sys: &mut System, t: f64, bit: u32) {
    let s = (t / group_temp(sys, bit)).sqrt();
    let a = &mut sys.atoms;
    for i in 0..a.len() {
        if a.mask_of(i) & bit != 0 {
            for c in a.v[i].iter_mut() {
                *c *= s;
            }
        }
    }
}

/// `velocity all scale T temp ID` with `compute temp/partial` (LAMMPS: the bias, here the
/// unflagged components, is removed, the rest scaled from the compute's temperature to T, the
/// bias restored): the flagged components are multiplied by √(T / T_partial), the others
/// kept with `bias yes`; with `bias no` (LAMMPS's default) every component is multiplied.
fn scale_partial(sys: &mut System, t: f64, flags: [bool; 3], bias: bool) -> CmdResult {
    let now = sys.thermo_partial(flags).temp;
    if now <= 0.0 {
        return Err("cannot scale a zero temperature".into());
    }
    let s = (t / now).sqrt();
    for v in sys.atoms.v.iter_mut() {
        for k in 0..3 {
            if flags[k] || !bias {
                v[k] *= s;
            }
        }
    }
    Ok(())
}

/// The keywords of `velocity all scale T`: `temp ID` and `bias yes|no` (default no, as in
/// LAMMPS: the whole velocity is scaled by the compute's temperature); the
/// others LAMMPS's velocity takes (`dist`, `sum`, `mom`, `rot`, `loop`, `rigid`, `units`) do
/// not change a scaling and are accepted.
fn scale_keywords<'a>(args: &'a [String], usage: &str) -> Result<(Option<&'a str>, bool), String> {
    let (mut temp, mut bias) = (None, false);
    let mut k = 0;
    while k < args.len() {
        need(&args[k..], 2, usage)?;
        let val = args[k + 1].as_str();
        match args[k].as_str() {
            "temp" => temp = Some(val),
            "bias" => {
                bias = match val {
                    "yes" => true,
                    "no" => false,
                    o => return Err(format!("velocity bias '{o}' must be yes or no")),
                }
            }
            "dist" | "sum" | "mom" | "rot" | "loop" | "rigid" | "units" => {}
            o => return Err(format!("unknown velocity scale keyword '{o}'")),
        }
        k += 2;
    }
    Ok((temp, bias))
}

/// Mass of atom `i` (1.0 where its type has none, which the caller rules out).
fn atom_mass(sys: &System, i: usize) -> f64 {
    sys.mass[sys.atoms.typ[i] as usize].unwrap_or(1.0)
}

/// Remove the centre-of-mass velocity of the atoms of mask `bit` from each of them.
fn zero_momentum(sys: &mut System, bit: u32) {
    let member = |a: &crate::engine::Atoms, i: usize| a.mask_of(i) & bit != 0;
    let p = if bit == 1 {
        sys.momentum()
    } else {
        let mut p = [0.0; 3];
        for i in (0..sys.atoms.len()).filter(|&i| member(&sys.atoms, i)) {
            let m = sys.mass[sys.atoms.typ[i] as usize].unwrap_or(0.0);
            for k in 0..3 {
                p[k] += m * sys.atoms.v[i][k];
            }
        }
        p
    };
    let mtot: f64 = (0..sys.atoms.len())
        .filter(|&i| member(&sys.atoms, i))
        .map(|i| atom_mass(sys, i))
        .sum();
    let a = &mut sys.atoms;
    for i in 0..a.len() {
        if member(a, i) {
            for k in 0..3 {
                a.v[i][k] -= p[k] / mtot;
            }
        }
    }
}

/// Parse the trailing `sum yes|no` / `units box|lattice` pairs of `velocity set` and
/// `velocity ramp` from `args[start..]`; returns the `sum` flag. `what` names the style in
/// the error for an unknown keyword.
fn parse_sum_keywords(
    args: &[String],
    start: usize,
    usage: &str,
    what: &str,
) -> Result<bool, String> {
    let mut sum = false;
    let mut k = start;
    while k < args.len() {
        need(&args[k..], 2, usage)?;
        match (args[k].as_str(), args[k + 1].as_str()) {
            ("sum", v) => sum = v == "yes",
            ("units", "box") | ("units", "lattice") => {}
            (o, _) => return Err(format!("unknown velocity {what} keyword '{o}'")),
        }
        k += 2;
    }
    Ok(sum)
}

/// `velocity GROUP create T SEED [dist ..] [mom ..] [rot no] [loop ..]`: the atoms of mask
/// `bit` only.
fn velocity_create(
    sys: &mut System,
    dim: usize,
    args: &[String],
    usage: &str,
    bit: u32,
) -> CmdResult {
    need(args, 4, usage)?;
    let t = parse_f64(&args[2], "temperature")?;
    if t < 0.0 {
        return Err(format!("temperature {t} must be >= 0"));
    }
    let seed: u32 = parse_int(&args[3], "seed")?;
    if seed == 0 {
        return Err("seed must be > 0".into());
    }
    let mut gaussian = false;
    let mut mom = true;
    let mut k = 4;
    while k < args.len() {
        need(&args[k..], 2, usage)?;
        let val = args[k + 1].as_str();
        match args[k].as_str() {
            "dist" => {
                gaussian = match val {
                    "uniform" => false,
                    "gaussian" => true,
                    o => return Err(format!("dist '{o}' must be uniform or gaussian")),
                }
            }
            "mom" => mom = val == "yes",
            "rot" => {
                if val != "no" {
                    return Err("rot yes is not supported (periodic systems)".into());
                }
            }
            "loop" | "sum" => {}
            w @ ("temp" | "bias") => {
                return Err(format!(
                    "velocity create with '{w}' is not supported: it creates with the \
                     temperature of all three components; create without it, then \
                     `velocity all scale T temp ID` with the temperature compute"
                ));
            }
            o => return Err(format!("unknown velocity keyword '{o}'")),
        }
        k += 2;
    }
    for i in 0..sys.atoms.len() {
        if sys.atoms.mask_of(i) & bit == 0 {
            continue;
        }
        let tag = sys.atoms.tag[i];
        let f = 1.0 / atom_mass(sys, i).sqrt();
        let mut v = [0.0; 3];
        for (d, vd) in v.iter_mut().enumerate().take(dim) {
            *vd = f * if gaussian {
                keyed_gaussian(seed, STREAM_VELOCITY, 0, tag, d as u32)
            } else {
                keyed_uniform(seed, STREAM_VELOCITY, 0, tag, d as u32) - 0.5
            };
        }
        sys.atoms.v[i] = v;
    }
    if mom {
        zero_momentum(sys, bit);
    }
    if group_temp(sys, bit) > 0.0 {
        scale_to(sys, t, bit);
    }
    Ok(())
}

/// `velocity all set VX VY VZ [sum yes|no] [units box|lattice]` (`NULL` leaves a component).
fn velocity_set(sys: &mut System, dim: usize, args: &[String], usage: &str, bit: u32) -> CmdResult {
    need(args, 5, usage)?;
    let mut val = [None; 3];
    for d in 0..3 {
        if args[2 + d] != "NULL" {
            val[d] = Some(parse_f64(&args[2 + d], "velocity")?);
        }
    }
    let sum = parse_sum_keywords(args, 5, usage, "set")?;
    let a = &mut sys.atoms;
    for i in 0..a.len() {
        if a.mask_of(i) & bit == 0 {
            continue;
        }
        let v = &mut a.v[i];
        for d in 0..dim {
            if let Some(x) = val[d] {
                v[d] = if sum { v[d] + x } else { x };
            }
        }
    }
    Ok(())
}

/// `velocity all ramp vx|vy|vz VLO VHI x|y|z CLO CHI [sum yes|no] [units box|lattice]`.
///
/// LAMMPS: v_a = vlo + f (vhi − vlo), f = (x_d − clo)/(chi − clo) clamped to [0, 1];
/// `sum yes` adds it to the current velocity.
fn velocity_ramp(sys: &mut System, dim: usize, args: &[String], bit: u32) -> CmdResult {
    let usage = "velocity all ramp vx|vy|vz VLO VHI x|y|z CLO CHI [sum yes|no] [units box|lattice]";
    need(args, 8, usage)?;
    let comp = |t: &str, names: [&str; 3]| {
        names
            .iter()
            .position(|n| *n == t)
            .ok_or_else(|| format!("velocity ramp: '{t}' must be one of {names:?}"))
    };
    let a = comp(&args[2], ["vx", "vy", "vz"])?;
    let (vlo, vhi) = (
        parse_f64(&args[3], "velocity")?,
        parse_f64(&args[4], "velocity")?,
    );
    let c = comp(&args[5], ["x", "y", "z"])?;
    let (clo, chi) = (
        parse_f64(&args[6], "coordinate")?,
        parse_f64(&args[7], "coordinate")?,
    );
    if chi <= clo {
        return Err(format!(
            "velocity ramp: coordinate range {clo} {chi} is empty"
        ));
    }
    if a >= dim || c >= dim {
        return Err("velocity ramp: a z component in a 2-D model".into());
    }
    let sum = parse_sum_keywords(args, 8, usage, "ramp")?;
    let atoms = &mut sys.atoms;
    for i in 0..atoms.len() {
        if atoms.mask_of(i) & bit == 0 {
            continue;
        }
        let (v, x) = (&mut atoms.v[i], atoms.x[i]);
        let f = ((x[c] - clo) / (chi - clo)).clamp(0.0, 1.0);
        let u = vlo + f * (vhi - vlo);
        v[a] = if sum { v[a] + u } else { u };
    }
    Ok(())
}

impl Interpreter<'_> {
    pub(super) fn cmd_velocity(&mut self, args: &[String]) -> CmdResult {
        let usage = "velocity GROUP create T SEED [dist uniform|gaussian] [mom yes|no] [rot no] [loop all|local|geom] | velocity GROUP set VX VY VZ [sum yes|no] | velocity GROUP zero linear | velocity GROUP scale T [temp ID] [bias yes|no]";
        need(args, 2, usage)?;
        let bit = self.group_bit(&args[0])?;
        let dim = self.dim;
        let sys = self.sys_mut()?;
        if sys.mass.iter().skip(1).any(|m| m.is_none()) {
            return Err("all masses must be set before velocity".into());
        }
        match args[1].as_str() {
            "create" => velocity_create(sys, dim, args, usage, bit),
            "set" => velocity_set(sys, dim, args, usage, bit),
            "ramp" => velocity_ramp(sys, dim, args, bit),
            "zero" => {
                need(args, 3, usage)?;
                if args[2] != "linear" {
                    return Err(format!("velocity zero '{}': only 'linear'", args[2]));
                }
                zero_momentum(sys, bit);
                Ok(())
            }
            "scale" => {
                need(args, 3, usage)?;
                let t = parse_f64(&args[2], "temperature")?;
                let (temp, bias) = scale_keywords(&args[3..], usage)?;
                let flags = match temp {
                    Some(id) => self.obs.temp_components(id)?,
                    None => [true; 3],
                };
                let sys = self.sys_mut()?;
                if flags == [true; 3] {
                    if group_temp(sys, bit) <= 0.0 {
                        return Err("cannot scale a zero temperature".into());
                    }
                    scale_to(sys, t, bit);
                } else if bit != 1 {
                    return Err(format!(
                        "velocity {} scale with temp of a temp/partial compute: group all only \
                         (the computes act on all atoms)",
                        args[0]
                    ));
                } else {
                    scale_partial(sys, t, flags, bias)?;
                }
                Ok(())
            }
            o => Err(format!(
                "velocity style '{o}' not supported (create, set, ramp, zero, scale)"
            )),
        }
    }
}
