//! `pair_style mdpd/nonlinear` and its `pair_coeff` lines (docs/manual/styles/pair_mdpd_nonlinear.md),
//! for both engines. The settings are those of `dpd/nonlinear` (one parser,
//! [`crate::forces::dpd::grammar`]); a `pair_coeff` line starts with the seven words of LAMMPS's
//! `pair_coeff … mdpd` line, so a LAMMPS line runs unchanged.

use crate::forces::dpd::grammar::{DpdStyle, settings};
use crate::forces::dpd::kernel::{Friction, PairCoeff};
use crate::grammar::{
    StyleSpec, at_most, coeff_types, need, parse_f64, sets_some_pair, type_pairs,
};

/// The style's name, the one place it is written.
pub(crate) const NAME: &str = "mdpd/nonlinear";

/// `pair_style mdpd/nonlinear …` (the words after the style name).
pub(crate) const PAIR_STYLE: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME,
    usage: "pair_style mdpd/nonlinear T rc seed [friction none|cross|dot] [noise plain|corrected|twostep] [weight s] [noise_dist gaussian|uniform]",
    keywords: &["friction", "noise", "weight", "noise_dist"],
};

/// `pair_coeff I J A B gamma0 rc rd [gamma1]`.
pub(crate) const PAIR_COEFF: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME,
    usage: "pair_coeff I J A B gamma0 rc rd [gamma1]",
    keywords: &[],
};

/// Parse `pair_style mdpd/nonlinear T rc seed [friction F] [noise N] [weight s] [noise_dist D]`.
pub fn pair_style<S: AsRef<str>>(args: &[S]) -> Result<DpdStyle, String> {
    settings(args, &PAIR_STYLE)
}

/// One parsed `pair_coeff` line of `mdpd/nonlinear`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MdpdCoeffLine {
    /// Type range of I (1-based, inclusive).
    pub i: (usize, usize),
    /// Type range of J.
    pub j: (usize, usize),
    /// The DPD part: `a` is A (the attraction when < 0), γ0, γ1 and r_c.
    pub coeff: PairCoeff,
    /// B, the many-body repulsion's amplitude.
    pub b: f64,
    /// r_d (0 < r_d ≤ r_c): the range of the many-body repulsion and of the density weight.
    pub rd: f64,
}

impl MdpdCoeffLine {
    /// The type pairs (i ≤ j) the line sets, as LAMMPS does: i in I, j in J with j ≥ i.
    pub fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        type_pairs((self.i, self.j))
    }
}

/// Parse a `pair_coeff I J A B gamma0 rc rd [gamma1]` line (all its words, types first) for
/// `ntypes` types under a style with `friction`: LAMMPS's `mdpd` line (I J A B gamma cutA cutB)
/// plus γ1 of the friction law, which must be 0 (or absent) with `friction none`.
pub fn pair_coeff<S: AsRef<str>>(
    args: &[S],
    ntypes: usize,
    friction: Friction,
) -> Result<MdpdCoeffLine, String> {
    let usage = PAIR_COEFF.usage;
    if args.get(3).map(AsRef::as_ref) == Some("eta") {
        return Err(format!(
            "pair_style {NAME} takes no 'eta … sc …' targets: the kinetic theory that designs \
             gamma0 from a viscosity is that of a fluid without many-body forces; give B and \
             gamma0; usage: {usage}"
        ));
    }
    need(args, 7, usage)?;
    at_most(args, 8, usage)?;
    let word = |k: usize| args[k].as_ref();
    let (i, j) = coeff_types(word(0), word(1), ntypes)?;
    let a = parse_f64(word(2), "A")?;
    let b = parse_f64(word(3), "B")?;
    let coeff = PairCoeff {
        a,
        gamma0: parse_f64(word(4), "gamma0")?,
        gamma1: match args.get(7) {
            Some(t) => parse_f64(t.as_ref(), "gamma1")?,
            None => 0.0,
        },
        rc: parse_f64(word(5), "rc")?,
    };
    let rd = parse_f64(word(6), "rd")?;
    coeff.validate()?;
    if !(rd.is_finite() && rd > 0.0) {
        return Err(format!("rd = {rd} must be > 0"));
    }
    if rd > coeff.rc {
        return Err(format!(
            "rd = {rd} must be <= rc = {} (the many-body repulsion and the density weight reach \
             r_d, inside the pair's cut-off)",
            coeff.rc
        ));
    }
    if friction == Friction::None && coeff.gamma1 != 0.0 {
        return Err(format!(
            "gamma1 = {} has no effect with 'friction none': set it to 0 or choose cross/dot",
            coeff.gamma1
        ));
    }
    let line = MdpdCoeffLine { i, j, coeff, b, rd };
    sets_some_pair((line.i, line.j), word(0), word(1))?;
    Ok(line)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lammps_line_and_gamma1() {
        let l = pair_coeff(
            &["1", "1", "-40", "25", "18", "1.0", "0.75"],
            1,
            Friction::None,
        )
        .expect("LAMMPS's mdpd line");
        assert_eq!(
            (l.coeff.a, l.b, l.coeff.gamma0, l.coeff.rc, l.rd),
            (-40.0, 25.0, 18.0, 1.0, 0.75)
        );
        assert_eq!(l.coeff.gamma1, 0.0);
        let e = pair_coeff(
            &["1", "1", "-40", "25", "18", "1", "0.75", "2"],
            1,
            Friction::None,
        )
        .expect_err("gamma1 with friction none");
        assert!(e.contains("friction none"), "{e}");
        let l = pair_coeff(
            &["1", "1", "-40", "25", "18", "1", "0.75", "2"],
            1,
            Friction::Dot,
        )
        .expect("gamma1 with friction dot");
        assert_eq!(l.coeff.gamma1, 2.0);
    }

    #[test]
    fn refusals_name_the_word() {
        let f = Friction::None;
        let e = pair_coeff(&["1", "1", "-40", "25", "18", "1"], 1, f).expect_err("6 words");
        assert!(e.contains("usage: pair_coeff I J A B gamma0 rc rd"), "{e}");
        let e =
            pair_coeff(&["1", "1", "-40", "25", "18", "0.7", "0.75"], 1, f).expect_err("rd > rc");
        assert!(e.contains("rd = 0.75 must be <= rc = 0.7"), "{e}");
        let e = pair_coeff(&["1", "1", "-40", "25", "18", "1", "0"], 1, f).expect_err("rd 0");
        assert!(e.contains("rd = 0 must be > 0"), "{e}");
        let e = pair_coeff(&["1", "1", "-40", "x", "18", "1", "0.75"], 1, f).expect_err("B");
        assert!(e.contains("'x'") && e.contains('B'), "{e}");
        let e =
            pair_coeff(&["1", "1", "-40", "25", "-1", "1", "0.75"], 1, f).expect_err("gamma0 < 0");
        assert!(e.contains("gamma0 = -1 must be >= 0"), "{e}");
        let e = pair_coeff(&["1", "1", "-40", "25", "18", "1", "0.75", "0", "9"], 1, f)
            .expect_err("9 words");
        assert!(e.contains("unexpected argument '9'"), "{e}");
        let e = pair_style(&["1", "1", "5", "density", "lucy"]).expect_err("keyword");
        assert!(e.contains("pair_style mdpd/nonlinear"), "{e}");
    }
}
