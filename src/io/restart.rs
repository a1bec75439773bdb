//! The standalone engine's restart file (`write_restart`, `read_restart`, `restart N FILE`):
//! a versioned, checksummed binary image of everything a bit-identical continuation needs.
//! The layout is specified in `docs/restart.md`; this module is its only reader and writer.
//!
//! ```text
//! magic   8 bytes  "DPDNLRST"
//! version u32      FORMAT_VERSION
//! length  u64      payload bytes
//! payload          fields of Restart, in the order of `encode_payload`
//! check   u64      FNV-1a 64 of every byte before it (magic through payload)
//! ```
//!
//! Integers and IEEE doubles are little-endian; doubles are stored as their bits, so a value
//! reads back exactly (NaN payloads and −0.0 included). Strings are a u32 byte count and UTF-8.
//! FNV-1a changes its state bijectively with every byte, so a file differing from the written
//! one in any single byte never passes the check; a truncated file fails the length test first.

use crate::engine::topology::{Angle, AtomStyle, Bond, SpecialBonds};
use crate::engine::{Atoms, Energies, PairTally};
use std::fmt;
use std::io::Write;
use std::path::Path;

/// The first 8 bytes of every restart file.
pub const MAGIC: &[u8; 8] = b"DPDNLRST";

/// The format version this build writes; it reads this one and every older one (version 1:
/// no topology block, an `atomic` system; versions 1 and 2: no unit style, `units lj`).
pub const FORMAT_VERSION: u32 = 3;

/// Bytes before the payload: magic, version and payload length.
const HEADER: usize = 8 + 4 + 8;

/// LAMMPS's own restart files start with this (its `MAGIC_STRING`), so a mix-up gets a hint.
const LAMMPS_MAGIC: &[u8] = b"LammpS RestartT";

/// Everything a continuation needs (docs/restart.md: what `read_restart` restores, and what
/// the script re-issues).
#[derive(Clone, Debug, PartialEq)]
pub struct Restart {
    /// Dimension, 2 or 3.
    pub dim: u32,
    /// Number of atom types (≥ 1).
    pub ntypes: u32,
    /// Lower box corner.
    pub lo: [f64; 3],
    /// Upper box corner.
    pub hi: [f64; 3],
    /// The triclinic state (None: an orthogonal box).
    pub tilt: Option<Tilt>,
    /// Current step.
    pub step: u64,
    /// Time step.
    pub dt: f64,
    /// Neighbour skin (`neighbor SKIN`).
    pub skin: f64,
    /// Per-type masses, index 0 unused (length `ntypes + 1`).
    pub masses: Vec<Option<f64>>,
    /// The command lines that defined the pair style: `pair_style …` then every `pair_coeff …`
    /// since, each as its words (command word first, variables already substituted).
    pub pair: Vec<Vec<String>>,
    /// The fixes, in definition order.
    pub fixes: Vec<FixRecord>,
    /// The atoms in their storage order (the order the next neighbour-list sort starts from).
    pub atoms: Atoms,
    /// Energy and virial of the last force evaluation.
    pub tally: PairTally,
    /// The topology of a molecular system (version 2; None: `atom_style atomic`).
    pub topo: Option<TopoRecord>,
    /// The unit style (version 3; `lj` in older files).
    pub units: crate::units::UnitStyle,
}

/// The topology block (version 2): what `read_restart` needs to rebuild bonds, angles,
/// molecule ids, their styles and `special_bonds` exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct TopoRecord {
    /// The atom style.
    pub style: AtomStyle,
    /// Number of bond types.
    pub nbondtypes: u32,
    /// Number of angle types.
    pub nangletypes: u32,
    /// Bonds in topology order.
    pub bonds: Vec<Bond>,
    /// Angles in topology order.
    pub angles: Vec<Angle>,
    /// Molecule ids in the atoms' storage order.
    pub mol: Vec<u32>,
    /// `special_bonds`.
    pub special: SpecialBonds,
    /// The `bond_style`/`bond_coeff` and `angle_style`/`angle_coeff` lines (words, command
    /// first) that rebuild the styles.
    pub lines: Vec<Vec<String>>,
    /// The energies of the last force evaluation by kind.
    pub energies: Energies,
}

