//! `fix ID GROUP momentum N [linear XFLAG YFLAG ZFLAG] [angular] [rescale]`: every N steps, at
//! the end of the step, the group's centre-of-mass velocity removed from its atoms in the
//! flagged components, with `angular` its rigid rotation about its centre of mass (unwrapped
//! positions, ω = I⁻¹ L), and with `rescale` their kinetic energy restored (LAMMPS's
//! `FixMomentum` and `Group::xcm`, `angmom`, `inertia`, `omega`).

use super::{Fix, System};

/// `fix momentum`.
#[derive(Clone, Debug)]
pub struct Momentum {
    id: String,
    bit: u32,
    every: u64,
    linear: [bool; 3],
    angular: bool,
    rescale: bool,
}

impl Momentum {
    /// Fix `id` on group bit `bit`.
    pub fn new(
        id: &str,
        bit: u32,
        every: u64,
        linear: [bool; 3],
        angular: bool,
        rescale: bool,
    ) -> Momentum {
        Momentum {
            id: id.to_string(),
            bit,
            every: every.max(1),
            linear,
            angular,
            rescale,
        }
    }

    /// The unwrapped position of atom `i` (LAMMPS's `Domain::unmap`).
    fn unwrapped(sys: &System, i: usize) -> [f64; 3] {
        let (x, im) = (sys.atoms.x[i], sys.atoms.image[i]);
        match &sys.tri {
            Some(t) => sys.bx.unwrap_tilted(x, im, t.reported_xy(&sys.bx)),
            None => sys.bx.unwrap(x, im),
        }
    }

    /// Remove the group's rigid rotation about its centre of mass: v −= ω × (x − x_cm) with
    /// ω = I⁻¹ L (LAMMPS's non-singular branch; a singular inertia tensor, below 1e-6, leaves
    /// the velocities and warns).
    fn remove_rotation(&self, sys: &mut System, mtot: f64) {
        let member = |sys: &System, i: usize| sys.atoms.mask_of(i) & self.bit != 0;
        let mass = |sys: &System, i: usize| sys.mass[sys.atoms.typ[i] as usize].unwrap_or(0.0);
        let n = sys.atoms.len();
        let mut cm = [0.0; 3];
        for i in (0..n).filter(|&i| member(sys, i)) {
            let u = Self::unwrapped(sys, i);
            for k in 0..3 {
                cm[k] += u[k] * mass(sys, i);
            }
        }
        let cm = cm.map(|c| c / mtot);
        let (mut l, mut it) = ([0.0; 3], [[0.0; 3]; 3]);
        for i in (0..n).filter(|&i| member(sys, i)) {
            let u = Self::unwrapped(sys, i);
            let (dx, dy, dz) = (u[0] - cm[0], u[1] - cm[1], u[2] - cm[2]);
            let (m, v) = (mass(sys, i), sys.atoms.v[i]);
            l[0] += m * (dy * v[2] - dz * v[1]);
            l[1] += m * (dz * v[0] - dx * v[2]);
            l[2] += m * (dx * v[1] - dy * v[0]);
            it[0][0] += m * (dy * dy + dz * dz);
            it[1][1] += m * (dx * dx + dz * dz);
            it[2][2] += m * (dx * dx + dy * dy);
            it[0][1] -= m * dx * dy;
            it[1][2] -= m * dy * dz;
            it[0][2] -= m * dx * dz;
        }
        it[1][0] = it[0][1];
        it[2][1] = it[1][2];
        it[2][0] = it[0][2];
        let Some(w) = omega(&it, &l) else {
            sys.warnings.push(format!(
                "fix {} momentum angular: the group's inertia tensor is singular; its rotation \
                 was not removed at step {}",
                self.id, sys.step
            ));
            return;
        };
        for i in 0..n {
            if member(sys, i) {
                let u = Self::unwrapped(sys, i);
                let (dx, dy, dz) = (u[0] - cm[0], u[1] - cm[1], u[2] - cm[2]);
                let v = &mut sys.atoms.v[i];
                v[0] -= w[1] * dz - w[2] * dy;
                v[1] -= w[2] * dx - w[0] * dz;
                v[2] -= w[0] * dy - w[1] * dx;
            }
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
        if self.angular {
            self.remove_rotation(sys, mtot);
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

/// ω = I⁻¹ L by the cofactors of I, when det I > 1e-6 (LAMMPS's `Group::omega`, its
/// non-singular branch, the same operations).
fn omega(i: &[[f64; 3]; 3], l: &[f64; 3]) -> Option<[f64; 3]> {
    let det =
        i[0][0] * i[1][1] * i[2][2] + i[0][1] * i[1][2] * i[2][0] + i[0][2] * i[1][0] * i[2][1]
            - i[0][0] * i[1][2] * i[2][1]
            - i[0][1] * i[1][0] * i[2][2]
            - i[2][0] * i[1][1] * i[0][2];
    if det <= 1.0e-6 {
        return None;
    }
    let mut inv = [
        [
            i[1][1] * i[2][2] - i[1][2] * i[2][1],
            -(i[0][1] * i[2][2] - i[0][2] * i[2][1]),
            i[0][1] * i[1][2] - i[0][2] * i[1][1],
        ],
        [
            -(i[1][0] * i[2][2] - i[1][2] * i[2][0]),
            i[0][0] * i[2][2] - i[0][2] * i[2][0],
            -(i[0][0] * i[1][2] - i[0][2] * i[1][0]),
        ],
        [
            i[1][0] * i[2][1] - i[1][1] * i[2][0],
            -(i[0][0] * i[2][1] - i[0][1] * i[2][0]),
            i[0][0] * i[1][1] - i[0][1] * i[1][0],
        ],
    ];
    for row in inv.iter_mut() {
        for c in row.iter_mut() {
            *c /= det;
        }
    }
    Some(std::array::from_fn(|r| {
        inv[r][0] * l[0] + inv[r][1] * l[1] + inv[r][2] * l[2]
    }))
}

#[cfg(test)]
mod tests {
    use super::omega;

    /// ω = I⁻¹ L for a diagonal and a full inertia tensor; a singular one gives none.
    #[test]
    fn omega_inverts_the_inertia_tensor() {
        let d = [[2.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 8.0]];
        assert_eq!(omega(&d, &[2.0, 4.0, 8.0]), Some([1.0, 1.0, 1.0]));
        let i = [[4.0, -1.0, 0.5], [-1.0, 3.0, -0.25], [0.5, -0.25, 5.0]];
        let w = [0.3, -0.7, 1.1];
        let l: [f64; 3] = std::array::from_fn(|r| (0..3).map(|c| i[r][c] * w[c]).sum());
        let back = omega(&i, &l).expect("invertible");
        for k in 0..3 {
            assert!((back[k] - w[k]).abs() < 1e-14);
        }
        assert_eq!(
            omega(
                &[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
                &[1.0; 3]
            ),
            None
        );
    }
}
