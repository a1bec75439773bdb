//! Bond and angle styles (`bond_style harmonic|fene`, `angle_style harmonic|cosine`): their
//! coefficients and the force of one bond or angle, with LAMMPS's formulas and conventions
//! (docs/models.md §4.9, P-23–P-26), so that the standalone engine and LAMMPS agree to
//! round-off. The driver (`System`, `topology.rs`) walks the topology in its fixed order.

use crate::grammar::{need, parse_f64, shown, type_range};

/// LAMMPS's 2^(1/3) (`MY_CUBEROOT2`): the WCA cut-off of `bond fene`, squared over σ².
const CUBEROOT2: f64 = 1.259_921_049_894_873_2;
/// LAMMPS's floor on sin θ in the angle forces (`SMALL` of `angle harmonic`).
const SMALL_SIN: f64 = 0.001;

/// A bond style's functional form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BondKind {
    /// E = K (r − r0)² (no ½, as LAMMPS); coefficients K r0.
    Harmonic,
    /// E = −½ K R0² ln(1 − (r/R0)²) + 4ε[(σ/r)¹² − (σ/r)⁶] + ε for r < 2^(1/6) σ; coefficients
    /// K R0 ε σ.
    Fene,
}

impl BondKind {
    /// The style word.
    pub fn word(self) -> &'static str {
        match self {
            BondKind::Harmonic => "harmonic",
            BondKind::Fene => "fene",
        }
    }

    fn ncoeff(self) -> usize {
        match self {
            BondKind::Harmonic => 2,
            BondKind::Fene => 4,
        }
    }

    fn usage(self) -> &'static str {
        match self {
            BondKind::Harmonic => "bond_coeff N K r0",
            BondKind::Fene => "bond_coeff N K R0 epsilon sigma",
        }
    }
}

/// An angle style's functional form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleKind {
    /// E = K (θ − θ0)²; coefficients K θ0 (θ0 in degrees).
    Harmonic,
    /// E = K (1 + cos θ); coefficient K.
    Cosine,
}

impl AngleKind {
    /// The style word.
    pub fn word(self) -> &'static str {
        match self {
            AngleKind::Harmonic => "harmonic",
            AngleKind::Cosine => "cosine",
        }
    }

    fn ncoeff(self) -> usize {
        match self {
            AngleKind::Harmonic => 2,
            AngleKind::Cosine => 1,
        }
    }

    fn usage(self) -> &'static str {
        match self {
            AngleKind::Harmonic => "angle_coeff N K theta0",
            AngleKind::Cosine => "angle_coeff N K",
        }
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

/// A bond style with its coefficients by bond type (index 0 unused).
#[derive(Clone, Debug, PartialEq)]
pub struct BondStyle {
    /// The form.
    pub kind: BondKind,
    /// Coefficients by type, as given (`None`: not set).
    pub coeff: Vec<Option<Vec<f64>>>,
}

/// A coefficient line's type range and numbers: `TYPE(S) c1 c2 …`, exactly `n` numbers.
fn coeff_line(
    args: &[String],
    ntypes: usize,
    n: usize,
    usage: &str,
    what: &str,
) -> Result<((usize, usize), Vec<f64>), String> {
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
    let names: &[&str] = match (what, n) {
        ("bond", 2) => &["K", "r0"],
        ("bond", _) => &["K", "R0", "epsilon", "sigma"],
        (_, 2) => &["K", "theta0"],
        _ => &["K"],
    };
    let mut c = Vec::with_capacity(n);
    for (k, tok) in args[1..=n].iter().enumerate() {
        c.push(parse_f64(tok, names[k])?);
    }
    Ok((range, c))
}

impl BondStyle {
    /// `bond_style harmonic|fene` for `ntypes` bond types.
    pub fn new(args: &[String], ntypes: usize) -> Result<BondStyle, String> {
        need(args, 1, "bond_style harmonic|fene")?;
        let kind = match args[0].as_str() {
            "harmonic" => BondKind::Harmonic,
            "fene" => BondKind::Fene,
            other => {
                return Err(format!(
                    "bond style '{}' not supported: only harmonic and fene",
                    shown(other)
                ));
            }
        };
        if let Some(w) = args.get(1) {
            return Err(format!(
                "bond_style {}: unexpected word '{}'",
                kind.word(),
                shown(w)
            ));
        }
        Ok(BondStyle {
            kind,
            coeff: vec![None; ntypes + 1],
        })
    }

    /// One `bond_coeff` line (its words after the command).
    pub fn set_coeff(&mut self, args: &[String]) -> Result<(), String> {
        let nt = self.coeff.len() - 1;
        let k = self.kind;
        let ((lo, hi), c) = coeff_line(args, nt, k.ncoeff(), k.usage(), "bond")?;
        if k == BondKind::Fene && c[1] <= 0.0 {
            return Err(format!("bond fene: R0 = {} must be > 0", c[1]));
        }
        for t in lo..=hi {
            self.coeff[t] = Some(c.clone());
        }
        Ok(())
    }

    /// The first bond type without coefficients.
    pub fn missing(&self) -> Option<usize> {
        (1..self.coeff.len()).find(|&t| self.coeff[t].is_none())
    }

