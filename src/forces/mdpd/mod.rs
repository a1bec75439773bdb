//! `pair_style mdpd/nonlinear`: many-body DPD (Warren 2003; LAMMPS's `mdpd/rhosum` + `mdpd`)
//! with the non-linear friction and noise schemes of `dpd/nonlinear` (docs/models.md §4.10).
//!
//! A force evaluation is two passes over the same pairs, through the seam every many-body style
//! uses ([`PrePass`]):
//! 1. the densities ρ̄_i = Σ_j m_j w_ρ(r_ij) (P-27, no self term);
//! 2. the pair forces: `dpd/nonlinear`'s kernel with a = A (the conservative, dissipative and
//!    random forces of the chosen friction and noise, NL-4–52), plus the many-body repulsion
//!    B (ρ̄_i + ρ̄_j) w_d(r) (P-28), central and applied ±, so momentum is conserved exactly.
//!
//! The DPD part is a [`DpdPair`] (its model, coefficient table, special blocks and set-up);
//! this style adds B and r_d per type pair, the density weight and the densities.

use std::sync::Arc;

pub mod grammar;
pub mod kernel;

use crate::forces::batcher::PairKernel;
use crate::forces::dpd::grammar::DpdStyle;
use crate::forces::dpd::kernel::{Friction, PairCoeff};
use crate::forces::dpd::{DpdPair, DpdPlan};
use crate::forces::plan::StylePlan;
use crate::forces::style::{
    PairStyle, PrePass, SetupContext, SetupNote, StyleDerived, StyleRecord, word,
};
use crate::forces::{Isa, PairBatch};
use kernel::{DensityWeight, ManyBodyCoeff, add_many_body};

/// `pair_style mdpd/nonlinear` + `pair_coeff`, and the densities of the current evaluation.
#[derive(Clone, Debug)]
pub struct MdpdPair {
    /// The settings as given.
    settings: DpdStyle,
    /// The DPD part: A (as `a`), γ0, γ1, r_c per type pair, the model and its tables.
    dpd: DpdPair,
    /// B and r_d per dense type-pair index (`None`: not set).
    many: Vec<Option<ManyBodyCoeff>>,
    /// The set-up's tables: B and r_d in four blocks (the plain pairs and the special classes
    /// 1–3, B scaled by their `special_lj` factors), the density weights and r_d².
    table: Vec<ManyBodyCoeff>,
    weights: Vec<DensityWeight>,
    rdsq: Vec<f64>,
    special: [f64; 4],
    /// The densities of the last pre-pass, in the driver's atom order.
    rho: Vec<f64>,
}

impl MdpdPair {
    /// The style from the words after `pair_style mdpd/nonlinear`, for `ntypes` types and time
    /// step `dt` (replaced at every set-up).
    pub fn new(args: &[String], ntypes: usize, dt: f64) -> Result<MdpdPair, String> {
        let settings = grammar::pair_style(args)?;
        Ok(MdpdPair {
            settings,
            dpd: DpdPair::with_settings(settings, ntypes, dt, grammar::NAME),
            many: vec![None; (ntypes + 1) * (ntypes + 1)],
            table: Vec::new(),
            weights: Vec::new(),
            rdsq: Vec::new(),
            special: [1.0; 4],
            rho: Vec::new(),
        })
    }

    /// The DPD part and the many-body part of type pair (i, j), if set.
    pub fn get(&self, i: usize, j: usize) -> Option<(PairCoeff, ManyBodyCoeff)> {
        let c = *self.dpd.ff.get(i, j)?;
        let m = (*self.many.get(i * (self.ntypes() + 1) + j)?)?;
        Some((c, m))
    }

    fn set(&mut self, i: usize, j: usize, c: PairCoeff, m: ManyBodyCoeff) {
        let n = self.ntypes() + 1;
        self.dpd.ff.set(i, j, c);
        self.many[i * n + j] = Some(m);
        self.many[j * n + i] = Some(m);
    }

    /// B in four blocks: the plain pairs, then the special classes 1-2, 1-3, 1-4 scaled by
    /// their `special_lj` factors, as the DPD part's A and γ0 (docs/models.md P-22).
    fn build_table(&mut self, special_lj: [f64; 4]) {
        self.special = special_lj;
        let block: Vec<ManyBodyCoeff> = self.many.iter().map(|m| m.unwrap_or_default()).collect();
        self.table = block.clone();
        for &f in &special_lj[1..] {
            self.table
                .extend(block.iter().map(|m| ManyBodyCoeff { b: f * m.b, ..*m }));
        }
    }
}

impl PrePass for MdpdPair {
    fn rcsq(&self) -> &[f64] {
        &self.rdsq
    }

    #[inline(always)]
    fn weight(&self, k: usize, rsq: f64) -> f64 {
        self.weights[k].w(rsq)
    }

    fn weights(&self, k: usize, rsq: &[f64], out: &mut [f64]) {
        self.weights[k].w_of_squares(rsq, out)
    }

