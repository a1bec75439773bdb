//! The columns of a data file's `Atoms` and `Velocities` lines for LAMMPS's atom styles beyond
//! the five of [`AtomStyle`]: `charge` (`id type q x y z`), `mdpd` (`id type rho x y z`),
//! `sphere` (`id type diameter density x y z`; velocities `id vx vy vz wx wy wz`) and `hybrid`
//! of these with the others (`id type x y z`, then each sub-style's own columns in the order
//! the sub-styles are named, a column two sub-styles share once, as LAMMPS's `AtomVecHybrid`
//! merges its sub-styles' fields).
//!
//! The DPD styles use none of these columns: charges must be 0 (no Coulomb force here); `rho`
//! (LAMMPS's `mdpd/rhosum` density, which `mdpd/nonlinear` computes itself) and the sphere
//! columns are read and written back unchanged.

use crate::engine::topology::AtomStyle;
use crate::grammar::shown;

/// One field of an `Atoms` line (`X` is three columns).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// The atom id.
    Id,
    /// The molecule id.
    Mol,
    /// The atom type.
    Type,
    /// The charge.
    Q,
    /// `mdpd`'s density.
    Rho,
    /// `sphere`'s diameter.
    Diameter,
    /// `sphere`'s density (its mass when the diameter is 0).
    Density,
    /// The position, x y z.
    X,
}

impl Field {
    /// The column's name in messages.
    fn name(self) -> &'static str {
        match self {
            Field::Id => "id",
            Field::Mol => "mol",
            Field::Type => "type",
            Field::Q => "q",
            Field::Rho => "rho",
            Field::Diameter => "diameter",
            Field::Density => "density",
            Field::X => "x y z",
        }
    }
}

/// The columns of an atom style's `Atoms` and `Velocities` lines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtomColumns {
    /// The style as written after `atom_style` (`charge`, `hybrid sphere bond`, …).
    pub words: Vec<String>,
    /// The style that decides the topology (the most molecular sub-style).
    pub base: AtomStyle,
    /// The fields of an `Atoms` line, before the optional image flags.
    pub atom: Vec<Field>,
    /// True when `Velocities` lines carry the angular velocity (`wx wy wz`, `sphere`).
    pub omega: bool,
}

impl Default for AtomColumns {
    fn default() -> AtomColumns {
        AtomColumns::of(AtomStyle::Atomic)
    }
}

/// The extra per-atom values of the columns beyond the five styles', one set per atom.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AtomExtra {
    /// `rho` (`mdpd`).
    pub rho: f64,
    /// `diameter` (`sphere`).
    pub diameter: f64,
    /// `density` (`sphere`).
    pub density: f64,
}

impl AtomColumns {
    /// The columns of one of the five styles.
    pub fn of(style: AtomStyle) -> AtomColumns {
        AtomColumns {
            words: vec![style.word().to_string()],
            base: style,
            atom: own_fields(style.word()).unwrap_or_default(),
            omega: false,
        }
    }

    /// The columns of `atom_style WORDS…`; an error names a style this engine does not read.
    pub fn parse(words: &[String]) -> Result<AtomColumns, String> {
        let first = words.first().map_or("", String::as_str);
        if first != "hybrid" {
            if let Some(extra) = words.get(1) {
                return Err(format!(
                    "atom_style {first}: unexpected argument '{}'",
                    shown(extra)
                ));
            }
            let base = base_of(first)?;
            return Ok(AtomColumns {
                words: vec![first.to_string()],
                base,
                atom: own_fields(first).unwrap_or_default(),
                omega: first == "sphere",
            });
        }
        let subs = &words[1..];
        if subs.is_empty() {
            return Err(
                "atom_style hybrid needs sub-styles, e.g. atom_style hybrid bond charge".into(),
            );
        }
        let mut atom = vec![Field::Id, Field::Type, Field::X];
        let mut base = AtomStyle::Atomic;
        let mut omega = false;
        for (k, w) in subs.iter().enumerate() {
            if w == "hybrid" {
                return Err("Atom style hybrid cannot have hybrid as an argument".into());
            }
            if subs[..k].contains(w) {
                return Err(format!(
                    "Atom style hybrid cannot use same atom style twice ('{}')",
                    shown(w)
                ));
            }
            let b = base_of(w).map_err(|e| format!("atom_style hybrid: {e}"))?;
            base = more_molecular(base, b);
            omega |= w == "sphere";
            for f in own_fields(w).unwrap_or_default() {
                if !atom.contains(&f) {
                    atom.push(f);
                }
            }
        }
        Ok(AtomColumns {
            words: words.to_vec(),
            base,
            atom,
            omega,
        })
    }

