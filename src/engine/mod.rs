//! The standalone engine: a periodic orthorhombic or sheared box in 2-D or 3-D, a cell-sorted
//! half neighbour list, the velocity-Verlet and Euler integrators, and the thermodynamic
//! measurements LAMMPS reports (same definitions, so one log parser and one diff read both
//! engines).
//!
//! [`System`] (this file) holds the state; its code is split by concern: `step.rs` sequences
//! the set-up and the step as LAMMPS's `Verlet::setup`/`Verlet::run` do, `shear.rs` drives the
//! sheared box (its state is [`lees_edwards::Triclinic`]), `bonded.rs` the bonds and angles
//! (styles in [`crate::forces::bonded`], topology in `topology.rs`), `thermo.rs` the thermo sums.
//! The force terms themselves are the forces layer's ([`crate::forces`]).

pub mod atoms;
pub mod domain;
pub mod fixes;
pub mod groups;
pub mod lees_edwards;
pub mod measure;
pub mod modify;
pub(crate) mod neighbor;
pub(crate) mod simd;
pub(crate) mod topology;

mod bonded;
mod shear;
mod step;
mod stress_atom;
mod thermo;

pub use crate::forces::dpd::ForceField;
pub use crate::forces::style::{PairStyle, SetupContext, SetupNote};
pub use atoms::Atoms;
pub use domain::SimBox;
pub use neighbor::{NeighborList, PairTally};
pub use stress_atom::{KineticBias, StressParts};
pub use thermo::{Thermo, check_atoms};
pub use topology::Topology;

use rayon::prelude::*;

/// Time integration scheme (`docs/models.md` §4.1, P-1 and P-2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// Velocity-Verlet as LAMMPS `fix nve`: half kick, drift, forces at the new step, half kick.
    VelocityVerlet,
    /// Euler (Hoogerbrugge–Koelman; finite-step paper eqs. 1–2): x += v δt and v += F/m δt from
    /// the state at t, then forces at the new state (`fix nve/euler`).
    Euler,
}

/// The modified PeX momentum push (`docs/models.md` §4.4, P-6;
/// `fix ID all pex/push dp [width W] [every N]`). Semantics mirror the LAMMPS fix (docs/fixes.md):
/// applied after the step's final integration.
#[derive(Clone, Debug, PartialEq)]
pub struct PexPush {
    /// Fix id (for `f_ID` in thermo).
    pub id: String,
    /// Momentum Δp_z moved per push.
    pub dp: f64,
    /// Slab width (None: the default of docs/fixes.md).
    pub width: Option<f64>,
    /// Push every N steps.
    pub every: u64,
    /// Accumulated momentum moved so far.
    pub total: f64,
}

/// Everything the engine integrates.
#[derive(Debug)]
pub struct System {
    /// The box.
    pub bx: SimBox,
    /// The atoms.
    pub atoms: Atoms,
    /// Number of atom types.
    pub ntypes: usize,
    /// Per-type masses (index 0 unused).
    pub mass: Vec<Option<f64>>,
    /// The pair style, once defined (`style.rs`: every style behind one trait).
    pub pair: Option<Box<dyn PairStyle>>,
    /// Neighbour list.
    pub neighbor: NeighborList,
    /// Time step.
    pub dt: f64,
    /// The unit style (`units`) and its constants: integrators, thermo and the pair styles'
    /// set-up take every conversion from it (`crate::units`).
    pub units: crate::units::Units,
    /// Current step (LAMMPS's `update->ntimestep`).
    pub step: u64,
    /// The names of the groups by mask bit (`group`; the masks are [`Atoms::mask`]).
    pub groups: groups::Groups,
    /// The integrator, if a `fix nve` or `fix nve/euler` is defined.
    pub integrator: Option<Integrator>,
    /// The fixes with per-step hooks (`modify/`): integrators on groups, force fixes,
    /// `momentum`. When none of them integrates, [`System::integrator`] integrates all atoms.
    pub modify: modify::Modify,
    /// True when the pair style stands for one sub-style of LAMMPS's `pair_style hybrid` or
    /// `hybrid/overlay` (`dpdnl verify`, which recomputes that style's share of a LAMMPS run):
    /// type pairs without coefficients belong to other styles ([`crate::forces::style::coverage`]).
    /// False in a standalone run, which has no hybrid.
    pub pair_substyle: bool,
    /// When true, [`System::setup`] leaves the fixes' set-up to the caller, who first hands
    /// them their variables ([`System::fix_inputs`]) and then calls [`System::setup_fixes`].
    pub defer_fix_setup: bool,
    /// PeX pushes defined with `fix … pex/push`.
    pub pex: Vec<PexPush>,
    /// Energy and virial of the last force evaluation.
    pub tally: PairTally,
    /// What the last [`System::setup`] resolved or found worth a warning (the caller logs them).
    pub setup_notes: Vec<SetupNote>,
    /// The tilt and `fix deform` of a triclinic box (None: orthogonal). A triclinic box runs
    /// the same neighbour list under Lees–Edwards boundaries (`lees_edwards.rs`).
    pub tri: Option<lees_edwards::Triclinic>,
    inv_mass: Vec<f64>,
    /// The per-atom values of a many-body style's pre-pass (engine order).
    prepass: Vec<f64>,
    /// The first fault of the last force evaluation (a non-finite many-body term, a bad FENE
    /// bond), reported by [`System::check_health`] and [`System::fault`].
    pair_fault: Option<String>,
    /// The last step of the coming run, when known ([`System::setup_run`]): `fix deform`'s
    /// rates depend on it as LAMMPS's do.
    run_end: Option<u64>,
    /// `run … start S stop E` of the coming run ([`System::setup_run_window`]).
    run_window: (Option<u64>, Option<u64>),
    /// The current run's first and last step for a pair style's ramp (LAMMPS's `beginstep`,
    /// `endstep`; [`crate::forces::PairStyle::at_step`]), set by [`System::setup`].
    run_steps: crate::forces::RunSteps,
    /// Rebuild the lists at the next step (LAMMPS re-neighbours on the steps it writes a
    /// restart file: [`System::rebuild_at_next_step`]).
    force_rebuild: bool,
    /// Bonds, angles, molecule style and `special_bonds` (None: `atom_style atomic`).
    pub topo: Option<Topology>,
    /// The energies of the last force evaluation by kind.
    pub energies: Energies,
    /// Warnings of the force evaluations since the caller last took them (LAMMPS's "FENE bond
    /// too long"), for the caller to print.
    pub warnings: Vec<String>,
    /// The bonded terms' working state (their special partners and index form).
    bonded: bonded::BondedState,
    /// LAMMPS's user ghost cut-off (`comm_modify cutoff`; 0: none), for the check of the
    /// bonded atoms' images at a run's set-up.
    pub comm_cutoff: f64,
}