/// The tilt of a triclinic box and the sliding-brick state of its last force evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tilt {
    /// Tilt factor xy (unflipped).
    pub xy: f64,
    /// Shear rate of the last force evaluation.
    pub rate: f64,
    /// Sliding-brick offset of the last force evaluation (xy mod L_x).
    pub offset: f64,
}

/// One fix: the words of its `fix` command (ID, group, style, arguments) and its mutable
/// state (empty for fixes that have none).
#[derive(Clone, Debug, PartialEq)]
pub struct FixRecord {
    /// `fix` arguments as given (after substitution): `words[0]` is the ID, `words[2]` the style.
    pub words: Vec<String>,
    /// The fix's internal state (e.g. `pex/push`: the momentum moved so far).
    pub state: Vec<f64>,
}

impl FixRecord {
    /// The fix ID.
    pub fn id(&self) -> &str {
        self.words.first().map_or("", String::as_str)
    }

    /// The fix style.
    pub fn style(&self) -> &str {
        self.words.get(2).map_or("", String::as_str)
    }
}

/// Why a restart file was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum RestartError {
    /// The file could not be read or written.
    Io(String),
    /// Too short to hold the header, or shorter than the header says.
    Truncated {
        /// Bytes the header (or a minimal file) needs.
        expected: u64,
        /// Bytes present.
        found: u64,
    },
    /// Not a dpdnl restart file; `lammps` when it is LAMMPS's own format.
    WrongMagic {
        /// The file starts as a LAMMPS restart file does.
        lammps: bool,
    },
    /// Written by a newer dpdnl.
    NewerVersion(u32),
    /// Version 0 (never written).
    BadVersion(u32),
    /// The checksum does not match the contents.
    Checksum {
        /// Stored in the file.
        stored: u64,
        /// Computed from the contents.
        computed: u64,
    },
    /// The checksum matches, but a field is out of range (a writer bug or a crafted file).
    Malformed(String),
}

impl fmt::Display for RestartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RestartError::Io(e) => write!(f, "{e}"),
            RestartError::Truncated { expected, found } => write!(
                f,
                "truncated: {found} bytes, the header needs {expected} (an interrupted copy?)"
            ),
            RestartError::WrongMagic { lammps: true } => write!(
                f,
                "this is a LAMMPS restart file; the standalone engine reads only its own (dpdnl) \
                 restart files (convert with LAMMPS: read_restart, write_data; then read_data)"
            ),
            RestartError::WrongMagic { lammps: false } => write!(
                f,
                "not a dpdnl restart file (it does not start with \"DPDNLRST\")"
            ),
            RestartError::NewerVersion(v) => write!(
                f,
                "format version {v} is newer than this dpdnl reads (up to {FORMAT_VERSION}); \
                 use the dpdnl that wrote it"
            ),
            RestartError::BadVersion(v) => write!(f, "invalid format version {v}"),
            RestartError::Checksum { stored, computed } => write!(
                f,
                "corrupted: checksum mismatch (stored {stored:#018x}, contents give \
                 {computed:#018x})"
            ),
            RestartError::Malformed(what) => write!(f, "malformed contents: {what}"),
        }
    }
}