    /// m_j w_ρ(r_ij) with the neighbour's own mass (per-atom masses: P-27 as written).
    #[inline(always)]
    fn weight_of(&self, k: usize, rsq: f64, m: f64) -> f64 {
        self.weights[k].w_mass(rsq, m)
    }

    /// No self term: ρ̄_i sums the other atoms only (Warren 2003; LAMMPS's `mdpd/rhosum`).
    fn complete(&self, _t: usize, sum: f64) -> f64 {
        sum
    }

    /// The many-body energy is tallied pair by pair (P-29), as LAMMPS's `mdpd` does, so an atom
    /// adds none of its own.
    fn energy_of(&self, _t: usize, d: f64) -> Option<f64> {
        d.is_finite().then_some(0.0)
    }

    fn fault(&self, who: &str, d: f64, step: u64) -> String {
        format!(
            "{} at step {step}: the density of atom {who} is not finite ({d}); reduce the time \
             step",
            grammar::NAME
        )
    }
}

impl PairStyle for MdpdPair {
    fn name(&self) -> &'static str {
        grammar::NAME
    }

    fn ntypes(&self) -> usize {
        self.dpd.ntypes()
    }

    /// New settings; every pair keeps its coefficients as given, its r_c and r_d included
    /// (each `pair_coeff` line gives them). Friction `none` with a kept γ1 ≠ 0 is refused.
    fn restyle(&mut self, args: &[String]) -> Result<(), String> {
        let settings = grammar::pair_style(args)?;
        let n = self.ntypes();
        let kept: Vec<_> = (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .filter_map(|(i, j)| self.get(i, j).map(|p| (i, j, p)))
            .collect();
        if settings.friction == Friction::None
            && let Some((i, j, (c, _))) = kept.iter().find(|(_, _, (c, _))| c.gamma1 != 0.0)
        {
            return Err(format!(
                "friction none, but the kept pair_coeff {i} {j} has gamma1 = {}, which must be \
                 0 with friction none (give the pair_coeff lines again after this pair_style)",
                c.gamma1
            ));
        }
        let dt = self.dpd.ff.model.timestep();
        let mut next = MdpdPair::new(args, n, dt)?;
        for (i, j, (c, m)) in kept {
            next.set(i, j, c, m);
        }
        *self = next;
        Ok(())
    }

    fn coeff(&mut self, args: &[String]) -> Result<(), String> {
        let line = grammar::pair_coeff(args, self.ntypes(), self.settings.friction)?;
        let m = ManyBodyCoeff {
            b: line.b,
            rd: line.rd,
        };
        for (i, j) in line.pairs() {
            self.set(i, j, line.coeff, m);
        }
        Ok(())
    }

    fn cutoff(&self, i: usize, j: usize) -> Option<f64> {
        self.dpd.cutoff(i, j)
    }

    /// The DPD part's set-up (coverage, kT = boltz T, the Euler warning, its tables), then, with
    /// per-type masses, one mass for the style's types (the density sum is symmetric only
    /// then; per-atom masses take each neighbour's own), the density weights and the
    /// many-body table.
    fn setup(&mut self, ctx: &SetupContext) -> Result<Vec<SetupNote>, String> {
        let mut notes = self.dpd.setup(ctx)?;
        let n = self.ntypes();
        let mut mass: Option<(usize, f64)> = None;
        // Per-atom masses: each neighbour's own mass at every pre-pass (`weight_of`), any
        // masses; the table's weights are for mass 1 and unused.
        let per_type = if ctx.per_atom_mass { 0 } else { n };
        for t in (1..=per_type).filter(|&t| self.covers_type(t)) {
            let m = ctx
                .mass
                .get(t)
                .copied()
                .flatten()
                .ok_or_else(|| format!("mass of atom type {t} is not set (mass)"))?;
            match mass {
                None => mass = Some((t, m)),
                Some((u, mu)) if mu != m => {
                    return Err(format!(
                        "pair_style {}: types {u} and {t} have different masses ({mu} and {m}); \
                         the density sum weights each neighbour by its mass (as LAMMPS's \
                         mdpd/rhosum does), which is symmetric in a pair only for one mass, so \
                         this version needs one mass for every type of the style",
                        grammar::NAME
                    ));
                }
                Some(_) => {}
            }
        }
        let m = mass.map_or(1.0, |(_, m)| m);
        let nn = (n + 1) * (n + 1);
        self.weights = vec![DensityWeight::default(); nn];
        self.rdsq = vec![0.0; nn];
        for (k, p) in self.many.iter().enumerate() {
            if let Some(p) = p {
                self.weights[k] = DensityWeight::new(p.rd, m);
                self.rdsq[k] = p.rd * p.rd;
            }
        }
        self.build_table(ctx.special_lj);
        if ctx.dim == 2 {
            notes.push(SetupNote::Info(format!(
                "pair_style {}: in 2-D the density weight keeps the 3-D Lucy normalisation \
                 105/(16 pi rd^3), as LAMMPS's mdpd/rhosum does (a density per volume, not per \
                 area: B and the coexistence densities are those of a LAMMPS 2-D mdpd run)",
                grammar::NAME
            )));
        }
        Ok(notes)
    }

    fn set_timestep(&mut self, dt: f64) {
        self.dpd.set_timestep(dt);
    }

    fn cut_table(&self) -> &[f64] {
        self.dpd.cut_table()
    }

    /// The DPD part scales A and γ0 by a pair's `special_lj` factor (P-22), and B with them, as
    /// LAMMPS's `mdpd` scales the whole conservative force; the density sum counts every
    /// neighbour that is not excluded (factor 0) in full, as `mdpd/rhosum` does.
    fn scales_special(&self) -> bool {
        true
    }

    fn set_special(&mut self, special_lj: [f64; 4]) {
        self.dpd.set_special(special_lj);
        if special_lj != self.special {
            self.build_table(special_lj);
        }
    }

    fn prepass(&self) -> Option<&dyn PrePass> {
        Some(self)
    }

    fn set_atom_values(&mut self, values: &[f64], _typ: &[u32], _mass: Option<&[f64]>) {
        self.rho.clear();
        self.rho.extend_from_slice(values);
    }

    fn kernel(&self, isa: Isa) -> Box<dyn PairKernel + '_> {
        Box::new(MdpdKernel {
            dpd: self.dpd.kernel(isa),
            many: &self.table,
            rho: &self.rho,
        })
    }

    fn clone_box(&self) -> Box<dyn PairStyle> {
        Box::new(self.clone())
    }
}

