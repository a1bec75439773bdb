//! Why a restart file was refused, and how that reads.

use super::FORMAT_VERSION;
use std::fmt;

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
