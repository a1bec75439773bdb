//! Molecular topology of the standalone engine: the atom style, bonds and angles by atom id
//! (so the cell sort leaves them alone), `special_bonds`, the 1-2/1-3/1-4 neighbours LAMMPS
//! derives from the bond graph, and the index form of all of it rebuilt after every sort
//! ([`BondedIndex`]): bonds and angles as atom indices in topology order, and each atom's
//! special partners, which the pair loop consults ([`SpecialPairs`]).

use std::collections::HashMap;

use crate::forces::bonded::{AngleStyle, BondStyle};
use crate::grammar::{parse_f64, shown};

/// LAMMPS's `atom_style` (the ones this engine reads).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AtomStyle {
    /// `id type x y z`.
    #[default]
    Atomic,
    /// `id mol type x y z`, bonds.
    Bond,
    /// `id mol type x y z`, bonds and angles.
    Angle,
    /// `id mol type x y z`, bonds, angles (dihedrals and impropers: none here).
    Molecular,
    /// `id mol type q x y z` (q must be 0: no Coulomb interactions here).
    Full,
}

impl AtomStyle {
    /// The style of a word, or an error naming it.
    pub fn from_word(w: &str) -> Result<AtomStyle, String> {
        Ok(match w {
            "atomic" => AtomStyle::Atomic,
            "bond" => AtomStyle::Bond,
            "angle" => AtomStyle::Angle,
            "molecular" => AtomStyle::Molecular,
            "full" => AtomStyle::Full,
            other => {
                const ONLY: &str =
                    "only atomic, bond, angle, molecular, full, charge, mdpd and hybrid of these";
                let why = match other {
                    "sphere" | "dipole" | "ellipsoid" => {
                        ": this engine has per-type masses only (the DPD styles use no radius, \
                         dipole or shape); use atom_style atomic with `mass`"
                    }
                    _ => "",
                };
                return Err(format!(
                    "atom_style '{}' not supported: {ONLY}{why}",
                    shown(other)
                ));
            }
        })
    }

    /// The style word.
    pub fn word(self) -> &'static str {
        match self {
            AtomStyle::Atomic => "atomic",
            AtomStyle::Bond => "bond",
            AtomStyle::Angle => "angle",
            AtomStyle::Molecular => "molecular",
            AtomStyle::Full => "full",
        }
    }

    /// True when atoms carry a molecule id and the system may have bonds.
    pub fn molecular(self) -> bool {
        self != AtomStyle::Atomic
    }

    /// True when the style holds angles.
    pub fn has_angles(self) -> bool {
        matches!(
            self,
            AtomStyle::Angle | AtomStyle::Molecular | AtomStyle::Full
        )
    }

    /// The columns of a data file's `Atoms` line (before the optional image flags).
    pub fn columns(self) -> &'static str {
        match self {
            AtomStyle::Atomic => "id type x y z",
            AtomStyle::Full => "id mol type q x y z",
            _ => "id mol type x y z",
        }
    }

    /// A code for restart files.
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The style of a restart code.
    pub fn from_code(c: u8) -> Option<AtomStyle> {
        [
            AtomStyle::Atomic,
            AtomStyle::Bond,
            AtomStyle::Angle,
            AtomStyle::Molecular,
            AtomStyle::Full,
        ]
        .get(c as usize)
        .copied()
    }
}

/// One bond: its type and the ids of its two atoms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bond {
    /// Bond type (1-based).
    pub typ: u32,
    /// Atom ids.
    pub atoms: [u32; 2],
}

/// One angle: its type and the ids of its three atoms (the middle one is the vertex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Angle {
    /// Angle type (1-based).
    pub typ: u32,
    /// Atom ids.
    pub atoms: [u32; 3],
}

/// LAMMPS's `special_bonds` settings: factors by class (0 ordinary, 1–3 for 1-2, 1-3, 1-4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecialBonds {
    /// `lj` factors (entry 0 is 1).
    pub lj: [f64; 4],
    /// `coul` factors (entry 0 is 1); with no charges they only decide, with `lj`, whether a
    /// pair of factor 0 is left out of the neighbour list (it is then, as in LAMMPS, when both
    /// are 0) — which changes nothing here, a pair of `lj` factor 0 has no force either way.
    pub coul: [f64; 4],
    /// `angle yes`: a 1-3 pair counts only when an angle holds both atoms as its ends.
    pub angle: bool,
    /// `dihedral yes`: a 1-4 pair counts only when a dihedral holds both (none here: no 1-4).
    pub dihedral: bool,
}

