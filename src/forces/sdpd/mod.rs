//! `pair_style sdpd` in the engine: its settings ([`SdpdField`]), their resolution at a run's
//! set-up (targets → η0 and s, the kernels and equations of state), the per-atom density
//! state between the two passes, and the [`PairKernel`] of the force pass ([`SdpdKernel`]).
//!
//! A force evaluation is two passes over the same pairs (`docs/models.md` §3.7):
//! 1. densities d_i = W_ii(0) + Σ_j W_ij(r_ij) (the pair loop's `pair_sum`), then per atom
//!    1/d_i, P_i/d_i² and the Tait energy u(d_i) ([`SdpdField::finish_densities`]);
//! 2. the pair forces of WF-12/19 through the same batch loop as `dpd/nonlinear`
//!    ([`SdpdKernel`]), so the forces are central and applied ±, momentum exactly conserved.

use std::sync::Arc;

pub mod grammar;
pub mod kernel;

use crate::fmtnum::short;
use crate::forces::batcher::PairKernel;
use crate::forces::plan::{
    DesignCheck, DesignInputs, DesignMethod, PairPlan, PairTheory, PlanPoint, StylePlan,
};
use crate::forces::style::{
    PairStyle, PrePass, SetupContext, SetupNote, StyleDerived, StyleRecord,
};
use crate::forces::{Isa, PairBatch};
use crate::theory::{Design, Dim, Fluid, TheoryError, sdpd as theory};
use grammar::{SdpdCoeffLine, SdpdStyle};
use kernel::{KernelShape, SdpdAtom, SdpdCoeff, Smoothing, Tait, sdpd_forces_batch};

/// One type pair's `pair_coeff` values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdpdPair {
    /// ρ0 (used from the I I line: a per-type property).
    pub rho0: f64,
    /// c_s (used from the I I line).
    pub c0: f64,
    /// η0 (a placeholder while `targets` is unresolved).
    pub eta0: f64,
    /// Kernel support.
    pub rc: f64,
    /// (η, Sc) targets.
    pub targets: Option<(f64, f64)>,
}

/// `pair_style sdpd` + `pair_coeff`, and the state of the current force evaluation.
#[derive(Clone, Debug)]
pub struct SdpdField {
    /// The style's settings (the kernel is replaced by the designed one at set-up when
    /// `pair_coeff … eta … sc …` is used).
    pub style: SdpdStyle,
    ntypes: usize,
    pairs: Vec<Option<SdpdPair>>,
    /// Dense per type-pair coefficients (index ti · (ntypes + 1) + tj), built at set-up.
    coeff: Vec<SdpdCoeff>,
    /// Squared cut-offs (0 for unset pairs).
    rcsq: Vec<f64>,
    /// The cut-offs by dense type-pair index (0 for unset pairs).
    cut: Vec<f64>,
    /// The words of every `pair_coeff` line applied, in order (replayed by `pair_style sdpd`
    /// given again, and stored in restart files).
    coeff_words: Vec<Vec<String>>,
    /// Per type: the equation of state and W(0) of the (t, t) kernel.
    tait: Vec<Option<Tait>>,
    w0: Vec<f64>,
    /// Per atom (the driver's order: engine order, or LAMMPS's owned + ghost atoms): the number
    /// density of the last evaluation.
    pub density: Vec<f64>,
    atoms: Vec<SdpdAtom>,
}

impl SdpdField {
    /// A field for `ntypes` types with no coefficients yet.
    pub fn new(style: SdpdStyle, ntypes: usize) -> SdpdField {
        let n = (ntypes + 1) * (ntypes + 1);
        SdpdField {
            style,
            ntypes,
            pairs: vec![None; n],
            coeff: Vec::new(),
            rcsq: Vec::new(),
            cut: Vec::new(),
            coeff_words: Vec::new(),
            tait: Vec::new(),
            w0: Vec::new(),
            density: Vec::new(),
            atoms: Vec::new(),
        }
    }

    /// The style from the words after `pair_style sdpd`, for `ntypes` types.
    pub fn from_words(args: &[String], ntypes: usize) -> Result<SdpdField, String> {
        Ok(SdpdField::new(grammar::pair_style(args)?, ntypes))
    }

    /// Number of atom types.
    pub fn ntypes(&self) -> usize {
        self.ntypes
    }

