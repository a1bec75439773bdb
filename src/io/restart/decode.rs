//! The payload read back field by field, every read bounds-checked and every value range-checked,
//! for every format version.

use super::{FixRecord, Restart, Tilt, TopoRecord};
use crate::engine::topology::{Angle, AtomStyle, Bond, SpecialBonds};
use crate::engine::{Atoms, Energies, PairTally};

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

pub(super) fn decode_payload(buf: &[u8], version: u32) -> Field<Restart> {
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
    let (groups, mask) = if version >= 4 {
        decode_groups(&mut i, atoms.len())?
    } else {
        (vec!["all".to_string()], Vec::new())
    };
    let mut atoms = atoms;
    atoms.mask = mask;
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
        groups,
    })
}

/// The groups block of a version-4 payload: the names by bit (`all` first, at most 32) and the
/// masks (none, or one per atom with bit 0 set and no bit of a free slot).
fn decode_groups(i: &mut In, natoms: usize) -> Field<(Vec<String>, Vec<u32>)> {
    let n = i.count(4, "group names")?;
    let names = (0..n)
        .map(|_| i.str("group name"))
        .collect::<Field<Vec<_>>>()?;
    crate::engine::groups::Groups::from_names(names.clone())?;
    let nmask = i.u64("number of group masks")?;
    if nmask != 0 && nmask != natoms as u64 {
        return Err(format!("{nmask} group masks for {natoms} atoms"));
    }
    i.check_room(nmask as usize, 4, "group masks")?;
    let mask = many(i, nmask as usize, |i| i.u32("group masks"))?;
    let defined: u32 = names
        .iter()
        .enumerate()
        .filter(|(_, n)| !n.is_empty())
        .map(|(b, _)| 1u32 << b)
        .sum();
    if let Some(m) = mask.iter().find(|&&m| m & 1 == 0 || m & !defined != 0) {
        return Err(format!(
            "group mask {m:#x}: not in 'all' or a bit of no group"
        ));
    }
    Ok((names, mask))
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
        mask: Vec::new(),
        vest: Vec::new(),
    })
}

pub(super) fn array<const N: usize>(b: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    a.copy_from_slice(&b[..N]);
    a
}
