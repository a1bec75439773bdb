//! The computes: `temp`, `temp/deform`, `pressure`, `pe`, `ke`, `msd`, `chunk/atom bin/1d`,
//! `sdpd/density` and
//! the built-in `thermo_temp`, `thermo_press`, `thermo_pe` (parsing, `uncompute`, the thermo
//! state they give, their global scalars and vectors).

use super::stress_atom::StressAtom;
use super::{Env, Observe, arg, parse_num};
use crate::engine::System;
use crate::engine::measure::{Bin1d, BinOrigin, Discard, Msd};

/// Names of the computes LAMMPS defines by itself.
pub(crate) const BUILTIN_COMPUTES: [&str; 3] = ["thermo_temp", "thermo_press", "thermo_pe"];

#[derive(Debug)]
pub(super) enum ComputeKind {
    /// `temp`: scalar T (dof = dN − d), vector Σ m v_a v_b (xx yy zz xy xz yz).
    Temp,
    /// `temp/deform`: as `temp` with the streaming velocity of `fix deform` removed
    /// (`System::thermo_deform`).
    TempDeform,
    /// `pressure TEMP-ID`: scalar P, vector P_ab (kinetic part of TEMP-ID + virial of all pair
    /// forces).
    Pressure(String),
    /// `pe`: total pair energy.
    Pe,
    /// `ke`: total kinetic energy.
    Ke,
    /// `msd`: vector of 4.
    Msd(Msd),
    /// `chunk/atom bin/1d`: per-atom chunk index.
    Chunk(Bin1d),
    /// `chunk/atom molecule`: chunk = molecule id (1 … the largest id; atoms of molecule 0 in
    /// no chunk), LAMMPS's `compress no`.
    ChunkMolecule,
    /// `gyration`: scalar R_g of the unwrapped, mass-weighted positions; vector of 6, the
    /// gyration tensor (xx yy zz xy xz yz).
    Gyration,
    /// `gyration/chunk CHUNK-ID` over `chunk/atom molecule`: vector of R_g per molecule
    /// 1 … `nchunk` (the largest molecule id when defined; ids do not change).
    GyrationChunk {
        /// The chunk compute.
        chunk: String,
        /// Number of chunks.
        nchunk: usize,
    },
    /// `sdpd/density`: per atom the number density d_i of `pair_style sdpd`'s last evaluation;
    /// vector [mean d, rms(d − mean)/mean].
    SdpdDensity,
    /// `temp/partial xflag yflag zflag`: as `temp` over the flagged velocity components
    /// (`System::thermo_partial`).
    TempPartial([bool; 3]),
    /// `reduce MODE INPUT…` (in `reduce`): a scalar (one input) or a vector.
    Reduce(super::reduce::Reduce),
    /// `stress/atom TEMP-ID|NULL [ke] [pair] [bond] [angle] [virial]`: per atom 6 columns
    /// (`System::stress_atom`).
    StressAtom(StressAtom),
}