    /// The force of a bond of type `t` at squared length `rsq`: (fbond, energy, flag), the force
    /// on the first atom being fbond · (x1 − x2) (LAMMPS's `bond->compute`). Coefficients must
    /// be set ([`BondStyle::missing`] is checked at set-up).
    #[inline]
    pub fn eval(&self, t: usize, rsq: f64) -> (f64, f64, BondFlag) {
        let Some(c) = self.coeff.get(t).and_then(|c| c.as_deref()) else {
            return (0.0, 0.0, BondFlag::Ok);
        };
        match self.kind {
            BondKind::Harmonic => {
                let r = rsq.sqrt();
                let dr = r - c[1];
                let rk = c[0] * dr;
                let fbond = if r > 0.0 { -2.0 * rk / r } else { 0.0 };
                (fbond, rk * dr, BondFlag::Ok)
            }
            BondKind::Fene => {
                let (k, r0, eps, sigma) = (c[0], c[1], c[2], c[3]);
                let r0sq = r0 * r0;
                let mut rlogarg = 1.0 - rsq / r0sq;
                let mut flag = BondFlag::Ok;
                if rlogarg < 0.1 {
                    flag = if rlogarg <= -3.0 {
                        BondFlag::Bad
                    } else {
                        BondFlag::TooLong
                    };
                    rlogarg = 0.1;
                }
                let mut fbond = -k / rlogarg;
                let mut e = -0.5 * k * r0sq * rlogarg.ln();
                if rsq < CUBEROOT2 * sigma * sigma {
                    let sr2 = sigma * sigma / rsq;
                    let sr6 = sr2 * sr2 * sr2;
                    fbond += 48.0 * eps * sr6 * (sr6 - 0.5) / rsq;
                    e += 4.0 * eps * sr6 * (sr6 - 1.0) + eps;
                }
                (fbond, e, flag)
            }
        }
    }

    /// The `bond_style` and `bond_coeff` lines that rebuild this style (restart files).
    pub fn lines(&self) -> Vec<Vec<String>> {
        let mut out = vec![vec!["bond_style".to_string(), self.kind.word().to_string()]];
        for (t, c) in self.coeff.iter().enumerate() {
            if let Some(c) = c {
                let mut l = vec!["bond_coeff".to_string(), t.to_string()];
                l.extend(c.iter().map(|&x| super::style::word(x)));
                out.push(l);
            }
        }
        out
    }
}

/// An angle style with its coefficients by angle type (index 0 unused).
#[derive(Clone, Debug, PartialEq)]
pub struct AngleStyle {
    /// The form.
    pub kind: AngleKind,
    /// Coefficients by type as given (θ0 in degrees; `None`: not set).
    pub coeff: Vec<Option<Vec<f64>>>,
    /// θ0 in radians by type (harmonic), as LAMMPS converts it: θ0/180 · π.
    theta0: Vec<f64>,
}

impl AngleStyle {
    /// `angle_style harmonic|cosine` for `ntypes` angle types.
    pub fn new(args: &[String], ntypes: usize) -> Result<AngleStyle, String> {
        need(args, 1, "angle_style harmonic|cosine")?;
        let kind = match args[0].as_str() {
            "harmonic" => AngleKind::Harmonic,
            "cosine" => AngleKind::Cosine,
            other => {
                return Err(format!(
                    "angle style '{}' not supported: only harmonic and cosine",
                    shown(other)
                ));
            }
        };
        if let Some(w) = args.get(1) {
            return Err(format!(
                "angle_style {}: unexpected word '{}'",
                kind.word(),
                shown(w)
            ));
        }
        Ok(AngleStyle {
            kind,
            coeff: vec![None; ntypes + 1],
            theta0: vec![0.0; ntypes + 1],
        })
    }

    /// One `angle_coeff` line (its words after the command).
    pub fn set_coeff(&mut self, args: &[String]) -> Result<(), String> {
        let nt = self.coeff.len() - 1;
        let k = self.kind;
        let ((lo, hi), c) = coeff_line(args, nt, k.ncoeff(), k.usage(), "angle")?;
        for t in lo..=hi {
            if k == AngleKind::Harmonic {
                self.theta0[t] = c[1] / 180.0 * std::f64::consts::PI;
            }
            self.coeff[t] = Some(c.clone());
        }
        Ok(())
    }

    /// The first angle type without coefficients.
    pub fn missing(&self) -> Option<usize> {
        (1..self.coeff.len()).find(|&t| self.coeff[t].is_none())
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
        let (a, e) = match self.kind {
            AngleKind::Harmonic => {
                let mut s = (1.0 - cs * cs).sqrt();
                if s < SMALL_SIN {
                    s = SMALL_SIN;
                }
                s = 1.0 / s;
                let dtheta = cs.acos() - self.theta0[t];
                let tk = c[0] * dtheta;
                (-2.0 * tk * s, tk * dtheta)
            }
            AngleKind::Cosine => (c[0], c[0] * (1.0 + cs)),
        };
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

    /// The `angle_style` and `angle_coeff` lines that rebuild this style (restart files).
    pub fn lines(&self) -> Vec<Vec<String>> {
        let mut out = vec![vec![
            "angle_style".to_string(),
            self.kind.word().to_string(),
        ]];
        for (t, c) in self.coeff.iter().enumerate() {
            if let Some(c) = c {
                let mut l = vec!["angle_coeff".to_string(), t.to_string()];
                l.extend(c.iter().map(|&x| super::style::word(x)));
                out.push(l);
            }
        }
        out
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
