//! `fix ID all dpdnl/frames N FILE`: the frames `dpdnl verify` reads (`dpdnl::io::frames`, the
//! format). The C++ fix gathers the atoms to one rank; this file parses the fix's words, says
//! which steps are due and writes each frame, with the pair style's name and settings.

use std::ffi::c_char;

use dpdnl::io::frames::{FrameAtoms, FrameHead, FrameWriter, flags};

use crate::pair::DpdnlPair;
use crate::styles::{put, words};
use crate::{DpdnlStatus, Error, c_str, guard, slice};

/// A `fix dpdnl/frames`: its period and, on the writing rank, the open file.
pub struct DpdnlFrames {
    every: u64,
    writer: Option<FrameWriter>,
}

/// What a frame says of the run besides its atoms (LAMMPS's `update`, `domain`, `force`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct DpdnlFrameHead {
    /// The step of the force (`update->ntimestep`).
    pub step: i64,
    /// 2 or 3.
    pub dimension: i32,
    /// Number of atom types.
    pub ntypes: i32,
    /// 1 for a triclinic box.
    pub triclinic: i32,
    /// 1 where the box is periodic along x, y, z.
    pub periodic: [i32; 3],
    /// 1 when the run integrates with `fix nve/euler`.
    pub euler: i32,
    /// 1 when the atom style is molecular.
    pub molecular: i32,
    /// Box corners.
    pub boxlo: [f64; 3],
    /// See `boxlo`.
    pub boxhi: [f64; 3],
    /// Tilt factors xy, xz, yz.
    pub tilt: [f64; 3],
    /// Time step.
    pub dt: f64,
    /// The run's first and last step.
    pub beginstep: i64,
    /// See `beginstep`.
    pub endstep: i64,
    /// The `special_bonds lj` factors in force.
    pub special_lj: [f64; 4],
}

/// Parse `fix ID GROUP dpdnl/frames N FILE` (`group` and the words after the style name) into
/// `*out`, a new handle; with `writer` != 0 (one rank), create FILE and write its header.
///
/// # Safety
/// `group` is a NUL-terminated string; `arg` points to `narg` NUL-terminated strings; `out` is
/// valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_frames_new(
    group: *const c_char,
    narg: i32,
    arg: *const *const c_char,
    writer: i32,
    out: *mut *mut DpdnlFrames,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        unsafe { put(out, std::ptr::null_mut())? };
        // SAFETY: forwarded caller's contract.
        let (group, w) = unsafe { (c_str(group, "group")?, words(narg, arg)?) };
        let (every, path) = dpdnl::grammar::fix::frames(group, &w).map_err(Error::invalid)?;
        let writer = match writer {
            0 => None,
            _ => Some(FrameWriter::create(&path).map_err(Error::invalid)?),
        };
        let h = Box::new(DpdnlFrames { every, writer });
        // SAFETY: forwarded caller's contract.
        unsafe { put(out, Box::into_raw(h)) }
    })
}

/// Free a handle of [`dpdnl_frames_new`] (null is a no-op), closing its file.
///
/// # Safety
/// `h` is null or a live handle, not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_frames_free(h: *mut DpdnlFrames) {
    if !h.is_null() {
        // SAFETY: a handle of dpdnl_frames_new by the caller's contract.
        drop(unsafe { Box::from_raw(h) });
    }
}

/// `*due` = 1 when the force of `step` is a frame (a multiple of N), else 0.
///
/// # Safety
/// `h` is a live handle; `due` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_frames_due(
    h: *const DpdnlFrames,
    step: i64,
    due: *mut i32,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or live by the caller's contract.
        let h = unsafe { h.as_ref() }.ok_or_else(|| Error::null("frames handle"))?;
        let yes = u64::try_from(step).is_ok_and(|s| s % h.every == 0);
        // SAFETY: forwarded caller's contract.
        unsafe { put(due, i32::from(yes)) }
    })
}

