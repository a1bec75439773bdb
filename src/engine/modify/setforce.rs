//! `fix ID GROUP setforce FX FY FZ [region R]`: the force components of the group's atoms set
//! after the forces (`NULL` leaves one; a number or an equal- or atom-style variable), at the
//! set-up's forces too (LAMMPS's `FixSetForce`).

use super::{Component, Fix, Input, InputValue, Selection, System};

/// `fix setforce`.
#[derive(Clone, Debug)]
pub struct SetForce {
    id: String,
    sel: Selection,
    value: [Component; 3],
}

impl SetForce {
    /// Fix `id` setting `value` on the atoms of `sel`.
    pub fn new(id: &str, sel: Selection, value: [Component; 3]) -> SetForce {
        SetForce {
            id: id.to_string(),
            sel,
            value,
        }
    }
}

impl Fix for SetForce {
    fn id(&self) -> &str {
        &self.id
    }
    fn setup(&mut self, sys: &mut System) {
        self.post_force(sys);
    }
    fn post_force(&mut self, sys: &mut System) {
        let a = &mut sys.atoms;
        for i in 0..a.len() {
            if self.sel.has(a, i) {
                for k in 0..3 {
                    if let Some(v) = self.value[k].at(i) {
                        a.f[i][k] = v;
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
