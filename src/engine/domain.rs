//! The simulation box: orthorhombic, periodic in every direction (`boundary p p p`).

/// An orthorhombic periodic box in 2-D or 3-D. In 2-D the z extent exists (LAMMPS requires it to
/// straddle 0) but z is never wrapped and every z coordinate is 0.
#[derive(Clone, Debug, PartialEq)]
pub struct SimBox {
    /// 2 or 3.
    pub dim: usize,
    /// Lower corner.
    pub lo: [f64; 3],
    /// Upper corner.
    pub hi: [f64; 3],
    len: [f64; 3],
    inv_len: [f64; 3],
}

impl SimBox {
    /// A box from its corners; `Err` if any extent is not positive and finite.
    pub fn new(dim: usize, lo: [f64; 3], hi: [f64; 3]) -> Result<SimBox, String> {
        let mut len = [0.0; 3];
        let mut inv_len = [0.0; 3];
        for d in 0..3 {
            len[d] = hi[d] - lo[d];
            if !(len[d].is_finite() && len[d] > 0.0) {
                return Err(format!(
                    "box extent in {} is {} (lo {} hi {}): must be positive",
                    ["x", "y", "z"][d],
                    len[d],
                    lo[d],
                    hi[d]
                ));
            }
            inv_len[d] = 1.0 / len[d];
        }
        if dim == 2 && !(lo[2] < 0.0 && hi[2] > 0.0) {
            return Err(format!(
                "a 2-D box must have z bounds straddling 0 (got {} {})",
                lo[2], hi[2]
            ));
        }
        Ok(SimBox {
            dim,
            lo,
            hi,
            len,
            inv_len,
        })
    }

    /// Edge lengths.
    pub fn len(&self) -> [f64; 3] {
        self.len
    }

    /// Volume in 3-D, area in 2-D (as LAMMPS's `vol` and pressure use).
    pub fn volume(&self) -> f64 {
        if self.dim == 3 {
            self.len[0] * self.len[1] * self.len[2]
        } else {
            self.len[0] * self.len[1]
        }
    }

    /// The minimum image of a separation vector: d − L round(d / L) in each periodic direction.
    /// Antisymmetric to the last bit (`round` and IEEE subtraction are sign-symmetric), so the
    /// pair (j, i) sees exactly −r_ij.
    #[inline(always)]
    pub fn min_image(&self, mut d: [f64; 3]) -> [f64; 3] {
        for k in 0..self.dim {
            // Round half away from zero through truncation (one instruction, no libm call);
            // both steps are odd functions, so the result stays exactly antisymmetric.
            let y = d[k] * self.inv_len[k];
            let n = (y + 0.5f64.copysign(y)) as i64 as f64;
            d[k] -= self.len[k] * n;
        }
        d
    }

    /// Map a position into [lo, hi) in each periodic direction, counting the crossings in `image`.
    #[inline]
    pub fn wrap(&self, x: &mut [f64; 3], image: &mut [i32; 3]) {
        for k in 0..self.dim {
            let shift = ((x[k] - self.lo[k]) * self.inv_len[k]).floor();
            if shift != 0.0 {
                x[k] -= shift * self.len[k];
                // Saturating: an atom blown ~2^31 box lengths away in one rebuild (a fuzzed
                // friction of 1e12) overflowed the count and panicked; the blow-up check then
                // names the atom instead.
                image[k] = image[k].saturating_add(shift as i32);
                // Round-off can leave x == hi; LAMMPS maps that to lo.
                if x[k] >= self.hi[k] {
                    x[k] = self.lo[k];
                    image[k] = image[k].saturating_add(1);
                }
            }
        }
    }

    /// The unwrapped position of a box with tilt xy, LAMMPS's `Domain::unmap`:
    /// x + ix L_x + iy xy along x.
    #[inline]
    pub fn unwrap_tilted(&self, x: [f64; 3], image: [i32; 3], xy: f64) -> [f64; 3] {
        let mut u = self.unwrap(x, image);
        u[0] += xy * f64::from(image[1]);
        u
    }

    /// The unwrapped position x + image · L.
    #[inline]
    pub fn unwrap(&self, x: [f64; 3], image: [i32; 3]) -> [f64; 3] {
        [
            x[0] + f64::from(image[0]) * self.len[0],
            x[1] + f64::from(image[1]) * self.len[1],
            x[2] + f64::from(image[2]) * self.len[2],
        ]
    }
}

