//! `compute ID GROUP reduce MODE INPUT…` (LAMMPS's `ComputeReduce`): each input, a per-atom
//! value (`x y z vx vy vz fx fy fz`, `c_ID`, `c_ID[k]`, `v_name` of an atom-style variable),
//! reduced over the group's atoms to one number by MODE (`sum`, `sumsq`, `ave`, `avesq`, `min`,
//! `max`). One input gives a global scalar, several a global vector (one element per input).
//! `sum` and `sumsq` are extensive (thermo output with `thermo_modify norm yes` divides them by
//! the atom count), the others intensive.
//!
//! Group: the atoms reduced over are those for which [`Reduce::members`] is true; with only
//! group `all` that is every atom (`fixes`' group masks plug in there).

use super::{Env, arg};
use crate::engine::System;
use crate::input::expr::AtomValue;

/// How the values of the atoms become one number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mode {
    Sum,
    SumSq,
    Ave,
    AveSq,
    Min,
    Max,
}

/// One input of `compute reduce`.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Input {
    /// `x`, `vx`, `fx`, …: an attribute of the atoms.
    Atom(AtomValue),
    /// `c_ID` (None) or `c_ID[k]` (1-based column): a compute's per-atom values.
    Compute(String, Option<usize>),
    /// `v_name`: an atom-style variable.
    Var(String),
}

/// A `compute reduce`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Reduce {
    pub(super) mode: Mode,
    pub(super) inputs: Vec<Input>,
}

const USAGE: &str = "compute ID all reduce sum|sumsq|ave|avesq|min|max INPUT… (INPUT: x y z vx vy \
                     vz fx fy fz, c_ID, c_ID[k] of a per-atom compute, v_name of an atom-style \
                     variable)";

impl Reduce {
    /// Parse `compute ID all reduce MODE INPUT…` (`args`: the whole command).
    pub(super) fn parse(args: &[String], env: &dyn Env) -> Result<Reduce, String> {
        let mode = match arg(args, 3, USAGE)? {
            "sum" => Mode::Sum,
            "sumsq" => Mode::SumSq,
            "ave" => Mode::Ave,
            "avesq" => Mode::AveSq,
            "min" => Mode::Min,
            "max" => Mode::Max,
            o => return Err(format!("compute reduce mode '{o}' unknown; usage: {USAGE}")),
        };
        arg(args, 4, USAGE)?;
        let mut inputs = Vec::new();
        for w in &args[4..] {
            inputs.push(Self::input(w, env)?);
        }
        Ok(Reduce { mode, inputs })
    }

    fn input(w: &str, env: &dyn Env) -> Result<Input, String> {
        if matches!(w, "replace" | "inputs") {
            return Err(format!(
                "compute reduce keyword '{w}' is not supported (the inputs are per-atom \
                 values; no replace)"
            ));
        }
        if let Some(a) = AtomValue::from_word(w)
            .filter(|a| !matches!(a, AtomValue::Id | AtomValue::Type | AtomValue::Mass))
        {
            return Ok(Input::Atom(a));
        }
        if let Some(name) = w.strip_prefix("v_") {
            return match env.var_style(name) {
                super::VarStyle::Atom => Ok(Input::Var(name.to_string())),
                super::VarStyle::Undefined => {
                    Err(format!("compute reduce: variable '{name}' is not defined"))
                }
                _ => Err(format!(
                    "compute reduce: variable '{name}' is not atom-style (reduce takes \
                     per-atom values)"
                )),
            };
        }
        if let Some(body) = w.strip_prefix("c_") {
            let (id, col) = env.observe().per_atom_ref(body, "compute reduce")?;
            return Ok(Input::Compute(id, col));
        }
        Err(format!(
            "compute reduce input '{w}' not supported; usage: {USAGE}"
        ))
    }

    /// Whether an input is compute `id`'s.
    pub(super) fn uses_compute(&self, id: &str) -> bool {
        self.inputs
            .iter()
            .any(|i| matches!(i, Input::Compute(c, _) if c == id))
    }

    /// Whether the values are extensive (`sum`, `sumsq`).
    pub(super) fn extensive(&self) -> bool {
        matches!(self.mode, Mode::Sum | Mode::SumSq)
    }

    /// Whether atom `i` is reduced over: group `all`, every atom (a group mask plugs in here).
    fn members(_sys: &System, _i: usize) -> bool {
        true
    }

    /// The reduced value of every input, in input order.
    pub(super) fn values(&self, env: &dyn Env, sys: &System) -> Result<Vec<f64>, String> {
        self.inputs
            .iter()
            .map(|input| {
                let per_atom = match input {
                    Input::Atom(a) => (0..sys.atoms.len())
                        .map(|i| super::atom_value(sys, i, *a))
                        .collect(),
                    Input::Var(name) => env.atom_variable(name)?,
                    Input::Compute(id, col) => env.observe().per_atom_column(id, *col, sys)?,
                };
                Ok(self.reduce(&per_atom, sys))
            })
            .collect()
    }

    /// One input's per-atom values (internal order) reduced over the group.
    fn reduce(&self, values: &[f64], sys: &System) -> f64 {
        let members = values
            .iter()
            .enumerate()
            .filter(|(i, _)| Self::members(sys, *i))
            .map(|(_, v)| *v);
        let count = (0..values.len()).filter(|&i| Self::members(sys, i)).count() as f64;
        match self.mode {
            Mode::Sum => members.sum(),
            Mode::SumSq => members.map(|v| v * v).sum(),
            // LAMMPS: a group with no atoms averages to 0.
            Mode::Ave if count > 0.0 => members.sum::<f64>() / count,
            Mode::AveSq if count > 0.0 => members.map(|v| v * v).sum::<f64>() / count,
            Mode::Ave | Mode::AveSq => 0.0,
            // LAMMPS's BIG (1e20) for an empty group.
            Mode::Min => members.fold(1e20, f64::min),
            Mode::Max => members.fold(-1e20, f64::max),
        }
    }
}
