//! The style object: everything one pair style is — its settings and `pair_coeff` lines (parsed
//! by its own `grammar` module, e.g. [`crate::forces::dpd::grammar`]), its set-up at each run,
//! an optional per-atom pre-pass (a many-body style's density), its batched kernel, its
//! cut-offs ([`PairStyle`]), and its restart lines, `write_data` coefficients and plan
//! ([`StyleRecord`], [`crate::forces::plan`]); what follows from those answers by one rule is [`StyleDerived`].
//!
//! The standalone engine (`System::pair`), the interpreter (`pair_style`, `pair_coeff`,
//! `write_restart`) and the C ABI's one handle for every LAMMPS style (`capi/src/pair/`) hold
//! a `Box<dyn PairStyle>` made by [`crate::forces::new_pair_style`] and never name a style: a
//! new style is one folder under `src/forces/` (grammar, kernel, the trait's implementation)
//! and one entry in [`crate::forces::PAIR_STYLES`].
//!
//! A force evaluation through a style, in either engine:
//! 1. if [`PairStyle::prepass`] is `Some`, the driver sums `weight(k, r²)` over the pairs in
//!    range into one value per atom (owned and, in LAMMPS, ghost atoms summed into their
//!    owners), completes each owned atom with [`PrePass::complete`] (its self term), adds
//!    [`PrePass::energy_of`] to the energy, communicates the values to the ghosts, and hands
//!    every atom's value to [`PairStyle::set_atom_values`];
//! 2. the pairs in range go through [`PairStyle::kernel`] in batches (`forces::batcher`), whose
//!    central forces are applied ±, so momentum is conserved exactly for every style.
//!
//! Bonded terms (bonds, angles) are a second kind of force term beside this one
//! (`forces::bonded`, `engine::topology`): styles with their own coefficients, evaluated over a
//! topology instead of a neighbour list; they share the tallies, not this trait. The pair
//! style sees the topology only through `SetupContext::special_lj` and the special pairs the
//! pair loop applies ([`PairStyle::scales_special`]).

use std::any::Any;
use std::fmt::Debug;
use std::sync::Arc;

use crate::forces::Isa;
use crate::forces::batcher::PairKernel;
use crate::forces::plan::StylePlan;

/// A line for the log from `System::setup` and the C ABI's set-up.
#[derive(Clone, Debug, PartialEq)]
pub enum SetupNote {
    /// Information (e.g. the γ and s resolved from `pair_coeff … eta … sc …`).
    Info(String),
    /// A warning (e.g. Euler finite-step heating, `crate::init::euler_warning`).
    Warning(String),
}

/// What a run's set-up knows that a pair style may need (the same in both engines: the C ABI
/// fills it from LAMMPS's state).
#[derive(Clone, Copy, Debug)]
pub struct SetupContext<'a> {
    /// 2 or 3.
    pub dim: u32,
    /// Number of atoms in the whole system.
    pub natoms: usize,
    /// Number density N / V (N / area in 2-D).
    pub density: f64,
    /// Per-type masses, index 0 unused (`None`: not set; every entry `None` when
    /// [`SetupContext::per_atom_mass`]).
    pub mass: &'a [Option<f64>],
    /// True when the atom style has per-atom masses (LAMMPS's `atom->rmass_flag`, through the
    /// C ABI's `DpdnlSetup::per_atom_mass`; never in the standalone engine): every evaluation
    /// then reads each atom's own mass (the kick and correction of the noise schemes, the
    /// many-body density sum, sDPD's equation of state: [`PrePass::weight_of`],
    /// [`PrePass::energy_of_mass`], [`PairStyle::set_atom_values`]) and the per-type masses
    /// are not used, as in LAMMPS.
    pub per_atom_mass: bool,
    /// Time step.
    pub dt: f64,
    /// True when the run integrates with `fix nve/euler` (the finite-step heating warning).
    pub euler: bool,
    /// LAMMPS's `special_bonds lj` factors by special class (0: an ordinary pair, 1–3: 1-2, 1-3,
    /// 1-4 neighbours); `[1.0; 4]` where there are no bonds.
    pub special_lj: [f64; 4],
    /// The unit style and its constants (LAMMPS's, through the C ABI; the `units` command's in
    /// the standalone engine): T of the pair styles is a temperature, kT = boltz T.
    pub units: crate::units::Units,
    /// True when the style is a sub-style of LAMMPS's `pair_style hybrid` or `hybrid/overlay`
    /// (the C ABI's `DpdnlSetup::substyle`; never in the standalone engine, which has no
    /// hybrid): type pairs without coefficients then belong to other styles ([`coverage`]).
    pub substyle: bool,
}

