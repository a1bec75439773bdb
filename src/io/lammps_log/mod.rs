//! LAMMPS log files: the thermo blocks, and column-by-column comparison of two logs or dumps.
//!
//! [`parse_log`] reads the thermo output that `thermo_style one/custom` prints (LAMMPS 2020 to
//! 2025 and this project's engine print the same shape): a header line whose first token is
//! `Step`, then one line of numbers per thermo step. A block ends at `Loop time of …` or at
//! the first other line that is not all numbers; `WARNING…` lines and blank lines inside a
//! block are skipped. A header followed by no rows is not a block. `thermo_style multi` and
//! `thermo_modify line yaml` output are not recognised.
//!
//! [`neighbor_summary`] reads LAMMPS's neighbour-list settings and "Dangerous builds" counts;
//! [`flip_records`] the machine-readable line of each run's box flips.
//!
//! The comparison functions ([`compare_exact`], [`compare_exact_logs`], [`compare_dumps_exact`],
//! [`compare_stats`]) return reports; the `dpdnl diff` command prints them, and other commands
//! (`crosscheck`) can use them directly.

mod exact;
mod flips;
mod neighbor;
mod report;
mod stats;
mod thermo;

pub use exact::{compare_dumps_exact, compare_exact, compare_exact_logs};
pub use flips::{FlipRecord, flip_records};
pub use neighbor::{NeighborSettings, NeighborSummary, neighbor_summary};
pub use report::{ColumnDiff, ExactReport, StepMax, Tolerance, differences};
pub use stats::{ColumnStats, StatsReport, compare_stats, z_score};
pub use thermo::{ThermoBlock, looks_like_dump, parse_log};
