//! Groups of atoms as LAMMPS keeps them: one bit per group in a per-atom `u32` mask
//! ([`Atoms::mask`]), `all` is bit 0 and always set, at most [`MAX_GROUPS`] groups. The table
//! of names ([`Groups`]) lives in the [`System`]; `group` commands, fixes, `velocity` and dumps
//! read a group through its bit.

use super::{Atoms, System};

/// Most groups a system may have (LAMMPS's `MAX_GROUP`): one bit of a `u32` each.
pub const MAX_GROUPS: usize = 32;

/// The names of the groups by bit (`names[b]` is the group of bit `b`; an empty name is a free
/// slot, left by `group ID delete`). `names[0]` is `all`.
#[derive(Clone, Debug, PartialEq)]
pub struct Groups {
    names: Vec<String>,
}

impl Default for Groups {
    fn default() -> Self {
        Groups {
            names: vec!["all".into()],
        }
    }
}

impl Groups {
    /// The table from names by bit (restart files); bit 0 must be `all`.
    pub fn from_names(names: Vec<String>) -> Result<Groups, String> {
        if names.first().map(String::as_str) != Some("all") || names.len() > MAX_GROUPS {
            return Err(format!(
                "group names {names:?}: the first must be 'all', at most {MAX_GROUPS}"
            ));
        }
        Ok(Groups { names })
    }

    /// The names by bit ("" for a free slot).
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The bit index of group `name`, if it exists.
    pub fn find(&self, name: &str) -> Option<usize> {
        (!name.is_empty())
            .then(|| self.names.iter().position(|n| n == name))
            .flatten()
    }

    /// The mask bit of group `name`, or an error naming it.
    pub fn bit(&self, name: &str) -> Result<u32, String> {
        self.find(name)
            .map(|b| 1u32 << b)
            .ok_or_else(|| format!("no group with ID '{name}' (define it with group)"))
    }

    /// The index of group `name`, created in the first free slot when new (LAMMPS's
    /// `find_or_create`).
    pub fn find_or_create(&mut self, name: &str) -> Result<usize, String> {
        if let Some(b) = self.find(name) {
            return Ok(b);
        }
        if let Some(b) = self.names.iter().position(String::is_empty) {
            self.names[b] = name.to_string();
            return Ok(b);
        }
        if self.names.len() == MAX_GROUPS {
            return Err(format!(
                "too many groups: at most {MAX_GROUPS}, 'all' included"
            ));
        }
        self.names.push(name.to_string());
        Ok(self.names.len() - 1)
    }

    /// Free the slot of group `name` (its atoms must be cleared by the caller).
    fn remove(&mut self, b: usize) {
        if b + 1 == self.names.len() {
            self.names.pop();
            while self.names.last().is_some_and(String::is_empty) {
                self.names.pop();
            }
        } else {
            self.names[b].clear();
        }
    }
}

impl Atoms {
    /// The group mask of atom `i` (1, group `all` only, while no group was ever defined).
    #[inline]
    pub fn mask_of(&self, i: usize) -> u32 {
        self.mask.get(i).copied().unwrap_or(1)
    }

    /// Every atom's mask, materialised (every atom in `all`) before a first group is written.
    pub fn masks_mut(&mut self) -> &mut [u32] {
        if self.mask.len() != self.x.len() {
            self.mask.resize(self.x.len(), 1);
        }
        &mut self.mask
    }
}

/// A comparison of LAMMPS's `group ID type|id|molecule OP V [V2]` form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Condition {
    /// `<`
    Lt(i64),
    /// `<=`
    Le(i64),
    /// `>`
    Gt(i64),
    /// `>=`
    Ge(i64),
    /// `==`
    Eq(i64),
    /// `!=`
    Ne(i64),
    /// `<> A B`: A ≤ v ≤ B.
    Between(i64, i64),
    /// A list item `a`, `a:b` or `a:b:c`: a ≤ v ≤ b and (v − a) divisible by c.
    Range(i64, i64, i64),
}

impl Condition {
    /// True when `v` meets the condition.
    pub fn holds(self, v: i64) -> bool {
        match self {
            Condition::Lt(a) => v < a,
            Condition::Le(a) => v <= a,
            Condition::Gt(a) => v > a,
            Condition::Ge(a) => v >= a,
            Condition::Eq(a) => v == a,
            Condition::Ne(a) => v != a,
            Condition::Between(a, b) => v >= a && v <= b,
            Condition::Range(a, b, c) => v >= a && v <= b && (v - a) % c == 0,
        }
    }
}