    /// Apply one parsed `pair_coeff` line.
    pub fn set_line(&mut self, line: &SdpdCoeffLine) {
        let p = SdpdPair {
            rho0: line.rho0,
            c0: line.c0,
            eta0: line.eta0,
            rc: line.rc,
            targets: line.targets,
        };
        let n = self.ntypes + 1;
        for (i, j) in line.pairs() {
            self.pairs[i * n + j] = Some(p);
            self.pairs[j * n + i] = Some(p);
        }
    }

    /// The values of a type pair, if set.
    pub fn get(&self, i: usize, j: usize) -> Option<&SdpdPair> {
        self.pairs.get(i * (self.ntypes + 1) + j)?.as_ref()
    }

    /// The first type pair without coefficients.
    pub fn missing(&self) -> Option<(usize, usize)> {
        (1..=self.ntypes)
            .flat_map(|i| (i..=self.ntypes).map(move |j| (i, j)))
            .find(|&(i, j)| self.get(i, j).is_none())
    }

    /// The largest cut-off.
    pub fn rc_max(&self) -> f64 {
        self.pairs
            .iter()
            .flatten()
            .map(|p| p.rc)
            .fold(0.0, f64::max)
    }

    /// Set-up of a run in unit style `units`: kT = boltz T, resolve (η, Sc) targets at number
    /// density `density` (one mass for all types), build every pair's kernel and coefficients
    /// for time step `dt` and the equation of state of every type in the style's pairs (every
    /// type as the top-level style; from its `I I` line) with its mass (its pressure
    /// c0² ρ0/7 × mvv2e, an energy per volume). Returns the lines to log.
    pub fn resolve(
        &mut self,
        dim: u32,
        density: f64,
        mass: &[Option<f64>],
        dt: f64,
        units: &crate::units::Units,
    ) -> Result<Vec<String>, String> {
        let n = self.ntypes + 1;
        let kt = units.kt(self.style.temp);
        let mut notes: Vec<String> = units
            .temperature_note(grammar::NAME, self.style.temp)
            .into_iter()
            .collect();
        let mut exponents: Vec<(String, f64)> = Vec::new();
        for i in 1..=self.ntypes {
            for j in i..=self.ntypes {
                let Some(p) = self.pairs[i * n + j] else {
                    continue;
                };
                let Some((eta, sc)) = p.targets else {
                    continue;
                };
                if kt == 0.0 {
                    return Err(format!(
                        "pair_coeff {i} {j} eta … sc …: the (eta, Sc) design needs T > 0: the \
                         kinetic theory's viscosity and diffusion scale with kT, so at T = 0 no \
                         eta0 gives the targets; give eta0 instead of eta and sc"
                    ));
                }
                let m = mass[i].unwrap_or(1.0);
                if mass[j] != mass[i] {
                    return Err(format!(
                        "pair_coeff {i} {j} eta … sc …: the kinetic theory behind the design is for \
                         one particle mass, but types {i} and {j} have different masses"
                    ));
                }
                let label = format!("{i} {j}");
                let fail = |e: crate::theory::TheoryError| {
                    format!(
                        "pair_coeff {label} eta {} sc {}: {e}",
                        crate::fmtnum::fmt_g(eta),
                        crate::fmtnum::fmt_g(sc)
                    )
                };
                let fluid = crate::theory::Fluid::new(dim, density, p.rc, m, kt)
                    .and_then(|f| f.with_mvv2e(units.mvv2e))
                    .map_err(fail)?;
                let d =
                    crate::theory::design_from_targets(&crate::theory::Targets { fluid, eta, sc })
                        .map_err(fail)?;
                let q = SdpdPair { eta0: d.eta0, ..p };
                self.pairs[i * n + j] = Some(q);
                self.pairs[j * n + i] = Some(q);
                notes.push(format!(
                    "pair_coeff {label} eta {eta} sc {sc} at n = {density}: eta0 = {}, kernel \
                     proposed s = {} (sDPD kinetic theory, docs/models.md 3.7)",
                    d.eta0, d.s
                ));
                exponents.push((label, d.s));
            }
        }
        let current = self.style.kernel.exponent().unwrap_or(0.0);
        if let Some((s, note)) =
            crate::init::common_exponent(self.name(), "kernel", &exponents, current)?
        {
            self.style.kernel = Smoothing::proposed(s)
                .ok_or_else(|| format!("designed kernel exponent s = {s} is not > 0"))?;
            notes.extend(note);
        }
        // Per-type equations of state from the (t, t) lines; cross lines' rho0/c0 are not used.
        self.tait = vec![None; n];
        self.w0 = vec![0.0; n];
        for t in 1..=self.ntypes {
            // A type in none of the style's pairs (a sub-style of `pair_style hybrid`) has no
            // equation of state here: its atoms get no density, energy or force from sdpd.
            if !self.covers_type(t) {
                continue;
            }
            let p = self.pairs[t * n + t].ok_or_else(|| {
                match (1..=self.ntypes).find(|&u| self.pairs[t * n + u].is_some()) {
                    Some(u) => format!(
                        "pair_style sdpd covers type pair {t} {u} but not {t} {t}: a type's \
                         equation of state (rho0, c0) and self density come from its pair_coeff \
                         {t} {t} line, so a type in any pair of the style needs that line too"
                    ),
                    None => format!("pair coefficients for types {t} {t} are not set (pair_coeff)"),
                }
            })?;
            let m = mass[t].ok_or_else(|| format!("mass of atom type {t} is not set (mass)"))?;
            let tait = Tait::in_units(p.rho0, p.c0, m, units.mvv2e)
                .map_err(|e| format!("pair_coeff {t} {t}: {e}"))?;
            self.tait[t] = Some(tait);
            self.w0[t] = KernelShape::new(self.style.kernel, dim, p.rc)?.w0();
        }
        for i in 1..=self.ntypes {
            for j in i + 1..=self.ntypes {
                if let (Some(p), Some(a), Some(b)) = (
                    self.pairs[i * n + j],
                    self.pairs[i * n + i],
                    self.pairs[j * n + j],
                ) && (p.rho0, p.c0) != (a.rho0, a.c0)
                    && (p.rho0, p.c0) != (b.rho0, b.c0)
                {
                    notes.push(format!(
                        "WARNING: pair_coeff {i} {j}: rho0 = {} and c0 = {} are not used: the \
                         equation of state is per type, from pair_coeff {i} {i} and {j} {j}",
                        p.rho0, p.c0
                    ));
                }
            }
        }
        let placeholder =
            SdpdCoeff::new(KernelShape::new(Smoothing::Lucy, dim, 1.0)?, 1.0, kt, dt)?;
        self.coeff = vec![placeholder; n * n];
        self.rcsq = vec![0.0; n * n];
        self.cut = vec![0.0; n * n];
        for i in 1..=self.ntypes {
            for j in 1..=self.ntypes {
                if let Some(p) = self.pairs[i * n + j] {
                    let shape = KernelShape::new(self.style.kernel, dim, p.rc)?;
                    self.coeff[i * n + j] = SdpdCoeff::new(shape, p.eta0, kt, dt)
                        .map_err(|e| format!("pair_coeff {i} {j}: {e}"))?;
                    self.rcsq[i * n + j] = p.rc * p.rc;
                    self.cut[i * n + j] = p.rc;
                }
            }
        }
        Ok(notes)
    }

