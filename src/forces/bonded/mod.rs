//! Bond and angle styles (`bond_style harmonic|fene`, `angle_style harmonic|cosine`), one file
//! each behind [`BondForm`] and [`AngleForm`], named only in [`BOND_STYLES`] and
//! [`ANGLE_STYLES`]: their coefficients and the force of one bond or angle, with LAMMPS's
//! formulas and conventions (docs/models.md §4.9, P-23–P-26), so that the standalone engine and
//! LAMMPS agree to round-off. The driver (`System`, `topology.rs`) walks the topology in its
//! fixed order.

use crate::grammar::{need, parse_f64, shown, type_range};

mod angle_cosine;
mod angle_harmonic;
#[cfg(feature = "test-style")]
mod angle_test_square;
mod bond_fene;
mod bond_harmonic;
#[cfg(feature = "test-style")]
mod bond_test_quartic;

/// What every bonded form has: its words (the grammar of its `*_coeff` lines).
pub trait Form: Sync + std::fmt::Debug {
    /// The style word (`bond_style WORD`, `angle_style WORD`).
    fn word(&self) -> &'static str;
    /// The usage line of its coefficient command.
    fn usage(&self) -> &'static str;
    /// The names of its coefficients, in order (their count is the line's).
    fn names(&self) -> &'static [&'static str];
    /// A check of one type's coefficients beyond their being numbers.
    fn check(&self, _c: &[f64]) -> Result<(), String> {
        Ok(())
    }
}

/// A bond style's functional form. A new bond style is one file implementing this trait (and
/// [`Form`]) and one entry in [`BOND_STYLES`].
pub trait BondForm: Form {
    /// (fbond, energy, flag) of a bond with coefficients `c` at squared length `rsq`, the force
    /// on the first atom being fbond · (x1 − x2) (LAMMPS's `bond->compute`).
    fn eval(&self, c: &[f64], rsq: f64) -> (f64, f64, BondFlag);
    /// LAMMPS's set-up warning of this form under `special_bonds lj` factors `lj`, if any.
    fn special_warning(&self, _lj: [f64; 4]) -> Option<&'static str> {
        None
    }
}

/// An angle style's functional form. A new angle style is one file implementing this trait (and
/// [`Form`]) and one entry in [`ANGLE_STYLES`].
pub trait AngleForm: Form {
    /// (a, energy) of an angle with coefficients `c` and cos θ = `cs` (clamped to [−1, 1]): the
    /// forces are a (cs d1/r1² − d2/(r1 r2)) on the first atom and likewise on the third
    /// (LAMMPS's `angle->compute`, [`AngleStyle::eval`]).
    fn eval(&self, c: &[f64], cs: f64) -> (f64, f64);
}

/// The bond styles, the one place that names them.
pub const BOND_STYLES: &[&dyn BondForm] = &[
    &bond_harmonic::Harmonic,
    &bond_fene::Fene,
    #[cfg(feature = "test-style")]
    &bond_test_quartic::Quartic,
];
/// The angle styles, the one place that names them.
pub const ANGLE_STYLES: &[&dyn AngleForm] = &[
    &angle_harmonic::Harmonic,
    &angle_cosine::Cosine,
    #[cfg(feature = "test-style")]
    &angle_test_square::Square,
];

/// "a, b and c" of the registry's words, for "not supported" errors.
fn words(w: Vec<&str>) -> String {
    match w.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => String::new(),
    }
}

/// What one bond evaluation found beside its force (LAMMPS's FENE checks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BondFlag {
    /// Nothing to report.
    Ok,
    /// FENE with 1 − (r/R0)² < 0.1: LAMMPS warns "FENE bond too long" and uses 0.1.
    TooLong,
    /// FENE with 1 − (r/R0)² ≤ −3: LAMMPS stops with "Bad FENE bond".
    Bad,
}

