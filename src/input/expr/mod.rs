//! LAMMPS variable formulas: equal-style (`variable name equal <formula>`) and atom-style
//! (`variable name atom <formula>`).
//!
//! Supported, following the LAMMPS `variable` documentation:
//!
//! - numbers: `100`, `-5.4`, `2.8e-4`, `.5`, `1.`;
//! - the constant `PI`;
//! - `v_name`: another variable, through [`ExprContext::variable`];
//! - `c_ID`, `c_ID[i]`, `f_ID`, `f_ID[i]`: a global scalar or vector element of a compute or fix,
//!   through [`ExprContext::reference`] (a context without computes rejects them);
//! - any other bare word: a thermo keyword (`step`, `temp`, `press`, `vol`, …), through
//!   [`ExprContext::thermo`];
//! - atom references `x[ID]` … (below);
//! - in atom-style formulas only, the per-atom values of [`AtomValue`] (`id mass type x y z vx
//!   vy vz fx fy fz`) and `v_name` of other atom-style variables;
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
//! `ln`/`log` of a non-positive value, `asin`/`acos` outside [−1, 1]. Vector variables and
//! group functions are not supported and give an error naming them.
//!
//! Atom references, in equal- and atom-style formulas: `x[ID]`, `vx[ID]`, `fx[ID]`,
//! `mass[ID]`, `type[ID]`, … (any word of [`AtomValue`] with an atom ID from 1), through
//! [`ExprContext::atom`]; an ID no atom has is an error, as in LAMMPS.
//!
//! A formula is parsed once into a [`Formula`] and can be evaluated many times. An atom-style
//! formula is first *bound* ([`Formula::bind_atoms`]): every part that does not depend on the
//! atom (thermo keywords, equal-style variables, constants) is evaluated once, and the rest is
//! evaluated per atom with [`Formula::eval_atom`].
//!
//! Every error names the offending token and its 1-based column in the formula.

mod boolean;
mod token;
pub use boolean::eval_boolean;
use token::tokenize;

/// What a formula may refer to: variables, thermo keywords, computes and fixes.
pub trait ExprContext {
    /// The value of equal-style variable `name` (the part after `v_`).
    fn variable(&self, name: &str) -> Result<f64, String>;
    /// The value of thermo keyword `keyword`; `None` if the word is not a thermo keyword.
    fn thermo(&self, keyword: &str) -> Option<Result<f64, String>>;
    /// The global scalar (`index` None) or 1-based vector element of compute or fix `id`;
    /// `None` if this context has no computes or fixes.
    fn reference(
        &self,
        _kind: RefKind,
        _id: &str,
        _index: Option<usize>,
    ) -> Option<Result<f64, String>> {
        None
    }
    /// The value `value` of the atom whose ID is `id` (LAMMPS's atom references `x[ID]`,
    /// `vx[ID]`, `mass[ID]`, …); `None` if this context has no atoms.
    fn atom(&self, _value: AtomValue, _id: u64) -> Option<Result<f64, String>> {
        None
    }
}

/// `c_` or `f_`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefKind {
    /// `c_ID`: a compute.
    Compute,
    /// `f_ID`: a fix.
    Fix,
}

/// A per-atom value usable in atom-style formulas (LAMMPS's "atom values").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AtomValue {
    /// `id`: the atom tag.
    Id,
    /// `mass`.
    Mass,
    /// `type`.
    Type,
    /// `x`, `y`, `z`: the position as stored (wrapped at neighbour-list builds, as LAMMPS).
    X,
    /// See [`AtomValue::X`].
    Y,
    /// See [`AtomValue::X`].
    Z,
    /// `vx`, `vy`, `vz`.
    Vx,
    /// See [`AtomValue::Vx`].
    Vy,
    /// See [`AtomValue::Vx`].
    Vz,
    /// `fx`, `fy`, `fz`.
    Fx,
    /// See [`AtomValue::Fx`].
    Fy,
    /// See [`AtomValue::Fx`].
    Fz,
}

