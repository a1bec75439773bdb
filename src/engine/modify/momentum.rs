//! `fix ID GROUP momentum N [linear XFLAG YFLAG ZFLAG] [rescale]`: every N steps, at the end of
//! the step, the group's centre-of-mass velocity removed from its atoms in the flagged
//! components, and with `rescale` their kinetic energy restored (LAMMPS's `FixMomentum`).

use super::{Fix, System};

/// `fix momentum`.
#[derive(Clone, Debug)]
pub struct Momentum {
    id: String,
    bit: u32,
    every: u64,
    linear: [bool; 3],
    rescale: bool,
}

impl Momentum {
    /// Fix `id` on group bit `bit`.
    pub fn new(id: &str, bit: u32, every: u64, linear: [bool; 3], rescale: bool) -> Momentum {
        Momentum {
            id: id.to_string(),
            bit,
            every: every.max(1),
            linear,
            rescale,
        }
    }

    /// Σ m v·v over the group.
    fn mv2(&self, sys: &System) -> f64 {
        let a = &sys.atoms;
        let mut ke = 0.0;
        for i in 0..a.len() {
            if a.mask_of(i) & self.bit != 0 {
                let m = sys.mass[a.typ[i] as usize].unwrap_or(0.0);
                let v = a.v[i];
                ke += m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            }
        }
        ke
    }
}

impl Fix for Momentum {
    fn id(&self) -> &str {
        &self.id
    }
    fn end_of_step(&mut self, sys: &mut System) {
        if !sys.step.is_multiple_of(self.every) {
            return;
        }
        let a = &sys.atoms;
        let (mut mtot, mut p) = (0.0, [0.0; 3]);
        for i in 0..a.len() {
            if a.mask_of(i) & self.bit != 0 {
                let m = sys.mass[a.typ[i] as usize].unwrap_or(0.0);
                mtot += m;
                for k in 0..3 {
                    p[k] += a.v[i][k] * m;
                }
            }
        }
        if mtot == 0.0 {
            return;
        }
        let before = if self.rescale { self.mv2(sys) } else { 0.0 };
        let vcm = p.map(|p| p / mtot);
        let a = &mut sys.atoms;
        for i in 0..a.len() {
            if a.mask_of(i) & self.bit != 0 {
                for k in 0..3 {
                    if self.linear[k] {
                        a.v[i][k] -= vcm[k];
                    }
                }
            }
        }
        if self.rescale {
            let after = self.mv2(sys);
            let factor = if after != 0.0 {
                (before / after).sqrt()
            } else {
                1.0
            };
            let a = &mut sys.atoms;
            for i in 0..a.len() {
                if a.mask_of(i) & self.bit != 0 {
                    for k in 0..3 {
                        a.v[i][k] *= factor;
                    }
                }
            }
        }
    }
}