impl ComputeKind {
    pub(super) fn style(&self) -> &'static str {
        match self {
            ComputeKind::Temp => "temp",
            ComputeKind::TempDeform => "temp/deform",
            ComputeKind::Pressure(_) => "pressure",
            ComputeKind::Pe => "pe",
            ComputeKind::Ke => "ke",
            ComputeKind::Msd(_) => "msd",
            ComputeKind::Chunk(_) | ComputeKind::ChunkMolecule => "chunk/atom",
            ComputeKind::Gyration => "gyration",
            ComputeKind::GyrationChunk { .. } => "gyration/chunk",
            ComputeKind::SdpdDensity => "sdpd/density",
            ComputeKind::Reduce(_) => "reduce",
            ComputeKind::TempPartial(_) => "temp/partial",
            ComputeKind::StressAtom(_) => "stress/atom",
        }
    }

    pub(super) fn has_scalar(&self) -> bool {
        if let ComputeKind::Reduce(r) = self {
            return r.inputs.len() == 1;
        }
        matches!(
            self,
            ComputeKind::Temp
                | ComputeKind::TempDeform
                | ComputeKind::TempPartial(_)
                | ComputeKind::Pressure(_)
                | ComputeKind::Pe
                | ComputeKind::Ke
                | ComputeKind::Gyration
        )
    }

    /// A `chunk/atom` compute (any style).
    pub(super) fn is_chunk(&self) -> bool {
        matches!(self, ComputeKind::Chunk(_) | ComputeKind::ChunkMolecule)
    }

    pub(super) fn vector_len(&self) -> Option<usize> {
        match self {
            ComputeKind::Temp
            | ComputeKind::TempDeform
            | ComputeKind::TempPartial(_)
            | ComputeKind::Pressure(_)
            | ComputeKind::Gyration => Some(6),
            ComputeKind::Msd(_) => Some(4),
            ComputeKind::GyrationChunk { nchunk, .. } => Some(*nchunk),
            ComputeKind::SdpdDensity => Some(2),
            ComputeKind::Reduce(r) if r.inputs.len() > 1 => Some(r.inputs.len()),
            _ => None,
        }
    }

    /// Whether the scalar (`index` None) or the vector is extensive (LAMMPS's `extscalar`,
    /// `extvector`): thermo output with `thermo_modify norm yes` divides it by the atom count.
    /// The temperatures' vectors (Σ m v_a v_b) are, their scalars are not.
    pub(super) fn extensive(&self, index: Option<usize>) -> bool {
        match self {
            ComputeKind::Reduce(r) => r.extensive(),
            ComputeKind::Temp | ComputeKind::TempDeform | ComputeKind::TempPartial(_) => {
                index.is_some()
            }
            k => matches!(k, ComputeKind::Pe | ComputeKind::Ke),
        }
    }

    /// Whether the compute has per-atom values (`c_ID` in `dump custom` and `fix ave/chunk`).
    pub(super) fn has_per_atom(&self) -> bool {
        matches!(self, ComputeKind::SdpdDensity | ComputeKind::StressAtom(_))
    }

    /// The per-atom columns: 0 for one value per atom, n for n columns.
    pub(super) fn per_atom_width(&self) -> usize {
        match self {
            ComputeKind::StressAtom(_) => 6,
            _ => 0,
        }
    }

    pub(super) fn is_temperature(&self) -> bool {
        matches!(
            self,
            ComputeKind::Temp | ComputeKind::TempDeform | ComputeKind::TempPartial(_)
        )
    }
}

/// The usage of `compute`, quoted in its errors.
const COMPUTE_USAGE: &str = "compute ID all temp | temp/deform | temp/partial XFLAG YFLAG ZFLAG | pressure TEMP-ID | pe | ke | gyration | sdpd/density | reduce MODE INPUT… | stress/atom TEMP-ID|NULL [ke] [pair] [bond] [angle] [virial] | msd [com yes|no] | chunk/atom molecule | chunk/atom bin/1d x|y|z lower|center|upper|COORD DELTA [units box|lattice|reduced] [discard mixed|yes|no] [bound x|y|z lo|lower hi|upper]";

/// A compute: its ID and what it computes.
#[derive(Debug)]
pub struct ComputeDef {
    pub(super) id: String,
    pub(super) kind: ComputeKind,
}

impl Observe {
    // ------------------------------------------------------------------ computes

