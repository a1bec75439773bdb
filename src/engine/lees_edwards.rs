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
//! (L_y at the run's start; formed from the run's length, [`Triclinic::start_run`]), and with
//! `remap v` an atom crossing y_hi (y_lo) has v_x changed by −h_rate_xy (+h_rate_xy), the
//! velocity of the image it becomes; ghost (image) velocities carry the same jump. The shear
//! rate is γ̇ = ∂v_x/∂y = R.
//!
//! The default, [`DeformOrder::Lammps`], is LAMMPS's `Verlet` step: integrate, rebuild the
//! lists if due (LAMMPS's rule, [`crate::engine::System`]: a pending flip, or an atom moved more
//! than ½(skin − Δ1 − Δ2), Δ the box corners' displacements; atoms are wrapped, with the velocity
//! jump, only then), forces, final integration, and `fix deform`'s `end_of_step`
//! ([`Triclinic::end_of_step`]: the new tilt on multiples of N, a flip decided when
//! |xy| > L_x/2 and done at the next step's rebuild, [`Triclinic::take_flip`]). So the forces
//! of step n see the box of step n − 1, as in LAMMPS. `order current` (standalone only) keeps
//! the former order: the forces of step n in the box of step n, atoms wrapped at every step,
//! flips only in the reported tilt.
//!
//! Pair forces (`neighbor/`, the same slab-parallel list as a periodic box): every pair uses
//! the Lees–Edwards minimum image r_ij and v_ij = v_i − v_j + Δv (Δv = −n_y γ̇ L_y e_x when the
//! nearest image of j lies n_y boxes away along y: `docs/models.md` §0 and P-5, the boundary
//! velocity jump included in v_ij), with the same kernel and the same keyed Gaussians (seed,
//! step, tags) as a periodic box. The list's rows through the y boundary are found with the
//! offset of its build (`neighbor/build.rs`, `RowBuild::x_runs`). Pairs whose raw separation
//! crosses no boundary see raw separations and velocities; the others get the current offset
//! and jump (`neighbor/slab.rs`, far pass). Same bits for any thread count, F_ji = −F_ij
//! exactly. Image flags follow LAMMPS's convention (the unwrapped x is x + ix L_x + iy xy).

use super::domain::{LeesEdwards, SimBox};

/// When the box of a `fix deform` changes relative to the force computation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeformOrder {
    /// LAMMPS's order (the default): the tilt changes in `end_of_step`, after the step's forces,
    /// so the forces of step n see the box of step n − 1; atoms are wrapped (with the velocity
    /// jump) only when the neighbour lists are rebuilt, by LAMMPS's rule; flips as LAMMPS.
    Lammps,
    /// `order current` (standalone only): the forces of step n see the box of step n, atoms are
    /// wrapped at every step, the lists keep a tilt allowance; a flip only changes the
    /// reported tilt.
    Current,
}

/// `fix ID all deform N xy erate R remap v [flip yes|no] [order lammps|current]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Deform {
    /// Fix id.
    pub id: String,
    /// Box update interval N (the tilt changes on steps that are multiples of N).
    pub every: u64,
    /// Engineering shear strain rate R (1/time): the tilt changes at R · L_y, γ̇ = R.
    pub erate: f64,
    /// `flip yes|no`: whether the box flips when |xy| exceeds L_x/2.
    pub flip: bool,
    /// LAMMPS's order (default) or the box of the current step.
    pub order: DeformOrder,
    /// Step at which the current run started (LAMMPS's `beginstep`).
    start_step: u64,
    /// Last step of the current run (LAMMPS's `endstep`).
    end_step: u64,
    /// Tilt at that step (LAMMPS's `tilt_start`).
    start_xy: f64,
    /// Tilt at the run's end if it did not flip (LAMMPS's `tilt_stop`).
    stop_xy: f64,
    /// Rate of change of the tilt, h_rate_xy = (tilt_stop − tilt_start)/(run time) (LAMMPS's
    /// `h_rate[5]`): the velocity jump of `remap v` and the streaming velocity's scale.
    h_rate: f64,
    /// A flip decided at the end of a step, done at the next step's rebuild: the new tilt and
    /// LAMMPS's `flipxy` (−1 or +1).
    pending_flip: Option<(f64, i32)>,
}

impl Deform {
    /// A deformation that starts with the next run.
    pub fn new(id: String, every: u64, erate: f64, flip: bool) -> Deform {
        Deform {
            id,
            every,
            erate,
            flip,
            order: DeformOrder::Lammps,
            start_step: 0,
            end_step: 0,
            start_xy: 0.0,
            stop_xy: 0.0,
            h_rate: 0.0,
            pending_flip: None,
        }
    }

