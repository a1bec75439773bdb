//! Cell-sorted half neighbour list and the deterministic pair-force evaluation.
//!
//! Determinism for any thread count: atoms are cut into fixed blocks of [`BLOCK_ATOMS`]
//! (independent of the thread count). Each block owns the rows (half list, j > i) of its atoms
//! and a buffer with one force per listed pair. Phase 1 evaluates every pair once, block by block
//! in parallel, writing F_ij into the pair's slot. Phase 2 gathers, for each atom, `+F_ij` over its
//! own row in list order and then `−F_ij` over the pairs where it is the j (a reverse index built
//! with the list, in increasing pair order). Every sum therefore has a fixed order, whatever
//! thread runs it. Energy and virial are summed per block in row order, then over blocks in order.

use super::atoms::Atoms;
use super::domain::SimBox;
use super::forcefield::ForceField;
use crate::kernel::{PairCoeff, PairInput, pair_force};
use crate::rng::pair_gaussian;
use rayon::prelude::*;

/// The linear index of cell coordinates (x fastest).
#[inline]
fn cell_id(c: [usize; 3], ncell: [usize; 3]) -> usize {
    (c[2] * ncell[1] + c[1]) * ncell[0] + c[0]
}

/// Atoms per block: the unit of parallel work and of the fixed summation order.
pub const BLOCK_ATOMS: usize = 256;

#[derive(Clone, Debug, Default)]
struct Block {
    start: usize,
    end: usize,
    row_start: Vec<u32>,
    nbr: Vec<u32>,
    pair_f: Vec<[f64; 3]>,
    virial: [f64; 6],
    energy: f64,
}

/// Energy and virial of one force evaluation (sums over pairs, not normalised).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairTally {
    /// Σ conservative pair energy.
    pub energy: f64,
    /// Σ_{pairs} r_ij,a F_ij,b in LAMMPS order xx, yy, zz, xy, xz, yz (all force parts).
    pub virial: [f64; 6],
}

/// The neighbour list with its cell sort and force buffers. Buffers are reused between builds, so
/// the step loop does not allocate once they have reached their working size.
#[derive(Debug, Default)]
pub struct NeighborList {
    /// Skin distance added to the largest cut-off.
    pub skin: f64,
    /// Number of builds so far.
    pub builds: u64,
    blocks: Vec<Block>,
    rev_start: Vec<u32>,
    rev: Vec<(u32, u32)>,
    x_at_build: Vec<[f64; 3]>,
    cell_of: Vec<u32>,
    cell_count: Vec<u32>,
    cell_start: Vec<u32>,
    perm: Vec<u32>,
    scratch: Atoms,
    ncell: [usize; 3],
    stencil_axes: [Vec<Vec<usize>>; 3],
}

impl NeighborList {
    /// An empty list with the given skin.
    pub fn new(skin: f64) -> NeighborList {
        NeighborList {
            skin,
            ..Default::default()
        }
    }

    /// True when some atom moved more than half the skin since the last build (or never built).
    pub fn needs_rebuild(&self, atoms: &Atoms) -> bool {
        if self.x_at_build.len() != atoms.len() || self.builds == 0 {
            return true;
        }
        let limit = 0.25 * self.skin * self.skin;
        atoms
            .x
            .par_iter()
            .zip(self.x_at_build.par_iter())
            .any(|(x, x0)| {
                let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
            })
    }

    /// Number of pairs held in the list.
    pub fn pairs(&self) -> usize {
        self.blocks.iter().map(|b| b.nbr.len()).sum()
    }

    /// Bytes held by the list and its buffers (for the memory report).
    pub fn bytes(&self) -> usize {
        let blocks: usize = self
            .blocks
            .iter()
            .map(|b| b.row_start.capacity() * 4 + b.nbr.capacity() * 4 + b.pair_f.capacity() * 24)
            .sum();
        blocks
            + self.rev_start.capacity() * 4
            + self.rev.capacity() * 8
            + self.x_at_build.capacity() * 24
            + (self.cell_of.capacity() + self.perm.capacity()) * 4
            + (self.cell_count.capacity() + self.cell_start.capacity()) * 4
    }