    /// Parse `compute ID all STYLE ARGS…` (checked against `env`, not yet added).
    pub fn parse_compute(args: &[String], env: &dyn Env) -> Result<ComputeDef, String> {
        if args.len() < 3 {
            return Err(format!("missing arguments; usage: {COMPUTE_USAGE}"));
        }
        let id = &args[0];
        if !id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(format!(
                "compute ID '{id}' must be alphanumeric, '_' or '-'"
            ));
        }
        if env.observe().compute(id).is_some() {
            return Err(format!("reuse of compute ID '{id}' (uncompute it first)"));
        }
        if args[1] != "all" {
            return Err(format!(
                "compute {} on group '{}' not supported in the standalone engine: its computes \
                 act on group all only (fixes, velocity and dump take a group)",
                args.get(2).map_or("", String::as_str),
                args[1]
            ));
        }
        let sys = env
            .system()
            .ok_or("compute needs a simulation box (create_box or read_data) first")?;
        Ok(ComputeDef {
            id: id.clone(),
            kind: Self::compute_kind(args, env, sys)?,
        })
    }

    /// What `compute ID all STYLE ARGS…` computes, from its style and arguments.
    fn compute_kind(args: &[String], env: &dyn Env, sys: &System) -> Result<ComputeKind, String> {
        let usage = COMPUTE_USAGE;
        let extra = |n: usize| -> Result<(), String> {
            if args.len() > n {
                Err(format!(
                    "compute {} takes no argument '{}'; usage: {usage}",
                    args[2], args[n]
                ))
            } else {
                Ok(())
            }
        };
        let kind = match args[2].as_str() {
            "temp" => {
                extra(3)?;
                ComputeKind::Temp
            }
            "temp/deform" => {
                extra(3)?;
                ComputeKind::TempDeform
            }
            "temp/partial" => {
                let usage = "compute ID all temp/partial xflag yflag zflag (each 0 or 1)";
                let mut flags = [false; 3];
                for (k, f) in flags.iter_mut().enumerate() {
                    *f = match arg(args, 3 + k, usage)? {
                        "0" => false,
                        "1" => true,
                        o => {
                            return Err(format!(
                                "compute temp/partial flag '{o}' must be 0 or 1; usage: {usage}"
                            ));
                        }
                    };
                }
                extra(6)?;
                if flags[2] && sys.dim() == 2 {
                    return Err("compute temp/partial cannot use vz (zflag 1) in 2-D".into());
                }
                ComputeKind::TempPartial(flags)
            }
            "pe" => {
                extra(3)?;
                ComputeKind::Pe
            }
            "ke" => {
                extra(3)?;
                ComputeKind::Ke
            }
            "gyration" => {
                extra(3)?;
                ComputeKind::Gyration
            }
            "gyration/chunk" => {
                let chunk = arg(args, 3, "compute ID all gyration/chunk CHUNK-ID")?;
                extra(4)?;
                Self::gyration_chunk(chunk, env, sys)?
            }
            "sdpd/density" => {
                extra(3)?;
                if sys.pair.as_deref().and_then(|p| p.prepass()).is_none() {
                    return Err(
                        "compute sdpd/density needs pair_style sdpd (define it first)".into(),
                    );
                }
                ComputeKind::SdpdDensity
            }
            "pressure" => Self::pressure(args, env)?,
            "stress/atom" => ComputeKind::StressAtom(StressAtom::parse(args, env)?),
            "reduce" => ComputeKind::Reduce(super::reduce::Reduce::parse(args, env)?),
            "msd" => ComputeKind::Msd(Msd::new(sys, Self::msd_com(args)?)),
            "chunk/atom" if args.get(3).map(String::as_str) == Some("molecule") => {
                extra(4)?;
                if sys.topo.is_none() {
                    return Err(
                        "compute chunk/atom molecule needs molecule ids (atom_style bond, \
                         angle, molecular or full)"
                            .into(),
                    );
                }
                ComputeKind::ChunkMolecule
            }
            "chunk/atom" => ComputeKind::Chunk(Self::parse_chunk(args, sys)?),
            o => {
                return Err(format!("compute style '{o}' not supported; usage: {usage}"));
            }
        };
        Ok(kind)
    }

    /// `compute ID all gyration/chunk CHUNK`: CHUNK must be a `chunk/atom molecule` compute;
    /// one chunk per molecule id of the system.
    fn gyration_chunk(chunk: &str, env: &dyn Env, sys: &System) -> Result<ComputeKind, String> {
        match env.observe().compute(chunk).map(|c| &c.kind) {
            Some(ComputeKind::ChunkMolecule) => {}
            Some(_) => {
                return Err(format!(
                    "compute gyration/chunk: compute '{chunk}' is not a chunk/atom \
                     molecule compute (the only chunk style supported here)"
                ));
            }
            None => {
                return Err(format!(
                    "compute gyration/chunk: chunk/atom compute '{chunk}' does not exist"
                ));
            }
        }
        let a = &sys.atoms;
        let nchunk = (0..a.len()).map(|i| a.mol_of(i)).max().unwrap_or(0) as usize;
        Ok(ComputeKind::GyrationChunk {
            chunk: chunk.to_string(),
            nchunk,
        })
    }

    /// `compute ID all pressure TEMP`: TEMP must be a temperature compute; no keywords.
    fn pressure(args: &[String], env: &dyn Env) -> Result<ComputeKind, String> {
        let t = arg(args, 3, COMPUTE_USAGE)?;
        match env.observe().compute(t) {
            Some(c) if c.kind.is_temperature() => {}
            Some(c) => {
                return Err(format!(
                    "compute pressure: compute '{t}' is a {} compute, not a temperature",
                    c.kind.style()
                ));
            }
            None => {
                return Err(format!(
                    "compute pressure: temperature compute '{t}' does not exist"
                ));
            }
        }
        if args.len() > 4 {
            return Err(format!(
                "compute pressure keyword '{}' not supported: the pressure always \
                 includes the kinetic part and the virial of all pair forces",
                args[4]
            ));
        }
        Ok(ComputeKind::Pressure(t.to_string()))
    }

    /// The keywords of `compute ID all msd [com yes|no] [average no]`: whether `com` is on.
    fn msd_com(args: &[String]) -> Result<bool, String> {
        let mut com = false;
        let mut k = 3;
        while k < args.len() {
            let v = arg(args, k + 1, COMPUTE_USAGE)?;
            let yes = match v {
                "yes" => true,
                "no" => false,
                o => {
                    return Err(format!("compute msd {} '{o}' must be yes or no", args[k]));
                }
            };
            match args[k].as_str() {
                "com" => com = yes,
                "average" if !yes => {}
                "average" => {
                    return Err("compute msd average yes is not supported".into());
                }
                o => return Err(format!("unknown compute msd keyword '{o}'")),
            }
            k += 2;
        }
        Ok(com)
    }

    fn parse_chunk(args: &[String], sys: &System) -> Result<Bin1d, String> {
        let usage = "compute ID all chunk/atom bin/1d x|y|z lower|center|upper|COORD DELTA [units box|lattice|reduced] [discard mixed|yes|no] [bound x|y|z lo|lower hi|upper]";
        let style = arg(args, 3, usage)?;
        if style != "bin/1d" {
            return Err(format!(
                "compute chunk/atom style '{style}' not supported: only bin/1d and molecule"
            ));
        }
        let axis_of = |t: &str| -> Result<usize, String> {
            match t {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" => Ok(2),
                o => Err(format!("chunk/atom dimension '{o}' must be x, y or z")),
            }
        };
        let axis = axis_of(arg(args, 4, usage)?)?;
        if axis == 2 && sys.dim() == 2 {
            return Err("cannot use compute chunk/atom bin z for a 2-D model".into());
        }
        let origin = match arg(args, 5, usage)? {
            "lower" => BinOrigin::Lower,
            "center" => BinOrigin::Center,
            "upper" => BinOrigin::Upper,
            t => BinOrigin::Coord(parse_num(t, "bin origin")?),
        };
        let delta = parse_num(arg(args, 6, usage)?, "bin width")?;
        if delta <= 0.0 {
            return Err(format!("bin width {delta} must be > 0"));
        }
        let mut b = Bin1d {
            axis,
            origin,
            delta,
            reduced: false,
            min: None,
            max: None,
            discard: Discard::Mixed,
        };
        let mut k = 7;
        while k < args.len() {
            let v = arg(args, k + 1, usage)?;
            match args[k].as_str() {
                "units" => {
                    b.reduced = match v {
                        // No lattice command: lattice units are box units (LAMMPS's default
                        // lattice has spacing 1).
                        "box" | "lattice" => false,
                        "reduced" => true,
                        o => return Err(format!("units '{o}' must be box, lattice or reduced")),
                    }
                }
                "discard" => {
                    b.discard = match v {
                        "mixed" => Discard::Mixed,
                        "yes" => Discard::Yes,
                        "no" => Discard::No,
                        o => return Err(format!("discard '{o}' must be mixed, yes or no")),
                    }
                }
                "bound" => {
                    if axis_of(v)? != axis {
                        return Err(format!(
                            "bound {v}: only the binned dimension {} can be bounded",
                            ["x", "y", "z"][axis]
                        ));
                    }
                    let lo = arg(args, k + 2, usage)?;
                    let hi = arg(args, k + 3, usage)?;
                    b.min = if lo == "lower" {
                        None
                    } else {
                        Some(parse_num(lo, "bound lo")?)
                    };
                    b.max = if hi == "upper" {
                        None
                    } else {
                        Some(parse_num(hi, "bound hi")?)
                    };
                    k += 4;
                    continue;
                }
                "nchunk" | "ids" | "compress" | "limit" | "region" | "pbc" => {
                    return Err(format!(
                        "compute chunk/atom keyword '{}' not supported (units, discard, bound)",
                        args[k]
                    ));
                }
                o => return Err(format!("unknown compute chunk/atom keyword '{o}'")),
            }
            k += 2;
        }
        // Validate now (LAMMPS checks at the first use).
        b.layout(&sys.bx)?;
        Ok(b)
    }

    /// Add a parsed compute.
    pub fn add_compute(&mut self, c: ComputeDef) {
        self.computes.push(c);
    }

    /// The thermodynamic state (temperature, kinetic energy, and the pressure of a `compute
    /// pressure` that uses it) with the kinetic tensor of temperature compute `id`.
    pub fn thermo_of_temp(&self, id: &str, sys: &System) -> Result<crate::engine::Thermo, String> {
        match self.compute(id).map(|c| &c.kind) {
            Some(ComputeKind::Temp) => Ok(sys.thermo()),
            Some(ComputeKind::TempDeform) => Ok(sys.thermo_deform()),
            Some(ComputeKind::TempPartial(f)) => Ok(sys.thermo_partial(*f)),
            Some(k) => Err(format!(
                "compute '{id}' is a {} compute, not a temperature",
                k.style()
            )),
            None => Err(format!("temperature compute '{id}' does not exist")),
        }
    }

    /// The velocity components temperature compute `id` counts (`velocity … temp ID`): all
    /// three for `temp`, the flagged ones for `temp/partial`; `temp/deform`'s bias (a
    /// streaming velocity) is refused there.
    pub fn temp_components(&self, id: &str) -> Result<[bool; 3], String> {
        match self.compute(id).map(|c| &c.kind) {
            Some(ComputeKind::Temp) => Ok([true; 3]),
            Some(ComputeKind::TempPartial(f)) => Ok(*f),
            Some(ComputeKind::TempDeform) => Err(format!(
                "velocity with temp/deform compute '{id}' is not supported (use temp or \
                 temp/partial)"
            )),
            Some(k) => Err(format!(
                "compute '{id}' is a {} compute, not a temperature",
                k.style()
            )),
            None => Err(format!("temperature compute '{id}' does not exist")),
        }
    }

    /// The state of pressure compute `id` (its temperature's kinetic part + the virial).
    pub fn thermo_of_press(&self, id: &str, sys: &System) -> Result<crate::engine::Thermo, String> {
        match self.compute(id).map(|c| &c.kind) {
            Some(ComputeKind::Pressure(t)) => self.thermo_of_temp(t, sys),
            Some(k) => Err(format!(
                "compute '{id}' is a {} compute, not a pressure",
                k.style()
            )),
            None => Err(format!("pressure compute '{id}' does not exist")),
        }
    }

    /// `thermo_modify temp ID`: check `id` is a temperature and, as LAMMPS does, make the
    /// built-in `thermo_press` use it.
    pub fn set_thermo_temp(&mut self, id: &str) -> Result<(), String> {
        match self.compute(id).map(|c| c.kind.is_temperature()) {
            Some(true) => {}
            Some(false) => {
                return Err(format!(
                    "thermo_modify temp: compute '{id}' is not a temperature compute"
                ));
            }
            None => return Err(format!("thermo_modify temp: compute '{id}' does not exist")),
        }
        for c in &mut self.computes {
            if c.id == "thermo_press" {
                c.kind = ComputeKind::Pressure(id.to_string());
            }
        }
        Ok(())
    }

    /// True if `id` is a `compute pressure`.
    pub fn is_pressure(&self, id: &str) -> bool {
        matches!(
            self.compute(id).map(|c| &c.kind),
            Some(ComputeKind::Pressure(_))
        )
    }

    /// `uncompute ID`.
    pub fn uncompute(&mut self, id: &str) -> Result<(), String> {
        if BUILTIN_COMPUTES.contains(&id) {
            return Err(format!("the built-in compute '{id}' cannot be deleted"));
        }
        let pos = self
            .computes
            .iter()
            .position(|c| c.id == id)
            .ok_or_else(|| format!("no compute with ID '{id}'"))?;
        for f in &self.fixes {
            if f.uses_compute(id) {
                return Err(format!(
                    "compute '{id}' is used by fix '{}' (unfix it first)",
                    f.id
                ));
            }
        }
        for c in &self.computes {
            let uses = match &c.kind {
                ComputeKind::Pressure(t) => t == id,
                ComputeKind::GyrationChunk { chunk, .. } => chunk == id,
                ComputeKind::Reduce(r) => r.uses_compute(id),
                ComputeKind::StressAtom(s) => s.uses_compute(id),
                _ => false,
            };
            if c.id != id && uses {
                return Err(format!("compute '{id}' is used by compute '{}'", c.id));
            }
        }
        self.computes.remove(pos);
        Ok(())
    }

    pub(super) fn compute_scalar(
        &self,
        c: &ComputeDef,
        env: &dyn Env,
        sys: &System,
    ) -> Result<f64, String> {
        Ok(match &c.kind {
            ComputeKind::Reduce(r) if r.inputs.len() == 1 => r.values(env, sys)?[0],
            ComputeKind::Temp => sys.thermo().temp,
            ComputeKind::TempDeform => sys.thermo_deform().temp,
            ComputeKind::TempPartial(f) => sys.thermo_partial(*f).temp,
            ComputeKind::Pressure(t) => self.thermo_of_temp(t, sys)?.press,
            ComputeKind::Pe => sys.tally.energy,
            ComputeKind::Ke => sys.thermo().ke,
            ComputeKind::Gyration => {
                let g = gyration_tensor(sys);
                (g[0] + g[1] + g[2]).sqrt()
            }
            k => {
                return Err(format!(
                    "compute {} '{}' does not calculate a global scalar",
                    k.style(),
                    c.id
                ));
            }
        })
    }

    pub(super) fn compute_vector(
        &self,
        c: &ComputeDef,
        env: &dyn Env,
        sys: &System,
    ) -> Result<Vec<f64>, String> {
        Ok(match &c.kind {
            ComputeKind::Reduce(r) if r.inputs.len() > 1 => r.values(env, sys)?,
            ComputeKind::Temp => sys.thermo().ke_tensor.to_vec(),
            ComputeKind::TempDeform => sys.thermo_deform().ke_tensor.to_vec(),
            ComputeKind::TempPartial(f) => sys.thermo_partial(*f).ke_tensor.to_vec(),
            ComputeKind::Pressure(t) => self.thermo_of_temp(t, sys)?.p_tensor.to_vec(),
            ComputeKind::Msd(m) => m.compute(sys)?.to_vec(),
            ComputeKind::Gyration => gyration_tensor(sys).to_vec(),
            ComputeKind::GyrationChunk { nchunk, .. } => gyration_by_molecule(sys, *nchunk),
            ComputeKind::SdpdDensity => {
                let d = sdpd_densities(c, sys)?;
                let n = d.len().max(1) as f64;
                let mean = d.iter().sum::<f64>() / n;
                let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
                vec![mean, var.sqrt() / mean]
            }
            k => {
                return Err(format!(
                    "compute {} '{}' does not calculate a global vector",
                    k.style(),
                    c.id
                ));
            }
        })
    }
}