    /// LAMMPS's h_rate_xy of the current run (see [`Deform::new`]'s fields).
    pub fn h_rate(&self) -> f64 {
        self.h_rate
    }
}

/// The triclinic (tilted in xy) state of a box.
#[derive(Clone, Debug, PartialEq)]
pub struct Triclinic {
    /// The tilt factor xy: with LAMMPS's order the box's tilt as LAMMPS has it (flipped when
    /// it flips); with `order current` unflipped (continuous in time).
    pub xy: f64,
    /// The deformation, if a `fix deform` is defined.
    pub deform: Option<Deform>,
    /// The sliding-brick state of the current step: rate γ̇ and offset xy mod L_x.
    pub le: LeesEdwards,
    /// `fix ID all flip/momentum [mode jump|check]`, if defined: Some(true) (`mode jump`) gives
    /// atoms put through y at a flip `remap v`'s velocity jump, so the momentum relative to the
    /// shear profile is conserved (LAMMPS's `fix deform` alone leaves their velocities alone
    /// and leaks it: issue 41, `docs/manual/styles/fix_flip_momentum.md`); Some(false)
    /// (`mode check`) only counts, as the engine does without the fix.
    pub flip_fix: Option<bool>,
    /// What this run's flips did to atoms put through y (counted with or without the fix).
    pub leak: FlipLeak,
}

/// The atoms that box flips put through the y boundary during a run, and the x momentum
/// relative to the shear profile that they changed: each such atom, put through without the
/// velocity jump, changes Σ m (v_x − γ̇ y) by m n_y h_rate_xy (n_y its crossings).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlipLeak {
    /// Atoms put through y at flips.
    pub atoms: u64,
    /// Σ m n_y h_rate_xy over them: the momentum leaked when no jump is applied (0 with
    /// `fix flip/momentum`, which applies it).
    pub momentum: f64,
    /// True when the jump was applied (`fix flip/momentum`).
    pub conserved: bool,
}

/// The y crossings an atom at `y` needs to be in [lo, hi) of a box of length `len` along y, as
/// LAMMPS's `Domain::remap`/`pbc` count them: n = ⌊(y − lo)/len⌋, and one more if round-off
/// leaves y − n len at hi.
#[inline]
pub fn y_crossings(y: f64, lo: f64, hi: f64, len: f64) -> i32 {
    let n = ((y - lo) * (1.0 / len)).floor();
    if n == 0.0 {
        return 0;
    }
    let extra = i32::from(y - n * len >= hi);
    (n as i32).saturating_add(extra)
}

/// `fix flip/momentum` on one atom of a tilted box before a flip (the box of tilt `xy` that the
/// flip will change): an atom outside [lo, hi) along y is put through y by n lattice vectors
/// b = (xy, L_y, 0), and, with `jump`, its v_x changes by −n h_rate_xy, the jump `remap v`
/// gives an atom through y (LAMMPS's `Domain::pbc`), so v_x − γ̇ y is kept. Returns n. The
/// LAMMPS fix calls it (through the C ABI) on every owned atom of the deformed group at the
/// flip's step, before `fix deform`'s `pre_exchange` flips and remaps; the standalone engine's
/// flip does the same with its `wrap_le` (`System::flip_box`).
pub fn flip_wrap_y(
    x: &mut [f64; 3],
    v: &mut [f64; 3],
    lo: f64,
    hi: f64,
    xy: f64,
    h_rate_xy: f64,
    jump: bool,
) -> i32 {
    let len = hi - lo;
    let n = y_crossings(x[1], lo, hi, len);
    if n != 0 {
        let nf = f64::from(n);
        x[1] -= nf * len;
        x[0] -= nf * xy;
        if jump {
            v[0] -= nf * h_rate_xy;
        }
    }
    n
}

/// The word that starts the machine-readable line following each end-of-run text of the flips
/// ([`flip_jump_note`], [`flip_leak_warning`]): `flip_leak: atoms=N jump=1` with the velocity
/// jump, `flip_leak: atoms=N jump=0 momentum=P V=V` without it (P and V as the warning prints
/// them). `crate::io::lammps_log::flip_records` reads it back; LAMMPS may append
/// ` (file:line)` to it.
pub const FLIP_RECORD: &str = "flip_leak:";

/// The machine-readable line of [`FLIP_RECORD`]: `momentum_v` the warning's P and V, as printed.
fn flip_record(leak: &FlipLeak, momentum_v: Option<(&str, &str)>) -> String {
    let mut line = format!(
        "{FLIP_RECORD} atoms={} jump={}",
        leak.atoms,
        u8::from(momentum_v.is_none())
    );
    if let Some((p, v)) = momentum_v {
        line += &format!(" momentum={p} V={v}");
    }
    line
}

