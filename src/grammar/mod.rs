//! One grammar for both engines: the arguments of every style this project defines
//! (`pair_style`/`pair_coeff dpd/nonlinear`, `fix nve/euler`, `fix pex/push`) are parsed and
//! validated here, once, into typed values. The standalone interpreter (`crate::input`) calls
//! these functions with the words of a script line; the LAMMPS styles call them through the
//! C ABI (`capi/`, argc/argv in, a typed struct or an error text out) and only forward what
//! LAMMPS gives them. The same line therefore gets the same verdict and the same message in
//! both engines.
//!
//! Usage strings and keyword lists come from each style's own table: the pair styles' in their
//! registry entry (`forces::PairStyleEntry::specs`, handed down: this module names no style),
//! the fixes' in [`SPECS`].
//!
//! Rules that used to differ between the engines, now one rule each (docs/input.md):
//! - seeds are integers in 1..=2147483647 (LAMMPS's `int` seeds, and the range the
//!   standalone engine always had);
//! - `pair_coeff I J a gamma0 gamma1` with `friction none` needs gamma1 = 0 (a non-zero
//!   gamma1 has no effect there, so a LAMMPS `pair dpd` habit is refused, not silently kept);
//! - `fix pex/push`: dp finite and > 0, width W in (0, Lx/2] checked at every run's set-up
//!   against the box of that run, `every` in 1..=2147483647.

pub mod fix;

/// The usage line and keywords of one style.
#[derive(Clone, Copy, Debug)]
pub struct StyleSpec {
    /// The command (`pair_style`, `pair_coeff`, `fix`).
    pub command: &'static str,
    /// The style name.
    pub style: &'static str,
    /// The usage string quoted in error messages.
    pub usage: &'static str,
    /// Optional keywords (each followed by one value).
    pub keywords: &'static [&'static str],
}

/// The fixes of this project. The pair styles' specs are in their registry entries
/// (`forces::PairStyleEntry::specs`); `forces::spec` looks a spec up in both (this module, at
/// the bottom of the crate, names no style).
pub(crate) const SPECS: &[StyleSpec] = &[
    fix::NVE,
    fix::NVE_EULER,
    fix::PEX_PUSH,
    fix::FLIP_MOMENTUM,
    fix::FRAMES,
];

/// The largest seed or step interval a style accepts (LAMMPS `int`).
pub(crate) const INT_MAX: u64 = i32::MAX as u64;

/// A token shortened for an error message (a 1 MB token is not echoed in full).
pub(crate) fn shown(tok: &str) -> String {
    const MAX: usize = 40;
    if tok.chars().count() <= MAX {
        tok.to_string()
    } else {
        let head: String = tok.chars().take(MAX).collect();
        format!("{head}… ({} characters)", tok.chars().count())
    }
}

/// A finite floating-point number.
pub(crate) fn parse_f64(tok: &str, what: &str) -> Result<f64, String> {
    let v: f64 = tok
        .parse()
        .map_err(|_| format!("expected a number for {what}, found '{}'", shown(tok)))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what} = '{}' is not finite", shown(tok)))
    }
}

/// An integer of type `T` (range errors included in the message).
pub(crate) fn parse_int<T: std::str::FromStr>(tok: &str, what: &str) -> Result<T, String> {
    tok.parse()
        .map_err(|_| format!("expected an integer for {what}, found '{}'", shown(tok)))
}

/// An integer in `lo..=hi`, checked before any narrowing.
pub(crate) fn parse_int_in(tok: &str, what: &str, lo: u64, hi: u64) -> Result<u64, String> {
    let v: i128 = tok
        .parse()
        .map_err(|_| format!("expected an integer for {what}, found '{}'", shown(tok)))?;
    if v < i128::from(lo) || v > i128::from(hi) {
        return Err(format!("{what} = {} must be in {lo}..={hi}", shown(tok)));
    }
    Ok(v as u64)
}