/// Which per-atom attribute a `group` selection reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Attribute {
    /// The atom type.
    Type,
    /// The atom id.
    Id,
    /// The molecule id.
    Molecule,
}

/// How a `group` command changes group `name` (LAMMPS's `Group::assign`: every style but
/// `clear` adds atoms to what the group holds).
#[derive(Clone, Debug, PartialEq)]
pub enum GroupOp {
    /// Add the atoms whose attribute meets any of the conditions.
    Select(Attribute, Vec<Condition>),
    /// Add the atoms inside the closed box `[lo, hi]` per axis (a `region block`).
    Block([[f64; 2]; 3]),
    /// Add the atoms of the first group that are in none of the others.
    Subtract(Vec<String>),
    /// Add the atoms of any of these groups.
    Union(Vec<String>),
    /// Add the atoms in all of these groups.
    Intersect(Vec<String>),
    /// Create the group with no atoms (or leave it as it is).
    Empty,
    /// Remove every atom from the group.
    Clear,
    /// Remove the group.
    Delete,
}

impl System {
    /// Apply `op` to group `name` (LAMMPS's `group` command; the checks of what uses a group
    /// are the interpreter's). Returns the number of atoms in the group afterwards (0 after
    /// `delete`).
    pub fn group_apply(&mut self, name: &str, op: &GroupOp) -> Result<usize, String> {
        if matches!(op, GroupOp::Clear | GroupOp::Delete) {
            let b = self
                .groups
                .find(name)
                .ok_or_else(|| format!("no group with ID '{name}'"))?;
            if b == 0 {
                return Err("group all cannot be cleared or deleted".into());
            }
            let keep = !(1u32 << b);
            self.atoms.masks_mut().iter_mut().for_each(|m| *m &= keep);
            if *op == GroupOp::Delete {
                self.groups.remove(b);
                return Ok(0);
            }
            return Ok(0);
        }
        let others = |names: &[String]| -> Result<Vec<u32>, String> {
            names.iter().map(|n| self.groups.bit(n)).collect()
        };
        let bits = match op {
            GroupOp::Subtract(g) | GroupOp::Union(g) | GroupOp::Intersect(g) => others(g)?,
            _ => Vec::new(),
        };
        let bit = 1u32 << self.groups.find_or_create(name)?;
        let a = &mut self.atoms;
        let n = a.len();
        for i in 0..n {
            let m = a.mask_of(i);
            let new = match op {
                GroupOp::Select(attr, conds) => {
                    let v = match attr {
                        Attribute::Type => a.typ[i] as i64,
                        Attribute::Id => a.tag[i] as i64,
                        Attribute::Molecule => a.mol_of(i) as i64,
                    };
                    if conds.iter().any(|c| c.holds(v)) {
                        m | bit
                    } else {
                        m
                    }
                }
                GroupOp::Block(b) => {
                    let inside = (0..3).all(|k| a.x[i][k] >= b[k][0] && a.x[i][k] <= b[k][1]);
                    if inside { m | bit } else { m }
                }
                // LAMMPS adds the first group's atoms, then takes out every atom of any other
                // group in turn (the group itself among them).
                GroupOp::Subtract(_) => {
                    bits[1..]
                        .iter()
                        .fold(if m & bits[0] != 0 { m | bit } else { m }, |m, &o| {
                            if m & o != 0 { m & !bit } else { m }
                        })
                }
                GroupOp::Union(_) if bits.iter().any(|&o| m & o != 0) => m | bit,
                GroupOp::Intersect(_) if bits.iter().all(|&o| m & o != 0) => m | bit,
                _ => m,
            };
            if new != m {
                a.masks_mut()[i] = new;
            }
        }
        Ok(self.group_count(bit))
    }

    /// The number of atoms whose mask has `bit`.
    pub fn group_count(&self, bit: u32) -> usize {
        (0..self.atoms.len())
            .filter(|&i| self.atoms.mask_of(i) & bit != 0)
            .count()
    }