impl Default for SpecialBonds {
    /// LAMMPS's defaults: lj and coul 0 0 0, angle no, dihedral no.
    fn default() -> SpecialBonds {
        SpecialBonds {
            lj: [1.0, 0.0, 0.0, 0.0],
            coul: [1.0, 0.0, 0.0, 0.0],
            angle: false,
            dihedral: false,
        }
    }
}

/// The usage of `special_bonds`.
pub(crate) const SPECIAL_USAGE: &str = "special_bonds [lj|coul|lj/coul a b c] [fene|charmm|dreiding|amber] [angle yes|no] [dihedral yes|no]";

impl SpecialBonds {
    /// A `special_bonds` command: every setting not given returns to its default, as in
    /// LAMMPS.
    pub fn parse(args: &[String]) -> Result<SpecialBonds, String> {
        if args.is_empty() {
            return Err(format!("missing arguments; usage: {SPECIAL_USAGE}"));
        }
        let mut s = SpecialBonds::default();
        let mut k = 0;
        let three = |k: usize, kw: &str| -> Result<[f64; 4], String> {
            if args.len() < k + 4 {
                return Err(format!(
                    "special_bonds {kw} needs 3 factors; usage: {SPECIAL_USAGE}"
                ));
            }
            let mut f = [1.0; 4];
            for b in 1..4 {
                let v = parse_f64(&args[k + b], "a special_bonds factor")?;
                if !(0.0..=1.0).contains(&v) {
                    return Err(format!(
                        "special_bonds {kw} factor {v} of 1-{} neighbours must be in [0, 1]",
                        b + 1
                    ));
                }
                f[b] = v;
            }
            Ok(f)
        };
        let yes_no = |k: usize, kw: &str| -> Result<bool, String> {
            match args.get(k + 1).map(String::as_str) {
                Some("yes") => Ok(true),
                Some("no") => Ok(false),
                Some(o) => Err(format!(
                    "special_bonds {kw} '{}' must be yes or no",
                    shown(o)
                )),
                None => Err(format!("special_bonds {kw} needs yes or no")),
            }
        };
        while k < args.len() {
            match args[k].as_str() {
                "lj" => {
                    s.lj = three(k, "lj")?;
                    k += 4;
                }
                "coul" => {
                    s.coul = three(k, "coul")?;
                    k += 4;
                }
                "lj/coul" => {
                    s.lj = three(k, "lj/coul")?;
                    s.coul = s.lj;
                    k += 4;
                }
                "fene" | "charmm" | "dreiding" | "amber" => {
                    (s.lj, s.coul) = match args[k].as_str() {
                        "fene" => ([1.0, 0.0, 1.0, 1.0], [1.0, 0.0, 1.0, 1.0]),
                        "charmm" => ([1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
                        "dreiding" => ([1.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]),
                        _ => ([1.0, 0.0, 0.0, 0.5], [1.0, 0.0, 0.0, 5.0 / 6.0]),
                    };
                    k += 1;
                }
                "angle" => {
                    s.angle = yes_no(k, "angle")?;
                    k += 2;
                }
                "dihedral" => {
                    s.dihedral = yes_no(k, "dihedral")?;
                    k += 2;
                }
                other => {
                    return Err(format!(
                        "unknown special_bonds keyword '{}'; usage: {SPECIAL_USAGE}",
                        shown(other)
                    ));
                }
            }
        }
        Ok(s)
    }

    /// The words of a `special_bonds` command that restores these settings exactly.
    pub fn words(&self) -> Vec<String> {
        let w = crate::forces::style::word;
        let mut out = vec!["lj".to_string()];
        out.extend(self.lj[1..].iter().map(|&f| w(f)));
        out.push("coul".into());
        out.extend(self.coul[1..].iter().map(|&f| w(f)));
        out.push("angle".into());
        out.push(if self.angle { "yes" } else { "no" }.into());
        out.push("dihedral".into());
        out.push(if self.dihedral { "yes" } else { "no" }.into());
        out
    }
}

/// The topology of a molecular system.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Topology {
    /// The atom style the system was made with.
    pub style: AtomStyle,
    /// Number of bond types.
    pub nbondtypes: usize,
    /// Number of angle types.
    pub nangletypes: usize,
    /// Bonds, in data-file order (the order they are evaluated in).
    pub bonds: Vec<Bond>,
    /// Angles, in data-file order.
    pub angles: Vec<Angle>,
    /// `special_bonds`.
    pub special: SpecialBonds,
    /// `bond_style`, once given.
    pub bond_style: Option<BondStyle>,
    /// `angle_style`, once given.
    pub angle_style: Option<AngleStyle>,
}

/// What the pair loop does with a pair of a special class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpecialAction {
    /// An ordinary pair (factor 1).
    #[default]
    Keep,
    /// Left out (factor 0).
    Exclude,
    /// Its coefficients are those of block `offset / (ntypes + 1)²` of the style's table.
    Offset(u32),
}

