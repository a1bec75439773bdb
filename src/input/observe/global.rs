//! Global values of computes, fixes and variables (`c_ID`, `c_ID[i]`, `f_ID[i]`, `v_name`): their
//! values for formulas, thermo output and the fixes, the checks a fix makes when it is defined,
//! and the expansion of `[*]` wildcards.

use super::{Env, Observe, Source, ValueRef, VarStyle};
use crate::input::expr::RefKind;

impl Observe {
    // ------------------------------------------------------------------ global values

    /// The value of `c_ID`, `c_ID[i]`, `f_ID`, `f_ID[i]` (for formulas and thermo output).
    pub fn reference(
        &self,
        kind: RefKind,
        id: &str,
        index: Option<usize>,
        env: &dyn Env,
    ) -> Result<f64, String> {
        let sys = env.system().ok_or("needs a simulation box")?;
        match kind {
            RefKind::Compute => {
                let c = self
                    .compute(id)
                    .ok_or_else(|| format!("compute '{id}' does not exist"))?;
                match index {
                    None => self.compute_scalar(c, env, sys),
                    Some(i) => {
                        let n = c.kind.vector_len().ok_or_else(|| {
                            format!(
                                "compute {} '{id}' does not calculate a global vector",
                                c.kind.style()
                            )
                        })?;
                        if i > n {
                            return Err(format!(
                                "compute '{id}' vector has {n} elements, [{i}] is out of range"
                            ));
                        }
                        Ok(self.compute_vector(c, env, sys)?[i - 1])
                    }
                }
            }
            RefKind::Fix => {
                if let Some(p) = sys.pex.iter().find(|p| p.id == id) {
                    return match index {
                        None => Ok(p.total),
                        Some(_) => Err(format!(
                            "fix pex/push '{id}' has a global scalar only (f_{id})"
                        )),
                    };
                }
                let f = self
                    .fix(id)
                    .ok_or_else(|| format!("fix '{id}' does not exist or has no global values"))?;
                match index {
                    None => f.scalar().ok_or_else(|| {
                        format!(
                            "fix {} '{id}' does not calculate a global scalar",
                            f.style()
                        )
                    }),
                    Some(i) => {
                        let n = f.vector_len().ok_or_else(|| {
                            format!(
                                "fix {} '{id}' does not calculate a global vector",
                                f.style()
                            )
                        })?;
                        if i > n {
                            return Err(format!(
                                "fix '{id}' vector has {n} elements, [{i}] is out of range"
                            ));
                        }
                        Ok(f.vector(i - 1))
                    }
                }
            }
        }
    }

    /// True if `c_ID…`/`f_ID…` is extensive (thermo output divides it by the atom count with
    /// `thermo_modify norm yes`, as LAMMPS).
    pub fn extensive(&self, kind: RefKind, id: &str, index: Option<usize>) -> bool {
        match kind {
            RefKind::Compute => self.compute(id).is_some_and(|c| c.kind.extensive(index)),
            RefKind::Fix => self.fix(id).is_some_and(|f| f.extensive(self, index)),
        }
    }

    pub(super) fn value_extensive(&self, v: &ValueRef) -> bool {
        match &v.source {
            Source::Compute(id) => self.extensive(RefKind::Compute, id, v.index),
            Source::Fix(id) => self.extensive(RefKind::Fix, id, v.index),
            Source::Var(_) => false,
        }
    }

    pub(super) fn global(&self, v: &ValueRef, env: &dyn Env) -> Result<f64, String> {
        match &v.source {
            Source::Compute(id) => self.reference(RefKind::Compute, id, v.index, env),
            Source::Fix(id) => self.reference(RefKind::Fix, id, v.index, env),
            Source::Var(name) => env.equal_variable(name),
        }
    }

    pub(super) fn global_vector(&self, v: &ValueRef, env: &dyn Env) -> Result<Vec<f64>, String> {
        let sys = env.system().ok_or("needs a simulation box")?;
        match &v.source {
            Source::Compute(id) => {
                let c = self
                    .compute(id)
                    .ok_or_else(|| format!("compute '{id}' does not exist"))?;
                self.compute_vector(c, env, sys)
            }
            Source::Fix(id) => {
                let f = self
                    .fix(id)
                    .ok_or_else(|| format!("fix '{id}' does not exist"))?;
                let n = f.vector_len().ok_or_else(|| {
                    format!(
                        "fix {} '{id}' does not calculate a global vector",
                        f.style()
                    )
                })?;
                Ok((0..n).map(|i| f.vector(i)).collect())
            }
            Source::Var(name) => Err(format!(
                "v_{name}: vector-style variables are not supported"
            )),
        }
    }

