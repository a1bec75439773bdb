//! `dpdnl-capi`: a C ABI over the `dpdnl` pair kernels, for the LAMMPS shim and other C/C++
//! callers. The header `capi/include/dpdnl.h` is generated from this file by cbindgen (the test
//! `tests/header.rs` fails when the committed header is stale; `DPDNL_BLESS_HEADER=1` rewrites it).
//!
//! # Contract
//! - Every function returns a [`DpdnlStatus`]; on failure a message is kept per thread and
//!   [`dpdnl_last_error`] returns it. No panic ever unwinds into the caller: every entry point runs
//!   inside `catch_unwind` and turns a panic into [`DpdnlStatus::Internal`].
//! - Parameters are validated here, once, with the core crate's own checks
//!   ([`PairCoeff::validate`], [`Weight::new`], [`Friction::from_keyword`], [`Noise::from_keyword`]);
//!   the kernels then trust them.
//! - [`dpdnl_compute`] walks a whole LAMMPS neighbour list in Rust: the hot loop never crosses the
//!   boundary per pair. Pairs in range are evaluated in batches of 64 by
//!   [`dpdnl::kernel::pair_forces_batch`] (SIMD lanes, the same bits as `pair_force`), and their
//!   forces and tallies are added in list order, so the result is that of the pair-by-pair loop.
//!   Forces, energy and virial follow LAMMPS's `ev_tally` (half list, newton on/off) and
//!   `ev_tally_full` (full list) conventions.
//! - The pair random number is [`dpdnl::rng::pair_gaussian`] keyed by (seed, step, tags), so every
//!   decomposition (MPI ranks, newton on/off) draws the same ξ_ij for the same pair and step.

use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

use dpdnl::engine::pair::{Batcher, DpdKernel, lane_force};
use dpdnl::kernel::{
    Friction, Isa, Noise, PairBatch, PairCoeff, PairInput, PairModel, PairTable, Weight, pair_force,
};
use dpdnl::rng::pair_gaussian;

mod styles;
pub use styles::*;

/// Result of every fallible call. Anything but `Ok` leaves a message for [`dpdnl_last_error`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DpdnlStatus {
    /// Success.
    Ok = 0,
    /// A required pointer was null.
    NullPointer = 1,
    /// An argument is out of range or malformed (the message names it).
    InvalidArgument = 2,
    /// A type pair has no coefficients (the message names the first one).
    Incomplete = 3,
    /// A bug inside the library (a caught panic); the message says where.
    Internal = 4,
}

/// The validated parameter table of `pair_style dpd/nonlinear` + `pair_coeff` (opaque to C).
pub struct DpdnlParams {
    kt: f64,
    seed: u32,
    friction: Friction,
    noise: Noise,
    weight: Weight,
    ntypes: usize,
    /// `coeff[i * (ntypes + 1) + j]`, types 1-based; `None` until set.
    coeff: Vec<Option<PairCoeff>>,
}

/// The four force parts of one pair as projections on e_ij, plus the conservative energy and
/// 1/r (force on i = `(fc + fd + fr + fa) * inv_r * r_ij`). Mirrors `dpdnl::kernel::PairForce`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DpdnlPairForce {
    /// Conservative part.
    pub fc: f64,
    /// Dissipative part.
    pub fd: f64,
    /// Random part.
    pub fr: f64,
    /// Spurious-drift correction (`noise corrected` only).
    pub fa: f64,
    /// Conservative pair energy a r_c (1 − r/r_c)² / 2.
    pub energy: f64,
    /// 1/r (0 when the pair is outside the cut-off).
    pub inv_r: f64,
}

/// Per-atom arrays of one MPI rank, owned atoms first then ghosts (LAMMPS layout).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlAtoms {
    /// Positions, `nall * 3` doubles (LAMMPS `&x[0][0]`).
    pub x: *const f64,
    /// Velocities, `nall * 3` doubles; ghost velocities must be current (`comm_modify vel yes`).
    pub v: *const f64,
    /// Global ids (LAMMPS `tagint`, 32-bit under SMALLBIG), `nall` entries, all > 0.
    pub tag: *const i32,
    /// Atom types, 1-based, `nall` entries.
    pub atom_type: *const i32,
    /// Per-type masses, 1-based: `ntypes + 1` entries (entry 0 unused). Ignored if `rmass` is set.
    pub mass: *const f64,
    /// Per-atom masses (`nall` entries), or null to use `mass`.
    pub rmass: *const f64,
    /// Number of owned atoms.
    pub nlocal: i32,
    /// Owned plus ghost atoms.
    pub nall: i32,
}

