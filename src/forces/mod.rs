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
pub mod plan;
pub mod sdpd;
#[cfg(feature = "test-style")]
pub mod spring;
pub mod style;

pub use bonded::{ANGLE_STYLES, BOND_STYLES};
pub use lanes::{BATCH, Isa, NoiseDist, PairBatch, in_range};
pub use plan::{DesignMethod, PairPlan, PlanPoint, StylePlan};
pub use style::{PairStyle, PrePass, RunSteps, SetupContext, SetupNote, StyleDerived, StyleRecord};

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
    /// How `dpdnl design --method` designs it from target (η, Sc), if it can be.
    pub design: Option<&'static dyn DesignMethod>,
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
        design: Some(&dpd::DpdDesign),
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
        design: Some(&sdpd::SdpdDesign),
    },
    PairStyleEntry {
        name: mdpd::grammar::NAME,
        about: "many-body DPD (free surfaces) with non-linear friction",
        make: |args, ntypes, dt| Ok(Box::new(mdpd::MdpdPair::new(args, ntypes, dt)?)),
        specs: &[mdpd::grammar::PAIR_STYLE, mdpd::grammar::PAIR_COEFF],
        design: None,
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
        design: None,
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
        design: None,
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
        design: None,
    },
    #[cfg(feature = "test-style")]
    PairStyleEntry {
        name: spring::grammar::NAME,
        about: "test only: a linear spring with a cut-off",
        make: |args, ntypes, _dt| Ok(Box::new(spring::SpringPair::new(args, ntypes)?)),
        specs: &[spring::grammar::PAIR_STYLE, spring::grammar::PAIR_COEFF],
        design: None,
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

/// The words of `dpdnl design --method`: the styles that can be designed, in registry order.
pub fn design_methods() -> impl Iterator<Item = &'static str> {
    PAIR_STYLES
        .iter()
        .filter_map(|s| s.design.map(|d| d.method()))
}

/// The design method `dpdnl design --method NAME` names.
pub fn design_method(name: &str) -> Option<&'static dyn DesignMethod> {
    PAIR_STYLES
        .iter()
        .filter_map(|s| s.design)
        .find(|d| d.method() == name)
}

/// Every usage spec: the pair styles' (from [`PAIR_STYLES`]), then the fixes'
/// (`grammar::SPECS`).
pub(crate) fn all_specs() -> impl Iterator<Item = &'static crate::grammar::StyleSpec> {
    PAIR_STYLES
        .iter()
        .flat_map(|p| p.specs.iter())
        .chain(crate::grammar::SPECS.iter())
}

/// The spec of `command style` (e.g. `("fix", "pex/push")`, `("pair_style", "sdpd")`).
pub fn spec(command: &str, style: &str) -> Option<&'static crate::grammar::StyleSpec> {
    all_specs().find(|s| s.command == command && s.style == style)
}

/// The usage of `pair_style` given without a style: the first registry entry's.
pub(crate) fn pair_style_usage() -> &'static str {
    PAIR_STYLES
        .first()
        .and_then(|s| s.specs.iter().find(|p| p.command == "pair_style"))
        .map_or("pair_style STYLE args", |p| p.usage)
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

    #[test]
    fn every_spec_is_unique_and_lists_its_keywords_in_the_usage() {
        for s in PAIR_STYLES {
            assert!(
                s.specs.iter().all(|p| p.style == s.name),
                "{}: a spec of another style",
                s.name
            );
        }
        let specs: Vec<_> = all_specs().collect();
        for (k, s) in specs.iter().enumerate() {
            assert!(
                specs[..k]
                    .iter()
                    .all(|o| (o.command, o.style, o.usage) != (s.command, s.style, s.usage)),
                "{s:?}"
            );
            for kw in s.keywords {
                assert!(s.usage.contains(kw), "{} lacks {kw}", s.usage);
            }
        }
    }

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
        let names: Vec<&str> = PAIR_STYLES.iter().map(|s| s.name).collect();
        assert!(names.starts_with(&["dpd/nonlinear", "sdpd", "mdpd/nonlinear"]));
        assert_eq!(
            e,
            format!(
                "pair style 'lj/cut' not supported: only {}",
                names.join(", ")
            )
        );
    }
}
