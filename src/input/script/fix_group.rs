//! The words of the fixes that act on a group through the engine's fix list
//! ([`crate::engine::modify`]): `nve`, `nve/euler`, `mvv/dpd`, `setforce`, `addforce`,
//! `aveforce`, `momentum`; and the refusal of `wall/reflect`.

use super::{CmdResult, Interpreter};
use crate::engine::modify::{
    AddForce, AveForce, Component, Fix, Integrate, Momentum, Scheme, Selection, SetForce,
};
use crate::grammar::{need, parse_f64, parse_int, shown};
use crate::input::observe::{Env, VarStyle};

/// The styles this file parses.
pub(super) const GROUP_FIXES: &[&str] = &[
    "nve",
    "nve/euler",
    "mvv/dpd",
    "setforce",
    "addforce",
    "aveforce",
    "momentum",
];

impl Interpreter<'_> {
    /// One component word of a force fix: a number, `NULL` (where `null_ok`), or `v_name` of an
    /// equal-style variable (or atom-style, where `atom_ok`).
    fn component(
        &self,
        style: &str,
        w: &str,
        null_ok: bool,
        atom_ok: bool,
    ) -> Result<Component, String> {
        if w == "NULL" {
            return if null_ok {
                Ok(Component::Null)
            } else {
                Err(format!("fix {style}: NULL is not allowed here (use 0.0)"))
            };
        }
        if let Some(name) = w.strip_prefix("v_") {
            return match self.var_style(name) {
                VarStyle::Equal => Ok(Component::Equal(name.to_string(), 0.0)),
                VarStyle::Atom if atom_ok => Ok(Component::Atom(name.to_string(), Vec::new())),
                VarStyle::Atom => Err(format!(
                    "fix {style}: variable '{name}' is atom-style; this fix takes equal-style \
                     variables only"
                )),
                VarStyle::Undefined => Err(format!(
                    "fix {style}: variable '{name}' is not defined (define it before the fix)"
                )),
                VarStyle::Other => Err(format!(
                    "fix {style}: variable '{name}' must be equal- or atom-style"
                )),
            };
        }
        let v = parse_f64(w, &format!("fix {style} force component"))?;
        if !v.is_finite() {
            return Err(format!(
                "fix {style}: force component '{}' must be finite",
                shown(w)
            ));
        }
        Ok(Component::Const(v))
    }

    /// A block region for a fix's `region` keyword.
    fn fix_region(&self, style: &str, id: &str) -> Result<[[f64; 2]; 3], String> {
        if self.prisms.contains_key(id) {
            return Err(format!(
                "fix {style} region: region '{id}' is a prism; only block regions select atoms \
                 here"
            ));
        }
        self.region_for_atoms(id)
    }

    /// `fix ID GROUP STYLE …` for a style of [`GROUP_FIXES`]: the fix, ready for the list.
    pub(super) fn group_fix(&mut self, args: &[String]) -> Result<Box<dyn Fix>, String> {
        let (id, style) = (args[0].as_str(), args[2].as_str());
        let bit = self.group_bit(&args[1])?;
        let rest = &args[3..];
        Ok(match style {
            "nve" | "nve/euler" => {
                crate::grammar::fix::integrator(style, rest)?;
                let scheme = if style == "nve" {
                    Scheme::Nve
                } else {
                    Scheme::Euler
                };
                Box::new(Integrate::new(id, bit, scheme))
            }
            "mvv/dpd" => {
                let usage = "fix ID GROUP mvv/dpd [LAMBDA]";
                if rest.len() > 1 {
                    return Err(format!(
                        "fix mvv/dpd takes at most one value; usage: {usage}"
                    ));
                }
                let lambda = match rest.first() {
                    Some(w) => parse_f64(w, "mvv/dpd lambda")?,
                    None => 0.5,
                };
                if !lambda.is_finite() {
                    return Err(format!("fix mvv/dpd: lambda {lambda} must be finite"));
                }
                Box::new(Integrate::new(id, bit, Scheme::Mvv(lambda)))
            }
            "setforce" | "addforce" | "aveforce" => self.force_fix(id, style, bit, rest)?,
            "momentum" => momentum(id, bit, rest, self.dim)?,
            o => return Err(format!("fix style '{o}' is not a group fix")),
        })
    }

    /// `setforce|addforce|aveforce FX FY FZ [keywords]`.
    fn force_fix(
        &self,
        id: &str,
        style: &str,
        bit: u32,
        rest: &[String],
    ) -> Result<Box<dyn Fix>, String> {
        let usage = match style {
            "setforce" => "fix ID GROUP setforce FX FY FZ [region R] (NULL, a number or v_name)",
            "addforce" => {
                "fix ID GROUP addforce FX FY FZ [every N] [region R] (a number or v_name)"
            }
            _ => {
                "fix ID GROUP aveforce FX FY FZ [region R] (NULL, a number or v_name of an equal-style variable)"
            }
        };
        need(rest, 3, usage)?;
        let null_ok = style != "addforce";
        let atom_ok = style != "aveforce";
        let mut c = [Component::Null, Component::Null, Component::Null];
        for k in 0..3 {
            c[k] = self.component(style, &rest[k], null_ok, atom_ok)?;
        }
        let (mut region, mut every) = (None, 1u64);
        let mut k = 3;
        while k < rest.len() {
            need(&rest[k..], 2, usage)?;
            match (rest[k].as_str(), style) {
                ("region", _) => region = Some(self.fix_region(style, &rest[k + 1])?),
                ("every", "addforce") => {
                    every = parse_int(&rest[k + 1], "addforce every")?;
                    if every == 0 {
                        return Err("fix addforce: every must be >= 1".into());
                    }
                }
                ("energy", "addforce") => {
                    return Err(
                        "fix addforce energy: not supported in the standalone engine (the \
                         force is applied; its potential energy is not tallied)"
                            .into(),
                    );
                }
                (o, _) => {
                    return Err(format!(
                        "fix {style} keyword '{}' not supported; usage: {usage}",
                        shown(o)
                    ));
                }
            }
            k += 2;
        }
        let sel = Selection { bit, region };
        Ok(match style {
            "setforce" => Box::new(SetForce::new(id, sel, c)),
            "addforce" => Box::new(AddForce::new(id, sel, c, every)),
            _ => Box::new(AveForce::new(id, sel, c)),
        })
    }

    /// `fix ID GROUP wall/reflect …`: refused with what to do.
    pub(super) fn wall_reflect(&self) -> CmdResult {
        Err(
            "fix wall/reflect needs a non-periodic boundary (boundary f or s), which the \
             standalone engine does not have (it is fully periodic); run the script in LAMMPS \
             (dpdnl verify checks this project's pair forces of such a run)"
                .into(),
        )
    }
}

