//! The standalone engine: a periodic orthorhombic box in 2-D or 3-D, a cell-sorted half
//! neighbour list, the velocity-Verlet and Euler integrators, and the thermodynamic measurements
//! LAMMPS reports (same definitions, so one log parser and one diff read both engines).

pub mod atoms;
pub mod bonded;
pub mod domain;
pub mod fixes;
pub mod forcefield;
pub mod lees_edwards;
pub mod measure;
pub mod neighbor;
pub mod pair;
pub mod sdpd;
pub mod simd;
pub mod style;
pub mod topology;

pub use atoms::Atoms;
pub use domain::SimBox;
pub use forcefield::ForceField;
pub use neighbor::{NeighborList, PairTally};
pub use style::{PairStyle, SetupContext};
pub use topology::Topology;

use rayon::prelude::*;

/// Time integration scheme (`docs/models.md` §4.1, P-1 and P-2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// Velocity-Verlet as LAMMPS `fix nve`: half kick, drift, forces at the new step, half kick.
    VelocityVerlet,
    /// Euler (Hoogerbrugge–Koelman; finite-step paper eqs. 1–2): x += v δt and v += F/m δt from
    /// the state at t, then forces at the new state (`fix nve/euler`).
    Euler,
}

/// The modified PeX momentum push (`docs/models.md` §4.4, P-6;
/// `fix ID all pex/push dp [width W] [every N]`). Semantics mirror the LAMMPS fix (docs/fixes.md):
/// applied after the step's final integration.
#[derive(Clone, Debug, PartialEq)]
pub struct PexPush {
    /// Fix id (for `f_ID` in thermo).
    pub id: String,
    /// Momentum Δp_z moved per push.
    pub dp: f64,
    /// Slab width (None: the default of docs/fixes.md).
    pub width: Option<f64>,
    /// Push every N steps.
    pub every: u64,
    /// Accumulated momentum moved so far.
    pub total: f64,
}

/// Everything the engine integrates.
#[derive(Debug)]
pub struct System {
    /// The box.
    pub bx: SimBox,
    /// The atoms.
    pub atoms: Atoms,
    /// Number of atom types.
    pub ntypes: usize,
    /// Per-type masses (index 0 unused).
    pub mass: Vec<Option<f64>>,
    /// The pair style, once defined (`style.rs`: every style behind one trait).
    pub pair: Option<Box<dyn PairStyle>>,
    /// Neighbour list.
    pub neighbor: NeighborList,
    /// Time step.
    pub dt: f64,
    /// The unit style (`units`) and its constants: integrators, thermo and the pair styles'
    /// set-up take every conversion from it (`crate::units`).
    pub units: crate::units::Units,
    /// Current step (LAMMPS's `update->ntimestep`).
    pub step: u64,
    /// The integrator, if a `fix nve` or `fix nve/euler` is defined.
    pub integrator: Option<Integrator>,
    /// PeX pushes defined with `fix … pex/push`.
    pub pex: Vec<PexPush>,
    /// Energy and virial of the last force evaluation.
    pub tally: PairTally,
    /// What the last [`System::setup`] resolved or found worth a warning (the caller logs them).
    pub setup_notes: Vec<SetupNote>,
    /// The tilt and `fix deform` of a triclinic box (None: orthogonal). A triclinic box runs
    /// the same neighbour list under Lees–Edwards boundaries (`lees_edwards.rs`).
    pub tri: Option<lees_edwards::Triclinic>,
    inv_mass: Vec<f64>,
    /// The per-atom values of a many-body style's pre-pass (engine order).
    prepass: Vec<f64>,
    /// The first fault of the last force evaluation (a non-finite many-body term, a bad FENE
    /// bond), reported by [`System::check_health`] and [`System::fault`].
    pair_fault: Option<String>,
    /// The last step of the coming run, when known ([`System::setup_run`]): `fix deform`'s
    /// rates depend on it as LAMMPS's do.
    run_end: Option<u64>,
    /// Rebuild the lists at the next step (LAMMPS re-neighbours on the steps it writes a
    /// restart file: [`System::rebuild_at_next_step`]).
    force_rebuild: bool,
    /// Bonds, angles, molecule style and `special_bonds` (None: `atom_style atomic`).
    pub topo: Option<Topology>,
    /// The energies of the last force evaluation by kind.
    pub energies: Energies,
    /// Warnings of the force evaluations since the caller last took them (LAMMPS's "FENE bond
    /// too long"), for the caller to print.
    pub warnings: Vec<String>,
    /// The special partners of every atom id, from the last set-up.
    partners: std::collections::HashMap<u32, Vec<(u32, u8)>>,
    /// The topology as indices of the current order (rebuilt after every sort).
    bonded: topology::BondedIndex,
    /// LAMMPS's user ghost cut-off (`comm_modify cutoff`; 0: none), for the check of the
    /// bonded atoms' images at a run's set-up.
    pub comm_cutoff: f64,
}

