//! placeholder
pub mod data;
pub mod dump_read;
pub mod lammps_log;
