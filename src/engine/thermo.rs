//! What a run reports: LAMMPS's thermo sums (`compute temp`, `compute pressure`,
//! `compute temp/deform`), the momentum, the memory in use, and the blow-up check of any atom
//! store.

use super::*;

/// Kinetic and configurational sums from which LAMMPS's thermo keywords follow, in the
/// system's unit style (LAMMPS's `compute temp`, `compute pressure`, thermo `ke`: `mvv2e`,
/// `boltz`, `nktv2p` of [`crate::units::Units`], all 1 in `units lj`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Thermo {
    /// mvv2e Σ m v_a v_b (xx, yy, zz, xy, xz, yz), energy units (`compute temp`'s vector).
    pub ke_tensor: [f64; 6],
    /// Degrees of freedom d N − d (as LAMMPS `compute temp`).
    pub dof: f64,
    /// Kinetic temperature mvv2e Σ m v² / (dof boltz).
    pub temp: f64,
    /// Scalar pressure (dof boltz T + trace virial) / (d V) × nktv2p.
    pub press: f64,
    /// Pressure tensor (mvv2e Σ m v_a v_b + W_ab) / V × nktv2p; in 2-D zz, xz, yz are 0 as in
    /// LAMMPS.
    pub p_tensor: [f64; 6],
    /// Total kinetic energy mvv2e Σ m v² / 2.
    pub ke: f64,
    /// Total potential energy (pair + bond + angle).
    pub pe: f64,
    /// Its parts.
    pub energies: Energies,
    /// Volume (area in 2-D).
    pub vol: f64,
}

