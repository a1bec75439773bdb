//! `pair_style dpd/nonlinear` and its `pair_coeff` lines (docs/input.md), for both engines.

use crate::forces::NoiseDist;
use crate::forces::dpd::kernel::{Friction, Noise, PairCoeff, PairModel, Weight};
use crate::grammar::{
    StyleSpec, TargetRules, at_most, coeff_types, eta_sc_targets, keywords, need, parse_f64,
    sets_some_pair, shown, temp_rc_seed, type_pairs,
};

/// The style's name, the one place it is written (the registry, the style object and its
/// usage strings read it).
pub(crate) const NAME: &str = "dpd/nonlinear";

/// `pair_style dpd/nonlinear …` (the words after the style name).
pub(crate) const PAIR_STYLE: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME,
    usage: "pair_style dpd/nonlinear T rc seed [friction none|cross|dot] [noise plain|corrected|twostep] [weight s] [noise_dist gaussian|uniform]",
    keywords: &["friction", "noise", "weight", "noise_dist"],
};

/// `pair_coeff I J a gamma0 gamma1 [rc]`.
pub(crate) const PAIR_COEFF: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME,
    usage: "pair_coeff I J a gamma0 gamma1 [rc] | I J a eta E sc S [gamma1 G] [rc R]",
    keywords: &[],
};

/// `pair_coeff I J a eta E sc S [gamma1 G] [rc R]`: γ0 and s from target η and Sc.
pub(crate) const PAIR_COEFF_TARGETS: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME,
    usage: "pair_coeff I J a eta E sc S [gamma1 G] [rc R]",
    keywords: &["gamma1", "rc"],
};

/// How the target form words its rules: Sc > 1/2 is the ideal DPD fluid's bound.
const TARGETS: TargetRules = TargetRules {
    eta_checked_first: false,
    sc_bound: "an ideal DPD fluid has Sc > 1/2",
};

/// The settings of `pair_style dpd/nonlinear`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DpdStyle {
    /// T as given (>= 0; 0: no random force, the friction kept): a temperature, as LAMMPS's `pair_style dpd` takes it; the set-up makes
    /// kT = boltz T of the run's unit style (T itself in `units lj`).
    pub temp: f64,
    /// Global cut-off (> 0).
    pub rc: f64,
    /// Noise seed, 1..=2147483647.
    pub seed: u32,
    /// Friction model.
    pub friction: Friction,
    /// Noise scheme.
    pub noise: Noise,
    /// Dissipative weight.
    pub weight: Weight,
    /// Distribution of the pair variate ξ_ij.
    pub dist: NoiseDist,
}

impl DpdStyle {
    /// The kernel's model at time step `dt`, with kT = T (`units lj`; the set-up sets the run's
    /// kT = boltz T and ftm2v).
    pub fn model(&self, dt: f64) -> PairModel {
        PairModel::new(self.temp, self.friction, self.noise, self.weight, dt).with_dist(self.dist)
    }

    /// The words of a `pair_style dpd/nonlinear` line that gives these settings back through
    /// [`pair_style`] exactly (numbers with 17 significant digits); LAMMPS restarts use it.
    /// `noise_dist` is written only when it is not the default, so the words of a Gaussian
    /// style are those of the versions before the keyword.
    pub fn to_words(&self) -> Vec<String> {
        let mut w = vec![
            format!("{:.17e}", self.temp),
            format!("{:.17e}", self.rc),
            self.seed.to_string(),
            "friction".into(),
            self.friction.keyword().into(),
            "noise".into(),
            self.noise.keyword().into(),
            "weight".into(),
            format!("{:.17e}", self.weight.exponent()),
        ];
        if self.dist != NoiseDist::Gaussian {
            w.extend(["noise_dist".into(), self.dist.keyword().into()]);
        }
        w
    }
}

/// Parse `pair_style dpd/nonlinear T rc seed [friction F] [noise N] [weight s] [noise_dist D]` (`args` are
/// the words after the style name).
pub fn pair_style<S: AsRef<str>>(args: &[S]) -> Result<DpdStyle, String> {
    settings(args, &PAIR_STYLE)
}

/// The settings `T rc seed [friction F] [noise N] [weight s] [noise_dist D]` of a DPD-form
/// style (`dpd/nonlinear`, `mdpd/nonlinear`), with `spec`'s usage and keywords in its messages.
pub(crate) fn settings<S: AsRef<str>>(args: &[S], spec: &StyleSpec) -> Result<DpdStyle, String> {
    let usage = spec.usage;
    need(args, 3, usage)?;
    let (temp, rc, seed) = temp_rc_seed(args)?;
    let k = friction_noise_keywords(&args[3..], spec)?;
    Ok(DpdStyle {
        temp,
        rc,
        seed,
        friction: k.friction,
        noise: k.noise,
        weight: k.weight,
        dist: k.dist,
    })
}

/// The friction, noise, weight and noise-distribution keywords of a DPD-form style.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FrictionNoise {
    /// `friction none|cross|dot` (default none).
    pub friction: Friction,
    /// `noise plain|corrected|twostep` (default plain).
    pub noise: Noise,
    /// `weight s` (default 2), where the style's spec lists it.
    pub weight: Weight,
    /// `noise_dist gaussian|uniform` (default gaussian).
    pub dist: NoiseDist,
}