    /// Wrap positions into the box, sort atoms by cell, and build the half list with cut-off
    /// `rc_max + skin`. Atom order changes; tags travel with the atoms.
    pub fn build(&mut self, atoms: &mut Atoms, bx: &SimBox, rc_max: f64) {
        let n = atoms.len();
        for (x, im) in atoms.x.iter_mut().zip(atoms.image.iter_mut()) {
            bx.wrap(x, im);
        }
        let cutoff = rc_max + self.skin;
        let len = bx.len();
        let mut ncell = [1usize; 3];
        for d in 0..bx.dim {
            ncell[d] = ((len[d] / cutoff).floor() as usize).max(1);
        }
        if ncell != self.ncell {
            self.ncell = ncell;
            for d in 0..3 {
                let m = ncell[d];
                self.stencil_axes[d] = (0..m)
                    .map(|c| {
                        if m >= 3 {
                            vec![(c + m - 1) % m, c, (c + 1) % m]
                        } else {
                            (0..m).collect()
                        }
                    })
                    .collect();
            }
        }
        let total_cells = ncell[0] * ncell[1] * ncell[2];
        let cell_coords = |x: &[f64; 3]| -> [usize; 3] {
            let mut c = [0usize; 3];
            for d in 0..bx.dim {
                let f = ((x[d] - bx.lo[d]) / len[d] * ncell[d] as f64).floor();
                c[d] = (f.max(0.0) as usize).min(ncell[d] - 1);
            }
            c
        };
        let cell_index = |x: &[f64; 3]| -> u32 { cell_id(cell_coords(x), ncell) as u32 };
        // Counting sort by cell, stable in the current order.
        self.cell_of.clear();
        self.cell_of.extend(atoms.x.iter().map(cell_index));
        self.cell_count.clear();
        self.cell_count.resize(total_cells + 1, 0);
        for &c in &self.cell_of {
            self.cell_count[c as usize + 1] += 1;
        }
        for c in 0..total_cells {
            self.cell_count[c + 1] += self.cell_count[c];
        }
        self.cell_start.clear();
        self.cell_start.extend_from_slice(&self.cell_count);
        self.perm.clear();
        self.perm.resize(n, 0);
        for (i, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut self.cell_count[c as usize];
            self.perm[*slot as usize] = i as u32;
            *slot += 1;
        }
        atoms.permute(&self.perm, &mut self.scratch);

        // Rows, block by block (each block independent: parallel and deterministic).
        let nblocks = n.div_ceil(BLOCK_ATOMS);
        self.blocks.resize_with(nblocks, Block::default);
        let cutsq = cutoff * cutoff;
        let x = &atoms.x;
        let cell_start = &self.cell_start;
        let axes = &self.stencil_axes;
        self.blocks.par_iter_mut().enumerate().for_each(|(b, blk)| {
            blk.start = b * BLOCK_ATOMS;
            blk.end = ((b + 1) * BLOCK_ATOMS).min(n);
            blk.row_start.clear();
            blk.nbr.clear();
            blk.row_start.push(0);
            for i in blk.start..blk.end {
                let xi = x[i];
                let c = cell_coords(&xi);
                for &cz in &axes[2][c[2]] {
                    for &cy in &axes[1][c[1]] {
                        for &cx in &axes[0][c[0]] {
                            let cell = cell_id([cx, cy, cz], ncell);
                            let lo = (cell_start[cell] as usize).max(i + 1);
                            let hi = cell_start[cell + 1] as usize;
                            for (j, xj) in x.iter().enumerate().take(hi).skip(lo) {
                                let d = bx.min_image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                                if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutsq {
                                    blk.nbr.push(j as u32);
                                }
                            }
                        }
                    }
                }
                blk.row_start.push(blk.nbr.len() as u32);
            }
            blk.pair_f.clear();
            blk.pair_f.resize(blk.nbr.len(), [0.0; 3]);
        });

        // Reverse index: for each atom j, the (block, slot) of the pairs where it is the j.
        self.rev_start.clear();
        self.rev_start.resize(n + 1, 0);
        for blk in &self.blocks {
            for &j in &blk.nbr {
                self.rev_start[j as usize + 1] += 1;
            }
        }
        for j in 0..n {
            self.rev_start[j + 1] += self.rev_start[j];
        }
        let total = self.rev_start[n] as usize;
        self.rev.clear();
        self.rev.resize(total, (0, 0));
        self.cell_count.clear();
        self.cell_count.extend_from_slice(&self.rev_start[..n]);
        for (b, blk) in self.blocks.iter().enumerate() {
            for (k, &j) in blk.nbr.iter().enumerate() {
                let slot = &mut self.cell_count[j as usize];
                self.rev[*slot as usize] = (b as u32, k as u32);
                *slot += 1;
            }
        }
        self.x_at_build.clear();
        self.x_at_build.extend_from_slice(&atoms.x);
        self.builds += 1;
    }