/// A LAMMPS neighbour list (`NeighList`): `inum`, `ilist`, `numneigh`, `firstneigh`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlNeighList {
    /// Number of atoms with a list.
    pub inum: i32,
    /// Their indices, `inum` entries.
    pub ilist: *const i32,
    /// `numneigh[i]`: length of atom i's list, valid for every i in `ilist`.
    pub numneigh: *const i32,
    /// `firstneigh[i]`: atom i's neighbours, valid for every i in `ilist`.
    pub firstneigh: *const *const i32,
    /// Mask applied to every neighbour entry (LAMMPS `NEIGHMASK`; the upper bits flag special
    /// bonds). 0x3FFFFFFF in LAMMPS 2021–2022, 0x1FFFFFFF in later versions: pass the header's.
    pub neighmask: i32,
    /// 0: half list (each pair once); 1: full list (each pair seen from both atoms).
    pub full: i32,
}

/// Step-level settings of one force evaluation.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlStep {
    /// Time step number used as the key of the pair noise (LAMMPS `update->ntimestep`), ≥ 0.
    pub step: i64,
    /// Time step δt (> 0): the random force scales as δt^(−1/2).
    pub dt: f64,
    /// LAMMPS `force->newton_pair` (half lists: 1 also updates ghost forces).
    pub newton_pair: i32,
    /// 2 or 3. Coordinates are used as given (z = 0 in 2-D under `fix enforce2d`).
    pub dimension: i32,
}

/// Energy and virial accumulators, following LAMMPS `Pair::ev_tally` / `ev_tally_full`.
/// Every pointer may be null when its flag is 0; results are added to what is there.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlTally {
    /// Nonzero: add the conservative energy to `*eng_vdwl`.
    pub eflag_global: i32,
    /// Nonzero: add the pair virial to `virial[0..6]` (xx, yy, zz, xy, xz, yz).
    pub vflag_global: i32,
    /// Global energy accumulator (LAMMPS `Pair::eng_vdwl`).
    pub eng_vdwl: *mut f64,
    /// Global virial accumulator, 6 doubles (LAMMPS `Pair::virial`).
    pub virial: *mut f64,
    /// Per-atom energy (`nall` doubles) or null.
    pub eatom: *mut f64,
    /// Per-atom virial (`nall * 6` doubles, LAMMPS `&vatom[0][0]`) or null.
    pub vatom: *mut f64,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

struct Error {
    status: DpdnlStatus,
    message: String,
}

impl Error {
    fn invalid(message: impl Into<String>) -> Error {
        Error {
            status: DpdnlStatus::InvalidArgument,
            message: message.into(),
        }
    }
    fn null(what: &str) -> Error {
        Error {
            status: DpdnlStatus::NullPointer,
            message: format!("{what} is a null pointer"),
        }
    }
}

fn set_last_error(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

/// Run one entry point: clear the message, catch any panic, turn errors into codes and text.
fn guard(f: impl FnOnce() -> Result<(), Error>) -> DpdnlStatus {
    set_last_error("");
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => DpdnlStatus::Ok,
        Ok(Err(e)) => {
            set_last_error(&e.message);
            e.status
        }
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            set_last_error(&format!("internal error in dpdnl (a bug): {what}"));
            DpdnlStatus::Internal
        }
    }
}

/// Read a C string argument.
///
/// # Safety
/// `p` is null or points to a NUL-terminated string valid for the call.
unsafe fn c_str<'a>(p: *const c_char, what: &str) -> Result<&'a str, Error> {
    if p.is_null() {
        return Err(Error::null(what));
    }
    // SAFETY: non-null and NUL-terminated by the caller's contract.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map_err(|_| Error::invalid(format!("{what} is not valid UTF-8")))
}

/// A shared slice from a C pointer and a length; a null pointer is accepted only when `len == 0`.
///
/// # Safety
/// If `len > 0`, `p` points to `len` initialised `T`s valid (and not mutated) for `'a`.
unsafe fn slice<'a, T>(p: *const T, len: usize, what: &str) -> Result<&'a [T], Error> {
    if len == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(Error::null(what));
    }
    // SAFETY: non-null, `len` valid elements by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

/// A mutable slice from a C pointer and a length; null accepted only when `len == 0`.
///
/// # Safety
/// If `len > 0`, `p` points to `len` initialised `T`s, valid and not aliased for `'a`.
unsafe fn slice_mut<'a, T>(p: *mut T, len: usize, what: &str) -> Result<&'a mut [T], Error> {
    if len == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(Error::null(what));
    }
    // SAFETY: non-null, `len` valid, unaliased elements by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

