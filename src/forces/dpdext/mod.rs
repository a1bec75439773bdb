//! `pair_style dpd/nonlinear/ext`, `dpd/nonlinear/tstat` and `dpd/nonlinear/ext/tstat`
//! ([`ExtPair`], one style object for the three names): `dpd/nonlinear`'s parallel friction and
//! noise (every friction model and noise scheme) with LAMMPS's `dpd/ext` perpendicular friction
//! and noise, and the thermostat-only forms (no conservative force, T ramped from Tstart to
//! Tstop over a run as LAMMPS's `dpd/tstat` does). docs/models.md §4.11–4.12.

pub mod grammar;
pub mod kernel;

use crate::forces::batcher::PairKernel;
use crate::forces::dpd::DpdPlan;
use crate::forces::dpd::kernel::{Friction, PairModel};
use crate::forces::lanes::{Isa, PairBatch};
use crate::forces::plan::StylePlan;
use crate::forces::style::{PairStyle, RunSteps, SetupContext, SetupNote, StyleRecord, word};
use grammar::{ExtStyle, Form};
use kernel::{ExtCoeff, ExtTable, ext_forces_batch_isa};
use std::sync::Arc;

/// The batch kernel of the three styles ([`kernel::ext_forces_batch_isa`]).
pub struct ExtKernel<'a> {
    model: &'a PairModel,
    table: &'a ExtTable,
    seed: u32,
    dim: u32,
    transverse: bool,
    isa: Isa,
}

impl PairKernel for ExtKernel<'_> {
    #[inline]
    fn evaluate(&self, step: u64, b: &mut PairBatch, _i: &[u32], _j: &[u32]) {
        ext_forces_batch_isa(
            self.isa,
            self.model,
            self.table,
            self.seed,
            step,
            self.dim,
            self.transverse,
            b,
        );
    }
}

/// One of the three styles with its coefficients.
#[derive(Clone, Debug)]
pub struct ExtPair {
    /// The settings as given.
    pub settings: ExtStyle,
    /// The kernel's model (kT of the temperature in force: Tstart, or the ramp's at the last
    /// [`PairStyle::at_step`]).
    pub model: PairModel,
    ntypes: usize,
    coeff: Vec<Option<ExtCoeff>>,
    /// Dense tables of the last set-up: coefficients (one block per special class), their
    /// constants for the current kT, cut-offs.
    table: Vec<ExtCoeff>,
    etable: ExtTable,
    cut: Vec<f64>,
    dt: f64,
    special: [f64; 4],
    dim: u32,
    boltz: f64,
}

impl ExtPair {
    /// The style `form` from the words after its name, for `ntypes` types and time step `dt`.
    pub fn new(form: Form, args: &[String], ntypes: usize, dt: f64) -> Result<ExtPair, String> {
        let settings = grammar::pair_style(form, args)?;
        Ok(ExtPair {
            model: settings.model(dt),
            settings,
            ntypes,
            coeff: vec![None; (ntypes + 1) * (ntypes + 1)],
            table: Vec::new(),
            etable: ExtTable::default(),
            cut: Vec::new(),
            dt,
            special: [1.0; 4],
            dim: 3,
            boltz: 1.0,
        })
    }

    /// The coefficients of type pair (i, j), if set.
    pub fn get(&self, i: usize, j: usize) -> Option<&ExtCoeff> {
        self.coeff.get(i * (self.ntypes + 1) + j)?.as_ref()
    }

    fn set(&mut self, i: usize, j: usize, c: ExtCoeff) {
        let n = self.ntypes + 1;
        self.coeff[i * n + j] = Some(c);
        self.coeff[j * n + i] = Some(c);
    }

    /// The temperature of step `step` of a run from `begin` to `end` (LAMMPS's `dpd/tstat`):
    /// Tstart + (step − begin)/(end − begin) (Tstop − Tstart), Tstart at step = begin (P-35).
    pub fn temperature_at(&self, step: u64, run: RunSteps) -> f64 {
        let s = &self.settings;
        if s.t_start == s.t_stop {
            return s.t_start;
        }
        let mut delta = step as f64 - run.begin as f64;
        if delta != 0.0 {
            delta /= run.end as f64 - run.begin as f64;
        }
        s.t_start + delta * (s.t_stop - s.t_start)
    }

