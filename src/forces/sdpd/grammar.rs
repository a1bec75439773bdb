//! `pair_style sdpd` and its `pair_coeff` lines (docs/input.md), for both engines.

use crate::forces::sdpd::kernel::Smoothing;
use crate::grammar::{
    StyleSpec, TargetRules, at_most, coeff_types, eta_sc_targets, keywords, need, parse_f64,
    sets_some_pair, shown, temp_rc_seed, type_pairs,
};

/// The style's name, the one place it is written (the registry, the style object and its
/// usage strings read it).
pub(crate) const NAME: &str = "sdpd";

/// `pair_style sdpd …` (the words after the style name).
pub(crate) const PAIR_STYLE: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME,
    usage: "pair_style sdpd T rc seed [kernel lucy|quintic|proposed S]",
    keywords: &["kernel"],
};

/// `pair_coeff I J rho0 c0 eta0 [rc]`.
pub(crate) const PAIR_COEFF: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME,
    usage: "pair_coeff I J rho0 c0 eta0 [rc] | I J rho0 c0 eta E sc S [rc R]",
    keywords: &[],
};

/// `pair_coeff I J rho0 c0 eta E sc S [rc R]`: η0 and the kernel's s from target η and Sc.
pub(crate) const PAIR_COEFF_TARGETS: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME,
    usage: "pair_coeff I J rho0 c0 eta E sc S [rc R]",
    keywords: &["rc"],
};

/// How the target form words its rules: η is checked as it is read, Sc > 1/2 is the kinetic
/// theory's bound.
const TARGETS: TargetRules = TargetRules {
    eta_checked_first: true,
    sc_bound: "the kinetic theory gives Sc > 1/2",
};

/// The settings of `pair_style sdpd`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdpdStyle {
    /// T of the random force as given (>= 0; 0: no random force): a temperature, kT = boltz T at set-up (T itself
    /// in `units lj`).
    pub temp: f64,
    /// Global cut-off, the kernel's support (> 0).
    pub rc: f64,
    /// Noise seed, 1..=2147483647.
    pub seed: u32,
    /// The kernel (default Lucy).
    pub kernel: Smoothing,
}

impl SdpdStyle {
    /// The words of a `pair_style sdpd` line that gives these settings back through
    /// [`pair_style`] exactly (numbers with 17 significant digits); LAMMPS restarts use it.
    pub fn to_words(&self) -> Vec<String> {
        let mut w = vec![
            format!("{:.17e}", self.temp),
            format!("{:.17e}", self.rc),
            self.seed.to_string(),
            "kernel".into(),
            self.kernel.keyword().into(),
        ];
        if let Smoothing::Proposed(s) = self.kernel {
            w.push(format!("{s:.17e}"));
        }
        w
    }
}

/// Parse `pair_style sdpd T rc seed [kernel lucy|quintic|proposed S]` (`args` are the words
/// after the style name).
pub fn pair_style<S: AsRef<str>>(args: &[S]) -> Result<SdpdStyle, String> {
    let usage = PAIR_STYLE.usage;
    need(args, 3, usage)?;
    let (temp, rc, seed) = temp_rc_seed(args)?;
    let mut kernel = Smoothing::Lucy;
    let rest = &args[3..];
    if let Some(key) = rest.first() {
        let key = key.as_ref();
        if key != "kernel" {
            return Err(format!(
                "unknown pair_style sdpd keyword '{}' (expected kernel); usage: {usage}",
                shown(key)
            ));
        }
        let name = rest
            .get(1)
            .map(AsRef::as_ref)
            .ok_or_else(|| format!("keyword 'kernel' needs a value; usage: {usage}"))?;
        kernel = match name {
            "lucy" => Smoothing::Lucy,
            "quintic" => Smoothing::Quintic,
            "proposed" => {
                let s = rest.get(2).map(AsRef::as_ref).ok_or_else(|| {
                    format!("kernel proposed needs its exponent S; usage: {usage}")
                })?;
                let s = parse_f64(s, "kernel exponent S")?;
                Smoothing::proposed(s)
                    .ok_or_else(|| format!("kernel exponent S = {s} must be > 0"))?
            }
            other => {
                return Err(format!(
                    "kernel '{}' must be lucy, quintic or proposed",
                    shown(other)
                ));
            }
        };
        let used = if matches!(kernel, Smoothing::Proposed(_)) {
            6
        } else {
            5
        };
        at_most(args, used, usage)?;
    }
    Ok(SdpdStyle {
        temp,
        rc,
        seed,
        kernel,
    })
}

/// One parsed `pair_coeff` line of `sdpd`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdpdCoeffLine {
    /// Type range of I (1-based, inclusive).
    pub i: (usize, usize),
    /// Type range of J.
    pub j: (usize, usize),
    /// Reference mass density ρ0 (> 0).
    pub rho0: f64,
    /// Sound speed c_s (> 0).
    pub c0: f64,
    /// Dissipative viscosity η0 (> 0; 1 stands in until set-up when `targets` is given).
    pub eta0: f64,
    /// Cut-off (the kernel's support, > 0).
    pub rc: f64,
    /// Target (η, Sc) of the `eta … sc …` form: η0 and the kernel exponent s are resolved from
    /// them at every run's set-up (the proposed kernel's kinetic theory, WF-60 / WF-45).
    pub targets: Option<(f64, f64)>,
}

