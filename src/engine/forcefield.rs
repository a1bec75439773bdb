//! The pair style's settings as the engine holds them: the global [`PairModel`], the seed and
//! the per type-pair [`PairCoeff`] table.

use crate::kernel::{PairCoeff, PairModel};

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
        }
    }

    /// Number of atom types.
    pub fn ntypes(&self) -> usize {
        self.ntypes
    }

    /// Set the coefficients of types (i, j) and (j, i).
    pub fn set(&mut self, i: usize, j: usize, c: PairCoeff) {
        let n = self.ntypes + 1;
        self.coeff[i * n + j] = Some(c);
        self.coeff[j * n + i] = Some(c);
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