/// The end-of-run log lines of a run whose flips put atoms through y with the velocity jump
/// (`fix flip/momentum`, mode jump): the note, then its [`FLIP_RECORD`] line; None when none
/// was.
pub fn flip_jump_note(leak: &FlipLeak) -> Option<String> {
    (leak.conserved && leak.atoms > 0).then(|| {
        format!(
            "fix flip/momentum: box flips put {} atom(s) through the y boundary, each with remap v's \
             velocity jump\n{}",
            leak.atoms,
            flip_record(leak, None)
        )
    })
}

/// The end-of-run warning of a run whose flips put atoms through y without the velocity jump
/// (plain `fix deform … remap v`, in LAMMPS and in the standalone engine alike); None when no
/// atom was or the jump was applied. `total_mass` turns the momentum into the mean velocity V
/// relative to the profile. The warning is followed by its [`FLIP_RECORD`] line.
pub fn flip_leak_warning(leak: &FlipLeak, total_mass: f64) -> Option<String> {
    if leak.atoms == 0 || leak.conserved {
        return None;
    }
    let dv = if total_mass > 0.0 {
        leak.momentum / total_mass
    } else {
        0.0
    };
    let (p, v) = (
        crate::fmtnum::fmt_g(leak.momentum),
        crate::fmtnum::fmt_g(dv),
    );
    Some(format!(
        "fix deform … remap v: box flips put {} atom(s) through the y boundary without remap v's \
         velocity jump (LAMMPS's fix deform does the same), so the total x momentum relative to \
         the shear profile changed by {p} (mean velocity V = {v}); temp/deform counts V²/2 as heat. \
         Add 'fix ID all flip/momentum' to apply the jump at flips too \
         (docs/manual/styles/fix_flip_momentum.md)\n{}",
        leak.atoms,
        flip_record(leak, Some((&p, &v))),
    ))
}

impl Triclinic {
    /// A box with tilt `xy` and no deformation.
    pub fn new(xy: f64) -> Triclinic {
        Triclinic {
            xy,
            deform: None,
            le: LeesEdwards::new(0.0),
            flip_fix: None,
            leak: FlipLeak::default(),
        }
    }

    /// True unless a `fix deform … order current` is defined.
    pub fn lammps_order(&self) -> bool {
        self.deform
            .as_ref()
            .is_none_or(|d| d.order == DeformOrder::Lammps)
    }

    /// The tilt as LAMMPS reports it. LAMMPS's order: the box's tilt. `order current`: with
    /// `flip yes` mapped into [−L_x/2, L_x/2], otherwise as it grew.
    pub fn reported_xy(&self, bx: &SimBox) -> f64 {
        let lx = bx.len()[0];
        match &self.deform {
            Some(d) if d.order == DeformOrder::Current && d.flip => {
                self.xy - lx * (self.xy / lx).round()
            }
            _ => self.xy,
        }
    }

    /// The streaming velocity u_x of `compute temp/deform` at height y: h_rate_xy · λ_y with
    /// λ_y = (y − y_lo)/L_y the fractional coordinate (LAMMPS `compute_temp_deform.cpp`:
    /// vstream = h_rate · λ + h_ratelo; h_ratelo_x = 0 for a tilt change; λ_y formed as
    /// LAMMPS's `x2lamda`, (1/L_y)·(y − y_lo)).
    #[inline]
    pub fn stream_x(&self, bx: &SimBox, y: f64) -> f64 {
        match &self.deform {
            Some(d) if d.order == DeformOrder::Lammps => {
                d.h_rate * ((1.0 / bx.len()[1]) * (y - bx.lo[1]))
            }
            _ => {
                let h_rate = self.le.rate * bx.len()[1];
                h_rate * (y - bx.lo[1]) / bx.len()[1]
            }
        }
    }

    /// Set the tilt (`order current` only), rate and offset for `step` (see the module notes).
    pub(crate) fn set_step(&mut self, bx: &SimBox, dt: f64, step: u64) {
        let [lx, ly, _] = bx.len();
        match &self.deform {
            Some(d) if d.order == DeformOrder::Current => {
                let every = d.every.max(1);
                // fix deform's end_of_step runs on multiples of N; the tilt is that of the latest.
                let m = (step - step % every).max(d.start_step);
                let elapsed = (m - d.start_step) as f64 * dt;
                self.xy = d.start_xy + d.erate * ly * elapsed;
                self.le.rate = d.erate;
            }
            // LAMMPS's order: the tilt is the box's, changed by `end_of_step`.
            Some(d) => self.le.rate = d.h_rate / ly,
            None => self.le.rate = 0.0,
        }
        let mut off = self.xy.rem_euclid(lx);
        if off >= lx {
            off = 0.0;
        }
        self.le.offset = off;
        // offset = xy + k L_x: an atom through y moves by the offset, its x image flag by k,
        // so x + ix L_x + iy xy (LAMMPS's unwrapped x) is kept.
        self.le.tilt_cells = ((off - self.xy) / lx).round();
    }