/// The energies of one force evaluation by kind (LAMMPS's `evdwl`, `ebond`, `eangle`);
/// [`System::tally`] holds their sum and the virial of every force.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Pair energy (`epair`, `evdwl`).
    pub epair: f64,
    /// Bond energy (`ebond`).
    pub ebond: f64,
    /// Angle energy (`eangle`).
    pub eangle: f64,
}

/// Most atom types a standalone system may have (`create_box`, `read_data`, `read_restart`):
/// per-type tables hold (N + 1)² entries, rebuilt at every run's set-up, so a count beyond
/// this is a typing error, not a model (a fuzzed `create_box 23333333333333 box` aborted in the
/// allocator).
pub(crate) const MAX_ATOM_TYPES: usize = 1000;

/// Refuse an atom type count outside 1..=[`MAX_ATOM_TYPES`], naming it.
pub(crate) fn check_ntypes(ntypes: usize) -> Result<(), String> {
    if ntypes == 0 {
        return Err("the number of atom types must be >= 1".into());
    }
    if ntypes > MAX_ATOM_TYPES {
        return Err(format!(
            "{ntypes} atom types: at most {MAX_ATOM_TYPES} are supported (per-type tables hold \
             (N + 1)^2 entries)"
        ));
    }
    Ok(())
}

impl System {
    /// An empty system in `bx` with `ntypes` atom types, in `units lj`; δt defaults to 0.005,
    /// skin to 0.3 (LAMMPS `units lj`).
    pub fn new(bx: SimBox, ntypes: usize) -> System {
        System {
            bx,
            atoms: Atoms::default(),
            ntypes,
            mass: vec![None; ntypes + 1],
            pair: None,
            neighbor: NeighborList::new(0.3),
            dt: 0.005,
            units: crate::units::Units::LJ,
            step: 0,
            groups: groups::Groups::default(),
            integrator: None,
            modify: modify::Modify::default(),
            defer_fix_setup: false,
            pair_substyle: false,
            pex: Vec::new(),
            tally: PairTally::default(),
            setup_notes: Vec::new(),
            tri: None,
            inv_mass: Vec::new(),
            prepass: Vec::new(),
            pair_fault: None,
            run_end: None,
            run_window: (None, None),
            run_steps: crate::forces::RunSteps::default(),
            force_rebuild: false,
            topo: None,
            energies: Energies::default(),
            warnings: Vec::new(),
            bonded: Default::default(),
            comm_cutoff: 0.0,
        }
    }

    /// Make `style` the pair style.
    pub fn set_pair(&mut self, style: impl PairStyle + 'static) {
        self.pair = Some(Box::new(style));
    }

    /// True when the box is triclinic: the pair loop and wrapping are Lees–Edwards's.
    pub fn is_triclinic(&self) -> bool {
        self.tri.is_some()
    }

    /// Dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.bx.dim
    }
}