    /// Block 0 the coefficients; blocks 1–3 the special classes scaled by their `special_lj`
    /// factor f: f a, f γ∥, f γ⊥ (each random force by √f), as P-22.
    fn build_tables(&mut self, dt: f64, special_lj: [f64; 4]) {
        self.dt = dt;
        self.special = special_lj;
        self.model.set_timestep(dt);
        let block: Vec<ExtCoeff> = self
            .coeff
            .iter()
            .map(|c| c.unwrap_or(ExtCoeff::INERT))
            .collect();
        self.cut = block.iter().map(|c| c.par.rc).collect();
        self.table = block.clone();
        for &f in &special_lj[1..] {
            self.table.extend(block.iter().map(|c| ExtCoeff {
                par: crate::forces::dpd::kernel::PairCoeff {
                    a: f * c.par.a,
                    gamma0: f * c.par.gamma0,
                    ..c.par
                },
                gamma_perp: f * c.gamma_perp,
                ..*c
            }));
        }
        self.etable = ExtTable::new(&self.model, &self.table);
    }

    fn nonzero_gamma1(&self) -> Option<(usize, usize, f64)> {
        let n = self.ntypes;
        (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .find_map(|(i, j)| {
                self.get(i, j)
                    .filter(|c| c.par.gamma1 != 0.0)
                    .map(|c| (i, j, c.par.gamma1))
            })
    }
}

impl PairStyle for ExtPair {
    fn name(&self) -> &'static str {
        self.settings.form.name()
    }

    fn ntypes(&self) -> usize {
        self.ntypes
    }

    /// As LAMMPS's `dpd/ext` and `dpd/tstat`: the coefficients are kept and every cut-off is
    /// reset to the new global one (`dpd/nonlinear/tstat`: the parallel weight to the new
    /// `weight`). Friction `none` with a kept γ1 ≠ 0 is refused.
    fn restyle(&mut self, args: &[String]) -> Result<(), String> {
        let settings = grammar::pair_style(self.settings.form, args)?;
        if settings.friction == Friction::None
            && let Some((i, j, g)) = self.nonzero_gamma1()
        {
            return Err(format!(
                "friction none, but the kept pair_coeff {i} {j} has gamma1 = {g}, which must be \
                 0 with friction none (give the pair_coeff lines again after this pair_style)"
            ));
        }
        let form = settings.form;
        for c in self.coeff.iter_mut().flatten() {
            c.par.rc = settings.rc;
            if form == Form::Tstat {
                c.w_par = settings.weight;
            }
        }
        self.model = settings.model(self.model.timestep());
        self.settings = settings;
        Ok(())
    }

    fn coeff(&mut self, args: &[String]) -> Result<(), String> {
        let line = grammar::pair_coeff(&self.settings, args, self.ntypes)?;
        for (i, j) in line.pairs() {
            self.set(i, j, line.coeff);
        }
        Ok(())
    }

    fn cutoff(&self, i: usize, j: usize) -> Option<f64> {
        self.get(i, j).map(|c| c.par.rc)
    }

    /// Coefficients complete, kT = boltz Tstart and ftm2v in the model, the dense tables.
    fn setup(&mut self, ctx: &SetupContext) -> Result<Vec<SetupNote>, String> {
        crate::forces::style::coverage(self, ctx)?;
        let u = ctx.units;
        self.boltz = u.boltz;
        self.dim = ctx.dim;
        self.model.kt = u.kt(self.settings.t_start);
        self.model.set_ftm2v(u.ftm2v);
        let notes = u
            .temperature_note(self.name(), self.settings.t_start)
            .map(SetupNote::Info)
            .into_iter()
            .collect();
        self.build_tables(ctx.dt, ctx.special_lj);
        Ok(notes)
    }

    fn set_timestep(&mut self, dt: f64) {
        if dt != self.dt {
            self.build_tables(dt, self.special);
        }
    }

