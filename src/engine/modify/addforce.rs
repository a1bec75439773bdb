//! `fix ID GROUP addforce FX FY FZ [every N] [region R]`: a force added to each of the group's
//! atoms after the forces, on the steps that are multiples of N (a number or an equal- or
//! atom-style variable per component), at the set-up's forces too (LAMMPS's `FixAddForce`).

use super::{Component, Fix, Input, InputValue, Selection, System};

/// `fix addforce`.
#[derive(Clone, Debug)]
pub struct AddForce {
    id: String,
    sel: Selection,
    value: [Component; 3],
    every: u64,
}

impl AddForce {
    /// Fix `id` adding `value` to the atoms of `sel` every `every` steps.
    pub fn new(id: &str, sel: Selection, value: [Component; 3], every: u64) -> AddForce {
        AddForce {
            id: id.to_string(),
            sel,
            value,
            every: every.max(1),
        }
    }
}

impl Fix for AddForce {
    fn id(&self) -> &str {
        &self.id
    }
    fn setup(&mut self, sys: &mut System) {
        self.post_force(sys);
    }
    fn post_force(&mut self, sys: &mut System) {
        if !sys.step.is_multiple_of(self.every) {
            return;
        }
        let a = &mut sys.atoms;
        for i in 0..a.len() {
            if self.sel.has(a, i) {
                for k in 0..3 {
                    if let Some(v) = self.value[k].at(i) {
                        a.f[i][k] += v;
                    }
                }
            }
        }
    }
    fn inputs(&self) -> Vec<Input> {
        Component::inputs(&self.value)
    }
    fn set_input(&mut self, k: usize, value: InputValue) {
        Component::set(&mut self.value, k, value);
    }
}
