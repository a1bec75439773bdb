//! `fix ave/histo`: histograms of per-atom values (atom attributes, atom-style variables) or of
//! global values, with LAMMPS's out-of-range rules and running minimum and maximum.

use super::ave_args::{Epoch, FixArgs};
use super::average::{Ave, Averager};
use super::per_atom::atom_value;
use super::{Env, Observe, Sample, Source, ValueRef, VarStyle, parse_i64, parse_num, parse_ref};
use crate::engine::System;
use crate::engine::measure::{HistoBins, HistoSample};
use crate::input::expr::AtomValue;
use crate::input::format::{FmtArg, sprintf};

#[derive(Clone, Debug, PartialEq)]
pub(super) enum HistoInput {
    Atom(AtomValue),
    AtomVar(String),
    Global(ValueRef),
}

#[derive(Debug)]
pub(super) struct AveHisto {
    pub(super) inputs: Vec<HistoInput>,
    vector: bool,
    bins: HistoBins,
    acc: HistoSample,
    pub(super) avg: Averager,
    minmax: Vec<[f64; 2]>,
    pub(super) total_minmax: [f64; 2],
}

/// The part of `fix ave/histo`'s parsing particular to it: the bins, the inputs (all per-atom
/// or all global), checked, and the file header.
pub(super) fn parse(f: FixArgs<'_>, env: &dyn Env) -> Result<(AveHisto, Vec<String>), String> {
    let FixArgs {
        args,
        id,
        style,
        raw_values,
        nevery,
        ave,
        vector,
        titles,
        beyond,
        ..
    } = f;
    let obs = env.observe();
    let lo = parse_num(&args[6], "histogram lo")?;
    let hi = parse_num(&args[7], "histogram hi")?;
    let nbins = parse_i64(&args[8], "number of bins")?;
    if lo >= hi {
        return Err(format!("illegal fix ave/histo: lo {lo} >= hi {hi}"));
    }
    // The upper bound as in compute chunk/atom: 10^11 bins aborted in the allocator.
    if !(1..100_000_000).contains(&nbins) {
        return Err(format!(
            "illegal fix ave/histo: {nbins} bins (need 1 to 10^8)"
        ));
    }
    let mut inputs = Vec::new();
    for w in &raw_values {
        if let Some(a) = AtomValue::from_word(w) {
            inputs.push(HistoInput::Atom(a));
            continue;
        }
        for e in obs.expand(w, vector)? {
            let (source, index) =
                parse_ref(&e)?.ok_or_else(|| format!("'{e}' is not c_ID, f_ID or v_name"))?;
            if let Source::Var(name) = &source
                && env.var_style(name) == VarStyle::Atom
            {
                if index.is_some() {
                    return Err(format!("{e}: atom-style variables take no index"));
                }
                inputs.push(HistoInput::AtomVar(name.clone()));
                continue;
            }
            if let Source::Compute(cid) = &source
                && obs.compute(cid).is_some_and(|c| c.kind.is_chunk())
            {
                return Err(format!(
                    "{e}: per-atom computes are not supported in fix ave/histo"
                ));
            }
            let v = ValueRef {
                text: e,
                source,
                index,
            };
            obs.check_global(&v, vector, nevery, style, env)?;
            inputs.push(HistoInput::Global(v));
        }
    }
    let peratom = matches!(inputs[0], HistoInput::Atom(_) | HistoInput::AtomVar(_));
    if inputs
        .iter()
        .any(|i| matches!(i, HistoInput::Global(_)) == peratom)
    {
        return Err("fix ave/histo inputs are not all global or all per-atom".into());
    }
    if peratom && !vector {
        return Err("fix ave/histo cannot input per-atom values in scalar mode \
                    (add 'mode vector')"
            .into());
    }
    let bins = HistoBins::new(lo, hi, nbins as usize, beyond);
    let header = vec![
        titles[0]
            .clone()
            .unwrap_or_else(|| format!("# Histogrammed data for fix {id}")),
        titles[1].clone().unwrap_or_else(|| {
            "# TimeStep Number-of-bins Total-counts Missing-counts Min-value Max-value".into()
        }),
        titles[2]
            .clone()
            .unwrap_or_else(|| "# Bin Coord Count Count/Total".into()),
    ];
    Ok((
        AveHisto {
            inputs,
            vector,
            acc: bins.empty(),
            bins,
            avg: Averager::new(ave),
            minmax: Vec::new(),
            total_minmax: [0.0, 0.0],
        },
        header,
    ))
}

