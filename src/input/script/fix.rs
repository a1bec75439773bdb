//! `fix` and `unfix`: time integration (`nve`, `nve/euler`), `enforce2d`, `pex/push`, `deform`
//! (Lees–Edwards), and the averaging fixes, which [`crate::input::observe`] parses.

use super::{CmdResult, Interpreter};
use crate::engine::lees_edwards::{Deform, DeformOrder};
use crate::engine::{PexPush, System};
use crate::grammar::{self, need, parse_f64, parse_int};
use crate::input::observe::Observe;

#[derive(Clone, Debug, PartialEq)]
pub(super) enum FixKind {
    /// A fix of the engine's list (`engine::modify`): integrators on a group, force fixes,
    /// `momentum` (`fix_group.rs`).
    Engine,
    Enforce2d,
    Pex,
    /// `deform … xy erate R remap v` (Lees–Edwards, `engine::lees_edwards`).
    Deform,
    /// `flip/momentum [mode jump|check]` (the velocity jump at flips, issue 41).
    FlipMomentum,
    /// `ave/time`, `ave/chunk`, `ave/histo` (in `observe`).
    Observe,
    /// `dpdnl/frames N FILE`: LAMMPS's (the frames `dpdnl verify` checks); words checked,
    /// nothing written here.
    Frames,
    /// `print` (in `fix_print`).
    Print,
}

