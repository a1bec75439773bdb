//! `pair_style dpd/nonlinear/ext`, `dpd/nonlinear/tstat`, `dpd/nonlinear/ext/tstat` and their
//! `pair_coeff` lines (docs/input.md), for both engines. The words follow LAMMPS's `dpd/ext`,
//! `dpd/tstat` and `dpd/ext/tstat`, so that a line of those moves over unchanged but for the
//! style name; this project's keywords come after LAMMPS's words.

use crate::forces::NoiseDist;
use crate::forces::dpd::kernel::{Friction, Noise, PairCoeff, PairModel, Weight};
use crate::forces::dpdext::kernel::ExtCoeff;
use crate::grammar::{
    INT_MAX, StyleSpec, coeff_types, keywords, need, parse_f64, parse_int_in, sets_some_pair,
    type_pairs,
};

/// `dpd/nonlinear/ext`: conservative, parallel and perpendicular parts.
pub(crate) const NAME_EXT: &str = "dpd/nonlinear/ext";
/// `dpd/nonlinear/tstat`: the parallel friction and noise only, T ramped over a run.
pub(crate) const NAME_TSTAT: &str = "dpd/nonlinear/tstat";
/// `dpd/nonlinear/ext/tstat`: parallel and perpendicular friction and noise, T ramped.
pub(crate) const NAME_EXT_TSTAT: &str = "dpd/nonlinear/ext/tstat";

/// Which of the three styles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `dpd/nonlinear/ext`.
    Ext,
    /// `dpd/nonlinear/tstat`.
    Tstat,
    /// `dpd/nonlinear/ext/tstat`.
    ExtTstat,
}

impl Form {
    /// The style's name.
    pub fn name(self) -> &'static str {
        match self {
            Form::Ext => NAME_EXT,
            Form::Tstat => NAME_TSTAT,
            Form::ExtTstat => NAME_EXT_TSTAT,
        }
    }

    /// True for the forms with the perpendicular friction and noise.
    pub fn transverse(self) -> bool {
        self != Form::Tstat
    }

    /// True for the thermostat-only forms (no conservative force, `Tstart Tstop`).
    pub fn tstat(self) -> bool {
        self != Form::Ext
    }

    /// The usage strings of its `pair_style` and `pair_coeff` lines.
    pub(crate) fn specs(self) -> (&'static StyleSpec, &'static StyleSpec) {
        match self {
            Form::Ext => (&PAIR_STYLE_EXT, &PAIR_COEFF_EXT),
            Form::Tstat => (&PAIR_STYLE_TSTAT, &PAIR_COEFF_TSTAT),
            Form::ExtTstat => (&PAIR_STYLE_EXT_TSTAT, &PAIR_COEFF_EXT_TSTAT),
        }
    }
}

/// `pair_style dpd/nonlinear/ext …`.
pub(crate) const PAIR_STYLE_EXT: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME_EXT,
    usage: "pair_style dpd/nonlinear/ext T rc seed [friction none|cross|dot] [noise plain|corrected|twostep] [noise_dist gaussian|uniform]",
    keywords: &["friction", "noise", "noise_dist"],
};

/// `pair_coeff I J a gamma gammaT s sT [rc] [gamma1 G]`.
pub(crate) const PAIR_COEFF_EXT: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME_EXT,
    usage: "pair_coeff I J a gamma gammaT s sT [rc] [gamma1 G]",
    keywords: &["gamma1"],
};

/// `pair_style dpd/nonlinear/tstat …`.
pub(crate) const PAIR_STYLE_TSTAT: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME_TSTAT,
    usage: "pair_style dpd/nonlinear/tstat Tstart Tstop rc seed [friction none|cross|dot] [noise plain|corrected|twostep] [weight s] [noise_dist gaussian|uniform]",
    keywords: &["friction", "noise", "weight", "noise_dist"],
};

/// `pair_coeff I J gamma [rc] [gamma1 G]`.
pub(crate) const PAIR_COEFF_TSTAT: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME_TSTAT,
    usage: "pair_coeff I J gamma [rc] [gamma1 G]",
    keywords: &["gamma1"],
};

/// `pair_style dpd/nonlinear/ext/tstat …`.
pub(crate) const PAIR_STYLE_EXT_TSTAT: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME_EXT_TSTAT,
    usage: "pair_style dpd/nonlinear/ext/tstat Tstart Tstop rc seed [friction none|cross|dot] [noise plain|corrected|twostep] [noise_dist gaussian|uniform]",
    keywords: &["friction", "noise", "noise_dist"],
};

/// `pair_coeff I J gamma gammaT s sT [rc] [gamma1 G]`.
pub(crate) const PAIR_COEFF_EXT_TSTAT: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME_EXT_TSTAT,
    usage: "pair_coeff I J gamma gammaT s sT [rc] [gamma1 G]",
    keywords: &["gamma1"],
};

