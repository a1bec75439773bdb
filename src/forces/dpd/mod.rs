//! `pair_style dpd/nonlinear` as a style object ([`DpdPair`]): its settings, the global
//! [`PairModel`], the seed and the per type-pair [`PairCoeff`] table ([`ForceField`]), its
//! set-up (η/Sc targets, the Euler warning) and its kernel (`docs/models.md` §1.1–1.4).

use std::sync::Arc;

pub mod grammar;
pub mod kernel;

use crate::fmtnum::short;
use crate::forces::batcher::PairKernel;
use crate::forces::lanes::{Isa, PairBatch};
use crate::forces::plan::{
    DesignCheck, DesignInputs, DesignMethod, PairPlan, PairTheory, PlanPoint, StylePlan,
};
use crate::forces::style::{PairStyle, SetupContext, SetupNote, StyleDerived, StyleRecord, word};
use crate::theory::{Design, Fluid, TheoryError, kinetic_theory};
use grammar::DpdStyle;
use kernel::{Friction, PairCoeff, PairModel, PairTable, pair_forces_batch_isa};

/// `pair_style dpd/nonlinear`'s batch kernel: [`kernel::pair_forces_batch`] (docs/models.md
/// §1.1–1.4).
pub struct DpdKernel<'a> {
    /// The global model (friction, noise, weight, δt).
    pub model: &'a PairModel,
    /// The per-type-pair coefficients.
    pub table: &'a PairTable,
    /// The noise seed.
    pub seed: u32,
    /// The instruction set of the lane loops (same bits with every one).
    pub isa: Isa,
}

impl PairKernel for DpdKernel<'_> {
    #[inline]
    fn evaluate(&self, step: u64, b: &mut PairBatch, _i: &[u32], _j: &[u32]) {
        pair_forces_batch_isa(self.isa, self.model, self.table, self.seed, step, b);
    }
}

/// `pair_style dpd/nonlinear` + `pair_coeff`, validated.
#[derive(Clone, Debug)]
pub struct ForceField {
    /// Global model (kT, friction, noise, weight, δt).
    pub model: PairModel,
    /// Seed of the keyed pair noise (> 0).
    pub seed: u32,
    /// Global cut-off (the default of `pair_coeff`'s optional rc).
    pub rc_global: f64,
    ntypes: usize,
    coeff: Vec<Option<PairCoeff>>,
    /// `pair_coeff … eta E sc S`: the (η, Sc) targets of a pair, resolved to `gamma0` (and the
    /// global weight exponent) at every run's set-up from the current density.
    targets: Vec<Option<(f64, f64)>>,
}

impl ForceField {
    /// A force field for `ntypes` atom types with no coefficients set yet.
    pub fn new(model: PairModel, seed: u32, rc_global: f64, ntypes: usize) -> ForceField {
        ForceField {
            model,
            seed,
            rc_global,
            ntypes,
            coeff: vec![None; (ntypes + 1) * (ntypes + 1)],
            targets: vec![None; (ntypes + 1) * (ntypes + 1)],
        }
    }

    /// Number of atom types.
    pub fn ntypes(&self) -> usize {
        self.ntypes
    }

    /// Set the coefficients of types (i, j) and (j, i) (clears any (η, Sc) target of the pair).
    pub fn set(&mut self, i: usize, j: usize, c: PairCoeff) {
        let n = self.ntypes + 1;
        self.coeff[i * n + j] = Some(c);
        self.coeff[j * n + i] = Some(c);
        self.targets[i * n + j] = None;
        self.targets[j * n + i] = None;
    }

    /// Set the coefficients of types (i, j) from targets η and Sc: `c.gamma0` is a placeholder
    /// until [`ForceField::resolve_targets`] runs.
    pub fn set_targets(&mut self, i: usize, j: usize, c: PairCoeff, eta: f64, sc: f64) {
        self.set(i, j, c);
        let n = self.ntypes + 1;
        self.targets[i * n + j] = Some((eta, sc));
        self.targets[j * n + i] = Some((eta, sc));
    }