/// FNV-1a, 64-bit (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The whole file: header, payload and checksum.
pub fn encode(r: &Restart) -> Vec<u8> {
    let mut payload = Vec::with_capacity(256 + r.atoms.len() * 104);
    encode_payload(r, &mut payload);
    let mut out = Vec::with_capacity(HEADER + payload.len() + 8);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    let sum = fnv1a64(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// Check the header and checksum of `bytes` and decode the payload.
pub fn decode(bytes: &[u8]) -> Result<Restart, RestartError> {
    if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
        let lammps = bytes.starts_with(LAMMPS_MAGIC);
        if !lammps && MAGIC.starts_with(bytes) {
            return Err(RestartError::Truncated {
                expected: (HEADER + 8) as u64,
                found: bytes.len() as u64,
            });
        }
        return Err(RestartError::WrongMagic { lammps });
    }
    if bytes.len() < HEADER {
        return Err(RestartError::Truncated {
            expected: (HEADER + 8) as u64,
            found: bytes.len() as u64,
        });
    }
    let version = u32::from_le_bytes(array(&bytes[8..12]));
    if version > FORMAT_VERSION {
        return Err(RestartError::NewerVersion(version));
    }
    if version == 0 {
        return Err(RestartError::BadVersion(version));
    }
    let len = u64::from_le_bytes(array(&bytes[12..20]));
    let total = len
        .checked_add((HEADER + 8) as u64)
        .ok_or(RestartError::Truncated {
            expected: u64::MAX,
            found: bytes.len() as u64,
        })?;
    if (bytes.len() as u64) < total {
        return Err(RestartError::Truncated {
            expected: total,
            found: bytes.len() as u64,
        });
    }
    if (bytes.len() as u64) > total {
        return Err(RestartError::Malformed(format!(
            "{} bytes after the checksum (the header says the file has {total})",
            bytes.len() as u64 - total
        )));
    }
    let end = HEADER + len as usize;
    let stored = u64::from_le_bytes(array(&bytes[end..end + 8]));
    let computed = fnv1a64(&bytes[..end]);
    if stored != computed {
        return Err(RestartError::Checksum { stored, computed });
    }
    decode_payload(&bytes[HEADER..end], version).map_err(RestartError::Malformed)
}

/// Write `bytes` to `path` through a temporary file in the same directory, synced and then
/// renamed over `path`: a reader (or a kill at any moment) sees the old file or the new one,
/// never part of one.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path
        .file_name()
        .ok_or_else(|| format!("'{}' is not a file name", path.display()))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let written = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("cannot write restart file {}: {e}", path.display())
    })
}

/// Read and decode the restart file at `path`.
pub fn read(path: &Path) -> Result<Restart, RestartError> {
    let bytes = std::fs::read(path).map_err(|e| RestartError::Io(format!("cannot read: {e}")))?;
    decode(&bytes)
}

/// A restart file name with its `*` replaced by `step` (LAMMPS's rule for `restart` and
/// `write_restart`).
pub(crate) fn file_for_step(name: &str, step: u64) -> String {
    name.replace('*', &step.to_string())
}

fn array<const N: usize>(b: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    a.copy_from_slice(&b[..N]);
    a
}

// ---------------------------------------------------------------------------- payload

/// Little-endian writers of the payload's primitive types.
struct Out<'a>(&'a mut Vec<u8>);