    /// Squared cut-offs by dense type-pair index (after [`SdpdField::resolve`]).
    pub fn rcsq(&self) -> &[f64] {
        &self.rcsq
    }

    /// The pair coefficients by dense type-pair index (after [`SdpdField::resolve`]).
    pub fn coeffs(&self) -> &[SdpdCoeff] {
        &self.coeff
    }

    /// W of the pair with dense index `k` at squared distance `rsq` (0 beyond its cut-off).
    #[inline(always)]
    pub fn w_pair(&self, k: usize, rsq: f64) -> f64 {
        if rsq < self.rcsq[k] {
            self.coeff[k].shape.w(rsq.sqrt())
        } else {
            0.0
        }
    }

    /// W(0) of type `t`'s kernel: the self term of its density (after [`SdpdField::resolve`]).
    pub fn self_density(&self, t: usize) -> f64 {
        self.w0[t]
    }

    /// The equation of state of an atom of type `t` and, with per-atom masses, mass `m` (the
    /// type's with that mass, [`Tait::with_mass`]); `None` for a type outside the style's pairs.
    #[inline]
    fn tait_of(&self, t: usize, m: Option<f64>) -> Option<Tait> {
        let tait = self.tait[t]?;
        Some(m.map_or(tait, |m| tait.with_mass(m)))
    }

