//! `group ID STYLE ARGS` (LAMMPS's semantics: every style but `clear` and `delete` adds atoms
//! to the group; the masks and the set algebra are [`crate::engine::groups`]).

use super::{CmdResult, Interpreter};
use crate::engine::groups::{Attribute, Condition, GroupOp};
use crate::grammar::{need, shown};

const USAGE: &str = "group ID type|id|molecule VALUES… | group ID type|id|molecule <|<=|>|>=|==|!=|<> V [V2] | group ID region REGION | group ID subtract|union|intersect G1 G2 … | group ID delete|clear|empty";

/// One integer of a `group` selection.
fn int(tok: &str) -> Result<i64, String> {
    tok.parse::<i64>()
        .map_err(|_| format!("group: '{}' is not an integer", shown(tok)))
}

/// A list item `a`, `a:b` or `a:b:c` (LAMMPS: c ≥ 1).
fn range(tok: &str) -> Result<Condition, String> {
    let parts: Vec<&str> = tok.split(':').collect();
    let bad = || {
        format!(
            "group: incorrect range string '{}' (a, a:b or a:b:c)",
            shown(tok)
        )
    };
    let (a, b, c) = match parts.as_slice() {
        [a] => (int(a)?, int(a)?, 1),
        [a, b] => (int(a)?, int(b)?, 1),
        [a, b, c] => (int(a)?, int(b)?, c.parse::<i64>().map_err(|_| bad())?),
        _ => return Err(bad()),
    };
    if c < 1 {
        return Err(format!(
            "group: range increment in '{}' must be >= 1",
            shown(tok)
        ));
    }
    Ok(Condition::Range(a, b, c))
}

/// The conditions of `group ID type|id|molecule ARGS` (`args` from the first value).
fn conditions(args: &[String]) -> Result<Vec<Condition>, String> {
    let op = args[0].as_str();
    if args.len() > 1 && matches!(op, "<" | "<=" | ">" | ">=" | "==" | "!=" | "<>") {
        let n = if op == "<>" { 3 } else { 2 };
        if args.len() != n {
            return Err(format!(
                "group: '{op}' takes {} value(s); usage: {USAGE}",
                n - 1
            ));
        }
        let a = int(&args[1])?;
        return Ok(vec![match op {
            "<" => Condition::Lt(a),
            "<=" => Condition::Le(a),
            ">" => Condition::Gt(a),
            ">=" => Condition::Ge(a),
            "==" => Condition::Eq(a),
            "!=" => Condition::Ne(a),
            _ => Condition::Between(a, int(&args[2])?),
        }]);
    }
    args.iter().map(|a| range(a)).collect()
}

impl Interpreter<'_> {
    /// `group ID STYLE ARGS`: prints LAMMPS's "N atoms in group ID".
    pub(super) fn cmd_group(&mut self, args: &[String]) -> CmdResult {
        need(args, 2, USAGE)?;
        let name = args[0].as_str();
        let n_min = |n: usize| need(args, n, USAGE);
        let op = match args[1].as_str() {
            s @ ("type" | "id" | "molecule") => {
                n_min(3)?;
                let attr = match s {
                    "type" => Attribute::Type,
                    "id" => Attribute::Id,
                    _ => Attribute::Molecule,
                };
                if attr == Attribute::Molecule && self.sys_mut()?.topo.is_none() {
                    return Err(
                        "group molecule: the atom style has no molecule ids (atom_style bond, \
                         angle, molecular or full)"
                            .into(),
                    );
                }
                GroupOp::Select(attr, conditions(&args[2..])?)
            }
            "region" => {
                n_min(3)?;
                if args.len() > 3 {
                    return Err(format!("group region takes one region ID; usage: {USAGE}"));
                }
                if self.prisms.contains_key(&args[2]) {
                    return Err(format!(
                        "group region: region '{}' is a prism; only block regions select \
                         atoms here",
                        args[2]
                    ));
                }
                GroupOp::Block(self.region_for_atoms(&args[2])?)
            }
            s @ ("subtract" | "union" | "intersect") => {
                n_min(if s == "union" { 3 } else { 4 })?;
                let g = args[2..].to_vec();
                match s {
                    "subtract" => GroupOp::Subtract(g),
                    "union" => GroupOp::Union(g),
                    _ => GroupOp::Intersect(g),
                }
            }
            s @ ("delete" | "clear" | "empty") => {
                if args.len() > 2 {
                    return Err(format!("group {s} takes no arguments; usage: {USAGE}"));
                }
                match s {
                    "delete" => {
                        self.group_in_use(name)?;
                        GroupOp::Delete
                    }
                    "clear" => GroupOp::Clear,
                    _ => GroupOp::Empty,
                }
            }
            s @ ("variable" | "include" | "dynamic" | "static") => {
                return Err(format!(
                    "group style '{s}' not supported in the standalone engine (type, id, \
                     molecule, region, subtract, union, intersect, delete, clear, empty); run \
                     the script in LAMMPS, or select the atoms by type, id or region"
                ));
            }
            o => {
                return Err(format!(
                    "group style '{}' unknown; usage: {USAGE}",
                    shown(o)
                ));
            }
        };
        let sys = self.sys_mut()?;
        let n = sys.group_apply(name, &op)?;
        if op != GroupOp::Delete {
            self.out(&format!("{n} atoms in group {name}"));
        }
        Ok(())
    }

    /// Refuse to delete a group a fix or a dump uses (as LAMMPS).
    fn group_in_use(&self, name: &str) -> CmdResult {
        if let Some((id, _)) = self
            .fix_lines
            .iter()
            .find(|(_, w)| w.get(1).map(String::as_str) == Some(name))
        {
            return Err(format!("group {name} cannot be deleted: fix {id} uses it"));
        }
        if let Some(d) = self.dumps.iter().find(|d| d.group == name) {
            return Err(format!(
                "group {name} cannot be deleted: dump {} uses it",
                d.id
            ));
        }
        Ok(())
    }

    /// The mask bit of group `name` of an existing system, for a command that takes a group.
    pub(super) fn group_bit(&mut self, name: &str) -> Result<u32, String> {
        self.sys_mut()?.groups.bit(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_conditions() {
        let w = |s: &str| s.split(' ').map(String::from).collect::<Vec<_>>();
        assert_eq!(range("3"), Ok(Condition::Range(3, 3, 1)));
        assert_eq!(range("2:9:3"), Ok(Condition::Range(2, 9, 3)));
        assert!(range("2:9:0").is_err());
        assert!(range("a:b").is_err());
        assert_eq!(conditions(&w("<> 2 5")), Ok(vec![Condition::Between(2, 5)]));
        assert_eq!(conditions(&w("<= 4")), Ok(vec![Condition::Le(4)]));
        assert!(conditions(&w("<> 2")).is_err());
        assert_eq!(conditions(&w("1 4:5")).map(|c| c.len()), Ok(2));
    }
}