impl AtomValue {
    /// The atom value named `word`, if any.
    pub fn from_word(word: &str) -> Option<AtomValue> {
        Some(match word {
            "id" => AtomValue::Id,
            "mass" => AtomValue::Mass,
            "type" => AtomValue::Type,
            "x" => AtomValue::X,
            "y" => AtomValue::Y,
            "z" => AtomValue::Z,
            "vx" => AtomValue::Vx,
            "vy" => AtomValue::Vy,
            "vz" => AtomValue::Vz,
            "fx" => AtomValue::Fx,
            "fy" => AtomValue::Fy,
            "fz" => AtomValue::Fz,
            _ => return None,
        })
    }
}

/// What binding an atom-style formula needs besides the scalar context.
pub trait AtomBinder {
    /// `Some(bound formula)` if `name` is an atom-style variable, `None` otherwise (then
    /// `v_name` is evaluated as an equal-style variable through the scalar context).
    fn atom_variable(&self, name: &str) -> Option<Result<Formula, String>>;
}

/// Evaluates an equal-style formula.
pub fn eval_equal(expr: &str, ctx: &dyn ExprContext) -> Result<f64, String> {
    Formula::parse(expr)?.eval(ctx)
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

/// A parsed formula node. Token indices refer to [`Formula::tokens`] (for error messages).
#[derive(Debug, Clone)]
enum Node {
    Num(f64),
    /// A word (PI, v_name, c_/f_ reference, thermo keyword or atom value), resolved at
    /// evaluation.
    Word(usize),
    /// A per-atom value (only after [`Formula::bind_atoms`]).
    Atom(AtomValue),
    /// Another bound atom-style formula (only after [`Formula::bind_atoms`]).
    Sub(Box<Formula>),
    Neg(Box<Node>),
    Not(Box<Node>),
    /// A left-associative chain of one precedence level: first, then (operator token, operand).
    Chain(Box<Node>, Vec<(usize, Node)>),
    /// A function call: name token, arguments.
    Call(usize, Vec<Node>),
}

/// A parsed formula.
#[derive(Debug, Clone)]
pub struct Formula {
    src: String,
    tokens: Vec<Token>,
    root: Node,
}

const OPERATORS: [&str; 16] = [
    "&&", "||", "|^", "==", "!=", "<=", ">=", "<", ">", "+", "-", "*", "/", "%", "^", "!",
];

fn err_at(src: &str, t: &Token, what: &str) -> String {
    format!("{what} '{}' (column {}) in '{}'", t.text, t.col, src)
}

struct Parser<'a> {
    src: &'a str,
    tokens: &'a [Token],
    pos: usize,
    depth: usize,
}

fn truth(v: f64) -> bool {
    v != 0.0
}

