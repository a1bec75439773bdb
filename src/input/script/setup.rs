//! The box and the atoms: `units`, `dimension`, `boundary`, `atom_style`, `region`,
//! `create_box`, `create_atoms`, `mass`, `neighbor`, `timestep`, `change_box`,
//! `reset_timestep` (`read_data` and `write_data`: `data`).

use super::{CmdResult, Interpreter, type_range};
use crate::engine::lees_edwards::Triclinic;
use crate::engine::{SimBox, System};
use crate::grammar::{at_most, need, parse_f64, parse_int};
use crate::io::data::AtomColumns;
use crate::rng::{STREAM_CREATE_ATOMS, keyed_uniform};

impl Interpreter<'_> {
    /// `units lj|real|metal|si|cgs|micro|nano`: LAMMPS's constants ([`crate::units::Units::standalone`]), and
    /// LAMMPS's default time step and neighbour skin of the style (as `Update::set_units`
    /// resets them). Before the box only, as in LAMMPS.
    pub(super) fn cmd_units(&mut self, args: &[String]) -> CmdResult {
        exact(args, 1, "units lj|real|metal|si|cgs|micro|nano")?;
        if self.sys.is_some() {
            return Err("Units command after simulation box is defined".into());
        }
        let u = crate::units::Units::standalone(&args[0])?;
        self.units = u;
        self.dt = u.default_dt();
        self.skin = u.default_skin();
        Ok(())
    }

    pub(super) fn cmd_dimension(&mut self, args: &[String]) -> CmdResult {
        exact(args, 1, "dimension 2|3")?;
        if self.sys.is_some() {
            return Err("dimension must be set before the box is created".into());
        }
        self.dim = match args[0].as_str() {
            "2" => 2,
            "3" => 3,
            o => return Err(format!("dimension '{o}' must be 2 or 3")),
        };
        Ok(())
    }

    pub(super) fn cmd_boundary(args: &[String]) -> CmdResult {
        exact(args, 3, "boundary p p p")?;
        if args.iter().take(3).any(|a| a != "p") {
            return Err(format!(
                "boundary '{}': only fully periodic boxes ('p p p') are supported",
                args.join(" ")
            ));
        }
        Ok(())
    }

    pub(super) fn cmd_atom_style(&mut self, args: &[String]) -> CmdResult {
        need(
            args,
            1,
            "atom_style atomic|bond|angle|molecular|full|charge|mdpd|hybrid …",
        )?;
        // The style words first (`hybrid` takes sub-styles), then the box.
        let columns = AtomColumns::parse(args)?;
        if columns.per_atom_mass() {
            return Err(format!(
                "atom_style {}: per-atom masses (sphere's diameter and density) are not \
                 supported: this engine has per-type masses only (the DPD styles use no radius); \
                 use atom_style atomic (or charge, mdpd, bond, …) with `mass`",
                columns.words.join(" ")
            ));
        }
        if self.sys.is_some() {
            return Err("atom_style command after simulation box is defined".into());
        }
        self.atom_style = columns.base;
        self.atom_columns = columns;
        Ok(())
    }

    pub(super) fn cmd_region(&mut self, args: &[String]) -> CmdResult {
        let usage = "region ID block xlo xhi ylo yhi zlo zhi [units box|lattice] | region ID prism xlo xhi ylo yhi zlo zhi xy xz yz [units box|lattice]";
        // The style word first: a style this engine lacks is named as such, whatever its
        // arguments.
        need(args, 2, usage)?;
        if !matches!(args[1].as_str(), "block" | "prism") {
            return Err(format!(
                "region style '{}' not supported: only 'block' and 'prism' (a script that \
                 builds its system with other shapes runs in LAMMPS; its `write_data` after the \
                 set-up gives a data file this engine reads)",
                args[1]
            ));
        }
        need(args, 8, usage)?;
        let prism = match args[1].as_str() {
            "block" => None,
            "prism" => {
                need(args, 11, usage)?;
                let mut t = [0.0; 3];
                for (k, name) in ["xy", "xz", "yz"].iter().enumerate() {
                    t[k] = parse_f64(&args[8 + k], name)?;
                }
                if t[1] != 0.0 || t[2] != 0.0 {
                    return Err(format!(
                        "region prism: tilt xz '{}' yz '{}' not supported: only xy (Lees–Edwards Couette flow)",
                        args[9], args[10]
                    ));
                }
                Some(t)
            }
            o => {
                return Err(format!(
                    "region style '{o}' not supported: only 'block' and 'prism'"
                ));
            }
        };
        let mut k = if prism.is_some() { 11 } else { 8 };
        while k < args.len() {
            need(&args[k..], 2, usage)?;
            match (args[k].as_str(), args[k + 1].as_str()) {
                ("units", "box") | ("units", "lattice") => {}
                ("side", "in") => {}
                (a, b) => return Err(format!("unsupported region keyword '{a} {b}'")),
            }
            k += 2;
        }
        let mut b = [[0.0; 2]; 3];
        for d in 0..3 {
            for s in 0..2 {
                let tok = &args[2 + 2 * d + s];
                b[d][s] = match tok.as_str() {
                    "INF" | "EDGE" => {
                        let sys = self
                            .sys
                            .as_ref()
                            .ok_or_else(|| format!("'{tok}' in a region needs an existing box"))?;
                        if s == 0 { sys.bx.lo[d] } else { sys.bx.hi[d] }
                    }
                    _ => parse_f64(tok, "region bound")?,
                };
            }
            if b[d][0] >= b[d][1] {
                return Err(format!(
                    "region {} bounds in {}: lo {} >= hi {}",
                    args[0],
                    ["x", "y", "z"][d],
                    b[d][0],
                    b[d][1]
                ));
            }
        }
        self.regions.insert(args[0].clone(), b);
        // What an atom is matched against (`group region`, a fix's `region`): INF is
        // unbounded there, as LAMMPS's ±BIG (an atom not yet wrapped back into the box stays
        // inside), EDGE the box face.
        let mut m = b;
        for d in 0..3 {
            for s in 0..2 {
                if args[2 + 2 * d + s] == "INF" {
                    m[d][s] = if s == 0 {
                        f64::NEG_INFINITY
                    } else {
                        f64::INFINITY
                    };
                }
            }
        }
        self.region_match.insert(args[0].clone(), m);
        match prism {
            Some(t) => {
                self.prisms.insert(args[0].clone(), t);
            }
            None => {
                self.prisms.remove(&args[0]);
            }
        }
        Ok(())
    }

    /// The bounds atoms are matched against in region `id` (INF unbounded).
    pub(super) fn region_for_atoms(&self, id: &str) -> Result<[[f64; 2]; 3], String> {
        self.region_match
            .get(id)
            .copied()
            .ok_or_else(|| format!("no region with ID '{id}'"))
    }

    pub(super) fn region(&self, id: &str) -> Result<[[f64; 2]; 3], String> {
        self.regions
            .get(id)
            .copied()
            .ok_or_else(|| format!("no region with ID '{id}'"))
    }

    pub(super) fn new_system(&mut self, ntypes: usize, lo: [f64; 3], hi: [f64; 3]) -> CmdResult {
        if self.sys.is_some() {
            return Err("a simulation box already exists".into());
        }
        crate::engine::check_ntypes(ntypes)?;
        let bx = SimBox::new(self.dim, lo, hi)?;
        let mut sys = System::new(bx, ntypes);
        sys.dt = self.dt;
        sys.units = self.units;
        sys.neighbor = crate::engine::NeighborList::new(self.skin);
        sys.comm_cutoff = self.comm_cutoff;
        if self.atom_style.molecular() {
            sys.topo = Some(self.pre_topo.topology(self.atom_style, 0, 0)?);
        }
        // A `pair_style` given before the box: made now, for the box's atom types.
        if let Some(words) = &self.pre_pair {
            sys.pair = Some(crate::forces::new_pair_style(
                &words[0],
                &words[1..],
                ntypes,
                self.dt,
            )?);
        }
        self.sys = Some(sys);
        Ok(())
    }

    pub(super) fn cmd_create_box(&mut self, args: &[String]) -> CmdResult {
        exact(args, 2, "create_box NTYPES REGION-ID")?;
        let ntypes: usize = parse_int(&args[0], "number of atom types")?;
        let r = self.region(&args[1])?;
        self.new_system(
            ntypes,
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
        )?;
        let d = self.dim;
        if let Some(t) = self.prisms.get(&args[1]).copied() {
            let sys = self.sys_mut()?;
            sys.tri = Some(Triclinic::new(t[0]));
            self.out(&format!(
                "Created triclinic box = ({} {} {}) to ({} {} {}) with tilt ({} {} {}) in {d}-D",
                r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], t[0], t[1], t[2]
            ));
            return Ok(());
        }
        self.out(&format!(
            "Created orthogonal box = ({} {} {}) to ({} {} {}) in {d}-D",
            r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1]
        ));
        Ok(())
    }

    pub(super) fn cmd_create_atoms(&mut self, args: &[String]) -> CmdResult {
        let usage = "create_atoms TYPE random N SEED REGION-ID | create_atoms TYPE single X Y Z";
        need(args, 2, usage)?;
        let dim = self.dim;
        let regions = self.regions.clone();
        let max_atoms = self.max_atoms;
        let sys = self.sys_mut()?;
        let t: u32 = parse_int(&args[0], "atom type")?;
        if t == 0 || t as usize > sys.ntypes {
            return Err(format!("atom type {t} out of range 1..{}", sys.ntypes));
        }
        let mut next = sys.atoms.max_tag();
        let mut created = 0usize;
        match args[1].as_str() {
            "random" => {
                need(args, 5, usage)?;
                if args.len() > 5 {
                    return Err(format!(
                        "create_atoms random keyword '{}' not supported",
                        args[5]
                    ));
                }
                let n: usize = parse_int(&args[2], "number of atoms")?;
                if let Some(cap) = max_atoms.filter(|&cap| n > cap.saturating_sub(sys.atoms.len()))
                {
                    return Err(format!(
                        "{n} more atoms beside {} exceed the cap of {cap} (Options::max_atoms)",
                        sys.atoms.len()
                    ));
                }
                memory_guard(n, sys.atoms.len())?;
                sys.atoms
                    .try_reserve(n)
                    .map_err(|e| format!("cannot allocate {n} atoms: {e}"))?;
                let seed: u32 = parse_int(&args[3], "seed")?;
                if seed == 0 {
                    return Err("seed must be > 0".into());
                }
                let r = if args[4] == "NULL" {
                    [
                        [sys.bx.lo[0], sys.bx.hi[0]],
                        [sys.bx.lo[1], sys.bx.hi[1]],
                        [sys.bx.lo[2], sys.bx.hi[2]],
                    ]
                } else {
                    *regions
                        .get(&args[4])
                        .ok_or_else(|| format!("no region with ID '{}'", args[4]))?
                };
                let mut lo = [0.0; 3];
                let mut hi = [0.0; 3];
                for d in 0..3 {
                    lo[d] = r[d][0].max(sys.bx.lo[d]);
                    hi[d] = r[d][1].min(sys.bx.hi[d]);
                    if lo[d] >= hi[d] {
                        return Err(format!("region {} does not overlap the box", args[4]));
                    }
                }
                for _ in 0..n {
                    next = next
                        .checked_add(1)
                        .ok_or("atom ids would exceed 2^32 - 1")?;
                    let mut x = [0.0; 3];
                    for d in 0..dim {
                        let u = keyed_uniform(seed, STREAM_CREATE_ATOMS, 0, next, d as u32);
                        x[d] = lo[d] + u * (hi[d] - lo[d]);
                    }
                    sys.atoms.push(next, t, x, [0.0; 3], [0; 3]);
                    created += 1;
                }
            }
            "single" => {
                exact(args, 5, usage)?;
                let mut x = [0.0; 3];
                for d in 0..3 {
                    x[d] = parse_f64(&args[2 + d], "coordinate")?;
                }
                if dim == 2 {
                    x[2] = 0.0;
                }
                // As LAMMPS (`remap no`): a point outside the box creates no atom.
                let inside = (0..dim).all(|d| x[d] >= sys.bx.lo[d] && x[d] < sys.bx.hi[d]);
                if inside {
                    next = next
                        .checked_add(1)
                        .ok_or("atom ids would exceed 2^32 - 1")?;
                    sys.atoms.push(next, t, x, [0.0; 3], [0; 3]);
                    created = 1;
                }
            }
            o => {
                return Err(format!(
                    "create_atoms style '{o}' not supported (random, single)"
                ));
            }
        }
        self.out(&format!("Created {created} atoms"));
        Ok(())
    }

    pub(super) fn cmd_mass(&mut self, args: &[String]) -> CmdResult {
        exact(args, 2, "mass TYPE(S) VALUE")?;
        let m = parse_f64(&args[1], "mass")?;
        if m <= 0.0 {
            return Err(format!("mass {m} must be > 0"));
        }
        let sys = self.sys_mut()?;
        let (lo, hi) = type_range(&args[0], sys.ntypes)?;
        for t in lo..=hi {
            sys.mass[t] = Some(m);
        }
        Ok(())
    }

    /// `comm_modify KEYWORD VALUE …`: only `cutoff Rcut` (LAMMPS's user ghost cut-off) matters
    /// here, to the check of the bonded atoms' images at a run's set-up
    /// (`System::check_bonded_images`); the other keywords (`vel`, `mode`, …) only matter to
    /// LAMMPS and are accepted as before.
    pub(super) fn cmd_comm_modify(&mut self, args: &[String]) -> CmdResult {
        let mut k = 0;
        while k < args.len() {
            if args[k] == "cutoff" {
                let v = args.get(k + 1).ok_or("comm_modify cutoff needs a value")?;
                let c = parse_f64(v, "comm_modify cutoff")?;
                if !(c >= 0.0 && c.is_finite()) {
                    return Err(format!("Invalid cutoff {c} in comm_modify command"));
                }
                self.comm_cutoff = c;
                if let Some(s) = self.sys.as_mut() {
                    s.comm_cutoff = c;
                }
                k += 1;
            }
            k += 1;
        }
        Ok(())
    }

    pub(super) fn cmd_neighbor(&mut self, args: &[String]) -> CmdResult {
        exact(args, 2, "neighbor SKIN bin")?;
        let skin = parse_f64(&args[0], "skin")?;
        if skin < 0.0 {
            return Err(format!("skin {skin} must be >= 0"));
        }
        if !["bin", "nsq", "multi"].contains(&args[1].as_str()) {
            return Err(format!("unknown neighbor style '{}'", args[1]));
        }
        self.skin = skin;
        if let Some(s) = self.sys.as_mut() {
            s.neighbor = crate::engine::NeighborList::new(skin);
        }
        Ok(())
    }

    pub(super) fn cmd_timestep(&mut self, args: &[String]) -> CmdResult {
        exact(args, 1, "timestep DT")?;
        let dt = parse_f64(&args[0], "timestep")?;
        if dt <= 0.0 {
            return Err(format!("timestep {dt} must be > 0"));
        }
        self.dt = dt;
        if let Some(s) = self.sys.as_mut() {
            s.dt = dt;
        }
        Ok(())
    }

    pub(super) fn cmd_change_box(&mut self, args: &[String]) -> CmdResult {
        need(args, 2, "change_box all triclinic")?;
        if args[0] != "all" {
            return Err(format!("group '{}' not supported: only 'all'", args[0]));
        }
        if let Some(o) = args[1..].iter().find(|a| *a != "triclinic") {
            return Err(format!(
                "change_box keyword '{o}' not supported: only 'change_box all triclinic'"
            ));
        }
        let sys = self.sys_mut()?;
        if sys.tri.is_none() {
            sys.tri = Some(Triclinic::new(0.0));
        }
        Ok(())
    }

    pub(super) fn cmd_reset_timestep(&mut self, args: &[String]) -> CmdResult {
        exact(args, 1, "reset_timestep N")?;
        let n: u64 = parse_int(&args[0], "timestep")?;
        self.sys_mut()?.step = n;
        Ok(())
    }
}

