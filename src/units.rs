//! LAMMPS's unit styles (`units lj|real|metal|…`) and the conversion constants of theirs that
//! this project needs, in one place for both engines.
//!
//! LAMMPS's unit styles are not coherent: a force times a time divided by a mass is a velocity
//! only after a factor `ftm2v`, a mass times a squared velocity is an energy only after
//! `mvv2e`, and an energy per volume is a pressure only after `nktv2p`. Every place of this
//! project that crosses one of those lines takes the factor from a [`Units`]:
//!
//! | where | what | constant |
//! |---|---|---|
//! | `pair_style dpd/nonlinear`, `sdpd` | T is a temperature, as for LAMMPS's `pair_style dpd`: kT = k_B T | `boltz` |
//! | `noise twostep` (kernel) | the pair-local kick v'' = v + (1/m_i + 1/m_j) δp e, δp a force × time | `ftm2v` |
//! | `noise corrected` (kernel) | F^A ∝ kT (1/m_i + 1/m_j): kT/m as a squared velocity | `ftm2v` (= 1/`mvv2e`) |
//! | `pair_style sdpd` | the Tait pressure c0² ρ0 / 7 (mass × velocity² per volume) as an energy per volume | `mvv2e` |
//! | (η, Sc) design, kinetic theory, Euler warning | the mass in m kT, m D / kT, kT / m | `mvv2e` (the theory's mass is m·mvv2e) |
//! | integrators (`fix nve`, `nve/euler`) | v += δt F / m | `ftm2v` |
//! | thermo (standalone engine) | temperature, kinetic energy, pressure, mass density | `boltz`, `mvv2e`, `nktv2p`, `mv2d` |
//!
//! A viscosity (`pair_coeff … eta E`, sDPD's `eta0`) is in LAMMPS's native unit energy × time
//! / volume (= force × time / area, what LAMMPS's `pair_style lubricate` takes): `lj` ε τ/σ³,
//! `real` (kcal/mol)·fs/Å³, `metal` eV·ps/Å³ (2-D: per area). LAMMPS's pressure output is that
//! energy per volume times `nktv2p`, so −pxy/γ̇ from thermo is η × `nktv2p`.
//!
//! The LAMMPS styles take the constants from LAMMPS (`force->boltz`, …, through the C ABI's
//! `DpdnlUnits`); the standalone engine reads `units lj`, `real`, `metal`, `si`, `cgs`, `micro`
//! and `nano` with the same numbers as LAMMPS's `Update::set_units` ([`Units::standalone`]);
//! only `electron` (atomic units, of no use to DPD) is LAMMPS's alone. In `lj` every factor is
//! 1, so multiplying by it changes no bit of an `lj` run; `si`, `cgs`, `micro` and `nano` are
//! coherent (mvv2e = ftm2v = nktv2p = mv2d = 1) and differ from `lj` by `boltz` alone.

use std::fmt;

/// One of LAMMPS's unit styles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnitStyle {
    /// Reduced units: mass m, distance σ, energy ε, time τ = σ √(m/ε), k_B = 1.
    Lj,
    /// g/mol, Å, fs, kcal/mol, K.
    Real,
    /// g/mol, Å, ps, eV, K.
    Metal,
    /// kg, m, s, J, K.
    Si,
    /// g, cm, s, erg, K.
    Cgs,
    /// amu, Bohr, fs, Hartree, K.
    Electron,
    /// pg, μm, μs, pg·μm²/μs², K.
    Micro,
    /// ag, nm, ns, ag·nm²/ns², K.
    Nano,
}

impl UnitStyle {
    /// Every unit style LAMMPS has.
    pub const ALL: [UnitStyle; 8] = [
        UnitStyle::Lj,
        UnitStyle::Real,
        UnitStyle::Metal,
        UnitStyle::Si,
        UnitStyle::Cgs,
        UnitStyle::Electron,
        UnitStyle::Micro,
        UnitStyle::Nano,
    ];

    /// The word of `units WORD`.
    pub fn name(self) -> &'static str {
        match self {
            UnitStyle::Lj => "lj",
            UnitStyle::Real => "real",
            UnitStyle::Metal => "metal",
            UnitStyle::Si => "si",
            UnitStyle::Cgs => "cgs",
            UnitStyle::Electron => "electron",
            UnitStyle::Micro => "micro",
            UnitStyle::Nano => "nano",
        }
    }

    /// The style of `units WORD`, if LAMMPS has it.
    pub fn from_name(word: &str) -> Option<UnitStyle> {
        UnitStyle::ALL.into_iter().find(|u| u.name() == word)
    }
}