/// Which type pairs a set-up covers: `Ok(false)` when the style has coefficients for every type
/// pair, `Ok(true)` when, as a sub-style of LAMMPS's `pair_style hybrid` or `hybrid/overlay`
/// ([`SetupContext::substyle`]), it has them for some pairs only: the others belong to other
/// styles, get no interaction from this one (cut-off 0 in [`PairStyle::cut_table`]), and
/// every derived quantity (the largest cut-off, designs, warnings) is over the style's own
/// pairs. As the top-level style every pair must be set, and a sub-style must be given at least
/// one pair.
pub fn coverage(style: &dyn PairStyle, ctx: &SetupContext) -> Result<bool, String> {
    let Some((i, j)) = style.missing() else {
        return Ok(false);
    };
    if !ctx.substyle {
        return Err(format!(
            "pair coefficients for types {i} {j} are not set (pair_coeff)"
        ));
    }
    if !style.covers_any() {
        return Err(format!(
            "pair_style {} as a sub-style of pair_style hybrid has no type pair: give it one \
             (pair_coeff I J {} …)",
            style.name(),
            style.name()
        ));
    }
    Ok(true)
}

/// The refusal of (η, Sc) targets on a subset of the type pairs (`pair_style hybrid`): the
/// kinetic theory behind the design is for one fluid whose every pair interacts through the
/// style, at the number density of all atoms. `coeff` names the style's own friction
/// coefficient, to give instead.
pub(crate) fn targets_on_subset(style: &str, coeff: &str) -> String {
    format!(
        "pair_coeff … eta … sc …: the design is for one fluid whose every type pair interacts \
         through pair_style {style} (at the number density of all atoms), but as a sub-style of \
         pair_style hybrid it covers only some type pairs; give {coeff} instead of eta and sc"
    )
}

/// The first and last step of the current run (LAMMPS's `update->beginstep` and `endstep`:
/// `run N` from step n gives n and n + N; `run N start S stop E` gives S and E).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunSteps {
    /// The step the run (or its `start`) begins at.
    pub begin: u64,
    /// The step the run (or its `stop`) ends at.
    pub end: u64,
}

/// A many-body style's pre-pass: one value per atom, d_i = complete(Σ_j w_k(r_ij²)) over the
/// pairs within the cut-off of their type pair (k the dense index `t_i (ntypes + 1) + t_j`).
pub trait PrePass: Sync {
    /// Squared cut-offs by dense type-pair index.
    fn rcsq(&self) -> &[f64];
    /// w_k(r²) of one pair (0 beyond its cut-off).
    fn weight(&self, k: usize, rsq: f64) -> f64;
    /// The same function on a row of squared distances of one type pair `k` (0 beyond it).
    fn weights(&self, k: usize, rsq: &[f64], out: &mut [f64]);
    /// The value of an atom of type `t` from its pair sum (the self term added).
    fn complete(&self, t: usize, sum: f64) -> f64;
    /// The energy of an atom of type `t` with value `d`, or `None` when its state is not
    /// finite ([`PrePass::fault`] says why).
    fn energy_of(&self, t: usize, d: f64) -> Option<f64>;
    /// With per-atom masses ([`SetupContext::per_atom_mass`]): the weight of one pair added to
    /// an atom whose neighbour in the pair has mass `m`, the same bits as [`PrePass::weight`]
    /// of the style set up with per-type mass `m`. The default: a weight that does not depend
    /// on the neighbour's mass.
    fn weight_of(&self, k: usize, rsq: f64, _m: f64) -> f64 {
        self.weight(k, rsq)
    }
    /// With per-atom masses: [`PrePass::energy_of`] of an atom of mass `m`, the same bits as
    /// that of the style set up with per-type mass `m`. The default: an energy that does not
    /// depend on the atom's mass.
    fn energy_of_mass(&self, t: usize, d: f64, _m: f64) -> Option<f64> {
        self.energy_of(t, d)
    }
    /// The error of an atom (`who`: its id) whose state is not finite at value `d`, `step`.
    fn fault(&self, who: &str, d: f64, step: u64) -> String;
}