impl DpdnlParams {
    fn new(
        kt: f64,
        seed: i64,
        friction: &str,
        noise: &str,
        weight_s: f64,
        ntypes: i32,
    ) -> Result<DpdnlParams, Error> {
        if !(kt.is_finite() && kt > 0.0) {
            return Err(Error::invalid(format!(
                "temperature kT = {kt} must be a finite number > 0"
            )));
        }
        if !(1..=i64::from(i32::MAX)).contains(&seed) {
            return Err(Error::invalid(format!(
                "seed = {seed} must be an integer in 1..={}",
                i32::MAX
            )));
        }
        let friction = Friction::from_keyword(friction).ok_or_else(|| {
            Error::invalid(format!(
                "unknown friction '{friction}' (expected none, cross or dot)"
            ))
        })?;
        let noise = Noise::from_keyword(noise).ok_or_else(|| {
            Error::invalid(format!(
                "unknown noise '{noise}' (expected plain, corrected or twostep)"
            ))
        })?;
        let weight = Weight::new(weight_s).ok_or_else(|| {
            Error::invalid(format!(
                "weight exponent s = {weight_s} must be a finite number > 0"
            ))
        })?;
        if ntypes < 1 {
            return Err(Error::invalid(format!(
                "number of atom types = {ntypes} must be >= 1"
            )));
        }
        let ntypes = ntypes as usize;
        Ok(DpdnlParams {
            kt,
            seed: seed as u32,
            friction,
            noise,
            weight,
            ntypes,
            coeff: vec![None; (ntypes + 1) * (ntypes + 1)],
        })
    }

    fn type_index(&self, t: i32, what: &str) -> Result<usize, Error> {
        if t < 1 || t as usize > self.ntypes {
            return Err(Error::invalid(format!(
                "{what} = {t} is not an atom type in 1..={}",
                self.ntypes
            )));
        }
        Ok(t as usize)
    }

    fn coeff(&self, i: i32, j: i32) -> Result<PairCoeff, Error> {
        let (i, j) = (self.type_index(i, "type I")?, self.type_index(j, "type J")?);
        self.coeff[i * (self.ntypes + 1) + j].ok_or_else(|| Error {
            status: DpdnlStatus::Incomplete,
            message: format!("pair coefficients for types {i} {j} are not set"),
        })
    }

    fn model(&self, dt: f64) -> Result<PairModel, Error> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid(format!(
                "time step dt = {dt} must be a finite number > 0"
            )));
        }
        Ok(PairModel::new(
            self.kt,
            self.friction,
            self.noise,
            self.weight,
            dt,
        ))
    }

    /// The dense table the hot loop reads; unset pairs get rc = 0 and never interact.
    fn dense_table(&self) -> Vec<PairCoeff> {
        let inert = PairCoeff {
            a: 0.0,
            gamma0: 0.0,
            gamma1: 0.0,
            rc: 0.0,
        };
        self.coeff.iter().map(|c| c.unwrap_or(inert)).collect()
    }
}

/// The library version (a static NUL-terminated string).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_version() -> *const c_char {
    c"dpdnl-capi 0.1.0".as_ptr()
}

/// The message of the last failed call on this thread ("" after a success). The pointer stays
/// valid until the next `dpdnl_*` call on the same thread.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Create a parameter table: `pair_style dpd/nonlinear` settings for `ntypes` atom types.
/// `friction` is "none", "cross" or "dot"; `noise` is "plain", "corrected" or "twostep";
/// `kt > 0`, `1 <= seed <= 2^31 − 1`, `weight_s > 0`, `ntypes >= 1`. On success `*out` holds a
/// table to release with [`dpdnl_params_free`]; on failure `*out` is null.
///
/// # Safety
/// `friction` and `noise` are NUL-terminated strings; `out` is null or valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_new(
    kt: f64,
    seed: i64,
    friction: *const c_char,
    noise: *const c_char,
    weight_s: f64,
    ntypes: i32,
    out: *mut *mut DpdnlParams,
) -> DpdnlStatus {
    guard(|| {
        if out.is_null() {
            return Err(Error::null("out"));
        }
        // SAFETY: `out` is non-null and valid for writing by the caller's contract.
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: NUL-terminated strings by the caller's contract.
        let (friction, noise) = unsafe { (c_str(friction, "friction")?, c_str(noise, "noise")?) };
        let p = DpdnlParams::new(kt, seed, friction, noise, weight_s, ntypes)?;
        // SAFETY: as above.
        unsafe { *out = Box::into_raw(Box::new(p)) };
        Ok(())
    })
}

