//! C `printf`-style formatting, as LAMMPS applies it in `thermo_modify format` and
//! `dump_modify format`.
//!
//! [`sprintf`] follows the C standard and prints what glibc prints for the supported subset:
//!
//! - conversions `%d %i` (integers), `%f %F %e %E %g %G` (floating point), `%s` and `%%`;
//! - flags `-` (left-justify), `+` (always a sign), space (a space where `+` would be), `0`
//!   (pad with zeros after the sign; ignored with `-`, and for integers when a precision is given),
//!   `#` (keep the decimal point, and for `%g` keep trailing zeros);
//! - a decimal field width and `.precision` (no `*`);
//! - length modifiers `h hh l ll L q j z t`, accepted and ignored (the value is always an `i64`
//!   or an `f64`), so the `%ld`/`%lld` that LAMMPS uses for step numbers work.
//!
//! The one known difference: `%#g` when rounding carries into a new exponent (`%#g` of
//! 999999.5): glibc 2.36 prints `1.e+06`, dropping the zeros that `#` keeps; we print the
//! standard's `1.00000e+06`.
//!
//! Infinities and NaNs print as `inf`/`nan` (`INF`/`NAN` for upper-case conversions), with a
//! sign when the sign bit is set or a `+`/space flag asks for one, padded with spaces even
//! under the `0` flag, as glibc does.
//!
//! The caller chooses the argument variant: an integer printed with a floating conversion is
//! converted to `f64` first (what C does after the caller's cast, `(double) i`), while a
//! [`FmtArg::Float`] given to `%d` or a number given to `%s` is an error (undefined behaviour
//! in C).

/// One argument of [`sprintf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FmtArg<'a> {
    /// An integer (`%d`, `%i`, …).
    Int(i64),
    /// A floating-point number (`%f`, `%e`, `%g`, …).
    Float(f64),
    /// A string (`%s`).
    Str(&'a str),
}

/// What kind of argument a conversion consumes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArgKind {
    /// An integer conversion.
    Int,
    /// A floating-point conversion.
    Float,
    /// A string conversion.
    Str,
}

#[derive(Debug, Clone, Copy, Default)]
struct Spec {
    left: bool,
    plus: bool,
    space: bool,
    zero: bool,
    alt: bool,
    width: usize,
    precision: Option<usize>,
    conv: u8,
}

impl Spec {
    fn kind(&self) -> ArgKind {
        match self.conv {
            b'd' | b'i' => ArgKind::Int,
            b's' => ArgKind::Str,
            _ => ArgKind::Float,
        }
    }
}

enum Piece<'f> {
    Literal(&'f str),
    Conv(Spec),
}

/// Field widths and precisions above this are refused (glibc would try to allocate them).
const MAX_FIELD: usize = 4096;

fn parse_number(bytes: &[u8], i: &mut usize) -> Option<usize> {
    let start = *i;
    let mut n: usize = 0;
    while *i < bytes.len() && bytes[*i].is_ascii_digit() {
        n = n
            .saturating_mul(10)
            .saturating_add((bytes[*i] - b'0') as usize);
        *i += 1;
    }
    (*i > start).then_some(n)
}

fn parse(fmt: &str) -> Result<Vec<Piece<'_>>, String> {
    let bytes = fmt.as_bytes();
    let mut pieces = Vec::new();
    let mut lit_start = 0;
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != b'%' {
            i += 1;
            continue;
        }
        if lit_start < i {
            pieces.push(Piece::Literal(&fmt[lit_start..i]));
        }
        let pct = i;
        i += 1;
        if i < bytes.len() && bytes[i] == b'%' {
            pieces.push(Piece::Literal("%"));
            i += 1;
            lit_start = i;
            continue;
        }
        let mut spec = Spec::default();
        while i < bytes.len() {
            match bytes[i] {
                b'-' => spec.left = true,
                b'+' => spec.plus = true,
                b' ' => spec.space = true,
                b'0' => spec.zero = true,
                b'#' => spec.alt = true,
                _ => break,
            }
            i += 1;
        }
        if let Some(w) = parse_number(bytes, &mut i) {
            spec.width = w;
        }
        if i < bytes.len() && bytes[i] == b'.' {
            i += 1;
            spec.precision = Some(parse_number(bytes, &mut i).unwrap_or(0));
        }
        if spec.width > MAX_FIELD || spec.precision.is_some_and(|p| p > MAX_FIELD) {
            return Err(format!(
                "format '{fmt}': width or precision above {MAX_FIELD} in the conversion at byte {pct}"
            ));
        }
        while i < bytes.len() && matches!(bytes[i], b'h' | b'l' | b'L' | b'q' | b'j' | b'z' | b't')
        {
            i += 1;
        }
        let Some(&c) = bytes.get(i) else {
            return Err(format!(
                "format '{fmt}': incomplete conversion '{}' at the end",
                &fmt[pct..]
            ));
        };
        match c {
            b'd' | b'i' | b'f' | b'F' | b'e' | b'E' | b'g' | b'G' | b's' => spec.conv = c,
            b'*' => {
                return Err(format!(
                    "format '{fmt}': '*' width/precision (at byte {i}) is not supported"
                ));
            }
            _ => {
                let bad = fmt[i..].chars().next().unwrap_or('?');
                return Err(format!(
                    "format '{fmt}': unsupported conversion '%{bad}' at byte {pct} \
                     (supported: d i f F e E g G s %)"
                ));
            }
        }
        i += 1;
        pieces.push(Piece::Conv(spec));
        lit_start = i;
    }
    if lit_start < bytes.len() {
        pieces.push(Piece::Literal(&fmt[lit_start..]));
    }
    Ok(pieces)
}

