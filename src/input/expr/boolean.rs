//! The Boolean of LAMMPS's `if` command (its `Variable::evaluate_boolean`): numbers, bare words
//! (strings), parentheses and the operators `!`, `< <= > >=`, `== !=`, `&&`, `||` and `|^`
//! (exclusive or), from the highest precedence to the lowest, left to right within a level.
//!
//! It is not an equal-style formula: no variables (`$` substitution has happened before), no
//! functions, no arithmetic. A number starts with a digit, `.` or `-`; a string with a letter and
//! goes on with letters, digits and `_`. Two strings compare with `==` and `!=` (byte for byte);
//! a string compared with a number, a string under any other operator, and a Boolean that is one
//! string are errors, as in LAMMPS. The result is 1 or 0 (or the number itself when the Boolean
//! is one number).

#[derive(Clone, Debug, PartialEq)]
enum Item {
    Num(f64),
    Str(String),
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Not,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
    Xor,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Op::Or | Op::Xor => 1,
            Op::And => 2,
            Op::Eq | Op::Ne => 3,
            Op::Lt | Op::Le | Op::Gt | Op::Ge => 4,
            Op::Not => 5,
        }
    }
}

const SYNTAX: &str = "invalid Boolean syntax in if command";

/// Evaluate the Boolean `s` of an `if` command (see the module's documentation).
pub fn eval_boolean(s: &str) -> Result<f64, String> {
    let b = s.as_bytes();
    let mut args: Vec<Item> = Vec::new();
    let mut ops: Vec<Op> = Vec::new();
    let mut expect_arg = true;
    let mut i = 0;
    let syntax = |at: usize| format!("{SYNTAX}: '{s}' (column {})", at + 1);
    loop {
        let c = b.get(i).copied();
        match c {
            Some(c) if c.is_ascii_whitespace() => i += 1,
            Some(b'(') => {
                if !expect_arg {
                    return Err(syntax(i));
                }
                let close = matching_paren(b, i).ok_or_else(|| syntax(i))?;
                args.push(Item::Num(eval_boolean(&s[i + 1..close])?));
                expect_arg = false;
                i = close + 1;
            }
            Some(c) if c.is_ascii_digit() || c == b'.' || c == b'-' => {
                if !expect_arg {
                    return Err(syntax(i));
                }
                let start = i;
                i += 1;
                while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                    i += 1;
                }
                if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                    i += 1;
                    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
                        i += 1;
                    }
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
                args.push(Item::Num(atof(&s[start..i])));
                expect_arg = false;
            }
            Some(c) if c.is_ascii_alphabetic() => {
                if !expect_arg {
                    return Err(syntax(i));
                }
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                    i += 1;
                }
                args.push(Item::Str(s[start..i].to_string()));
                expect_arg = false;
            }
            None | Some(b'<' | b'>' | b'=' | b'!' | b'&' | b'|') => {
                let at = i;
                let next = b.get(i + 1).copied();
                let (op, len) = match (c, next) {
                    (None, _) => (None, 0),
                    (Some(b'='), Some(b'=')) => (Some(Op::Eq), 2),
                    (Some(b'!'), Some(b'=')) => (Some(Op::Ne), 2),
                    (Some(b'!'), _) => (Some(Op::Not), 1),
                    (Some(b'<'), Some(b'=')) => (Some(Op::Le), 2),
                    (Some(b'<'), _) => (Some(Op::Lt), 1),
                    (Some(b'>'), Some(b'=')) => (Some(Op::Ge), 2),
                    (Some(b'>'), _) => (Some(Op::Gt), 1),
                    (Some(b'&'), Some(b'&')) => (Some(Op::And), 2),
                    (Some(b'|'), Some(b'|')) => (Some(Op::Or), 2),
                    (Some(b'|'), Some(b'^')) => (Some(Op::Xor), 2),
                    _ => return Err(syntax(at)),
                };
                i += len;
                if op == Some(Op::Not) && expect_arg {
                    ops.push(Op::Not);
                    continue;
                }
                if expect_arg {
                    return Err(syntax(at));
                }
                expect_arg = true;
                let prec = op.map_or(0, Op::precedence);
                while let Some(&top) = ops.last() {
                    if top.precedence() < prec {
                        break;
                    }
                    ops.pop();
                    reduce(top, &mut args, s)?;
                }
                match op {
                    None => break,
                    Some(op) => ops.push(op),
                }
            }
            Some(_) => return Err(syntax(i)),
        }
    }
    if !ops.is_empty() || args.len() != 1 {
        return Err(syntax(s.len()));
    }
    match args.pop() {
        Some(Item::Num(v)) => Ok(v),
        Some(Item::Str(w)) => Err(format!(
            "if command Boolean cannot be a single string ('{w}'): compare it, e.g. \"{w} == word\""
        )),
        None => Err(syntax(s.len())),
    }
}