/// The energies of one force evaluation by kind (LAMMPS's `evdwl`, `ebond`, `eangle`);
/// [`System::tally`] holds their sum and the virial of every force.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Pair energy (`epair`, `evdwl`).
    pub epair: f64,
    /// Bond energy (`ebond`).
    pub ebond: f64,
    /// Angle energy (`eangle`).
    pub eangle: f64,
}

/// A line for the log from [`System::setup`].
#[derive(Clone, Debug, PartialEq)]
pub enum SetupNote {
    /// Information (e.g. the γ and s resolved from `pair_coeff … eta … sc …`).
    Info(String),
    /// A warning (e.g. Euler finite-step heating, `crate::init::euler_warning`).
    Warning(String),
}

/// Kinetic and configurational sums from which LAMMPS's thermo keywords follow, in the
/// system's unit style (LAMMPS's `compute temp`, `compute pressure`, thermo `ke`: `mvv2e`,
/// `boltz`, `nktv2p` of [`crate::units::Units`], all 1 in `units lj`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Thermo {
    /// mvv2e Σ m v_a v_b (xx, yy, zz, xy, xz, yz), energy units (`compute temp`'s vector).
    pub ke_tensor: [f64; 6],
    /// Degrees of freedom d N − d (as LAMMPS `compute temp`).
    pub dof: f64,
    /// Kinetic temperature mvv2e Σ m v² / (dof boltz).
    pub temp: f64,
    /// Scalar pressure (dof boltz T + trace virial) / (d V) × nktv2p.
    pub press: f64,
    /// Pressure tensor (mvv2e Σ m v_a v_b + W_ab) / V × nktv2p; in 2-D zz, xz, yz are 0 as in
    /// LAMMPS.
    pub p_tensor: [f64; 6],
    /// Total kinetic energy mvv2e Σ m v² / 2.
    pub ke: f64,
    /// Total potential energy (pair + bond + angle).
    pub pe: f64,
    /// Its parts.
    pub energies: Energies,
    /// Volume (area in 2-D).
    pub vol: f64,
}

/// Most atom types a standalone system may have (`create_box`, `read_data`, `read_restart`):
/// per-type tables hold (N + 1)² entries, rebuilt at every run's set-up, so a count beyond
/// this is a typing error, not a model (a fuzzed `create_box 23333333333333 box` aborted in the
/// allocator).
pub(crate) const MAX_ATOM_TYPES: usize = 1000;

/// Refuse an atom type count outside 1..=[`MAX_ATOM_TYPES`], naming it.
pub(crate) fn check_ntypes(ntypes: usize) -> Result<(), String> {
    if ntypes == 0 {
        return Err("the number of atom types must be >= 1".into());
    }
    if ntypes > MAX_ATOM_TYPES {
        return Err(format!(
            "{ntypes} atom types: at most {MAX_ATOM_TYPES} are supported (per-type tables hold \
             (N + 1)^2 entries)"
        ));
    }
    Ok(())
}

