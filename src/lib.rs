//! `dpdnl`: dissipative particle dynamics with non-linear (velocity-dependent) friction.
//!
//! - [`kernel`]: pure pair kernels (weights, friction models, noise schemes), shared with the C ABI.
//! - [`rng`]: the counter-based pair random number keyed by (seed, step, min tag, max tag).
//! - [`theory`]: closed-form kinetic theory, (η, Sc) design and the finite-step temperature.
//! - [`init`]: what both engines resolve and check at a run's set-up ((η, Sc) → γ, s; Euler heating).
//! - [`engine`]: the standalone engine (boxes, neighbour lists, integrators, measurements).
//! - [`grammar`]: the arguments of this project's styles, parsed once for both engines (C ABI too).
//! - [`input`]: the LAMMPS-input subset the engine reads.
//! - [`io`]: LAMMPS file formats (data, dump, log) read and written.
//! - [`analysis`]: what the papers measure (MB histograms, NEMD, Einstein–Helfand, MSD, Couette), from LAMMPS-format outputs.
//! - [`stats`]: block averaging and simple fits used by measurements and comparisons.
//! - [`plot`]: small PNG/SVG figures (lines, points with error bars, log axes, legends).
//!
//! The library never prints; the `dpdnl` binary decides what a person sees.

// Component loops `for k in 0..dim` index several arrays at once (x, v, f, box lengths);
// they read closer to the equations than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod engine;
pub mod fmtnum;
pub mod grammar;
pub mod init;
pub mod input;
pub mod io;
pub mod kernel;
pub mod plot;
pub mod report;
pub mod rng;
pub mod stats;
pub mod theory;
