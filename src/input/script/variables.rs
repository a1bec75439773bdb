//! `variable` and the formula context of the interpreter: variables, thermo keywords, computes,
//! fixes and atom references as a formula sees them.

use super::{CmdResult, Interpreter, Var, control};
use crate::grammar::need;
use crate::input::expr::eval_equal;
use crate::input::expr::{AtomBinder, AtomValue, ExprContext, Formula, RefKind};
use crate::input::observe;

impl Interpreter<'_> {
    pub(super) fn cmd_variable(&mut self, args: &[String]) -> CmdResult {
        need(args, 2, "variable NAME STYLE ARGS…")?;
        let name = args[0].clone();
        if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("variable name '{name}' must be alphanumeric or _"));
        }
        match args[1].as_str() {
            "delete" => {
                self.vars.remove(&name);
            }
            "index" => {
                need(args, 3, "variable NAME index VALUE…")?;
                // As LAMMPS: an index variable already defined (e.g. by -var) is kept.
                self.vars
                    .entry(name)
                    .or_insert(Var::Index(args[2..].to_vec(), 0));
            }
            "loop" => {
                let values = control::loop_values(&args[2..])?;
                self.vars.entry(name).or_insert(Var::Index(values, 0));
            }
            "string" => {
                need(args, 3, "variable NAME string VALUE")?;
                self.vars.insert(name, Var::Str(args[2].clone()));
            }
            "equal" => {
                need(args, 3, "variable NAME equal FORMULA")?;
                self.vars.insert(name, Var::Equal(args[2..].join(" ")));
            }
            "atom" => {
                need(args, 3, "variable NAME atom FORMULA")?;
                let f = args[2..].join(" ");
                Formula::parse(&f)?;
                self.vars.insert(name, Var::Atom(f));
            }
            o => {
                return Err(format!(
                    "variable style '{o}' not supported (index, loop, string, equal, atom, delete)"
                ));
            }
        }
        Ok(())
    }
}

/// The number a string-valued variable holds.
pub(super) fn number_of(name: &str, s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| format!("variable '{name}' = '{s}' is not a number"))
}

/// The formula context of an interpreter: variables, thermo keywords, computes and fixes;
/// the depth guards against variables that refer to themselves.
pub(super) struct Ctx<'a, 'b>(pub(super) &'a Interpreter<'b>, pub(super) usize);

impl ExprContext for Ctx<'_, '_> {
    fn variable(&self, name: &str) -> Result<f64, String> {
        if self.1 > 64 {
            return Err(format!("variable '{name}' refers to itself"));
        }
        match self.0.vars.get(name) {
            None => Err(format!("variable '{name}' is not defined")),
            Some(Var::Index(v, at)) => number_of(name, &v[*at]),
            Some(Var::Str(s)) => number_of(name, s),
            Some(Var::Equal(e)) => eval_equal(e, &Ctx(self.0, self.1 + 1)),
            Some(Var::Atom(_)) => Err(format!(
                "variable '{name}' is atom-style: not usable in an equal-style formula"
            )),
        }
    }
    fn thermo(&self, keyword: &str) -> Option<Result<f64, String>> {
        self.0.thermo_value(keyword)
    }
    fn atom(&self, value: AtomValue, id: u64) -> Option<Result<f64, String>> {
        let Some(sys) = self.0.sys.as_ref() else {
            return Some(Err("needs a simulation box".into()));
        };
        let tags = &sys.atoms.tag;
        // As LAMMPS: an ID past the largest is an error, one no atom has (a gap) gives 0.
        let largest = tags.iter().copied().max().map_or(0, u64::from);
        if id > largest {
            return Some(Err(format!(
                "atom ID {id} is larger than the largest atom ID, {largest}"
            )));
        }
        Some(Ok(tags
            .iter()
            .position(|&t| u64::from(t) == id)
            .map_or(0.0, |i| observe::atom_value(sys, i, value))))
    }
    fn reference(
        &self,
        kind: RefKind,
        id: &str,
        index: Option<usize>,
    ) -> Option<Result<f64, String>> {
        Some(self.0.obs.reference(kind, id, index, self.0))
    }
}

impl AtomBinder for Ctx<'_, '_> {
    fn atom_variable(&self, name: &str) -> Option<Result<Formula, String>> {
        let Some(Var::Atom(src)) = self.0.vars.get(name) else {
            return None;
        };
        if self.1 > 64 {
            return Some(Err(format!("variable '{name}' refers to itself")));
        }
        let inner = Ctx(self.0, self.1 + 1);
        Some(Formula::parse(src).and_then(|f| f.bind_atoms(&inner, &inner)))
    }
}
