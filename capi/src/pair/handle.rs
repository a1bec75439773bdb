//! The handle's life and its settings: new, free, settings, coefficients, cut-offs, threads and
//! the host's launcher, and what the style needs from its driver.

use super::{DpdnlPair, DpdnlPairInfo, emit, handle, owned, type_count, type_pair};
use crate::compute::Workers;
use crate::styles::{put, words};
use crate::team::DpdnlLaunch;
use crate::{DpdnlStatus, Error, c_str, guard};
use dpdnl::StyleDerived;
use dpdnl::host::from_restart_lines;
use dpdnl::new_pair_style;
use std::ffi::c_char;

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
