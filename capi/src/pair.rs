//! One C handle for every pair style: an opaque [`DpdnlPair`] holds the style object of the
//! standalone engine (`dpdnl::host::PairStyle`: the same grammar, set-up, kernel and
//! restart lines), so a LAMMPS style forwards `narg/arg`, marshals arrays and does MPI, and
//! knows no coefficient, rule or equation of its own.
//!
//! One force evaluation:
//! - a style with a pre-pass ([`DpdnlPairInfo::values_per_atom`] = 1, e.g. `sdpd`'s density):
//!   [`dpdnl_pair_prepass`] sums over the half list into `values` (owned atoms, and ghosts with
//!   newton on; the C++ style then sums ghost parts into their owners, `reverse_comm`),
//!   [`dpdnl_pair_prepass_finish`] completes the owned atoms and tallies their energy, the
//!   style sends the owners' values to their ghosts (`forward_comm`);
//! - [`dpdnl_pair_compute`]: the pair forces through the style's kernel, the same list walk and
//!   `ev_tally` conventions (half list: newton on or off; full list: `ev_tally_full`).

use std::ffi::{CString, c_char};
use std::sync::OnceLock;

use dpdnl::host::Isa;
use dpdnl::host::SetupNote;
use dpdnl::host::check_special;
use dpdnl::host::{PAIR_STYLES, from_restart_lines};
use dpdnl::{PairStyle, SetupContext, new_pair_style};

use crate::compute::{Workers, walk_pairs};
use crate::init::set_last_message;
use crate::list::{for_each_row, special_class};
use crate::styles::{put, words};
use crate::team::DpdnlLaunch;
use crate::working::WorkingList;
use crate::{
    DpdnlAtoms, DpdnlNeighList, DpdnlStatus, DpdnlStep, DpdnlTally, Error, c_str, guard, slice,
    slice_mut,
};
use dpdnl::host::SpecialRule;

/// A pair style and its coefficients (opaque to C).
pub struct DpdnlPair {
    style: Box<dyn PairStyle>,
    /// The special-bond factors of the last set-up.
    special: [f64; 4],
    /// The types of the atoms of the last [`dpdnl_pair_compute`] (scratch).
    typ: Vec<u32>,
    /// The text of the last [`dpdnl_pair_restart`].
    text: Vec<u8>,
    /// The threads of [`dpdnl_pair_compute`] when more than one ([`dpdnl_pair_threads`]).
    workers: Option<Workers>,
    /// The host's parallel launcher for those threads ([`dpdnl_pair_launcher`]).
    launch: DpdnlLaunch,
    /// The working copy of the LAMMPS list of [`dpdnl_pair_compute`].
    working: WorkingList,
}

/// What a style needs from its C++ driver.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DpdnlPairInfo {
    /// Values per atom of the style's pre-pass (0: none; 1: one double per owned and ghost atom,
    /// communicated between the passes).
    pub values_per_atom: i32,
    /// 1 when [`dpdnl_pair_single`] answers (LAMMPS's `single_enable`).
    pub single: i32,
    /// 1 when [`dpdnl_pair_data`] answers (LAMMPS's `writedata`).
    pub data: i32,
}

/// The host's unit style and its conversion constants (LAMMPS: `update->unit_style`,
/// `force->boltz`, `force->mvv2e`, `force->ftm2v`, `force->nktv2p`, `force->mv2d`), so that no
/// constant is written in the host's code: T of the pair styles is a temperature (kT = boltz
/// T, as for LAMMPS's `pair_style dpd`), the two-step kick and the correction of `noise
/// corrected` take ftm2v, the theory's mass and sDPD's pressure mvv2e (`dpdnl::units`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlUnits {
    /// The unit style's name, NUL-terminated: one of LAMMPS's (lj real metal si cgs electron
    /// micro nano); null is an error.
    pub style: *const c_char,
    /// Boltzmann's constant in energy / temperature.
    pub boltz: f64,
    /// mass × velocity² → energy.
    pub mvv2e: f64,
    /// force × time / mass → velocity.
    pub ftm2v: f64,
    /// energy / volume → pressure.
    pub nktv2p: f64,
    /// mass / volume → mass density.
    pub mv2d: f64,
}