/// Rows of `n` triples at `p`.
///
/// # Safety
/// `p` is null only when `n == 0`, else valid for `3 n` doubles.
unsafe fn rows<'a>(p: *const f64, n: usize, what: &str) -> Result<&'a [[f64; 3]], Error> {
    // SAFETY: `[f64; 3]` is 3 consecutive doubles; size by the caller's contract.
    unsafe { slice(p.cast::<[f64; 3]>(), n, what) }
}

/// Append one frame of `n` atoms (every atom of the run, gathered on the writing rank): ids
/// `tag`, types `typ`, masses `mass`, and `3 n` doubles each of positions `x`, velocities `v`
/// and the style's own force `f`; the style's name and settings from `pair`. On a rank
/// without the file (`writer` 0 at [`dpdnl_frames_new`]) an error.
///
/// # Safety
/// `h` and `pair` are live handles; `head` is valid; the arrays hold `n` (or `3 n`) values.
#[allow(clippy::too_many_arguments)]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_frames_write(
    h: *mut DpdnlFrames,
    pair: *mut DpdnlPair,
    head: *const DpdnlFrameHead,
    n: i64,
    tag: *const i32,
    typ: *const i32,
    mass: *const f64,
    x: *const f64,
    v: *const f64,
    f: *const f64,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: null or live by the caller's contract.
        let h = unsafe { h.as_mut() }.ok_or_else(|| Error::null("frames handle"))?;
        // SAFETY: null or valid by the caller's contract.
        let c = unsafe { head.as_ref() }.ok_or_else(|| Error::null("head"))?;
        // SAFETY: forwarded caller's contract.
        let (style, settings) = unsafe { crate::pair::describe(pair)? };
        let n = usize::try_from(n).map_err(|_| Error::invalid(format!("n = {n} < 0")))?;
        // SAFETY: sizes by the caller's contract.
        let (tag, typ, mass, x, v, f) = unsafe {
            (
                slice(tag, n, "tag")?,
                slice(typ, n, "type")?,
                slice(mass, n, "mass")?,
                rows(x, n, "x")?,
                rows(v, n, "v")?,
                rows(f, n, "f")?,
            )
        };
        let unsigned = |a: &[i32], what: &str| {
            a.iter()
                .map(|&t| u32::try_from(t).map_err(|_| Error::invalid(format!("{what} {t} < 0"))))
                .collect::<Result<Vec<u32>, Error>>()
        };
        let (tag, typ) = (unsigned(tag, "atom id")?, unsigned(typ, "atom type")?);
        let mut fl = 0;
        for (bit, on) in [
            (flags::TRICLINIC, c.triclinic),
            (flags::PERIODIC_X, c.periodic[0]),
            (flags::PERIODIC_X << 1, c.periodic[1]),
            (flags::PERIODIC_X << 2, c.periodic[2]),
            (flags::EULER, c.euler),
            (flags::MOLECULAR, c.molecular),
        ] {
            if on != 0 {
                fl |= bit;
            }
        }
        let fh = FrameHead {
            step: u64::try_from(c.step).unwrap_or(0),
            dimension: u32::try_from(c.dimension).unwrap_or(0),
            flags: fl,
            ntypes: u32::try_from(c.ntypes).unwrap_or(0),
            boxlo: c.boxlo,
            boxhi: c.boxhi,
            tilt: c.tilt,
            dt: c.dt,
            beginstep: u64::try_from(c.beginstep).unwrap_or(0),
            endstep: u64::try_from(c.endstep).unwrap_or(0),
            special_lj: c.special_lj,
            style,
            settings,
        };
        let atoms = FrameAtoms {
            tag: &tag,
            typ: &typ,
            mass,
            x,
            v,
            f,
        };
        let w = h
            .writer
            .as_mut()
            .ok_or_else(|| Error::invalid("this rank does not write the frames"))?;
        w.write(&fh, atoms).map_err(Error::invalid)
    })
}