fn flag(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

const LEVELS: [&[&str]; 7] = [
    &["||", "|^"],
    &["&&"],
    &["==", "!="],
    &["<", "<=", ">", ">="],
    &["+", "-"],
    &["*", "/", "%"],
    &["^"],
];

impl Parser<'_> {
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

    /// Parses precedence level `level` (0 = `||`, 6 = `^`, 7 = unary), left-associative.
    fn level(&mut self, level: usize) -> Result<Node, String> {
        if level == LEVELS.len() {
            return self.unary();
        }
        let ops = LEVELS[level];
        let first = self.level(level + 1)?;
        let mut rest = Vec::new();
        while self.peek_op().is_some_and(|op| ops.contains(&op)) {
            let op_tok = self.pos;
            self.pos += 1;
            rest.push((op_tok, self.level(level + 1)?));
        }
        Ok(if rest.is_empty() {
            first
        } else {
            Node::Chain(Box::new(first), rest)
        })
    }

    fn enter(&mut self) -> Result<(), String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let msg = format!("formula nested deeper than {MAX_DEPTH} levels");
            return Err(match self.tokens.get(self.pos) {
                Some(t) => err_at(self.src, t, &format!("{msg} at")),
                None => self.err_end(&msg),
            });
        }
        Ok(())
    }

    fn unary(&mut self) -> Result<Node, String> {
        self.enter()?;
        let v = match self.peek_op() {
            Some("-") => {
                self.pos += 1;
                self.unary().map(|v| Node::Neg(Box::new(v)))
            }
            Some("!") => {
                self.pos += 1;
                self.unary().map(|v| Node::Not(Box::new(v)))
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
            Some(t) => Err(err_at(self.src, t, &format!("expected {name}, found"))),
            None => Err(self.err_end(&format!("expected {name}"))),
        }
    }

    fn primary(&mut self) -> Result<Node, String> {
        let Some(t) = self.tokens.get(self.pos) else {
            return Err(self.err_end("expected a value"));
        };
        let at = self.pos;
        self.pos += 1;
        match &t.tok {
            Tok::Num(v) => Ok(Node::Num(*v)),
            Tok::LParen => {
                let v = self.level(0)?;
                self.expect(Tok::RParen, "')'")?;
                Ok(v)
            }
            Tok::Word(_) => {
                if matches!(
                    self.tokens.get(self.pos),
                    Some(Token {
                        tok: Tok::LParen,
                        ..
                    })
                ) {
                    self.pos += 1;
                    self.enter()?;
                    let r = self.call(at);
                    self.depth -= 1;
                    r
                } else {
                    Ok(Node::Word(at))
                }
            }
            _ => Err(err_at(self.src, t, "expected a value, found")),
        }
    }

    fn call(&mut self, name: usize) -> Result<Node, String> {
        let mut args = vec![self.level(0)?];
        while matches!(
            self.tokens.get(self.pos),
            Some(Token {
                tok: Tok::Comma,
                ..
            })
        ) {
            self.pos += 1;
            args.push(self.level(0)?);
        }
        self.expect(Tok::RParen, "')'")?;
        Ok(Node::Call(name, args))
    }
}

