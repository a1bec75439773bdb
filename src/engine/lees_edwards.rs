//! Lees–Edwards boundaries in the standalone engine: the triclinic box of LAMMPS
//! (`region … prism`, `change_box all triclinic`) with `fix deform … xy erate R remap v`, in the
//! sliding-brick form (`docs/models.md` §4.3, P-5, and §3.5, Couette flow; weighting-function
//! paper §5).
//!
//! A periodic box with tilt xy has the lattice vectors a = (L_x, 0, 0), b = (xy, L_y, 0),
//! c = (0, 0, L_z). Positions are kept in the orthogonal box [lo, hi): the image at +L_y is
//! displaced by xy along x, and xy only matters modulo L_x, so the "sliding brick" offset is
//! `offset = xy mod L_x` ([`LeesEdwards`]). The same lattice as LAMMPS's, so the same physics;
//! the wrapped coordinates differ from LAMMPS's by lattice vectors only.
//!
//! Under `fix deform … xy erate R`, LAMMPS changes the tilt at the rate h_rate_xy = R · L_y
//! (L_y at the run's start), so xy(n) = xy_start + R L_y (n − n_start) δt, and with `remap v`
//! an atom crossing y_hi (y_lo) has v_x changed by −h_rate_xy (+h_rate_xy), the velocity of the
//! image it becomes; ghost (image) velocities carry the same jump. The shear rate is
//! γ̇ = ∂v_x/∂y = R. Here the offset used at step n is xy(n) mod L_x (LAMMPS computes the
//! forces of step n in the box of step n − 1, since `fix deform` changes the box at the end of
//! a step: a constant shift γ̇ L_y δt of the image lattice, the same flow).
//!
//! Pair forces: every pair uses the Lees–Edwards minimum image r_ij and
//! v_ij = v_i − v_j + Δv (Δv = −n_y γ̇ L_y e_x when the nearest image of j lies n_y boxes
//! away along y: `docs/models.md` §0 and P-5, the boundary velocity jump included in v_ij),
//! with the same kernel ([`crate::kernel::pair_forces_batch`], bit for bit
//! [`crate::kernel::pair_force`]) and the same keyed Gaussians (seed, step, tags) as the
//! periodic engine. The pair loop here is serial (deterministic for any thread count): a cell
//! list rebuilt every step whose cells across the sheared y boundary are found with the
//! current offset, each pair once (j > i in atom index), F_ji = −F_ij from one evaluation.

use super::atoms::Atoms;
use super::domain::{LeesEdwards, SimBox};
use super::forcefield::ForceField;
use super::neighbor::PairTally;
use super::pair::{Batcher, DpdKernel, PairKernel, lane_force};
use super::sdpd::SdpdField;
use crate::kernel::{self, Isa, PairBatch, PairCoeff, PairTable};

/// `fix ID all deform N xy erate R remap v [flip yes|no]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Deform {
    /// Fix id.
    pub id: String,
    /// Box update interval N (the tilt changes on steps that are multiples of N).
    pub every: u64,
    /// Engineering shear strain rate R (1/time): the tilt changes at R · L_y, γ̇ = R.
    pub erate: f64,
    /// `flip yes|no`: only the reported tilt (`xy`) depends on it; the lattice does not.
    pub flip: bool,
    /// Step at which the current run started (LAMMPS's `beginstep`).
    start_step: u64,
    /// Tilt at that step (LAMMPS's `tilt_start`, unflipped).
    start_xy: f64,
}

impl Deform {
    /// A deformation that starts with the next run.
    pub fn new(id: String, every: u64, erate: f64, flip: bool) -> Deform {
        Deform {
            id,
            every,
            erate,
            flip,
            start_step: 0,
            start_xy: 0.0,
        }
    }
}

/// The triclinic (tilted in xy) state of a box.
#[derive(Clone, Debug, PartialEq)]
pub struct Triclinic {
    /// The tilt factor xy, unflipped (continuous in time).
    pub xy: f64,
    /// The deformation, if a `fix deform` is defined.
    pub deform: Option<Deform>,
    /// The sliding-brick state of the current step: rate γ̇ and offset xy mod L_x.
    pub le: LeesEdwards,
}

impl Triclinic {
    /// A box with tilt `xy` and no deformation.
    pub fn new(xy: f64) -> Triclinic {
        Triclinic {
            xy,
            deform: None,
            le: LeesEdwards::new(0.0),
        }
    }

    /// The tilt as LAMMPS reports it: with `flip yes` mapped into [−L_x/2, L_x/2] (LAMMPS flips
    /// the box by L_x when |xy| exceeds L_x/2), otherwise as it grew.
    pub fn reported_xy(&self, bx: &SimBox) -> f64 {
        let lx = bx.len()[0];
        match &self.deform {
            Some(d) if !d.flip => self.xy,
            _ => self.xy - lx * (self.xy / lx).round(),
        }
    }