/// One pair style (see the module documentation). `Any` lets a test read one style's own
/// fields (`&dyn Any` by trait upcasting); no code path of the engines downcasts: they use the
/// trait.
pub trait PairStyle: StyleRecord + Any + Send + Sync + Debug {
    /// The style's name (`dpd/nonlinear`, `sdpd`).
    fn name(&self) -> &'static str;
    /// Number of atom types the coefficient tables hold.
    fn ntypes(&self) -> usize;
    /// `pair_style` given again with the same style: new settings (the words after the style
    /// name); the coefficients are kept under this style's rule (documented on each style).
    fn restyle(&mut self, args: &[String]) -> Result<(), String>;
    /// Apply one `pair_coeff` line (its words, types first).
    fn coeff(&mut self, args: &[String]) -> Result<(), String>;
    /// The cut-off of type pair (i, j), or `None` when it has no coefficients.
    fn cutoff(&self, i: usize, j: usize) -> Option<f64>;
    /// Set-up of a run: every pair set (or, as a sub-style of LAMMPS's `hybrid`, the pairs
    /// [`coverage`] allows), targets resolved, the per-run tables built. Returns the lines to
    /// log.
    fn setup(&mut self, ctx: &SetupContext) -> Result<Vec<SetupNote>, String>;
    /// A new time step between set-ups (LAMMPS's `fix dt/reset`); the default keeps the set-up's.
    fn set_timestep(&mut self, _dt: f64) {}
    /// The step whose forces come next, of a run from `run.begin` to `run.end` (LAMMPS's
    /// `update->ntimestep`, `beginstep`, `endstep`), before [`PairStyle::kernel`] at every force
    /// evaluation, the set-up's included: a thermostat's temperature ramp
    /// (`dpd/nonlinear/tstat`, docs/models.md P-35). The default ignores it.
    fn at_step(&mut self, _step: u64, _run: RunSteps) {}
    /// The cut-offs by dense type-pair index (`(ntypes + 1)²`, 0 for unset pairs), after
    /// [`PairStyle::setup`].
    fn cut_table(&self) -> &[f64];
    /// True when the kernel's coefficient table holds one block per special class: the
    /// coefficients of a pair of class b (1–3) at index `k + b (ntypes + 1)²`, scaled by its
    /// `special_lj` factor (docs/models.md §4.8, P-22). A style that does not scale refuses
    /// fractional factors ([`check_special`]).
    fn scales_special(&self) -> bool {
        false
    }
    /// New `special_lj` factors between set-ups (LAMMPS's `pair_modify pair NAME special lj …`
    /// under `pair_style hybrid`, in force only around this sub-style's evaluation), already
    /// accepted by [`check_special`]: a style that scales its coefficients rebuilds its blocks;
    /// the default keeps nothing (the pair walk reads factors 0 and 1 itself).
    fn set_special(&mut self, _special_lj: [f64; 4]) {}
    /// The many-body pre-pass, if the style has one (after [`PairStyle::setup`]).
    fn prepass(&self) -> Option<&dyn PrePass> {
        None
    }
    /// The pre-pass values of every atom the kernel will see (owned and ghost atoms in LAMMPS),
    /// their types and, with per-atom masses ([`SetupContext::per_atom_mass`]), their masses,
    /// before [`PairStyle::kernel`]; ignored by styles without a pre-pass.
    fn set_atom_values(&mut self, _values: &[f64], _typ: &[u32], _mass: Option<&[f64]>) {}
    /// The batched pair kernel (after [`PairStyle::setup`]), its lanes in instruction set `isa`.
    fn kernel(&self, isa: Isa) -> Box<dyn PairKernel + '_>;
    /// The conservative force F(r)/r and energy of one pair of types (i, j) at distance² `rsq`
    /// (LAMMPS's `Pair::single`, as `pair dpd` returns it), or `None` when the style has no
    /// pair-wise answer (a many-body style).
    fn single(&self, _i: usize, _j: usize, _rsq: f64) -> Option<(f64, f64)> {
        None
    }
    /// A copy of the style.
    fn clone_box(&self) -> Box<dyn PairStyle>;
}