impl System {
    /// An empty system in `bx` with `ntypes` atom types, in `units lj`; δt defaults to 0.005,
    /// skin to 0.3 (LAMMPS `units lj`).
    pub fn new(bx: SimBox, ntypes: usize) -> System {
        System {
            bx,
            atoms: Atoms::default(),
            ntypes,
            mass: vec![None; ntypes + 1],
            pair: None,
            neighbor: NeighborList::new(0.3),
            dt: 0.005,
            units: crate::units::Units::LJ,
            step: 0,
            integrator: None,
            pex: Vec::new(),
            tally: PairTally::default(),
            setup_notes: Vec::new(),
            tri: None,
            inv_mass: Vec::new(),
            prepass: Vec::new(),
            pair_fault: None,
            run_end: None,
            force_rebuild: false,
            topo: None,
            energies: Energies::default(),
            warnings: Vec::new(),
            partners: Default::default(),
            bonded: Default::default(),
            comm_cutoff: 0.0,
        }
    }

    /// Make `style` the pair style.
    pub fn set_pair(&mut self, style: impl PairStyle + 'static) {
        self.pair = Some(Box::new(style));
    }

    /// True when the box is triclinic: the pair loop and wrapping are Lees–Edwards's.
    pub fn is_triclinic(&self) -> bool {
        self.tri.is_some()
    }