    /// Whether any pair was given (η, Sc) targets.
    pub fn has_targets(&self) -> bool {
        self.targets.iter().any(Option::is_some)
    }

    /// Resolve every (η, Sc) target at number density `density` and mass `mass`
    /// ([`crate::init::resolve_design`]) with the model's kT, in a unit style of mass × velocity²
    /// → energy factor `mvv2e` (1 in `units lj`): sets `gamma0` of those pairs and the global
    /// weight exponent. Returns the lines to log.
    pub fn resolve_targets(
        &mut self,
        dim: u32,
        density: f64,
        mass: f64,
        mvv2e: f64,
    ) -> Result<Vec<String>, String> {
        let n = self.ntypes + 1;
        let kt = self.model.kt;
        let mut lines = Vec::new();
        let mut exponents = Vec::new();
        for i in 1..=self.ntypes {
            for j in i..=self.ntypes {
                let (Some((eta, sc)), Some(c)) = (self.targets[i * n + j], self.coeff[i * n + j])
                else {
                    continue;
                };
                let label = format!("{i} {j}");
                let r = crate::init::resolve_design(
                    &label, dim, density, c.rc, mass, kt, mvv2e, eta, sc,
                )?;
                let c = PairCoeff {
                    gamma0: r.gamma,
                    ..c
                };
                self.coeff[i * n + j] = Some(c);
                self.coeff[j * n + i] = Some(c);
                lines.push(r.message);
                exponents.push((label, r.s));
            }
        }
        let current = self.model.weight.exponent();
        if let Some((s, note)) =
            crate::init::common_exponent(grammar::NAME, "weight", &exponents, current)?
        {
            self.model.weight = kernel::Weight::new(s)
                .ok_or_else(|| format!("designed weight exponent s = {s} is not > 0"))?;
            lines.extend(note);
        }
        Ok(lines)
    }

    /// The (η, Sc) targets of a type pair, if it has them.
    pub fn target(&self, i: usize, j: usize) -> Option<(f64, f64)> {
        *self.targets.get(i * (self.ntypes + 1) + j)?
    }

    /// The first set pair (i ≤ j) with γ1 ≠ 0, and its γ1.
    pub fn nonzero_gamma1(&self) -> Option<(usize, usize, f64)> {
        (1..=self.ntypes)
            .flat_map(|i| (i..=self.ntypes).map(move |j| (i, j)))
            .find_map(|(i, j)| {
                self.get(i, j)
                    .filter(|c| c.gamma1 != 0.0)
                    .map(|c| (i, j, c.gamma1))
            })
    }

    /// Coefficients of a type pair, if set.
    pub fn get(&self, i: usize, j: usize) -> Option<&PairCoeff> {
        self.coeff.get(i * (self.ntypes + 1) + j)?.as_ref()
    }

    /// The first type pair without coefficients, if any.
    pub fn missing(&self) -> Option<(usize, usize)> {
        for i in 1..=self.ntypes {
            for j in i..=self.ntypes {
                if self.get(i, j).is_none() {
                    return Some((i, j));
                }
            }
        }
        None
    }

    /// A dense table for the hot loop: `table[ti * (ntypes + 1) + tj]` (unset pairs are inert).
    pub fn dense_table(&self) -> Vec<PairCoeff> {
        self.coeff
            .iter()
            .map(|c| {
                c.unwrap_or(PairCoeff {
                    a: 0.0,
                    gamma0: 0.0,
                    gamma1: 0.0,
                    rc: 0.0,
                })
            })
            .collect()
    }

    /// The largest cut-off over all set type pairs.
    pub fn rc_max(&self) -> f64 {
        self.coeff
            .iter()
            .flatten()
            .map(|c| c.rc)
            .fold(0.0, f64::max)
    }
}

