//! The payload written field by field, little-endian (docs/restart.md).

use super::Restart;

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
pub(super) fn encode_payload(r: &Restart, buf: &mut Vec<u8>) {
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
    o.len(r.groups.len());
    r.groups.iter().for_each(|g| o.str(g));
    o.u64(r.atoms.mask.len() as u64);
    r.atoms.mask.iter().for_each(|&m| o.u32(m));
}
