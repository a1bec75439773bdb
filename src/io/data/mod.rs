//! LAMMPS data files (`read_data` / `write_data`) for `atom_style atomic`, `bond`, `angle`,
//! `molecular` and `full`, and the columns of `charge`, `mdpd`, `sphere` and `hybrid` of these
//! ([`AtomColumns`]).
//!
//! Supported: the header keywords `atoms`, `atom types`, `bonds`, `bond types`, `angles`,
//! `angle types` (dihedrals and impropers: 0), the `extra … per atom` counts LAMMPS writes
//! (accepted, not needed), `xlo xhi`, `ylo yhi`, `zlo zhi`, `xy xz yz` (a triclinic box tilted
//! in xy only: xz = yz = 0); the sections `Masses`, `Atoms` (the
//! style's columns, `id [mol] type [q] x y z`, with optional image flags `ix iy iz`),
//! `Velocities` (`id vx vy vz`), `Bonds` (`id type a1 a2`), `Angles` (`id type a1 a2 a3`),
//! and the coefficient sections `Pair Coeffs`, `PairIJ Coeffs`, `Bond Coeffs`, `Angle Coeffs`
//! (kept as words, in file order, for the styles: [`CoeffSection`]). Anything else is an error
//! naming the file and line. Real numbers (box bounds, masses, coordinates, velocities) must be
//! finite: `nan`, `inf` or `1e999` is an error naming the file, line and column. A bond or angle
//! naming an atom id the file lacks, or a type out of range, is an error naming the file and
//! line. Image flags are taken as they are: bonded atoms whose image flags put them more than
//! half a box apart are LAMMPS's "Inconsistent image flags", a warning of each run's set-up
//! (`engine::System`), not an error of the file.

use std::fmt::Write as _;

use crate::engine::topology::{Angle, AtomStyle, Bond};

/// The content of a data file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DataFile {
    /// Number of atom types.
    pub ntypes: usize,
    /// Box lower corner.
    pub lo: [f64; 3],
    /// Box upper corner.
    pub hi: [f64; 3],
    /// The tilt factors `[xy, xz, yz]` of a triclinic box (xz = yz = 0), None: orthogonal.
    pub tilt: Option<[f64; 3]>,
    /// Masses by type (1-based, index 0 unused); None where the file gives none.
    pub masses: Vec<Option<f64>>,
    /// Atoms: (tag, type, x, image).
    pub atoms: Vec<(u32, u32, [f64; 3], [i32; 3])>,
    /// Velocities by tag, in file order (empty when the file has no Velocities section).
    pub velocities: Vec<(u32, [f64; 3])>,
    /// The atom style of the `Atoms` columns.
    pub style: AtomStyle,
    /// Molecule ids, one per atom of `atoms` (empty for `atomic`).
    pub mol: Vec<u32>,
    /// Number of bond types.
    pub nbondtypes: usize,
    /// Number of angle types.
    pub nangletypes: usize,
    /// Bonds, in file order.
    pub bonds: Vec<Bond>,
    /// Angles, in file order.
    pub angles: Vec<Angle>,
    /// The coefficient sections (`Pair Coeffs`, `PairIJ Coeffs`, `Bond Coeffs`, `Angle
    /// Coeffs`), in file order.
    pub coeffs: Vec<CoeffSection>,
    /// The style named after `#` on the `Atoms` line (write_data's hint), if any (none when
    /// `Atoms` is the first section: LAMMPS does not see it there).
    pub atoms_hint: Option<String>,
    /// The columns of the `Atoms` and `Velocities` lines (those of `style` unless a `charge`,
    /// `mdpd`, `sphere` or `hybrid` style was given: [`parse_data_columns`]).
    pub columns: AtomColumns,
    /// The values of the columns beyond the five styles', one per atom of `atoms` (empty for
    /// those styles).
    pub extra: Vec<AtomExtra>,
    /// The angular velocities of `sphere`'s `Velocities` lines, one per line of `velocities`
    /// (empty without them).
    pub omega: Vec<[f64; 3]>,
}

/// Which coefficient section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoeffKind {
    /// `Pair Coeffs`: one line `I c…` per atom type, LAMMPS's `pair_coeff I I c…`.
    Pair,
    /// `PairIJ Coeffs`: one line `I J c…` per type pair I ≤ J, `pair_coeff I J c…`.
    PairIJ,
    /// `Bond Coeffs`: one line `N c…` per bond type, `bond_coeff N c…`.
    Bond,
    /// `Angle Coeffs`: one line `N c…` per angle type, `angle_coeff N c…`.
    Angle,
}

impl CoeffKind {
    /// The section's title.
    pub fn title(self) -> &'static str {
        match self {
            CoeffKind::Pair => "Pair Coeffs",
            CoeffKind::PairIJ => "PairIJ Coeffs",
            CoeffKind::Bond => "Bond Coeffs",
            CoeffKind::Angle => "Angle Coeffs",
        }
    }

    /// The style command the section needs (`pair_style`, `bond_style`, `angle_style`).
    pub fn style_command(self) -> &'static str {
        match self {
            CoeffKind::Pair | CoeffKind::PairIJ => "pair_style",
            CoeffKind::Bond => "bond_style",
            CoeffKind::Angle => "angle_style",
        }
    }
}

/// One coefficient section of a data file, as read: LAMMPS's `read_data` hands each line to
/// the style's `coeff` (a `Pair Coeffs` line `I c…` as `I I c…`).
#[derive(Clone, Debug, PartialEq)]
pub struct CoeffSection {
    /// Which section.
    pub kind: CoeffKind,
    /// 1-based line number of the section's title.
    pub line: usize,
    /// The style named after `#` on the title line (write_data's hint), if any (none for the
    /// file's first section, as LAMMPS reads it).
    pub style: Option<String>,
    /// The lines: (1-based line number, words without the comment).
    pub lines: Vec<(usize, Vec<String>)>,
}