/// The checked [`dpdnl::Units`] of `u` (every constant finite and > 0, a LAMMPS unit style).
///
/// # Safety
/// `u.style` is null or a NUL-terminated string.
pub(crate) unsafe fn units_of(u: &DpdnlUnits) -> Result<dpdnl::Units, Error> {
    // SAFETY: forwarded caller's contract.
    let style = unsafe { c_str(u.style, "units.style")? };
    dpdnl::Units::from_host(style, u.boltz, u.mvv2e, u.ftm2v, u.nktv2p, u.mv2d)
        .map_err(Error::invalid)
}

/// What a run's set-up knows (LAMMPS's state at `init_style`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlSetup {
    /// 2 or 3.
    pub dimension: i32,
    /// Atoms in the whole system (LAMMPS `atom->natoms`).
    pub natoms: i64,
    /// Volume of the box (area in 2-D).
    pub volume: f64,
    /// Per-type masses, `ntypes + 1` doubles (entry 0 unused), or null (per-atom masses).
    pub mass: *const f64,
    /// Time step.
    pub dt: f64,
    /// Nonzero when a `fix nve/euler` is defined (the finite-step warning).
    pub euler: i32,
    /// LAMMPS's `special_bonds lj` factors (`force->special_lj`, 4 doubles: entry 0 unused,
    /// then 1-2, 1-3, 1-4), or null: no bonded neighbours.
    pub special_lj: *const f64,
    /// The unit style and its constants.
    pub units: DpdnlUnits,
    /// Nonzero when the style is a sub-style of the host's `pair_style hybrid` or
    /// `hybrid/overlay` (LAMMPS: `force->pair != this`): type pairs without coefficients then
    /// belong to other styles and get no interaction from this one; zero: the top-level style,
    /// every type pair must be set (`dpdnl::host::coverage`, the rule).
    pub substyle: i32,
}

/// The styles' names and LAMMPS's one-line descriptions, as C strings that live as long as the
/// library.
fn style_names() -> &'static [(CString, CString)] {
    static NAMES: OnceLock<Vec<(CString, CString)>> = OnceLock::new();
    NAMES.get_or_init(|| {
        PAIR_STYLES
            .iter()
            .map(
                |&dpdnl::host::PairStyleEntry {
                     name, about: what, ..
                 }| {
                    let text = |s: String| CString::new(s).unwrap_or_default();
                    (
                        text(name.to_string()),
                        text(format!("pair_style {name} (dpdnl: {what})")),
                    )
                },
            )
            .collect()
    })
}

/// The number of pair styles this library provides (the C++ side registers each of them with
/// LAMMPS under [`dpdnl_pair_style_name`]).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_style_count() -> i32 {
    PAIR_STYLES.len() as i32
}

/// The name of pair style `k` (0-based), a static string; null when `k` is out of range.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_style_name(k: i32) -> *const c_char {
    usize::try_from(k)
        .ok()
        .and_then(|k| style_names().get(k))
        .map_or(std::ptr::null(), |(n, _)| n.as_ptr())
}

/// The line LAMMPS prints when pair style `k` is registered ("pair_style NAME (dpdnl: …)"), a
/// static string; null when `k` is out of range.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_style_info(k: i32) -> *const c_char {
    usize::try_from(k)
        .ok()
        .and_then(|k| style_names().get(k))
        .map_or(std::ptr::null(), |(_, i)| i.as_ptr())
}

/// The handle behind `h`.
///
/// # Safety
/// `h` is null or a live handle not used concurrently.
unsafe fn handle<'a>(h: *mut DpdnlPair) -> Result<&'a mut DpdnlPair, Error> {
    // SAFETY: caller's contract.
    unsafe { h.as_mut() }.ok_or_else(|| Error::null("pair handle"))
}

/// A type count from C (at least 1: LAMMPS may define a pair style before its box).
fn type_count(ntypes: i32) -> usize {
    usize::try_from(ntypes).unwrap_or(0).max(1)
}

/// Words as owned strings.
fn owned(w: &[&str]) -> Vec<String> {
    w.iter().map(|s| s.to_string()).collect()
}

/// Write a new handle for `style` through `out` (null first, so a failure leaves null).
///
/// # Safety
/// `out` is null or valid for writing.
unsafe fn emit(out: *mut *mut DpdnlPair, style: Box<dyn PairStyle>) -> Result<(), Error> {
    let h = Box::new(DpdnlPair {
        style,
        special: [1.0; 4],
        typ: Vec::new(),
        text: Vec::new(),
        workers: None,
        launch: None,
        working: WorkingList::default(),
    });
    // SAFETY: forwarded caller's contract.
    unsafe { put(out, Box::into_raw(h)) }
}

