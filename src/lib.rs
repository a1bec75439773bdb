//! `dpdnl`: dissipative particle dynamics with non-linear (velocity-dependent) friction.
//!
//! # What a user of the crate gets
//!
//! The main types are re-exported at the crate root:
//!
//! - **Pair kernels** ([`forces::dpd::kernel`]): [`pair_force`] on one pair ([`PairModel`], [`PairCoeff`],
//!   [`PairInput`] → [`PairForce`]; [`Weight`], [`Friction`], [`Noise`]) and
//!   [`pair_forces_batch`], the same bits on a [`PairBatch`] of SIMD lanes ([`PairTable`]).
//! - **The pair random number** ([`rng`]): [`pair_gaussian`], keyed by (seed, step, tags).
//! - **The standalone engine** ([`engine`]): [`System`] over a [`SimBox`] and [`Atoms`], its
//!   [`Integrator`] and [`Thermo`].
//! - **The forces layer** ([`forces`]): every pair, bond and angle style, one registry per kind;
//!   the pair-style seam [`PairStyle`] (what a style is and computes; [`new_pair_style`],
//!   [`SetupContext`]), [`StyleRecord`] (what it writes and reports) and [`StyleDerived`] (what
//!   follows from its answers), and the batch seam [`PairKernel`] ([`DpdKernel`]).
//! - **The interpreter** ([`input`]): [`Interpreter`] runs a LAMMPS-style script under
//!   [`Options`], talking to a [`Console`] ([`Collect`] keeps the lines); errors are
//!   [`ScriptError`].
//! - **Readers** ([`io`], [`analysis`]): LAMMPS data files ([`parse_data`]), dumps
//!   ([`parse_dump`]), logs ([`parse_log`]), `fix ave/*` files ([`analysis::formats`]), and the
//!   engine's restart files ([`io::restart`]).
//! - **Theory and set-up** ([`theory`], [`init`]): kinetic theory, (η, Sc) design, the
//!   finite-step temperature; what a run's set-up resolves and checks in both engines.
//! - **A host engine's facade** ([`host`]): what the C ABI needs to run the styles and fixes on
//!   LAMMPS's atoms and lists.
//! - **Units** ([`units`]): LAMMPS's unit styles and the conversion constants both engines
//!   take from one [`Units`].
//! - **Grammar** ([`grammar`]): the arguments of this project's styles, parsed once for both
//!   engines (and the C ABI).
//! - **Analyses and reports** ([`analysis`], [`report`], [`stats`], [`plot`], [`fmtnum`]): what
//!   the papers measure (MB, PeX NEMD, Einstein–Helfand, MSD, Couette) from either engine's
//!   files, their typed results and JSON, block averages and fits, small PNG/SVG figures, and
//!   LAMMPS's `%g` number form.
//!
//! The library never prints; the `dpdnl` binary decides what a person sees.

// Component loops `for k in 0..dim` index several arrays at once (x, v, f, box lengths);
// they read closer to the equations than zipped iterators.
#![allow(clippy::needless_range_loop)]
#![warn(unreachable_pub)]
#![warn(missing_docs)]

// The fields of the analyses' result records are their columns, named as in the files and
// documented on each struct and in docs/; one line per field would repeat the struct's text.
#[allow(missing_docs)]
pub mod analysis;
pub mod engine;
pub mod fmtnum;
pub mod forces;
pub mod grammar;
pub mod host;
pub mod init;
pub mod input;
pub mod io;
// The fields of the figure description (series, panels, bands) are documented on their
// structs and read as the plotting options they set.
#[allow(missing_docs)]
pub mod plot;
// Result records serialised as JSON: their fields are the keys of `--json` and the Python
// dicts, documented on each struct and in docs/.
#[allow(missing_docs)]
pub mod report;
pub mod rng;
pub mod stats;
pub mod theory;
pub mod units;

pub use engine::{Atoms, Integrator, SimBox, System, Thermo};
pub use forces::batcher::PairKernel;
pub use forces::dpd::DpdKernel;
pub use forces::dpd::kernel::{
    Friction, Noise, PairCoeff, PairForce, PairInput, PairModel, PairTable, Weight, pair_force,
    pair_forces_batch,
};
pub use forces::{NoiseDist, PairBatch};
pub use forces::{PairStyle, RunSteps, SetupContext, StyleDerived, StyleRecord, new_pair_style};
pub use input::{Collect, Console, Interpreter, Options, ScriptError};
pub use io::data::parse_data;
pub use io::dump_read::parse_dump;
pub use io::lammps_log::parse_log;
pub use rng::pair_gaussian;
pub use units::{UnitStyle, Units};