/// `momentum N [linear XF YF ZF] [angular] [rescale]`.
fn momentum(id: &str, bit: u32, rest: &[String], dim: usize) -> Result<Box<dyn Fix>, String> {
    let usage = "fix ID GROUP momentum N [linear XFLAG YFLAG ZFLAG] [angular] [rescale]";
    need(rest, 1, usage)?;
    let every: u64 = parse_int(&rest[0], "momentum interval N")?;
    if every == 0 {
        return Err("fix momentum: N must be >= 1".into());
    }
    let (mut linear, mut any_linear, mut angular, mut rescale) = ([false; 3], false, false, false);
    let mut k = 1;
    while k < rest.len() {
        match rest[k].as_str() {
            "linear" => {
                need(&rest[k..], 4, usage)?;
                for d in 0..3 {
                    linear[d] = match rest[k + 1 + d].as_str() {
                        "0" => false,
                        "1" => true,
                        o => {
                            return Err(format!(
                                "fix momentum linear: flag '{}' must be 0 or 1",
                                shown(o)
                            ));
                        }
                    };
                }
                any_linear = true;
                k += 4;
            }
            "rescale" => {
                rescale = true;
                k += 1;
            }
            "angular" => {
                angular = true;
                k += 1;
            }
            o => {
                return Err(format!(
                    "fix momentum keyword '{}' not supported; usage: {usage}",
                    shown(o)
                ));
            }
        }
    }
    if !any_linear && !angular {
        return Err(format!(
            "fix momentum needs 'linear X Y Z' or 'angular'; usage: {usage}"
        ));
    }
    let _ = dim;
    Ok(Box::new(Momentum::new(
        id, bit, every, linear, angular, rescale,
    )))
}
