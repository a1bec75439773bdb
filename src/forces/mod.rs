//! The forces layer: every force term of both engines, one registry per kind.
//!
//! - **Pair styles** ([`PAIR_STYLES`]): each style is one folder holding its grammar, set-up,
//!   kernel and [`PairStyle`] implementation: [`dpd`] (`pair_style dpd/nonlinear`) and [`sdpd`]
//!   (`pair_style sdpd`). The seam they share is [`style`] (the trait, the set-up context, the
//!   pre-pass of a many-body style, the typed plan) and [`batcher`] (the batch kernel the pair
//!   loops call), and [`lanes`] (the lane batch [`PairBatch`] every kernel reads, the instruction
//!   sets [`Isa`], the keyed noise of a batch's lanes).
//! - **Bond and angle styles** ([`BOND_STYLES`], [`ANGLE_STYLES`]): one file each in
//!   [`bonded`].
//!
//! The registries are the only places that name a style; the engines, the interpreter and the
//! C ABI reach every style through its trait. The standalone engine's pair loops and the C
//! ABI's walk of a LAMMPS list (the drivers) live outside this layer, in `engine` and `capi`.

pub mod batcher;
pub mod bonded;
pub mod dpd;
pub mod dpdext;
pub mod lanes;
pub mod mdpd;
pub mod sdpd;
pub mod style;

pub use bonded::{ANGLE_STYLES, BOND_STYLES};
pub use lanes::{BATCH, Isa, NoiseDist, PairBatch, in_range};
pub use style::{
    PairStyle, PrePass, RunSteps, SetupContext, SetupNote, StyleDerived, StylePlan, StyleRecord,
};

/// How the registry makes a pair style: from the words after its name, for `ntypes` atom types
/// and time step `dt`.
pub type MakePairStyle = fn(&[String], usize, f64) -> Result<Box<dyn PairStyle>, String>;

/// One pair style of the registry.
pub struct PairStyleEntry {
    /// The name after `pair_style`.
    pub name: &'static str,
    /// One line on what it is (what LAMMPS prints when the plugin registers it).
    pub about: &'static str,
    /// A new style from the words after its name, for `ntypes` atom types and time step `dt`.
    pub make: MakePairStyle,
    /// The usage strings and keywords of its `pair_style` and `pair_coeff` lines (quoted in
    /// error messages and the bad-input table).
    pub specs: &'static [crate::grammar::StyleSpec],
}