/// `pair_style dpd/nonlinear` + `pair_coeff`: the style object of both engines.
#[derive(Clone, Debug)]
pub struct DpdPair {
    /// The settings as given (the weight may be replaced by a design at set-up, in `ff.model`).
    pub settings: DpdStyle,
    /// The model, seed and coefficients.
    pub ff: ForceField,
    /// Dense tables of the last set-up: coefficients, their kernel constants, cut-offs.
    table: Vec<PairCoeff>,
    ptable: PairTable,
    cut: Vec<f64>,
    dt: f64,
    special: [f64; 4],
    /// The style name its set-up messages give (`dpd/nonlinear`, or the many-body style that
    /// holds this one for its DPD part, `crate::forces::mdpd`).
    label: &'static str,
}

impl DpdPair {
    /// The style from the words after `pair_style dpd/nonlinear`, for `ntypes` types and time
    /// step `dt` (replaced at every set-up).
    pub fn new(args: &[String], ntypes: usize, dt: f64) -> Result<DpdPair, String> {
        let settings = grammar::pair_style(args)?;
        Ok(DpdPair::with_settings(settings, ntypes, dt, grammar::NAME))
    }

    /// The style of parsed `settings` with no coefficients yet, whose set-up messages name
    /// `label` (a style that holds a `DpdPair` for its DPD part).
    pub(crate) fn with_settings(
        settings: DpdStyle,
        ntypes: usize,
        dt: f64,
        label: &'static str,
    ) -> DpdPair {
        let ff = ForceField::new(settings.model(dt), settings.seed, settings.rc, ntypes);
        DpdPair {
            label,
            ..DpdPair::from_field_with(settings, ff)
        }
    }

    /// The style over a force field built by hand (tests, benchmarks).
    pub fn from_field(ff: ForceField) -> DpdPair {
        let m = &ff.model;
        let settings = DpdStyle {
            temp: m.kt,
            rc: ff.rc_global,
            seed: ff.seed,
            friction: m.friction,
            noise: m.noise,
            weight: m.weight,
            dist: m.dist,
        };
        DpdPair::from_field_with(settings, ff)
    }

    fn from_field_with(settings: DpdStyle, ff: ForceField) -> DpdPair {
        DpdPair {
            settings,
            ff,
            table: Vec::new(),
            ptable: PairTable::default(),
            cut: Vec::new(),
            dt: 0.0,
            special: [1.0; 4],
            label: grammar::NAME,
        }
    }

    /// The dense tables for time step `dt`: block 0 the coefficients; blocks 1–3 (the special
    /// classes 1-2, 1-3, 1-4) the same scaled by `special_lj`: f a and f γ0, so the pair keeps
    /// its fluctuation–dissipation balance (docs/models.md §4.8, P-22).
    fn build_tables(&mut self, dt: f64, special_lj: [f64; 4]) {
        self.dt = dt;
        self.special = special_lj;
        self.ff.model.set_timestep(dt);
        let block = self.ff.dense_table();
        self.cut = block.iter().map(|c| c.rc).collect();
        self.table = block.clone();
        for &f in &special_lj[1..] {
            self.table.extend(block.iter().map(|c| PairCoeff {
                a: f * c.a,
                gamma0: f * c.gamma0,
                ..*c
            }));
        }
        self.ptable = PairTable::new(&self.ff.model, &self.table);
    }

    /// The Euler heating warning for the pair with the largest `gamma0` (the worst case), in a
    /// unit style of mass × velocity² → energy factor `mvv2e`.
    fn euler_note(
        &self,
        dim: u32,
        density: f64,
        mass: f64,
        mvv2e: f64,
        dt: f64,
    ) -> Result<Option<String>, String> {
        let ff = &self.ff;
        let mut worst: Option<PairCoeff> = None;
        let mut conservative = false;
        for i in 1..=ff.ntypes() {
            for j in i..=ff.ntypes() {
                if let Some(c) = ff.get(i, j) {
                    conservative |= c.a != 0.0;
                    if worst.is_none_or(|w| c.gamma0 > w.gamma0) {
                        worst = Some(*c);
                    }
                }
            }
        }
        let Some(c) = worst else { return Ok(None) };
        crate::init::euler_warning(
            dim,
            density,
            c.rc,
            mass,
            ff.model.kt,
            mvv2e,
            c.gamma0,
            ff.model.weight.exponent(),
            dt,
            conservative,
            ff.model.friction != Friction::None,
        )
    }
}