/// Bytes per atom the engine needs at least (atom data measured 95–148 B/atom, BENCHMARKS.md;
/// the neighbour structures come on top).
const MIN_BYTES_PER_ATOM: u64 = 150;

/// Refuse to create `n` more atoms (beside `have`) when even their atom data would not fit in
/// the memory this machine has available (`MemAvailable` of /proc/meminfo; no check where that
/// cannot be read), with the estimate and the available memory in the message.
fn memory_guard(n: usize, have: usize) -> CmdResult {
    let need = (n as u64 + have as u64).saturating_mul(MIN_BYTES_PER_ATOM);
    let Some(avail) = available_memory() else {
        return Ok(());
    };
    if need > avail {
        return Err(format!(
            "{} atoms need at least {:.1} GB ({MIN_BYTES_PER_ATOM} B/atom of atom data, before \
             neighbour lists) but this machine has {:.1} GB available",
            n as u64 + have as u64,
            need as f64 / 1e9,
            avail as f64 / 1e9
        ));
    }
    Ok(())
}

/// `MemAvailable` from /proc/meminfo, in bytes.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// Exactly `n` words: missing ones and trailing ones are errors (LAMMPS's "Illegal … command").
fn exact(args: &[String], n: usize, usage: &str) -> CmdResult {
    need(args, n, usage)?;
    at_most(args, n, usage)
}
