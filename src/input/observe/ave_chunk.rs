//! `fix ave/chunk` over the bins of a `compute chunk/atom bin/1d`: per-chunk sums of per-atom
//! values (velocities, forces, densities, temperature, atom-style variables), normalised and
//! averaged as LAMMPS does, and the lock that keeps the chunks fixed while a fix averages.

use super::ave_args::{Epoch, FixArgs, Norm};
use super::average::{Ave, Averager, Schedule};
use super::compute::ComputeKind;
use super::{Env, Observe, Sample, Source, VarStyle, parse_ref};
use crate::engine::System;
use crate::engine::measure;
use crate::input::format::{FmtArg, sprintf};

#[derive(Clone, Debug, PartialEq)]
pub(super) enum ChunkValue {
    V(usize),
    F(usize),
    DensityNumber,
    DensityMass,
    Mass,
    Temp,
    Var(String),
    /// `c_ID` or `c_ID[k]` (1-based): a compute's per-atom values or column.
    Compute(String, Option<usize>),
}

#[derive(Debug)]
pub(super) struct AveChunk {
    pub(super) chunk: String,
    values: Vec<ChunkValue>,
    norm: Norm,
    adof: f64,
    /// The unit style of the box (`temp`: mvv2e / boltz; `density/mass`: mv2d).
    units: crate::units::Units,
    nchunk: usize,
    /// Chunks are spatial bins with a coordinate column (bin/1d); molecules have none.
    spatial: bool,
    coord: Vec<f64>,
    count_many: Vec<f64>,
    values_many: Vec<f64>,
    count_sum: Vec<f64>,
    avg: Averager,
    format: String,
    /// The fix holds its lock on the chunk compute forever (`ave running|window`).
    pub(super) lock_forever: bool,
}

impl AveChunk {
    /// Whether a value is compute `id`'s per-atom values.
    pub(super) fn uses_value_compute(&self, id: &str) -> bool {
        self.values
            .iter()
            .any(|v| matches!(v, ChunkValue::Compute(c, _) if c == id))
    }
}

/// The lock a fix holds on a chunk compute, so that the chunks cannot change while it
/// averages (LAMMPS `ComputeChunkAtom::lock`): fix ID, first step, last step (−1: forever).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ChunkLock {
    pub(super) fix: String,
    start: i64,
    stop: i64,
}

/// What the chunk lock needs of an `ave/chunk` fix at one sample
/// ([`Observe::lock_chunk`]): its chunk compute, averaging mode, whether it already holds
/// the lock forever, and where the sample falls in its schedule.
pub(super) struct LockRequest {
    chunk: String,
    ave: Ave,
    forever: bool,
    irepeat: i64,
    nrepeat: i64,
    nevery: i64,
}

impl AveChunk {
    /// This fix's [`LockRequest`] under schedule `s`.
    pub(super) fn lock_request(&self, s: &Schedule) -> LockRequest {
        LockRequest {
            chunk: self.chunk.clone(),
            ave: self.avg.ave,
            forever: self.lock_forever,
            irepeat: s.irepeat,
            nrepeat: s.nrepeat,
            nevery: s.nevery,
        }
    }
}