    /// Start of a run (`System::setup`) from `step` to `end` (None: not known, taken as one step
    /// on; the tilt is linear in the step either way): the deformation restarts from the
    /// current tilt, as LAMMPS's `fix deform` does at every run's `init`, with its
    /// `tilt_stop = tilt_start + Δt·R·L_y` and `h_rate = (tilt_stop − tilt_start)/Δt`, Δt the
    /// run's time (the same operations, so the same bits).
    pub fn start_run(&mut self, bx: &SimBox, dt: f64, step: u64, end: Option<u64>) {
        self.leak = FlipLeak::default();
        let xy = self.xy;
        let ly = bx.len()[1];
        if let Some(d) = self.deform.as_mut() {
            d.start_step = step;
            d.end_step = end.unwrap_or(step + 1).max(step);
            d.start_xy = xy;
            let delt = (d.end_step - d.start_step) as f64 * dt;
            d.stop_xy = d.start_xy + delt * d.erate * ly;
            d.h_rate = if delt != 0.0 {
                (d.stop_xy - d.start_xy) / delt
            } else {
                0.0
            };
        }
    }

    /// LAMMPS's `FixDeform::init` outside a run (as `write_data` calls it): LAMMPS's `run`
    /// leaves `beginstep = endstep = 0`, so the run's time is 0 and h_rate = 0 (the wrap that
    /// follows gives no velocity jump).
    pub(crate) fn init_outside_run(&mut self, bx: &SimBox, dt: f64, step: u64) {
        if self.lammps_order() {
            self.start_run(bx, dt, step, Some(step));
        }
    }

    /// LAMMPS's `FixDeform::end_of_step` at `step` (LAMMPS's order only; nothing on steps that
    /// are not a multiple of N): the new tilt tilt_start + δ (tilt_stop − tilt_start),
    /// δ = (step − begin)/(end − begin), moved by whole box lengths to the value nearest the
    /// current tilt, and, with `flip yes`, a flip decided when |xy| > L_x/2 (done by
    /// [`Triclinic::take_flip`] at the next step's rebuild, as LAMMPS's `pre_exchange`).
    pub fn end_of_step(&mut self, bx: &SimBox, step: u64) {
        let current_xy = self.xy;
        let Some(d) = self.deform.as_mut() else {
            return;
        };
        if d.order != DeformOrder::Lammps || !step.is_multiple_of(d.every.max(1)) {
            return;
        }
        let mut delta = step.saturating_sub(d.start_step) as f64;
        if delta != 0.0 {
            delta /= (d.end_step - d.start_step) as f64;
        }
        let mut target = d.start_xy + delta * (d.stop_xy - d.start_xy);
        // The nearest value to the current tilt, by LAMMPS's loops (the same operations,
        // subtracting and adding the box length, so the same bits).
        let denom = bx.hi[0] - bx.lo[0];
        let current = current_xy / denom;
        let mut guard = 0u32;
        while target / denom - current > 0.0 && guard < 1_000_000 {
            target -= denom;
            guard += 1;
        }
        while target / denom - current < 0.0 && guard < 2_000_000 {
            target += denom;
            guard += 1;
        }
        if (target / denom - 1.0 - current).abs() < (target / denom - current).abs() {
            target -= denom;
        }
        if d.flip {
            let xprd = bx.hi[0] - bx.lo[0];
            let xprdinv = 1.0 / xprd;
            if target * xprdinv < -0.5 || target * xprdinv > 0.5 {
                let mut tilt_flip = target;
                let mut flipxy = 0;
                if tilt_flip * xprdinv < -0.5 {
                    tilt_flip += xprd;
                    flipxy = 1;
                }
                if tilt_flip * xprdinv > 0.5 {
                    tilt_flip -= xprd;
                    flipxy = -1;
                }
                if flipxy != 0 {
                    d.pending_flip = Some((tilt_flip, flipxy));
                }
            }
        }
        self.xy = target;
    }

    /// True when a flip decided at the end of the last step waits for this step's rebuild.
    pub fn flip_pending(&self) -> bool {
        self.deform
            .as_ref()
            .is_some_and(|d| d.pending_flip.is_some())
    }

    /// Do a pending flip (LAMMPS's `FixDeform::pre_exchange`): the tilt becomes the flipped
    /// one; returns LAMMPS's `flipxy` (the x image flag of every atom changes by
    /// −flipxy · iy, `Domain::image_flip`), None without a flip.
    pub(crate) fn take_flip(&mut self) -> Option<i32> {
        let (xy, flipxy) = self.deform.as_mut()?.pending_flip.take()?;
        self.xy = xy;
        Some(flipxy)
    }
}