impl Out<'_> {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn i32(&mut self, v: i32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    fn vec3(&mut self, v: &[f64; 3]) {
        v.iter().for_each(|&x| self.f64(x));
    }
    fn len(&mut self, n: usize) {
        self.u32(u32::try_from(n).unwrap_or(u32::MAX));
    }
    fn str(&mut self, s: &str) {
        self.len(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
    fn words(&mut self, w: &[String]) {
        self.len(w.len());
        w.iter().for_each(|s| self.str(s));
    }
}

/// The payload, field by field (docs/restart.md, "Payload, version 1").
fn encode_payload(r: &Restart, buf: &mut Vec<u8>) {
    let mut o = Out(buf);
    o.u32(r.dim);
    o.u32(r.ntypes);
    o.vec3(&r.lo);
    o.vec3(&r.hi);
    match &r.tilt {
        Some(t) => {
            o.u8(1);
            o.f64(t.xy);
            o.f64(t.rate);
            o.f64(t.offset);
        }
        None => o.u8(0),
    }
    o.u64(r.step);
    o.f64(r.dt);
    o.f64(r.skin);
    for t in 1..=r.ntypes as usize {
        let m = r.masses.get(t).copied().flatten();
        o.u8(u8::from(m.is_some()));
        o.f64(m.unwrap_or(0.0));
    }
    o.len(r.pair.len());
    r.pair.iter().for_each(|l| o.words(l));
    o.len(r.fixes.len());
    for f in &r.fixes {
        o.words(&f.words);
        o.len(f.state.len());
        f.state.iter().for_each(|&v| o.f64(v));
    }
    let a = &r.atoms;
    o.u64(a.len() as u64);
    a.tag.iter().for_each(|&t| o.u32(t));
    a.typ.iter().for_each(|&t| o.u32(t));
    a.x.iter().for_each(|v| o.vec3(v));
    a.v.iter().for_each(|v| o.vec3(v));
    a.f.iter().for_each(|v| o.vec3(v));
    a.image
        .iter()
        .for_each(|im| im.iter().for_each(|&k| o.i32(k)));
    o.f64(r.tally.energy);
    r.tally.virial.iter().for_each(|&w| o.f64(w));
    match &r.topo {
        None => o.u8(0),
        Some(t) => {
            o.u8(1);
            o.u8(t.style.code());
            o.u32(t.nbondtypes);
            o.u32(t.nangletypes);
            o.u64(t.bonds.len() as u64);
            for b in &t.bonds {
                o.u32(b.typ);
                b.atoms.iter().for_each(|&a| o.u32(a));
            }
            o.u64(t.angles.len() as u64);
            for a in &t.angles {
                o.u32(a.typ);
                a.atoms.iter().for_each(|&k| o.u32(k));
            }
            o.u64(t.mol.len() as u64);
            t.mol.iter().for_each(|&m| o.u32(m));
            t.special.lj.iter().for_each(|&f| o.f64(f));
            t.special.coul.iter().for_each(|&f| o.f64(f));
            o.u8(u8::from(t.special.angle));
            o.u8(u8::from(t.special.dihedral));
            o.len(t.lines.len());
            t.lines.iter().for_each(|l| o.words(l));
            o.f64(t.energies.epair);
            o.f64(t.energies.ebond);
            o.f64(t.energies.eangle);
        }
    }
    o.str(r.units.name());
}

/// The topology block of a version-2 payload.
fn decode_topo(i: &mut In, natoms: usize) -> Field<TopoRecord> {
    let code = i.u8("atom style")?;
    let style =
        AtomStyle::from_code(code).ok_or_else(|| format!("atom style code {code} (0..4)"))?;
    let nbondtypes = i.u32("bond types")?;
    let nangletypes = i.u32("angle types")?;
    let nb = i.u64("number of bonds")?;
    let nb = usize::try_from(nb).map_err(|_| format!("{nb} bonds"))?;
    i.check_room(nb, 12, "bonds")?;
    let mut bonds = Vec::with_capacity(nb);
    for _ in 0..nb {
        let typ = i.u32("bonds")?;
        let atoms = [i.u32("bonds")?, i.u32("bonds")?];
        if typ == 0 || typ > nbondtypes {
            return Err(format!("bond type {typ} (types are 1..{nbondtypes})"));
        }
        bonds.push(Bond { typ, atoms });
    }
    let na = i.u64("number of angles")?;
    let na = usize::try_from(na).map_err(|_| format!("{na} angles"))?;
    i.check_room(na, 16, "angles")?;
    let mut angles = Vec::with_capacity(na);
    for _ in 0..na {
        let typ = i.u32("angles")?;
        let atoms = [i.u32("angles")?, i.u32("angles")?, i.u32("angles")?];
        if typ == 0 || typ > nangletypes {
            return Err(format!("angle type {typ} (types are 1..{nangletypes})"));
        }
        angles.push(Angle { typ, atoms });
    }
    let nm = i.u64("molecule ids")?;
    if nm != natoms as u64 {
        return Err(format!("{nm} molecule ids for {natoms} atoms"));
    }
    i.check_room(natoms, 4, "molecule ids")?;
    let mol = many(i, natoms, |i| i.u32("molecule ids"))?;
    let mut special = SpecialBonds::default();
    for f in special.lj.iter_mut().chain(special.coul.iter_mut()) {
        *f = i.f64("special_bonds")?;
        if !(0.0..=1.0).contains(f) {
            return Err(format!("special_bonds factor {f} (must be in [0, 1])"));
        }
    }
    special.angle = i.u8("special_bonds")? == 1;
    special.dihedral = i.u8("special_bonds")? == 1;
    let nlines = i.count(4, "bond and angle style lines")?;
    let lines = (0..nlines)
        .map(|_| i.words("bond or angle style line"))
        .collect::<Field<Vec<_>>>()?;
    let energies = Energies {
        epair: i.f64("energies")?,
        ebond: i.f64("energies")?,
        eangle: i.f64("energies")?,
    };
    Ok(TopoRecord {
        style,
        nbondtypes,
        nangletypes,
        bonds,
        angles,
        mol,
        special,
        lines,
        energies,
    })
}

/// Little-endian readers with bounds checks: running past the end is an error naming the field.
struct In<'a> {
    buf: &'a [u8],
    pos: usize,
}