    /// True for the columns of one of the five styles (read and written by their own code).
    pub fn is_plain(&self) -> bool {
        *self == AtomColumns::of(self.base)
    }

    /// The style's word as `write_data` names it after `Atoms #` (`hybrid` for a hybrid).
    pub fn word(&self) -> &str {
        self.words.first().map_or("atomic", String::as_str)
    }

    /// The columns of an `Atoms` line as text (`id type q x y z`).
    pub fn describe(&self) -> String {
        self.atom
            .iter()
            .map(|f| f.name())
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The number of values of an `Atoms` line before the image flags.
    pub fn count(&self) -> usize {
        self.atom
            .iter()
            .map(|f| if *f == Field::X { 3 } else { 1 })
            .sum()
    }

    /// True when atoms carry per-atom masses (`sphere`): the standalone engine has per-type
    /// masses only.
    pub fn per_atom_mass(&self) -> bool {
        self.atom.contains(&Field::Density)
    }
}

/// The fields of a style's own `Atoms` line (LAMMPS's `fields_data_atom`), or None for a style
/// this engine does not read.
fn own_fields(word: &str) -> Option<Vec<Field>> {
    use Field::*;
    Some(match word {
        "atomic" => vec![Id, Type, X],
        "bond" | "angle" | "molecular" => vec![Id, Mol, Type, X],
        "full" => vec![Id, Mol, Type, Q, X],
        "charge" => vec![Id, Type, Q, X],
        "mdpd" => vec![Id, Type, Rho, X],
        "sphere" => vec![Id, Type, Diameter, Density, X],
        _ => return None,
    })
}

/// The topology style of one (sub-)style word.
fn base_of(word: &str) -> Result<AtomStyle, String> {
    match word {
        "charge" | "mdpd" | "sphere" => Ok(AtomStyle::Atomic),
        w => AtomStyle::from_word(w),
    }
}

/// The topology of two sub-styles together: the one that allows more (LAMMPS takes the
/// maximum of `bonds_allow` and `angles_allow`), `full` above `molecular` for its charges.
fn more_molecular(a: AtomStyle, b: AtomStyle) -> AtomStyle {
    let rank = |s: AtomStyle| match s {
        AtomStyle::Atomic => 0,
        AtomStyle::Bond => 1,
        AtomStyle::Angle => 2,
        AtomStyle::Molecular => 3,
        AtomStyle::Full => 4,
    };
    if rank(b) > rank(a) { b } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn hybrid_merges_sub_style_fields_in_order() {
        let c = AtomColumns::parse(&w("hybrid sphere bond")).unwrap();
        assert_eq!(c.describe(), "id type x y z diameter density mol");
        assert_eq!((c.base, c.omega, c.count()), (AtomStyle::Bond, true, 8));
        let c = AtomColumns::parse(&w("hybrid full charge mdpd")).unwrap();
        assert_eq!(c.describe(), "id type x y z mol q rho");
        assert_eq!(c.base, AtomStyle::Full);
        let c = AtomColumns::parse(&w("charge")).unwrap();
        assert_eq!(
            (c.describe().as_str(), c.is_plain()),
            ("id type q x y z", false)
        );
        assert!(AtomColumns::parse(&w("full")).unwrap().is_plain());
    }

    #[test]
    fn hybrid_refusals_name_the_word() {
        for (words, part) in [
            ("hybrid", "needs sub-styles"),
            ("hybrid bond bond", "same atom style twice ('bond')"),
            ("hybrid hybrid", "cannot have hybrid"),
            (
                "hybrid bond dipole",
                "atom_style hybrid: atom_style 'dipole' not supported",
            ),
            ("charge 1", "unexpected argument '1'"),
        ] {
            let e = AtomColumns::parse(&w(words)).unwrap_err();
            assert!(e.contains(part), "{words}: {e}");
        }
    }
}

#[cfg(test)]
mod data_files {
    use super::*;
    use crate::io::data::{format_data, parse_data_columns};

