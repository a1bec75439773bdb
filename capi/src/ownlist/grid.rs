//! The bins of one build: their geometry over the atoms' bounding box, the stencil a row
//! visits, the atoms sorted into them, and which bins have a ghost within reach.

use super::passes::bin_atoms;
use super::sorted::Sorted;
use super::{BIN_FRACTION, Cloud};
use crate::team::Team;

/// The bins over the atoms' bounding box: side ≥ the list's reach (wider for a sparse cloud).
#[derive(Clone, Copy, Debug)]
pub(super) struct Geometry {
    dim: usize,
    lo: [f64; 3],
    /// Bins per axis.
    pub(super) nb: [usize; 3],
    width: [f64; 3],
    /// Bins within `reach` along each axis.
    reachb: [i64; 3],
    /// The largest row cut-off plus the margin.
    reach: f64,
}

impl Geometry {
    /// The bins for `nall` atoms in the box `lo`..`hi` (`dim` axes) and pairs within `reach`.
    pub(super) fn new(dim: usize, lo: [f64; 3], hi: [f64; 3], reach: f64, nall: usize) -> Self {
        let mut side = if reach > 0.0 {
            BIN_FRACTION * reach
        } else {
            1.0
        };
        let count = |s: f64| -> [usize; 3] {
            let mut n = [1usize; 3];
            for d in 0..dim {
                n[d] = (((hi[d] - lo[d]) / s).floor() as usize).clamp(1, 1 << 20);
            }
            n
        };
        // A sparse cloud (a huge box, a tiny cut-off) is given wider bins: at most
        // max(4 nall, 4096) of them, so a build stays linear in the atoms.
        let cap = (4 * nall).max(4096) as f64;
        let mut nb = count(side);
        while nb.iter().map(|&k| k as f64).product::<f64>() > cap {
            side *= 1.5;
            nb = count(side);
        }
        let mut width = [1.0f64; 3];
        let mut reachb = [0i64; 3];
        for d in 0..dim {
            width[d] = ((hi[d] - lo[d]) / nb[d] as f64).max(side);
            reachb[d] = (reach / width[d]).ceil() as i64;
        }
        Geometry {
            dim,
            lo,
            nb,
            width,
            reachb,
            reach,
        }
    }

    /// The number of bins.
    pub(super) fn nbins(&self) -> usize {
        self.nb[0] * self.nb[1] * self.nb[2]
    }

    /// The bin of position `p` (x fastest).
    pub(super) fn bin_of(&self, p: &[f64]) -> usize {
        let (lo, width, nb) = (&self.lo, &self.width, &self.nb);
        let mut b = 0usize;
        for d in (0..self.dim).rev() {
            let k = (((p[d] - lo[d]) / width[d]) as usize).min(nb[d] - 1);
            b = b * nb[d] + k;
        }
        b
    }

    /// The stencil: for each (y, z) bin offset whose nearest points can be within `reach`,
    /// the x offsets that can (a run of bins contiguous in bin order, x fastest).
    fn stencil(&self) -> Vec<(i64, i64, i64)> {
        let (dim, reach, width) = (self.dim, self.reach, self.width);
        let mut stencil: Vec<(i64, i64, i64)> = Vec::new();
        let r = |d: usize| if d < dim { self.reachb[d] } else { 0 };
        let gap = |o: i64, d: usize| {
            let g = (o.abs() - 1).max(0) as f64 * width[d];
            g * g
        };
        for oz in -r(2)..=r(2) {
            for oy in -r(1)..=r(1) {
                let g = gap(oy, 1) + if dim == 3 { gap(oz, 2) } else { 0.0 };
                if g >= reach * reach {
                    continue;
                }
                let ox = (0..=r(0))
                    .take_while(|&o| g + gap(o, 0) < reach * reach)
                    .last()
                    .unwrap_or(0);
                stencil.push((oy, oz, ox));
            }
        }
        stencil
    }
}