/// Release a table from [`dpdnl_params_new`] (null is ignored).
///
/// # Safety
/// `params` is null or a pointer returned by `dpdnl_params_new` and not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_free(params: *mut DpdnlParams) {
    if params.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the pointer came from `Box::into_raw` in `dpdnl_params_new` (caller's contract).
        drop(unsafe { Box::from_raw(params) });
    }));
}

/// Check one set of pair coefficients without a table (`pair_coeff` argument validation):
/// finite a, gamma0 >= 0, gamma1 >= 0, rc > 0.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_coeff_check(a: f64, gamma0: f64, gamma1: f64, rc: f64) -> DpdnlStatus {
    guard(|| {
        PairCoeff {
            a,
            gamma0,
            gamma1,
            rc,
        }
        .validate()
        .map_err(Error::invalid)
    })
}

/// Set the coefficients of type pair (itype, jtype) and (jtype, itype); types are 1-based.
///
/// # Safety
/// `params` is null or a live table from [`dpdnl_params_new`], not used concurrently.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_set_coeff(
    params: *mut DpdnlParams,
    itype: i32,
    jtype: i32,
    a: f64,
    gamma0: f64,
    gamma1: f64,
    rc: f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live, unaliased table by the caller's contract.
        let p = unsafe { params.as_mut() }.ok_or_else(|| Error::null("params"))?;
        let (i, j) = (
            p.type_index(itype, "type I")?,
            p.type_index(jtype, "type J")?,
        );
        let c = PairCoeff {
            a,
            gamma0,
            gamma1,
            rc,
        };
        c.validate()
            .map_err(|m| Error::invalid(format!("types {i} {j}: {m}")))?;
        let n = p.ntypes + 1;
        p.coeff[i * n + j] = Some(c);
        p.coeff[j * n + i] = Some(c);
        Ok(())
    })
}

/// `Ok` if every type pair has coefficients, else `Incomplete` naming the first missing pair.
///
/// # Safety
/// `params` is null or a live table from [`dpdnl_params_new`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_params_check_complete(params: *const DpdnlParams) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live table by the caller's contract.
        let p = unsafe { params.as_ref() }.ok_or_else(|| Error::null("params"))?;
        for i in 1..=p.ntypes as i32 {
            for j in i..=p.ntypes as i32 {
                p.coeff(i, j)?;
            }
        }
        Ok(())
    })
}

/// ξ_ij, the standard Gaussian of pair (tag_i, tag_j) at `step` (`dpdnl::rng::pair_gaussian`;
/// symmetric in the tags).
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_pair_gaussian(seed: u32, step: u64, tag_i: u32, tag_j: u32) -> f64 {
    catch_unwind(|| pair_gaussian(seed, step, tag_i, tag_j)).unwrap_or(f64::NAN)
}

/// One pair through the kernel (`dpdnl::kernel::pair_force`), for tests and `Pair::single`.
/// `dr` = r_i − r_j and `dv` = v_i − v_j (3 doubles each), `inv_mass_sum` = 1/m_i + 1/m_j,
/// `xi` the pair's Gaussian, `dt` > 0. Outside the cut-off every part is 0.
///
/// # Safety
/// `params` is null or a live table; `dr`, `dv` are null or point to 3 doubles; `out` is null or
/// valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_force(
    params: *const DpdnlParams,
    itype: i32,
    jtype: i32,
    dr: *const f64,
    dv: *const f64,
    inv_mass_sum: f64,
    xi: f64,
    dt: f64,
    out: *mut DpdnlPairForce,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or a live table by the caller's contract.
        let p = unsafe { params.as_ref() }.ok_or_else(|| Error::null("params"))?;
        // SAFETY: null or 3 doubles each by the caller's contract.
        let (dr, dv) = unsafe { (slice(dr, 3, "dr")?, slice(dv, 3, "dv")?) };
        // SAFETY: null or valid for writing by the caller's contract.
        let out = unsafe { out.as_mut() }.ok_or_else(|| Error::null("out"))?;
        let c = p.coeff(itype, jtype)?;
        let model = p.model(dt)?;
        let input = PairInput {
            dr: [dr[0], dr[1], dr[2]],
            dv: [dv[0], dv[1], dv[2]],
            inv_mass_sum,
            xi,
        };
        let f = pair_force(&model, &c, &input);
        *out = DpdnlPairForce {
            fc: f.fc,
            fd: f.fd,
            fr: f.fr,
            fa: f.fa,
            energy: f.energy,
            inv_r: f.inv_r,
        };
        Ok(())
    })
}