impl SdpdCoeffLine {
    /// The type pairs (i ≤ j) the line sets, as LAMMPS does: i in I, j in J with j ≥ i.
    pub fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        type_pairs((self.i, self.j))
    }
}

/// A finite number > 0.
fn positive(tok: &str, what: &str) -> Result<f64, String> {
    let v = parse_f64(tok, what)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{what} = {v} must be > 0"))
    }
}

/// Parse a `pair_coeff` line of `sdpd` (all its words, types first) for `ntypes` types under
/// the pair style `style`.
pub fn pair_coeff<S: AsRef<str>>(
    args: &[S],
    ntypes: usize,
    style: &SdpdStyle,
) -> Result<SdpdCoeffLine, String> {
    let targets = args.get(4).map(AsRef::as_ref) == Some("eta");
    let usage = if targets {
        PAIR_COEFF_TARGETS.usage
    } else {
        PAIR_COEFF.usage
    };
    need(args, if targets { 8 } else { 5 }, usage)?;
    let word = |k: usize| args[k].as_ref();
    let (i, j) = coeff_types(word(0), word(1), ntypes)?;
    let rho0 = positive(word(2), "rho0")?;
    let c0 = positive(word(3), "c0")?;
    let (eta0, rc, targets) = if targets {
        let (eta, sc) = eta_sc_targets(args, 4, usage, TARGETS)?;
        if !matches!(style.kernel, Smoothing::Proposed(_)) {
            return Err(format!(
                "pair_coeff … eta … sc … designs the proposed kernel's exponent: pair_style sdpd \
                 needs 'kernel proposed S' (it has kernel {})",
                style.kernel.keyword()
            ));
        }
        let mut rc = style.rc;
        keywords(&args[8..], &PAIR_COEFF_TARGETS, |_, val| {
            rc = positive(val, "rc")?;
            Ok(())
        })?;
        (1.0, rc, Some((eta, sc)))
    } else {
        at_most(args, 6, usage)?;
        let eta0 = positive(word(4), "eta0")?;
        let rc = match args.get(5) {
            Some(t) => positive(t.as_ref(), "rc")?,
            None => style.rc,
        };
        (eta0, rc, None)
    };
    let p0 = c0 * c0 * rho0 / 7.0;
    if !p0.is_finite() {
        return Err(format!(
            "the Tait pressure scale P0 = c0^2 rho0 / 7 overflows (c0 = {c0}, rho0 = {rho0})"
        ));
    }
    let line = SdpdCoeffLine {
        i,
        j,
        rho0,
        c0,
        eta0,
        rc,
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
        for k in [
            &["kernel", "lucy"][..],
            &["kernel", "quintic"],
            &["kernel", "proposed", "0.3"],
        ] {
            let mut w = vec!["1.5", "2.5", "77"];
            w.extend_from_slice(k);
            let s = pair_style(&w).unwrap();
            assert_eq!(pair_style(&s.to_words()).unwrap(), s);
        }
    }

    #[test]
    fn bad_words_are_refused() {
        assert!(pair_style(&["1", "1", "5", "kernel", "gauss"]).is_err());
        assert!(pair_style(&["1", "1", "5", "kernel", "proposed"]).is_err());
        assert!(pair_style(&["1", "1", "5", "kernel", "proposed", "0"]).is_err());
        assert!(pair_style(&["1", "1", "5", "kernel", "lucy", "2"]).is_err());
        let st = pair_style(&["1", "2.5", "5"]).unwrap();
        assert_eq!(st.kernel, Smoothing::Lucy);
        assert!(pair_coeff(&["1", "1", "0", "10", "5"], 1, &st).is_err());
        assert!(pair_coeff(&["1", "1", "4", "-1", "5"], 1, &st).is_err());
        assert!(pair_coeff(&["1", "1", "4", "10", "0"], 1, &st).is_err());
        assert!(pair_coeff(&["1", "1", "4", "10", "5", "2", "x"], 1, &st).is_err());
        assert!(pair_coeff(&["1", "1", "4", "1e200", "5"], 1, &st).is_err());
        // Targets need the proposed kernel.
        assert!(pair_coeff(&["1", "1", "4", "10", "eta", "49", "sc", "400"], 1, &st).is_err());
        let st = pair_style(&["1", "2.5", "5", "kernel", "proposed", "1"]).unwrap();
        let l = pair_coeff(&["1", "1", "4", "10", "eta", "49", "sc", "400"], 1, &st).unwrap();
        assert_eq!(l.targets, Some((49.0, 400.0)));
        assert_eq!(l.rc, 2.5);
    }
}
