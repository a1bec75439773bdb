//! Frame files of `fix ID all dpdnl/frames N FILE` (LAMMPS side) read by `dpdnl verify`: at
//! every N-th step, the state a dpdnl pair style's force saw (positions and the velocities it
//! used, ids, types, masses, step, box) and that style's own share of the force per atom.
//!
//! Format, version 1 (every number little-endian; `docs/manual/verify.md`):
//!
//! ```text
//! file   = "DPDNLFRM" u32 version u32 0, then frames
//! frame  = "FRAM" u32 0, u64 body length L, body (L bytes), u64 FNV-1a 64 of the body
//! body   = u64 step, u64 n, u32 dimension, u32 flags, u32 ntypes,
//!          f64 boxlo[3], boxhi[3], tilt[3] (xy xz yz), dt,
//!          u64 beginstep, u64 endstep, f64 special_lj[4],
//!          u32 length + bytes: the pair style's name,
//!          u32 length + bytes: the style's settings (its restart lines),
//!          u32 tag[n], u32 type[n], f64 mass[n], f64 x[3n], f64 v[3n], f64 f[3n]
//! flags  = bit 0 triclinic, bits 1-3 periodic in x, y, z, bit 4 fix nve/euler,
//!          bit 5 molecular (atom->molecular)
//! ```
//!
//! The checksum is the restart files' ([`crate::io::restart::fnv1a64`]). A frame whose bytes end
//! early (a run killed while writing) is reported as truncated, naming the frame.

use crate::io::restart::fnv1a64;
use std::io::{Read, Write};

/// The first 8 bytes of a frame file.
pub const MAGIC: &[u8; 8] = b"DPDNLFRM";
/// The format version this build writes and reads.
pub const VERSION: u32 = 1;
const FRAME_TAG: &[u8; 4] = b"FRAM";

/// Flag bits of a frame (see the module's format).
pub mod flags {
    /// The box is triclinic (tilt factors apply).
    pub const TRICLINIC: u32 = 1;
    /// Periodic in x; `PERIODIC_X << d` for axis d.
    pub const PERIODIC_X: u32 = 2;
    /// The run integrates with `fix nve/euler`.
    pub const EULER: u32 = 16;
    /// The atom style is molecular (bonded neighbours may be scaled by `special_bonds`).
    pub const MOLECULAR: u32 = 32;
}

/// What one frame says of the run at its step, besides the per-atom arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameHead {
    /// The step whose force this is (the step that keys the pair noise).
    pub step: u64,
    /// 2 or 3.
    pub dimension: u32,
    /// [`flags`].
    pub flags: u32,
    /// Number of atom types of the run.
    pub ntypes: u32,
    /// Lower corner of the box.
    pub boxlo: [f64; 3],
    /// Upper corner of the box.
    pub boxhi: [f64; 3],
    /// Tilt factors xy, xz, yz (0 for an orthogonal box).
    pub tilt: [f64; 3],
    /// Time step.
    pub dt: f64,
    /// First and last step of the run (LAMMPS's `beginstep`, `endstep`: a temperature ramp).
    pub beginstep: u64,
    /// See `beginstep`.
    pub endstep: u64,
    /// `special_bonds lj` factors in force.
    pub special_lj: [f64; 4],
    /// The pair style's name (`dpd/nonlinear`, …).
    pub style: String,
    /// The style's settings and coefficients as its restart lines.
    pub settings: String,
}

impl FrameHead {
    /// True when axis `d` is periodic.
    pub fn periodic(&self, d: usize) -> bool {
        self.flags & (flags::PERIODIC_X << d) != 0
    }
}

/// Per-atom arrays of a frame, borrowed (what a writer takes).
#[derive(Clone, Copy, Debug)]
pub struct FrameAtoms<'a> {
    /// Atom ids.
    pub tag: &'a [u32],
    /// Atom types (1-based).
    pub typ: &'a [u32],
    /// Masses.
    pub mass: &'a [f64],
    /// Positions the force saw.
    pub x: &'a [[f64; 3]],
    /// Velocities the force used.
    pub v: &'a [[f64; 3]],
    /// The style's own force on each atom (ghost contributions summed).
    pub f: &'a [[f64; 3]],
}