impl PairStyle for DpdPair {
    fn name(&self) -> &'static str {
        grammar::NAME
    }

    fn ntypes(&self) -> usize {
        self.ff.ntypes()
    }

    /// As LAMMPS's `pair dpd`: the coefficients are kept and every cut-off is reset to the new
    /// global one. Friction `none` with a kept γ1 ≠ 0 is refused (the grammar's rule).
    fn restyle(&mut self, args: &[String]) -> Result<(), String> {
        let settings = grammar::pair_style(args)?;
        if settings.friction == Friction::None
            && let Some((i, j, g)) = self.ff.nonzero_gamma1()
        {
            return Err(format!(
                "friction none, but the kept pair_coeff {i} {j} has gamma1 = {g}, which must be \
                 0 with friction none (give the pair_coeff lines again after this pair_style)"
            ));
        }
        let mut ff = ForceField::new(
            settings.model(self.ff.model.timestep()),
            settings.seed,
            settings.rc,
            self.ff.ntypes(),
        );
        let n = self.ff.ntypes();
        for i in 1..=n {
            for j in i..=n {
                let Some(&c) = self.ff.get(i, j) else {
                    continue;
                };
                let c = PairCoeff {
                    rc: settings.rc,
                    ..c
                };
                match self.ff.target(i, j) {
                    Some((eta, sc)) => ff.set_targets(i, j, c, eta, sc),
                    None => ff.set(i, j, c),
                }
            }
        }
        self.settings = settings;
        self.ff = ff;
        Ok(())
    }

    fn coeff(&mut self, args: &[String]) -> Result<(), String> {
        let ff = &mut self.ff;
        let line = grammar::pair_coeff(args, ff.ntypes(), ff.model.friction, ff.rc_global)?;
        for (i, j) in line.pairs() {
            match line.targets {
                Some((eta, sc)) => ff.set_targets(i, j, line.coeff, eta, sc),
                None => ff.set(i, j, line.coeff),
            }
        }
        Ok(())
    }

    fn cutoff(&self, i: usize, j: usize) -> Option<f64> {
        self.ff.get(i, j).map(|c| c.rc)
    }

    /// Coefficients complete, the unit style's kT = boltz T and ftm2v in the model, (η, Sc)
    /// targets resolved (one per-type mass, T > 0), the Euler warning (T > 0), the dense
    /// tables. Per-atom masses need nothing here: the pair walk gives the kernel each pair's
    /// 1/m_i + 1/m_j.
    fn setup(&mut self, ctx: &SetupContext) -> Result<Vec<SetupNote>, String> {
        let mut notes = Vec::new();
        let subset = crate::forces::style::coverage(self, ctx)?;
        if subset && self.ff.has_targets() {
            return Err(crate::forces::style::targets_on_subset(
                grammar::NAME,
                "gamma0",
            ));
        }
        let u = ctx.units;
        self.ff.model.kt = u.kt(self.settings.temp);
        self.ff.model.set_ftm2v(u.ftm2v);
        notes.extend(
            u.temperature_note(self.label, self.settings.temp)
                .map(SetupNote::Info),
        );
        // The masses of the types in the style's own pairs (every type as the top-level style).
        let masses: Vec<f64> = (1..=self.ff.ntypes())
            .filter(|&t| self.covers_type(t))
            .filter_map(|t| ctx.mass.get(t).copied().flatten())
            .collect();
        let m_min = masses.iter().copied().fold(f64::INFINITY, f64::min);
        if self.ff.has_targets() {
            if ctx.per_atom_mass {
                return Err(format!(
                    "pair_coeff … eta … sc …: the (eta, Sc) design is for one particle mass (the \
                     kinetic theory of docs/models.md), but the atom style has per-atom masses, \
                     which may differ from atom to atom; pair_style {} uses each atom's own mass \
                     in its forces, so give gamma0 instead of eta and sc",
                    self.label
                ));
            }
            if masses.len() != self.ff.ntypes() {
                return Err(
                    "pair_coeff dpd/nonlinear eta ... sc ...: needs per-type masses".into(),
                );
            }
            if self.ff.model.kt == 0.0 {
                return Err(
                    "pair_coeff … eta … sc …: the (eta, Sc) design needs T > 0: the kinetic \
                     theory's viscosity and diffusion scale with kT, so at T = 0 no gamma0 gives \
                     the targets; give gamma0 instead of eta and sc"
                        .into(),
                );
            }
            if masses.iter().any(|&m| m != m_min) {
                return Err(
                    "pair_coeff … eta … sc …: the kinetic theory behind the design is \
                            for one particle mass, but the atom types have different masses"
                        .into(),
                );
            }
            for line in self
                .ff
                .resolve_targets(ctx.dim, ctx.density, m_min, u.mvv2e)?
            {
                notes.push(SetupNote::Info(line));
            }
        }
        // The finite-step prediction is for a thermostat at kT > 0 (T = 0: none to heat).
        if ctx.euler
            && self.ff.model.kt > 0.0
            && ctx.natoms > 0
            && !masses.is_empty()
            && let Some(w) = self.euler_note(ctx.dim, ctx.density, m_min, u.mvv2e, ctx.dt)?
        {
            notes.push(SetupNote::Warning(w));
        }
        self.build_tables(ctx.dt, ctx.special_lj);
        Ok(notes)
    }

    fn set_timestep(&mut self, dt: f64) {
        if dt != self.dt {
            self.build_tables(dt, self.special);
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
        Box::new(DpdKernel {
            model: &self.ff.model,
            table: &self.ptable,
            seed: self.ff.seed,
            isa,
        })
    }

    /// The conservative part, as LAMMPS's `pair dpd` `single()` returns it:
    /// F/r = a (1 − r/r_c) / r and E = a r_c (1 − r/r_c)² / 2 (docs/models.md §1.1).
    fn single(&self, i: usize, j: usize, rsq: f64) -> Option<(f64, f64)> {
        let c = self.ff.get(i, j)?;
        Some(c.conservative(rsq))
    }

    fn clone_box(&self) -> Box<dyn PairStyle> {
        Box::new(self.clone())
    }
}