/// The pair styles this project provides, the one place that names them: a new pair style is
/// its folder here, its `pub mod` line and one entry in this table.
pub const PAIR_STYLES: &[PairStyleEntry] = &[
    PairStyleEntry {
        name: dpd::grammar::NAME,
        about: "DPD with non-linear friction",
        make: |args, ntypes, dt| Ok(Box::new(dpd::DpdPair::new(args, ntypes, dt)?)),
        specs: &[
            dpd::grammar::PAIR_STYLE,
            dpd::grammar::PAIR_COEFF,
            dpd::grammar::PAIR_COEFF_TARGETS,
        ],
    },
    PairStyleEntry {
        name: sdpd::grammar::NAME,
        about: "smoothed DPD, Lucy/quintic/proposed kernels",
        make: |args, ntypes, _dt| Ok(Box::new(sdpd::SdpdField::from_words(args, ntypes)?)),
        specs: &[
            sdpd::grammar::PAIR_STYLE,
            sdpd::grammar::PAIR_COEFF,
            sdpd::grammar::PAIR_COEFF_TARGETS,
        ],
    },
    PairStyleEntry {
        name: mdpd::grammar::NAME,
        about: "many-body DPD (free surfaces) with non-linear friction",
        make: |args, ntypes, dt| Ok(Box::new(mdpd::MdpdPair::new(args, ntypes, dt)?)),
        specs: &[mdpd::grammar::PAIR_STYLE, mdpd::grammar::PAIR_COEFF],
    },
    PairStyleEntry {
        name: dpdext::grammar::NAME_EXT,
        about: "DPD with non-linear parallel and constant perpendicular friction (dpd/ext)",
        make: |args, ntypes, dt| {
            Ok(Box::new(dpdext::ExtPair::new(
                dpdext::grammar::Form::Ext,
                args,
                ntypes,
                dt,
            )?))
        },
        specs: &[
            dpdext::grammar::PAIR_STYLE_EXT,
            dpdext::grammar::PAIR_COEFF_EXT,
        ],
    },
    PairStyleEntry {
        name: dpdext::grammar::NAME_TSTAT,
        about: "DPD thermostat with non-linear friction, T ramped (dpd/tstat)",
        make: |args, ntypes, dt| {
            Ok(Box::new(dpdext::ExtPair::new(
                dpdext::grammar::Form::Tstat,
                args,
                ntypes,
                dt,
            )?))
        },
        specs: &[
            dpdext::grammar::PAIR_STYLE_TSTAT,
            dpdext::grammar::PAIR_COEFF_TSTAT,
        ],
    },
    PairStyleEntry {
        name: dpdext::grammar::NAME_EXT_TSTAT,
        about: "DPD thermostat, parallel and perpendicular friction, T ramped (dpd/ext/tstat)",
        make: |args, ntypes, dt| {
            Ok(Box::new(dpdext::ExtPair::new(
                dpdext::grammar::Form::ExtTstat,
                args,
                ntypes,
                dt,
            )?))
        },
        specs: &[
            dpdext::grammar::PAIR_STYLE_EXT_TSTAT,
            dpdext::grammar::PAIR_COEFF_EXT_TSTAT,
        ],
    },
];

/// A new pair style `name` from the words after the name, for `ntypes` atom types and time
/// step `dt`; an error names the style or the word at fault.
pub fn new_pair_style(
    name: &str,
    args: &[String],
    ntypes: usize,
    dt: f64,
) -> Result<Box<dyn PairStyle>, String> {
    match PAIR_STYLES.iter().find(|s| s.name == name) {
        Some(s) => (s.make)(args, ntypes, dt),
        None => Err(format!(
            "pair style '{}' not supported: only {}",
            crate::grammar::shown(name),
            PAIR_STYLES
                .iter()
                .map(|s| s.name)
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// Rebuild a style from its [`StyleRecord::restart_lines`] for `ntypes` types.
pub fn from_restart_lines(
    lines: &[Vec<String>],
    ntypes: usize,
    dt: f64,
) -> Result<Box<dyn PairStyle>, String> {
    let head = lines
        .first()
        .filter(|l| l.len() >= 2 && l[0] == "pair_style")
        .ok_or("restart: the pair style's lines do not start with pair_style")?;
    let mut style = new_pair_style(&head[1], &head[2..], ntypes, dt)?;
    for line in &lines[1..] {
        match line.split_first() {
            Some((cmd, args)) if cmd == "pair_coeff" => style.coeff(args)?,
            _ => {
                return Err(format!(
                    "restart: unexpected pair line '{}'",
                    line.join(" ")
                ));
            }
        }
    }
    Ok(style)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every listed style is made by [`new_pair_style`] (its own grammar answers, not the
    /// unknown-style error), and an unknown name lists them.
    #[test]
    fn every_listed_style_is_made() {
        for s in PAIR_STYLES {
            let name = s.name;
            let e = new_pair_style(name, &[], 1, 1.0).expect_err("no arguments");
            assert!(!e.contains("not supported"), "{name}: {e}");
        }
        let e = new_pair_style("lj/cut", &[], 1, 1.0).expect_err("unknown");
        assert_eq!(
            e,
            "pair style 'lj/cut' not supported: only dpd/nonlinear, sdpd, mdpd/nonlinear, \
             dpd/nonlinear/ext, dpd/nonlinear/tstat, dpd/nonlinear/ext/tstat"
        );
    }
}