impl Observe {
    /// The per-atom values of compute `id` (in the atoms' internal order), for `c_ID` in
    /// `dump custom` and `fix ave/chunk`.
    pub fn compute_per_atom(&self, id: &str, sys: &System) -> Result<Vec<f64>, String> {
        self.per_atom_column(id, None, sys)
    }

    /// Whether compute `id` exists and has per-atom values.
    pub fn has_per_atom(&self, id: &str) -> bool {
        self.compute(id).is_some_and(|c| c.kind.has_per_atom())
    }

    /// The per-atom values of compute `id`: Some(0) for one value per atom (`c_ID`), Some(n)
    /// for n columns (`c_ID[1]` … `c_ID[n]`), None without per-atom values.
    pub(super) fn per_atom_width(&self, id: &str) -> Option<usize> {
        self.compute(id)
            .filter(|c| c.kind.has_per_atom())
            .map(|c| c.kind.per_atom_width())
    }

    /// Column `col` (1-based; None: the per-atom vector) of compute `id`'s per-atom values.
    pub(crate) fn per_atom_column(
        &self,
        id: &str,
        col: Option<usize>,
        sys: &System,
    ) -> Result<Vec<f64>, String> {
        let c = self
            .compute(id)
            .ok_or_else(|| format!("compute '{id}' does not exist"))?;
        match (&c.kind, col) {
            (ComputeKind::SdpdDensity, None) => Ok(sdpd_densities(c, sys)?.to_vec()),
            (ComputeKind::StressAtom(s), Some(k @ 1..=6)) => {
                let st = sys
                    .stress_atom(s.parts_with(self.kinetic_bias(s.temp_id())?))
                    .map_err(|e| format!("compute stress/atom '{id}': {e}"))?;
                Ok(st.iter().map(|r| r[k - 1]).collect())
            }
            (k, _) if !k.has_per_atom() => Err(format!(
                "compute {} '{id}' does not calculate per-atom values",
                k.style()
            )),
            (_, None) => Err(format!(
                "compute '{id}' has per-atom columns: give c_{id}[k]"
            )),
            (_, Some(k)) => Err(format!("compute '{id}' has no per-atom column [{k}]")),
        }
    }
}