/// Lees–Edwards "sliding brick" boundaries for planar Couette flow (`docs/models.md` §4.3, P-5;
/// weighting-function paper §5): flow along x, gradient along y. The periodic image at +L_y is
/// displaced by `offset` along x and moves with velocity +γ̇ L_y along x (the image at −L_y by
/// −offset and −γ̇ L_y). Equivalent to LAMMPS's `fix deform … xy erate γ̇ remap v` on a tilted box,
/// in the orthogonal-box form. Used by the neighbour list (its rows, minimum images and wrapping
/// under shear, `neighbor/`) and by the deformation in `lees_edwards.rs`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeesEdwards {
    /// Shear rate γ̇ = ∂v_x/∂y.
    pub rate: f64,
    /// Current x displacement of the +L_y image, in [0, L_x).
    pub offset: f64,
    /// offset − xy in box lengths L_x (an integer): an atom crossing y moves by the offset
    /// instead of the tilt, so its x image flag changes by this much (LAMMPS's unwrapped
    /// x + ix L_x + iy xy is kept).
    pub tilt_cells: f64,
}

impl LeesEdwards {
    /// No displacement yet (t = 0).
    pub fn new(rate: f64) -> LeesEdwards {
        LeesEdwards {
            rate,
            offset: 0.0,
            tilt_cells: 0.0,
        }
    }

    /// The velocity jump γ̇ L_y of the +L_y image.
    pub fn jump(&self, bx: &SimBox) -> f64 {
        self.rate * bx.len[1]
    }

    /// Advance the image displacement by γ̇ L_y δt, kept in [0, L_x).
    pub fn advance(&mut self, bx: &SimBox, dt: f64) {
        let lx = bx.len[0];
        self.offset = (self.offset + self.jump(bx) * dt).rem_euclid(lx);
        if self.offset >= lx {
            self.offset = 0.0;
        }
    }
}

impl SimBox {
    /// Every periodic image of separation `d` = r_i − r_j with |r|² in [`min_sq`, `rcsq`), and
    /// its Lees–Edwards velocity correction Δv_x (0 in a periodic box), appended to `out`, for a
    /// box shorter than 2 r_c along the axes `short` (P-4b): along a short axis the nearest
    /// image and its neighbours at ±L are tried (with r_c ≤ L no farther one is in range),
    /// along the others the nearest image only (one at most is in range). Under Lees–Edwards
    /// an image n_y boxes along y moves by n_y · offset along x and adds n_y γ̇ L_y to Δv_x,
    /// as [`SimBox::min_image_le`]; x is then reduced to its nearest image again. Order: n_y,
    /// then n_x, then n_z, each −1, 0, +1.
    #[allow(clippy::too_many_arguments)]
    pub fn images_within(
        &self,
        d: [f64; 3],
        le: Option<&LeesEdwards>,
        short: [bool; 3],
        rcsq: f64,
        min_sq: f64,
        out: &mut Vec<([f64; 3], f64)>,
    ) {
        let round = |y: f64| (y + 0.5f64.copysign(y)) as i64 as f64;
        let (dm, dvx_m, off, jump) = match le {
            None => (self.min_image(d), 0.0, 0.0, 0.0),
            Some(le) => {
                let (dm, dvx) = self.min_image_le(d, le);
                (dm, dvx, le.offset, le.jump(self))
            }
        };
        let span = |k: usize| -> std::ops::RangeInclusive<i32> {
            if short[k] && k < self.dim {
                -1..=1
            } else {
                0..=0
            }
        };
        for ny in span(1) {
            let fy = f64::from(ny);
            let y = dm[1] + fy * self.len[1];
            let mut x0 = dm[0];
            if ny != 0 {
                x0 += fy * off;
                x0 -= self.len[0] * round(x0 * self.inv_len[0]);
            }
            let dvx = dvx_m + fy * jump;
            for nx in span(0) {
                let x = x0 + f64::from(nx) * self.len[0];
                for nz in span(2) {
                    let z = dm[2] + f64::from(nz) * self.len[2];
                    let rsq = x * x + y * y + z * z;
                    if rsq < rcsq && rsq >= min_sq {
                        out.push(([x, y, z], dvx));
                    }
                }
            }
        }
    }

    /// The image key's frame of this box (P-4b): its lengths, the Lees–Edwards offset as the
    /// tilt xy, every axis of the dimension periodic.
    pub fn image_frame(&self, le: Option<&LeesEdwards>) -> crate::rng::ImageFrame {
        let xy = le.map_or(0.0, |l| l.offset);
        crate::rng::ImageFrame::new(self.dim, self.len, [xy, 0.0, 0.0], [true; 3])
    }

