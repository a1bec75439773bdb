//! `pair_style` and `pair_coeff`: the words go to the style object (`engine::style`, one for
//! both engines), which parses them with [`crate::grammar`]. A `pair_style` of another style
//! replaces the old one and its coefficients; the same style again keeps its coefficients
//! under that style's rule (`PairStyle::restyle`), as LAMMPS does. A restart file stores the
//! style's own `restart_lines`, which `read_restart` re-issues.

use super::{CmdResult, Interpreter};
use crate::grammar::{self, need};

impl Interpreter<'_> {
    pub(super) fn cmd_pair_style(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, grammar::pair::PAIR_STYLE.usage)?;
        let dt = self.dt;
        let sys = self.sys_mut()?;
        match sys.pair.as_deref_mut() {
            Some(style) if style.name() == args[0] => style.restyle(&args[1..])?,
            _ => {
                sys.pair = Some(crate::engine::style::new_pair_style(
                    &args[0],
                    &args[1..],
                    sys.ntypes,
                    dt,
                )?)
            }
        }
        Ok(())
    }

    /// `pair_coeff I J a gamma0 gamma1 [rc]` or `I J a eta E sc S [gamma1 G] [rc R]` (γ0 and
    /// the weight exponent then come from the targets η and Sc at every run's set-up,
    /// `crate::init::resolve_design`); under `sdpd`, `I J rho0 c0 eta0 [rc]` or
    /// `I J rho0 c0 eta E sc S [rc R]`.
    pub(super) fn cmd_pair_coeff(&mut self, args: &[String]) -> CmdResult {
        let sys = self.sys_mut()?;
        let style = sys
            .pair
            .as_deref_mut()
            .ok_or("pair_coeff before pair_style")?;
        style.coeff(args)
    }
}
