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

/// `x` with `d` decimals where that shows it (|x| in [10^(3−d), 1e6): at least four
/// significant digits, as `{x:.d}`), else in exponent form with `d` significant digits: the
/// numbers of `units si` (γ0 ~ 1e-12) or `nano` (n ~ 1e25) would print as 0.0000 or as
/// thirty digits in fixed form.
pub fn fixed(x: f64, d: usize) -> String {
    let a = x.abs();
    let lo = 10f64.powi(3 - d as i32);
    if x == 0.0 || !x.is_finite() || (lo..1e6).contains(&a) {
        format!("{x:.d$}")
    } else {
        format!("{x:.prec$e}", prec = d.saturating_sub(1))
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

#[cfg(test)]
mod tests {
    use super::fixed;

    #[test]
    fn fixed_keeps_decimals_in_range_and_switches_outside() {
        assert_eq!(fixed(140.8123456789012, 10), "140.8123456789");
        assert_eq!(fixed(0.0, 10), "0.0000000000");
        assert_eq!(fixed(0.0139, 6), "0.013900");
        assert_eq!(fixed(2.0e-12, 10), "2.000000000e-12");
        assert_eq!(fixed(3.0e18, 10), "3.000000000e18");
        assert_eq!(fixed(-2.5e-4, 6), "-2.50000e-4");
        assert_eq!(fixed(2.0e-12, 10).parse::<f64>(), Ok(2.0e-12));
    }
}