impl fmt::Display for UnitStyle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The unit styles the standalone engine reads: all but `electron` (LAMMPS with this project's
/// styles runs every one of [`UnitStyle::ALL`]).
pub const STANDALONE_STYLES: [UnitStyle; 7] = [
    UnitStyle::Lj,
    UnitStyle::Real,
    UnitStyle::Metal,
    UnitStyle::Si,
    UnitStyle::Cgs,
    UnitStyle::Micro,
    UnitStyle::Nano,
];

/// A unit style and its conversion constants, named as LAMMPS's `Force` members.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// The style.
    pub style: UnitStyle,
    /// Boltzmann's constant k_B in energy / temperature (`force->boltz`).
    pub boltz: f64,
    /// mass × velocity² → energy (`force->mvv2e`).
    pub mvv2e: f64,
    /// force × time / mass → velocity (`force->ftm2v`).
    pub ftm2v: f64,
    /// energy / volume → pressure (`force->nktv2p`).
    pub nktv2p: f64,
    /// mass / volume → mass density (`force->mv2d`; thermo `density`, `ave/chunk
    /// density/mass`).
    pub mv2d: f64,
}

/// √mvv2e of `units real` as LAMMPS writes it (Å/fs per √((kcal/mol)/(g/mol))).
const REAL_V: f64 = 48.88821291;

impl Units {
    /// `units lj`: every factor 1.
    pub const LJ: Units = Units {
        style: UnitStyle::Lj,
        boltz: 1.0,
        mvv2e: 1.0,
        ftm2v: 1.0,
        nktv2p: 1.0,
        mv2d: 1.0,
    };

    /// `units real` (LAMMPS's `Update::set_units`, the thermochemical calorie).
    pub const REAL: Units = Units {
        style: UnitStyle::Real,
        boltz: 0.0019872067,
        mvv2e: REAL_V * REAL_V,
        ftm2v: 1.0 / REAL_V / REAL_V,
        nktv2p: 68568.415,
        mv2d: 1.0 / 0.602214129,
    };

    /// `units metal` (LAMMPS's `Update::set_units`).
    pub const METAL: Units = Units {
        style: UnitStyle::Metal,
        boltz: 8.617343e-5,
        mvv2e: 1.0364269e-4,
        ftm2v: 1.0 / 1.0364269e-4,
        nktv2p: 1.6021765e6,
        mv2d: 1.0 / 0.602214129,
    };

    /// `units si`: kg, m, s, J, K (LAMMPS's `Update::set_units`).
    pub const SI: Units = Units::coherent(UnitStyle::Si, 1.3806504e-23);

    /// `units cgs`: g, cm, s, erg, K (LAMMPS's `Update::set_units`).
    pub const CGS: Units = Units::coherent(UnitStyle::Cgs, 1.3806504e-16);

    /// `units micro`: pg, μm, μs, pg·μm²/μs², K (LAMMPS's `Update::set_units`).
    pub const MICRO: Units = Units::coherent(UnitStyle::Micro, 1.3806504e-8);

    /// `units nano`: ag, nm, ns, ag·nm²/ns², K (LAMMPS's `Update::set_units`).
    pub const NANO: Units = Units::coherent(UnitStyle::Nano, 0.013806504);

    /// A coherent style: every conversion factor 1, Boltzmann's constant `boltz`.
    const fn coherent(style: UnitStyle, boltz: f64) -> Units {
        Units {
            style,
            boltz,
            mvv2e: 1.0,
            ftm2v: 1.0,
            nktv2p: 1.0,
            mv2d: 1.0,
        }
    }

    /// The units of `units WORD` in the standalone engine (any style of
    /// [`STANDALONE_STYLES`]); any other word is refused, naming what is read and that LAMMPS
    /// runs the other styles.
    pub fn standalone(word: &str) -> Result<Units, String> {
        match UnitStyle::from_name(word) {
            Some(UnitStyle::Lj) => Ok(Units::LJ),
            Some(UnitStyle::Real) => Ok(Units::REAL),
            Some(UnitStyle::Metal) => Ok(Units::METAL),
            Some(UnitStyle::Si) => Ok(Units::SI),
            Some(UnitStyle::Cgs) => Ok(Units::CGS),
            Some(UnitStyle::Micro) => Ok(Units::MICRO),
            Some(UnitStyle::Nano) => Ok(Units::NANO),
            Some(u) => Err(format!(
                "units '{u}' not supported by the standalone engine: it reads {} (LAMMPS with \
                 this project's styles runs every unit style)",
                standalone_list()
            )),
            None => Err(format!(
                "units '{}' is not a LAMMPS unit style (lj real metal si cgs electron micro nano)",
                crate::grammar::shown(word)
            )),
        }
    }

