//! `pair_style` and `pair_coeff`: the words are parsed by [`crate::grammar::pair`] and
//! [`crate::grammar::sdpd`] (one grammar for both engines); this file puts the result into the
//! system's pair style (`dpd/nonlinear` or `sdpd`; a new `pair_style` replaces the old one and
//! its coefficients, except that `sdpd` given again keeps its coefficients, as LAMMPS does), and
//! keeps the accepted lines' words, which a restart file stores and
//! `read_restart` re-issues (so every pair style is covered without restart code of its own).

use super::{CmdResult, Interpreter};
use crate::engine::ForceField;
use crate::engine::sdpd::SdpdField;
use crate::grammar::{self, need};

impl Interpreter<'_> {
    pub(super) fn cmd_pair_style(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, grammar::pair::PAIR_STYLE.usage)?;
        match args[0].as_str() {
            "dpd/nonlinear" => {
                let style = grammar::pair::pair_style(&args[1..])?;
                let dt = self.dt;
                let sys = self.sys_mut()?;
                sys.ff = Some(ForceField::new(
                    style.model(dt),
                    style.seed,
                    style.rc,
                    sys.ntypes,
                ));
                sys.sdpd = None;
            }
            "sdpd" => {
                let style = grammar::sdpd::pair_style(&args[1..])?;
                // As LAMMPS: the same style again keeps its coefficients (they are applied
                // again under the new settings, so one the new kernel refuses is an error here).
                let again = self.sys_mut()?.sdpd.is_some();
                let old: Vec<Vec<String>> = if again {
                    self.pair_lines
                        .iter()
                        .filter(|l| l.first().is_some_and(|w| w == "pair_coeff"))
                        .cloned()
                        .collect()
                } else {
                    Vec::new()
                };
                let sys = self.sys_mut()?;
                sys.sdpd = Some(SdpdField::new(style, sys.ntypes));
                sys.ff = None;
                self.pair_lines = vec![command_words("pair_style", args)];
                for line in old {
                    self.cmd_pair_coeff(&line[1..])?;
                }
                return Ok(());
            }
            other => {
                return Err(format!(
                    "pair style '{}' not supported: only dpd/nonlinear and sdpd",
                    grammar::shown(other)
                ));
            }
        }
        self.pair_lines = vec![command_words("pair_style", args)];
        Ok(())
    }

    /// `pair_coeff I J a gamma0 gamma1 [rc]` or `I J a eta E sc S [gamma1 G] [rc R]` (γ0 and
    /// the weight exponent then come from the targets η and Sc at every run's set-up,
    /// `crate::init::resolve_design`); under `sdpd`, `I J rho0 c0 eta0 [rc]` or
    /// `I J rho0 c0 eta E sc S [rc R]`.
    pub(super) fn cmd_pair_coeff(&mut self, args: &[String]) -> CmdResult {
        let sys = self.sys_mut()?;
        let ntypes = sys.ntypes;
        if let Some(sd) = sys.sdpd.as_mut() {
            let line = grammar::sdpd::pair_coeff(args, ntypes, &sd.style)?;
            sd.set_line(&line);
        } else {
            let ff = sys.ff.as_mut().ok_or("pair_coeff before pair_style")?;
            let line = grammar::pair::pair_coeff(args, ntypes, ff.model.friction, ff.rc_global)?;
            for (i, j) in line.pairs() {
                match line.targets {
                    Some((eta, sc)) => ff.set_targets(i, j, line.coeff, eta, sc),
                    None => ff.set(i, j, line.coeff),
                }
            }
        }
        self.pair_lines.push(command_words("pair_coeff", args));
        Ok(())
    }
}

/// A command line as words, command first (what a restart file stores to re-issue it).
fn command_words(cmd: &str, args: &[String]) -> Vec<String> {
    std::iter::once(cmd.to_string())
        .chain(args.iter().cloned())
        .collect()
}