/// Apply `op` to the top of `args` (one operand for `!`, two otherwise).
fn reduce(op: Op, args: &mut Vec<Item>, s: &str) -> Result<(), String> {
    let short = || format!("{SYNTAX}: '{s}'");
    let b = args.pop().ok_or_else(short)?;
    let truth = |t: bool| Item::Num(if t { 1.0 } else { 0.0 });
    if op == Op::Not {
        let Item::Num(v) = b else {
            return Err(only_numbers(s));
        };
        args.push(truth(v == 0.0));
        return Ok(());
    }
    let a = args.pop().ok_or_else(short)?;
    let r = match (a, b) {
        (Item::Num(x), Item::Num(y)) => truth(match op {
            Op::Lt => x < y,
            Op::Le => x <= y,
            Op::Gt => x > y,
            Op::Ge => x >= y,
            Op::Eq => x == y,
            Op::Ne => x != y,
            Op::And => x != 0.0 && y != 0.0,
            Op::Or => x != 0.0 || y != 0.0,
            Op::Xor => (x == 0.0) != (y == 0.0),
            Op::Not => false,
        }),
        (Item::Str(x), Item::Str(y)) => match op {
            Op::Eq => truth(x == y),
            Op::Ne => truth(x != y),
            _ => return Err(only_numbers(s)),
        },
        (Item::Str(w), Item::Num(_)) | (Item::Num(_), Item::Str(w)) => {
            return Err(match op {
                Op::Eq | Op::Ne => format!(
                    "if command Boolean compares the string '{w}' with a number: '{s}' \
                     (strings compare only with strings, with == and !=)"
                ),
                _ => only_numbers(s),
            });
        }
    };
    args.push(r);
    Ok(())
}

fn only_numbers(s: &str) -> String {
    format!(
        "if command Boolean: < <= > >= && || |^ and ! operate on numbers only: '{s}' \
         (strings compare with == and !=)"
    )
}

/// The index of the `)` that closes the `(` at `open`.
fn matching_paren(b: &[u8], open: usize) -> Option<usize> {
    let mut level = 0usize;
    for (k, &c) in b.iter().enumerate().skip(open) {
        match c {
            b'(' => level += 1,
            b')' => {
                level -= 1;
                if level == 0 {
                    return Some(k);
                }
            }
            _ => {}
        }
    }
    None
}

/// C's `atof`: the longest leading number, 0 when there is none (`-`, `.`, `1e`).
fn atof(t: &str) -> f64 {
    (1..=t.len())
        .rev()
        .find_map(|n| t[..n].parse::<f64>().ok())
        .unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::eval_boolean as b;

    // The Booleans of LAMMPS's own unit test of the if command (unittest/commands/
    // test_variables.cpp, IfCommand), re-stated: what is true, what is false, what is refused;
    // the verdicts are those of LAMMPS 20220106's `if` (run on each case).
    #[test]
    fn lammps_if_cases() {
        for t in [
            "1>0",
            "0<1",
            "(0<=0)",
            "(1>=1)",
            "(-1.0e-1<0.0E+0)|^(1<0)",
            "(1==1.0)&&(2>=1)",
            "!(a==b)",
            "x==x|^1==0",
            "x!=x|^a!=b",
            "(1)",
            "step_a == step_a",
            "!((1!=1.0)||(2|^1))",
        ] {
            assert_eq!(b(t), Ok(1.0), "{t}");
        }
        for f in ["1>2", "2<1", "(1<=0)", "(0>=1)", "(1>=2)&&(0&&1)", "!1"] {
            assert_eq!(b(f), Ok(0.0), "{f}");
        }
        for (bad, why) in [
            ("()", "syntax"),
            ("1 1", "syntax"),
            ("1a", "syntax"),
            ("1=<2", "syntax"),
            ("1&<2", "syntax"),
            ("1|<2", "syntax"),
            ("(1)(", "syntax"),
            ("(1)1", "syntax"),
            ("1!=a", "with a number"),
            ("(v_one==1.0)&&(2>=1)", "with a number"),
            ("a<b", "numbers only"),
            ("a>=b", "numbers only"),
            ("(something)", "single string"),
            ("", "syntax"),
        ] {
            let e = b(bad).expect_err(bad);
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    #[test]
    fn precedence_and_numbers() {
        // && binds tighter than ||: 1 || (0 && 0) = 1.
        assert_eq!(b("1 || 0 && 0"), Ok(1.0));
        // Comparisons before &&.
        assert_eq!(b("2 > 1 && 3 < 4"), Ok(1.0));
        // A lone number is its own value.
        assert_eq!(b("2.5"), Ok(2.5));
        assert_eq!(b("-3e2 < -299"), Ok(1.0));
        // ! before comparison: !0 < 2 is (!0) < 2.
        assert_eq!(b("!0 < 2"), Ok(1.0));
    }
}