    /// Check a global value for `style` in scalar or vector mode; returns the vector length in
    /// vector mode.
    pub(super) fn check_global(
        &self,
        v: &ValueRef,
        vector: bool,
        nevery: i64,
        style: &str,
        env: &dyn Env,
    ) -> Result<Option<usize>, String> {
        let t = &v.text;
        match &v.source {
            Source::Compute(id) => {
                let c = self
                    .compute(id)
                    .ok_or_else(|| format!("{t}: compute ID '{id}' does not exist"))?;
                let name = c.kind.style();
                match (vector, v.index) {
                    (false, None) if !c.kind.has_scalar() => Err(format!(
                        "{t}: compute {name} does not calculate a global scalar"
                    )),
                    (false, Some(i)) => match c.kind.vector_len() {
                        None => Err(format!(
                            "{t}: compute {name} does not calculate a global vector"
                        )),
                        Some(n) if i > n => Err(format!(
                            "{t}: compute vector is accessed out of range ({n})"
                        )),
                        _ => Ok(None),
                    },
                    (true, None) => match c.kind.vector_len() {
                        None => Err(format!(
                            "{t}: compute {name} does not calculate a global vector"
                        )),
                        n => Ok(n),
                    },
                    (true, Some(_)) => Err(format!(
                        "{t}: compute {name} does not calculate a global array"
                    )),
                    _ => Ok(None),
                }
            }
            Source::Fix(id) => {
                let sys = env.system().ok_or("needs a simulation box")?;
                let (has_scalar, vlen, freq, name) = if sys.pex.iter().any(|p| &p.id == id) {
                    (true, None, 1, "pex/push")
                } else if let Some(f) = self.fix(id) {
                    (
                        f.scalar().is_some(),
                        f.vector_len(),
                        f.global_freq(),
                        f.style(),
                    )
                } else {
                    return Err(format!(
                        "{t}: fix ID '{id}' does not exist or has no global values"
                    ));
                };
                if nevery % freq != 0 {
                    return Err(format!(
                        "{t}: fix {name} is not computed at compatible times (its values change \
                         every {freq} steps; Nevery = {nevery})"
                    ));
                }
                match (vector, v.index) {
                    (false, None) if !has_scalar => Err(format!(
                        "{t}: fix {name} does not calculate a global scalar"
                    )),
                    (false, Some(i)) => match vlen {
                        None => Err(format!(
                            "{t}: fix {name} does not calculate a global vector"
                        )),
                        Some(n) if i > n => {
                            Err(format!("{t}: fix vector is accessed out of range ({n})"))
                        }
                        _ => Ok(None),
                    },
                    (true, None) => match vlen {
                        None => Err(format!(
                            "{t}: fix {name} does not calculate a global vector"
                        )),
                        n => Ok(n),
                    },
                    (true, Some(_)) => {
                        Err(format!("{t}: fix {name} global arrays are not supported"))
                    }
                    _ => Ok(None),
                }
            }
            Source::Var(name) => {
                if vector {
                    return Err(format!(
                        "{t}: fix {style} cannot use a variable in vector mode"
                    ));
                }
                if v.index.is_some() {
                    return Err(format!("{t}: vector-style variables are not supported"));
                }
                match env.var_style(name) {
                    VarStyle::Equal => Ok(None),
                    VarStyle::Undefined => Err(format!(
                        "{t}: variable '{name}' for fix {style} does not exist"
                    )),
                    _ => Err(format!(
                        "{t}: fix {style} variable '{name}' is not an equal-style variable"
                    )),
                }
            }
        }
    }

    /// Expand `c_ID[*]`, `c_ID[n*]`, `c_ID[*m]`, `c_ID[n*m]` (and `f_`) in scalar mode into
    /// single elements, as LAMMPS's `expand_args`.
    pub(super) fn expand(&self, word: &str, vector: bool) -> Result<Vec<String>, String> {
        let Some((head, rest)) = word.split_once('[') else {
            return Ok(vec![word.to_string()]);
        };
        let Some(range) = rest.strip_suffix(']') else {
            return Ok(vec![word.to_string()]);
        };
        let Some((a, b)) = range.split_once('*') else {
            return Ok(vec![word.to_string()]);
        };
        if vector {
            return Err(format!(
                "'{word}': wildcards in vector mode would select array columns (not supported)"
            ));
        }
        let len = match (&word[..2], &head[2..]) {
            ("c_", id) => self.compute(id).and_then(|c| c.kind.vector_len()),
            ("f_", id) => self.fix(id).and_then(|f| f.vector_len()),
            _ => None,
        }
        .ok_or_else(|| format!("'{word}': wildcard on something without a global vector"))?;
        let lo = if a.is_empty() {
            1
        } else {
            a.parse()
                .map_err(|_| format!("'{word}': bad wildcard range"))?
        };
        let hi = if b.is_empty() {
            len
        } else {
            b.parse()
                .map_err(|_| format!("'{word}': bad wildcard range"))?
        };
        if lo < 1 || hi > len || lo > hi {
            return Err(format!("'{word}': wildcard range out of 1..{len}"));
        }
        Ok((lo..=hi).map(|i| format!("{head}[{i}]")).collect())
    }
}
