//! Equal-style formulas: values, precedence (as the LAMMPS `variable` documentation states it),
//! and errors that name the token and column.

use dpdnl::input::expr::{ExprContext, eval_equal};

struct Ctx;

impl ExprContext for Ctx {
    fn variable(&self, name: &str) -> Result<f64, String> {
        match name {
            "a" => Ok(2.0),
            "kT" => Ok(1.5),
            "bad" => Err("variable bad is a string".into()),
            _ => Err(format!("no variable {name}")),
        }
    }
    fn thermo(&self, keyword: &str) -> Option<Result<f64, String>> {
        match keyword {
            "step" => Some(Ok(1000.0)),
            "temp" => Some(Ok(0.9)),
            "vol" => Some(Ok(1000.0)),
            "press" => Some(Err("pressure not available before the first run".into())),
            _ => None,
        }
    }
}

fn ev(s: &str) -> f64 {
    match eval_equal(s, &Ctx) {
        Ok(v) => v,
        Err(e) => panic!("{s:?} failed: {e}"),
    }
}

fn err(s: &str) -> String {
    match eval_equal(s, &Ctx) {
        Ok(v) => panic!("{s:?} should fail, gave {v}"),
        Err(e) => e,
    }
}

#[test]
fn numbers() {
    // Exactly representable results, or results of a single correctly rounded operation.
    assert_eq!(ev("100"), 100.0);
    assert_eq!(ev("-5.4"), -5.4);
    assert_eq!(ev("2.8e-4"), 2.8e-4);
    assert_eq!(ev(".5"), 0.5);
    assert_eq!(ev("1."), 1.0);
    assert_eq!(ev("1E+3"), 1000.0);
    assert_eq!(ev("  7 "), 7.0);
}

#[test]
fn precedence_as_documented() {
    // Unary minus binds tighter than ^ ("-2^2 evaluates to 4").
    assert_eq!(ev("-2^2"), 4.0);
    // Left to right, ^ included.
    assert_eq!(ev("2^3^2"), 64.0);
    assert_eq!(ev("2^-1"), 0.5);
    assert_eq!(ev("2*3^2"), 18.0);
    assert_eq!(ev("1+2*3"), 7.0);
    assert_eq!(ev("(1+2)*3"), 9.0);
    assert_eq!(ev("8/4/2"), 1.0);
    assert_eq!(ev("10-4-3"), 3.0);
    assert_eq!(ev("7%4*2"), 6.0);
    assert_eq!(ev("-7%4"), -3.0); // fmod keeps the sign of the dividend
    assert_eq!(ev("1+1<3"), 1.0);
    assert_eq!(ev("1<2==1"), 1.0); // (1<2)==1
    assert_eq!(ev("2==2&&0"), 0.0);
    assert_eq!(ev("0&&1||1"), 1.0); // (0&&1)||1
    assert_eq!(ev("1||0&&0"), 1.0); // 1||(0&&0)
    assert_eq!(ev("1|^1"), 0.0);
    assert_eq!(ev("1|^0"), 1.0);
    assert_eq!(ev("!0"), 1.0);
    assert_eq!(ev("!3"), 0.0);
    assert_eq!(ev("!0+1"), 2.0);
    assert_eq!(ev("--3"), 3.0);
    assert_eq!(ev("2*-3"), -6.0);
    assert_eq!(ev("3>=3"), 1.0);
    assert_eq!(ev("3>3"), 0.0);
    assert_eq!(ev("3<=2"), 0.0);
    assert_eq!(ev("3!=2"), 1.0);
}

#[test]
fn functions_and_constants() {
    assert_eq!(ev("PI"), std::f64::consts::PI);
    assert_eq!(ev("sqrt(16)"), 4.0);
    assert_eq!(ev("abs(-2.5)"), 2.5);
    assert_eq!(ev("ceil(1.2)+floor(-1.2)"), 0.0);
    assert_eq!(ev("round(2.5)"), 3.0);
    assert_eq!(ev("round(-2.5)"), -3.0);
    assert_eq!(ev("log(1000)"), 3.0);
    assert_eq!(ev("ln(1)"), 0.0);
    assert_eq!(ev("exp(0)"), 1.0);
    assert_eq!(ev("sign(-0.1)"), -1.0);
    assert_eq!(ev("atan2(0,-1)"), std::f64::consts::PI);
    let close = |s: &str, want: f64| {
        let got = ev(s);
        assert!(
            (got - want).abs() <= 1e-15 * want.abs().max(1.0),
            "{s}: {got} vs {want}"
        );
    };
    close("sin(PI/6)", 0.5);
    close("cos(PI/3)", 0.5);
    close("tan(PI/4)", 1.0);
    close("asin(1)", std::f64::consts::FRAC_PI_2);
    close("acos(0)", std::f64::consts::FRAC_PI_2);
    close("atan(1)*4", std::f64::consts::PI);
    close("cosh(1)^2-sinh(1)^2", 1.0);
    close("tanh(0.5)", 0.5f64.tanh());
    close("sqrt(2)^2", 2.0);
}