/// Pass 2: `dpd/nonlinear`'s batch kernel, then the many-body repulsion of each lane
/// ([`add_many_body`]).
struct MdpdKernel<'a> {
    dpd: Box<dyn PairKernel + 'a>,
    many: &'a [ManyBodyCoeff],
    rho: &'a [f64],
}

impl PairKernel for MdpdKernel<'_> {
    #[inline]
    fn evaluate(&self, step: u64, b: &mut PairBatch, i: &[u32], j: &[u32]) {
        self.dpd.evaluate(step, b, i, j);
        add_many_body(self.many, self.rho, b, i, j);
    }
}

impl StyleRecord for MdpdPair {
    fn plan(&self, _units: &crate::units::Units, _dt: f64) -> Arc<dyn StylePlan> {
        Arc::new(MdpdPlan(DpdPlan {
            model: self.dpd.ff.model,
            coeffs: Vec::new(),
        }))
    }

    fn atom_values(&self) -> Option<&[f64]> {
        Some(&self.rho)
    }

    /// The `pair_style` line of the current settings and one `pair_coeff I J A B gamma0 rc rd
    /// gamma1` line per set pair (numbers with 17 significant digits).
    fn restart_lines(&self) -> Vec<Vec<String>> {
        let mut head = vec!["pair_style".to_string(), grammar::NAME.to_string()];
        head.extend(self.settings.to_words());
        let mut lines = vec![head];
        let n = self.ntypes();
        for i in 1..=n {
            for j in i..=n {
                let Some((c, m)) = self.get(i, j) else {
                    continue;
                };
                lines.push(vec![
                    "pair_coeff".into(),
                    i.to_string(),
                    j.to_string(),
                    word(c.a),
                    word(m.b),
                    word(c.gamma0),
                    word(c.rc),
                    word(m.rd),
                    word(c.gamma1),
                ]);
            }
        }
        lines
    }

    /// `A B gamma0 rc rd` (and `gamma1` when it is not 0): a `pair_coeff` line's numbers, so
    /// that `read_data` gives them back.
    fn writes_data(&self) -> bool {
        true
    }

    fn data_coeffs(&self, i: usize, j: usize) -> Option<Vec<f64>> {
        self.get(i, j).map(|(c, m)| {
            let mut v = vec![c.a, m.b, c.gamma0, c.rc, m.rd];
            if c.gamma1 != 0.0 {
                v.push(c.gamma1);
            }
            v
        })
    }
}

/// A planned run of `pair_style mdpd/nonlinear`: the model of its DPD part; no pair-wise kinetic
/// theory applies to a many-body style.
#[derive(Clone, Debug)]
pub struct MdpdPlan(pub DpdPlan);

impl StylePlan for MdpdPlan {
    fn kt(&self) -> Option<f64> {
        self.0.kt()
    }
    fn weight_exponent(&self) -> Option<f64> {
        self.0.weight_exponent()
    }
    fn summary(&self) -> Option<String> {
        self.0.summary()
    }
    fn notes(&self) -> Vec<SetupNote> {
        vec![SetupNote::Info(format!(
            "pair_style {} is many-body: the ideal-fluid kinetic theory does not apply to it, so \
             no pair has a prediction",
            grammar::NAME
        ))]
    }
}
