//! The sheared box's part of the driver (the state is `lees_edwards::Triclinic`, in
//! `System::tri`): the tilt of the step for the neighbour list, LAMMPS's re-neighbouring rule
//! under deformation, flips, wrapping with the `remap v` jump, the momentum-leak warning.

use super::*;

impl System {
    /// A sheared box: the tilt, offset and rate of the current step, handed to the neighbour
    /// list (`lees_edwards.rs`); a periodic box: none.
    pub(super) fn set_shear(&mut self) {
        let ly = self.bx.len()[1];
        let dt = self.dt;
        let shear = self.tri.as_mut().map(|t| {
            t.set_step(&self.bx, dt, self.step);
            // LAMMPS's order rebuilds by LAMMPS's rule: no tilt allowance.
            let drift = if t.lammps_order() {
                0.0
            } else {
                t.le.rate * ly * dt
            };
            (t.le, t.xy, drift)
        });
        self.neighbor.set_shear(shear);
    }

    /// LAMMPS's reneighbouring decision for a triclinic box (`Neighbor::decide` with
    /// `delay 0 every 1 check yes`, `check_distance` with its box check): a flip pending, or
    /// an atom moved more than δ = ½ (skin − (Δ1 + Δ2)) since the last build, Δ1 ≥ Δ2 the two
    /// largest displacements of the box's corners (here the tilt's change, on the corners at
    /// y_hi), formed with LAMMPS's operations.
    pub(super) fn lammps_rebuild_due(&self, setup: bool) -> bool {
        let Some(t) = self.tri.as_ref() else {
            return self.neighbor.needs_rebuild(&self.atoms);
        };
        if t.flip_pending() && !setup {
            return true;
        }
        let (h0, lo) = (self.bx.len()[0], self.bx.lo[0]);
        let (xy0, xy1) = (self.neighbor.xy_at_build(), t.xy);
        let (mut d1, mut d2) = (0.0f64, 0.0f64);
        for c in 0..8u32 {
            let (l0, l1, l2) = (f64::from(c & 1), f64::from((c >> 1) & 1), f64::from(c >> 2));
            let corner = |xy: f64| h0 * l0 + xy * l1 + 0.0 * l2 + lo;
            let delx = corner(xy1) - corner(xy0);
            let delta = (delx * delx).sqrt();
            if delta > d1 {
                d1 = delta;
            } else if delta > d2 {
                d2 = delta;
            }
        }
        let delta = (0.5 * (self.neighbor.skin - (d1 + d2))).max(0.0);
        // The list's own validity too: LAMMPS's rule is the stricter one whenever δ > 0, but
        // with δ = 0 it rebuilds only once an atom moves at all (atoms at rest: never).
        self.neighbor.moved_beyond(&self.atoms, delta * delta)
            || self.neighbor.needs_rebuild(&self.atoms)
    }

    /// A flip decided at the end of the last step (LAMMPS's `FixDeform::pre_exchange`, before
    /// the rebuild): the tilt changes by a box length, every x image flag by −flipxy · iy
    /// (`Domain::image_flip`), and every atom outside the box is put back into it
    /// (`Domain::remap`: its velocity is left alone, also for an atom through y, whose velocity
    /// jump LAMMPS's `remap` does not apply; with `fix flip/momentum` an atom through y gets
    /// the jump, as `Domain::pbc` would give it). The atoms put through y and the momentum
    /// relative to the profile that they changed are counted in `Triclinic::leak`.
    pub(super) fn flip_box(&mut self) {
        let Some(flipxy) = self.tri.as_mut().and_then(|t| t.take_flip()) else {
            return;
        };
        for im in self.atoms.image.iter_mut() {
            im[0] = im[0].saturating_sub(flipxy.saturating_mul(im[1]));
        }
        self.set_shear();
        let Some(t) = self.tri.as_mut() else {
            return;
        };
        let bx = &self.bx;
        let jump = t.le.jump(bx);
        // With fix flip/momentum the atoms put through y get remap v's velocity jump; without
        // it (LAMMPS's remap) the same wrap with a jump of 0 (rate 0: v_x − n·0 is v_x).
        let mut le = t.le;
        if t.flip_fix == Some(true) {
            t.leak.conserved = true;
        } else {
            le.rate = 0.0;
        }
        let a = &mut self.atoms;
        let crossings: Vec<i32> =
            a.x.par_iter_mut()
                .zip(a.v.par_iter_mut())
                .zip(a.image.par_iter_mut())
                .map(|((x, v), im)| bx.wrap_le(x, v, im, &le))
                .collect();
        // Counted in storage order (a serial sum: the same bits on any number of threads), at
        // the jump the atom got or would have got.
        for (&n, &typ) in crossings.iter().zip(&a.typ) {
            if n != 0 {
                let m = self
                    .mass
                    .get(typ as usize)
                    .copied()
                    .flatten()
                    .unwrap_or(0.0);
                t.leak.atoms += 1;
                t.leak.momentum += m * f64::from(n) * jump;
            }
        }
    }