/// All pair forces of one LAMMPS neighbour list, accumulated into `f` (`nall * 3` doubles,
/// LAMMPS `&f[0][0]`), with energy and virial tallied into `tally` (may be null when nothing is
/// tallied).
///
/// Half list (`full == 0`): each listed pair once; force on i is added, force on j subtracted if
/// `newton_pair` or j is owned; energy/virial as LAMMPS `ev_tally` (newton on: the whole pair;
/// off: half for each owned partner; per-atom halves likewise). Full list: only i's force, and
/// half of the pair's energy/virial to i (`ev_tally_full`).
///
/// # Safety
/// Every non-null pointer in `atoms`, `list`, `tally` and `f` is valid for the sizes documented
/// on those structs and not aliased by another argument; `params` is a live table.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_compute(
    params: *const DpdnlParams,
    atoms: *const DpdnlAtoms,
    list: *const DpdnlNeighList,
    step: *const DpdnlStep,
    f: *mut f64,
    tally: *mut DpdnlTally,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: each pointer is null or valid for reading by the caller's contract.
        let (p, atoms, list, step) = unsafe {
            (
                params.as_ref().ok_or_else(|| Error::null("params"))?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
                list.as_ref().ok_or_else(|| Error::null("list"))?,
                step.as_ref().ok_or_else(|| Error::null("step"))?,
            )
        };
        // SAFETY: null or valid for reading by the caller's contract.
        let tally = unsafe { tally.as_ref() }.copied();
        // SAFETY: forwarded caller's contract on every array.
        unsafe { compute(p, atoms, list, step, f, tally) }
    })
}

/// Where the tallies go, resolved to slices once.
struct Sinks<'a> {
    eng: Option<&'a mut f64>,
    virial: Option<&'a mut [f64]>,
    eatom: Option<&'a mut [f64]>,
    vatom: Option<&'a mut [f64]>,
}