    /// The streaming velocity u_x of `compute temp/deform` at height y: h_rate_xy · λ_y with
    /// λ_y = (y − y_lo)/L_y the fractional coordinate (LAMMPS `compute_temp_deform.cpp`:
    /// vstream = h_rate · λ + h_ratelo; h_ratelo_x = 0 for a tilt change).
    #[inline]
    pub fn stream_x(&self, bx: &SimBox, y: f64) -> f64 {
        let h_rate = self.le.rate * bx.len()[1];
        h_rate * (y - bx.lo[1]) / bx.len()[1]
    }

    /// Set the tilt, rate and offset for `step` (see the module notes).
    fn set_step(&mut self, bx: &SimBox, dt: f64, step: u64) {
        let [lx, ly, _] = bx.len();
        if let Some(d) = &self.deform {
            let every = d.every.max(1);
            // fix deform's end_of_step runs on multiples of N; the tilt is that of the latest.
            let m = (step - step % every).max(d.start_step);
            let elapsed = (m - d.start_step) as f64 * dt;
            self.xy = d.start_xy + d.erate * ly * elapsed;
            self.le.rate = d.erate;
        } else {
            self.le.rate = 0.0;
        }
        let mut off = self.xy.rem_euclid(lx);
        if off >= lx {
            off = 0.0;
        }
        self.le.offset = off;
    }
}

/// Work arrays of the Lees–Edwards pair loop (kept between steps: no allocation per step once
/// grown).
#[derive(Clone, Debug, Default)]
pub struct LeWork {
    ncell: [usize; 3],
    cell_of: Vec<u32>,
    cell_start: Vec<u32>,
    cell_atoms: Vec<u32>,
    /// Per cell, its candidate neighbour cells (itself included), sorted and unique.
    stencil_start: Vec<u32>,
    stencil: Vec<u32>,
    batcher: Batcher,
}

impl Triclinic {
    /// Start of a run (`System::setup`): the deformation restarts from `step` and the current
    /// tilt, as LAMMPS's `fix deform` does at every run's `init`.
    pub fn start_run(&mut self, step: u64) {
        let xy = self.xy;
        if let Some(d) = self.deform.as_mut() {
            d.start_step = step;
            d.start_xy = xy;
        }
    }
}

impl LeWork {
    /// Wrap every atom into the box under Lees–Edwards (x shifted by the offset and v_x by
    /// the velocity jump on a y crossing, [`SimBox::wrap_le`]) and evaluate all pair forces
    /// at `self.step` with the Lees–Edwards minimum image and velocity jump.
    #[allow(clippy::too_many_arguments)]
    pub fn compute_forces(
        &mut self,
        tri: &mut Triclinic,
        bx: &SimBox,
        a: &mut Atoms,
        ff: &ForceField,
        coeffs: &[PairCoeff],
        inv_mass: &[f64],
        dt: f64,
        step: u64,
    ) -> PairTally {
        let le = self.prepare(tri, bx, a, ff.rc_max(), dt, step);
        let table = PairTable::new(&ff.model, coeffs);
        let kernel = DpdKernel {
            model: &ff.model,
            table: &table,
            seed: ff.seed,
            isa: Isa::detect(),
        };
        let rcsq: Vec<f64> = coeffs.iter().map(|c| c.rc * c.rc).collect();
        self.force_pass(bx, &le, a, &kernel, &rcsq, ff.ntypes() + 1, inv_mass, step)
    }

    /// `pair_style sdpd` under Lees–Edwards: the wrap and cells of [`LeWork::compute_forces`],
    /// the density pass over the same pairs, then the force pass with [`SdpdField::kernel`].
    #[allow(clippy::too_many_arguments)]
    pub fn compute_sdpd(
        &mut self,
        tri: &mut Triclinic,
        bx: &SimBox,
        a: &mut Atoms,
        sd: &mut SdpdField,
        inv_mass: &[f64],
        dt: f64,
        step: u64,
    ) -> PairTally {
        let le = self.prepare(tri, bx, a, sd.rc_max(), dt, step);
        let nt = sd.ntypes() + 1;
        let rcsq = sd.rcsq().to_vec();
        let mut dens = std::mem::take(&mut sd.density);
        dens.clear();
        dens.resize(a.len(), 0.0);
        self.for_each_pair(bx, &le, &a.x, &a.typ, nt, &rcsq, |i, j, dr, _, k| {
            let w = sd.w_pair(k, kernel::dot(dr, dr));
            dens[i] += w;
            dens[j] += w;
        });
        sd.density = dens;
        sd.finish_densities(&a.typ, &a.tag);
        let mut tally = self.force_pass(bx, &le, a, &sd.kernel(), &rcsq, nt, inv_mass, step);
        tally.energy += sd.energy;
        tally
    }