impl StyleRecord for DpdPair {
    fn plan(&self, _units: &crate::units::Units, _dt: f64) -> Arc<dyn StylePlan> {
        let n = self.ff.ntypes();
        let coeffs = (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .filter_map(|(i, j)| self.ff.get(i, j).map(|c| (i, j, *c)))
            .collect();
        Arc::new(DpdPlan {
            model: self.ff.model,
            coeffs,
        })
    }
    fn restart_lines(&self) -> Vec<Vec<String>> {
        let settings = DpdStyle {
            weight: self.ff.model.weight,
            ..self.settings
        };
        let mut head = vec!["pair_style".to_string(), grammar::NAME.to_string()];
        head.extend(settings.to_words());
        let mut lines = vec![head];
        let n = self.ff.ntypes();
        for i in 1..=n {
            for j in i..=n {
                let Some(c) = self.ff.get(i, j) else { continue };
                let mut l = vec!["pair_coeff".into(), i.to_string(), j.to_string(), word(c.a)];
                match self.ff.target(i, j) {
                    Some((eta, sc)) => l.extend([
                        "eta".into(),
                        word(eta),
                        "sc".into(),
                        word(sc),
                        "gamma1".into(),
                        word(c.gamma1),
                        "rc".into(),
                        word(c.rc),
                    ]),
                    None => l.extend([word(c.gamma0), word(c.gamma1), word(c.rc)]),
                }
                lines.push(l);
            }
        }
        lines
    }
    /// `a gamma0 gamma1 rc` (LAMMPS's "Pair Coeffs" / "PairIJ Coeffs" sections).
    fn writes_data(&self) -> bool {
        true
    }
    fn data_coeffs(&self, i: usize, j: usize) -> Option<Vec<f64>> {
        self.ff
            .get(i, j)
            .map(|c| vec![c.a, c.gamma0, c.gamma1, c.rc])
    }
}

/// A planned run of a DPD-form style: its model (kT, friction, noise, weight; δt set) and (i, j,
/// coefficients) for i ≤ j, (η, Sc) targets resolved.
#[derive(Clone, Debug)]
pub struct DpdPlan {
    /// The model.
    pub model: PairModel,
    /// The pairs' coefficients.
    pub coeffs: Vec<(usize, usize, PairCoeff)>,
}

impl StylePlan for DpdPlan {
    fn kt(&self) -> Option<f64> {
        Some(self.model.kt)
    }
    fn weight_exponent(&self) -> Option<f64> {
        Some(self.model.weight.exponent())
    }
    fn summary(&self) -> Option<String> {
        Some(format!(
            "friction {}, noise {}, weight s = {}",
            self.model.friction.keyword(),
            self.model.noise.keyword(),
            short(self.model.weight.exponent())
        ))
    }
    /// The ideal fluid's kinetic theory of each pair with γ0 > 0 (a = 0; γ1 dropped: the
    /// zero-shear limit), docs/models.md 3.2; the finite-step theory applies with (γ0, s).
    fn pairs(&self, at: &PlanPoint) -> Result<Vec<PairPlan>, TheoryError> {
        let s = self.model.weight.exponent();
        let mut out = Vec::with_capacity(self.coeffs.len());
        for &(i, j, c) in &self.coeffs {
            let theory = if c.gamma0 <= 0.0 {
                Err("gamma0 = 0: no dissipation, no kinetic theory".to_string())
            } else {
                let fluid = at.fluid(c.rc, self.model.kt)?;
                Ok(PairTheory {
                    predicted: kinetic_theory(&fluid, c.gamma0, s)?,
                    fluid,
                    title: format!(
                        "kinetic theory of the ideal fluid, w_D = (1 - r/r_c)^s (docs/models.md 3.2){}{}",
                        if c.a != 0.0 {
                            "; a != 0 adds a conservative viscosity not in it"
                        } else {
                            ""
                        },
                        if c.gamma1 != 0.0 {
                            "; gamma0 only: the zero-shear limit of the non-linear friction"
                        } else {
                            ""
                        }
                    ),
                    finite_step: Some((c.gamma0, s)),
                })
            };
            out.push(PairPlan {
                i,
                j,
                label: None,
                coeffs: vec![
                    ("a", c.a),
                    ("gamma0", c.gamma0),
                    ("gamma1", c.gamma1),
                    ("rc", c.rc),
                ],
                words: Vec::new(),
                theory,
            });
        }
        Ok(out)
    }
}

/// `dpdnl design --method dpd`: γ and the weight exponent of `pair_style dpd/nonlinear`
/// (friction none, noise plain).
pub struct DpdDesign;

impl DesignMethod for DpdDesign {
    fn method(&self) -> &'static str {
        "dpd"
    }
    fn check(&self, design: &Design, fluid: &Fluid) -> Result<DesignCheck, String> {
        Ok(DesignCheck {
            values: vec![("gamma", design.gamma)],
            title: "check: kinetic theory of (gamma, s) with w_D = (1 - r/r_c)^s".to_string(),
            predicted: kinetic_theory(fluid, design.gamma, design.s).map_err(|e| e.to_string())?,
        })
    }
    fn lines_note(&self) -> &'static str {
        "input lines for LAMMPS and dpdnl (friction none, noise plain; set the seed you want)"
    }
    fn lines(&self, design: &Design, fluid: &Fluid, inputs: &DesignInputs) -> (String, String) {
        (
            format!(
                "pair_style {} {} {} {} weight {}",
                grammar::NAME,
                short(inputs.temp),
                short(fluid.cutoff),
                inputs.seed,
                short(design.s)
            ),
            format!("pair_coeff * * 0.0 {} 0.0", short(design.gamma)),
        )
    }
}
