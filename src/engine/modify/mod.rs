//! The fixes of a run and the order of their hooks (LAMMPS's `Modify`): one list, called at
//! each point of a velocity-Verlet step in the order the fixes were defined —
//! `initial_integrate`, `post_integrate`, the forces, `post_force`, `final_integrate`,
//! `end_of_step` — and, after the set-up's forces, each fix's `setup` (LAMMPS's
//! `Verlet::setup`: the force fixes apply at step 0's forces too).
//!
//! A fix is one small type implementing [`Fix`] in its own file here; a new fix is one file and
//! one line of the interpreter that parses its words. The hot loops (pair forces, neighbour
//! lists) are untouched: a fix's per-atom work is a plain loop over its group's atoms.
//!
//! Values that come from the interpreter (equal- and atom-style variables) are [`Input`]s: the
//! engine names them ([`System::fix_inputs`]), the interpreter evaluates them after the forces
//! of the step and hands them back ([`System::set_fix_input`]) before `post_force` runs.

mod addforce;
mod aveforce;
mod integrate;
mod momentum;
mod setforce;

pub use addforce::AddForce;
pub use aveforce::AveForce;
pub use integrate::{Integrate, Scheme};
pub(crate) use integrate::{euler, nve_final, nve_initial};
pub use momentum::Momentum;
pub use setforce::SetForce;

use super::System;

/// One fix of the list. Every hook does nothing by default.
pub trait Fix: std::fmt::Debug + Send + Sync {
    /// The fix ID.
    fn id(&self) -> &str;
    /// True for a fix that moves atoms (LAMMPS's `time_integrate`).
    fn integrates(&self) -> bool {
        false
    }
    /// The integrator a pair style's set-up should assume, for a time-integration fix.
    fn scheme(&self) -> Option<super::Integrator> {
        None
    }
    /// At the set-up, after the first forces (LAMMPS's `Fix::setup`).
    fn setup(&mut self, _sys: &mut System) {}
    /// Before the forces: the first half of an integrator.
    fn initial_integrate(&mut self, _sys: &mut System) {}
    /// After the integrators' first half, before the forces.
    fn post_integrate(&mut self, _sys: &mut System) {}
    /// After the forces.
    fn post_force(&mut self, _sys: &mut System) {}
    /// After `post_force`: the second half of an integrator.
    fn final_integrate(&mut self, _sys: &mut System) {}
    /// At the end of the step.
    fn end_of_step(&mut self, _sys: &mut System) {}
    /// The variables this fix reads at the coming `post_force` (or set-up).
    fn inputs(&self) -> Vec<Input> {
        Vec::new()
    }
    /// The value of its input `k` (an index into [`Fix::inputs`]).
    fn set_input(&mut self, _k: usize, _value: InputValue) {}
}

/// A variable a fix reads: its name and whether it is atom-style (one value per atom).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The variable name (without `v_`).
    pub name: String,
    /// Atom-style (else equal-style).
    pub atom: bool,
}

/// The value of an [`Input`].
#[derive(Clone, Debug, PartialEq)]
pub enum InputValue {
    /// An equal-style value.
    Equal(f64),
    /// An atom-style value per atom, in the atoms' current order.
    Atom(Vec<f64>),
}

/// One component of a force fix: unchanged (`NULL`), a constant, or a variable's value (the
/// last one handed in).
#[derive(Clone, Debug, PartialEq)]
pub enum Component {
    /// `NULL`: the component is left alone.
    Null,
    /// A number.
    Const(f64),
    /// `v_name` of an equal-style variable.
    Equal(String, f64),
    /// `v_name` of an atom-style variable.
    Atom(String, Vec<f64>),
}

impl Component {
    /// The value for atom `i` (`None` for `NULL`).
    #[inline]
    pub fn at(&self, i: usize) -> Option<f64> {
        match self {
            Component::Null => None,
            Component::Const(v) | Component::Equal(_, v) => Some(*v),
            Component::Atom(_, v) => Some(v.get(i).copied().unwrap_or(0.0)),
        }
    }

    /// The inputs of three components.
    pub(crate) fn inputs(c: &[Component; 3]) -> Vec<Input> {
        c.iter()
            .filter_map(|c| match c {
                Component::Equal(n, _) => Some(Input {
                    name: n.clone(),
                    atom: false,
                }),
                Component::Atom(n, _) => Some(Input {
                    name: n.clone(),
                    atom: true,
                }),
                _ => None,
            })
            .collect()
    }