    /// The end-of-run warning of the flips' momentum leak (`lees_edwards::flip_leak_warning`),
    /// once per run: the counts start again at the next run's set-up.
    pub fn flip_leak_warning(&self) -> Option<String> {
        let t = self.tri.as_ref()?;
        if t.leak.conserved {
            return None;
        }
        let total: f64 = self
            .atoms
            .typ
            .iter()
            .map(|&ty| self.mass.get(ty as usize).copied().flatten().unwrap_or(0.0))
            .sum();
        lees_edwards::flip_leak_warning(&t.leak, total)
    }

    /// Put every atom into the box without changing a velocity, as LAMMPS's `Domain::remap`
    /// (after `read_data`): a tilted box moves an atom through y by the tilt, its image flags
    /// keep x + ix L_x + iy xy. Orthogonal boxes: nothing (the first build wraps them).
    pub fn remap_into_box(&mut self) {
        let dt = self.dt;
        let Some(t) = self.tri.as_mut() else {
            return;
        };
        t.set_step(&self.bx, dt, self.step);
        let mut le = t.le;
        le.rate = 0.0;
        let bx = &self.bx;
        for (x, im) in self.atoms.x.iter_mut().zip(self.atoms.image.iter_mut()) {
            let mut v = [0.0; 3];
            bx.wrap_le(x, &mut v, im, &le);
        }
    }

    /// LAMMPS's `Domain::pbc` on a tilted box as `write_data` does it: every atom outside the
    /// box is wrapped, through y by the tilt; `remap v`'s velocity jump is h_rate, which is 0
    /// outside a run (`init_outside_run`), so no velocity changes. Returns the tilt as LAMMPS
    /// reports it.
    pub fn pbc(&mut self) -> f64 {
        // LAMMPS's `write_data` runs `init` first, outside a run: `fix deform`'s h_rate is 0.
        let (dt, step) = (self.dt, self.step);
        if let Some(t) = self.tri.as_mut() {
            t.init_outside_run(&self.bx, dt, step);
        }
        self.set_shear();
        let Some(t) = self.tri.as_ref() else {
            return 0.0;
        };
        let le = t.le;
        let bx = &self.bx;
        let a = &mut self.atoms;
        for ((x, v), im) in a.x.iter_mut().zip(a.v.iter_mut()).zip(a.image.iter_mut()) {
            bx.wrap_le(x, v, im, &le);
        }
        // (Positions moved: every run's set-up builds a fresh list.)
        t.reported_xy(&self.bx)
    }

    /// A position of the box (orthogonal storage) and its image flags (LAMMPS's convention for
    /// the tilt `tri.xy`) as LAMMPS holds them in the tilted cell of tilt `xy`:
    /// x ∈ [x_lo + xy λ_y, x_hi + xy λ_y), λ_y = (y − y_lo)/L_y, same unwrapped position.
    pub fn to_tilted_cell(&self, x: &mut [f64; 3], im: &mut [i32; 3], xy: f64) {
        let [lx, ly, _] = self.bx.len();
        if let Some(t) = &self.tri {
            // Image flags relative to the written tilt (they differ by whole L_x).
            let k = ((t.xy - xy) / lx).round();
            im[0] = im[0].saturating_add((k * f64::from(im[1])) as i32);
        }
        let lambda_y = (x[1] - self.bx.lo[1]) / ly;
        let k = ((x[0] - self.bx.lo[0] - xy * lambda_y) / lx).floor();
        if k != 0.0 && k.is_finite() {
            x[0] -= k * lx;
            im[0] = im[0].saturating_add(k as i32);
        }
    }

    /// LAMMPS's `end_of_step` of `fix deform` (LAMMPS's order): the box's tilt of step
    /// `self.step`, after its forces.
    pub(super) fn deform_end_of_step(&mut self) {
        if let Some(t) = self.tri.as_mut() {
            t.end_of_step(&self.bx, self.step);
        }
    }
}
