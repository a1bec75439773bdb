//! `fix ave/time`: global values (computes, fixes, equal-style variables), in scalar or vector
//! mode, averaged over Nrepeat samples and written on the Nfreq steps.

use super::ave_args::{Epoch, FixArgs};
use super::average::Averager;
use super::{Env, Observe, Sample, ValueRef, parse_ref};
use crate::input::format::{FmtArg, sprintf};

#[derive(Debug)]
pub(super) struct AveTime {
    pub(super) values: Vec<ValueRef>,
    pub(super) vector: bool,
    pub(super) nrows: usize,
    sum: Vec<f64>,
    avg: Averager,
    format: String,
}

impl AveTime {
    pub(super) fn value(&self, row: usize, col: usize) -> f64 {
        let nv = self.values.len();
        if self.avg.norm == 0 {
            return 0.0;
        }
        self.avg
            .total
            .get(row * nv + col)
            .map_or(0.0, |t| t / self.avg.norm as f64)
    }
}

/// The part of `fix ave/time`'s parsing particular to it: the values, checked, and the file
/// header.
pub(super) fn parse(f: FixArgs<'_>, env: &dyn Env) -> Result<(AveTime, Vec<String>), String> {
    let FixArgs {
        id,
        style,
        raw_values,
        nevery,
        ave,
        vector,
        format,
        titles,
        ..
    } = f;
    let obs = env.observe();
    let mut values = Vec::new();
    for w in &raw_values {
        for e in obs.expand(w, vector)? {
            let (source, index) =
                parse_ref(&e)?.ok_or_else(|| format!("'{e}' is not c_ID, f_ID or v_name"))?;
            values.push(ValueRef {
                text: e,
                source,
                index,
            });
        }
    }
    let mut nrows = 1;
    for (n, v) in values.iter().enumerate() {
        let len = obs.check_global(v, vector, nevery, style, env)?;
        if vector {
            let len = len.unwrap_or(0);
            if n == 0 {
                nrows = len;
            } else if len != nrows {
                return Err(format!(
                    "fix ave/time columns have inconsistent lengths ({} has {len}, \
                     {} has {nrows})",
                    v.text, values[0].text
                ));
            }
        }
    }
    let names: Vec<&str> = values.iter().map(|v| v.text.as_str()).collect();
    let mut header = vec![
        titles[0]
            .clone()
            .unwrap_or_else(|| format!("# Time-averaged data for fix {id}")),
    ];
    if vector {
        header.push(
            titles[1]
                .clone()
                .unwrap_or_else(|| "# TimeStep Number-of-rows".into()),
        );
        header.push(
            titles[2]
                .clone()
                .unwrap_or_else(|| format!("# Row {}", names.join(" "))),
        );
    } else {
        header.push(
            titles[1]
                .clone()
                .unwrap_or_else(|| format!("# TimeStep {}", names.join(" "))),
        );
    }
    Ok((
        AveTime {
            values,
            vector,
            nrows,
            sum: Vec::new(),
            avg: Averager::new(ave),
            format,
        },
        header,
    ))
}

/// Phase 2 of `end_of_step` for `fix ave/time`: add sample `x`; at the end of the epoch, the
/// text to write (None before).
pub(super) fn accumulate(
    t: &mut AveTime,
    x: Vec<f64>,
    e: Epoch<'_>,
) -> Result<Option<String>, String> {
    let Epoch {
        step,
        first,
        done,
        nrepeat,
        ..
    } = e;
    let mut text = String::new();
    if first {
        t.sum = vec![0.0; x.len()];
    }
    for (s, v) in t.sum.iter_mut().zip(&x) {
        *s += v;
    }
    if !done {
        return Ok(None);
    }
    for s in t.sum.iter_mut() {
        *s /= nrepeat;
    }
    t.avg.push(&t.sum);
    let nv = t.values.len();
    let norm = t.avg.norm as f64;
    if t.vector {
        text.push_str(&format!("{step} {}\n", t.nrows));
        for r in 0..t.nrows {
            text.push_str(&(r + 1).to_string());
            for c in 0..nv {
                let v = t.avg.total[r * nv + c] / norm;
                text.push_str(&sprintf(&t.format, &[FmtArg::Float(v)])?);
            }
            text.push('\n');
        }
    } else {
        text.push_str(&step.to_string());
        for c in 0..nv {
            let v = t.avg.total[c] / norm;
            text.push_str(&sprintf(&t.format, &[FmtArg::Float(v)])?);
        }
        text.push('\n');
    }
    Ok(Some(text))
}

impl Observe {
    /// Phase 1 of `end_of_step` for `fix ave/time`: one sample of its values.
    pub(super) fn sample_time(&self, t: &AveTime, env: &dyn Env) -> Result<Sample, String> {
        let mut out = Vec::with_capacity(t.nrows * t.values.len());
        if t.vector {
            let cols = t
                .values
                .iter()
                .map(|v| self.global_vector(v, env))
                .collect::<Result<Vec<_>, _>>()?;
            for r in 0..t.nrows {
                for c in &cols {
                    out.push(c.get(r).copied().unwrap_or(0.0));
                }
            }
        } else {
            for v in &t.values {
                out.push(self.global(v, env)?);
            }
        }
        Ok(Sample::Time(out))
    }
}