/// The special-bond rule (`docs/models.md` §4.8), written once for every pair loop (the
/// standalone engine's pair and density passes, the C ABI's walks of LAMMPS's lists): what a
/// pair of bonded neighbours of class 1–3 (1-2, 1-3, 1-4) gets under the `special_bonds lj`
/// factors: factor 1 an ordinary pair, 0 left out, fractional the coefficients of the class's
/// scaled block of the style's table (`PairStyle::scales_special`; a style without scaled
/// blocks refuses fractional factors at set-up, `check_special`). Class 0 (not bonded) is
/// always kept.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpecialRule {
    action: [SpecialAction; 4],
}

impl SpecialRule {
    /// The rule for factors `lj` (entry 0 unused), a style that does (`scales`) or does not
    /// hold scaled blocks, and `ntypes` atom types (a block is (ntypes + 1)² entries).
    pub fn new(lj: [f64; 4], scales: bool, ntypes: usize) -> SpecialRule {
        let block = ((ntypes + 1) * (ntypes + 1)) as u32;
        let mut action = [SpecialAction::Keep; 4];
        for c in 1..4 {
            action[c] = if lj[c] == 0.0 {
                SpecialAction::Exclude
            } else if lj[c] == 1.0 || !scales {
                SpecialAction::Keep
            } else {
                SpecialAction::Offset(c as u32 * block)
            };
        }
        SpecialRule { action }
    }

    /// What a pair of class `class` (0–3) gets.
    #[inline(always)]
    pub fn action(&self, class: usize) -> SpecialAction {
        self.action[class & 3]
    }

    /// Whether a pair of class `class` is left out.
    #[inline(always)]
    pub fn excludes(&self, class: usize) -> bool {
        self.action(class) == SpecialAction::Exclude
    }

    /// The offset of a kept pair's coefficient index (0 unless its class is scaled).
    #[inline(always)]
    pub fn offset(&self, class: usize) -> u32 {
        match self.action(class) {
            SpecialAction::Offset(o) => o,
            _ => 0,
        }
    }
}

/// Each atom's special partners (by index, after the last sort), and what a pair of each class
/// gets: the pair loop's view of [`Topology::special`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpecialPairs {
    /// Row starts by atom index (length n + 1).
    pub start: Vec<u32>,
    /// Partner ids.
    pub tag: Vec<u32>,
    /// Partner classes (1–3).
    pub class: Vec<u8>,
    /// What a pair of each class gets.
    pub rule: SpecialRule,
}

impl SpecialPairs {
    /// The class of the pair (atom index `i`, atom id `tag_j`): 0 when not special.
    #[inline]
    pub fn class_of(&self, i: usize, tag_j: u32) -> usize {
        let (a, b) = (self.start[i] as usize, self.start[i + 1] as usize);
        self.tag[a..b]
            .iter()
            .position(|&t| t == tag_j)
            .map_or(0, |k| self.class[a + k] as usize)
    }
}

