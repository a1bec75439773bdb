//! Numbers for messages: [`fmt_g`] prints like C's `%g` (six significant digits), so an error
//! or warning shows `1e+300`, not the 301 digits of Rust's `{}`; [`short`] is the round-trip
//! form of `dpdnl design`/`theory` (pasting a printed number back reproduces it bit for bit).

/// The shortest round-trip decimal form; exponent form outside [1e-5, 1e16).
pub fn short(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-5..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `x` as C's `printf("%g", x)` prints it: six significant digits, trailing zeros removed,
/// exponent form (`1.5e-07`, `1e+300`, at least two exponent digits) when the decimal exponent
/// after rounding is below −4 or at least 6, else fixed form (`0.0001`, `123457`, `-2.5`).
/// Non-finite values keep Rust's spelling (`NaN`, `inf`, `-inf`) rather than C's `nan`.
pub fn fmt_g(x: f64) -> String {
    const P: i32 = 6;
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return if x.is_sign_negative() { "-0" } else { "0" }.into();
    }
    // The exponent after rounding to P significant digits decides the form, as in C.
    let sci = format!("{:.*e}", (P - 1) as usize, x);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if !(-4..P).contains(&exp) {
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", strip_zeros(mantissa), exp.abs())
    } else {
        let decimals = (P - 1 - exp) as usize;
        strip_zeros(&format!("{x:.decimals$}")).to_string()
    }
}

/// `1.50000` → `1.5`, `2.000` → `2`; integers are left alone.
fn strip_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}