/// The argument kinds the conversions of `fmt` consume, in order (`%%` consumes none).
pub fn conversion_kinds(fmt: &str) -> Result<Vec<ArgKind>, String> {
    Ok(parse(fmt)?
        .iter()
        .filter_map(|p| match p {
            Piece::Conv(s) => Some(s.kind()),
            Piece::Literal(_) => None,
        })
        .collect())
}

/// Checks that `fmt` parses and has exactly `n_expected` conversions (not counting `%%`).
pub fn validate_format(fmt: &str, n_expected: usize) -> Result<(), String> {
    let n = conversion_kinds(fmt)?.len();
    if n != n_expected {
        return Err(format!(
            "format '{fmt}' has {n} conversion(s), expected {n_expected}"
        ));
    }
    Ok(())
}

/// Formats `args` by `fmt` as C `sprintf` (glibc) would; see the module docs for the subset.
///
/// Errors: a malformed or unsupported conversion, too few or too many arguments, or an
/// argument whose variant does not suit its conversion.
pub fn sprintf(fmt: &str, args: &[FmtArg]) -> Result<String, String> {
    let pieces = parse(fmt)?;
    let mut out = String::with_capacity(fmt.len() + 16 * args.len());
    let mut next = args.iter();
    let mut n_used = 0;
    for piece in &pieces {
        match piece {
            Piece::Literal(s) => out.push_str(s),
            Piece::Conv(spec) => {
                let Some(arg) = next.next() else {
                    return Err(format!(
                        "format '{fmt}': conversion {} has no argument ({} given)",
                        n_used + 1,
                        args.len()
                    ));
                };
                n_used += 1;
                format_one(&mut out, spec, arg)
                    .map_err(|e| format!("format '{fmt}': argument {n_used} ({arg:?}): {e}"))?;
            }
        }
    }
    if n_used != args.len() {
        return Err(format!(
            "format '{fmt}' has {n_used} conversion(s) but {} argument(s) were given",
            args.len()
        ));
    }
    Ok(out)
}

fn format_one(out: &mut String, spec: &Spec, arg: &FmtArg) -> Result<(), String> {
    match (spec.kind(), arg) {
        (ArgKind::Int, FmtArg::Int(v)) => format_int(out, spec, *v),
        (ArgKind::Float, FmtArg::Float(v)) => format_float(out, spec, *v),
        (ArgKind::Float, FmtArg::Int(v)) => format_float(out, spec, *v as f64),
        (ArgKind::Str, FmtArg::Str(s)) => {
            let s = match spec.precision {
                Some(p) => truncate_chars(s, p),
                None => s,
            };
            pad(out, spec.width, spec.left, "", s, false);
        }
        (ArgKind::Int, _) => return Err(format!("%{} needs an integer", spec.conv as char)),
        (ArgKind::Float, _) => return Err(format!("%{} needs a number", spec.conv as char)),
        (ArgKind::Str, _) => return Err("%s needs a string".to_string()),
    }
    Ok(())
}

fn truncate_chars(s: &str, n: usize) -> &str {
    match s.char_indices().nth(n) {
        Some((i, _)) => &s[..i],
        None => s,
    }
}

/// Writes `sign` then `body` into a field of `width` characters: spaces before (or after, if
/// `left`), or zeros between the sign and the body if `zero`.
fn pad(out: &mut String, width: usize, left: bool, sign: &str, body: &str, zero: bool) {
    let len = sign.len() + body.chars().count();
    let fill = width.saturating_sub(len);
    if left {
        out.push_str(sign);
        out.push_str(body);
        out.extend(std::iter::repeat_n(' ', fill));
    } else if zero {
        out.push_str(sign);
        out.extend(std::iter::repeat_n('0', fill));
        out.push_str(body);
    } else {
        out.extend(std::iter::repeat_n(' ', fill));
        out.push_str(sign);
        out.push_str(body);
    }
}