    /// Dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.bx.dim
    }

    /// [`System::setup`] for a run that ends at step `last` (LAMMPS's `endstep`): `fix deform`
    /// forms its tilt and rate from the run's length, as LAMMPS does, so the same bits.
    pub fn setup_run(&mut self, last: u64) -> Result<(), String> {
        self.run_end = Some(last);
        self.setup()
    }

    /// Rebuild the neighbour lists at the next step whatever the atoms did, as LAMMPS does on a
    /// step it writes a restart file (`restart N`: `Neighbor::decide`); under shear that is
    /// also when atoms are wrapped with the velocity jump.
    pub fn rebuild_at_next_step(&mut self) {
        self.force_rebuild = true;
    }

    /// Check everything a run needs and evaluate the forces of the current step (LAMMPS's
    /// `Verlet::setup`: forces are keyed with the current step).
    pub fn setup(&mut self) -> Result<(), String> {
        for t in 1..=self.ntypes {
            if self.mass[t].is_none() {
                return Err(format!("mass of atom type {t} is not set (mass)"));
            }
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(format!("timestep {} must be > 0", self.dt));
        }
        self.setup_notes.clear();
        let ctx = SetupContext {
            dim: self.bx.dim as u32,
            natoms: self.atoms.len(),
            density: self.atoms.len() as f64 / self.bx.volume(),
            mass: &self.mass,
            dt: self.dt,
            euler: self.integrator == Some(Integrator::Euler),
            special_lj: self.special_lj(),
            units: self.units,
            substyle: false,
        };
        let style = self
            .pair
            .as_deref_mut()
            .ok_or("no pair style defined (pair_style dpd/nonlinear … or sdpd …)")?;
        style::check_special(style, ctx.special_lj)?;
        self.setup_notes = style.setup(&ctx)?;
        let rule =
            topology::SpecialRule::new(ctx.special_lj, style.scales_special(), style.ntypes());
        let rc_max = style.rc_max();
        for p in &self.pex {
            crate::grammar::fix::pex_box_check(p.width, self.bx.len()[0], self.tri.is_some(), true)
                .map_err(|e| format!("fix {} pex/push: {e}", p.id))?;
        }
        crate::init::check_box_images(self.bx.len(), [true; 3], self.bx.dim, rc_max)?;
        self.inv_mass = self
            .mass
            .iter()
            .map(|m| m.map_or(0.0, |m| 1.0 / m))
            .collect();
        if self.dim() == 2 {
            for (x, v) in self.atoms.x.iter_mut().zip(self.atoms.v.iter_mut()) {
                x[2] = 0.0;
                v[2] = 0.0;
            }
        }
        let end = self.run_end.take();
        if let Some(t) = self.tri.as_mut() {
            if t.flip_fix.is_some() {
                // The standalone `fix deform` is always `xy erate … remap v` of group all.
                let d = t.deform.as_ref().map(|d| (d.id.as_str(), true, true, true));
                crate::grammar::fix::flip_momentum_setup(d)?;
            }
            t.start_run(&self.bx, self.dt, self.step, end);
        }
        // Every run starts from a fresh list (so a continuation from a restart file, which
        // builds one too, gets the same bits).
        self.set_shear();
        self.neighbor.build(&mut self.atoms, &self.bx, rc_max);
        self.setup_topology(rule, rc_max)?;
        self.compute_forces(true);
        Ok(())
    }

    /// The `special_bonds lj` factors of the pair loop ([1; 4] without a topology).
    pub fn special_lj(&self) -> [f64; 4] {
        match &self.topo {
            Some(t) if !t.bonds.is_empty() => t.special.lj,
            _ => [1.0; 4],
        }
    }

    /// The fault of the last force evaluation, if any (a bad FENE bond, a non-finite
    /// many-body term): cheap, for a check at every step.
    pub fn fault(&self) -> Option<&str> {
        self.pair_fault.as_deref()
    }

    /// A sheared box: the tilt, offset and rate of the current step, handed to the neighbour
    /// list (`lees_edwards.rs`); a periodic box: none.
    fn set_shear(&mut self) {
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
    fn lammps_rebuild_due(&self, setup: bool) -> bool {
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
    fn flip_box(&mut self) {
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
        let (lo, hi, ly) = (bx.lo[1], bx.hi[1], bx.len()[1]);
        let jump = t.le.jump(bx);
        // Counted before the wrap, in storage order (a serial sum: the same bits on any number
        // of threads).
        for (x, &typ) in self.atoms.x.iter().zip(&self.atoms.typ) {
            let n = lees_edwards::y_crossings(x[1], lo, hi, ly);
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
        // With fix flip/momentum the atoms put through y get remap v's velocity jump; without
        // it (LAMMPS's remap) the same wrap with a jump of 0 (rate 0: v_x − n·0 is v_x).
        let mut le = t.le;
        if t.flip_fix == Some(true) {
            t.leak.conserved = true;
        } else {
            le.rate = 0.0;
        }
        let a = &mut self.atoms;
        a.x.par_iter_mut()
            .zip(a.v.par_iter_mut())
            .zip(a.image.par_iter_mut())
            .for_each(|((x, v), im)| bx.wrap_le(x, v, im, &le));
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
    fn deform_end_of_step(&mut self) {
        if let Some(t) = self.tri.as_mut() {
            t.end_of_step(&self.bx, self.step);
        }
    }

    /// The forces of the current step: the pair style's, then the bonded terms. `setup`: the
    /// set-up's evaluation, right after a build (a pending flip waits for the first step).
    fn compute_forces(&mut self, setup: bool) {
        self.compute_pair_forces(setup);
        self.add_bonded();
    }

    /// The pair part of [`System::compute_forces`] through the pair style (`style.rs`): its
    /// pre-pass, if it has one, then its kernel, over the same list (periodic or sheared),
    /// after the list's rebuild when one is due.
    fn compute_pair_forces(&mut self, setup: bool) {
        self.set_shear();
        let lammps = self.tri.as_ref().is_some_and(|t| t.lammps_order());
        if !lammps {
            self.neighbor.wrap_sheared(&mut self.atoms, &self.bx);
        }
        let Some(rc_max) = self.pair.as_deref().map(|s| s.rc_max()) else {
            return;
        };
        let forced = std::mem::take(&mut self.force_rebuild) && !setup;
        let rebuild = forced
            || if lammps {
                self.lammps_rebuild_due(setup)
            } else {
                self.neighbor.needs_rebuild(&self.atoms)
            };
        if rebuild {
            if lammps {
                self.flip_box();
            }
            self.neighbor.build(&mut self.atoms, &self.bx, rc_max);
        }
        let Some(style) = self.pair.as_deref_mut() else {
            return;
        };
        let ntypes = style.ntypes();
        let mut extra_energy = 0.0;
        self.pair_fault = None;
        if self.topo.is_some() && self.bonded.build != self.neighbor.builds {
            let rule = self.bonded.special.rule;
            if let Some(t) = &self.topo
                && let Err(e) = t.index(&self.atoms.tag, &self.partners, rule, &mut self.bonded)
            {
                self.pair_fault.get_or_insert(e);
            }
            self.bonded.build = self.neighbor.builds;
        }
        let special = (!self.bonded.special.tag.is_empty()).then_some(&self.bonded.special);
        if let Some(pp) = style.prepass() {
            let mut sums = std::mem::take(&mut self.prepass);
            self.neighbor.pair_sum(
                &self.atoms,
                &self.bx,
                pp.rcsq(),
                ntypes,
                |k, rsq| pp.weight(k, rsq),
                |k, rsq, out| pp.weights(k, rsq, out),
                &mut sums,
                special,
            );
            for (k, d) in sums.iter_mut().enumerate() {
                let t = self.atoms.typ[k] as usize;
                *d = pp.complete(t, *d);
                match pp.energy_of(t, *d) {
                    Some(u) => extra_energy += u,
                    None if self.pair_fault.is_none() => {
                        let who = self.atoms.tag[k].to_string();
                        self.pair_fault = Some(pp.fault(&who, *d, self.step));
                    }
                    None => {}
                }
            }
            style.set_atom_values(&sums, &self.atoms.typ);
            self.prepass = sums;
        }
        let style = &*style;
        let kernel = style.kernel(self.neighbor.isa());
        self.tally = self.neighbor.compute_forces(
            &mut self.atoms,
            &self.bx,
            &*kernel,
            style.cut_table(),
            ntypes,
            &self.inv_mass,
            self.step,
            special,
        );
        self.tally.energy += extra_energy;
        self.energies.epair = self.tally.energy;
    }

    /// The bonded forces after the pair forces: energies and virial into the tally.
    fn add_bonded(&mut self) {
        if self.topo.is_some() {
            let b = self.bonded_forces();
            self.tally.energy = self.energies.epair + self.energies.ebond + self.energies.eangle;
            for c in 0..6 {
                self.tally.virial[c] += b.virial[c];
            }
        }
    }

    /// Advance one step with the configured integrator (after [`System::setup`]), then apply
    /// the PeX pushes (LAMMPS `end_of_step`, in definition order).
    pub fn step_once(&mut self) {
        self.advance();
        for k in 0..self.pex.len() {
            self.apply_pex_push(k);
        }
    }

    /// One step of integration and forces, without the end-of-step fixes: the caller applies
    /// [`System::apply_pex_push`] and its measurements in the order the fixes were defined.
    pub fn advance(&mut self) {
        self.step += 1;
        let dt = self.dt;
        let ftm2v = self.units.ftm2v;
        let mass = &self.mass;
        let a = &mut self.atoms;
        match self.integrator {
            Some(Integrator::VelocityVerlet) => {
                // dtf / m per type, as LAMMPS `fix nve` forms it (dtf = δt/2 · ftm2v).
                let dtf = 0.5 * dt * ftm2v;
                let dtfm: Vec<f64> = mass.iter().map(|m| m.map_or(0.0, |m| dtf / m)).collect();
                a.x.par_iter_mut()
                    .zip(a.v.par_iter_mut())
                    .zip(a.f.par_iter().zip(a.typ.par_iter()))
                    .for_each(|((x, v), (f, &t))| {
                        let dtfm = dtfm[t as usize];
                        for k in 0..3 {
                            v[k] += dtfm * f[k];
                            x[k] += dt * v[k];
                        }
                    });
                self.compute_forces(false);
                let a = &mut self.atoms;
                a.v.par_iter_mut()
                    .zip(a.f.par_iter().zip(a.typ.par_iter()))
                    .for_each(|(v, (f, &t))| {
                        let dtfm = dtfm[t as usize];
                        for k in 0..3 {
                            v[k] += dtfm * f[k];
                        }
                    });
            }
            Some(Integrator::Euler) => {
                // (δt · ftm2v) / m, as the LAMMPS fix passes δt · ftm2v.
                let dtf = dt * ftm2v;
                let dtfm: Vec<f64> = mass.iter().map(|m| m.map_or(0.0, |m| dtf / m)).collect();
                a.x.par_iter_mut()
                    .zip(a.v.par_iter_mut())
                    .zip(a.f.par_iter().zip(a.typ.par_iter()))
                    .for_each(|((x, v), (f, &t))| {
                        fixes::euler_update(x, v, f, dt, dtfm[t as usize])
                    });
                self.compute_forces(false);
            }
            None => self.compute_forces(false),
        }
        if self.dim() == 2 {
            for (v, f) in self.atoms.v.iter_mut().zip(self.atoms.f.iter_mut()) {
                v[2] = 0.0;
                f[2] = 0.0;
            }
        }
        self.deform_end_of_step();
    }

    /// The end-of-step action of PeX push `k` (index into [`System::pex`]) at the current step;
    /// does nothing on steps that are not a multiple of its `every`. See docs/fixes.md.
    pub fn apply_pex_push(&mut self, k: usize) {
        let step = self.step;
        let Some(push) = self.pex.get_mut(k) else {
            return;
        };
        if !step.is_multiple_of(push.every) {
            return;
        }
        let bx = &self.bx;
        let lx = bx.len()[0];
        let slabs = fixes::PexSlabs::new(bx.lo[0], bx.hi[0], push.width.unwrap_or(lx / 20.0));
        let a = &mut self.atoms;
        let pick = fixes::PexPick::select(&slabs, &a.x, &a.v, &a.tag, |_| true);
        if let (Some((_, slow)), Some((_, fast))) = (pick.slow, pick.fast) {
            let (mass, typ) = (&self.mass, &a.typ);
            fixes::pex_apply(
                &mut a.v,
                &a.tag,
                |i| mass[typ[i] as usize].unwrap_or(1.0),
                push.dp,
                slow,
                fast,
            );
            push.total += push.dp;
        }
    }

    /// The blow-up check of a run (docs/input.md, "run"): every position, velocity and force
    /// finite, and no atom moving more than half the box length along any axis in one step
    /// (|v_k| δt > L_k / 2: the integration no longer resolves anything). The error names the
    /// step, the atom id and the quantity. O(N); the run loop calls it at thermo output and at
    /// least every 100 steps.
    pub fn check_health(&self) -> Result<(), String> {
        if let Some(e) = &self.pair_fault {
            return Err(e.clone());
        }
        let a = &self.atoms;
        check_atoms(
            self.step,
            self.dt,
            self.dim(),
            self.bx.len(),
            a.len(),
            |i| (a.tag[i], a.x[i], a.v[i], a.f[i]),
        )
    }

    /// The thermodynamic state with LAMMPS's definitions (`docs/models.md` §4.5, P-7–P-9).
    pub fn thermo(&self) -> Thermo {
        let mut kt = [0.0; 6];
        for ((v, &t), _) in self.atoms.v.iter().zip(&self.atoms.typ).zip(0..) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            kt[0] += m * v[0] * v[0];
            kt[1] += m * v[1] * v[1];
            kt[2] += m * v[2] * v[2];
            kt[3] += m * v[0] * v[1];
            kt[4] += m * v[0] * v[2];
            kt[5] += m * v[1] * v[2];
        }
        self.thermo_from_kinetic(kt)
    }

    /// The kinetic part of `compute temp/deform` (LAMMPS definitions): Σ m (v − u)_a (v − u)_b
    /// with the streaming velocity u = (h_rate_xy (y − y_lo)/L_y, 0, 0) of the current
    /// deformation (u = 0 without one), its temperature over dof = dN − d, and the pressure of
    /// `compute pressure ID` with this temperature: (Σ m (v−u)_a (v−u)_b + W_ab)/V.
    pub fn thermo_deform(&self) -> Thermo {
        let mut kt = [0.0; 6];
        for ((v, &t), x) in self.atoms.v.iter().zip(&self.atoms.typ).zip(&self.atoms.x) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            let u = self
                .tri
                .as_ref()
                .map_or(0.0, |tr| tr.stream_x(&self.bx, x[1]));
            let w = [v[0] - u, v[1], v[2]];
            kt[0] += m * w[0] * w[0];
            kt[1] += m * w[1] * w[1];
            kt[2] += m * w[2] * w[2];
            kt[3] += m * w[0] * w[1];
            kt[4] += m * w[0] * w[2];
            kt[5] += m * w[1] * w[2];
        }
        self.thermo_from_kinetic(kt)
    }

    /// The thermodynamic state from the kinetic tensor `kt` = Σ m v_a v_b (xx yy zz xy xz yz,
    /// mass × velocity²) of some temperature compute and the last force evaluation's virial,
    /// with LAMMPS's unit factors (each 1, so no bit changes, in `units lj`).
    fn thermo_from_kinetic(&self, kt: [f64; 6]) -> Thermo {
        let u = &self.units;
        let kt = kt.map(|x| u.mvv2e * x);
        let d = self.dim();
        let n = self.atoms.len() as f64;
        let dof = d as f64 * n - d as f64;
        let mv2 = if d == 3 {
            kt[0] + kt[1] + kt[2]
        } else {
            kt[0] + kt[1]
        };
        let temp = if dof > 0.0 {
            mv2 / (dof * u.boltz)
        } else {
            0.0
        };
        let vol = self.bx.volume();
        let w = self.tally.virial;
        let trace = if d == 3 {
            w[0] + w[1] + w[2]
        } else {
            w[0] + w[1]
        };
        let press = (dof * u.boltz * temp + trace) / (d as f64 * vol) * u.nktv2p;
        let mut p = [0.0; 6];
        for a in 0..6 {
            p[a] = (kt[a] + w[a]) / vol * u.nktv2p;
        }
        if d == 2 {
            p[2] = 0.0;
            p[4] = 0.0;
            p[5] = 0.0;
        }
        Thermo {
            ke_tensor: kt,
            dof,
            temp,
            press,
            p_tensor: p,
            ke: 0.5 * mv2,
            pe: self.tally.energy,
            energies: self.energies,
            vol,
        }
    }

    /// Total momentum Σ m v.
    pub fn momentum(&self) -> [f64; 3] {
        let mut p = [0.0; 3];
        for (v, &t) in self.atoms.v.iter().zip(&self.atoms.typ) {
            let m = self.mass[t as usize].unwrap_or(0.0);
            for k in 0..3 {
                p[k] += m * v[k];
            }
        }
        p
    }

    /// Bytes per atom held by the atom arrays and the neighbour structures.
    pub fn bytes(&self) -> (usize, usize) {
        let a = &self.atoms;
        let atom_bytes = a.x.capacity() * 24 * 3
            + a.tag.capacity() * 4
            + a.typ.capacity() * 4
            + a.image.capacity() * 12;
        (atom_bytes, self.neighbor.bytes())
    }
}

/// The blow-up check of [`System::check_health`] for any atom store (the C ABI passes LAMMPS's
/// owned atoms): `atom(i)` gives (tag, x, v, f) of atom i < n; `len` the box lengths. The first
/// non-finite position, velocity or force, or a velocity that crosses half the box length in
/// one step, is an error naming the step, the atom and the quantity.
pub fn check_atoms(
    step: u64,
    dt: f64,
    dim: usize,
    len: [f64; 3],
    n: usize,
    atom: impl Fn(usize) -> (u32, [f64; 3], [f64; 3], [f64; 3]),
) -> Result<(), String> {
    let axis = ["x", "y", "z"];
    for i in 0..n {
        let (tag, x, v, f) = atom(i);
        for (what, q) in [("position", &x), ("velocity", &v), ("force", &f)] {
            if let Some(k) = (0..3).find(|&k| !q[k].is_finite()) {
                return Err(format!(
                    "blow-up at step {step}: atom {tag} has a non-finite {what} ({}{} = {})",
                    &what[..1],
                    axis[k],
                    q[k]
                ));
            }
        }
        if let Some(k) = (0..dim).find(|&k| v[k].abs() * dt > 0.5 * len[k]) {
            return Err(format!(
                "blow-up at step {step}: atom {tag} moves {:.3e} per step along {} (v{} = {:.3e}), more than half the box length {}; reduce the time step or check the force field",
                v[k].abs() * dt,
                axis[k],
                axis[k],
                v[k],
                len[k]
            ));
        }
    }
    Ok(())
}
