//! LAMMPS equal-style variable formulas (`variable name equal <formula>`).
//!
//! Supported, following the LAMMPS `variable` documentation:
//!
//! - numbers: `100`, `-5.4`, `2.8e-4`, `.5`, `1.`;
//! - the constant `PI`;
//! - `v_name`: another variable, through [`ExprContext::variable`];
//! - any other bare word: a thermo keyword (`step`, `temp`, `press`, `vol`, …), through
//!   [`ExprContext::thermo`];
//! - functions `sqrt exp ln log abs sign sin cos tan asin acos atan atan2(y,x) ceil floor round
//!   sinh cosh tanh` (`ln` is the natural log, `log` base 10, `round` rounds halves away from
//!   zero as C `round`);
//! - operators, from the highest precedence to the lowest, as the documentation lists them:
//!
//!   | level | operators | |
//!   |---|---|---|
//!   | 1 | unary `-`, unary `!` | prefix |
//!   | 2 | `^` | |
//!   | 3 | `*` `/` `%` | |
//!   | 4 | `+` `-` | |
//!   | 5 | `<` `<=` `>` `>=` | |
//!   | 6 | `==` `!=` | |
//!   | 7 | `&&` | |
//!   | 8 | `\|\|` and `\|^` (exclusive or) | |
//!
//!   Binary operators are evaluated left to right, `^` included: `2^3^2` is `(2^3)^2` = 64,
//!   and because unary minus binds tighter than `^`, `-2^2` is 4 (the documentation states
//!   both). Comparisons and logical operators give 1 or 0; any non-zero value is true. Both
//!   operands of `&&`/`||` are always evaluated (no short-circuit), so an error anywhere in a
//!   formula is always reported.
//!
//! Errors, as LAMMPS reports them: division or modulo by zero, `sqrt` of a negative value,
//! `ln`/`log` of a non-positive value, `asin`/`acos` outside [−1, 1]. Compute, fix and atom
//! references (`c_ID`, `f_ID`, `x[12]`), vector variables and group functions are not
//! supported and give an error naming them.
//!
//! Every error names the offending token and its 1-based column in the formula.

/// What a formula may refer to: variables and thermo keywords.
pub trait ExprContext {
    /// The value of equal-style variable `name` (the part after `v_`).
    fn variable(&self, name: &str) -> Result<f64, String>;
    /// The value of thermo keyword `keyword`; `None` if the word is not a thermo keyword.
    fn thermo(&self, keyword: &str) -> Option<Result<f64, String>>;
}

/// Evaluates an equal-style formula.
pub fn eval_equal(expr: &str, ctx: &dyn ExprContext) -> Result<f64, String> {
    let tokens = tokenize(expr)?;
    let mut p = Parser {
        src: expr,
        tokens,
        pos: 0,
        depth: 0,
        ctx,
    };
    let v = p.or_level()?;
    match p.tokens.get(p.pos) {
        None => Ok(v),
        Some(t) => Err(p.err_at(t, "unexpected")),
    }
}

/// Nesting limit (parentheses, function calls and unary operators), so that no input can
/// exhaust the stack.
const MAX_DEPTH: usize = 200;

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Word(String),
    Op(&'static str),
    LParen,
    RParen,
    Comma,
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    /// 1-based column (in characters) of the first character.
    col: usize,
    text: String,
}

const OPERATORS: [&str; 16] = [
    "&&", "||", "|^", "==", "!=", "<=", ">=", "<", ">", "+", "-", "*", "/", "%", "^", "!",
];

fn tokenize(src: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<(usize, char)> = src.char_indices().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let (b, c) = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let rest = &src[b..];
        if c.is_ascii_digit() || (c == '.' && rest[1..].starts_with(|d: char| d.is_ascii_digit())) {
            let len = number_len(rest.as_bytes());
            let text = &rest[..len];
            let v: f64 = text
                .parse()
                .map_err(|_| format!("bad number '{text}' (column {col}) in '{src}'"))?;
            out.push(Token {
                tok: Tok::Num(v),
                col,
                text: text.to_string(),
            });
            i += text.chars().count();
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let len = rest
                .find(|d: char| !(d.is_ascii_alphanumeric() || d == '_'))
                .unwrap_or(rest.len());
            let word = &rest[..len];
            out.push(Token {
                tok: Tok::Word(word.to_string()),
                col,
                text: word.to_string(),
            });
            i += len;
            continue;
        }
        let single = match c {
            '(' => Some(Tok::LParen),
            ')' => Some(Tok::RParen),
            ',' => Some(Tok::Comma),
            _ => None,
        };
        if let Some(tok) = single {
            out.push(Token {
                tok,
                col,
                text: c.to_string(),
            });
            i += 1;
            continue;
        }
        match OPERATORS.iter().find(|op| rest.starts_with(**op)) {
            Some(op) => {
                out.push(Token {
                    tok: Tok::Op(op),
                    col,
                    text: op.to_string(),
                });
                i += op.len();
            }
            None if c == '[' => {
                return Err(format!(
                    "indexed references (x[1], c_ID[2]) are not supported: '[' (column {col}) \
                     in '{src}'"
                ));
            }
            None => {
                return Err(format!(
                    "unexpected character '{c}' (column {col}) in '{src}'"
                ));
            }
        }
    }
    Ok(out)
}