impl CoeffSection {
    /// The words of the coefficient command of line `k` (after the command name): a `Pair
    /// Coeffs` line `I c…` becomes `I I c…`, as LAMMPS's `read_data` passes it to the style.
    pub fn command_words(&self, k: usize) -> Vec<String> {
        let words = &self.lines[k].1;
        match (self.kind, words.split_first()) {
            (CoeffKind::Pair, Some((first, rest))) => std::iter::once(first.clone())
                .chain(std::iter::once(first.clone()))
                .chain(rest.iter().cloned())
                .collect(),
            _ => words.clone(),
        }
    }
}

/// Style names LAMMPS's `read_data` ignores at the end of a name when it compares a section's
/// `# style` with the style defined (`ReadData::style_match`'s `suffixes`).
const STYLE_SUFFIXES: [&str; 11] = [
    "/cuda",
    "/gpu",
    "/opt",
    "/omp",
    "/kk",
    "/coul/cut",
    "/coul/long",
    "/coul/msm",
    "/coul/dsf",
    "/coul/debye",
    "/coul/charmm",
];

/// LAMMPS's `ReadData::style_match(one, two)`, rule for rule: `one` (the `# style` of a data
/// file's section) matches the defined style `two` when, with the suffixes above removed from
/// either, `one` is empty, the two have the same length (LAMMPS compares only the lengths
/// there), or `one` is a prefix of `two`. A mismatch is a warning in LAMMPS ("… style in data
/// file differs from currently defined … style"), not an error.
pub fn style_match(one: &str, two: &str) -> bool {
    let strip = |s: &str| -> usize {
        let b = s.as_bytes();
        let mut len = b.len();
        for suf in STYLE_SUFFIXES {
            // As LAMMPS: each suffix in turn, against the name from len − |suffix| to its end.
            if len > suf.len() && &b[len - suf.len()..] == suf.as_bytes() {
                len -= suf.len();
            }
        }
        len
    };
    let (len1, len2) = (strip(one), strip(two));
    len1 == 0 || len1 == len2 || two.as_bytes().starts_with(&one.as_bytes()[..len1])
}

mod columns;
mod read;
mod write;

pub use columns::{AtomColumns, AtomExtra, Field};
pub use read::{parse_data, parse_data_columns, parse_data_styled};
pub use write::{CoeffRows, format_data, format_data_with};

#[cfg(test)]
mod tests {
    use super::*;

    /// LAMMPS's `style_match`, rule for rule: an empty hint, a prefix, the suffixes, and its
    /// quirk of matching any two names of the same length.
    #[test]
    fn style_match_is_lammps_rule() {
        for (one, two, want) in [
            ("dpd/nonlinear", "dpd/nonlinear", true),
            ("", "harmonic", true),
            ("harm", "harmonic", true),
            ("harmonic", "fene", false),
            ("dpd/nonlinear", "sdpd", false),
            ("dpd/nonlinear", "zero", false),
            ("fene", "zero", true),
            ("fene2", "fene", false),
            ("lj/cut/omp", "lj/cut", true),
            ("lj/cut", "lj/cut/coul/long", true),
            ("sdpd/kk", "sdpd", true),
        ] {
            assert_eq!(style_match(one, two), want, "{one} vs {two}");
        }
    }

    /// `Pair Coeffs` (one line per type, given to the style as `I I c…`) and `PairIJ Coeffs`
    /// (one line per type pair) in file order with their hints; the first section's hint is
    /// not seen, as LAMMPS does not see it.
    #[test]
    fn coefficient_sections_in_file_order() {
        let head = "title\n\n2 atoms\n2 atom types\n\n0 4 xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n";
        let atoms = "\nAtoms # atomic\n\n1 1 1 1 1\n2 2 2 2 2\n";
        let text = format!(
            "{head}\nPair Coeffs # dpd/nonlinear\n\n1 25 4.5 0 1\n2 20 3 0 1 # a comment\n\
             \nPairIJ Coeffs # sdpd\n\n1 1 4 10 10\n1 2 4 10 8 2.2\n2 2 6 10 10\n{atoms}"
        );
        let d = parse_data(&text, "t.data").unwrap();
        assert_eq!(d.coeffs.len(), 2);
        let (p, ij) = (&d.coeffs[0], &d.coeffs[1]);
        assert_eq!(
            (p.kind, p.line, p.style.as_deref()),
            (CoeffKind::Pair, 10, None)
        );
        assert_eq!(p.command_words(1), ["2", "2", "20", "3", "0", "1"]);
        assert_eq!(ij.kind, CoeffKind::PairIJ);
        assert_eq!(ij.style.as_deref(), Some("sdpd"));
        assert_eq!(ij.lines.len(), 3);
        assert_eq!(ij.command_words(1), ["1", "2", "4", "10", "8", "2.2"]);
        assert_eq!(d.atoms_hint.as_deref(), Some("atomic"));
        // Atoms first: its hint is not seen either.
        let d = parse_data(&format!("{head}{atoms}"), "t.data").unwrap();
        assert_eq!(d.atoms_hint, None);
        // A line short: the blank line after it is read as the second line (as LAMMPS does).
        let short = format!("{head}\nMasses\n\n1 1\n2 1\n\nPair Coeffs\n\n1 25 4.5 0 1\n\n{atoms}");
        let e = parse_data(&short, "t.data").unwrap_err();
        assert_eq!(e, "t.data:18: Unexpected empty line in Pair Coeffs section");
    }
}