/// What a style writes and reports about itself: its restart and `write_data` lines, the typed
/// plan that dry runs and `dpdnl theory` print, the per-atom values a compute reads. The
/// supertrait of [`PairStyle`]: the writers and reporters of both engines need only this.
pub trait StyleRecord {
    /// The lines (words, command first) that rebuild this style's settings and coefficients
    /// exactly: what a restart file stores, in both engines.
    fn restart_lines(&self) -> Vec<Vec<String>>;
    /// True when the style writes `write_data` coefficients ([`StyleRecord::data_coeffs`]).
    fn writes_data(&self) -> bool {
        false
    }
    /// The numbers of a `write_data` coefficient line of type pair (i, j) (after the types), or
    /// `None` when the style writes no data coefficients.
    fn data_coeffs(&self, _i: usize, _j: usize) -> Option<Vec<f64>> {
        None
    }
    /// The per-atom values of the last pre-pass (sDPD's densities, in the engine's atom
    /// order), if the style has a pre-pass and it ran.
    fn atom_values(&self) -> Option<&[f64]> {
        None
    }
    /// What a run would use, after [`PairStyle::setup`] (`units` for kT, `dt` the time step):
    /// the report `dpdnl theory SCRIPT` and dry runs read ([`crate::forces::plan`]).
    fn plan(&self, units: &crate::units::Units, dt: f64) -> Arc<dyn StylePlan>;
}

/// What follows from a style's answers by one rule for every style (which type pairs it
/// covers, its largest cut-off, whether it is pair-wise): implemented for every [`PairStyle`],
/// never by a style itself.
pub trait StyleDerived {
    /// True when every pair's force depends on that pair alone ([`PairStyle::single`] answers).
    fn pairwise(&self) -> bool;
    /// The first type pair without coefficients, if any.
    fn missing(&self) -> Option<(usize, usize)>;
    /// True when type `t` is in at least one type pair with coefficients.
    fn covers_type(&self, t: usize) -> bool;
    /// True when at least one type pair has coefficients.
    fn covers_any(&self) -> bool;
    /// The largest cut-off over the set type pairs.
    fn rc_max(&self) -> f64;
}

impl<T: PairStyle + ?Sized> StyleDerived for T {
    fn pairwise(&self) -> bool {
        self.prepass().is_none()
    }
    fn missing(&self) -> Option<(usize, usize)> {
        let n = self.ntypes();
        (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .find(|&(i, j)| self.cutoff(i, j).is_none())
    }
    fn covers_type(&self, t: usize) -> bool {
        (1..=self.ntypes()).any(|u| self.cutoff(t, u).is_some())
    }
    fn covers_any(&self) -> bool {
        (1..=self.ntypes()).any(|t| self.covers_type(t))
    }
    fn rc_max(&self) -> f64 {
        let n = self.ntypes();
        (1..=n)
            .flat_map(|i| (i..=n).map(move |j| (i, j)))
            .filter_map(|(i, j)| self.cutoff(i, j))
            .fold(0.0, f64::max)
    }
}

impl Clone for Box<dyn PairStyle> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// `special_bonds lj` factors a style can honour: any factor in [0, 1] for a style that scales
/// its coefficients ([`PairStyle::scales_special`]); only 0 (the pair excluded) or 1 for the
/// others (a many-body density sum has no pair factor).
pub fn check_special(style: &dyn PairStyle, special: [f64; 4]) -> Result<(), String> {
    for (b, &f) in special.iter().enumerate().skip(1) {
        if !(0.0..=1.0).contains(&f) {
            return Err(format!(
                "special_bonds lj factor {f} of 1-{} neighbours must be in [0, 1]",
                b + 1
            ));
        }
        if f != 0.0 && f != 1.0 && !style.scales_special() {
            return Err(format!(
                "pair_style {} cannot weight bonded neighbours (special_bonds lj factor {f} of \
                 1-{} neighbours): its many-body density sum has no pair factor; use factors 0 \
                 (excluded) or 1",
                style.name(),
                b + 1
            ));
        }
    }
    Ok(())
}

/// A number as a restart word: 17 significant digits, read back exactly.
pub(crate) fn word(x: f64) -> String {
    format!("{x:.17e}")
}