/// A new pair style `name` ("dpd/nonlinear", "sdpd") from the words after the name (LAMMPS's
/// `Pair::settings(narg, arg)`) for `ntypes` atom types; `*out` gets a handle to release with
/// [`dpdnl_pair_free`] (null on failure, the message says why).
///
/// # Safety
/// `name` is a NUL-terminated string; `arg` points to `narg` NUL-terminated strings; `out` is
/// valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_new(
    name: *const c_char,
    narg: i32,
    arg: *const *const c_char,
    ntypes: i32,
    out: *mut *mut DpdnlPair,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        unsafe { put(out, std::ptr::null_mut())? };
        // SAFETY: forwarded caller's contract.
        let (name, w) = unsafe { (c_str(name, "name")?, words(narg, arg)?) };
        let style =
            new_pair_style(name, &owned(&w), type_count(ntypes), 1.0).map_err(Error::invalid)?;
        // SAFETY: forwarded caller's contract.
        unsafe { emit(out, style) }
    })
}

/// Release a handle (null is ignored).
///
/// # Safety
/// `h` is null or a live handle, not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_free(h: *mut DpdnlPair) {
    if !h.is_null() {
        // SAFETY: a pointer from Box::into_raw in `emit`, freed once (caller's contract).
        drop(unsafe { Box::from_raw(h) });
    }
}

/// The same pair style given again with new settings (the words after its name): the
/// coefficients are kept under the style's rule (`PairStyle::restyle`).
///
/// # Safety
/// `h` is a live handle; `arg` points to `narg` NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_settings(
    h: *mut DpdnlPair,
    narg: i32,
    arg: *const *const c_char,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, w) = unsafe { (handle(h)?, words(narg, arg)?) };
        h.style.restyle(&owned(&w)).map_err(Error::invalid)
    })
}

/// Apply one `pair_coeff` line (all its words, types first: LAMMPS's `Pair::coeff(narg, arg)`)
/// with `ntypes` atom types (the style's tables grow when the box has more types than the
/// style was made for).
///
/// # Safety
/// `h` is a live handle; `arg` points to `narg` NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_coeff(
    h: *mut DpdnlPair,
    ntypes: i32,
    narg: i32,
    arg: *const *const c_char,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, w) = unsafe { (handle(h)?, words(narg, arg)?) };
        let nt = type_count(ntypes);
        if nt != h.style.ntypes() {
            h.style =
                from_restart_lines(&h.style.restart_lines(), nt, 1.0).map_err(Error::invalid)?;
        }
        h.style.coeff(&owned(&w)).map_err(Error::invalid)
    })
}

/// Whether type pair (i, j) has coefficients (`*set` 1 or 0), and its cut-off in `*rc`.
///
/// # Safety
/// `h` is a live handle; `rc` and `set` are valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_cutoff(
    h: *mut DpdnlPair,
    i: i32,
    j: i32,
    rc: *mut f64,
    set: *mut i32,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let (i, j) = type_pair(h, i, j)?;
        let c = h.style.cutoff(i, j);
        // SAFETY: valid for writing (caller's contract).
        unsafe {
            put(rc, c.unwrap_or(0.0))?;
            put(set, i32::from(c.is_some()))
        }
    })
}

/// The most threads [`dpdnl_pair_threads`] accepts.
const MAX_THREADS: i32 = 1024;

/// The number of threads of [`dpdnl_pair_compute`] on this handle (1 to 1024; 1 when never
/// set). The LAMMPS styles pass LAMMPS's OpenMP threads per MPI rank (`package omp N`, `-pk omp
/// N`, `-sf omp`, or `OMP_NUM_THREADS` at start-up) before every run's set-up
/// ([`dpdnl_pair_init`] then names a count above 1 in its notes). Forces, energy and
/// virial are the same bits for every count: the rows are evaluated in parallel, and every sum is
/// formed in list order as with one thread. The threads are the host's when it handed over a
/// launcher ([`dpdnl_pair_launcher`]), else they come from a pool per count, created once and
/// shared by the handles. sDPD's pre-pass ([`dpdnl_pair_prepass`]) runs on one thread.
///
/// # Safety
/// `h` is a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_threads(h: *mut DpdnlPair, threads: i32) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        if !(1..=MAX_THREADS).contains(&threads) {
            return Err(Error::invalid(format!(
                "threads = {threads} must be in 1..={MAX_THREADS}"
            )));
        }
        let n = threads as usize;
        if h.workers.as_ref().map_or(1, Workers::threads) != n {
            h.workers = if n > 1 {
                Some(Workers::new(n, h.launch)?)
            } else {
                None
            };
        }
        Ok(())
    })
}