/// The settings of one of the three styles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtStyle {
    /// Which style.
    pub form: Form,
    /// T (`dpd/nonlinear/ext`) or Tstart, a temperature (>= 0).
    pub t_start: f64,
    /// Tstop (= Tstart for `dpd/nonlinear/ext`).
    pub t_stop: f64,
    /// Global cut-off (> 0).
    pub rc: f64,
    /// Noise seed, 1..=2147483647.
    pub seed: u32,
    /// Friction model of the parallel part.
    pub friction: Friction,
    /// Noise scheme of the parallel part.
    pub noise: Noise,
    /// The parallel weight of `dpd/nonlinear/tstat` (`weight s`); the ext forms give theirs per
    /// pair (this stays the default).
    pub weight: Weight,
    /// Distribution of ξ_ij and of the components of ξ⃗_ij.
    pub dist: NoiseDist,
}

impl ExtStyle {
    /// The kernel's model at time step `dt`, kT = Tstart (`units lj`; the set-up and the ramp
    /// set the run's kT and ftm2v).
    pub fn model(&self, dt: f64) -> PairModel {
        PairModel::new(self.t_start, self.friction, self.noise, self.weight, dt)
            .with_dist(self.dist)
    }

    /// The words after the style name that give these settings back exactly.
    pub fn to_words(&self) -> Vec<String> {
        let mut w = vec![format!("{:.17e}", self.t_start)];
        if self.form.tstat() {
            w.push(format!("{:.17e}", self.t_stop));
        }
        w.extend([
            format!("{:.17e}", self.rc),
            self.seed.to_string(),
            "friction".into(),
            self.friction.keyword().into(),
            "noise".into(),
            self.noise.keyword().into(),
        ]);
        if self.form == Form::Tstat {
            w.extend(["weight".into(), format!("{:.17e}", self.weight.exponent())]);
        }
        if self.dist != NoiseDist::Gaussian {
            w.extend(["noise_dist".into(), self.dist.keyword().into()]);
        }
        w
    }
}

/// Parse the words after the style name of `form`.
pub fn pair_style<S: AsRef<str>>(form: Form, args: &[S]) -> Result<ExtStyle, String> {
    let (spec, _) = form.specs();
    let usage = spec.usage;
    let temps = if form.tstat() { 2 } else { 1 };
    need(args, temps + 2, usage)?;
    let word = |k: usize| args[k].as_ref();
    let names: &[&str] = if form.tstat() {
        &["Tstart", "Tstop"]
    } else {
        &["T"]
    };
    let mut t = [0.0; 2];
    for (k, name) in names.iter().enumerate() {
        t[k] = parse_f64(word(k), name)?;
        // T = 0 as for dpd/nonlinear: no random force, the friction kept.
        if t[k].is_nan() || t[k] < 0.0 {
            return Err(format!("{name} = {} must be >= 0", t[k]));
        }
    }
    let (t_start, t_stop) = (t[0], if form.tstat() { t[1] } else { t[0] });
    let rc = parse_f64(word(temps), "rc")?;
    if rc <= 0.0 {
        return Err(format!("rc = {rc} must be > 0"));
    }
    let seed = parse_int_in(word(temps + 1), "seed", 1, INT_MAX)? as u32;
    let k = crate::forces::dpd::grammar::friction_noise_keywords(&args[temps + 2..], spec)?;
    Ok(ExtStyle {
        form,
        t_start,
        t_stop,
        rc,
        seed,
        friction: k.friction,
        noise: k.noise,
        weight: k.weight,
        dist: k.dist,
    })
}

/// One parsed `pair_coeff` line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtCoeffLine {
    /// Type range of I.
    pub i: (usize, usize),
    /// Type range of J.
    pub j: (usize, usize),
    /// The coefficients (`dpd/nonlinear/tstat`: γ⊥ = 0 and the style's weight).
    pub coeff: ExtCoeff,
}

impl ExtCoeffLine {
    /// The type pairs (i ≤ j) the line sets.
    pub fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        type_pairs((self.i, self.j))
    }
}