/// Length in bytes of the number at the start of `s`: digits, an optional fraction and an
/// optional exponent (`e`/`E`, optional sign, at least one digit).
fn number_len(s: &[u8]) -> usize {
    let digits = |mut i: usize| {
        while i < s.len() && s[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits(0);
    if i < s.len() && s[i] == b'.' {
        i = digits(i + 1);
    }
    if i < s.len() && (s[i] == b'e' || s[i] == b'E') {
        let mut j = i + 1;
        if j < s.len() && (s[j] == b'+' || s[j] == b'-') {
            j += 1;
        }
        let k = digits(j);
        if k > j {
            i = k;
        }
    }
    i
}

struct Parser<'a> {
    src: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    depth: usize,
    ctx: &'a dyn ExprContext,
}

fn truth(v: f64) -> bool {
    v != 0.0
}

fn flag(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

impl Parser<'_> {
    fn err_at(&self, t: &Token, what: &str) -> String {
        format!("{what} '{}' (column {}) in '{}'", t.text, t.col, self.src)
    }

    fn err_end(&self, what: &str) -> String {
        format!("{what} at the end of '{}'", self.src)
    }

    fn peek_op(&self) -> Option<&'static str> {
        match self.tokens.get(self.pos) {
            Some(Token {
                tok: Tok::Op(op), ..
            }) => Some(op),
            _ => None,
        }
    }

    /// Parses a left-associative level whose operators are `ops`, with `next` below it.
    fn binary_level(
        &mut self,
        ops: &[&str],
        next: fn(&mut Self) -> Result<f64, String>,
        apply: fn(&Self, &str, f64, f64, &Token) -> Result<f64, String>,
    ) -> Result<f64, String> {
        let mut lhs = next(self)?;
        while let Some(op) = self.peek_op().filter(|op| ops.contains(op)) {
            let op_tok = self.tokens[self.pos].clone();
            self.pos += 1;
            let rhs = next(self)?;
            lhs = apply(self, op, lhs, rhs, &op_tok)?;
        }
        Ok(lhs)
    }

    fn or_level(&mut self) -> Result<f64, String> {
        self.binary_level(&["||", "|^"], Self::and_level, |_, op, a, b, _| {
            Ok(flag(if op == "||" {
                truth(a) || truth(b)
            } else {
                truth(a) != truth(b)
            }))
        })
    }

    fn and_level(&mut self) -> Result<f64, String> {
        self.binary_level(&["&&"], Self::eq_level, |_, _, a, b, _| {
            Ok(flag(truth(a) && truth(b)))
        })
    }

    fn eq_level(&mut self) -> Result<f64, String> {
        self.binary_level(&["==", "!="], Self::rel_level, |_, op, a, b, _| {
            Ok(flag(if op == "==" { a == b } else { a != b }))
        })
    }

    fn rel_level(&mut self) -> Result<f64, String> {
        self.binary_level(
            &["<", "<=", ">", ">="],
            Self::add_level,
            |_, op, a, b, _| {
                Ok(flag(match op {
                    "<" => a < b,
                    "<=" => a <= b,
                    ">" => a > b,
                    _ => a >= b,
                }))
            },
        )
    }

    fn add_level(&mut self) -> Result<f64, String> {
        self.binary_level(&["+", "-"], Self::mul_level, |_, op, a, b, _| {
            Ok(if op == "+" { a + b } else { a - b })
        })
    }

    fn mul_level(&mut self) -> Result<f64, String> {
        self.binary_level(
            &["*", "/", "%"],
            Self::pow_level,
            |p, op, a, b, t| match op {
                "*" => Ok(a * b),
                _ if b == 0.0 => Err(p.err_at(
                    t,
                    if op == "/" {
                        "division by zero at"
                    } else {
                        "modulo by zero at"
                    },
                )),
                "/" => Ok(a / b),
                _ => Ok(a % b),
            },
        )
    }

    fn pow_level(&mut self) -> Result<f64, String> {
        self.binary_level(&["^"], Self::unary, |_, _, a, b, _| Ok(a.powf(b)))
    }

    fn enter(&mut self) -> Result<(), String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let msg = format!("formula nested deeper than {MAX_DEPTH} levels");
            return Err(match self.tokens.get(self.pos) {
                Some(t) => self.err_at(t, &format!("{msg} at")),
                None => self.err_end(&msg),
            });
        }
        Ok(())
    }

    fn unary(&mut self) -> Result<f64, String> {
        self.enter()?;
        let v = match self.peek_op() {
            Some("-") => {
                self.pos += 1;
                self.unary().map(|v| -v)
            }
            Some("!") => {
                self.pos += 1;
                self.unary().map(|v| flag(!truth(v)))
            }
            _ => self.primary(),
        };
        self.depth -= 1;
        v
    }

    fn expect(&mut self, want: Tok, name: &str) -> Result<(), String> {
        match self.tokens.get(self.pos) {
            Some(t) if t.tok == want => {
                self.pos += 1;
                Ok(())
            }
            Some(t) => Err(self.err_at(t, &format!("expected {name}, found"))),
            None => Err(self.err_end(&format!("expected {name}"))),
        }
    }

    fn primary(&mut self) -> Result<f64, String> {
        let Some(t) = self.tokens.get(self.pos).cloned() else {
            return Err(self.err_end("expected a value"));
        };
        self.pos += 1;
        match &t.tok {
            Tok::Num(v) => Ok(*v),
            Tok::LParen => {
                let v = self.or_level()?;
                self.expect(Tok::RParen, "')'")?;
                Ok(v)
            }
            Tok::Word(w) => {
                if matches!(
                    self.tokens.get(self.pos),
                    Some(Token {
                        tok: Tok::LParen,
                        ..
                    })
                ) {
                    self.pos += 1;
                    self.function(w, &t)
                } else {
                    self.word(w, &t)
                }
            }
            _ => Err(self.err_at(&t, "expected a value, found")),
        }
    }

    fn word(&mut self, w: &str, t: &Token) -> Result<f64, String> {
        if w == "PI" {
            return Ok(std::f64::consts::PI);
        }
        if let Some(name) = w.strip_prefix("v_") {
            return self
                .ctx
                .variable(name)
                .map_err(|e| format!("{} ({e})", self.err_at(t, "variable")));
        }
        if w.starts_with("c_") || w.starts_with("f_") {
            return Err(self.err_at(t, "compute and fix references are not supported:"));
        }
        match self.ctx.thermo(w) {
            Some(r) => r.map_err(|e| format!("{} ({e})", self.err_at(t, "thermo keyword"))),
            None => Err(self.err_at(t, "unknown word")),
        }
    }

    fn function(&mut self, name: &str, t: &Token) -> Result<f64, String> {
        self.enter()?;
        let r = self.function_inner(name, t);
        self.depth -= 1;
        r
    }

    fn function_inner(&mut self, name: &str, t: &Token) -> Result<f64, String> {
        let mut args = vec![self.or_level()?];
        while matches!(
            self.tokens.get(self.pos),
            Some(Token {
                tok: Tok::Comma,
                ..
            })
        ) {
            self.pos += 1;
            args.push(self.or_level()?);
        }
        self.expect(Tok::RParen, "')'")?;
        let n_args = if name == "atan2" { 2 } else { 1 };
        let known = matches!(
            name,
            "sqrt"
                | "exp"
                | "ln"
                | "log"
                | "abs"
                | "sign"
                | "sin"
                | "cos"
                | "tan"
                | "asin"
                | "acos"
                | "atan"
                | "atan2"
                | "ceil"
                | "floor"
                | "round"
                | "sinh"
                | "cosh"
                | "tanh"
        );
        if !known {
            return Err(self.err_at(t, "unknown function"));
        }
        if args.len() != n_args {
            return Err(self.err_at(
                t,
                &format!("{n_args} argument(s) expected, {} given to", args.len()),
            ));
        }
        let x = args[0];
        let domain = |ok: bool, what: &str| {
            if ok {
                Ok(())
            } else {
                Err(self.err_at(t, &format!("{what} (argument {x}) for")))
            }
        };
        Ok(match name {
            "sqrt" => {
                domain(x >= 0.0, "square root of a negative value")?;
                x.sqrt()
            }
            "exp" => x.exp(),
            "ln" => {
                domain(x > 0.0, "log of a zero or negative value")?;
                x.ln()
            }
            "log" => {
                domain(x > 0.0, "log of a zero or negative value")?;
                x.log10()
            }
            "abs" => x.abs(),
            "sign" => {
                if x >= 0.0 {
                    1.0
                } else {
                    -1.0
                }
            }
            "sin" => x.sin(),
            "cos" => x.cos(),
            "tan" => x.tan(),
            "asin" => {
                domain((-1.0..=1.0).contains(&x), "asin outside [-1, 1]")?;
                x.asin()
            }
            "acos" => {
                domain((-1.0..=1.0).contains(&x), "acos outside [-1, 1]")?;
                x.acos()
            }
            "atan" => x.atan(),
            "atan2" => x.atan2(args[1]),
            "ceil" => x.ceil(),
            "floor" => x.floor(),
            "round" => x.round(),
            "sinh" => x.sinh(),
            "cosh" => x.cosh(),
            _ => x.tanh(),
        })
    }
}