/// One frame, owned (what a reader gives).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// Everything but the per-atom arrays.
    pub head: FrameHead,
    /// Atom ids.
    pub tag: Vec<u32>,
    /// Atom types.
    pub typ: Vec<u32>,
    /// Masses.
    pub mass: Vec<f64>,
    /// Positions.
    pub x: Vec<[f64; 3]>,
    /// Velocities.
    pub v: Vec<[f64; 3]>,
    /// The style's force.
    pub f: Vec<[f64; 3]>,
}

impl Frame {
    /// The per-atom arrays, borrowed.
    pub fn atoms(&self) -> FrameAtoms<'_> {
        FrameAtoms {
            tag: &self.tag,
            typ: &self.typ,
            mass: &self.mass,
            x: &self.x,
            v: &self.v,
            f: &self.f,
        }
    }
}

/// The file header (magic, version, reserved word).
pub fn file_header() -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out
}

/// One frame's bytes: tag, length, body and checksum. `Err` when the arrays' lengths differ.
pub fn encode_frame(head: &FrameHead, a: FrameAtoms<'_>) -> Result<Vec<u8>, String> {
    let n = a.tag.len();
    if [a.typ.len(), a.mass.len(), a.x.len(), a.v.len(), a.f.len()]
        .iter()
        .any(|&m| m != n)
    {
        return Err("frame arrays of different lengths".into());
    }
    let mut b = Vec::with_capacity(200 + head.style.len() + head.settings.len() + n * 88);
    b.extend_from_slice(&head.step.to_le_bytes());
    b.extend_from_slice(&(n as u64).to_le_bytes());
    b.extend_from_slice(&head.dimension.to_le_bytes());
    b.extend_from_slice(&head.flags.to_le_bytes());
    b.extend_from_slice(&head.ntypes.to_le_bytes());
    let scalars = head.boxlo.iter().chain(&head.boxhi).chain(&head.tilt);
    for v in scalars.chain(std::iter::once(&head.dt)) {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&head.beginstep.to_le_bytes());
    b.extend_from_slice(&head.endstep.to_le_bytes());
    for v in &head.special_lj {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for s in [&head.style, &head.settings] {
        b.extend_from_slice(&(s.len() as u32).to_le_bytes());
        b.extend_from_slice(s.as_bytes());
    }
    for &t in a.tag.iter().chain(a.typ) {
        b.extend_from_slice(&t.to_le_bytes());
    }
    for &m in a.mass {
        b.extend_from_slice(&m.to_le_bytes());
    }
    for rows in [a.x, a.v, a.f] {
        for r in rows {
            for c in r {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let mut out = Vec::with_capacity(b.len() + 24);
    out.extend_from_slice(FRAME_TAG);
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(b.len() as u64).to_le_bytes());
    out.extend_from_slice(&b);
    out.extend_from_slice(&fnv1a64(&b).to_le_bytes());
    Ok(out)
}

/// A frame file being written: the header at creation, each frame flushed whole.
pub struct FrameWriter {
    file: std::io::BufWriter<std::fs::File>,
    path: String,
}

impl FrameWriter {
    /// Create (truncate) `path` and write the file header.
    pub fn create(path: &str) -> Result<FrameWriter, String> {
        let f = std::fs::File::create(path).map_err(|e| format!("cannot create {path}: {e}"))?;
        let mut w = FrameWriter {
            file: std::io::BufWriter::with_capacity(1 << 20, f),
            path: path.to_string(),
        };
        w.put(&file_header())?;
        Ok(w)
    }

    fn put(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.file
            .write_all(bytes)
            .and_then(|_| self.file.flush())
            .map_err(|e| format!("cannot write {}: {e}", self.path))
    }

    /// Append one frame.
    pub fn write(&mut self, head: &FrameHead, a: FrameAtoms<'_>) -> Result<(), String> {
        let bytes = encode_frame(head, a)?;
        self.put(&bytes)
    }
}

/// A cursor over a body's bytes.
struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        let end = end.ok_or("the frame's body is shorter than its arrays")?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().unwrap_or([0; 4]),
        ))
    }
    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().unwrap_or([0; 8]),
        ))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn text(&mut self) -> Result<String, String> {
        let n = self.u32()? as usize;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| "a name is not UTF-8".to_string())
    }
    fn u32s(&mut self, n: usize) -> Result<Vec<u32>, String> {
        let raw = self.take(n.checked_mul(4).ok_or("atom count too large")?)?;
        Ok(raw
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }
    fn f64s(&mut self, n: usize) -> Result<Vec<f64>, String> {
        let raw = self.take(n.checked_mul(8).ok_or("atom count too large")?)?;
        Ok(raw
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect())
    }
    fn rows(&mut self, n: usize) -> Result<Vec<[f64; 3]>, String> {
        let flat = self.f64s(n.checked_mul(3).ok_or("atom count too large")?)?;
        Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    }
}