    /// Hand input `k` (counted over the variable components of `c`) its value.
    pub(crate) fn set(c: &mut [Component; 3], k: usize, value: InputValue) {
        let Some(slot) = c
            .iter_mut()
            .filter(|c| matches!(c, Component::Equal(..) | Component::Atom(..)))
            .nth(k)
        else {
            return;
        };
        match (slot, value) {
            (Component::Equal(_, v), InputValue::Equal(x)) => *v = x,
            (Component::Atom(_, v), InputValue::Atom(x)) => *v = x,
            _ => {}
        }
    }
}

/// Which atoms a fix acts on: its group's mask bit and, optionally, a block region (closed
/// bounds per axis, as LAMMPS's `region block` matches).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Selection {
    /// The group's mask bit.
    pub bit: u32,
    /// A block region the atom must be in at the time of the hook.
    pub region: Option<[[f64; 2]; 3]>,
}

impl Selection {
    /// The atoms of group bit `bit`, anywhere.
    pub fn group(bit: u32) -> Selection {
        Selection { bit, region: None }
    }

    /// True when atom `i` of `a` is selected.
    #[inline]
    pub fn has(&self, a: &super::Atoms, i: usize) -> bool {
        a.mask_of(i) & self.bit != 0
            && self
                .region
                .is_none_or(|b| (0..3).all(|k| a.x[i][k] >= b[k][0] && a.x[i][k] <= b[k][1]))
    }
}

/// The fix list, in definition order.
#[derive(Debug, Default)]
pub struct Modify {
    fixes: Vec<Box<dyn Fix>>,
}

impl Modify {
    /// Append a fix (its ID must be new: the interpreter checks).
    pub fn add(&mut self, fix: Box<dyn Fix>) {
        self.fixes.push(fix);
    }

    /// Remove the fix `id`; true when there was one.
    pub fn remove(&mut self, id: &str) -> bool {
        let n = self.fixes.len();
        self.fixes.retain(|f| f.id() != id);
        self.fixes.len() != n
    }

    /// True when there are no fixes.
    pub fn is_empty(&self) -> bool {
        self.fixes.is_empty()
    }

    /// True when some fix moves atoms.
    pub fn integrates(&self) -> bool {
        self.fixes.iter().any(|f| f.integrates())
    }

    /// The scheme of the first time-integration fix.
    pub fn scheme(&self) -> Option<super::Integrator> {
        self.fixes.iter().find_map(|f| f.scheme())
    }
}

/// The points of a step where the list is called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Hook {
    Setup,
    InitialIntegrate,
    PostIntegrate,
    PostForce,
    FinalIntegrate,
}

impl System {
    /// Call `hook` of every fix, in definition order.
    pub(crate) fn run_hook(&mut self, hook: Hook) {
        if self.modify.is_empty() {
            return;
        }
        let mut m = std::mem::take(&mut self.modify);
        for f in m.fixes.iter_mut() {
            match hook {
                Hook::Setup => f.setup(self),
                Hook::InitialIntegrate => f.initial_integrate(self),
                Hook::PostIntegrate => f.post_integrate(self),
                Hook::PostForce => f.post_force(self),
                Hook::FinalIntegrate => f.final_integrate(self),
            }
        }
        self.modify = m;
    }

    /// The `end_of_step` of fix `id` (the interpreter calls it in the order of every fix,
    /// its own measurements among them). False when there is no such fix.
    pub fn fix_end_of_step(&mut self, id: &str) -> bool {
        let mut m = std::mem::take(&mut self.modify);
        let found = match m.fixes.iter_mut().find(|f| f.id() == id) {
            Some(f) => {
                f.end_of_step(self);
                true
            }
            None => false,
        };
        self.modify = m;
        found
    }

    /// The variables each fix reads next: (fix index, its inputs).
    pub fn fix_inputs(&self) -> Vec<(usize, Vec<Input>)> {
        self.modify
            .fixes
            .iter()
            .enumerate()
            .map(|(k, f)| (k, f.inputs()))
            .filter(|(_, i)| !i.is_empty())
            .collect()
    }

    /// Hand input `k` of fix number `fix` (as [`System::fix_inputs`] lists them) its value.
    pub fn set_fix_input(&mut self, fix: usize, k: usize, value: InputValue) {
        if let Some(f) = self.modify.fixes.get_mut(fix) {
            f.set_input(k, value);
        }
    }
}