#[test]
fn references() {
    assert_eq!(ev("v_a*v_kT"), 3.0);
    assert_eq!(ev("step/vol"), 1.0);
    assert_eq!(ev("temp*(v_a+1)"), 0.9 * 3.0);
    assert_eq!(ev("sqrt(v_a^2)"), 2.0);
}

#[test]
fn errors_name_token_and_column() {
    let cases: &[(&str, &[&str])] = &[
        ("1 + foo", &["unknown word", "'foo'", "column 5"]),
        ("v_nope + 1", &["'v_nope'", "no variable nope"]),
        ("2*v_bad", &["'v_bad'", "string"]),
        ("press/2", &["'press'", "not available"]),
        ("1/0", &["division by zero", "'/'", "column 2"]),
        ("1%0", &["modulo by zero", "column 2"]),
        ("sqrt(-1)", &["square root", "'sqrt'"]),
        ("ln(0)", &["log of a zero"]),
        ("log(-3)", &["log of a zero"]),
        ("asin(2)", &["asin"]),
        ("acos(-1.5)", &["acos"]),
        ("foo(1)", &["unknown function", "'foo'"]),
        ("atan2(1)", &["2 argument(s) expected", "'atan2'"]),
        ("sin(1,2)", &["1 argument(s) expected", "'sin'"]),
        ("(1+2", &["expected ')'", "end"]),
        ("1+2)", &["unexpected", "')'", "column 4"]),
        ("1 2", &["unexpected", "'2'", "column 3"]),
        ("", &["expected a value"]),
        ("1+", &["expected a value", "end"]),
        ("*3", &["'*'", "column 1"]),
        ("3 $ 4", &["'$'", "column 3"]),
        (
            "x[12]",
            &["atom references are not supported here", "column 1"],
        ),
        ("v_a[2]", &["indexed", "column 4"]),
        ("c_myTemp", &["compute and fix", "'c_myTemp'"]),
        ("f_ave", &["compute and fix"]),
        ("1 = 2", &["'='", "column 3"]),
    ];
    for (s, needles) in cases {
        let e = err(s);
        for n in *needles {
            assert!(e.contains(n), "error for {s:?} lacks {n:?}: {e}");
        }
        assert!(
            e.contains(&format!("'{s}'")),
            "error for {s:?} should quote it: {e}"
        );
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let deep = format!("{}1{}", "(".repeat(10_000), ")".repeat(10_000));
    assert!(err(&deep).contains("nested deeper"));
    let minus = format!("{}1", "-".repeat(10_000));
    assert!(err(&minus).contains("nested deeper"));
    let calls = format!("{}1{}", "abs(".repeat(10_000), ")".repeat(10_000));
    assert!(err(&calls).contains("nested deeper"));
    // Moderate nesting is fine.
    assert_eq!(ev(&format!("{}1{}", "(".repeat(100), ")".repeat(100))), 1.0);
}

#[test]
fn random_strings_never_panic() {
    // A fixed xorshift generator over an alphabet of formula characters: every string must give
    // Ok or Err. Also check a property: an Ok result of "(s)" equals that of "s".
    let alphabet: Vec<char> = "0123456789.eE+-*/%^!<>=&|(),_ vPIsqrtabcos[]λ\t"
        .chars()
        .collect();
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut n_ok = 0;
    for _ in 0..50_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let len = (state % 12) as usize;
        let mut s = String::new();
        let mut r = state;
        for _ in 0..len {
            r = r.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            s.push(alphabet[((r >> 33) % alphabet.len() as u64) as usize]);
        }
        if let Ok(v) = eval_equal(&s, &Ctx) {
            n_ok += 1;
            let w = eval_equal(&format!("({s})"), &Ctx).expect("parenthesised valid formula");
            assert!(v == w || (v.is_nan() && w.is_nan()), "{s:?}: {v} vs {w}");
        }
    }
    assert!(
        n_ok > 100,
        "the generator should produce some valid formulas ({n_ok})"
    );
}