impl Interpreter<'_> {
    /// `fix ID all STYLE …`: define the fix, keep its words for restart files and give it the
    /// state of a restart file's fix of the same ID and style.
    pub(super) fn cmd_fix(&mut self, args: &[String]) -> CmdResult {
        self.define_fix(args)?;
        self.fix_lines.insert(args[0].clone(), args.to_vec());
        self.claim_fix_state(&args[0], &args[2])
    }

    fn define_fix(&mut self, args: &[String]) -> CmdResult {
        let usage = "fix ID GROUP nve | nve/euler | mvv/dpd [LAMBDA] | setforce … | addforce … | aveforce … | momentum … | enforce2d | print N TEXT … | fix ID all pex/push DP [width W] [every N] | deform … | flip/momentum [mode jump|check] | dpdnl/frames N FILE | ave/time … | ave/chunk … | ave/histo …";
        need(args, 3, usage)?;
        let id = args[0].clone();
        if self.fixes.iter().any(|(i, _)| i == &id) {
            return Err(format!("fix ID '{id}' already exists (unfix it first)"));
        }
        if super::fix_group::GROUP_FIXES.contains(&args[2].as_str()) {
            let fix = self.group_fix(args)?;
            if args[2] == "momentum" {
                let bit = self.group_bit(&args[1])?;
                if self.sys_mut()?.group_count(bit) == 0 {
                    return Err(format!("fix momentum: group '{}' has no atoms", args[1]));
                }
            }
            let sys = self.sys_mut()?;
            sys.modify.add(fix);
            sys.integrator = sys.modify.scheme();
            self.fixes.push((id, FixKind::Engine));
            return Ok(());
        }
        match args[2].as_str() {
            "wall/reflect" => return self.wall_reflect(),
            "enforce2d" => {
                self.group_bit(&args[1])?;
            }
            s if args[1] != "all" => {
                return Err(format!(
                    "fix {s} on group '{}' not supported: only group all",
                    args[1]
                ));
            }
            _ => {}
        }
        if matches!(args[2].as_str(), "ave/time" | "ave/chunk" | "ave/histo") {
            let f = Observe::parse_fix(args, &*self)?;
            self.obs.add_fix(f);
            self.fixes.push((id, FixKind::Observe));
            return Ok(());
        }
        if args[2] == "dpdnl/frames" {
            grammar::fix::frames(&args[1], &args[3..])?;
            self.out(
                "fix dpdnl/frames: LAMMPS writes the frames; the standalone engine's forces are \
                 the reference `dpdnl verify` recomputes, so it writes none",
            );
            self.fixes.push((id, FixKind::Frames));
            return Ok(());
        }
        if args[2] == "print" {
            self.sys_mut()?;
            let p = super::fix_print::PrintFix::parse(args)?;
            self.prints.insert(id.clone(), p);
            self.fixes.push((id, FixKind::Print));
            return Ok(());
        }
        let dim = self.dim;
        let sys = self.sys_mut()?;
        let kind = match args[2].as_str() {
            "enforce2d" => {
                if dim != 2 {
                    return Err("fix enforce2d needs dimension 2".into());
                }
                FixKind::Enforce2d
            }
            "pex/push" => {
                let p = grammar::fix::pex_push(&args[3..], dim)?;
                sys.pex.push(PexPush {
                    id: id.clone(),
                    dp: p.dp,
                    width: p.width,
                    every: p.every,
                    total: 0.0,
                });
                FixKind::Pex
            }
            "deform" => {
                Self::fix_deform(sys, &id, args)?;
                FixKind::Deform
            }
            "flip/momentum" => {
                let jump = grammar::fix::flip_momentum(&args[3..])?;
                let Some(tri) = sys.tri.as_mut() else {
                    return Err(
                        "fix flip/momentum needs a triclinic box (region … prism … or \
                                change_box all triclinic) with a fix deform … xy … remap v"
                            .into(),
                    );
                };
                if tri.flip_fix.is_some() {
                    return Err("only one fix flip/momentum is allowed".into());
                }
                tri.flip_fix = Some(jump);
                FixKind::FlipMomentum
            }
            o => return Err(format!("fix style '{o}' not supported; {usage}")),
        };
        self.fixes.push((id, kind));
        Ok(())
    }

    /// `fix ID all deform N xy erate R remap v [flip yes|no] [units box|lattice]`: the only
    /// form Couette flow needs (Lees–Edwards, `engine::lees_edwards`).
    fn fix_deform(sys: &mut System, id: &str, args: &[String]) -> CmdResult {
        let usage = "fix ID all deform N xy erate R remap v [flip yes|no] [units box|lattice] [order lammps|current]";
        need(args, 7, usage)?;
        let every: u64 = parse_int(&args[3], "deform interval N")?;
        if every == 0 {
            return Err("fix deform: N must be >= 1".into());
        }
        if args[4] != "xy" {
            return Err(format!(
                "fix deform parameter '{}' not supported: only 'xy erate R remap v' (Couette flow)",
                args[4]
            ));
        }
        if args[5] != "erate" {
            return Err(format!(
                "fix deform xy style '{}' not supported: only 'erate'",
                args[5]
            ));
        }
        let erate = parse_f64(&args[6], "erate")?;
        if !erate.is_finite() {
            return Err(format!("fix deform: erate '{}' must be finite", args[6]));
        }
        let (mut remap_v, mut flip, mut order) = (false, true, DeformOrder::Lammps);
        let mut k = 7;
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            let val = args[k + 1].as_str();
            match (args[k].as_str(), val) {
                ("remap", "v") => remap_v = true,
                ("remap", o) => {
                    return Err(format!(
                        "fix deform remap '{o}' not supported: only 'remap v' (Lees–Edwards)"
                    ));
                }
                ("flip", "yes") => flip = true,
                ("flip", "no") => flip = false,
                ("flip", o) => return Err(format!("fix deform flip '{o}' must be yes or no")),
                ("order", "lammps") => order = DeformOrder::Lammps,
                ("order", "current") => order = DeformOrder::Current,
                ("order", o) => {
                    return Err(format!(
                        "fix deform order '{o}' must be lammps or current (standalone only)"
                    ));
                }
                ("units", "box" | "lattice") => {}
                (o, _) => {
                    return Err(format!(
                        "fix deform keyword '{o}' not supported; usage: {usage}"
                    ));
                }
            }
            k += 2;
        }
        if !remap_v {
            return Err(
                "fix deform needs 'remap v' here (LAMMPS's default 'remap x' is not supported)"
                    .into(),
            );
        }
        let Some(tri) = sys.tri.as_mut() else {
            return Err(
                "fix deform xy needs a triclinic box (region … prism … or change_box all triclinic)"
                    .into(),
            );
        };
        if tri.deform.is_some() {
            return Err("only one fix deform is allowed".into());
        }
        let mut d = Deform::new(id.to_string(), every, erate, flip);
        d.order = order;
        tri.deform = Some(d);
        Ok(())
    }

    pub(super) fn cmd_unfix(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, "unfix ID")?;
        let pos = self
            .fixes
            .iter()
            .position(|(id, _)| id == &args[0])
            .ok_or_else(|| format!("no fix with ID '{}'", args[0]))?;
        if let Some(user) = self.obs.fix_user(&args[0]) {
            return Err(format!("fix '{}' is used by fix '{user}'", args[0]));
        }
        let (id, kind) = self.fixes.remove(pos);
        self.fix_lines.remove(&id);
        if let Some(sys) = self.sys.as_mut() {
            match kind {
                FixKind::Engine => {
                    sys.modify.remove(&id);
                    sys.integrator = sys.modify.scheme();
                }
                FixKind::Pex => sys.pex.retain(|p| p.id != id),
                FixKind::Deform => {
                    if let Some(t) = sys.tri.as_mut() {
                        t.deform = None;
                    }
                }
                FixKind::FlipMomentum => {
                    if let Some(t) = sys.tri.as_mut() {
                        t.flip_fix = None;
                    }
                }
                FixKind::Enforce2d | FixKind::Frames => {}
                FixKind::Observe => {
                    self.obs.unfix(&id);
                }
                FixKind::Print => {
                    self.prints.remove(&id);
                }
            }
        }
        Ok(())
    }
}