/// The part of `fix ave/chunk`'s parsing particular to it: the chunk compute, the values and
/// the file header.
pub(super) fn parse(f: FixArgs<'_>, env: &dyn Env) -> Result<(AveChunk, Vec<String>), String> {
    let FixArgs {
        args,
        id,
        sys,
        raw_values,
        ave,
        format,
        titles,
        norm,
        ..
    } = f;
    let obs = env.observe();
    let cid = &args[6];
    let spatial = match obs.compute(cid) {
        Some(c) if c.kind.is_chunk() => matches!(c.kind, ComputeKind::Chunk(_)),
        Some(_) => {
            return Err(format!(
                "fix ave/chunk: compute '{cid}' is not a chunk/atom compute"
            ));
        }
        None => {
            return Err(format!(
                "fix ave/chunk: chunk/atom compute '{cid}' does not exist"
            ));
        }
    };
    let mut values = Vec::new();
    for w in &raw_values {
        values.push(match *w {
            "vx" => ChunkValue::V(0),
            "vy" => ChunkValue::V(1),
            "vz" => ChunkValue::V(2),
            "fx" => ChunkValue::F(0),
            "fy" => ChunkValue::F(1),
            "fz" => ChunkValue::F(2),
            "density/number" => ChunkValue::DensityNumber,
            "density/mass" => ChunkValue::DensityMass,
            "mass" => ChunkValue::Mass,
            "temp" => ChunkValue::Temp,
            w if w.strip_prefix("c_").is_some_and(|b| {
                env.observe()
                    .has_per_atom(b.split_once('[').map_or(b, |(id, _)| id))
            }) =>
            {
                let (id, col) = env.observe().per_atom_ref(&w[2..], "fix ave/chunk")?;
                ChunkValue::Compute(id, col)
            }
            w => match parse_ref(w)? {
                Some((Source::Var(name), None)) => match env.var_style(&name) {
                    VarStyle::Atom => ChunkValue::Var(name),
                    VarStyle::Undefined => {
                        return Err(format!(
                            "{w}: variable '{name}' for fix ave/chunk does not exist"
                        ));
                    }
                    _ => {
                        return Err(format!(
                            "{w}: fix ave/chunk variable '{name}' is not an \
                             atom-style variable"
                        ));
                    }
                },
                _ => {
                    return Err(format!(
                        "fix ave/chunk value '{w}' not supported (vx vy vz fx fy fz \
                         density/number density/mass mass temp v_NAME c_ID or c_ID[k] of a per-atom compute)"
                    ));
                }
            },
        });
    }
    let header = vec![
        titles[0]
            .clone()
            .unwrap_or_else(|| format!("# Chunk-averaged data for fix {id} and group all")),
        titles[1]
            .clone()
            .unwrap_or_else(|| "# Timestep Number-of-chunks Total-count".into()),
        titles[2].clone().unwrap_or_else(|| {
            if spatial {
                format!("# Chunk Coord1 Ncount {}", raw_values.join(" "))
            } else {
                format!("# Chunk Ncount {}", raw_values.join(" "))
            }
        }),
    ];
    Ok((
        AveChunk {
            chunk: cid.clone(),
            values,
            norm,
            adof: sys.dim() as f64,
            units: sys.units,
            nchunk: 0,
            spatial,
            coord: Vec::new(),
            count_many: Vec::new(),
            values_many: Vec::new(),
            count_sum: Vec::new(),
            avg: Averager::new(ave),
            format,
            lock_forever: false,
        },
        header,
    ))
}

/// Phase 2 of `end_of_step` for `fix ave/chunk`: add one sample; at the end of the epoch, the
/// text to write (None before).
pub(super) fn accumulate(
    c: &mut AveChunk,
    coord: Vec<f64>,
    volume: f64,
    count: Vec<f64>,
    values: Vec<f64>,
    e: Epoch<'_>,
) -> Result<Option<String>, String> {
    let Epoch {
        id,
        step,
        first,
        done,
        nrepeat,
    } = e;
    add_sample(c, coord, &count, &values, id, first)?;
    if !done {
        return Ok(None);
    }
    let flat = epoch_average(c, nrepeat, volume);
    c.avg.push(&flat);
    epoch_text(c, step).map(Some)
}

/// Add one sample's per-chunk sums to the epoch's (LAMMPS's operations, in order).
fn add_sample(
    c: &mut AveChunk,
    coord: Vec<f64>,
    count: &[f64],
    values: &[f64],
    id: &str,
    first: bool,
) -> Result<(), String> {
    let nv = c.values.len();
    if first {
        c.nchunk = coord.len();
        c.coord = coord;
        c.count_many = vec![0.0; c.nchunk];
        c.values_many = vec![0.0; c.nchunk * nv];
        c.count_sum = vec![0.0; c.nchunk];
    } else if coord.len() != c.nchunk {
        return Err(format!(
            "fix ave/chunk '{id}': the number of chunks changed within an Nfreq epoch"
        ));
    }
    let n = c.nchunk;
    match c.norm {
        Norm::All => {
            for m in 0..n {
                c.count_many[m] += count[m];
                for j in 0..nv {
                    c.values_many[m * nv + j] += values[m * nv + j];
                }
            }
        }
        Norm::Sample | Norm::None => {
            c.count_many.copy_from_slice(count);
            for m in 0..n {
                let cm = c.count_many[m];
                if cm > 0.0 {
                    for j in 0..nv {
                        let v = values[m * nv + j];
                        let u = &c.units;
                        c.values_many[m * nv + j] += match c.values[j] {
                            ChunkValue::Temp => u.mvv2e * v / (c.adof * cm * u.boltz),
                            ChunkValue::DensityNumber => v,
                            ChunkValue::DensityMass => u.mv2d * v,
                            _ if c.norm == Norm::None => v,
                            _ => v / cm,
                        };
                    }
                }
                c.count_sum[m] += cm;
            }
        }
    }
    Ok(())
}