fn sign_str(negative: bool, spec: &Spec) -> &'static str {
    if negative {
        "-"
    } else if spec.plus {
        "+"
    } else if spec.space {
        " "
    } else {
        ""
    }
}

fn format_int(out: &mut String, spec: &Spec, v: i64) {
    let mut digits = v.unsigned_abs().to_string();
    if let Some(p) = spec.precision {
        if p == 0 && v == 0 {
            digits.clear();
        } else if digits.len() < p {
            digits.insert_str(0, &"0".repeat(p - digits.len()));
        }
    }
    let zero = spec.zero && !spec.left && spec.precision.is_none();
    pad(
        out,
        spec.width,
        spec.left,
        sign_str(v < 0, spec),
        &digits,
        zero,
    );
}

fn format_float(out: &mut String, spec: &Spec, v: f64) {
    let upper = spec.conv.is_ascii_uppercase();
    let sign = sign_str(v.is_sign_negative(), spec);
    if !v.is_finite() {
        let body = match (v.is_nan(), upper) {
            (true, false) => "nan",
            (true, true) => "NAN",
            (false, false) => "inf",
            (false, true) => "INF",
        };
        pad(out, spec.width, spec.left, sign, body, false);
        return;
    }
    let a = v.abs();
    let p = spec.precision.unwrap_or(6);
    let body = match spec.conv.to_ascii_lowercase() {
        b'f' => fixed(a, p, spec.alt),
        b'e' => exponential(a, p, spec.alt, upper),
        _ => general(a, p, spec.alt, upper),
    };
    pad(
        out,
        spec.width,
        spec.left,
        sign,
        &body,
        spec.zero && !spec.left,
    );
}

/// `%f` of a non-negative finite `a`. Rust's fixed formatting is exact and rounds ties to
/// even on the exact binary value, as glibc does in the default rounding mode.
fn fixed(a: f64, p: usize, alt: bool) -> String {
    let mut s = format!("{a:.p$}");
    if alt && p == 0 {
        s.push('.');
    }
    s
}

/// Digits and decimal exponent of `a` rounded to `p` digits after the point, from Rust's
/// exact `{:e}` formatting: `("1.2345", -3)`.
fn sci_parts(a: f64, p: usize) -> (String, i32) {
    let s = format!("{a:.p$e}");
    match s.split_once('e') {
        Some((m, e)) => (m.to_string(), e.parse().unwrap_or(0)),
        None => (s, 0),
    }
}

fn exp_suffix(e: i32, upper: bool) -> String {
    let sign = if e < 0 { '-' } else { '+' };
    let letter = if upper { 'E' } else { 'e' };
    format!("{letter}{sign}{:02}", e.unsigned_abs())
}

/// `%e` of a non-negative finite `a`.
fn exponential(a: f64, p: usize, alt: bool, upper: bool) -> String {
    let (mut m, e) = sci_parts(a, p);
    if alt && p == 0 {
        m.push('.');
    }
    m + &exp_suffix(e, upper)
}

/// `%g` of a non-negative finite `a` (C11 7.21.6.1): with P the precision (0 taken as 1) and X
/// the exponent `%e` would print at precision P − 1, use `%f` with precision P − 1 − X when
/// P > X ≥ −4, else `%e` with precision P − 1; then, unless `#`, drop trailing zeros of the
/// fraction and a trailing decimal point.
///
/// One deliberate difference from glibc (2.36): under `#`, when rounding carries into a new
/// exponent (`%#g` of 999999.5), glibc drops the kept zeros (`1.e+06`); we print what the
/// standard asks for (`1.00000e+06`).
fn general(a: f64, p: usize, alt: bool, upper: bool) -> String {
    let p = p.max(1);
    let (mantissa, x) = sci_parts(a, p - 1);
    let x_is_fixed = x >= -4 && (x as i64) < p as i64;
    let (mut body, suffix) = if x_is_fixed {
        let fp = (p as i64 - 1 - x as i64) as usize;
        (fixed(a, fp, false), String::new())
    } else {
        (mantissa, exp_suffix(x, upper))
    };
    if alt {
        if !body.contains('.') {
            body.push('.');
        }
    } else if body.contains('.') {
        let trimmed = body.trim_end_matches('0').trim_end_matches('.');
        body.truncate(trimmed.len());
    }
    body + &suffix
}