    /// The minimum image of r_ij = r_i − r_j under Lees–Edwards boundaries, and the velocity
    /// correction Δv_x to add to v_ij = v_i − v_j (`docs/models.md` §0 and P-5: v_ij includes the
    /// boundary velocity jump). When the nearest image of j lies n_y boxes away along y,
    /// r_ij.x also shifts by −n_y·offset and Δv_x = −n_y γ̇ L_y. Exactly antisymmetric, like
    /// [`SimBox::min_image`]: the pair (j, i) gets −r_ij and −Δv_x. In 2-D z is left alone.
    #[inline]
    pub fn min_image_le(&self, mut d: [f64; 3], le: &LeesEdwards) -> ([f64; 3], f64) {
        let round = |y: f64| (y + 0.5f64.copysign(y)) as i64 as f64;
        let ny = round(d[1] * self.inv_len[1]);
        d[1] -= self.len[1] * ny;
        d[0] -= le.offset * ny;
        d[0] -= self.len[0] * round(d[0] * self.inv_len[0]);
        if self.dim == 3 {
            d[2] -= self.len[2] * round(d[2] * self.inv_len[2]);
        }
        (d, -ny * le.jump(self))
    }

    /// Map a position back into the box under Lees–Edwards boundaries: crossing y_hi (y_lo)
    /// moves the atom by −offset (+offset) along x and changes v_x by −γ̇ L_y (+γ̇ L_y), so it
    /// re-enters with the velocity of the image it becomes; then x and z wrap periodically.
    /// `image` counts the crossings as LAMMPS does for a tilted box: the unwrapped position
    /// x + ix L_x + iy xy (LAMMPS's `Domain::unmap`) is kept, so a y crossing also changes ix
    /// by [`LeesEdwards::tilt_cells`]. Returns the y crossings, as
    /// [`crate::engine::lees_edwards::y_crossings`] counts them.
    pub fn wrap_le(
        &self,
        x: &mut [f64; 3],
        v: &mut [f64; 3],
        image: &mut [i32; 3],
        le: &LeesEdwards,
    ) -> i32 {
        let ny = ((x[1] - self.lo[1]) * self.inv_len[1]).floor();
        let mut crossings = 0;
        if ny != 0.0 {
            x[1] -= ny * self.len[1];
            x[0] -= ny * le.offset;
            v[0] -= ny * le.jump(self);
            crossings = ny as i32;
            image[1] = image[1].saturating_add(crossings); // saturating: as in `wrap`
            image[0] = image[0].saturating_add((ny * le.tilt_cells) as i32);
            // Round-off can leave y == hi: that point is the image of lo, one more crossing.
            if x[1] >= self.hi[1] {
                x[1] = self.lo[1];
                x[0] -= le.offset;
                v[0] -= le.jump(self);
                crossings = crossings.saturating_add(1);
                image[1] = image[1].saturating_add(1);
                image[0] = image[0].saturating_add(le.tilt_cells as i32);
            }
        }
        let mut im = [0; 3];
        let mut y = *x;
        self.wrap(&mut y, &mut im);
        x[0] = y[0];
        image[0] = image[0].saturating_add(im[0]);
        if self.dim == 3 {
            x[2] = y[2];
            image[2] = image[2].saturating_add(im[2]);
        }
        crossings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bx() -> SimBox {
        SimBox::new(3, [0.0, -2.0, 0.0], [6.0, 2.0, 5.0]).unwrap()
    }

    #[test]
    fn zero_shear_is_the_periodic_minimum_image() {
        let b = bx();
        let le = LeesEdwards::new(0.0);
        for d in [[2.9, 1.9, -2.4], [-5.5, 3.1, 4.9], [0.1, -3.9, 0.2]] {
            let (m, dv) = b.min_image_le(d, &le);
            assert_eq!(m, b.min_image(d));
            assert_eq!(dv, 0.0);
        }
    }

    #[test]
    fn sliding_image_offset_and_velocity_jump() {
        let b = bx();
        let mut le = LeesEdwards::new(0.5);
        le.advance(&b, 1.5); // offset = γ̇ L_y t = 0.5 · 4 · 1.5 = 3
        assert_eq!(le.offset, 3.0);
        assert_eq!(le.jump(&b), 2.0);
        // i near the top, j near the bottom: j's nearest image is the one at +L_y, displaced
        // by +3 in x and moving with +2 in x.
        let ri = [1.0, 1.8, 1.0];
        let rj = [4.2, -1.9, 1.0];
        let d = [ri[0] - rj[0], ri[1] - rj[1], ri[2] - rj[2]];
        let (m, dv) = b.min_image_le(d, &le);
        let image_j = [rj[0] + 3.0, rj[1] + 4.0, rj[2]];
        let want = b.min_image([ri[0] - image_j[0], ri[1] - image_j[1], 0.0]);
        assert!(
            (m[0] - want[0]).abs() < 1e-12 && (m[1] - want[1]).abs() < 1e-12,
            "{m:?}"
        );
        assert!((m[1] - -0.3).abs() < 1e-12);
        assert_eq!(dv, -2.0, "v_ij = v_i - (v_j + 2)");
    }

    #[test]
    fn antisymmetric_to_the_last_bit() {
        let b = bx();
        let mut le = LeesEdwards::new(0.37);
        le.advance(&b, 2.71);
        let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..10_000 {
            let mut d = [0.0; 3];
            for c in d.iter_mut() {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                *c = (s % 2_000_000) as f64 / 100_000.0 - 10.0;
            }
            let (a, dva) = b.min_image_le(d, &le);
            let (m, dvm) = b.min_image_le([-d[0], -d[1], -d[2]], &le);
            assert_eq!([-a[0], -a[1], -a[2]], m, "{d:?}");
            assert_eq!(-dva, dvm);
            assert!(a[0].abs() <= 3.0 + 1e-12 && a[1].abs() <= 2.0 + 1e-12);
        }
    }

    #[test]
    fn wrapping_keeps_lammps_unwrapped_position() {
        // LAMMPS's unwrapped x + ix L_x + iy xy (tilt xy, offset = xy mod L_x) is kept by every
        // wrap, through y (by the offset) and x, for tilts of either sign and beyond L_x.
        let b = bx();
        for xy in [1.3, -2.2, 7.9, -13.1] {
            let mut le = LeesEdwards::new(0.4);
            le.offset = f64::rem_euclid(xy, 6.0);
            le.tilt_cells = ((le.offset - xy) / 6.0).round();
            for x0 in [
                [6.7, 2.4, 1.0],
                [-0.3, -2.5, 5.2],
                [3.0, -6.1, -0.4],
                [11.9, 5.9, 2.0],
            ] {
                let (mut x, mut v, mut im) = (x0, [0.0; 3], [2, -1, 0]);
                let u0 = b.unwrap_tilted(x, im, xy);
                b.wrap_le(&mut x, &mut v, &mut im, &le);
                let u1 = b.unwrap_tilted(x, im, xy);
                for k in 0..3 {
                    assert!(
                        (u0[k] - u1[k]).abs() < 1e-12,
                        "xy {xy} {x0:?}: {u0:?} vs {u1:?}"
                    );
                }
                assert!(
                    (0.0..6.0).contains(&x[0]) && (-2.0..2.0).contains(&x[1]),
                    "{x:?}"
                );
            }
        }
    }

    #[test]
    fn wrapping_keeps_pair_geometry_and_relative_velocity() {
        // An atom leaving through the top re-enters at the bottom shifted by −offset, with
        // v_x − γ̇L_y: its separation and relative velocity to any other atom are unchanged.
        let b = bx();
        let mut le = LeesEdwards::new(0.8);
        le.advance(&b, 0.9);
        let (mut x, mut v, mut im) = ([5.5, 2.3, 4.9], [0.2, 0.1, -0.3], [0; 3]);
        let (xj, vj) = ([1.0, 1.5, 0.5], [0.0, 0.0, 0.0]);
        let sep = |x: [f64; 3], v: [f64; 3]| {
            let (d, dv) = b.min_image_le([x[0] - xj[0], x[1] - xj[1], x[2] - xj[2]], &le);
            (d, v[0] - vj[0] + dv)
        };
        let (d0, w0) = sep(x, v);
        b.wrap_le(&mut x, &mut v, &mut im, &le);
        assert!((b.lo[1]..b.hi[1]).contains(&x[1]) && (0.0..6.0).contains(&x[0]));
        assert_eq!(im[1], 1);
        let (d1, w1) = sep(x, v);
        for k in 0..3 {
            assert!((d0[k] - d1[k]).abs() < 1e-12, "{d0:?} vs {d1:?}");
        }
        assert!((w0 - w1).abs() < 1e-12, "{w0} vs {w1}");
    }

    #[test]
    fn wrap_le_returns_the_crossings_of_y_crossings() {
        // The flip's leak count reads wrap_le's answer: the same n as LAMMPS's count, also at
        // the round-off point just below lo, which lands on hi.
        let b = bx();
        let le = LeesEdwards::new(0.5);
        let below = -2.0 - f64::EPSILON;
        for y in [
            0.3,
            2.0,
            2.1,
            5.9,
            6.0,
            -2.0,
            -2.1,
            -6.5,
            13.7,
            below,
            1e300,
            f64::NAN,
        ] {
            let (mut x, mut v, mut im) = ([1.0, y, 1.0], [0.0; 3], [0; 3]);
            let n = b.wrap_le(&mut x, &mut v, &mut im, &le);
            let want = crate::engine::lees_edwards::y_crossings(y, -2.0, 2.0, 4.0);
            assert_eq!(n, want, "y = {y}");
        }
    }
}