/// The topology as atom indices of the current storage order, rebuilt after every sort.
#[derive(Clone, Debug, Default)]
pub struct BondedIndex {
    /// (i, j, type) per bond, in topology order.
    pub bonds: Vec<[u32; 3]>,
    /// (i, j, k, type) per angle, in topology order.
    pub angles: Vec<[u32; 4]>,
    /// The special partners of each atom.
    pub special: SpecialPairs,
    /// The neighbour-list build this index belongs to.
    pub build: u64,
}

/// An atom id → index map over the current order: dense where the ids are, hashed otherwise
/// (as LAMMPS's `atom_modify map array|hash`).
enum TagMap {
    Dense(Vec<u32>),
    Hash(HashMap<u32, u32>),
}

impl TagMap {
    fn new(tags: &[u32]) -> TagMap {
        let max = tags.iter().copied().max().unwrap_or(0) as usize;
        if max <= 4 * tags.len() + 1024 {
            let mut m = vec![u32::MAX; max + 1];
            for (i, &t) in tags.iter().enumerate() {
                m[t as usize] = i as u32;
            }
            TagMap::Dense(m)
        } else {
            TagMap::Hash(
                tags.iter()
                    .enumerate()
                    .map(|(i, &t)| (t, i as u32))
                    .collect(),
            )
        }
    }

    fn get(&self, tag: u32) -> Option<u32> {
        match self {
            TagMap::Dense(m) => m.get(tag as usize).copied().filter(|&i| i != u32::MAX),
            TagMap::Hash(h) => h.get(&tag).copied(),
        }
    }
}

impl Topology {
    /// The special partners of every atom id (LAMMPS's `Special::build`): 1-2 from the bonds,
    /// 1-3 through one more bond, 1-4 through two; a partner keeps its nearest class, never
    /// the atom itself; with `angle yes` a 1-3 pair only when an angle has both as its ends,
    /// with `dihedral yes` no 1-4 pair (there are no dihedrals). Lists sorted by class, then id.
    pub fn special_partners(&self) -> HashMap<u32, Vec<(u32, u8)>> {
        let mut adj: HashMap<u32, Vec<u32>> = HashMap::new();
        for b in &self.bonds {
            let [a, c] = b.atoms;
            adj.entry(a).or_default().push(c);
            adj.entry(c).or_default().push(a);
        }
        for v in adj.values_mut() {
            v.sort_unstable();
            v.dedup();
        }
        let angle_ends: std::collections::HashSet<(u32, u32)> = if self.special.angle {
            self.angles
                .iter()
                .flat_map(|a| [(a.atoms[0], a.atoms[2]), (a.atoms[2], a.atoms[0])])
                .collect()
        } else {
            Default::default()
        };
        let mut out = HashMap::new();
        for (&i, one) in &adj {
            let mut list: Vec<(u32, u8)> = one.iter().map(|&j| (j, 1)).collect();
            let known = |list: &Vec<(u32, u8)>, t: u32| t == i || list.iter().any(|p| p.0 == t);
            let mut two = Vec::new();
            for &j in one {
                for &k in &adj[&j] {
                    two.push(k);
                }
            }
            two.sort_unstable();
            two.dedup();
            let mut three = Vec::new();
            for &k in &two {
                for &l in &adj[&k] {
                    three.push(l);
                }
            }
            three.sort_unstable();
            three.dedup();
            for &k in &two {
                if !known(&list, k) && (!self.special.angle || angle_ends.contains(&(i, k))) {
                    list.push((k, 2));
                }
            }
            if !self.special.dihedral {
                // 1-4: one bond beyond a 1-3 candidate (taken before the angle trim, as
                // LAMMPS does), unless already listed.
                for &l in &three {
                    if !known(&list, l) {
                        list.push((l, 3));
                    }
                }
            }
            out.insert(i, list);
        }
        out
    }