    /// 1/d and P/d² of an atom of type `t` at number density `d` (after resolve).
    #[inline]
    pub fn atom_terms(&self, t: usize, d: f64) -> SdpdAtom {
        self.atom_terms_of(t, d, None)
    }

    /// [`SdpdField::atom_terms`] of an atom of mass `m` when given (per-atom masses).
    #[inline]
    pub fn atom_terms_of(&self, t: usize, d: f64, m: Option<f64>) -> SdpdAtom {
        match self.tait_of(t, m) {
            Some(tait) => SdpdAtom {
                inv_d: 1.0 / d,
                pterm: tait.pressure_term(d),
            },
            None => SdpdAtom::default(),
        }
    }

    /// The Tait energy u(d) of an atom of type `t` (after resolve).
    #[inline]
    pub fn atom_energy(&self, t: usize, d: f64) -> f64 {
        self.tait[t].map_or(0.0, |tait| tait.energy(d))
    }

    /// The pre-pass energy of an atom of type `t`, mass `m` when given, at density `d`: `None`
    /// when its pressure is not finite.
    fn energy_with(&self, t: usize, d: f64, m: Option<f64>) -> Option<f64> {
        let tait = self.tait_of(t, m);
        self.atom_terms_of(t, d, m)
            .pterm
            .is_finite()
            .then(|| tait.map_or(0.0, |tait| tait.energy(d)))
    }
}

impl PrePass for SdpdField {
    fn rcsq(&self) -> &[f64] {
        &self.rcsq
    }

    #[inline(always)]
    fn weight(&self, k: usize, rsq: f64) -> f64 {
        self.w_pair(k, rsq)
    }

    fn weights(&self, k: usize, rsq: &[f64], out: &mut [f64]) {
        self.coeff[k].shape.w_of_squares(rsq, out)
    }

    fn complete(&self, t: usize, sum: f64) -> f64 {
        sum + self.w0[t]
    }

    fn energy_of(&self, t: usize, d: f64) -> Option<f64> {
        self.energy_with(t, d, None)
    }

    /// The Tait energy with the atom's own mass (per-atom masses: ρ_i = m_i d_i).
    fn energy_of_mass(&self, t: usize, d: f64, m: f64) -> Option<f64> {
        self.energy_with(t, d, Some(m))
    }

    fn fault(&self, who: &str, d: f64, step: u64) -> String {
        format!(
            "sdpd at step {step}: the Tait pressure of atom {who} is not finite (number density \
             d = {d}); reduce the time step or raise c0"
        )
    }
}

