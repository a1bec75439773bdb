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
    /// ([`crate::init::resolve_design`]): sets `gamma0` of those pairs and the global weight
    /// exponent. Returns the lines to log.
    pub fn resolve_targets(
        &mut self,
        dim: u32,
        density: f64,
        mass: f64,
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
                let r = crate::init::resolve_design(&label, dim, density, c.rc, mass, kt, eta, sc)?;
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
        if let Some((s, note)) = crate::init::common_exponent("dpd/nonlinear", &exponents, current)?
        {
            self.model.weight = crate::kernel::Weight::new(s)
                .ok_or_else(|| format!("designed weight exponent s = {s} is not > 0"))?;
            lines.extend(note);
        }
        Ok(lines)
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