    /// The index form of the topology for atoms with ids `tags` (storage order), with
    /// `partners` from [`Topology::special_partners`] and the special-bond rule `rule`. An id
    /// without an atom is an error naming it (the data file's checks make that impossible for
    /// the atoms they read).
    pub fn index(
        &self,
        tags: &[u32],
        partners: &HashMap<u32, Vec<(u32, u8)>>,
        rule: SpecialRule,
        out: &mut BondedIndex,
    ) -> Result<(), String> {
        let map = TagMap::new(tags);
        let find = |t: u32, what: &str| {
            map.get(t)
                .ok_or_else(|| format!("{what} atom {t} missing (no atom has this id)"))
        };
        out.bonds.clear();
        for b in &self.bonds {
            out.bonds
                .push([find(b.atoms[0], "Bond")?, find(b.atoms[1], "Bond")?, b.typ]);
        }
        out.angles.clear();
        for a in &self.angles {
            out.angles.push([
                find(a.atoms[0], "Angle")?,
                find(a.atoms[1], "Angle")?,
                find(a.atoms[2], "Angle")?,
                a.typ,
            ]);
        }
        let sp = &mut out.special;
        sp.start.clear();
        sp.tag.clear();
        sp.class.clear();
        sp.start.push(0);
        for t in tags {
            if let Some(list) = partners.get(t) {
                for &(p, c) in list {
                    if rule.action(c as usize) != SpecialAction::Keep {
                        sp.tag.push(p);
                        sp.class.push(c);
                    }
                }
            }
            sp.start.push(sp.tag.len() as u32);
        }
        sp.rule = rule;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn special_bonds_reset_unstated_settings() {
        let s = SpecialBonds::parse(&w("lj 0 0.5 1 angle yes")).unwrap();
        assert_eq!(s.lj, [1.0, 0.0, 0.5, 1.0]);
        assert_eq!(s.coul, [1.0, 0.0, 0.0, 0.0]);
        assert!(s.angle);
        let f = SpecialBonds::parse(&w("fene")).unwrap();
        assert_eq!(
            (f.lj, f.coul, f.angle),
            ([1.0, 0.0, 1.0, 1.0], [1.0, 0.0, 1.0, 1.0], false)
        );
        assert!(
            SpecialBonds::parse(&w("harmonic"))
                .unwrap_err()
                .contains("'harmonic'")
        );
        assert!(SpecialBonds::parse(&w("lj 0 1.5 1")).is_err());
        assert_eq!(SpecialBonds::parse(&s.words()).unwrap(), s);
    }

    /// A linear chain 1-2-3-4-5: atom 1 has 2 (1-2), 3 (1-3), 4 (1-4); a ring closes 1-5.
    #[test]
    fn chain_and_ring_classes() {
        let mut t = Topology::default();
        for k in 1..5 {
            t.bonds.push(Bond {
                typ: 1,
                atoms: [k, k + 1],
            });
        }
        let p = t.special_partners();
        assert_eq!(p[&1], vec![(2, 1), (3, 2), (4, 3)]);
        assert_eq!(p[&3], vec![(2, 1), (4, 1), (1, 2), (5, 2)]);
        t.bonds.push(Bond {
            typ: 1,
            atoms: [5, 1],
        });
        let p = t.special_partners();
        // In the 5-ring every other atom is 1-2 or 1-3; nothing is 1-4, nor the atom itself.
        assert_eq!(p[&1], vec![(2, 1), (5, 1), (3, 2), (4, 2)]);
    }

    /// The rule of docs/models.md §4.8: 0 drops, 1 keeps, a fraction takes its class's block
    /// (of (ntypes + 1)² entries) when the style scales, and is kept as is otherwise (such a
    /// style refuses fractional factors at set-up); class 0 is always an ordinary pair.
    #[test]
    fn special_rule_drops_keeps_and_scales() {
        let rule = SpecialRule::new([1.0, 0.0, 0.5, 1.0], true, 2);
        assert_eq!(rule.action(0), SpecialAction::Keep);
        assert!(rule.excludes(1));
        assert_eq!(rule.action(2), SpecialAction::Offset(2 * 9));
        assert_eq!((rule.offset(2), rule.offset(3), rule.offset(0)), (18, 0, 0));
        assert!(!rule.excludes(3) && !rule.excludes(0));
        let plain = SpecialRule::new([1.0, 0.0, 0.5, 1.0], false, 2);
        assert_eq!(plain.action(2), SpecialAction::Keep);
        assert!(plain.excludes(1));
        assert_eq!(SpecialRule::default().action(1), SpecialAction::Keep);
    }
}
