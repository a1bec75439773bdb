//! The file around the payload: magic, format version, length and FNV-1a checksum; the whole
//! file encoded and checked.

use super::decode::{array, decode_payload};
use super::encode::encode_payload;
use super::{Restart, RestartError};

/// The first 8 bytes of every restart file.
pub const MAGIC: &[u8; 8] = b"DPDNLRST";

/// The format version this build writes; it reads this one and every older one (version 1:
/// no topology block, an `atomic` system; versions 1 and 2: no unit style, `units lj`; versions 1 to 3: no groups, every atom in `all` only).
pub const FORMAT_VERSION: u32 = 4;

/// Bytes before the payload: magic, version and payload length.
pub(super) const HEADER: usize = 8 + 4 + 8;

/// LAMMPS's own restart files start with this (its `MAGIC_STRING`), so a mix-up gets a hint.
const LAMMPS_MAGIC: &[u8] = b"LammpS RestartT";

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