/// The host's threads for [`dpdnl_pair_compute`]'s threaded walk ([`dpdnl_pair_threads`] above
/// 1): `launch` runs a team body on `nthreads` threads and returns when all are done
/// ([`DpdnlLaunch`]); null: this library's own pool. The LAMMPS styles pass an OpenMP parallel
/// region when they are compiled with OpenMP against LAMMPS's OpenMP runtime, so that the
/// force pass runs on LAMMPS's own OpenMP threads: a pool of other threads would compete for
/// the cores with LAMMPS's threads, which wait busily between their loops (with `package omp
/// 2`, 2 cores: the plugin's 2 threads were slower than 1). The bits are the same either way.
///
/// # Safety
/// `h` is a live handle; `launch` is null or keeps [`DpdnlLaunch`]'s contract while `h` lives.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_launcher(
    h: *mut DpdnlPair,
    launch: DpdnlLaunch,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        h.launch = launch;
        match &mut h.workers {
            Some(w) => w.set_launch(launch),
            None => Ok(()),
        }
    })
}

/// Checked 1-based types of the style.
fn type_pair(h: &DpdnlPair, i: i32, j: i32) -> Result<(usize, usize), Error> {
    let nt = h.style.ntypes() as i32;
    if !(1..=nt).contains(&i) || !(1..=nt).contains(&j) {
        return Err(Error::invalid(format!("types {i} {j} outside 1..={nt}")));
    }
    Ok((i as usize, j as usize))
}

/// What the style needs from its driver (a null handle gives all zeros).
///
/// # Safety
/// `h` is null or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_info(h: *const DpdnlPair) -> DpdnlPairInfo {
    // SAFETY: caller's contract.
    let Some(h) = (unsafe { h.as_ref() }) else {
        return DpdnlPairInfo::default();
    };
    let s = &h.style;
    DpdnlPairInfo {
        values_per_atom: i32::from(s.prepass().is_some()),
        single: i32::from(s.pairwise()),
        data: i32::from(s.writes_data()),
    }
}

/// A set-up error as LAMMPS users meet it: a type pair without coefficients in the top-level
/// style is most often meant for another style, which `pair_style hybrid` provides.
fn lammps_hint(e: String) -> String {
    if e.contains("are not set (pair_coeff)") {
        format!(
            "{e}; as the top-level pair style this style needs coefficients for every type pair \
             (under pair_style hybrid or hybrid/overlay it may take some type pairs only, the \
             others going to other styles)"
        )
    } else {
        e
    }
}

