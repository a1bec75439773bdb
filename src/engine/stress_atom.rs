//! LAMMPS's `compute stress/atom`: the per-atom stress × volume of each atom,
//! −nktv2p (mvv2e m v_a v_b + W_ab,i), with the kinetic part's velocities less the bias of a
//! temperature compute and W_i the atom's share of the virial of the last force evaluation
//! (½ of each pair and bond, ⅓ of each angle; tallied while
//! [`System::set_virial_atom`] is on).

use super::System;

/// The velocity bias a temperature compute removes before the kinetic part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KineticBias {
    /// `compute temp` (or no temperature compute): none.
    None,
    /// `compute temp/partial`: the unflagged components.
    Partial([bool; 3]),
    /// `compute temp/deform`: the streaming velocity of `fix deform`.
    Deform,
}

/// Which parts `compute stress/atom` sums (its keywords `ke pair bond angle virial`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StressParts {
    /// The kinetic part, with this bias removed; None without `ke`.
    pub ke: Option<KineticBias>,
    /// The virial of the pair forces.
    pub pair: bool,
    /// The virial of the bonds.
    pub bond: bool,
    /// The virial of the angles.
    pub angle: bool,
}

impl System {
    /// Switch the per-atom virial tally of the force evaluations on or off (LAMMPS's
    /// `vflag_atom`). Off, the pair loop is the same code and gives the same bits.
    pub fn set_virial_atom(&mut self, on: bool) {
        self.neighbor.virial_atom_on = on;
    }

    /// The velocity of atom `i` less `bias`.
    fn thermal_velocity(&self, i: usize, bias: KineticBias) -> [f64; 3] {
        let v = self.atoms.v[i];
        match bias {
            KineticBias::None => v,
            KineticBias::Partial(f) => std::array::from_fn(|k| if f[k] { v[k] } else { 0.0 }),
            KineticBias::Deform => {
                let u = self
                    .tri
                    .as_ref()
                    .map_or(0.0, |tr| tr.stream_x(&self.bx, self.atoms.x[i][1]));
                [v[0] - u, v[1], v[2]]
            }
        }
    }

    /// The per-atom stress × volume (xx yy zz xy xz yz, pressure × volume units) of `parts`,
    /// in the atoms' internal order. An error when a virial part is asked for and the last
    /// force evaluation did not tally it per atom.
    pub fn stress_atom(&self, parts: StressParts) -> Result<Vec<[f64; 6]>, String> {
        let n = self.atoms.len();
        let stale = "the per-atom virial is tallied from the set-up of the first run after \
                     the compute is defined: evaluate it during or after a run";
        let mut s = vec![[0.0; 6]; n];
        let mut add = |w: &[[f64; 6]]| -> Result<(), String> {
            if w.len() != n {
                return Err(stale.to_string());
            }
            for (s, w) in s.iter_mut().zip(w) {
                for c in 0..6 {
                    s[c] += w[c];
                }
            }
            Ok(())
        };
        if parts.pair && self.pair.is_some() {
            add(&self.neighbor.virial_atom)?;
        }
        let topo = self.topo.as_ref();
        if parts.bond && topo.is_some_and(|t| t.bond_style.is_some()) {
            add(&self.bonded.virial_bond)?;
        }
        if parts.angle && topo.is_some_and(|t| t.angle_style.is_some()) {
            add(&self.bonded.virial_angle)?;
        }
        let u = &self.units;
        if let Some(bias) = parts.ke {
            for (i, s) in s.iter_mut().enumerate() {
                let m = u.mvv2e * self.mass[self.atoms.typ[i] as usize].unwrap_or(0.0);
                super::measure::add_outer(s, m, self.thermal_velocity(i, bias));
            }
        }
        for s in &mut s {
            for c in s.iter_mut() {
                *c *= -u.nktv2p;
            }
        }
        Ok(s)
    }
}