/// The time average across the epoch's Nrepeat samples (LAMMPS's operations, in order): the
/// counts of the chunks, then their values, flat.
fn epoch_average(c: &AveChunk, nrepeat: f64, volume: f64) -> Vec<f64> {
    let n = c.nchunk;
    let nv = c.values.len();
    let mut count_sum = vec![0.0; n];
    let mut values_sum = vec![0.0; n * nv];
    match c.norm {
        Norm::All => {
            count_sum.copy_from_slice(&c.count_many);
            values_sum.copy_from_slice(&c.values_many);
            for m in 0..n {
                if count_sum[m] > 0.0 {
                    for j in 0..nv {
                        let v = &mut values_sum[m * nv + j];
                        match c.values[j] {
                            ChunkValue::Temp => {
                                *v *= c.units.mvv2e / (c.adof * count_sum[m] * c.units.boltz)
                            }
                            ChunkValue::DensityMass => *v *= c.units.mv2d / nrepeat,
                            ChunkValue::DensityNumber => *v /= nrepeat,
                            _ => *v /= count_sum[m],
                        }
                    }
                }
                count_sum[m] /= nrepeat;
            }
        }
        Norm::Sample | Norm::None => {
            for m in 0..n {
                for j in 0..nv {
                    values_sum[m * nv + j] = c.values_many[m * nv + j] / nrepeat;
                }
                count_sum[m] = c.count_sum[m] / nrepeat;
            }
        }
    }
    for j in 0..nv {
        if matches!(
            c.values[j],
            ChunkValue::DensityNumber | ChunkValue::DensityMass
        ) {
            for m in 0..n {
                values_sum[m * nv + j] /= volume;
            }
        }
    }
    let mut flat = count_sum;
    flat.extend_from_slice(&values_sum);
    flat
}

/// The file's lines for the epoch ending at `step`: its header line, then one line per chunk.
fn epoch_text(c: &AveChunk, step: u64) -> Result<String, String> {
    let n = c.nchunk;
    let nv = c.values.len();
    let mut text = String::new();
    let norm = c.avg.norm as f64;
    let total: f64 = c.avg.total[..n].iter().sum();
    text.push_str(&format!(
        "{step} {n} {}\n",
        sprintf("%g", &[FmtArg::Float(total)])?
    ));
    for m in 0..n {
        let count = sprintf("%g", &[FmtArg::Float(c.avg.total[m] / norm)])?;
        if c.spatial {
            text.push_str(&format!(
                "  {} {} {count}",
                m + 1,
                sprintf("%g", &[FmtArg::Float(c.coord[m])])?,
            ));
        } else {
            text.push_str(&format!("  {} {count}", m + 1));
        }
        for j in 0..nv {
            let v = c.avg.total[n + m * nv + j] / norm;
            text.push_str(&sprintf(&c.format, &[FmtArg::Float(v)])?);
        }
        text.push('\n');
    }
    Ok(text)
}

impl Observe {
    /// Lock chunk compute `chunk` for fix `fix` from `start` to `stop` (LAMMPS's rule: a second
    /// fix may only share the lock with the same steps).
    fn lock(&mut self, chunk: &str, fix: &str, start: i64, stop: i64) -> Result<(), String> {
        let new = ChunkLock {
            fix: fix.to_string(),
            start,
            stop,
        };
        match self.locks.iter_mut().find(|(c, _)| c == chunk) {
            None => self.locks.push((chunk.to_string(), new)),
            Some((_, l)) => {
                if l.start != start || l.stop != stop {
                    return Err(format!(
                        "two fix commands use compute chunk/atom '{chunk}' in incompatible ways: \
                         fix '{}' keeps its chunks fixed over steps {}..{}, fix '{fix}' over \
                         {start}..{} (LAMMPS refuses this too)",
                        l.fix,
                        l.start,
                        if l.stop < 0 {
                            "end".to_string()
                        } else {
                            l.stop.to_string()
                        },
                        if stop < 0 {
                            "end".to_string()
                        } else {
                            stop.to_string()
                        },
                    ));
                }
                l.fix = fix.to_string();
            }
        }
        Ok(())
    }