/// Set-up of a run (`Pair::init_style`): every pair set (as a sub-style, `setup.substyle`,
/// the pairs with coefficients only; the others get no interaction and `*rc_max` is over the
/// style's own pairs), kT = boltz T in the host's units,
/// (η, Sc) targets resolved at the current density, the per-run tables built, the Euler
/// warning. `*rc_max` gets the largest cut-off; [`crate::dpdnl_last_message`] holds the lines
/// to log, one per line, warnings starting with "WARNING: ".
///
/// # Safety
/// `h` is a live handle; `setup` is valid for reading (its `mass` null or `ntypes + 1`
/// doubles, its `units.style` a NUL-terminated string); `rc_max` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_init(
    h: *mut DpdnlPair,
    setup: *const DpdnlSetup,
    rc_max: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, s) = unsafe {
            (
                handle(h)?,
                setup.as_ref().ok_or_else(|| Error::null("setup"))?,
            )
        };
        let nt = h.style.ntypes();
        let dim = match s.dimension {
            2 => 2,
            3 => 3,
            d => return Err(Error::invalid(format!("dimension {d} must be 2 or 3"))),
        };
        if !(s.dt.is_finite() && s.dt > 0.0) {
            return Err(Error::invalid(format!("timestep {} must be > 0", s.dt)));
        }
        // SAFETY: forwarded caller's contract.
        let units = unsafe { units_of(&s.units)? };
        let mass: Vec<Option<f64>> = if s.mass.is_null() {
            vec![None; nt + 1]
        } else {
            // SAFETY: ntypes + 1 doubles (caller's contract).
            let m = unsafe { slice(s.mass, nt + 1, "mass")? };
            m.iter()
                .enumerate()
                .map(|(t, &x)| (t > 0).then_some(x))
                .collect()
        };
        let natoms = usize::try_from(s.natoms).unwrap_or(0);
        let special = if s.special_lj.is_null() {
            [1.0; 4]
        } else {
            // SAFETY: 4 doubles (caller's contract).
            let f = unsafe { slice(s.special_lj, 4, "special_lj")? };
            [1.0, f[1], f[2], f[3]]
        };
        check_special(&*h.style, special).map_err(Error::invalid)?;
        h.special = special;
        let ctx = SetupContext {
            dim,
            natoms,
            density: s.natoms as f64 / s.volume,
            mass: &mass,
            dt: s.dt,
            euler: s.euler != 0,
            special_lj: special,
            units,
            substyle: s.substyle != 0,
        };
        let notes = h
            .style
            .setup(&ctx)
            .map_err(|e| Error::invalid(lammps_hint(e)))?;
        let mut text: Vec<String> = notes
            .into_iter()
            .map(|n| match n {
                SetupNote::Info(t) => t,
                SetupNote::Warning(t) => format!("WARNING: {t}"),
            })
            .collect();
        if let Some(w) = &h.workers {
            text.push(format!(
                "pair_style {}: {} threads per MPI task, {} (the same bits for every count)",
                h.style.name(),
                w.threads(),
                if w.on_host_threads() {
                    "on the host's threads (LAMMPS: its OpenMP threads)"
                } else {
                    "on dpdnl's own thread pool"
                }
            ));
        }
        // SAFETY: valid for writing (caller's contract).
        unsafe { put(rc_max, h.style.rc_max())? };
        set_last_message(&text.join("\n"));
        Ok(())
    })
}

/// The special-bond factors in force for the next [`dpdnl_pair_compute`] (LAMMPS's
/// `force->special_lj`, 4 doubles: entry 0 unused, then 1-2, 1-3, 1-4), given before every
/// evaluation: under `pair_style hybrid`, `pair_modify pair NAME special lj …` sets a sub-style's
/// own factors only around its evaluation, after its set-up. Factors equal to the last ones
/// change nothing; others are checked as at set-up (`check_special`) and the style's scaled
/// coefficient blocks rebuilt.
///
/// # Safety
/// `h` is a live handle; `special_lj` is null (no change) or holds 4 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_special(
    h: *mut DpdnlPair,
    special_lj: *const f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        if special_lj.is_null() {
            return Ok(());
        }
        // SAFETY: 4 doubles (caller's contract).
        let f = unsafe { slice(special_lj, 4, "special_lj")? };
        let special = [1.0, f[1], f[2], f[3]];
        if special != h.special {
            check_special(&*h.style, special).map_err(Error::invalid)?;
            h.style.set_special(special);
            h.special = special;
        }
        Ok(())
    })
}

/// Positions (`3 nall`), types (`nall`), nlocal and nall of one rank's atoms.
type AtomViews<'a> = (&'a [f64], &'a [i32], usize, usize);

/// Checked views of the atoms' positions and types (`nall` entries).
///
/// # Safety
/// As [`DpdnlAtoms`].
unsafe fn positions_types<'a>(a: &DpdnlAtoms, nt: usize) -> Result<AtomViews<'a>, Error> {
    if a.nlocal < 0 || a.nall < a.nlocal {
        return Err(Error::invalid(format!(
            "nlocal = {} and nall = {} must satisfy 0 <= nlocal <= nall",
            a.nlocal, a.nall
        )));
    }
    let (nlocal, nall) = (a.nlocal as usize, a.nall as usize);
    // SAFETY: sizes as documented on DpdnlAtoms (caller's contract).
    let (x, ty) = unsafe {
        (
            slice(a.x, 3 * nall, "x")?,
            slice(a.atom_type, nall, "type")?,
        )
    };
    if let Some(bad) = ty.iter().position(|&t| t < 1 || t as usize > nt) {
        return Err(Error::invalid(format!(
            "atom {bad} has type {} outside 1..={nt}",
            ty[bad]
        )));
    }
    Ok((x, ty, nlocal, nall))
}