/// The body of [`dpdnl_compute`].
///
/// # Safety
/// As [`dpdnl_compute`].
unsafe fn compute(
    p: &DpdnlParams,
    atoms: &DpdnlAtoms,
    list: &DpdnlNeighList,
    st: &DpdnlStep,
    f: *mut f64,
    tally: Option<DpdnlTally>,
) -> Result<(), Error> {
    if st.step < 0 {
        return Err(Error::invalid(format!("step = {} must be >= 0", st.step)));
    }
    if st.dimension != 2 && st.dimension != 3 {
        return Err(Error::invalid(format!(
            "dimension = {} must be 2 or 3",
            st.dimension
        )));
    }
    let model = p.model(st.dt)?;
    if atoms.nlocal < 0 || atoms.nall < atoms.nlocal {
        return Err(Error::invalid(format!(
            "nlocal = {} and nall = {} must satisfy 0 <= nlocal <= nall",
            atoms.nlocal, atoms.nall
        )));
    }
    if list.inum < 0 {
        return Err(Error::invalid(format!("inum = {} must be >= 0", list.inum)));
    }
    let (nlocal, nall, inum) = (
        atoms.nlocal as usize,
        atoms.nall as usize,
        list.inum as usize,
    );
    let nt = p.ntypes;
    // SAFETY: sizes as documented on `DpdnlAtoms`, `DpdnlNeighList` (caller's contract).
    let (x, v, tag, ty, ilist) = unsafe {
        (
            slice(atoms.x, 3 * nall, "x")?,
            slice(atoms.v, 3 * nall, "v")?,
            slice(atoms.tag, nall, "tag")?,
            slice(atoms.atom_type, nall, "type")?,
            slice(list.ilist, inum, "ilist")?,
        )
    };
    // SAFETY: `nall * 3` doubles, not aliased by the read-only arrays (caller's contract).
    let f = unsafe { slice_mut(f, 3 * nall, "f")? };
    if let Some(bad) = ty.iter().position(|&t| t < 1 || t as usize > nt) {
        return Err(Error::invalid(format!(
            "atom {bad} has type {} outside 1..={nt}",
            ty[bad]
        )));
    }
    // 1/m per atom (per-atom masses) or per type.
    let (inv_mass, per_atom) = if atoms.rmass.is_null() {
        // SAFETY: `ntypes + 1` doubles (caller's contract).
        let mass = unsafe { slice(atoms.mass, nt + 1, "mass")? };
        (inverse_masses(&mass[1..], 1)?, false)
    } else {
        // SAFETY: `nall` doubles (caller's contract).
        let rmass = unsafe { slice(atoms.rmass, nall, "rmass")? };
        (inverse_masses(rmass, 0)?, true)
    };
    let inv_m = |i: usize| {
        if per_atom {
            inv_mass[i]
        } else {
            inv_mass[ty[i] as usize - 1]
        }
    };
    if inum > 0 && (list.numneigh.is_null() || list.firstneigh.is_null()) {
        return Err(Error::null("numneigh/firstneigh"));
    }

    let t = tally.unwrap_or(DpdnlTally {
        eflag_global: 0,
        vflag_global: 0,
        eng_vdwl: std::ptr::null_mut(),
        virial: std::ptr::null_mut(),
        eatom: std::ptr::null_mut(),
        vatom: std::ptr::null_mut(),
    });
    // SAFETY: each is null or valid for its documented size, unaliased (caller's contract).
    let mut sinks = unsafe {
        Sinks {
            eng: if t.eflag_global != 0 {
                Some(t.eng_vdwl.as_mut().ok_or_else(|| Error::null("eng_vdwl"))?)
            } else {
                None
            },
            virial: if t.vflag_global != 0 {
                Some(slice_mut(t.virial, 6, "virial")?)
            } else {
                None
            },
            eatom: (!t.eatom.is_null())
                .then(|| slice_mut(t.eatom, nall, "eatom"))
                .transpose()?,
            vatom: (!t.vatom.is_null())
                .then(|| slice_mut(t.vatom, 6 * nall, "vatom"))
                .transpose()?,
        }
    };
    let tallying = sinks.eng.is_some()
        || sinks.virial.is_some()
        || sinks.eatom.is_some()
        || sinks.vatom.is_some();

    let table = p.dense_table();
    let ptable = PairTable::new(&model, &table);
    let full = list.full != 0;
    let newton = st.newton_pair != 0;
    let mask = list.neighmask as u32 as usize;
    let step = st.step as u64;

    // In-range pairs are gathered, in list order, into batches of BATCH (`Batcher`, the driver
    // the standalone Lees–Edwards loop uses too) evaluated through the pair-style seam
    // (`DpdKernel`: `pair_forces_batch`, the same function as `pair_force` for each pair, same
    // bits, in SIMD lanes); `Apply` then adds the forces and tallies in list order as the
    // pair-by-pair loop did, so every sum is formed in the same order.
    let kernel = DpdKernel {
        model: &model,
        table: &ptable,
        seed: p.seed,
        isa: Isa::detect(),
    };
    let mut bt = Batcher::default();
    // The lanes' v_ij, 1/m_i + 1/m_j and tags (r_ij and the coefficient index are in place).
    let gather = |b: &mut PairBatch, l: usize, i: usize, j: usize| {
        for d in 0..3 {
            b.dv[d][l] = v[3 * i + d] - v[3 * j + d];
        }
        b.inv_mass_sum[l] = inv_m(i) + inv_m(j);
        b.tag_i[l] = tag[i] as u32;
        b.tag_j[l] = tag[j] as u32;
    };
    let mut apply = Apply {
        f,
        sinks: &mut sinks,
        tallying,
        full,
        newton,
        nlocal,
        row: None,
    };
    for &i in ilist {
        if i < 0 || i as usize >= nall {
            return Err(Error::invalid(format!("ilist entry {i} outside 0..{nall}")));
        }
        let i = i as usize;
        // SAFETY: `numneigh` and `firstneigh` are valid for every i in ilist (caller's contract).
        let (n, first) = unsafe { (*list.numneigh.add(i), *list.firstneigh.add(i)) };
        // SAFETY: `firstneigh[i]` holds `numneigh[i]` ints (caller's contract).
        let jlist = unsafe { slice(first, n.max(0) as usize, "firstneigh[i]")? };
        let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
        let row = ty[i] as usize * (nt + 1);
        for &jraw in jlist {
            let j = jraw as u32 as usize & mask;
            if j >= nall {
                return Err(Error::invalid(format!(
                    "neighbour index {j} of atom {i} outside 0..{nall}"
                )));
            }
            let k = row + ty[j] as usize;
            let rc = table[k].rc;
            let dr = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
            let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
            // Every listed pair is written to the next lane, and only a pair in range keeps it
            // (the kernel checks again): with half the listed pairs in range (n = 16, skin 0.3)
            // a branch here is mispredicted half the time. The rest of the lane (velocities,
            // masses, tags) is gathered for the kept pairs only, in `gather`.
            let l = bt.lane();
            for (lane, &c) in bt.batch.dr.iter_mut().zip(&dr) {
                lane[l] = c;
            }
            bt.batch.coeff[l] = k as u32;
            if bt.commit(i as u32, j as u32, rsq < rc * rc) {
                bt.flush(&kernel, step, gather, |b, l, i, j| apply.lane(b, l, i, j));
            }
        }
    }
    bt.flush(&kernel, step, gather, |b, l, i, j| apply.lane(b, l, i, j));
    apply.finish_row();
    Ok(())
}