    /// The ramp: kT of step `step` (P-35), the tables' σ's with it.
    fn at_step(&mut self, step: u64, run: RunSteps) {
        if self.settings.t_start == self.settings.t_stop {
            return;
        }
        let kt = self.boltz * self.temperature_at(step, run);
        if kt != self.model.kt {
            self.model.kt = kt;
            self.etable = ExtTable::new(&self.model, &self.table);
        }
    }

    fn cut_table(&self) -> &[f64] {
        &self.cut
    }

    fn scales_special(&self) -> bool {
        true
    }

    fn set_special(&mut self, special_lj: [f64; 4]) {
        if special_lj != self.special {
            self.build_tables(self.dt, special_lj);
        }
    }

    fn kernel(&self, isa: Isa) -> Box<dyn PairKernel + '_> {
        Box::new(ExtKernel {
            model: &self.model,
            table: &self.etable,
            seed: self.settings.seed,
            dim: self.dim,
            transverse: self.settings.form.transverse(),
            isa,
        })
    }

    /// The conservative part, as LAMMPS's `dpd/ext` `single()` returns it (0 for the
    /// thermostat-only forms, whose a is 0).
    fn single(&self, i: usize, j: usize, rsq: f64) -> Option<(f64, f64)> {
        let c = self.get(i, j)?.par;
        Some(c.conservative(rsq))
    }

    fn clone_box(&self) -> Box<dyn PairStyle> {
        Box::new(self.clone())
    }
}

impl StyleRecord for ExtPair {
    /// `dpd/nonlinear/tstat` is `dpd/nonlinear` with a = 0 for the kinetic theory (at Tstart);
    /// the transverse forms have no theory here ([`ExtPlan`]).
    fn plan(&self, _units: &crate::units::Units, _dt: f64) -> Arc<dyn StylePlan> {
        if self.settings.form.transverse() {
            return Arc::new(ExtPlan {
                name: self.name(),
                model: self.model,
            });
        }
        let n = self.ntypes;
        let coeffs = (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .filter_map(|(i, j)| self.get(i, j).map(|c| (i, j, c.par)))
            .collect();
        Arc::new(DpdPlan {
            model: self.model,
            coeffs,
        })
    }

    fn restart_lines(&self) -> Vec<Vec<String>> {
        let form = self.settings.form;
        let mut head = vec!["pair_style".to_string(), self.name().to_string()];
        head.extend(self.settings.to_words());
        let mut lines = vec![head];
        let n = self.ntypes;
        for i in 1..=n {
            for j in i..=n {
                let Some(c) = self.get(i, j) else { continue };
                let mut l = vec!["pair_coeff".into(), i.to_string(), j.to_string()];
                if form == Form::Ext {
                    l.push(word(c.par.a));
                }
                l.push(word(c.par.gamma0));
                if form.transverse() {
                    l.extend([
                        word(c.gamma_perp),
                        word(0.5 * c.w_par.exponent()),
                        word(0.5 * c.w_perp.exponent()),
                    ]);
                }
                l.extend([word(c.par.rc), "gamma1".into(), word(c.par.gamma1)]);
                lines.push(l);
            }
        }
        lines
    }
}

/// A planned run of a transverse form (`dpd/nonlinear/ext`, `dpd/nonlinear/ext/tstat`): its
/// thermostat, and no kinetic theory (the ideal-fluid theory covers the central friction only).
#[derive(Clone, Debug)]
pub struct ExtPlan {
    /// The style's name.
    pub name: &'static str,
    /// The model of the parallel part (kT at Tstart, friction, noise).
    pub model: PairModel,
}

impl StylePlan for ExtPlan {
    fn kt(&self) -> Option<f64> {
        Some(self.model.kt)
    }
    fn summary(&self) -> Option<String> {
        Some(format!(
            "friction {}, noise {}, parallel and perpendicular weights per pair",
            self.model.friction.keyword(),
            self.model.noise.keyword(),
        ))
    }
    fn notes(&self) -> Vec<SetupNote> {
        vec![SetupNote::Info(format!(
            "pair_style {}: the ideal-fluid kinetic theory covers the central (parallel) \
             friction only, not the perpendicular friction gammaT nor a weight exponent per \
             pair, so no pair has a prediction",
            self.name
        ))]
    }
}