impl PairStyle for SdpdField {
    fn name(&self) -> &'static str {
        grammar::NAME
    }

    fn ntypes(&self) -> usize {
        self.ntypes
    }

    /// The new settings with every `pair_coeff` line applied again (so a line the new settings
    /// refuse is an error here), as LAMMPS keeps a style's coefficients.
    fn restyle(&mut self, args: &[String]) -> Result<(), String> {
        let mut next = SdpdField::from_words(args, self.ntypes)?;
        for line in &self.coeff_words {
            next.coeff(line)?;
        }
        *self = next;
        Ok(())
    }

    fn coeff(&mut self, args: &[String]) -> Result<(), String> {
        let line = grammar::pair_coeff(args, self.ntypes, &self.style)?;
        self.set_line(&line);
        self.coeff_words.push(args.to_vec());
        Ok(())
    }

    fn cutoff(&self, i: usize, j: usize) -> Option<f64> {
        self.get(i, j).map(|p| p.rc)
    }

    fn setup(&mut self, ctx: &SetupContext) -> Result<Vec<SetupNote>, String> {
        let subset = crate::forces::style::coverage(self, ctx)?;
        if subset && self.pairs.iter().flatten().any(|p| p.targets.is_some()) {
            return Err(crate::forces::style::targets_on_subset(
                grammar::NAME,
                "eta0",
            ));
        }
        // Per-type masses of the types in the style's own pairs (every type as the top-level
        // style), unless the atom style has per-atom masses: then each atom's own mass enters
        // its equation of state at every evaluation (`set_atom_values`, `energy_of_mass`).
        let placeholder = vec![Some(1.0); self.ntypes + 1];
        let mass = if ctx.per_atom_mass {
            if self.pairs.iter().flatten().any(|p| p.targets.is_some()) {
                return Err(
                    "pair_coeff … eta … sc …: the (eta, Sc) design is for one particle mass (the \
                     sDPD kinetic theory of docs/models.md 3.7), but the atom style has per-atom \
                     masses, which may differ from atom to atom; give eta0 instead of eta and sc"
                        .into(),
                );
            }
            &placeholder[..]
        } else {
            if let Some(t) = (1..=self.ntypes)
                .find(|&t| self.covers_type(t) && ctx.mass.get(t).is_none_or(Option::is_none))
            {
                return Err(format!("mass of atom type {t} is not set (mass)"));
            }
            ctx.mass
        };
        let lines = self.resolve(ctx.dim, ctx.density, mass, ctx.dt, &ctx.units)?;
        Ok(lines
            .into_iter()
            .map(|line| match line.strip_prefix("WARNING: ") {
                Some(w) => SetupNote::Warning(w.to_string()),
                None => SetupNote::Info(line),
            })
            .collect())
    }

    fn cut_table(&self) -> &[f64] {
        &self.cut
    }

    fn prepass(&self) -> Option<&dyn PrePass> {
        Some(self)
    }

    /// Each atom's 1/d and P/d², with its own mass where the atom style has per-atom masses
    /// (ρ_i = m_i d_i in the equation of state of its type).
    fn set_atom_values(&mut self, values: &[f64], typ: &[u32], mass: Option<&[f64]>) {
        let mut atoms = std::mem::take(&mut self.atoms);
        atoms.clear();
        match mass {
            None => atoms.extend(
                typ.iter()
                    .zip(values)
                    .map(|(&t, &d)| self.atom_terms(t as usize, d)),
            ),
            Some(m) => atoms.extend(
                typ.iter()
                    .zip(values)
                    .zip(m)
                    .map(|((&t, &d), &m)| self.atom_terms_of(t as usize, d, Some(m))),
            ),
        }
        self.atoms = atoms;
        self.density.clear();
        self.density.extend_from_slice(values);
    }

    fn kernel(&self, isa: Isa) -> Box<dyn PairKernel + '_> {
        Box::new(SdpdKernel {
            coeff: &self.coeff,
            atoms: &self.atoms,
            seed: self.style.seed,
            isa,
        })
    }

    fn clone_box(&self) -> Box<dyn PairStyle> {
        Box::new(self.clone())
    }
}

/// Pass 2 of `pair_style sdpd`: the forces of WF-12/19 with the keyed pair Gaussian of the
/// lane's tags ([`sdpd_forces_batch`], bit for bit `kernel::sdpd_pair_force`).
pub(crate) struct SdpdKernel<'a> {
    coeff: &'a [SdpdCoeff],
    atoms: &'a [SdpdAtom],
    seed: u32,
    /// The instruction set of the lane loops (the same bits with every one).
    pub isa: Isa,
}

impl PairKernel for SdpdKernel<'_> {
    #[inline]
    fn evaluate(&self, step: u64, b: &mut PairBatch, i: &[u32], j: &[u32]) {
        sdpd_forces_batch(self.isa, self.coeff, self.atoms, self.seed, step, b, i, j);
    }
}

