//! The state updates of this project's fixes, for both engines: the Euler step of
//! `fix nve/euler` (docs/models.md P-2, FS-1–2) and the modified PeX push of `fix pex/push`
//! (docs/models.md P-6; ties, empty slabs and MPI: docs/fixes.md).
//! The standalone engine calls them on its arrays; the LAMMPS fixes call them through the C ABI
//! on one MPI rank's atoms and only do the MPI reductions themselves.

/// The Euler update of one atom from the state at t (docs/models.md P-2, FS-1–2):
/// x += δt v(t), then v += (δt/m) F(t). `dtfm` is δt·ftm2v / m, formed by the caller as LAMMPS
/// does (a division by the mass).
#[inline]
pub fn euler_update(x: &mut [f64; 3], v: &mut [f64; 3], f: &[f64; 3], dtv: f64, dtfm: f64) {
    for k in 0..3 {
        x[k] += dtv * v[k]; // uses v(t): updated below
        v[k] += dtfm * f[k];
    }
}

/// The two slabs of a PeX push along x: centred at xlo + Lx/4 (slab 1, where the slowest v_z
/// is picked) and xlo + 3Lx/4 (slab 2, the fastest), of width `w`.
#[derive(Clone, Copy, Debug)]
pub struct PexSlabs {
    lo: f64,
    hi: f64,
    lx: f64,
    c1: f64,
    c2: f64,
    half_w: f64,
}

/// Which slab an atom is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slab {
    /// Slab 1 (slowest v_z donates).
    Slow,
    /// Slab 2 (fastest v_z donates).
    Fast,
}

impl PexSlabs {
    /// Slabs of width `w` in a box spanning `lo..hi` along x.
    pub fn new(lo: f64, hi: f64, w: f64) -> PexSlabs {
        let lx = hi - lo;
        PexSlabs {
            lo,
            hi,
            lx,
            c1: lo + 0.25 * lx,
            c2: lo + 0.75 * lx,
            half_w: 0.5 * w,
        }
    }

    /// The slab of an atom at x (wrapped once into [lo, hi): atoms leave the box by less than
    /// one length between neighbour-list builds). An atom is in a slab when |x − c| < W/2.
    #[inline]
    pub fn of(&self, x: f64) -> Option<Slab> {
        let xw = if x < self.lo {
            x + self.lx
        } else if x >= self.hi {
            x - self.lx
        } else {
            x
        };
        if (xw - self.c1).abs() < self.half_w {
            Some(Slab::Slow)
        } else if (xw - self.c2).abs() < self.half_w {
            Some(Slab::Fast)
        } else {
            None
        }
    }
}

/// The atoms a push exchanges, as (v_z, tag): the slowest of slab 1 and the fastest of slab 2,
/// ties broken by the lowest tag. `None` when a slab is empty. This is the reduction MPI's
/// MINLOC/MAXLOC computes over ranks, so a rank's pick combines with the others' exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PexPick {
    /// Slowest v_z in slab 1 and its tag.
    pub slow: Option<(f64, u32)>,
    /// Fastest v_z in slab 2 and its tag.
    pub fast: Option<(f64, u32)>,
}

impl PexPick {
    /// Consider one atom.
    #[inline]
    pub fn offer(&mut self, slab: Slab, vz: f64, tag: u32) {
        match slab {
            Slab::Slow => {
                if self
                    .slow
                    .is_none_or(|(v0, t0)| vz < v0 || (vz == v0 && tag < t0))
                {
                    self.slow = Some((vz, tag));
                }
            }
            Slab::Fast => {
                if self
                    .fast
                    .is_none_or(|(v0, t0)| vz > v0 || (vz == v0 && tag < t0))
                {
                    self.fast = Some((vz, tag));
                }
            }
        }
    }

    /// The pick over atoms `x`, `v`, `tag` for which `member(i)` holds.
    pub fn select(
        slabs: &PexSlabs,
        x: &[[f64; 3]],
        v: &[[f64; 3]],
        tag: &[u32],
        member: impl Fn(usize) -> bool,
    ) -> PexPick {
        let mut p = PexPick::default();
        for i in 0..x.len() {
            if member(i)
                && let Some(s) = slabs.of(x[i][0])
            {
                p.offer(s, v[i][2], tag[i]);
            }
        }
        p
    }
}

/// The momentum exchange itself, for the atoms of tags `slow` and `fast` (both present
/// somewhere): v_z += dp/m on the slow atom, −= dp/m on the fast one, for each local atom `i`
/// whose tag matches (`mass(i)` its mass).
pub fn pex_apply(
    v: &mut [[f64; 3]],
    tag: &[u32],
    mass: impl Fn(usize) -> f64,
    dp: f64,
    slow: u32,
    fast: u32,
) {
    for i in 0..v.len() {
        if tag[i] == slow {
            v[i][2] += dp / mass(i);
        }
        if tag[i] == fast {
            v[i][2] -= dp / mass(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slabs_and_ties() {
        let s = PexSlabs::new(0.0, 4.0, 0.4);
        assert_eq!(s.of(1.0), Some(Slab::Slow));
        assert_eq!(s.of(3.1), Some(Slab::Fast));
        assert_eq!(s.of(-1.0), Some(Slab::Fast)); // wrapped to 3.0
        assert_eq!(s.of(2.0), None);
        let x = [[1.0, 0.0, 0.0], [1.1, 0.0, 0.0], [3.0, 0.0, 0.0]];
        let v = [[0.0, 0.0, -1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 2.0]];
        let p = PexPick::select(&s, &x, &v, &[7, 3, 5], |_| true);
        assert_eq!(p.slow, Some((-1.0, 3)));
        assert_eq!(p.fast, Some((2.0, 5)));
        let mut v = v;
        pex_apply(&mut v, &[7, 3, 5], |_| 2.0, 0.5, 3, 5);
        assert_eq!(v[1][2], -0.75);
        assert_eq!(v[2][2], 1.75);
        assert_eq!(v[0][2], -1.0);
    }
}