/// The style's tables exist (its set-up ran for these types).
fn ready(h: &DpdnlPair) -> Result<(), Error> {
    let n = h.style.ntypes() + 1;
    if h.style.cut_table().len() != n * n {
        return Err(Error::invalid("dpdnl_pair_init has not run"));
    }
    Ok(())
}

/// The style's pre-pass and type count, after its set-up (a style without one is an error).
fn prepass_of(h: &DpdnlPair) -> Result<(&dyn dpdnl::host::PrePass, usize), Error> {
    ready(h)?;
    let pp = h
        .style
        .prepass()
        .ok_or_else(|| Error::invalid(format!("{} has no pre-pass", h.style.name())))?;
    Ok((pp, h.style.ntypes()))
}

/// The pre-pass, pass 1: `values[0..nall]` is overwritten with Σ_j w(r_ij) over the half list
/// `list`, added to i and to j (j owned, or any j when `newton_pair` is non-zero), without the
/// self term. A style without a pre-pass is an error.
///
/// # Safety
/// `h` is a live handle; `atoms` and `list` as for [`dpdnl_pair_compute`]; `values` holds `nall`
/// doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_prepass(
    h: *mut DpdnlPair,
    atoms: *const DpdnlAtoms,
    list: *const DpdnlNeighList,
    newton_pair: i32,
    values: *mut f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a, list) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
                list.as_ref().ok_or_else(|| Error::null("list"))?,
            )
        };
        let (pp, nt) = prepass_of(h)?;
        // SAFETY: forwarded caller's contract.
        let (x, ty, nlocal, nall) = unsafe { positions_types(a, nt)? };
        // SAFETY: nall doubles (caller's contract).
        let rho = unsafe { slice_mut(values, nall, "values")? };
        rho.fill(0.0);
        let newton = newton_pair != 0;
        let rcsq = pp.rcsq();
        let rule = SpecialRule::new(h.special, h.style.scales_special(), nt);
        // SAFETY: forwarded caller's contract.
        unsafe {
            for_each_row(list, nall, |i, jlist, mask| {
                let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
                let row = ty[i] as usize * (nt + 1);
                let mut di = 0.0;
                for &jraw in jlist {
                    // A bonded neighbour of factor 0 is not in the sum (fractional factors
                    // are refused at set-up: `check_special`).
                    if rule.excludes(special_class(jraw)) {
                        continue;
                    }
                    let j = jraw as u32 as usize & mask;
                    let k = row + ty[j] as usize;
                    let dr = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
                    let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
                    if rsq < rcsq[k] {
                        let w = pp.weight(k, rsq);
                        di += w;
                        if newton || j < nlocal {
                            rho[j] += w;
                        }
                    }
                }
                rho[i] += di;
                Ok(())
            })?
        };
        Ok(())
    })
}

/// The pre-pass's end for the owned atoms: each value completed (its self term), and the
/// per-atom energy added to `tally->eng_vdwl` (when `eflag_global`) and `tally->eatom[i]` (when
/// not null). A non-finite state is an error naming the atom's tag (`tag` may be null: the
/// index is named).
///
/// # Safety
/// `h` is a live handle; `atoms` as for [`dpdnl_pair_compute`] (types and tags of the owned atoms are
/// read); `values` holds `nlocal` doubles; `tally` is null or as for [`dpdnl_pair_compute`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_prepass_finish(
    h: *mut DpdnlPair,
    atoms: *const DpdnlAtoms,
    step: i64,
    values: *mut f64,
    tally: *const DpdnlTally,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
            )
        };
        let (pp, nt) = prepass_of(h)?;
        // SAFETY: forwarded caller's contract.
        let (_, ty, nlocal, _) = unsafe { positions_types(a, nt)? };
        // SAFETY: nlocal entries (caller's contract).
        let (rho, tag) = unsafe {
            (
                slice_mut(values, nlocal, "values")?,
                if a.tag.is_null() {
                    &[][..]
                } else {
                    slice(a.tag, nlocal, "tag")?
                },
            )
        };
        // SAFETY: null or valid (caller's contract).
        let t = unsafe { tally.as_ref() }.copied();
        let mut energy = 0.0;
        // SAFETY: nall >= nlocal doubles when non-null (caller's contract).
        let mut eatom = match t {
            Some(t) if !t.eatom.is_null() => Some(unsafe { slice_mut(t.eatom, nlocal, "eatom")? }),
            _ => None,
        };
        let step = step.max(0) as u64;
        for i in 0..nlocal {
            let ti = ty[i] as usize;
            let d = pp.complete(ti, rho[i]);
            rho[i] = d;
            let Some(u) = pp.energy_of(ti, d) else {
                let who = tag.get(i).map_or(format!("index {i}"), |t| t.to_string());
                return Err(Error::invalid(pp.fault(&who, d, step)));
            };
            energy += u;
            if let Some(e) = eatom.as_deref_mut() {
                e[i] += u;
            }
        }
        if let Some(t) = t
            && t.eflag_global != 0
        {
            // SAFETY: valid for reading and writing when eflag_global (caller's contract).
            let e = unsafe { t.eng_vdwl.as_mut() }.ok_or_else(|| Error::null("eng_vdwl"))?;
            *e += energy;
        }
        Ok(())
    })
}