/// Parse a `pair_coeff` line (all its words, types first) of `style` for `ntypes` types.
pub fn pair_coeff<S: AsRef<str>>(
    style: &ExtStyle,
    args: &[S],
    ntypes: usize,
) -> Result<ExtCoeffLine, String> {
    let (_, spec) = style.form.specs();
    let usage = spec.usage;
    // The numbers LAMMPS's style takes before its optional rc.
    let (conservative, npos) = match style.form {
        Form::Ext => (true, 5),
        Form::Tstat => (false, 1),
        Form::ExtTstat => (false, 4),
    };
    need(args, 2 + npos, usage)?;
    let word = |k: usize| args[k].as_ref();
    let (i, j) = coeff_types(word(0), word(1), ntypes)?;
    let mut k = 2;
    let mut next = |what: &str| {
        let v = parse_f64(word(k), what);
        k += 1;
        v
    };
    let a = if conservative { next("a")? } else { 0.0 };
    let gamma = next("gamma")?;
    let (gamma_perp, s_par, s_perp) = if style.form.transverse() {
        (next("gammaT")?, next("s")?, next("sT")?)
    } else {
        (0.0, 0.5 * style.weight.exponent(), 1.0)
    };
    let mut rc = style.rc;
    if let Some(w) = args.get(k).map(AsRef::as_ref)
        && w != "gamma1"
    {
        rc = parse_f64(w, "rc")?;
        k += 1;
    }
    let mut gamma1 = 0.0;
    keywords(&args[k..], spec, |_, val| {
        gamma1 = parse_f64(val, "gamma1")?;
        Ok(())
    })?;
    let par = PairCoeff {
        a,
        gamma0: gamma,
        gamma1,
        rc,
    };
    par.validate().map_err(|e| e.replace("gamma0", "gamma"))?;
    if !(gamma_perp.is_finite() && gamma_perp >= 0.0) {
        return Err(format!("gammaT = {gamma_perp} must be finite and >= 0"));
    }
    let weight = |s: f64, name: &str| {
        Weight::new(2.0 * s)
            .filter(|_| s.is_finite() && s > 0.0)
            .ok_or_else(|| format!("{name} = {s} must be finite and > 0"))
    };
    let coeff = ExtCoeff {
        par,
        gamma_perp,
        w_par: if style.form.transverse() {
            weight(s_par, "s")?
        } else {
            style.weight
        },
        w_perp: weight(s_perp, "sT")?,
    };
    if style.friction == Friction::None && gamma1 != 0.0 {
        return Err(format!(
            "gamma1 = {gamma1} has no effect with 'friction none': set it to 0 or choose cross/dot"
        ));
    }
    let line = ExtCoeffLine { i, j, coeff };
    sets_some_pair((line.i, line.j), word(0), word(1))?;
    Ok(line)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restart_words_round_trip() {
        for (form, words) in [
            (
                Form::Ext,
                vec!["1.5", "1.0", "7", "friction", "dot", "noise", "twostep"],
            ),
            (
                Form::Tstat,
                vec![
                    "1.0",
                    "2.0",
                    "1.0",
                    "7",
                    "weight",
                    "1.5",
                    "noise_dist",
                    "uniform",
                ],
            ),
            (
                Form::ExtTstat,
                vec!["1.0", "2.0", "1.0", "7", "friction", "cross"],
            ),
        ] {
            let s = pair_style(form, &words).unwrap();
            assert_eq!(pair_style(form, &s.to_words()).unwrap(), s, "{form:?}");
        }
    }

    /// LAMMPS's words are read as LAMMPS reads them; this project's keyword follows them.
    #[test]
    fn lammps_lines_move_over() {
        let ext = pair_style(Form::Ext, &["1.0", "1.0", "7", "friction", "cross"]).unwrap();
        let l = pair_coeff(&ext, &["1", "1", "25", "4.5", "3", "1", "0.5", "0.9"], 1).unwrap();
        assert_eq!(
            (
                l.coeff.par.a,
                l.coeff.par.gamma0,
                l.coeff.gamma_perp,
                l.coeff.par.rc
            ),
            (25.0, 4.5, 3.0, 0.9)
        );
        assert_eq!(l.coeff.w_par, Weight::new(2.0).unwrap());
        assert_eq!(l.coeff.w_perp, Weight::new(1.0).unwrap());
        let l = pair_coeff(
            &ext,
            &["1", "1", "25", "4.5", "3", "1", "0.5", "gamma1", "2"],
            1,
        )
        .unwrap();
        assert_eq!((l.coeff.par.gamma1, l.coeff.par.rc), (2.0, 1.0));
        let t = pair_style(Form::Tstat, &["1.0", "2.0", "1.0", "7"]).unwrap();
        let l = pair_coeff(&t, &["1", "1", "4.5", "0.8"], 1).unwrap();
        assert_eq!(
            (l.coeff.par.a, l.coeff.par.gamma0, l.coeff.par.rc),
            (0.0, 4.5, 0.8)
        );
        assert!(pair_coeff(&t, &["1", "1", "4.5", "gamma1", "1"], 1).is_err());
        assert!(pair_coeff(&ext, &["1", "1", "25", "4.5", "3", "0", "0.5"], 1).is_err());
        assert!(pair_coeff(&ext, &["1", "1", "25", "4.5", "-3", "1", "0.5"], 1).is_err());
        assert!(pair_style(Form::Ext, &["1.0", "1.0", "7", "weight", "1"]).is_err());
    }
}
