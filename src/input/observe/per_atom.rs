//! Per-atom values of a [`System`] as the script language sees them: the attributes of
//! [`AtomValue`] (`id mass type x y z vx vy vz fx fy fz`) and atom-style formulas (`variable …
//! atom`) evaluated for every atom.

use super::Observe;
use crate::engine::System;
use crate::engine::measure::mass_of;
use crate::input::expr::{AtomValue, Formula};
use rayon::prelude::*;

/// One per-atom value of atom `i`.
pub(crate) fn atom_value(sys: &System, i: usize, v: AtomValue) -> f64 {
    let a = &sys.atoms;
    match v {
        AtomValue::Id => f64::from(a.tag[i]),
        AtomValue::Mass => mass_of(sys, i),
        AtomValue::Type => f64::from(a.typ[i]),
        AtomValue::X => a.x[i][0],
        AtomValue::Y => a.x[i][1],
        AtomValue::Z => a.x[i][2],
        AtomValue::Vx => a.v[i][0],
        AtomValue::Vy => a.v[i][1],
        AtomValue::Vz => a.v[i][2],
        AtomValue::Fx => a.f[i][0],
        AtomValue::Fy => a.f[i][1],
        AtomValue::Fz => a.f[i][2],
    }
}

/// Evaluates a bound atom-style formula ([`Formula::bind_atoms`]) for every atom, in the atoms'
/// internal order.
pub(crate) fn eval_atoms(f: &Formula, sys: &System) -> Result<Vec<f64>, String> {
    if let Some(c) = f.constant() {
        return Ok(vec![c; sys.atoms.len()]);
    }
    (0..sys.atoms.len())
        .into_par_iter()
        .map(|i| f.eval_atom(&|v| atom_value(sys, i, v)))
        .collect()
}

impl Observe {
    /// `ID` or `ID[k]` (a per-atom reference after its `c_`): the compute's ID and column,
    /// checked against its per-atom values; `what` names the user in errors.
    pub fn per_atom_ref(&self, body: &str, what: &str) -> Result<(String, Option<usize>), String> {
        let (id, col) = match body.split_once('[') {
            Some((id, k)) => {
                let k = k
                    .strip_suffix(']')
                    .and_then(|k| k.parse::<usize>().ok())
                    .filter(|&k| k >= 1)
                    .ok_or_else(|| format!("{what} 'c_{body}': expected c_ID[k] with k >= 1"))?;
                (id, Some(k))
            }
            None => (body, None),
        };
        let width = self.per_atom_width(id).ok_or_else(|| {
            if self.compute(id).is_some() {
                format!("{what}: compute '{id}' does not calculate per-atom values")
            } else {
                format!("{what}: compute '{id}' does not exist")
            }
        })?;
        match (col, width) {
            (None, 0) => {}
            (Some(k), n) if n > 0 && k <= n => {}
            (None, n) => {
                return Err(format!(
                    "{what}: compute '{id}' has {n} per-atom columns: give one, c_{id}[k]"
                ));
            }
            (Some(k), 0) => {
                return Err(format!(
                    "{what}: compute '{id}' has one per-atom value, not [{k}]"
                ));
            }
            (Some(k), n) => {
                return Err(format!(
                    "{what}: compute '{id}' has {n} per-atom columns, [{k}] is out of range"
                ));
            }
        }
        Ok((id.to_string(), col))
    }
}
