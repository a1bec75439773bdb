//! placeholder
pub mod data;
pub mod lammps_log;
pub mod dump_read;