    /// Make group `name` hold exactly the atoms of ids `tags` (created when new): the way a
    /// membership read from elsewhere (LAMMPS's state) is installed. An id that is no atom of
    /// the system is an error naming it; `all` must list every atom.
    pub fn set_group_members(&mut self, name: &str, tags: &[u32]) -> Result<usize, String> {
        let pos: std::collections::HashMap<u32, usize> = self
            .atoms
            .tag
            .iter()
            .enumerate()
            .map(|(i, &t)| (t, i))
            .collect();
        let mut member = vec![false; self.atoms.len()];
        for &t in tags {
            let i = *pos
                .get(&t)
                .ok_or_else(|| format!("group {name}: atom id {t} is not in the system"))?;
            member[i] = true;
        }
        let b = self.groups.find_or_create(name)?;
        if b == 0 {
            return if member.iter().all(|&m| m) {
                Ok(member.len())
            } else {
                Err("group all must hold every atom".into())
            };
        }
        let bit = 1u32 << b;
        for (m, &inside) in self.atoms.masks_mut().iter_mut().zip(&member) {
            if inside {
                *m |= bit;
            } else {
                *m &= !bit;
            }
        }
        Ok(self.group_count(bit))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::SimBox;

    fn sys() -> System {
        let mut s = System::new(SimBox::new(3, [0.0; 3], [10.0; 3]).unwrap(), 3);
        for t in 1..=6u32 {
            let x = [t as f64, 0.0, 0.0];
            s.atoms.push(t, 1 + (t - 1) % 3, x, [0.0; 3], [0; 3]);
        }
        s
    }

    fn members(s: &System, name: &str) -> Vec<u32> {
        let bit = s.groups.bit(name).unwrap();
        (0..s.atoms.len())
            .filter(|&i| s.atoms.mask_of(i) & bit != 0)
            .map(|i| s.atoms.tag[i])
            .collect()
    }

    #[test]
    fn selections_and_set_algebra_follow_lammps() {
        let mut s = sys();
        let sel = |a, c| GroupOp::Select(a, c);
        s.group_apply("t1", &sel(Attribute::Type, vec![Condition::Range(1, 1, 1)]))
            .unwrap();
        assert_eq!(members(&s, "t1"), [1, 4]);
        s.group_apply("odd", &sel(Attribute::Id, vec![Condition::Range(1, 6, 2)]))
            .unwrap();
        assert_eq!(members(&s, "odd"), [1, 3, 5]);
        s.group_apply("mid", &sel(Attribute::Id, vec![Condition::Between(2, 4)]))
            .unwrap();
        s.group_apply("u", &GroupOp::Union(vec!["t1".into(), "mid".into()]))
            .unwrap();
        assert_eq!(members(&s, "u"), [1, 2, 3, 4]);
        s.group_apply("i", &GroupOp::Intersect(vec!["odd".into(), "mid".into()]))
            .unwrap();
        assert_eq!(members(&s, "i"), [3]);
        s.group_apply("d", &GroupOp::Subtract(vec!["all".into(), "odd".into()]))
            .unwrap();
        assert_eq!(members(&s, "d"), [2, 4, 6]);
        let b = [[2.5, 4.0], [-1.0, 1.0], [-1.0, 1.0]];
        s.group_apply("blk", &GroupOp::Block(b)).unwrap();
        assert_eq!(members(&s, "blk"), [3, 4]);
        s.group_apply("blk", &GroupOp::Clear).unwrap();
        assert!(members(&s, "blk").is_empty());
        s.group_apply("mid", &GroupOp::Delete).unwrap();
        assert!(s.groups.find("mid").is_none());
        // The freed bit is the next new group's.
        let b_mid = 3;
        assert_eq!(s.groups.find_or_create("new").unwrap(), b_mid);
        assert!(s.group_apply("all", &GroupOp::Delete).is_err());
        assert_eq!(s.set_group_members("odd", &[2, 6]).unwrap(), 2);
        assert_eq!(members(&s, "odd"), [2, 6]);
        assert!(s.set_group_members("odd", &[99]).is_err());
    }

    #[test]
    fn at_most_32_groups() {
        let mut s = sys();
        for k in 1..MAX_GROUPS {
            s.group_apply(&format!("g{k}"), &GroupOp::Empty).unwrap();
        }
        assert!(s.group_apply("one_more", &GroupOp::Empty).is_err());
    }
}