/// The three words every pair style of this project starts with, `T rc seed`: T and rc finite
/// and > 0, the seed in 1..=2147483647 (`args` has at least three words: `need` first).
pub(crate) fn temp_rc_seed<S: AsRef<str>>(args: &[S]) -> Result<(f64, f64, u32), String> {
    let temp = parse_f64(args[0].as_ref(), "T")?;
    // T = 0, as LAMMPS's pair dpd has it: no random force, the friction kept (every noise
    // scheme: each random part and the correction are proportional to sqrt(kT) or kT).
    if temp.is_nan() || temp < 0.0 {
        return Err(format!("T = {temp} must be >= 0"));
    }
    let rc = parse_f64(args[1].as_ref(), "rc")?;
    if rc <= 0.0 {
        return Err(format!("rc = {rc} must be > 0"));
    }
    let seed = parse_int_in(args[2].as_ref(), "seed", 1, INT_MAX)? as u32;
    Ok((temp, rc, seed))
}

/// How a pair style words its target form `eta E sc S` (the one rule is [`eta_sc_targets`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TargetRules {
    /// η ≤ 0 is refused as soon as η is read (`eta = E must be > 0`), before S is read;
    /// otherwise after S is read, as `eta = E must be finite and > 0`.
    pub eta_checked_first: bool,
    /// Why Sc ≤ 1/2 is unreachable, after `sc = S is unreachable: `.
    pub sc_bound: &'static str,
}

/// The targets (η, Sc) of a `pair_coeff` line's words `eta E sc S` at `args[at..at + 4]`
/// (`args[at]` is `eta`; the caller has checked that the four words are there): the word `sc`
/// in its place (else `usage`), η > 0, Sc > 1/2, as `rules` words them.
pub(crate) fn eta_sc_targets<S: AsRef<str>>(
    args: &[S],
    at: usize,
    usage: &str,
    rules: TargetRules,
) -> Result<(f64, f64), String> {
    let word = |k: usize| args[at + k].as_ref();
    if word(2) != "sc" {
        return Err(format!(
            "expected 'sc' after 'eta {}', got '{}'; usage: {usage}",
            shown(word(1)),
            shown(word(2))
        ));
    }
    let eta = parse_f64(word(1), "eta")?;
    if rules.eta_checked_first && eta <= 0.0 {
        return Err(format!("eta = {eta} must be > 0"));
    }
    let sc = parse_f64(word(3), "sc")?;
    if eta <= 0.0 {
        return Err(format!("eta = {eta} must be finite and > 0"));
    }
    if sc <= 0.5 {
        return Err(format!("sc = {sc} is unreachable: {}", rules.sc_bound));
    }
    Ok((eta, sc))
}

/// At least `n` words, else the usage.
pub fn need<S: AsRef<str>>(args: &[S], n: usize, usage: &str) -> Result<(), String> {
    if args.len() < n {
        Err(format!("missing arguments; usage: {usage}"))
    } else {
        Ok(())
    }
}

/// The type ranges I and J of a `pair_coeff` line (its first two words), for every pair style
/// of this project: as LAMMPS (since 2022), two plain type numbers with J < I are read as `J I`.
pub(crate) fn coeff_types(ti: &str, tj: &str, ntypes: usize) -> Result<TypePairs, String> {
    let mut i = type_range(ti, ntypes)?;
    let mut j = type_range(tj, ntypes)?;
    let plain = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
    if plain(ti) && plain(tj) && j.0 < i.0 {
        std::mem::swap(&mut i, &mut j);
    }
    Ok((i, j))
}

/// Type ranges (I, J), 1-based and inclusive.
pub(crate) type TypePairs = ((usize, usize), (usize, usize));

/// The type pairs (i ≤ j) ranges I and J set, as LAMMPS does: i in I, j in J with j ≥ i.
pub(crate) fn type_pairs((i, j): TypePairs) -> impl Iterator<Item = (usize, usize)> {
    (i.0..=i.1).flat_map(move |a| (j.0.max(a)..=j.1).map(move |b| (a, b)))
}