/// Phase 2 of `end_of_step` for `fix ave/histo`: add histogram `s`; at the end of the epoch,
/// the text to write (None before).
pub(super) fn accumulate(
    h: &mut AveHisto,
    s: HistoSample,
    e: Epoch<'_>,
) -> Result<Option<String>, String> {
    let Epoch {
        step, first, done, ..
    } = e;
    let mut text = String::new();
    if first {
        h.acc = h.bins.empty();
    }
    for (a, b) in h.acc.bins.iter_mut().zip(&s.bins) {
        *a += b;
    }
    h.acc.stats[0] += s.stats[0];
    h.acc.stats[1] += s.stats[1];
    h.acc.stats[2] = h.acc.stats[2].min(s.stats[2]);
    h.acc.stats[3] = h.acc.stats[3].max(s.stats[3]);
    if !done {
        return Ok(None);
    }
    let mut flat = vec![h.acc.stats[0], h.acc.stats[1]];
    flat.extend_from_slice(&h.acc.bins);
    h.avg.push(&flat);
    let (mn, mx) = (h.acc.stats[2], h.acc.stats[3]);
    h.total_minmax = match h.avg.ave {
        Ave::One => [mn, mx],
        // LAMMPS starts the running min and max from 0, not from ±BIG.
        Ave::Running => [h.total_minmax[0].min(mn), h.total_minmax[1].max(mx)],
        Ave::Window(nw) => {
            // avg.push already advanced its slot: the one just filled is before it.
            let slot = (h.avg.iwindow + nw - 1) % nw;
            // Slots fill in order 0, 1, …: grown as they come, as the averager's.
            if h.minmax.len() <= slot {
                h.minmax.resize(slot + 1, [0.0, 0.0]);
            }
            h.minmax[slot] = [mn, mx];
            let m = if h.avg.full { nw } else { slot + 1 };
            let mut t = h.minmax[0];
            for e in &h.minmax[1..m] {
                t = [t[0].min(e[0]), t[1].max(e[1])];
            }
            t
        }
    };
    let tot = &h.avg.total;
    let g = |v: f64| sprintf("%g", &[FmtArg::Float(v)]);
    text.push_str(&format!(
        "{step} {} {} {} {} {}\n",
        h.bins.nbins,
        g(tot[0])?,
        g(tot[1])?,
        g(h.total_minmax[0])?,
        g(h.total_minmax[1])?
    ));
    for i in 0..h.bins.nbins {
        let (count, frac) = if tot[0] != 0.0 {
            (tot[2 + i], tot[2 + i] / tot[0])
        } else {
            (0.0, 0.0)
        };
        text.push_str(&format!(
            "{} {} {} {}\n",
            i + 1,
            g(h.bins.coord[i])?,
            g(count)?,
            g(frac)?
        ));
    }
    Ok(Some(text))
}

impl Observe {
    /// Phase 1 of `end_of_step` for `fix ave/histo`: this step's histogram.
    pub(super) fn sample_histo(
        &self,
        h: &AveHisto,
        env: &dyn Env,
        sys: &System,
    ) -> Result<Sample, String> {
        let mut s = h.bins.empty();
        for input in &h.inputs {
            match input {
                HistoInput::Atom(a) => {
                    for i in 0..sys.atoms.len() {
                        h.bins.add(&mut s, atom_value(sys, i, *a));
                    }
                }
                HistoInput::AtomVar(name) => {
                    for v in env.atom_variable(name)? {
                        h.bins.add(&mut s, v);
                    }
                }
                HistoInput::Global(v) if h.vector => {
                    for x in self.global_vector(v, env)? {
                        h.bins.add(&mut s, x);
                    }
                }
                HistoInput::Global(v) => h.bins.add(&mut s, self.global(v, env)?),
            }
        }
        Ok(Sample::Histo(s))
    }
}