/// Where the leaves of a formula get their values.
#[derive(Clone, Copy)]
enum Leaves<'a> {
    /// Equal-style: words through the context.
    Scalar(&'a dyn ExprContext),
    /// Bound atom-style: per-atom values.
    Atom(&'a dyn Fn(AtomValue) -> f64),
}

impl Formula {
    /// Parses `src`; errors name the token and its column.
    pub fn parse(src: &str) -> Result<Formula, String> {
        let tokens = tokenize(src)?;
        let mut p = Parser {
            src,
            tokens: &tokens,
            pos: 0,
            depth: 0,
        };
        let root = p.level(0)?;
        if let Some(t) = tokens.get(p.pos) {
            return Err(err_at(src, t, "unexpected"));
        }
        Ok(Formula {
            src: src.to_string(),
            tokens,
            root,
        })
    }

    /// The formula's text.
    pub fn source(&self) -> &str {
        &self.src
    }

    /// The value, if the formula is a constant (e.g. after binding).
    pub fn constant(&self) -> Option<f64> {
        match self.root {
            Node::Num(v) => Some(v),
            _ => None,
        }
    }

    /// Evaluates an equal-style formula.
    pub fn eval(&self, ctx: &dyn ExprContext) -> Result<f64, String> {
        self.ev(&self.root, Leaves::Scalar(ctx))
    }

    /// Binds an atom-style formula: evaluates every part that does not depend on the atom
    /// (through `ctx`), keeps per-atom values and other atom-style variables (`binder`).
    pub fn bind_atoms(
        &self,
        ctx: &dyn ExprContext,
        binder: &dyn AtomBinder,
    ) -> Result<Formula, String> {
        Ok(Formula {
            src: self.src.clone(),
            tokens: self.tokens.clone(),
            root: self.bind(&self.root, ctx, binder)?,
        })
    }

    /// Evaluates a bound atom-style formula for one atom whose values `atom` returns.
    pub fn eval_atom(&self, atom: &dyn Fn(AtomValue) -> f64) -> Result<f64, String> {
        self.ev(&self.root, Leaves::Atom(atom))
    }

    fn err_at(&self, t: usize, what: &str) -> String {
        err_at(&self.src, &self.tokens[t], what)
    }

    fn word_text(&self, t: usize) -> &str {
        &self.tokens[t].text
    }

    fn bind(
        &self,
        node: &Node,
        ctx: &dyn ExprContext,
        binder: &dyn AtomBinder,
    ) -> Result<Node, String> {
        let num = |n: &Node| match n {
            Node::Num(v) => Some(*v),
            _ => None,
        };
        Ok(match node {
            Node::Num(v) => Node::Num(*v),
            Node::Atom(a) => Node::Atom(*a),
            Node::Sub(f) => Node::Sub(f.clone()),
            Node::Word(t) => {
                let w = self.word_text(*t);
                if let Some(a) = AtomValue::from_word(w) {
                    return Ok(Node::Atom(a));
                }
                if let Some(name) = w.strip_prefix("v_")
                    && let Some(f) = binder.atom_variable(name)
                {
                    let f = f.map_err(|e| format!("{} ({e})", self.err_at(*t, "variable")))?;
                    return Ok(match f.constant() {
                        Some(v) => Node::Num(v),
                        None => Node::Sub(Box::new(f)),
                    });
                }
                Node::Num(self.word(*t, ctx)?)
            }
            Node::Neg(a) => {
                let a = self.bind(a, ctx, binder)?;
                match num(&a) {
                    Some(v) => Node::Num(-v),
                    None => Node::Neg(Box::new(a)),
                }
            }
            Node::Not(a) => {
                let a = self.bind(a, ctx, binder)?;
                match num(&a) {
                    Some(v) => Node::Num(flag(!truth(v))),
                    None => Node::Not(Box::new(a)),
                }
            }
            Node::Chain(first, rest) => {
                let first = self.bind(first, ctx, binder)?;
                let mut bound = Vec::with_capacity(rest.len());
                for (op, n) in rest {
                    bound.push((*op, self.bind(n, ctx, binder)?));
                }
                if let Some(mut v) = num(&first)
                    && bound.iter().all(|(_, n)| num(n).is_some())
                {
                    for (op, n) in &bound {
                        v = self.binary(*op, v, num(n).unwrap_or(0.0))?;
                    }
                    Node::Num(v)
                } else {
                    Node::Chain(Box::new(first), bound)
                }
            }
            Node::Call(name, args) => {
                let mut bound = Vec::with_capacity(args.len());
                for a in args {
                    bound.push(self.bind(a, ctx, binder)?);
                }
                let vals: Vec<f64> = bound.iter().filter_map(num).collect();
                if vals.len() == bound.len() {
                    Node::Num(self.function(*name, &vals)?)
                } else {
                    Node::Call(*name, bound)
                }
            }
        })
    }

    fn ev(&self, node: &Node, leaves: Leaves) -> Result<f64, String> {
        match node {
            Node::Num(v) => Ok(*v),
            Node::Word(t) => match leaves {
                Leaves::Scalar(ctx) => self.word(*t, ctx),
                Leaves::Atom(_) => Err(self.err_at(*t, "unbound word")),
            },
            Node::Atom(a) => match leaves {
                Leaves::Atom(f) => Ok(f(*a)),
                Leaves::Scalar(_) => Err(format!(
                    "per-atom value {a:?} in an equal-style formula '{}'",
                    self.src
                )),
            },
            Node::Sub(f) => f.ev(&f.root, leaves),
            Node::Neg(a) => Ok(-self.ev(a, leaves)?),
            Node::Not(a) => Ok(flag(!truth(self.ev(a, leaves)?))),
            Node::Chain(first, rest) => {
                let mut v = self.ev(first, leaves)?;
                for (op, n) in rest {
                    let rhs = self.ev(n, leaves)?;
                    v = self.binary(*op, v, rhs)?;
                }
                Ok(v)
            }
            Node::Call(name, args) => {
                let mut vals = Vec::with_capacity(args.len());
                for a in args {
                    vals.push(self.ev(a, leaves)?);
                }
                self.function(*name, &vals)
            }
        }
    }

    fn binary(&self, op_tok: usize, a: f64, b: f64) -> Result<f64, String> {
        let op = match self.tokens[op_tok].tok {
            Tok::Op(op) => op,
            _ => return Err(self.err_at(op_tok, "expected an operator, found")),
        };
        Ok(match op {
            "||" => flag(truth(a) || truth(b)),
            "|^" => flag(truth(a) != truth(b)),
            "&&" => flag(truth(a) && truth(b)),
            "==" => flag(a == b),
            "!=" => flag(a != b),
            "<" => flag(a < b),
            "<=" => flag(a <= b),
            ">" => flag(a > b),
            ">=" => flag(a >= b),
            "+" => a + b,
            "-" => a - b,
            "*" => a * b,
            "/" | "%" if b == 0.0 => {
                return Err(self.err_at(
                    op_tok,
                    if op == "/" {
                        "division by zero at"
                    } else {
                        "modulo by zero at"
                    },
                ));
            }
            "/" => a / b,
            "%" => a % b,
            _ => a.powf(b),
        })
    }

    fn word(&self, t: usize, ctx: &dyn ExprContext) -> Result<f64, String> {
        let w = self.word_text(t);
        if w == "PI" {
            return Ok(std::f64::consts::PI);
        }
        if let Some(name) = w.strip_prefix("v_") {
            return ctx
                .variable(name)
                .map_err(|e| format!("{} ({e})", self.err_at(t, "variable")));
        }
        if let Some((name, idx)) = w.split_once('[')
            && let Some(value) = AtomValue::from_word(name)
        {
            let id: u64 = idx.trim_end_matches(']').parse().unwrap_or(0);
            if id == 0 {
                return Err(self.err_at(t, "atom ID must be >= 1 in"));
            }
            return match ctx.atom(value, id) {
                None => Err(self.err_at(t, "atom references are not supported here:")),
                Some(r) => r.map_err(|e| format!("{} ({e})", self.err_at(t, "atom reference"))),
            };
        }
        let kind = if w.starts_with("c_") {
            Some(RefKind::Compute)
        } else if w.starts_with("f_") {
            Some(RefKind::Fix)
        } else {
            None
        };
        if let Some(kind) = kind {
            let body = &w[2..];
            let (id, index) = match body.split_once('[') {
                Some((id, idx)) => {
                    let n: usize = idx.trim_end_matches(']').parse().unwrap_or(0);
                    if n == 0 {
                        return Err(self.err_at(t, "index must be >= 1 in"));
                    }
                    (id, Some(n))
                }
                None => (body, None),
            };
            return match ctx.reference(kind, id, index) {
                None => Err(self.err_at(t, "compute and fix references are not supported:")),
                Some(r) => r.map_err(|e| format!("{} ({e})", self.err_at(t, "reference"))),
            };
        }
        match ctx.thermo(w) {
            Some(r) => r.map_err(|e| format!("{} ({e})", self.err_at(t, "thermo keyword"))),
            None if AtomValue::from_word(w).is_some() => {
                Err(self.err_at(t, "per-atom value (only atom-style variables can use it):"))
            }
            None => Err(self.err_at(t, "unknown word")),
        }
    }

    fn function(&self, t: usize, args: &[f64]) -> Result<f64, String> {
        let name = self.word_text(t);
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