/// A coefficient line's type range and numbers: `TYPE(S) c1 c2 …`, exactly `n` numbers.
fn coeff_line(
    args: &[String],
    ntypes: usize,
    names: &[&str],
    usage: &str,
    what: &str,
) -> Result<((usize, usize), Vec<f64>), String> {
    let n = names.len();
    need(args, n + 1, usage)?;
    if args.len() > n + 1 {
        return Err(format!(
            "unexpected word '{}'; usage: {usage}",
            shown(&args[n + 1])
        ));
    }
    if ntypes == 0 {
        return Err(format!("{what}_coeff: the system has no {what} types"));
    }
    let range = type_range(&args[0], ntypes).map_err(|e| format!("{what} {e}"))?;
    let mut c = Vec::with_capacity(n);
    for (k, tok) in args[1..=n].iter().enumerate() {
        c.push(parse_f64(tok, names[k])?);
    }
    Ok((range, c))
}

/// A bonded style (`what` = "bond" or "angle") with its coefficients by type (index 0 unused):
/// [`BondStyle`] and [`AngleStyle`].
#[derive(Debug)]
pub struct Styled<F: ?Sized + 'static> {
    /// The form.
    pub form: &'static F,
    /// Coefficients by type, as given (`None`: not set).
    pub coeff: Vec<Option<Vec<f64>>>,
    what: &'static str,
}

/// A bond style with its coefficients by bond type.
pub type BondStyle = Styled<dyn BondForm>;
/// An angle style with its coefficients by angle type (θ0 in degrees, as given).
pub type AngleStyle = Styled<dyn AngleForm>;

impl<F: ?Sized> Clone for Styled<F> {
    fn clone(&self) -> Self {
        Styled {
            form: self.form,
            coeff: self.coeff.clone(),
            what: self.what,
        }
    }
}

impl<F: ?Sized + Form> PartialEq for Styled<F> {
    fn eq(&self, other: &Self) -> bool {
        self.form.word() == other.form.word() && self.coeff == other.coeff
    }
}

impl<F: ?Sized + Form> Styled<F> {
    /// `WHAT_style WORD` of the forms `all` for `ntypes` types.
    fn pick(
        all: &[&'static F],
        what: &'static str,
        args: &[String],
        ntypes: usize,
    ) -> Result<Self, String> {
        let names: Vec<&str> = all.iter().map(|f| f.word()).collect();
        need(args, 1, &format!("{what}_style {}", names.join("|")))?;
        let Some(&form) = all.iter().find(|f| f.word() == args[0]) else {
            return Err(format!(
                "{what} style '{}' not supported: only {}",
                shown(&args[0]),
                words(names)
            ));
        };
        if let Some(w) = args.get(1) {
            return Err(format!(
                "{what}_style {}: unexpected word '{}'",
                form.word(),
                shown(w)
            ));
        }
        Ok(Styled {
            form,
            coeff: vec![None; ntypes + 1],
            what,
        })
    }

    /// One coefficient line (its words after the command).
    pub fn set_coeff(&mut self, args: &[String]) -> Result<(), String> {
        let nt = self.coeff.len() - 1;
        let f = self.form;
        let ((lo, hi), c) = coeff_line(args, nt, f.names(), f.usage(), self.what)?;
        f.check(&c)?;
        for t in lo..=hi {
            self.coeff[t] = Some(c.clone());
        }
        Ok(())
    }

    /// The first type without coefficients.
    pub fn missing(&self) -> Option<usize> {
        (1..self.coeff.len()).find(|&t| self.coeff[t].is_none())
    }

    /// The `WHAT_style` and `WHAT_coeff` lines that rebuild this style (restart files).
    pub fn lines(&self) -> Vec<Vec<String>> {
        let mut out = vec![vec![
            format!("{}_style", self.what),
            self.form.word().to_string(),
        ]];
        for (t, c) in self.coeff.iter().enumerate() {
            if let Some(c) = c {
                let mut l = vec![format!("{}_coeff", self.what), t.to_string()];
                l.extend(c.iter().map(|&x| crate::forces::style::word(x)));
                out.push(l);
            }
        }
        out
    }
}

impl BondStyle {
    /// `bond_style WORD` ([`BOND_STYLES`]) for `ntypes` bond types.
    pub fn new(args: &[String], ntypes: usize) -> Result<BondStyle, String> {
        Self::pick(BOND_STYLES, "bond", args, ntypes)
    }