/// Adds evaluated pairs to the forces and tallies, in list order. The force on i is summed over
/// its row in `row` and added to f[i] when the next row starts (or at the end), as the
/// pair-by-pair loop did.
struct Apply<'a, 'b> {
    f: &'a mut [f64],
    sinks: &'a mut Sinks<'b>,
    tallying: bool,
    full: bool,
    newton: bool,
    nlocal: usize,
    /// The row being summed: atom i and the force on it so far.
    row: Option<(usize, [f64; 3])>,
}

impl Apply<'_, '_> {
    #[inline(always)]
    fn lane(&mut self, b: &PairBatch, l: usize, i: usize, j: usize) {
        if self.row.is_some_and(|(r, _)| r != i) {
            self.finish_row();
        }
        let (dr, fv) = lane_force(b, l);
        let fi = &mut self.row.get_or_insert((i, [0.0; 3])).1;
        fi[0] += fv[0];
        fi[1] += fv[1];
        fi[2] += fv[2];
        let j_owned = j < self.nlocal;
        if !self.full && (self.newton || j_owned) {
            self.f[3 * j] -= fv[0];
            self.f[3 * j + 1] -= fv[1];
            self.f[3 * j + 2] -= fv[2];
        }
        if self.tallying {
            tally_pair(
                self.sinks,
                i,
                j,
                b.energy[l],
                b.fpair[l],
                dr,
                self.full,
                self.newton,
                i < self.nlocal,
                j_owned,
            );
        }
    }

    fn finish_row(&mut self) {
        if let Some((i, fi)) = self.row.take() {
            self.f[3 * i] += fi[0];
            self.f[3 * i + 1] += fi[1];
            self.f[3 * i + 2] += fi[2];
        }
    }
}

/// `1/m` for each mass, checking they are finite and > 0 (`offset` shifts the reported index).
fn inverse_masses(m: &[f64], offset: usize) -> Result<Vec<f64>, Error> {
    m.iter()
        .enumerate()
        .map(|(k, &mk)| {
            if mk.is_finite() && mk > 0.0 {
                Ok(1.0 / mk)
            } else {
                Err(Error::invalid(format!(
                    "mass[{}] = {mk} must be a finite number > 0",
                    k + offset
                )))
            }
        })
        .collect()
}