/// Parse the keywords `[friction F] [noise N] [weight s] [noise_dist D]` that `spec` lists (the
/// one parser of every DPD-form style: `dpd/nonlinear`, `mdpd/nonlinear` and the ext and
/// tstat forms).
pub(crate) fn friction_noise_keywords<S: AsRef<str>>(
    args: &[S],
    spec: &StyleSpec,
) -> Result<FrictionNoise, String> {
    let mut k = FrictionNoise {
        friction: Friction::None,
        noise: Noise::Plain,
        weight: Weight::STANDARD,
        dist: NoiseDist::Gaussian,
    };
    keywords(args, spec, |key, val| {
        match key {
            "friction" => {
                k.friction = Friction::from_keyword(val).ok_or_else(|| {
                    format!("friction '{}' must be none, cross or dot", shown(val))
                })?
            }
            "noise" => {
                k.noise = Noise::from_keyword(val).ok_or_else(|| {
                    format!("noise '{}' must be plain, corrected or twostep", shown(val))
                })?
            }
            "noise_dist" => {
                k.dist = NoiseDist::from_keyword(val).ok_or_else(|| {
                    format!("noise_dist '{}' must be gaussian or uniform", shown(val))
                })?
            }
            _ => {
                let s = parse_f64(val, "weight exponent")?;
                k.weight =
                    Weight::new(s).ok_or_else(|| format!("weight exponent {s} must be > 0"))?
            }
        }
        Ok(())
    })?;
    Ok(k)
}

/// One parsed `pair_coeff` line of `dpd/nonlinear`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DpdCoeffLine {
    /// Type range of I (1-based, inclusive).
    pub i: (usize, usize),
    /// Type range of J.
    pub j: (usize, usize),
    /// The coefficients (γ0 = 1 stands in until set-up when `targets` is given).
    pub coeff: PairCoeff,
    /// Target (η, Sc) of the `eta … sc …` form: γ0 and the weight exponent are resolved from
    /// them at every run's set-up (`crate::init::resolve_design`).
    pub targets: Option<(f64, f64)>,
}

impl DpdCoeffLine {
    /// The type pairs (i ≤ j) the line sets, as LAMMPS does: i in I, j in J with j ≥ i.
    pub fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        type_pairs((self.i, self.j))
    }
}

/// Parse a `pair_coeff` line of `dpd/nonlinear` (all its words, types first) for `ntypes`
/// types, under a pair style with `friction` and global cut-off `rc_global`.
pub fn pair_coeff<S: AsRef<str>>(
    args: &[S],
    ntypes: usize,
    friction: Friction,
    rc_global: f64,
) -> Result<DpdCoeffLine, String> {
    let targets = args.get(3).map(AsRef::as_ref) == Some("eta");
    let usage = if targets {
        PAIR_COEFF_TARGETS.usage
    } else {
        PAIR_COEFF.usage
    };
    need(args, if targets { 7 } else { 5 }, usage)?;
    let word = |k: usize| args[k].as_ref();
    let (i, j) = coeff_types(word(0), word(1), ntypes)?;
    let a = parse_f64(word(2), "a")?;
    let (coeff, targets) = if targets {
        let (eta, sc) = eta_sc_targets(args, 3, usage, TARGETS)?;
        let (mut gamma1, mut rc) = (0.0, rc_global);
        keywords(&args[7..], &PAIR_COEFF_TARGETS, |key, val| {
            match key {
                "gamma1" => gamma1 = parse_f64(val, "gamma1")?,
                _ => rc = parse_f64(val, "rc")?,
            }
            Ok(())
        })?;
        // γ0 = 1 stands in until set-up; the rest is validated now, so a bad value fails on
        // this line.
        let c = PairCoeff {
            a,
            gamma0: 1.0,
            gamma1,
            rc,
        };
        (c, Some((eta, sc)))
    } else {
        at_most(args, 6, usage)?;
        let c = PairCoeff {
            a,
            gamma0: parse_f64(word(3), "gamma0")?,
            gamma1: parse_f64(word(4), "gamma1")?,
            rc: match args.get(5) {
                Some(t) => parse_f64(t.as_ref(), "rc")?,
                None => rc_global,
            },
        };
        (c, None)
    };
    coeff.validate()?;
    if friction == Friction::None && coeff.gamma1 != 0.0 {
        return Err(format!(
            "gamma1 = {} has no effect with 'friction none': set it to 0 or choose cross/dot",
            coeff.gamma1
        ));
    }
    let line = DpdCoeffLine {
        i,
        j,
        coeff,
        targets,
    };
    sets_some_pair((line.i, line.j), word(0), word(1))?;
    Ok(line)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restart_words_round_trip() {
        let s = pair_style(&[
            "0.1",
            "1.0",
            "2147483647",
            "friction",
            "dot",
            "noise",
            "twostep",
            "weight",
            "0.3",
        ])
        .unwrap();
        assert_eq!(pair_style(&s.to_words()).unwrap(), s);
    }

    #[test]
    fn seeds_and_gamma1() {
        assert!(pair_style(&["1", "1", "0"]).is_err());
        assert!(pair_style(&["1", "1", "2147483648"]).is_err());
        assert!(pair_coeff(&["1", "1", "25", "4.5", "1.0"], 1, Friction::None, 1.0).is_err());
        assert!(pair_coeff(&["1", "1", "25", "4.5", "1.0"], 1, Friction::Dot, 1.0).is_ok());
        assert!(
            pair_coeff(
                &["1", "1", "25", "4.5", "0", "1", "x"],
                1,
                Friction::Dot,
                1.0
            )
            .is_err()
        );
    }
}
