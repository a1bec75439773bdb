//! `pair_style` and `pair_coeff`: the words go to the style object (`forces::style`, one for
//! both engines), which parses them with [`crate::grammar`]. A `pair_style` of another style
//! replaces the old one and its coefficients; the same style again keeps its coefficients
//! under that style's rule (`PairStyle::restyle`), as LAMMPS does. A restart file stores the
//! style's own `restart_lines`, which `read_restart` re-issues.
//!
//! As in LAMMPS, `pair_style` may come before the box: its words are checked at once and kept
//! until `create_box`, `read_data` or `read_restart` makes the box, which makes the style for
//! the box's atom types (and `read_data` then applies the file's `Pair Coeffs` or `PairIJ
//! Coeffs` section to it). `pair_coeff` needs the box, as in LAMMPS.

use super::{CmdResult, Interpreter};
use crate::grammar::{self, need};

/// The standalone engine has one pair style per run: `pair_style hybrid` (and `hybrid/overlay`,
/// `hybrid/scaled`), which LAMMPS provides, is refused with a pointer to it.
fn hybrid_refusal(name: &str) -> String {
    format!(
        "style '{}': the standalone engine runs one pair style over every type pair and has \
         no pair_style hybrid or hybrid/overlay; LAMMPS with the dpdnl plugin (or build/lmp_dpdnl) runs \
         dpd/nonlinear and sdpd as sub-styles of hybrid and hybrid/overlay, on any subset of \
         type pairs",
        grammar::shown(name)
    )
}

/// The words of sub-style `name` in `pair_style hybrid… ARGS` (`args[0]` the hybrid word):
/// `name` and the longest run of words after it that the style parses (the next sub-style's
/// name ends it). `name` must occur once.
fn pick_substyle(args: &[String], name: &str, dt: f64) -> Result<Vec<String>, String> {
    let at: Vec<usize> = (1..args.len()).filter(|&k| args[k] == name).collect();
    let &[at] = at.as_slice() else {
        return Err(format!(
            "style '{}' names sub-style {name} {} times: dpdnl verify recomputes one",
            grammar::shown(&args[0]),
            at.len()
        ));
    };
    let rest = &args[at + 1..];
    let mut first_err = None;
    for k in (0..=rest.len()).rev() {
        match crate::forces::new_pair_style(name, &rest[..k], 1, dt) {
            Ok(_) => return Ok(args[at..=at + k].to_vec()),
            Err(e) => {
                first_err.get_or_insert(e);
            }
        }
    }
    Err(first_err.unwrap_or_default())
}

impl Interpreter<'_> {
    pub(super) fn cmd_pair_style(&mut self, args: &[String]) -> CmdResult {
        need(args, 1, crate::forces::pair_style_usage())?;
        if args[0].starts_with("hybrid") {
            return match self.substyle.clone() {
                Some(name) => {
                    let words = pick_substyle(args, &name, self.dt)?;
                    self.cmd_pair_style(&words)
                }
                None => Err(hybrid_refusal(&args[0])),
            };
        }
        let dt = self.dt;
        let Some(sys) = self.sys.as_mut() else {
            // Before the box: checked now (the same words and messages as after it), made for
            // the box's atom types when the box exists. With no coefficients yet, the same
            // style again is the same as a new one.
            crate::forces::new_pair_style(&args[0], &args[1..], 1, dt)?;
            self.pre_pair = Some(args.to_vec());
            return Ok(());
        };
        match sys.pair.as_deref_mut() {
            Some(style) if style.name() == args[0] => style.restyle(&args[1..])?,
            _ => {
                sys.pair = Some(crate::forces::new_pair_style(
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