/// The pair forces of every listed pair of one LAMMPS neighbour list through the style's
/// kernel, accumulated into `f` (`nall * 3` doubles, LAMMPS `&f[0][0]`), with energy and virial
/// tallied into `tally` (null when nothing is tallied). Half list (`full == 0`): each listed
/// pair once; the force on i is added, the force on j subtracted if `newton_pair` or j is
/// owned; energy and virial as LAMMPS's `ev_tally` (newton on: the whole pair; off: half for
/// each owned partner; per-atom halves likewise). Full list: only i's force, and half of the
/// pair's energy and virial to i (`ev_tally_full`). A style with a pre-pass reads every atom's
/// value from `values[0..nall]` (owned and ghost atoms, ghosts communicated); `values` may be
/// null for the others.
///
/// # Safety
/// `h` is a live handle; every non-null pointer in `atoms`, `list`, `step`, `tally` and `f` is
/// valid for the sizes documented on those structs and not aliased by another argument;
/// `values` is null or holds `nall` doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_compute(
    h: *mut DpdnlPair,
    atoms: *const DpdnlAtoms,
    list: *const DpdnlNeighList,
    step: *const DpdnlStep,
    values: *const f64,
    f: *mut f64,
    tally: *mut DpdnlTally,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a, list, st) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
                list.as_ref().ok_or_else(|| Error::null("list"))?,
                step.as_ref().ok_or_else(|| Error::null("step"))?,
            )
        };
        ready(h)?;
        if !(st.dt.is_finite() && st.dt > 0.0) {
            return Err(Error::invalid(format!(
                "time step dt = {} must be a finite number > 0",
                st.dt
            )));
        }
        let nt = h.style.ntypes();
        if h.style.prepass().is_some() {
            // SAFETY: forwarded caller's contract.
            let (_, ty, _, nall) = unsafe { positions_types(a, nt)? };
            // SAFETY: nall doubles (caller's contract).
            let rho = unsafe { slice(values, nall, "values")? };
            h.typ.clear();
            h.typ.extend(ty.iter().map(|&t| t as u32));
            h.style.set_atom_values(rho, &h.typ);
        }
        h.style.set_timestep(st.dt);
        let style = &*h.style;
        let kernel = style.kernel(Isa::detect());
        let workers = h.workers.as_mut();
        let special = SpecialRule::new(h.special, style.scales_special(), nt);
        // SAFETY: null or valid (caller's contract).
        let t = unsafe { tally.as_ref() }.copied();
        // SAFETY: forwarded caller's contract.
        unsafe {
            walk_pairs(
                &*kernel,
                style.cut_table(),
                nt,
                Some(special),
                a,
                list,
                st,
                f,
                t,
                workers,
                Some(&mut h.working),
            )
        }
    })
}

/// Separates the words of a line in the restart text.
const WORD_SEP: char = '\u{1f}';
/// The first line of the restart text.
const RESTART_MAGIC: &str = "dpdnl-pair-restart 1";

