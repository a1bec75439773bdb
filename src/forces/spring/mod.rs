//! `pair_style test/spring` (cargo feature `test-style`): the smallest pair style, a linear
//! spring with a cut-off ([`kernel`]), built only to show that a new pair style is its folder
//! (`grammar.rs`, `kernel.rs`, this file) and its two lines in `forces/mod.rs`. It has no
//! thermostat and no kinetic theory, so its plan keeps every default of [`StylePlan`].

use std::sync::Arc;

pub mod grammar;
pub mod kernel;

use crate::forces::batcher::PairKernel;
use crate::forces::plan::StylePlan;
use crate::forces::style::{PairStyle, SetupContext, SetupNote, StyleRecord, coverage, word};
use crate::forces::{Isa, PairBatch};
use kernel::{SpringCoeff, spring_batch, spring_pair};

/// `pair_style test/spring` + `pair_coeff`.
#[derive(Clone, Debug)]
pub struct SpringPair {
    ntypes: usize,
    /// The `pair_style` cut-off (the default of `pair_coeff`).
    rc: f64,
    /// The coefficients by dense type-pair index `i (ntypes + 1) + j` (`None`: not set).
    coeff: Vec<Option<SpringCoeff>>,
    /// The set-up's tables: coefficients and cut-offs (0 where unset).
    table: Vec<SpringCoeff>,
    cut: Vec<f64>,
}

impl SpringPair {
    /// A style from the words after its name, for `ntypes` types.
    pub fn new(args: &[String], ntypes: usize) -> Result<SpringPair, String> {
        let nn = (ntypes + 1) * (ntypes + 1);
        Ok(SpringPair {
            ntypes,
            rc: grammar::pair_style(args)?,
            coeff: vec![None; nn],
            table: Vec::new(),
            cut: Vec::new(),
        })
    }

    fn get(&self, i: usize, j: usize) -> Option<SpringCoeff> {
        *self.coeff.get(i * (self.ntypes + 1) + j)?
    }
}

impl PairStyle for SpringPair {
    fn name(&self) -> &'static str {
        grammar::NAME
    }
    fn ntypes(&self) -> usize {
        self.ntypes
    }
    /// A new default cut-off; every pair keeps its k and r_c.
    fn restyle(&mut self, args: &[String]) -> Result<(), String> {
        self.rc = grammar::pair_style(args)?;
        Ok(())
    }
    fn coeff(&mut self, args: &[String]) -> Result<(), String> {
        let (pairs, k, rc) = grammar::pair_coeff(args, self.ntypes, self.rc)?;
        let n = self.ntypes + 1;
        for (i, j) in pairs {
            self.coeff[i * n + j] = Some(SpringCoeff { k, rc });
            self.coeff[j * n + i] = Some(SpringCoeff { k, rc });
        }
        Ok(())
    }
    fn cutoff(&self, i: usize, j: usize) -> Option<f64> {
        self.get(i, j).map(|c| c.rc)
    }
    fn setup(&mut self, ctx: &SetupContext) -> Result<Vec<SetupNote>, String> {
        coverage(self, ctx)?;
        self.table = self.coeff.iter().map(|c| c.unwrap_or_default()).collect();
        self.cut = self.table.iter().map(|c| c.rc).collect();
        Ok(Vec::new())
    }
    fn cut_table(&self) -> &[f64] {
        &self.cut
    }
    fn kernel(&self, _isa: Isa) -> Box<dyn PairKernel + '_> {
        Box::new(SpringKernel(&self.table))
    }
    fn single(&self, i: usize, j: usize, rsq: f64) -> Option<(f64, f64)> {
        Some(spring_pair(&self.get(i, j)?, rsq))
    }
    fn clone_box(&self) -> Box<dyn PairStyle> {
        Box::new(self.clone())
    }
}

/// The batch kernel: [`spring_batch`] over the set-up's table.
struct SpringKernel<'a>(&'a [SpringCoeff]);

impl PairKernel for SpringKernel<'_> {
    fn evaluate(&self, _step: u64, b: &mut PairBatch, _i: &[u32], _j: &[u32]) {
        spring_batch(self.0, b);
    }
}

/// The plan of a style without a thermostat or kinetic theory: every default.
#[derive(Debug)]
struct SpringPlan;

impl StylePlan for SpringPlan {}

impl StyleRecord for SpringPair {
    fn restart_lines(&self) -> Vec<Vec<String>> {
        let mut lines = vec![vec![
            "pair_style".to_string(),
            grammar::NAME.to_string(),
            word(self.rc),
        ]];
        for i in 1..=self.ntypes {
            for j in i..=self.ntypes {
                if let Some(c) = self.get(i, j) {
                    lines.push(vec![
                        "pair_coeff".into(),
                        i.to_string(),
                        j.to_string(),
                        word(c.k),
                        word(c.rc),
                    ]);
                }
            }
        }
        lines
    }
    fn plan(&self, _units: &crate::units::Units, _dt: f64) -> Arc<dyn StylePlan> {
        Arc::new(SpringPlan)
    }
}