    fn unlock(&mut self, chunk: &str, fix: &str) {
        self.locks.retain(|(c, l)| !(c == chunk && l.fix == fix));
    }

    /// The chunk lock of fix `id` as its sample at `step` is accumulated (`r`: the fix's
    /// [`AveChunk::lock_request`]). True when the fix now holds its lock forever (the caller
    /// sets [`AveChunk::lock_forever`]).
    pub(super) fn lock_chunk(
        &mut self,
        r: LockRequest,
        id: &str,
        step: u64,
    ) -> Result<bool, String> {
        // LAMMPS locks the chunk compute on the first sample of an epoch.
        let LockRequest {
            chunk,
            ave,
            forever,
            irepeat,
            nrepeat,
            nevery,
        } = r;
        let step = step as i64;
        if irepeat == 0 {
            if nrepeat > 1 && ave == Ave::One {
                let stop = step + (nrepeat - 1) * nevery;
                self.lock(&chunk, id, step, stop)?;
            } else if ave != Ave::One && !forever {
                self.lock(&chunk, id, step, -1)?;
                return Ok(true);
            }
        } else if irepeat + 1 == nrepeat && nrepeat > 1 && ave == Ave::One {
            self.unlock(&chunk, id);
        }
        Ok(false)
    }

    /// Phase 1 of `end_of_step` for `fix ave/chunk`: one sample of its per-chunk sums.
    pub(super) fn sample_chunk(
        &self,
        c: &AveChunk,
        env: &dyn Env,
        sys: &System,
    ) -> Result<Sample, String> {
        let (bins, coord, volume) = match self.compute(&c.chunk).map(|d| &d.kind) {
            Some(ComputeKind::Chunk(b)) => {
                let layout = b.layout(&sys.bx)?;
                (layout.assign(sys), layout.coord, layout.volume)
            }
            // Molecules: chunk = molecule id (compress no: 1 … the largest id), the whole box
            // as the volume of a density (LAMMPS, for chunks that are not bins).
            Some(ComputeKind::ChunkMolecule) => {
                let a = &sys.atoms;
                let n = (0..a.len()).map(|i| a.mol_of(i)).max().unwrap_or(0) as usize;
                let bins = (0..a.len())
                    .map(|i| (a.mol_of(i) as usize).checked_sub(1))
                    .collect();
                (bins, vec![0.0; n], sys.bx.volume())
            }
            _ => {
                return Err(format!(
                    "chunk/atom compute '{}' for fix ave/chunk does not exist",
                    c.chunk
                ));
            }
        };
        let n = coord.len();
        let nv = c.values.len();
        let mut count = vec![0.0; n];
        let mut values = vec![0.0; n * nv];
        for b in bins.iter().flatten() {
            count[*b] += 1.0;
        }
        for (m, v) in c.values.iter().enumerate() {
            let per_atom: Vec<f64> = match v {
                ChunkValue::V(d) => sys.atoms.v.iter().map(|v| v[*d]).collect(),
                ChunkValue::F(d) => sys.atoms.f.iter().map(|f| f[*d]).collect(),
                ChunkValue::DensityNumber => vec![1.0; sys.atoms.len()],
                ChunkValue::DensityMass | ChunkValue::Mass => (0..sys.atoms.len())
                    .map(|i| measure::mass_of(sys, i))
                    .collect(),
                ChunkValue::Temp => (0..sys.atoms.len())
                    .map(|i| {
                        let v = sys.atoms.v[i];
                        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * measure::mass_of(sys, i)
                    })
                    .collect(),
                ChunkValue::Var(name) => env.atom_variable(name)?,
                ChunkValue::Compute(id, col) => env.observe().per_atom_column(id, *col, sys)?,
            };
            for (i, b) in bins.iter().enumerate() {
                if let Some(b) = b {
                    values[b * nv + m] += per_atom[i];
                }
            }
        }
        Ok(Sample::Chunk {
            coord,
            volume,
            count,
            values,
        })
    }
}