/// The style as restart text (its `restart_lines`: the `pair_style` line and, unless
/// `settings_only`, its `pair_coeff` lines): `*data` and `*len` get bytes valid until the next
/// call on `h`. [`dpdnl_pair_from_restart`] reads them back.
///
/// # Safety
/// `h` is a live handle; `data` and `len` are valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_restart(
    h: *mut DpdnlPair,
    settings_only: i32,
    data: *mut *const c_char,
    len: *mut i64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let mut lines = h.style.restart_lines();
        if settings_only != 0 {
            lines.truncate(1);
        }
        let mut text = String::from(RESTART_MAGIC);
        for l in &lines {
            text.push('\n');
            text.push_str(&l.join(&WORD_SEP.to_string()));
        }
        h.text = text.into_bytes();
        // SAFETY: valid for writing (caller's contract).
        unsafe {
            put(data, h.text.as_ptr().cast::<c_char>())?;
            put(len, h.text.len() as i64)
        }
    })
}

/// A style from the text of [`dpdnl_pair_restart`] (`len` bytes at `data`) for `ntypes` types;
/// `*out` gets a new handle (null on failure: a corrupt or foreign text is named).
///
/// # Safety
/// `data` holds `len` bytes; `out` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_from_restart(
    data: *const c_char,
    len: i64,
    ntypes: i32,
    out: *mut *mut DpdnlPair,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        unsafe { put(out, std::ptr::null_mut())? };
        let n = usize::try_from(len)
            .map_err(|_| Error::invalid(format!("restart text length {len} < 0")))?;
        // SAFETY: `len` bytes (caller's contract).
        let bytes = unsafe { slice(data.cast::<u8>(), n, "data")? };
        let corrupt = |why: &str| Error::invalid(format!("corrupt pair style restart text: {why}"));
        let text = std::str::from_utf8(bytes).map_err(|_| corrupt("not UTF-8"))?;
        let mut it = text.split('\n');
        if it.next() != Some(RESTART_MAGIC) {
            return Err(corrupt("no 'dpdnl-pair-restart 1' header"));
        }
        let lines: Vec<Vec<String>> = it
            .map(|l| l.split(WORD_SEP).map(str::to_string).collect())
            .collect();
        let style = from_restart_lines(&lines, type_count(ntypes), 1.0).map_err(Error::invalid)?;
        // SAFETY: forwarded caller's contract.
        unsafe { emit(out, style) }
    })
}

/// The numbers of a `write_data` coefficient line of type pair (i, j): up to `cap` doubles into
/// `out`, their count in `*n` (0 when the style writes no data coefficients or the pair is not
/// set).
///
/// # Safety
/// `h` is a live handle; `out` holds `cap` doubles; `n` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_data(
    h: *mut DpdnlPair,
    i: i32,
    j: i32,
    out: *mut f64,
    cap: i32,
    n: *mut i32,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let (i, j) = type_pair(h, i, j)?;
        let v = h.style.data_coeffs(i, j).unwrap_or_default();
        let cap = usize::try_from(cap).unwrap_or(0);
        if v.len() > cap {
            return Err(Error::invalid(format!(
                "{} numbers do not fit in {cap}",
                v.len()
            )));
        }
        // SAFETY: `cap` doubles (caller's contract).
        let dst = unsafe { slice_mut(out, v.len(), "out")? };
        dst.copy_from_slice(&v);
        // SAFETY: valid for writing (caller's contract).
        unsafe { put(n, v.len() as i32) }
    })
}

/// LAMMPS's `Pair::single` for types (i, j) at distance² `rsq`: the conservative force F/r
/// into `*fforce` and the energy into the return slot `*energy`, both scaled by `factor`
/// (LAMMPS's special-bond factor, as `pair dpd` scales them). A style without a pair-wise
/// answer (many-body) is an error.
///
/// # Safety
/// `h` is a live handle; `fforce` and `energy` are valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_single(
    h: *mut DpdnlPair,
    i: i32,
    j: i32,
    rsq: f64,
    factor: f64,
    fforce: *mut f64,
    energy: *mut f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let h = unsafe { handle(h)? };
        let (i, j) = type_pair(h, i, j)?;
        if h.style.cutoff(i, j).is_none() {
            return Err(Error::invalid(format!(
                "pair_style {} has no coefficients for types {i} {j} (single)",
                h.style.name()
            )));
        }
        let (fpair, e) = h.style.single(i, j, rsq).ok_or_else(|| {
            Error::invalid(format!("pair style {} has no single()", h.style.name()))
        })?;
        // SAFETY: valid for writing (caller's contract).
        unsafe {
            put(fforce, factor * fpair)?;
            put(energy, factor * e)
        }
    })
}