type Field<T> = Result<T, String>;

impl<'a> In<'a> {
    fn take(&mut self, n: usize, what: &str) -> Field<&'a [u8]> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| format!("the payload ends inside {what}"))?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u8(&mut self, what: &str) -> Field<u8> {
        Ok(self.take(1, what)?[0])
    }
    fn u32(&mut self, what: &str) -> Field<u32> {
        Ok(u32::from_le_bytes(array(self.take(4, what)?)))
    }
    fn i32(&mut self, what: &str) -> Field<i32> {
        Ok(i32::from_le_bytes(array(self.take(4, what)?)))
    }
    fn u64(&mut self, what: &str) -> Field<u64> {
        Ok(u64::from_le_bytes(array(self.take(8, what)?)))
    }
    fn f64(&mut self, what: &str) -> Field<f64> {
        Ok(f64::from_bits(self.u64(what)?))
    }
    fn vec3(&mut self, what: &str) -> Field<[f64; 3]> {
        Ok([self.f64(what)?, self.f64(what)?, self.f64(what)?])
    }
    /// A count of items of at least `item` bytes each, checked against the bytes left (so a
    /// bad count cannot ask for a huge allocation).
    fn count(&mut self, item: usize, what: &str) -> Field<usize> {
        let n = self.u32(what)? as usize;
        self.check_room(n, item, what)?;
        Ok(n)
    }
    fn check_room(&self, n: usize, item: usize, what: &str) -> Field<()> {
        if n.saturating_mul(item) > self.buf.len() - self.pos {
            return Err(format!("{what}: count {n} exceeds the payload"));
        }
        Ok(())
    }
    fn str(&mut self, what: &str) -> Field<String> {
        let n = self.count(1, what)?;
        let b = self.take(n, what)?;
        String::from_utf8(b.to_vec()).map_err(|_| format!("{what} is not UTF-8"))
    }
    fn words(&mut self, what: &str) -> Field<Vec<String>> {
        let n = self.count(4, what)?;
        (0..n).map(|_| self.str(what)).collect()
    }
}

fn decode_payload(buf: &[u8], version: u32) -> Field<Restart> {
    let mut i = In { buf, pos: 0 };
    let dim = i.u32("dimension")?;
    if dim != 2 && dim != 3 {
        return Err(format!("dimension {dim} (must be 2 or 3)"));
    }
    let ntypes = i.u32("number of atom types")?;
    if ntypes == 0 {
        return Err("0 atom types".into());
    }
    let lo = i.vec3("box bounds")?;
    let hi = i.vec3("box bounds")?;
    let tilt = match i.u8("triclinic flag")? {
        0 => None,
        1 => Some(Tilt {
            xy: i.f64("tilt")?,
            rate: i.f64("tilt")?,
            offset: i.f64("tilt")?,
        }),
        o => return Err(format!("triclinic flag {o} (must be 0 or 1)")),
    };
    let step = i.u64("step")?;
    let dt = i.f64("timestep")?;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(format!("timestep {dt} (must be > 0)"));
    }
    let skin = i.f64("skin")?;
    if !(skin.is_finite() && skin >= 0.0) {
        return Err(format!("skin {skin} (must be >= 0)"));
    }
    i.check_room(ntypes as usize, 9, "masses")?;
    let mut masses = vec![None];
    for t in 1..=ntypes {
        let set = i.u8("masses")?;
        let m = i.f64("masses")?;
        if set == 1 && !(m.is_finite() && m > 0.0) {
            return Err(format!("mass of type {t} is {m}"));
        }
        masses.push((set == 1).then_some(m));
    }
    let nlines = i.count(4, "pair style lines")?;
    let pair = (0..nlines)
        .map(|_| i.words("pair style line"))
        .collect::<Field<Vec<_>>>()?;
    let nfix = i.count(8, "fixes")?;
    let mut fixes = Vec::with_capacity(nfix);
    for _ in 0..nfix {
        let words = i.words("fix line")?;
        let n = i.count(8, "fix state")?;
        let state = (0..n).map(|_| i.f64("fix state")).collect::<Field<_>>()?;
        fixes.push(FixRecord { words, state });
    }
    let atoms = decode_atoms(&mut i, ntypes)?;
    let energy = i.f64("energy")?;
    let mut virial = [0.0; 6];
    for w in virial.iter_mut() {
        *w = i.f64("virial")?;
    }
    let topo = if version >= 2 {
        match i.u8("topology flag")? {
            0 => None,
            1 => Some(decode_topo(&mut i, atoms.len())?),
            o => return Err(format!("topology flag {o} (must be 0 or 1)")),
        }
    } else {
        None
    };
    let units = if version >= 3 {
        let name = i.str("unit style")?;
        crate::units::Units::standalone(&name)?.style
    } else {
        crate::units::UnitStyle::Lj
    };
    if i.pos != buf.len() {
        return Err(format!("{} bytes after the last field", buf.len() - i.pos));
    }
    Ok(Restart {
        dim,
        ntypes,
        lo,
        hi,
        tilt,
        step,
        dt,
        skin,
        masses,
        pair,
        fixes,
        atoms,
        tally: PairTally { energy, virial },
        topo,
        units,
    })
}

