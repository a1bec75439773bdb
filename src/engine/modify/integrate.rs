//! The time-integration fixes on a group: `nve` (velocity Verlet), `nve/euler` (Euler,
//! docs/models.md P-2) and `mvv/dpd [λ]` (the modified velocity Verlet of LAMMPS's DPD-MESO
//! package: x moves with v + δt/2 F/m, v is predicted with λ δt F/m for the forces, and then
//! corrected to v + δt/2 (F + F')/m).
//!
//! On group `all` the velocity-Verlet and Euler updates are the engine's parallel loops (the same
//! bits as before groups); on another group a plain loop over its atoms with the same
//! arithmetic per atom, as LAMMPS's `fix nve` does.

use super::{Fix, System};
use crate::engine::{Integrator, fixes};
use rayon::prelude::*;

/// Which integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// `fix nve`.
    Nve,
    /// `fix nve/euler`.
    Euler,
    /// `fix mvv/dpd [λ]` (λ = 0.5: velocity Verlet's positions and velocities).
    Mvv(f64),
}

/// A time-integration fix on a group.
#[derive(Clone, Debug)]
pub struct Integrate {
    id: String,
    bit: u32,
    scheme: Scheme,
}

impl Integrate {
    /// Fix `id` integrating the atoms of group bit `bit` with `scheme`.
    pub fn new(id: &str, bit: u32, scheme: Scheme) -> Integrate {
        Integrate {
            id: id.to_string(),
            bit,
            scheme,
        }
    }
}

/// dtf / m per type (`dtf` = the factor LAMMPS forms: δt/2 · ftm2v or δt · ftm2v).
fn per_type(sys: &System, dtf: f64) -> Vec<f64> {
    sys.mass
        .iter()
        .map(|m| m.map_or(0.0, |m| dtf / m))
        .collect()
}

/// The first half of velocity Verlet on the atoms of `bit` (`fix nve`'s `initial_integrate`).
pub(crate) fn nve_initial(sys: &mut System, bit: u32) {
    let dt = sys.dt;
    let dtfm = per_type(sys, 0.5 * dt * sys.units.ftm2v);
    let a = &mut sys.atoms;
    if bit == 1 {
        a.x.par_iter_mut()
            .zip(a.v.par_iter_mut())
            .zip(a.f.par_iter().zip(a.typ.par_iter()))
            .for_each(|((x, v), (f, &t))| {
                let dtfm = dtfm[t as usize];
                for k in 0..3 {
                    v[k] += dtfm * f[k];
                    x[k] += dt * v[k];
                }
            });
        return;
    }
    for i in 0..a.len() {
        if a.mask_of(i) & bit != 0 {
            let dtfm = dtfm[a.typ[i] as usize];
            for k in 0..3 {
                a.v[i][k] += dtfm * a.f[i][k];
                a.x[i][k] += dt * a.v[i][k];
            }
        }
    }
}

/// The second half of velocity Verlet on the atoms of `bit`.
pub(crate) fn nve_final(sys: &mut System, bit: u32) {
    let dtfm = per_type(sys, 0.5 * sys.dt * sys.units.ftm2v);
    let a = &mut sys.atoms;
    if bit == 1 {
        a.v.par_iter_mut()
            .zip(a.f.par_iter().zip(a.typ.par_iter()))
            .for_each(|(v, (f, &t))| {
                let dtfm = dtfm[t as usize];
                for k in 0..3 {
                    v[k] += dtfm * f[k];
                }
            });
        return;
    }
    for i in 0..a.len() {
        if a.mask_of(i) & bit != 0 {
            let dtfm = dtfm[a.typ[i] as usize];
            for k in 0..3 {
                a.v[i][k] += dtfm * a.f[i][k];
            }
        }
    }
}

/// The Euler update of the atoms of `bit` (`fix nve/euler`; (δt · ftm2v) / m, as the LAMMPS
/// fix passes δt · ftm2v).
pub(crate) fn euler(sys: &mut System, bit: u32) {
    let dt = sys.dt;
    let dtfm = per_type(sys, dt * sys.units.ftm2v);
    let a = &mut sys.atoms;
    if bit == 1 {
        a.x.par_iter_mut()
            .zip(a.v.par_iter_mut())
            .zip(a.f.par_iter().zip(a.typ.par_iter()))
            .for_each(|((x, v), (f, &t))| fixes::euler_update(x, v, f, dt, dtfm[t as usize]));
        return;
    }
    for i in 0..a.len() {
        if a.mask_of(i) & bit != 0 {
            let (x, v, f) = (&mut a.x[i], &mut a.v[i], &a.f[i]);
            fixes::euler_update(x, v, f, dt, dtfm[a.typ[i] as usize]);
        }
    }
}

/// `fix mvv/dpd`'s first part: v_est = v + dtfm F, x += δt v_est, v += 2λ dtfm F (LAMMPS's
/// DPD-MESO `FixMvvDPD::initial_integrate`, the same operations in the same order).
fn mvv_initial(sys: &mut System, bit: u32, lambda: f64) {
    let dt = sys.dt;
    let dtfm = per_type(sys, 0.5 * dt * sys.units.ftm2v);
    let a = &mut sys.atoms;
    a.vest.resize(a.x.len(), [0.0; 3]);
    for i in 0..a.len() {
        if a.mask_of(i) & bit != 0 {
            let dtfm = dtfm[a.typ[i] as usize];
            for k in 0..3 {
                a.vest[i][k] = a.v[i][k] + dtfm * a.f[i][k];
            }
            for k in 0..3 {
                a.x[i][k] += dt * a.vest[i][k];
            }
            for k in 0..3 {
                a.v[i][k] += 2.0 * lambda * dtfm * a.f[i][k];
            }
        }
    }
}

/// `fix mvv/dpd`'s second part: v = v_est + dtfm F (the new forces).
fn mvv_final(sys: &mut System, bit: u32) {
    let dtfm = per_type(sys, 0.5 * sys.dt * sys.units.ftm2v);
    let a = &mut sys.atoms;
    for i in 0..a.len().min(a.vest.len()) {
        if a.mask_of(i) & bit != 0 {
            let dtfm = dtfm[a.typ[i] as usize];
            for k in 0..3 {
                a.v[i][k] = a.vest[i][k] + dtfm * a.f[i][k];
            }
        }
    }
}

impl Fix for Integrate {
    fn id(&self) -> &str {
        &self.id
    }
    fn integrates(&self) -> bool {
        true
    }
    fn scheme(&self) -> Option<Integrator> {
        Some(match self.scheme {
            Scheme::Euler => Integrator::Euler,
            Scheme::Nve | Scheme::Mvv(_) => Integrator::VelocityVerlet,
        })
    }
    fn initial_integrate(&mut self, sys: &mut System) {
        match self.scheme {
            Scheme::Nve => nve_initial(sys, self.bit),
            Scheme::Euler => euler(sys, self.bit),
            Scheme::Mvv(l) => mvv_initial(sys, self.bit, l),
        }
    }
    fn final_integrate(&mut self, sys: &mut System) {
        match self.scheme {
            Scheme::Nve => nve_final(sys, self.bit),
            Scheme::Euler => {}
            Scheme::Mvv(_) => mvv_final(sys, self.bit),
        }
    }
}