/// LAMMPS `ev_tally` (half list) / `ev_tally_full` (full list) for one pair.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn tally_pair(
    s: &mut Sinks,
    i: usize,
    j: usize,
    evdwl: f64,
    fpair: f64,
    d: [f64; 3],
    full: bool,
    newton: bool,
    i_owned: bool,
    j_owned: bool,
) {
    let v = [
        d[0] * d[0] * fpair,
        d[1] * d[1] * fpair,
        d[2] * d[2] * fpair,
        d[0] * d[1] * fpair,
        d[0] * d[2] * fpair,
        d[1] * d[2] * fpair,
    ];
    // Global sums, in LAMMPS's order of operations: ev_tally_full adds half to i; ev_tally adds
    // the whole pair with newton on, and half per owned partner with newton off.
    if let Some(e) = s.eng.as_deref_mut() {
        if full {
            *e += 0.5 * evdwl;
        } else if newton {
            *e += evdwl;
        } else {
            if i_owned {
                *e += 0.5 * evdwl;
            }
            if j_owned {
                *e += 0.5 * evdwl;
            }
        }
    }
    if let Some(vir) = s.virial.as_deref_mut() {
        if !full && newton {
            for k in 0..6 {
                vir[k] += v[k];
            }
        } else {
            let times = if full {
                1
            } else {
                u8::from(i_owned) + u8::from(j_owned)
            };
            for _ in 0..times {
                for k in 0..6 {
                    vir[k] += 0.5 * v[k];
                }
            }
        }
    }
    let to_i = full || newton || i_owned;
    let to_j = !full && (newton || j_owned);
    if let Some(ea) = s.eatom.as_deref_mut() {
        let half = 0.5 * evdwl;
        if to_i {
            ea[i] += half;
        }
        if to_j {
            ea[j] += half;
        }
    }
    if let Some(va) = s.vatom.as_deref_mut() {
        for k in 0..6 {
            let half = 0.5 * v[k];
            if to_i {
                va[6 * i + k] += half;
            }
            if to_j {
                va[6 * j + k] += half;
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Init-time resolution shared with the standalone engine (`dpdnl::init`): the same numbers and
// the same log lines in both engines.

thread_local! {
    static LAST_MESSAGE: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_message(message: &str) {
    let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_MESSAGE.with(|e| *e.borrow_mut() = text);
}

/// The line to log left by the last successful [`dpdnl_design_pair`], [`dpdnl_common_exponent`]
/// or [`dpdnl_euler_warning`] on this thread ("" when there is nothing to say). Valid until the
/// next such call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_last_message() -> *const c_char {
    LAST_MESSAGE.with(|e| e.borrow().as_ptr())
}

/// `pair_coeff I J a eta E sc S`: the `gamma0` and weight exponent s that give viscosity `eta`
/// and Schmidt number `sc` at number density `density` (N/V; per area in 2-D), cut-off `rc`,
/// mass `mass`, thermostat `kt` (exact kinetic-theory inversion, `dpdnl::init::resolve_design`).
/// On success `*gamma0` and `*s` are set and [`dpdnl_last_message`] holds the line to log.
///
/// # Safety
/// `gamma0` and `s` are null or valid for writing.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dpdnl_design_pair(
    itype: i32,
    jtype: i32,
    dimension: i32,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
    eta: f64,
    sc: f64,
    gamma0: *mut f64,
    s: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        if gamma0.is_null() {
            return Err(Error::null("gamma0"));
        }
        if s.is_null() {
            return Err(Error::null("s"));
        }
        let dim = u32::try_from(dimension)
            .map_err(|_| Error::invalid(format!("dimension {dimension} must be 2 or 3")))?;
        let label = format!("{itype} {jtype}");
        let r = dpdnl::init::resolve_design(&label, dim, density, rc, mass, kt, eta, sc)
            .map_err(Error::invalid)?;
        // SAFETY: both pointers are non-null and valid for writing by the caller's contract.
        unsafe {
            *gamma0 = r.gamma;
            *s = r.s;
        }
        set_last_message(&r.message);
        Ok(())
    })
}

/// The one weight exponent of `n` designed pairs (`itype[k] jtype[k]` needs `s[k]`): an error
/// if they differ (the exponent is global in the pair style). `current` is the pair style's
/// exponent; `*s_out` gets the common one (or `current` when `n` is 0), and
/// [`dpdnl_last_message`] says so when it replaces `current`.
///
/// # Safety
/// `itype`, `jtype` and `s` hold `n` entries (or are null when `n` is 0); `s_out` is valid for
/// writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_common_exponent(
    n: i32,
    itype: *const i32,
    jtype: *const i32,
    s: *const f64,
    current: f64,
    s_out: *mut f64,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        if s_out.is_null() {
            return Err(Error::null("s_out"));
        }
        let n = usize::try_from(n).map_err(|_| Error::invalid(format!("n = {n} < 0")))?;
        let mut designs = Vec::with_capacity(n);
        if n > 0 {
            if itype.is_null() || jtype.is_null() || s.is_null() {
                return Err(Error::null("itype, jtype or s"));
            }
            // SAFETY: non-null and holding n entries by the caller's contract.
            let (it, jt, sv) = unsafe {
                (
                    std::slice::from_raw_parts(itype, n),
                    std::slice::from_raw_parts(jtype, n),
                    std::slice::from_raw_parts(s, n),
                )
            };
            for k in 0..n {
                designs.push((format!("{} {}", it[k], jt[k]), sv[k]));
            }
        }
        let (value, note) = dpdnl::init::common_exponent(&designs, current)
            .map_err(Error::invalid)?
            .unwrap_or((current, None));
        // SAFETY: non-null and valid for writing by the caller's contract.
        unsafe { *s_out = value };
        set_last_message(note.as_deref().unwrap_or(""));
        Ok(())
    })
}

/// The Euler finite-step heating check of `dpdnl::init::euler_warning` (finite-step paper
/// eqs. 22 and 25): [`dpdnl_last_message`] holds the warning text, or "" when δt is small
/// enough. `gamma` is the largest `gamma0`, `mass` the lightest mass, `conservative` non-zero
/// when some pair has a ≠ 0, `nonlinear` non-zero for friction cross/dot.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn dpdnl_euler_warning(
    dimension: i32,
    density: f64,
    rc: f64,
    mass: f64,
    kt: f64,
    gamma: f64,
    s: f64,
    dt: f64,
    conservative: i32,
    nonlinear: i32,
) -> DpdnlStatus {
    set_last_message("");
    guard(|| {
        let dim = u32::try_from(dimension)
            .map_err(|_| Error::invalid(format!("dimension {dimension} must be 2 or 3")))?;
        let w = dpdnl::init::euler_warning(
            dim,
            density,
            rc,
            mass,
            kt,
            gamma,
            s,
            dt,
            conservative != 0,
            nonlinear != 0,
        )
        .map_err(Error::invalid)?;
        set_last_message(w.as_deref().unwrap_or(""));
        Ok(())
    })
}
