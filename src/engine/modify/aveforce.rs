//! `fix ID GROUP aveforce FX FY FZ [region R]`: each selected atom's force component replaced
//! by the selection's average plus FX (`NULL` leaves it; a number or an equal-style variable),
//! after the forces and at the set-up's forces (LAMMPS's `FixAveForce`).

use super::{Component, Fix, Input, InputValue, Selection, System};

/// `fix aveforce`.
#[derive(Clone, Debug)]
pub struct AveForce {
    id: String,
    sel: Selection,
    value: [Component; 3],
}

impl AveForce {
    /// Fix `id` on the atoms of `sel` (no atom-style component: the caller refuses one).
    pub fn new(id: &str, sel: Selection, value: [Component; 3]) -> AveForce {
        AveForce {
            id: id.to_string(),
            sel,
            value,
        }
    }
}

impl Fix for AveForce {
    fn id(&self) -> &str {
        &self.id
    }
    fn setup(&mut self, sys: &mut System) {
        self.post_force(sys);
    }
    fn post_force(&mut self, sys: &mut System) {
        let a = &mut sys.atoms;
        let (mut sum, mut n) = ([0.0; 3], 0.0);
        for i in 0..a.len() {
            if self.sel.has(a, i) {
                for k in 0..3 {
                    sum[k] += a.f[i][k];
                }
                n += 1.0;
            }
        }
        if n == 0.0 {
            return;
        }
        let ave: [Option<f64>; 3] =
            std::array::from_fn(|k| self.value[k].at(0).map(|v| sum[k] / n + v));
        for i in 0..a.len() {
            if self.sel.has(a, i) {
                for k in 0..3 {
                    if let Some(v) = ave[k] {
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
