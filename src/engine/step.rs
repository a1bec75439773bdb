//! The driver of a run, in LAMMPS's order: the set-up (`Verlet::setup`: checks, the pair
//! style's set-up, the first forces) and the step (`Verlet::run`: the first half kick and the
//! drift, the box's deformation, re-neighbouring, the forces of the new step: pair, then
//! bonded, the second half kick, the PeX push).

use super::*;
use crate::forces::style::StyleDerived;

impl System {
    /// [`System::setup`] for a run that ends at step `last` (LAMMPS's `endstep`): `fix deform`
    /// forms its tilt and rate from the run's length, as LAMMPS does, so the same bits.
    pub fn setup_run(&mut self, last: u64) -> Result<(), String> {
        self.run_end = Some(last);
        self.setup()
    }

    /// [`System::setup_run`] with LAMMPS's `run N start S stop E`: the steps a pair style's
    /// temperature ramp runs between (`beginstep`, `endstep`; `None`: the run's own first and
    /// last step). S after the first step or E before the last is an error, as in LAMMPS.
    /// `fix deform` takes its rate from the run itself, so it refuses a window.
    pub fn setup_run_window(
        &mut self,
        last: u64,
        start: Option<u64>,
        stop: Option<u64>,
    ) -> Result<(), String> {
        if start.is_some_and(|s| s > self.step) {
            return Err("run start: the start step is after the first step of the run".into());
        }
        if stop.is_some_and(|s| s < last) {
            return Err("run stop: the stop step is before the last step of the run".into());
        }
        if (start.is_some() || stop.is_some())
            && self.tri.as_ref().is_some_and(|t| t.deform.is_some())
        {
            return Err("run start/stop: not supported with fix deform".into());
        }
        self.run_window = (start, stop);
        let r = self.setup_run(last);
        self.run_window = (None, None);
        r
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
            euler: self.modify.scheme().or(self.integrator) == Some(Integrator::Euler),
            special_lj: self.special_lj(),
            units: self.units,
            substyle: self.pair_substyle,
            per_atom_mass: false,
        };
        let style = self
            .pair
            .as_deref_mut()
            .ok_or("no pair style defined (pair_style dpd/nonlinear … or sdpd …)")?;
        crate::forces::style::check_special(style, ctx.special_lj)?;
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
        self.run_steps = crate::forces::RunSteps {
            begin: self.run_window.0.unwrap_or(self.step),
            end: self.run_window.1.or(end).unwrap_or(self.step),
        };
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
        if !self.defer_fix_setup {
            self.setup_fixes();
        }
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

    /// The forces of the current step: the pair style's, then the bonded terms. `setup`: the
    /// set-up's evaluation, right after a build (a pending flip waits for the first step).
    pub(super) fn compute_forces(&mut self, setup: bool) {
        self.neighbor.virial_atom.clear();
        self.compute_pair_forces(setup);
        self.add_bonded();
    }

    /// The pair part of [`System::compute_forces`] through the pair style (`style.rs`): its
    /// pre-pass, if it has one, then its kernel, over the same list (periodic or sheared),
    /// after the list's rebuild when one is due.
    pub(super) fn compute_pair_forces(&mut self, setup: bool) {
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
        // The topology's index form for the current atom order, after a build sorted the atoms.
        let bonded = &mut self.bonded;
        if self.topo.is_some() && bonded.index.build != self.neighbor.builds {
            let rule = bonded.index.special.rule;
            if let Some(t) = &self.topo
                && let Err(e) = t.index(&self.atoms.tag, &bonded.partners, rule, &mut bonded.index)
            {
                self.pair_fault.get_or_insert(e);
            }
            bonded.index.build = self.neighbor.builds;
        }
        let special =
            (!self.bonded.index.special.tag.is_empty()).then_some(&self.bonded.index.special);
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
            style.set_atom_values(&sums, &self.atoms.typ, None);
            self.prepass = sums;
        }
        style.at_step(self.step, self.run_steps);
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
    pub(super) fn add_bonded(&mut self) {
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
        self.advance_to_forces();
        self.advance_finish();
    }

    /// The first part of [`System::advance`] (LAMMPS's `Verlet::run` up to the forces): the
    /// step number, the fixes' `initial_integrate` and `post_integrate`, the forces of the new
    /// step. A caller whose fixes read variables evaluates them here
    /// ([`System::fix_inputs`]), then calls [`System::advance_finish`].
    pub fn advance_to_forces(&mut self) {
        self.step += 1;
        if self.modify.integrates() {
            self.run_hook(modify::Hook::InitialIntegrate);
        } else {
            match self.integrator {
                Some(Integrator::VelocityVerlet) => modify::nve_initial(self, 1),
                Some(Integrator::Euler) => modify::euler(self, 1),
                None => {}
            }
        }
        self.run_hook(modify::Hook::PostIntegrate);
        self.compute_forces(false);
    }

    /// The rest of [`System::advance`]: the fixes' `post_force` and `final_integrate`, the
    /// plane of a 2-D model, `fix deform`'s end of step.
    pub fn advance_finish(&mut self) {
        self.run_hook(modify::Hook::PostForce);
        if self.modify.integrates() {
            self.run_hook(modify::Hook::FinalIntegrate);
        } else if self.integrator == Some(Integrator::VelocityVerlet) {
            modify::nve_final(self, 1);
        }
        if self.dim() == 2 {
            for (v, f) in self.atoms.v.iter_mut().zip(self.atoms.f.iter_mut()) {
                v[2] = 0.0;
                f[2] = 0.0;
            }
        }
        self.deform_end_of_step();
    }

    /// The fixes' set-up after the set-up's forces (LAMMPS's `Modify::setup`: `setforce`,
    /// `addforce`, `aveforce` act on step 0's forces). [`System::setup`] calls it unless
    /// [`System::defer_fix_setup`] is set.
    pub fn setup_fixes(&mut self) {
        self.run_hook(modify::Hook::Setup);
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
}