impl StyleRecord for SdpdField {
    fn plan(&self, units: &crate::units::Units, _dt: f64) -> Arc<dyn StylePlan> {
        let n = self.ntypes;
        let pairs = (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .filter_map(|(i, j)| self.get(i, j).map(|p| (i, j, *p)))
            .collect();
        Arc::new(SdpdPlan {
            kt: units.kt(self.style.temp),
            kernel: self.style.kernel,
            pairs,
        })
    }
    fn atom_values(&self) -> Option<&[f64]> {
        Some(&self.density)
    }
    /// The `pair_style` line of the current settings (the kernel a design chose) and the
    /// `pair_coeff` lines as given.
    fn restart_lines(&self) -> Vec<Vec<String>> {
        let mut head = vec!["pair_style".to_string(), grammar::NAME.to_string()];
        head.extend(self.style.to_words());
        let mut lines = vec![head];
        for w in &self.coeff_words {
            lines.push(
                std::iter::once("pair_coeff".to_string())
                    .chain(w.iter().cloned())
                    .collect(),
            );
        }
        lines
    }
    /// `rho0 c0 eta0 rc` (η0 as resolved at the last set-up).
    fn writes_data(&self) -> bool {
        true
    }
    fn data_coeffs(&self, i: usize, j: usize) -> Option<Vec<f64>> {
        self.get(i, j).map(|p| vec![p.rho0, p.c0, p.eta0, p.rc])
    }
}

/// A planned run of `pair_style sdpd` (targets resolved).
#[derive(Clone, Debug)]
pub struct SdpdPlan {
    /// kT of the random force (boltz T, an energy).
    pub kt: f64,
    /// The kernel (the designed one when targets were given).
    pub kernel: Smoothing,
    /// (i, j, values) for i ≤ j.
    pub pairs: Vec<(usize, usize, SdpdPair)>,
}

impl StylePlan for SdpdPlan {
    fn kt(&self) -> Option<f64> {
        Some(self.kt)
    }
    /// 2, whatever the kernel: the value a run's record has always shown for `sdpd` (the
    /// standard DPD weight's; each pair's `kernel` names the kernel).
    fn weight_exponent(&self) -> Option<f64> {
        Some(2.0)
    }
    fn summary(&self) -> Option<String> {
        Some(format!(
            "pair_style {}, kernel {}",
            grammar::NAME,
            self.kernel
        ))
    }
    /// The ideal sDPD fluid's kinetic theory of each pair (docs/models.md 3.7, Table 1).
    fn pairs(&self, at: &PlanPoint) -> Result<Vec<PairPlan>, TheoryError> {
        let mut out = Vec::with_capacity(self.pairs.len());
        for &(i, j, p) in &self.pairs {
            let fluid = at.fluid(p.rc, self.kt)?;
            out.push(PairPlan {
                i,
                j,
                label: Some(format!("{}, kernel {}", grammar::NAME, self.kernel)),
                coeffs: vec![
                    ("rho0", p.rho0),
                    ("c0", p.c0),
                    ("eta0", p.eta0),
                    ("rc", p.rc),
                ],
                words: vec![("kernel", self.kernel.keyword())],
                theory: Ok(PairTheory {
                    predicted: theory::kinetic_theory(&fluid, self.kernel, p.eta0)?,
                    fluid,
                    title:
                        "kinetic theory of sDPD (docs/models.md 3.7, Table 1; the Tait pressure \
                            adds a conservative viscosity not in it)"
                            .to_string(),
                    finite_step: None,
                }),
            });
        }
        Ok(out)
    }
}

/// `dpdnl design --method sdpd`: η0 and the proposed kernel's s of `pair_style sdpd` (the same
/// kinetic theory as DPD's, docs/models.md 3.7).
pub struct SdpdDesign;

impl DesignMethod for SdpdDesign {
    fn method(&self) -> &'static str {
        "sdpd"
    }
    fn check(&self, design: &Design, fluid: &Fluid) -> Result<DesignCheck, String> {
        let kernel = Smoothing::proposed(design.s).ok_or("designed s is not > 0")?;
        Ok(DesignCheck {
            values: Vec::new(),
            title: format!(
                "check: kinetic theory of the proposed sDPD kernel with (eta0, s) (Table 1, eq. {})",
                if fluid.dim == Dim::Three { "45" } else { "60" }
            ),
            predicted: theory::kinetic_theory(fluid, kernel, design.eta0)
                .map_err(|e| e.to_string())?,
        })
    }
    fn lines_note(&self) -> &'static str {
        "input lines for LAMMPS and dpdnl (rho0 = m n; choose the sound speed c0 so that the \
         density fluctuates little, docs/models.md 3.7; set the seed you want)"
    }
    fn lines(&self, design: &Design, fluid: &Fluid, inputs: &DesignInputs) -> (String, String) {
        (
            format!(
                "pair_style {} {} {} {} kernel proposed {}",
                grammar::NAME,
                short(inputs.temp),
                short(fluid.cutoff),
                inputs.seed,
                short(design.s)
            ),
            format!(
                "pair_coeff * * {} {} {}",
                short(fluid.mass * fluid.density),
                inputs.c0.map_or("C0".to_string(), short),
                short(design.eta0)
            ),
        )
    }
}
