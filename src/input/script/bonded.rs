//! The topology commands: `bond_style`, `bond_coeff`, `angle_style`, `angle_coeff`,
//! `special_bonds` (the styles and formulas are in `forces::bonded`, the special neighbours in
//! `engine::topology`). As in LAMMPS, the styles and `special_bonds` may come before the box
//! (`read_data` then applies them, and its `Bond Coeffs`/`Angle Coeffs` sections need them);
//! the coefficients need the box.

use super::{CmdResult, Interpreter};
use crate::engine::Topology;
use crate::engine::topology::SpecialBonds;
use crate::forces::bonded::{AngleStyle, BondStyle};

/// What the topology commands set before the box exists.
#[derive(Clone, Debug, Default)]
pub(super) struct PreTopology {
    /// `bond_style` words.
    pub(super) bond: Option<Vec<String>>,
    /// `angle_style` words.
    pub(super) angle: Option<Vec<String>>,
    /// `special_bonds`.
    pub(super) special: SpecialBonds,
}

impl PreTopology {
    /// The topology of a new molecular system with these settings and the type counts.
    pub(super) fn topology(
        &self,
        style: crate::engine::topology::AtomStyle,
        nbondtypes: usize,
        nangletypes: usize,
    ) -> Result<Topology, String> {
        Ok(Topology {
            style,
            nbondtypes,
            nangletypes,
            special: self.special,
            bond_style: self
                .bond
                .as_ref()
                .map(|w| BondStyle::new(w, nbondtypes))
                .transpose()?,
            angle_style: self
                .angle
                .as_ref()
                .map(|w| AngleStyle::new(w, nangletypes))
                .transpose()?,
            ..Topology::default()
        })
    }
}

impl Interpreter<'_> {
    fn need_molecular(&self, cmd: &str) -> CmdResult {
        if !self.atom_style.molecular() {
            return Err(format!(
                "{cmd} command when no bonds allowed (atom_style {}; use bond, angle, molecular \
                 or full)",
                self.atom_style.word()
            ));
        }
        Ok(())
    }

    pub(super) fn cmd_bond_style(&mut self, args: &[String]) -> CmdResult {
        self.need_molecular("bond_style")?;
        // Checked now, whatever the box.
        BondStyle::new(args, 1)?;
        match self.sys.as_mut().and_then(|s| s.topo.as_mut()) {
            Some(t) => t.bond_style = Some(BondStyle::new(args, t.nbondtypes)?),
            None => self.pre_topo.bond = Some(args.to_vec()),
        }
        Ok(())
    }

    pub(super) fn cmd_angle_style(&mut self, args: &[String]) -> CmdResult {
        self.need_molecular("angle_style")?;
        if !self.atom_style.has_angles() {
            return Err(format!(
                "angle_style command when no angles allowed (atom_style {})",
                self.atom_style.word()
            ));
        }
        AngleStyle::new(args, 1)?;
        match self.sys.as_mut().and_then(|s| s.topo.as_mut()) {
            Some(t) => t.angle_style = Some(AngleStyle::new(args, t.nangletypes)?),
            None => self.pre_topo.angle = Some(args.to_vec()),
        }
        Ok(())
    }

    fn topo_mut(&mut self, cmd: &str) -> Result<&mut Topology, String> {
        self.need_molecular(cmd)?;
        self.sys
            .as_mut()
            .and_then(|s| s.topo.as_mut())
            .ok_or_else(|| format!("{cmd} command before simulation box is defined"))
    }

    pub(super) fn cmd_bond_coeff(&mut self, args: &[String]) -> CmdResult {
        let t = self.topo_mut("bond_coeff")?;
        t.bond_style
            .as_mut()
            .ok_or("bond_coeff command before bond_style is defined")?
            .set_coeff(args)
    }

    pub(super) fn cmd_angle_coeff(&mut self, args: &[String]) -> CmdResult {
        let t = self.topo_mut("angle_coeff")?;
        t.angle_style
            .as_mut()
            .ok_or("angle_coeff command before angle_style is defined")?
            .set_coeff(args)
    }

    pub(super) fn cmd_special_bonds(&mut self, args: &[String]) -> CmdResult {
        let s = SpecialBonds::parse(args)?;
        match self.sys.as_mut().and_then(|s| s.topo.as_mut()) {
            Some(t) => t.special = s,
            None => self.pre_topo.special = s,
        }
        Ok(())
    }
}