/// The bins of one build: the owned atoms and the ghosts, each in bin order.
#[derive(Debug, Default)]
pub(super) struct Grid {
    /// Bins per axis.
    pub(super) nb: [usize; 3],
    pub(super) own: Sorted,
    pub(super) ghost: Sorted,
    /// Each atom's bin.
    pub(super) bins: Vec<u32>,
    /// Each owned atom's place in `own`'s bin order.
    pub(super) pos: Vec<u32>,
    /// Whether a bin's stencil holds any ghost (most of a large rank's bins: none).
    pub(super) ghost_near: Vec<bool>,
    /// (y offset, z offset, largest x offset) of the bins a row visits.
    pub(super) stencil: Vec<(i64, i64, i64)>,
    /// (cut-off + margin)² of each type's row.
    pub(super) row_sq: Vec<f64>,
}

impl Grid {
    /// The grid of `geo` for the atoms of `c`, rows of type t reaching `row_sq[t]`.
    pub(super) fn fill(
        &mut self,
        c: &Cloud,
        geo: &Geometry,
        row_sq: Vec<f64>,
        team: Option<&Team>,
    ) {
        self.sort_atoms(c, geo, team);
        self.mark_ghost_near(geo);
        self.nb = geo.nb;
        self.stencil = geo.stencil();
        self.row_sq = row_sq;
    }

    /// Counting sorts by bin: the owned atoms, and the ghosts; each owned atom's place.
    fn sort_atoms(&mut self, c: &Cloud, geo: &Geometry, team: Option<&Team>) {
        let nall = c.ty.len();
        let nbins = geo.nbins();
        bin_atoms(c, geo, &mut self.bins, team);
        self.own.sort(0..c.nlocal, &self.bins, nbins, c, team);
        self.ghost.sort(c.nlocal..nall, &self.bins, nbins, c, team);
        self.pos.clear();
        self.pos.resize(c.nlocal, 0);
        for (k, &a) in self.own.order.iter().enumerate() {
            self.pos[a as usize] = k as u32;
        }
    }

    /// Which bins have a ghost within the stencil's reach (a box of ±reachb bins): from a
    /// summed-volume table of the ghosts per bin.
    fn mark_ghost_near(&mut self, geo: &Geometry) {
        let nb = geo.nb;
        self.ghost_near.clear();
        self.ghost_near.resize(geo.nbins(), false);
        let (px, py, pz) = (nb[0] + 1, nb[1] + 1, nb[2] + 1);
        let mut sat = vec![0u32; px * py * pz];
        let at = |x: usize, y: usize, z: usize| (z * py + y) * px + x;
        for z in 0..nb[2] {
            for y in 0..nb[1] {
                for x in 0..nb[0] {
                    let b = (z * nb[1] + y) * nb[0] + x;
                    let here = self.ghost.start[b + 1] - self.ghost.start[b];
                    sat[at(x + 1, y + 1, z + 1)] = here
                        + sat[at(x, y + 1, z + 1)]
                        + sat[at(x + 1, y, z + 1)]
                        + sat[at(x + 1, y + 1, z)]
                        + sat[at(x, y, z)]
                        - sat[at(x, y, z + 1)]
                        - sat[at(x, y + 1, z)]
                        - sat[at(x + 1, y, z)];
                }
            }
        }
        let r = |d: usize| {
            if d < geo.dim {
                geo.reachb[d] as usize
            } else {
                0
            }
        };
        for z in 0..nb[2] {
            let (z0, z1) = (z.saturating_sub(r(2)), (z + r(2) + 1).min(nb[2]));
            for y in 0..nb[1] {
                let (y0, y1) = (y.saturating_sub(r(1)), (y + r(1) + 1).min(nb[1]));
                for x in 0..nb[0] {
                    let (x0, x1) = (x.saturating_sub(r(0)), (x + r(0) + 1).min(nb[0]));
                    let sum = (sat[at(x1, y1, z1)] as i64)
                        - sat[at(x0, y1, z1)] as i64
                        - sat[at(x1, y0, z1)] as i64
                        - sat[at(x1, y1, z0)] as i64
                        + sat[at(x0, y0, z1)] as i64
                        + sat[at(x0, y1, z0)] as i64
                        + sat[at(x1, y0, z0)] as i64
                        - sat[at(x0, y0, z0)] as i64;
                    self.ghost_near[(z * nb[1] + y) * nb[0] + x] = sum > 0;
                }
            }
        }
    }
}