/// Bytes per atom in the payload: tag, type, x, v, f, image.
const ATOM_BYTES: usize = 4 + 4 + 3 * 24 + 12;

/// `n` values read by `f`.
fn many<'a, T>(
    i: &mut In<'a>,
    n: usize,
    mut f: impl FnMut(&mut In<'a>) -> Field<T>,
) -> Field<Vec<T>> {
    (0..n).map(|_| f(i)).collect()
}

fn decode_atoms(i: &mut In, ntypes: u32) -> Field<Atoms> {
    let n = i.u64("number of atoms")?;
    let n = usize::try_from(n).map_err(|_| format!("{n} atoms"))?;
    i.check_room(n, ATOM_BYTES, "atoms")?;
    let tag = many(i, n, |i| i.u32("atom ids"))?;
    let typ = many(i, n, |i| i.u32("atom types"))?;
    let x = many(i, n, |i| i.vec3("positions"))?;
    let v = many(i, n, |i| i.vec3("velocities"))?;
    let f = many(i, n, |i| i.vec3("forces"))?;
    let image = many(i, n, |i| {
        Ok([
            i.i32("image flags")?,
            i.i32("image flags")?,
            i.i32("image flags")?,
        ])
    })?;
    if let Some(k) = typ.iter().position(|&t| t == 0 || t > ntypes) {
        return Err(format!(
            "atom {} has type {} (types are 1..{ntypes})",
            tag[k], typ[k]
        ));
    }
    let mut sorted = tag.clone();
    sorted.sort_unstable();
    if sorted.first() == Some(&0) {
        return Err("an atom has id 0".into());
    }
    if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!("atom id {} appears twice", w[0]));
    }
    Ok(Atoms {
        x,
        v,
        f,
        tag,
        typ,
        image,
        mol: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Restart {
        let mut atoms = Atoms::default();
        atoms.push(3, 1, [0.5, -0.0, 1.25], [1e-300, 2.0, -3.0], [1, -2, 0]);
        atoms.push(1, 2, [4.0, 1.0, 0.1], [0.0, -1.0, 0.5], [0, 0, 7]);
        atoms.f[1] = [0.1, 0.2, 0.3];
        Restart {
            dim: 3,
            ntypes: 2,
            lo: [0.0; 3],
            hi: [5.0, 5.0, 5.0],
            tilt: Some(Tilt {
                xy: 1.5,
                rate: 0.2,
                offset: 1.5,
            }),
            step: 1234,
            dt: 0.01,
            skin: 0.3,
            masses: vec![None, Some(1.0), Some(2.5)],
            pair: vec![
                vec!["pair_style".into(), "dpd/nonlinear".into(), "1.0".into()],
                vec!["pair_coeff".into(), "*".into(), "*".into()],
            ],
            fixes: vec![FixRecord {
                words: vec!["p".into(), "all".into(), "pex/push".into(), "0.1".into()],
                state: vec![7.25],
            }],
            atoms,
            tally: PairTally {
                energy: -1.5,
                virial: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            },
            topo: Some(TopoRecord {
                style: AtomStyle::Angle,
                nbondtypes: 1,
                nangletypes: 2,
                bonds: vec![Bond {
                    typ: 1,
                    atoms: [3, 1],
                }],
                angles: vec![Angle {
                    typ: 2,
                    atoms: [3, 1, 3],
                }],
                mol: vec![7, 0],
                special: SpecialBonds {
                    lj: [1.0, 0.0, 0.5, 1.0],
                    coul: [1.0, 0.0, 0.0, 0.0],
                    angle: true,
                    dihedral: false,
                },
                lines: vec![vec!["bond_style".into(), "fene".into()]],
                energies: Energies {
                    epair: 1.0,
                    ebond: -2.0,
                    eangle: -0.5,
                },
            }),
            units: crate::units::UnitStyle::Real,
        }
    }

    /// `file` re-written as format `version` with its payload cut to `payload_len` bytes.
    fn as_version(file: &[u8], version: u32, payload_len: usize) -> Vec<u8> {
        let payload = &file[HEADER..HEADER + payload_len];
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&version.to_le_bytes());
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(payload);
        let sum = fnv1a64(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// A version-2 file (before the unit style): read as `units lj`.
    #[test]
    fn version_2_files_read_as_lj() {
        let mut r = sample();
        let v3 = encode(&r);
        // Version 2's payload is version 3's without the unit style string ("real": 4 + 4
        // bytes) at its end.
        let v2 = as_version(&v3, 2, v3.len() - HEADER - 8 - 8);
        r.units = crate::units::UnitStyle::Lj;
        assert_eq!(decode(&v2), Ok(r));
    }

    /// A version-1 file (before topology): no topology block, read as an atomic system.
    #[test]
    fn version_1_files_still_read() {
        let mut r = sample();
        r.topo = None;
        let v3 = encode(&r);
        // Version 1's payload is version 3's without the unit style string ("real": 8 bytes)
        // and the topology flag before it (1 byte).
        let v1 = as_version(&v3, 1, v3.len() - HEADER - 8 - 8 - 1);
        r.units = crate::units::UnitStyle::Lj;
        assert_eq!(decode(&v1), Ok(r));
    }

    #[test]
    fn round_trip_is_exact() {
        let r = sample();
        let back = decode(&encode(&r)).expect("decodes");
        assert_eq!(back.atoms.x[0][1].to_bits(), (-0.0f64).to_bits());
        assert_eq!(format!("{back:?}"), format!("{r:?}"));
        assert_eq!(back, r);
    }

    #[test]
    fn every_flipped_byte_and_every_truncation_is_refused() {
        let bytes = encode(&sample());
        for k in 0..bytes.len() {
            let mut b = bytes.clone();
            b[k] ^= 0x10;
            assert!(decode(&b).is_err(), "byte {k} flipped was accepted");
            assert!(
                decode(&bytes[..k]).is_err(),
                "truncated to {k} was accepted"
            );
        }
    }

    #[test]
    fn errors_say_what_is_wrong() {
        let bytes = encode(&sample());
        let mut b = bytes.clone();
        b[30] ^= 1;
        assert!(matches!(decode(&b), Err(RestartError::Checksum { .. })));
        let mut b = bytes.clone();
        b[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
        assert_eq!(
            decode(&b),
            Err(RestartError::NewerVersion(FORMAT_VERSION + 1))
        );
        assert_eq!(
            decode(b"LammpS RestartT\0\0\0\0\0\0\0\0\0\0"),
            Err(RestartError::WrongMagic { lammps: true })
        );
        assert_eq!(
            decode(b"hello world, not a restart file"),
            Err(RestartError::WrongMagic { lammps: false })
        );
        assert!(matches!(
            decode(&bytes[..bytes.len() - 1]),
            Err(RestartError::Truncated { .. })
        ));
        assert!(matches!(
            decode(&bytes[..3]),
            Err(RestartError::Truncated { .. })
        ));
    }

    #[test]
    fn fnv1a64_known_answers() {
        // Published FNV-1a 64 test vectors.
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn star_is_the_step() {
        assert_eq!(file_for_step("run.*.restart", 500), "run.500.restart");
        assert_eq!(file_for_step("plain.restart", 500), "plain.restart");
    }
}