/// The densities of the last `pair_style sdpd` evaluation (one per atom, internal order).
fn sdpd_densities<'a>(c: &ComputeDef, sys: &'a System) -> Result<&'a [f64], String> {
    let density = sys
        .pair
        .as_deref()
        .and_then(|p| p.atom_values())
        .ok_or_else(|| {
            format!(
                "compute sdpd/density '{}': the pair style is no longer sdpd",
                c.id
            )
        })?;
    if density.len() != sys.atoms.len() {
        return Err(format!(
            "compute sdpd/density '{}': no densities yet (they are computed by a run's set-up)",
            c.id
        ));
    }
    Ok(density)
}

/// LAMMPS's `compute gyration` of group all: the mass-weighted tensor
/// Σ m (r − r_cm)_a (r − r_cm)_b / M of the unwrapped positions (by image flags), components
/// xx yy zz xy xz yz; R_g is the square root of its trace.
fn gyration_tensor(sys: &System) -> [f64; 6] {
    let cm = crate::engine::measure::center_of_mass(sys);
    let mut g = [0.0; 6];
    let mut mtot = 0.0;
    for i in 0..sys.atoms.len() {
        let m = crate::engine::measure::mass_of(sys, i);
        let u = crate::engine::measure::unwrapped(sys, i);
        let d = [u[0] - cm[0], u[1] - cm[1], u[2] - cm[2]];
        crate::engine::measure::add_outer(&mut g, m, d);
        mtot += m;
    }
    if mtot > 0.0 {
        for v in g.iter_mut() {
            *v /= mtot;
        }
    }
    g
}

