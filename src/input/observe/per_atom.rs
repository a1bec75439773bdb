//! Per-atom values of a [`System`] as the script language sees them: the attributes of
//! [`AtomValue`] (`id mass type x y z vx vy vz fx fy fz`) and atom-style formulas (`variable …
//! atom`) evaluated for every atom.

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
