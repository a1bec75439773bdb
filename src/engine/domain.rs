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
                image[k] += shift as i32;
                // Round-off can leave x == hi; LAMMPS maps that to lo.
                if x[k] >= self.hi[k] {
                    x[k] = self.lo[k];
                    image[k] += 1;
                }
            }
        }
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