/// The error of a `pair_coeff` line whose ranges set no pair (`pair_coeff 2* 1`: pairs are set
/// for I ≤ J only, as in LAMMPS), naming its two type words.
pub(crate) fn sets_some_pair(types: TypePairs, ti: &str, tj: &str) -> Result<(), String> {
    if type_pairs(types).next().is_none() {
        return Err(format!(
            "types '{}' '{}' set no type pair (pairs are I <= J)",
            shown(ti),
            shown(tj)
        ));
    }
    Ok(())
}

/// A LAMMPS type range: `*`, `n`, `n*`, `*n`, `m*n`, within 1..=ntypes.
pub(crate) fn type_range(tok: &str, ntypes: usize) -> Result<(usize, usize), String> {
    let bad = || {
        format!(
            "invalid type or type range '{}' (types are 1..{ntypes})",
            shown(tok)
        )
    };
    let (lo, hi) = match tok.split_once('*') {
        None => {
            let t: usize = tok.parse().map_err(|_| bad())?;
            (t, t)
        }
        Some((a, b)) => {
            let lo = if a.is_empty() {
                1
            } else {
                a.parse().map_err(|_| bad())?
            };
            let hi = if b.is_empty() {
                ntypes
            } else {
                b.parse().map_err(|_| bad())?
            };
            (lo, hi)
        }
    };
    if lo < 1 || hi > ntypes || lo > hi {
        return Err(bad());
    }
    Ok((lo, hi))
}

/// `keyword value` pairs after the positional words: calls `f(keyword, value)` for each, with
/// the spec's usage when a value is missing or a keyword unknown.
pub fn keywords<S: AsRef<str>>(
    args: &[S],
    spec: &StyleSpec,
    mut f: impl FnMut(&str, &str) -> Result<(), String>,
) -> Result<(), String> {
    let mut k = 0;
    while k < args.len() {
        let key = args[k].as_ref();
        if !spec.keywords.contains(&key) {
            return Err(format!(
                "unknown {} {} keyword '{}' (expected {}); usage: {}",
                spec.command,
                spec.style,
                shown(key),
                spec.keywords.join(", "),
                spec.usage
            ));
        }
        let value = args
            .get(k + 1)
            .ok_or_else(|| format!("keyword '{key}' needs a value; usage: {}", spec.usage))?;
        f(key, value.as_ref())?;
        k += 2;
    }
    Ok(())
}

/// No words beyond `n` (a trailing token is an error, never silently dropped).
pub(crate) fn at_most<S: AsRef<str>>(args: &[S], n: usize, usage: &str) -> Result<(), String> {
    match args.get(n) {
        Some(extra) => Err(format!(
            "unexpected argument '{}'; usage: {usage}",
            shown(extra.as_ref())
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_are_range_checked_before_narrowing() {
        assert_eq!(parse_int_in("7", "every", 1, INT_MAX), Ok(7));
        assert!(parse_int_in("4294967297", "every", 1, INT_MAX).is_err());
        assert!(parse_int_in("0", "every", 1, INT_MAX).is_err());
        assert!(parse_int_in("-3", "every", 1, INT_MAX).is_err());
        assert!(parse_int_in("1e3", "every", 1, INT_MAX).is_err());
    }

    #[test]
    fn long_tokens_are_cut_in_messages() {
        let tok = "x".repeat(1_000_000);
        let e = parse_f64(&tok, "T").unwrap_err();
        assert!(e.len() < 200, "{}", e.len());
    }

    #[test]
    fn type_ranges() {
        assert_eq!(type_range("*", 3), Ok((1, 3)));
        assert_eq!(type_range("2*", 3), Ok((2, 3)));
        assert_eq!(type_range("*2", 3), Ok((1, 2)));
        assert_eq!(type_range("2", 3), Ok((2, 2)));
        assert!(type_range("0", 3).is_err());
        assert!(type_range("3*2", 3).is_err());
        assert!(type_range("4", 3).is_err());
    }
}