    /// The units of a host (LAMMPS: `update->unit_style` and `force->boltz`, …): the style
    /// must be one LAMMPS has and every constant finite and > 0.
    pub fn from_host(
        style: &str,
        boltz: f64,
        mvv2e: f64,
        ftm2v: f64,
        nktv2p: f64,
        mv2d: f64,
    ) -> Result<Units, String> {
        let style = UnitStyle::from_name(style).ok_or_else(|| {
            format!(
                "unit style '{}' is not one of LAMMPS's (lj real metal si cgs electron micro nano)",
                crate::grammar::shown(style)
            )
        })?;
        for (name, v) in [
            ("boltz", boltz),
            ("mvv2e", mvv2e),
            ("ftm2v", ftm2v),
            ("nktv2p", nktv2p),
            ("mv2d", mv2d),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!(
                    "units {style}: {name} = {v} must be a finite number > 0 (LAMMPS's \
                     force->{name})"
                ));
            }
        }
        Ok(Units {
            style,
            boltz,
            mvv2e,
            ftm2v,
            nktv2p,
            mv2d,
        })
    }

    /// True for `units lj`.
    pub fn is_lj(&self) -> bool {
        self.style == UnitStyle::Lj
    }

    /// kT = k_B T of a temperature T (the T of `pair_style dpd/nonlinear` and `sdpd`, as of
    /// LAMMPS's `pair_style dpd`); T itself in `lj`.
    pub fn kt(&self, t: f64) -> f64 {
        self.boltz * t
    }

    /// The time step LAMMPS sets with `units` (LAMMPS's `Update::set_units`).
    pub fn default_dt(&self) -> f64 {
        match self.style {
            UnitStyle::Lj => 0.005,
            UnitStyle::Real => 1.0,
            UnitStyle::Metal | UnitStyle::Electron => 0.001,
            UnitStyle::Si | UnitStyle::Cgs => 1.0e-8,
            UnitStyle::Micro => 2.0,
            UnitStyle::Nano => 0.00045,
        }
    }

    /// The neighbour skin LAMMPS sets with `units` (LAMMPS's `Update::set_units`).
    pub fn default_skin(&self) -> f64 {
        match self.style {
            UnitStyle::Lj => 0.3,
            UnitStyle::Real | UnitStyle::Metal | UnitStyle::Electron => 2.0,
            UnitStyle::Si => 0.001,
            UnitStyle::Cgs | UnitStyle::Micro | UnitStyle::Nano => 0.1,
        }
    }

    /// The line a set-up logs outside `lj`: what T means and the kT it gives (`style`: the pair
    /// style's name). None in `lj`, where kT = T.
    pub fn temperature_note(&self, style: &str, t: f64) -> Option<String> {
        use crate::fmtnum::short as n;
        (!self.is_lj()).then(|| {
            format!(
                "pair_style {style}: units {}: T = {} is a temperature (as for pair_style dpd): \
                 kT = boltz T = {} energy units (boltz = {}, mvv2e = {}, ftm2v = {})",
                self.style,
                n(t),
                n(self.kt(t)),
                n(self.boltz),
                n(self.mvv2e),
                n(self.ftm2v)
            )
        })
    }
}

impl Default for Units {
    fn default() -> Self {
        Units::LJ
    }
}

/// "lj, real, metal, si, cgs, micro and nano".
fn standalone_list() -> String {
    let names: Vec<&str> = STANDALONE_STYLES.iter().map(|u| u.name()).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The products LAMMPS's dynamics rely on: a force × time / mass as a velocity, squared and
    /// times a mass, is an energy (mvv2e ftm2v = 1 to rounding in every standalone style).
    #[test]
    fn constants_are_consistent() {
        for u in [
            Units::LJ,
            Units::REAL,
            Units::METAL,
            Units::SI,
            Units::CGS,
            Units::MICRO,
            Units::NANO,
        ] {
            assert!(
                (u.mvv2e * u.ftm2v - 1.0).abs() < 4.0 * f64::EPSILON,
                "{u:?}"
            );
            assert_eq!(Units::standalone(u.style.name()), Ok(u));
        }
        assert_eq!(Units::LJ.kt(0.7).to_bits(), 0.7f64.to_bits());
        assert_eq!(Units::REAL.kt(300.0), 0.0019872067 * 300.0);
        // LAMMPS writes mvv2e of real as a product: the same double here.
        assert_eq!(Units::REAL.mvv2e, 48.88821291 * 48.88821291);
    }

    #[test]
    fn names_and_refusals() {
        for u in UnitStyle::ALL {
            assert_eq!(UnitStyle::from_name(u.name()), Some(u));
        }
        let e = Units::standalone("electron").expect_err("electron is LAMMPS-only");
        assert!(
            e.contains("'electron'") && e.contains("lj, real, metal, si, cgs, micro and nano"),
            "{e}"
        );
        let e = Units::standalone("furlong").expect_err("not a unit style");
        assert!(e.contains("'furlong'"), "{e}");
        assert!(Units::from_host("si", 1.38e-23, 1.0, 1.0, 1.0, 1.0).is_ok());
        let e = Units::from_host("real", 0.0, 1.0, 1.0, 1.0, 1.0).expect_err("boltz 0");
        assert!(e.contains("boltz = 0"), "{e}");
        assert!(Units::from_host("parsec", 1.0, 1.0, 1.0, 1.0, 1.0).is_err());
        assert_eq!(Units::LJ.temperature_note("x", 1.0), None);
    }
}