    /// Set the tilt of `step`, wrap the atoms and sort them into cells of side ≥ `rc_max`.
    fn prepare(
        &mut self,
        tri: &mut Triclinic,
        bx: &SimBox,
        a: &mut Atoms,
        rc_max: f64,
        dt: f64,
        step: u64,
    ) -> LeesEdwards {
        tri.set_step(bx, dt, step);
        let le = tri.le;
        for ((x, v), im) in a.x.iter_mut().zip(a.v.iter_mut()).zip(a.image.iter_mut()) {
            bx.wrap_le(x, v, im, &le);
        }
        build_cells(self, bx, &le, &a.x, rc_max);
        le
    }

    /// Every pair (i, j > i) within the cut-off of its type pair, once, in a fixed order:
    /// `visit(i, j, r_ij, Δv_x, k)` with the Lees–Edwards minimum image r_ij, the boundary
    /// velocity jump Δv_x to add to v_ij (domain.rs `min_image_le`) and the dense type-pair
    /// index k.
    #[allow(clippy::too_many_arguments)]
    fn for_each_pair(
        &self,
        bx: &SimBox,
        le: &LeesEdwards,
        x: &[[f64; 3]],
        typ: &[u32],
        nt: usize,
        rcsq: &[f64],
        mut visit: impl FnMut(usize, usize, [f64; 3], f64, usize),
    ) {
        let w = self;
        let ncells = w.cell_start.len() - 1;
        for c in 0..ncells {
            let (s0, s1) = (w.stencil_start[c] as usize, w.stencil_start[c + 1] as usize);
            for ia in w.cell_start[c]..w.cell_start[c + 1] {
                let i = w.cell_atoms[ia as usize] as usize;
                let (xi, ti) = (x[i], typ[i] as usize);
                for &cn in &w.stencil[s0..s1] {
                    let cn = cn as usize;
                    for ja in w.cell_start[cn]..w.cell_start[cn + 1] {
                        let j = w.cell_atoms[ja as usize] as usize;
                        if j <= i {
                            continue;
                        }
                        let k = ti * nt + typ[j] as usize;
                        let d = [xi[0] - x[j][0], xi[1] - x[j][1], xi[2] - x[j][2]];
                        let (dr, dvx) = bx.min_image_le(d, le);
                        let rsq = kernel::dot(dr, dr);
                        if !(rsq < rcsq[k]
                            && rsq >= kernel::MIN_PAIR_DISTANCE * kernel::MIN_PAIR_DISTANCE)
                        {
                            continue;
                        }
                        visit(i, j, dr, dvx, k);
                    }
                }
            }
        }
    }

    /// The pair forces of `kernel` over [`LeWork::for_each_pair`]'s pairs, into `a.f`.
    #[allow(clippy::too_many_arguments)]
    fn force_pass(
        &mut self,
        bx: &SimBox,
        le: &LeesEdwards,
        a: &mut Atoms,
        kernel: &dyn PairKernel,
        rcsq: &[f64],
        nt: usize,
        inv_mass: &[f64],
        step: u64,
    ) -> PairTally {
        for f in a.f.iter_mut() {
            *f = [0.0; 3];
        }
        let mut tally = PairTally::default();
        let (x, v, typ, tag) = (&a.x, &a.v, &a.typ, &a.tag);
        let f = &mut a.f;
        let mut bt = std::mem::take(&mut self.batcher);
        // f_i += F, f_j −= F, W_ab += r_a F_b: the same operations as the periodic engine's
        // `neighbor::flush`.
        let mut apply = |b: &PairBatch, l: usize, i: usize, j: usize| {
            let (dr, fv) = lane_force(b, l);
            for q in 0..3 {
                f[i][q] += fv[q];
                f[j][q] -= fv[q];
            }
            tally.add_pair(dr, fv, b.energy[l]);
        };
        self.for_each_pair(bx, le, x, typ, nt, rcsq, |i, j, dr, dvx, k| {
            let (vi, vj) = (v[i], v[j]);
            let l = bt.lane();
            let b = &mut *bt.batch;
            for q in 0..3 {
                b.dr[q][l] = dr[q];
            }
            // v_ij with the boundary velocity jump (domain.rs `min_image_le`).
            b.dv[0][l] = vi[0] - vj[0] + dvx;
            b.dv[1][l] = vi[1] - vj[1];
            b.dv[2][l] = vi[2] - vj[2];
            b.inv_mass_sum[l] = inv_mass[typ[i] as usize] + inv_mass[typ[j] as usize];
            b.coeff[l] = k as u32;
            b.tag_i[l] = tag[i];
            b.tag_j[l] = tag[j];
            if bt.commit(i as u32, j as u32, true) {
                bt.flush(kernel, step, |_, _, _, _| {}, &mut apply);
            }
        });
        bt.flush(kernel, step, |_, _, _, _| {}, &mut apply);
        self.batcher = bt;
        tally
    }
}

