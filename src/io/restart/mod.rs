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
mod decode;
mod encode;
mod error;
mod frame;

pub use error::RestartError;
pub use frame::{FORMAT_VERSION, MAGIC, decode, encode, fnv1a64};

use crate::engine::topology::{Angle, AtomStyle, Bond, SpecialBonds};
use crate::engine::{Atoms, Energies, PairTally};
use std::io::Write;
use std::path::Path;

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
    /// The group names by mask bit, `all` first (version 4; only `all` in older files, whose
    /// atoms have no masks). The masks are `atoms.mask`.
    pub groups: Vec<String>,
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

#[cfg(test)]
mod tests {
    use super::frame::HEADER;
    use super::*;

    fn sample() -> Restart {
        let mut atoms = Atoms::default();
        atoms.push(3, 1, [0.5, -0.0, 1.25], [1e-300, 2.0, -3.0], [1, -2, 0]);
        atoms.push(1, 2, [4.0, 1.0, 0.1], [0.0, -1.0, 0.5], [0, 0, 7]);
        atoms.f[1] = [0.1, 0.2, 0.3];
        atoms.mask = vec![1, 5];
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
            groups: vec!["all".into(), String::new(), "wall".into()],
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

    /// The bytes of the version-4 groups block of a record with only `all` and no masks:
    /// the name count (4), "all" (4 + 3), the mask count (8).
    const NO_GROUPS: usize = 4 + 7 + 8;

    /// A record without groups (what a file before version 4 reads as).
    fn sample_without_groups() -> Restart {
        let mut r = sample();
        r.groups = vec!["all".into()];
        r.atoms.mask.clear();
        r
    }

    /// A version-3 file (before groups): every atom in `all` only.
    #[test]
    fn version_3_files_read_without_groups() {
        let r = sample_without_groups();
        let v4 = encode(&r);
        let v3 = as_version(&v4, 3, v4.len() - HEADER - 8 - NO_GROUPS);
        assert_eq!(decode(&v3), Ok(r));
    }

    /// A version-2 file (before the unit style): read as `units lj`.
    #[test]
    fn version_2_files_read_as_lj() {
        let mut r = sample_without_groups();
        let v4 = encode(&r);
        // Version 2's payload is version 3's without the unit style string ("real": 4 + 4
        // bytes) at its end.
        let v2 = as_version(&v4, 2, v4.len() - HEADER - 8 - NO_GROUPS - 8);
        r.units = crate::units::UnitStyle::Lj;
        assert_eq!(decode(&v2), Ok(r));
    }

    /// A version-1 file (before topology): no topology block, read as an atomic system.
    #[test]
    fn version_1_files_still_read() {
        let mut r = sample_without_groups();
        r.topo = None;
        let v4 = encode(&r);
        // Version 1's payload is version 3's without the unit style string ("real": 8 bytes)
        // and the topology flag before it (1 byte).
        let v1 = as_version(&v4, 1, v4.len() - HEADER - 8 - NO_GROUPS - 8 - 1);
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