/// Decode a frame's body (checksum already checked).
pub fn decode_body(body: &[u8]) -> Result<Frame, String> {
    let mut c = Cursor { b: body, at: 0 };
    let mut h = FrameHead {
        step: c.u64()?,
        ..Default::default()
    };
    let n = usize::try_from(c.u64()?).map_err(|_| "atom count too large")?;
    h.dimension = c.u32()?;
    h.flags = c.u32()?;
    h.ntypes = c.u32()?;
    for v in h.boxlo.iter_mut().chain(&mut h.boxhi).chain(&mut h.tilt) {
        *v = c.f64()?;
    }
    h.dt = c.f64()?;
    h.beginstep = c.u64()?;
    h.endstep = c.u64()?;
    for v in &mut h.special_lj {
        *v = c.f64()?;
    }
    h.style = c.text()?;
    h.settings = c.text()?;
    let frame = Frame {
        head: h,
        tag: c.u32s(n)?,
        typ: c.u32s(n)?,
        mass: c.f64s(n)?,
        x: c.rows(n)?,
        v: c.rows(n)?,
        f: c.rows(n)?,
    };
    if c.at != body.len() {
        return Err(format!(
            "{} bytes after the frame's arrays",
            body.len() - c.at
        ));
    }
    Ok(frame)
}

/// Reads the frames of one file in order.
pub struct FrameReader<R: Read> {
    src: R,
    name: String,
    index: usize,
}

impl FrameReader<std::io::BufReader<std::fs::File>> {
    /// Open `path` and check its header.
    pub fn open(path: &std::path::Path) -> Result<Self, String> {
        let name = path.display().to_string();
        let f = std::fs::File::open(path).map_err(|e| format!("cannot open {name}: {e}"))?;
        FrameReader::new(std::io::BufReader::with_capacity(1 << 20, f), &name)
    }
}

impl<R: Read> FrameReader<R> {
    /// A reader over `src` (named `name` in messages); reads and checks the file header.
    pub fn new(mut src: R, name: &str) -> Result<Self, String> {
        let mut head = [0u8; 16];
        src.read_exact(&mut head)
            .map_err(|_| format!("{name}: too short for a frame file (no header)"))?;
        if &head[..8] != MAGIC {
            return Err(format!(
                "{name}: not a dpdnl frame file (written by fix dpdnl/frames; its first bytes \
                 are DPDNLFRM)"
            ));
        }
        let version = u32::from_le_bytes([head[8], head[9], head[10], head[11]]);
        if version != VERSION {
            return Err(format!(
                "{name}: frame format version {version}; this build reads version {VERSION}"
            ));
        }
        Ok(FrameReader {
            src,
            name: name.to_string(),
            index: 0,
        })
    }

