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
//! Pair forces (`neighbor/`, the same slab-parallel list as a periodic box): every pair uses
//! the Lees–Edwards minimum image r_ij and v_ij = v_i − v_j + Δv (Δv = −n_y γ̇ L_y e_x when the
//! nearest image of j lies n_y boxes away along y: `docs/models.md` §0 and P-5, the boundary
//! velocity jump included in v_ij), with the same kernel and the same keyed Gaussians (seed,
//! step, tags) as a periodic box. The list's rows through the y boundary are found with the
//! offset of its build (`neighbor/build.rs`, `RowBuild::x_runs`); it is rebuilt when
//! 2·(largest displacement) + |xy − xy_build| exceeds the skin. Atoms are wrapped (x shifted by
//! the offset, v_x by the jump) at every step (`NeighborList::wrap_sheared`, the list kept;
//! LAMMPS wraps only at reneighbouring). Pairs whose raw separation crosses no boundary see raw
//! separations and velocities; the others get the current offset and jump
//! (`neighbor/slab.rs`, far pass). Same bits for any thread count, F_ji = −F_ij exactly.

use super::domain::{LeesEdwards, SimBox};

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
    pub(crate) fn set_step(&mut self, bx: &SimBox, dt: f64, step: u64) {
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
