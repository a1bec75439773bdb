//! `pair_style test/spring rc` and `pair_coeff I J k [rc]` (the test-only style of the `test-style`
//! feature): the words of both engines, parsed once.

use crate::grammar::{
    StyleSpec, at_most, coeff_types, need, parse_f64, sets_some_pair, type_pairs,
};

/// The style's name, the one place it is written.
pub(crate) const NAME: &str = "test/spring";

/// `pair_style test/spring rc`.
pub(crate) const PAIR_STYLE: StyleSpec = StyleSpec {
    command: "pair_style",
    style: NAME,
    usage: "pair_style test/spring rc",
    keywords: &[],
};

/// `pair_coeff I J k [rc]`.
pub(crate) const PAIR_COEFF: StyleSpec = StyleSpec {
    command: "pair_coeff",
    style: NAME,
    usage: "pair_coeff I J k [rc]",
    keywords: &[],
};

/// A cut-off: finite and > 0.
fn cutoff(word: &str) -> Result<f64, String> {
    let rc = parse_f64(word, "rc")?;
    if rc <= 0.0 {
        return Err(format!("rc = {rc} must be > 0"));
    }
    Ok(rc)
}

/// Parse the words after `pair_style test/spring`: the default cut-off.
pub fn pair_style<S: AsRef<str>>(args: &[S]) -> Result<f64, String> {
    need(args, 1, PAIR_STYLE.usage)?;
    at_most(args, 1, PAIR_STYLE.usage)?;
    cutoff(args[0].as_ref())
}

/// One parsed `pair_coeff` line: the type pairs (i ≤ j) it sets, k and r_c.
pub type SpringLine = (Vec<(usize, usize)>, f64, f64);

/// Parse `pair_coeff I J k [rc]` (`rc`: the style's default when absent) for `ntypes` types.
pub fn pair_coeff<S: AsRef<str>>(args: &[S], ntypes: usize, rc: f64) -> Result<SpringLine, String> {
    need(args, 3, PAIR_COEFF.usage)?;
    at_most(args, 4, PAIR_COEFF.usage)?;
    let word = |k: usize| args[k].as_ref();
    let types = coeff_types(word(0), word(1), ntypes)?;
    sets_some_pair(types, word(0), word(1))?;
    let k = parse_f64(word(2), "k")?;
    let rc = args.get(3).map_or(Ok(rc), |w| cutoff(w.as_ref()))?;
    Ok((type_pairs(types).collect(), k, rc))
}