/// Sort atoms into cells of side ≥ `rc` and, per cell, list every cell that can hold a partner
/// within `rc` under the current offset: the rows y ± 1 (z ± 1 in 3-D) with x ± 1, except that
/// a row reached through the y boundary is displaced by ∓offset along x, so its candidate
/// x cells are the four starting one below ⌊(x_cell − (±offset))/w⌋. A superset is enough: the
/// distance test uses the exact Lees–Edwards minimum image.
fn build_cells(w: &mut LeWork, bx: &SimBox, le: &LeesEdwards, x: &[[f64; 3]], rc: f64) {
    let len = bx.len();
    let nc = super::neighbor::cell_grid(len, bx.dim, rc, x.len());
    w.ncell = nc;
    let total = nc[0] * nc[1] * nc[2];
    let cw = [
        len[0] / nc[0] as f64,
        len[1] / nc[1] as f64,
        len[2] / nc[2] as f64,
    ];
    w.cell_of.clear();
    w.cell_start.clear();
    w.cell_start.resize(total + 1, 0);
    for p in x {
        let mut c = [0usize; 3];
        for d in 0..bx.dim {
            let q = ((p[d] - bx.lo[d]) / cw[d]).floor();
            c[d] = if q < 0.0 {
                0
            } else {
                (q as usize).min(nc[d] - 1)
            };
        }
        let id = (c[2] * nc[1] + c[1]) * nc[0] + c[0];
        w.cell_of.push(id as u32);
        w.cell_start[id + 1] += 1;
    }
    for k in 0..total {
        w.cell_start[k + 1] += w.cell_start[k];
    }
    w.cell_atoms.clear();
    w.cell_atoms.resize(x.len(), 0);
    let mut fill: Vec<u32> = w.cell_start[..total].to_vec();
    for (i, &c) in w.cell_of.iter().enumerate() {
        w.cell_atoms[fill[c as usize] as usize] = i as u32;
        fill[c as usize] += 1;
    }
    // Stencils.
    let wrap = |c: i64, m: usize| c.rem_euclid(m as i64) as usize;
    let near = |c: usize, m: usize| -> Vec<usize> {
        if m < 3 {
            (0..m).collect()
        } else {
            vec![wrap(c as i64 - 1, m), c, wrap(c as i64 + 1, m)]
        }
    };
    w.stencil_start.clear();
    w.stencil.clear();
    w.stencil_start.push(0);
    let mut cells: Vec<u32> = Vec::with_capacity(64);
    let zs: Vec<Vec<usize>> = (0..nc[2]).map(|cz| near(cz, nc[2])).collect();
    for cz in 0..nc[2] {
        for cy in 0..nc[1] {
            for cx in 0..nc[0] {
                cells.clear();
                for dy in -1i64..=1 {
                    let ry = cy as i64 + dy;
                    // n_y of the image the row is reached through (+1: above y_hi).
                    let ny = if ry >= nc[1] as i64 {
                        1
                    } else if ry < 0 {
                        -1
                    } else {
                        0
                    };
                    let row = wrap(ry, nc[1]);
                    let xs: Vec<usize> = if ny == 0 {
                        near(cx, nc[0])
                    } else if nc[0] < 4 {
                        (0..nc[0]).collect()
                    } else {
                        // Atoms of the row appear at x_j + n_y · offset: the partners of
                        // x_i ∈ [cx w, (cx+1) w) have x_j ∈ [cx w − n_y off − rc, (cx+1) w − n_y off + rc).
                        let base =
                            ((cx as f64 * cw[0] - ny as f64 * le.offset) / cw[0]).floor() as i64;
                        (base - 1..=base + 2).map(|k| wrap(k, nc[0])).collect()
                    };
                    for &z in &zs[cz] {
                        for &xc in &xs {
                            cells.push(((z * nc[1] + row) * nc[0] + xc) as u32);
                        }
                    }
                }
                cells.sort_unstable();
                cells.dedup();
                w.stencil.extend_from_slice(&cells);
                w.stencil_start.push(w.stencil.len() as u32);
            }
        }
    }
}