    fn w(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    /// A data file of `atom_style STYLE` as LAMMPS's write_data lays it out, its `Atoms` and
    /// `Velocities` lines given: read, written, read back equal, and the written text read the
    /// same as the original.
    fn round_trip(style: &str, atoms: &str, vels: &str, bonds: bool) -> crate::io::data::DataFile {
        let c = AtomColumns::parse(&w(style)).unwrap();
        let head = if bonds {
            "3 atoms\n2 atom types\n1 bonds\n1 bond types\n"
        } else {
            "3 atoms\n2 atom types\n"
        };
        let tail = if bonds { "\nBonds\n\n1 1 1 2\n" } else { "" };
        let text = format!(
            "LAMMPS data file via write_data, timestep = 5\n\n{head}\n0 4 xlo xhi\n0 4 ylo yhi\n\
             0 4 zlo zhi\n\nMasses\n\n1 1\n2 2\n\nAtoms # {}\n\n{atoms}\nVelocities\n\n{vels}{tail}",
            c.word()
        );
        let d = parse_data_columns(&text, "t.data", &c).unwrap();
        let written = format_data(&d, "again");
        let back = parse_data_columns(&written, "again.data", &c).unwrap();
        assert_eq!(back, d, "{written}");
        assert!(
            written.contains(&format!("Atoms # {}", c.word())),
            "{written}"
        );
        d
    }

    #[test]
    fn charge_mdpd_sphere_and_hybrid_data_files_round_trip() {
        let d = round_trip(
            "charge",
            "1 1 0 0.5 0.5 0.5 0 0 0\n2 2 0.0 1.5 1.5 1.5 1 0 0\n3 1 0 2.5 2.5 2.5 0 0 -1\n",
            "1 0.1 0.2 0.3\n2 0 0 0\n3 -1 0 1\n",
            false,
        );
        assert_eq!(d.atoms[2].3, [0, 0, -1]);
        let d = round_trip(
            "mdpd",
            "1 1 5.25 0.5 0.5 0.5 0 0 0\n2 2 6.125 1.5 1.5 1.5\n3 1 0 2.5 2.5 2.5 0 0 0\n",
            "1 0.1 0.2 0.3\n2 0 0 0\n3 -1 0 1\n",
            false,
        );
        assert_eq!(d.extra[1].rho, 6.125);
        let d = round_trip(
            "sphere",
            "1 1 1 1.9098593171027443 0.5 0.5 0.5 0 0 0\n2 2 0 2.0 1.5 1.5 1.5 0 0 0\n\
             3 1 0.5 3 2.5 2.5 2.5 0 0 0\n",
            "1 0.1 0.2 0.3 1 2 3\n2 0 0 0 0 0 0\n3 -1 0 1 0 0 0.5\n",
            false,
        );
        assert_eq!((d.extra[0].diameter, d.extra[2].density), (1.0, 3.0));
        assert_eq!(d.omega[0], [1.0, 2.0, 3.0]);
        let d = round_trip(
            "hybrid sphere bond",
            "1 1 0.5 0.5 0.5 1 2 7 0 0 0\n2 2 1.5 1.5 1.5 1 2 7 0 0 0\n\
             3 1 2.5 2.5 2.5 1 2 8 0 0 0\n",
            "1 0.1 0.2 0.3 0 0 0\n2 0 0 0 0 0 0\n3 -1 0 1 0 0 0\n",
            true,
        );
        assert_eq!((d.mol.clone(), d.bonds.len()), (vec![7, 7, 8], 1));
        let d = round_trip(
            "hybrid bond charge mdpd",
            "1 1 0.5 0.5 0.5 3 0 4.5 0 0 0\n2 2 1.5 1.5 1.5 3 0 4 0 0 0\n\
             3 1 2.5 2.5 2.5 4 0 1 0 0 0\n",
            "1 0.1 0.2 0.3\n2 0 0 0\n3 -1 0 1\n",
            true,
        );
        assert_eq!((d.mol[2], d.extra[0].rho), (4, 4.5));
    }

    #[test]
    fn refusals_of_the_extra_columns_name_the_line() {
        let c = AtomColumns::parse(&w("charge")).unwrap();
        let text = "t\n\n1 atoms\n1 atom types\n\n0 4 xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n\n\
                    Atoms # charge\n\n1 1 0.5 1 1 1\n";
        let e = parse_data_columns(text, "t.data", &c).unwrap_err();
        assert!(e.starts_with("t.data:12: atom 1 has charge 0.5"), "{e}");
        let e = parse_data_columns(&text.replace("0.5 1 1 1", "1 1 1"), "t.data", &c).unwrap_err();
        assert!(e.contains("needs 'id type q x y z [ix iy iz]'"), "{e}");
        let c = AtomColumns::parse(&w("sphere")).unwrap();
        let text = text
            .replace("# charge", "# sphere")
            .replace("0.5 1 1 1", "1 0 1 1 1");
        let e = parse_data_columns(&text, "t.data", &c).unwrap_err();
        assert!(e.contains("Invalid density in Atoms section"), "{e}");
    }
}