    /// Evaluate all pair forces at `step` (the noise key), overwrite `atoms.f`, and return the
    /// energy and virial. `inv_mass[t]` is 1/m of type t. Requires a current list.
    pub fn compute_forces(
        &mut self,
        atoms: &mut Atoms,
        bx: &SimBox,
        ff: &ForceField,
        table: &[PairCoeff],
        inv_mass: &[f64],
        step: u64,
    ) -> PairTally {
        let nt = ff.ntypes() + 1;
        let model = &ff.model;
        let seed = ff.seed;
        let (x, v, tag, typ) = (&atoms.x, &atoms.v, &atoms.tag, &atoms.typ);
        self.blocks.par_iter_mut().for_each(|blk| {
            let mut virial = [0.0; 6];
            let mut energy = 0.0;
            for i in blk.start..blk.end {
                let (xi, vi, ti) = (x[i], v[i], typ[i] as usize);
                let row = blk.row_start[i - blk.start] as usize
                    ..blk.row_start[i - blk.start + 1] as usize;
                for k in row {
                    let j = blk.nbr[k] as usize;
                    let dr = bx.min_image([xi[0] - x[j][0], xi[1] - x[j][1], xi[2] - x[j][2]]);
                    let c = &table[ti * nt + typ[j] as usize];
                    let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
                    if rsq >= c.rc * c.rc {
                        blk.pair_f[k] = [0.0; 3];
                        continue;
                    }
                    let input = PairInput {
                        dr,
                        dv: [vi[0] - v[j][0], vi[1] - v[j][1], vi[2] - v[j][2]],
                        inv_mass_sum: inv_mass[ti] + inv_mass[typ[j] as usize],
                        xi: pair_gaussian(seed, step, tag[i], tag[j]),
                    };
                    let pf = pair_force(model, c, &input);
                    let fv = pf.vector(dr);
                    blk.pair_f[k] = fv;
                    energy += pf.energy;
                    virial[0] += dr[0] * fv[0];
                    virial[1] += dr[1] * fv[1];
                    virial[2] += dr[2] * fv[2];
                    virial[3] += dr[0] * fv[1];
                    virial[4] += dr[0] * fv[2];
                    virial[5] += dr[1] * fv[2];
                }
            }
            blk.virial = virial;
            blk.energy = energy;
        });

        let blocks = &self.blocks;
        let (rev_start, rev) = (&self.rev_start, &self.rev);
        atoms
            .f
            .par_chunks_mut(BLOCK_ATOMS)
            .zip(blocks.par_iter())
            .for_each(|(fchunk, blk)| {
                for (li, fi) in fchunk.iter_mut().enumerate() {
                    let mut s = [0.0; 3];
                    let row = blk.row_start[li] as usize..blk.row_start[li + 1] as usize;
                    for p in &blk.pair_f[row] {
                        s[0] += p[0];
                        s[1] += p[1];
                        s[2] += p[2];
                    }
                    let i = blk.start + li;
                    for &(b, k) in &rev[rev_start[i] as usize..rev_start[i + 1] as usize] {
                        let p = blocks[b as usize].pair_f[k as usize];
                        s[0] -= p[0];
                        s[1] -= p[1];
                        s[2] -= p[2];
                    }
                    *fi = s;
                }
            });

        let mut tally = PairTally::default();
        for blk in blocks {
            tally.energy += blk.energy;
            for a in 0..6 {
                tally.virial[a] += blk.virial[a];
            }
        }
        tally
    }
}