    /// The next frame, `Ok(None)` at the end of the file.
    pub fn next_frame(&mut self) -> Result<Option<Frame>, String> {
        let k = self.index + 1;
        let mut tag = [0u8; 16];
        let mut got = 0;
        while got < tag.len() {
            match self.src.read(&mut tag[got..]) {
                Ok(0) => break,
                Ok(m) => got += m,
                Err(e) => return Err(format!("{}: frame {k}: {e}", self.name)),
            }
        }
        if got == 0 {
            return Ok(None);
        }
        let name = &self.name;
        if got < tag.len() || &tag[..4] != FRAME_TAG {
            return Err(format!(
                "{name}: frame {k}: truncated or corrupt frame header"
            ));
        }
        let len = u64::from_le_bytes(tag[8..16].try_into().unwrap_or([0; 8]));
        let len = usize::try_from(len).map_err(|_| format!("{name}: frame {k}: bad length"))?;
        let mut body = Vec::new();
        body.try_reserve_exact(len)
            .map_err(|_| format!("{name}: frame {k}: length {len} cannot be held"))?;
        body.resize(len, 0);
        let mut sum = [0u8; 8];
        self.src
            .read_exact(&mut body)
            .and_then(|_| self.src.read_exact(&mut sum))
            .map_err(|_| format!("{name}: frame {k}: truncated (the run stopped while writing)"))?;
        if fnv1a64(&body) != u64::from_le_bytes(sum) {
            return Err(format!(
                "{name}: frame {k}: checksum mismatch (corrupt file)"
            ));
        }
        let frame = decode_body(&body).map_err(|e| format!("{name}: frame {k}: {e}"))?;
        self.index = k;
        Ok(Some(frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Frame {
        Frame {
            head: FrameHead {
                step: 42,
                dimension: 3,
                flags: flags::PERIODIC_X | flags::PERIODIC_X << 1,
                ntypes: 2,
                boxlo: [0.0, -1.0, 0.5],
                boxhi: [5.0, 4.0, 6.5],
                tilt: [0.25, 0.0, 0.0],
                dt: 0.01,
                beginstep: 0,
                endstep: 100,
                special_lj: [1.0, 0.0, 0.5, 1.0],
                style: "dpd/nonlinear".into(),
                settings: "pair_style dpd/nonlinear 1 1.5 7\n".into(),
            },
            tag: vec![3, 1],
            typ: vec![1, 2],
            mass: vec![1.0, 2.5],
            x: vec![[0.1, 0.2, 0.3], [1.0, 2.0, 3.0]],
            v: vec![[-0.1, 0.0, 1e-300], [4.0, 5.0, 6.0]],
            f: vec![[1.0, -1.0, 0.0], [-1.0, 1.0, f64::MIN_POSITIVE]],
        }
    }

    #[test]
    fn frames_round_trip_bit_for_bit() {
        let a = sample();
        let mut b = a.clone();
        b.head.step = 43;
        let mut bytes = file_header();
        bytes.extend(encode_frame(&a.head, a.atoms()).unwrap());
        bytes.extend(encode_frame(&b.head, b.atoms()).unwrap());
        let mut r = FrameReader::new(bytes.as_slice(), "t").unwrap();
        assert_eq!(r.next_frame().unwrap(), Some(a));
        assert_eq!(r.next_frame().unwrap(), Some(b));
        assert_eq!(r.next_frame().unwrap(), None);
    }

    #[test]
    fn a_flipped_bit_or_a_cut_frame_is_named() {
        let a = sample();
        let mut bytes = file_header();
        bytes.extend(encode_frame(&a.head, a.atoms()).unwrap());
        let mut bad = bytes.clone();
        let last = bad.len() - 20;
        bad[last] ^= 1;
        let e = FrameReader::new(bad.as_slice(), "t").unwrap().next_frame();
        assert!(e.unwrap_err().contains("frame 1: checksum"));
        let cut = &bytes[..bytes.len() - 3];
        let e = FrameReader::new(cut, "t").unwrap().next_frame();
        assert!(e.unwrap_err().contains("frame 1: truncated"));
        assert!(FrameReader::new(&b"DPDNLRST\x03\0\0\0\0\0\0\0"[..], "t").is_err());
    }

    #[test]
    fn arrays_of_different_lengths_are_refused() {
        let mut a = sample();
        a.mass.pop();
        assert!(encode_frame(&a.head, a.atoms()).is_err());
    }
}