impl System {
    /// The thermodynamic state with LAMMPS's definitions (`docs/models.md` §4.5, P-7–P-9).
    pub fn thermo(&self) -> Thermo {
        let mut kt = [0.0; 6];
        for ((v, &t), _) in self.atoms.v.iter().zip(&self.atoms.typ).zip(0..) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            super::measure::add_outer(&mut kt, m, *v);
        }
        self.thermo_from_kinetic(kt)
    }

    /// The kinetic part of `compute temp/deform` (LAMMPS definitions): Σ m (v − u)_a (v − u)_b
    /// with the streaming velocity u = (h_rate_xy (y − y_lo)/L_y, 0, 0) of the current
    /// deformation (u = 0 without one), its temperature over dof = dN − d, and the pressure of
    /// `compute pressure ID` with this temperature: (Σ m (v−u)_a (v−u)_b + W_ab)/V.
    pub fn thermo_deform(&self) -> Thermo {
        let mut kt = [0.0; 6];
        for ((v, &t), x) in self.atoms.v.iter().zip(&self.atoms.typ).zip(&self.atoms.x) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            let u = self
                .tri
                .as_ref()
                .map_or(0.0, |tr| tr.stream_x(&self.bx, x[1]));
            let w = [v[0] - u, v[1], v[2]];
            super::measure::add_outer(&mut kt, m, w);
        }
        self.thermo_from_kinetic(kt)
    }

    /// The thermodynamic state from the kinetic tensor `kt` = Σ m v_a v_b (xx yy zz xy xz yz,
    /// mass × velocity²) of some temperature compute and the last force evaluation's virial,
    /// with LAMMPS's unit factors (each 1, so no bit changes, in `units lj`).
    pub(super) fn thermo_from_kinetic(&self, kt: [f64; 6]) -> Thermo {
        let d = self.dim() as f64;
        let n = self.atoms.len() as f64;
        self.thermo_from_kinetic_dof(kt, d * n - d)
    }

    /// The kinetic part of LAMMPS's `compute temp/partial xflag yflag zflag`: Σ m v_a v_b of
    /// the flagged components only (a product with an unflagged component is 0), over
    /// dof = n_f N − (n_f / d) d, n_f the number of flags set (LAMMPS's `dof_compute` with
    /// its default extra dof d), and the pressure of `compute pressure ID` with it.
    pub fn thermo_partial(&self, flags: [bool; 3]) -> Thermo {
        let on = flags.map(|f| if f { 1.0 } else { 0.0 });
        let mut kt = [0.0; 6];
        for (v, &t) in self.atoms.v.iter().zip(&self.atoms.typ) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            let w = [on[0] * v[0], on[1] * v[1], on[2] * v[2]];
            super::measure::add_outer(&mut kt, m, w);
        }
        let d = self.dim() as f64;
        let nper = on.iter().sum::<f64>();
        let dof = nper * self.atoms.len() as f64 - (nper / d) * d;
        self.thermo_from_kinetic_dof(kt, dof)
    }

    /// [`System::thermo_from_kinetic`] with the degrees of freedom of the temperature given.
    fn thermo_from_kinetic_dof(&self, kt: [f64; 6], dof: f64) -> Thermo {
        let u = &self.units;
        let kt = kt.map(|x| u.mvv2e * x);
        let d = self.dim();
        let mv2 = if d == 3 {
            kt[0] + kt[1] + kt[2]
        } else {
            kt[0] + kt[1]
        };
        let temp = if dof > 0.0 {
            mv2 / (dof * u.boltz)
        } else {
            0.0
        };
        let vol = self.bx.volume();
        let w = self.tally.virial;
        let trace = if d == 3 {
            w[0] + w[1] + w[2]
        } else {
            w[0] + w[1]
        };
        let press = (dof * u.boltz * temp + trace) / (d as f64 * vol) * u.nktv2p;
        let mut p = [0.0; 6];
        for a in 0..6 {
            p[a] = (kt[a] + w[a]) / vol * u.nktv2p;
        }
        if d == 2 {
            p[2] = 0.0;
            p[4] = 0.0;
            p[5] = 0.0;
        }
        Thermo {
            ke_tensor: kt,
            dof,
            temp,
            press,
            p_tensor: p,
            ke: 0.5 * mv2,
            pe: self.tally.energy,
            energies: self.energies,
            vol,
        }
    }

    /// Total momentum Σ m v.
    pub fn momentum(&self) -> [f64; 3] {
        let mut p = [0.0; 3];
        for (v, &t) in self.atoms.v.iter().zip(&self.atoms.typ) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            for k in 0..3 {
                p[k] += m * v[k];
            }
        }
        p
    }

    /// Bytes per atom held by the atom arrays and the neighbour structures.
    pub fn bytes(&self) -> (usize, usize) {
        let a = &self.atoms;
        let atom_bytes = a.x.capacity() * 24 * 3
            + a.tag.capacity() * 4
            + a.typ.capacity() * 4
            + a.image.capacity() * 12;
        (atom_bytes, self.neighbor.bytes())
    }
}

/// The blow-up check of [`System::check_health`] for any atom store (the C ABI passes LAMMPS's
/// owned atoms): `atom(i)` gives (tag, x, v, f) of atom i < n; `len` the box lengths. The first
/// non-finite position, velocity or force, or a velocity that crosses half the box length in
/// one step, is an error naming the step, the atom and the quantity.
pub fn check_atoms(
    step: u64,
    dt: f64,
    dim: usize,
    len: [f64; 3],
    n: usize,
    atom: impl Fn(usize) -> (u32, [f64; 3], [f64; 3], [f64; 3]),
) -> Result<(), String> {
    let axis = ["x", "y", "z"];
    for i in 0..n {
        let (tag, x, v, f) = atom(i);
        for (what, q) in [("position", &x), ("velocity", &v), ("force", &f)] {
            if let Some(k) = (0..3).find(|&k| !q[k].is_finite()) {
                return Err(format!(
                    "blow-up at step {step}: atom {tag} has a non-finite {what} ({}{} = {})",
                    &what[..1],
                    axis[k],
                    q[k]
                ));
            }
        }
        if let Some(k) = (0..dim).find(|&k| v[k].abs() * dt > 0.5 * len[k]) {
            return Err(format!(
                "blow-up at step {step}: atom {tag} moves {:.3e} per step along {} (v{} = {:.3e}), more than half the box length {}; reduce the time step or check the force field",
                v[k].abs() * dt,
                axis[k],
                axis[k],
                v[k],
                len[k]
            ));
        }
    }
    Ok(())
}