    /// The force of a bond of type `t` at squared length `rsq`: (fbond, energy, flag), the force
    /// on the first atom being fbond · (x1 − x2) (LAMMPS's `bond->compute`). Coefficients must
    /// be set ([`BondStyle::missing`] is checked at set-up).
    #[inline]
    pub fn eval(&self, t: usize, rsq: f64) -> (f64, f64, BondFlag) {
        let Some(c) = self.coeff.get(t).and_then(|c| c.as_deref()) else {
            return (0.0, 0.0, BondFlag::Ok);
        };
        self.form.eval(c, rsq)
    }
}

impl AngleStyle {
    /// `angle_style WORD` ([`ANGLE_STYLES`]) for `ntypes` angle types.
    pub fn new(args: &[String], ntypes: usize) -> Result<AngleStyle, String> {
        Self::pick(ANGLE_STYLES, "angle", args, ntypes)
    }

    /// The forces of an angle of type `t` with arms d1 = x1 − x2 and d2 = x3 − x2: (f1, f3,
    /// energy); the middle atom gets −(f1 + f3) (LAMMPS's `angle->compute`).
    #[inline]
    pub fn eval(&self, t: usize, d1: [f64; 3], d2: [f64; 3]) -> ([f64; 3], [f64; 3], f64) {
        let Some(c) = self.coeff.get(t).and_then(|c| c.as_deref()) else {
            return ([0.0; 3], [0.0; 3], 0.0);
        };
        let rsq1 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
        let rsq2 = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
        let r1 = rsq1.sqrt();
        let r2 = rsq2.sqrt();
        let mut cs = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
        cs /= r1 * r2;
        cs = cs.clamp(-1.0, 1.0);
        let (a, e) = self.form.eval(c, cs);
        let a11 = a * cs / rsq1;
        let a12 = -a / (r1 * r2);
        let a22 = a * cs / rsq2;
        let f1 = [
            a11 * d1[0] + a12 * d2[0],
            a11 * d1[1] + a12 * d2[1],
            a11 * d1[2] + a12 * d2[2],
        ];
        let f3 = [
            a22 * d2[0] + a12 * d1[0],
            a22 * d2[1] + a12 * d1[1],
            a22 * d2[2] + a12 * d1[2],
        ];
        (f1, f3, e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn fene_flags_follow_lammps_thresholds() {
        let mut b = BondStyle::new(&w("fene"), 1).unwrap();
        b.set_coeff(&w("1 30 1.5 1 1")).unwrap();
        // 1 − r²/R0² < 0.1 from r > sqrt(0.9)·1.5; ≤ −3 from r ≥ 3.
        assert_eq!(b.eval(1, 1.0).2, BondFlag::Ok);
        assert_eq!(b.eval(1, 0.95 * 2.25).2, BondFlag::TooLong);
        assert_eq!(b.eval(1, 9.0).2, BondFlag::Bad);
        // Clamped: the force at the threshold and beyond is −K/0.1 (no WCA there).
        assert_eq!(b.eval(1, 0.95 * 2.25).0, -30.0 / 0.1);
    }

    #[test]
    fn coefficient_errors_name_the_word() {
        let mut b = BondStyle::new(&w("harmonic"), 2).unwrap();
        assert!(b.set_coeff(&w("3 1 1")).unwrap_err().contains("'3'"));
        assert!(b.set_coeff(&w("1 1 x")).unwrap_err().contains("'x'"));
        assert!(
            b.set_coeff(&w("1 1 1 1"))
                .unwrap_err()
                .contains("unexpected word")
        );
        assert_eq!(b.missing(), Some(1));
        b.set_coeff(&w("* 100 1")).unwrap();
        assert_eq!(b.missing(), None);
        assert!(BondStyle::new(&w("morse"), 1).is_err());
        assert!(AngleStyle::new(&w("charmm"), 1).is_err());
    }
}