/// LAMMPS's `compute gyration/chunk` over molecules 1 … `n`: per molecule, the mass-weighted
/// R_g of its atoms' unwrapped positions about its own centre of mass (0 for a molecule with
/// no mass).
fn gyration_by_molecule(sys: &System, n: usize) -> Vec<f64> {
    use crate::engine::measure::{mass_of, unwrapped};
    let a = &sys.atoms;
    let chunk = |i: usize| (a.mol_of(i) as usize).checked_sub(1).filter(|&c| c < n);
    let mut mass = vec![0.0; n];
    let mut cm = vec![[0.0; 3]; n];
    for i in 0..a.len() {
        if let Some(c) = chunk(i) {
            let (m, u) = (mass_of(sys, i), unwrapped(sys, i));
            mass[c] += m;
            for k in 0..3 {
                cm[c][k] += m * u[k];
            }
        }
    }
    for (c, m) in cm.iter_mut().zip(&mass) {
        if *m > 0.0 {
            for v in c.iter_mut() {
                *v /= m;
            }
        }
    }
    let mut rg = vec![0.0; n];
    for i in 0..a.len() {
        if let Some(c) = chunk(i) {
            let u = unwrapped(sys, i);
            let d = [u[0] - cm[c][0], u[1] - cm[c][1], u[2] - cm[c][2]];
            rg[c] += mass_of(sys, i) * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
    for (r, m) in rg.iter_mut().zip(&mass) {
        *r = if *m > 0.0 { (*r / m).sqrt() } else { 0.0 };
    }
    rg
}

impl Observe {
    /// Whether a `compute stress/atom` is defined: the force evaluations then tally the
    /// per-atom virial (`System::set_virial_atom`).
    pub fn wants_virial_atom(&self) -> bool {
        self.computes
            .iter()
            .any(|c| matches!(c.kind, ComputeKind::StressAtom(_)))
    }

    /// The velocity bias a `compute stress/atom` removes from its kinetic part: that of its
    /// temperature compute `temp` (none for `temp` and `NULL`, the unflagged components for
    /// `temp/partial`, the streaming velocity for `temp/deform`).
    fn kinetic_bias(&self, temp: Option<&str>) -> Result<crate::engine::KineticBias, String> {
        use crate::engine::KineticBias;
        let Some(t) = temp else {
            return Ok(KineticBias::None);
        };
        match self.compute(t).map(|c| &c.kind) {
            Some(ComputeKind::TempPartial(f)) => Ok(KineticBias::Partial(*f)),
            Some(ComputeKind::TempDeform) => Ok(KineticBias::Deform),
            Some(_) => Ok(KineticBias::None),
            None => Err(format!(
                "compute stress/atom: temperature compute '{t}' does not exist"
            )),
        }
    }
}
