//! The fixes' grammar and physics (`dpdnl::grammar::fix`, `dpdnl::engine::fixes`), for the
//! LAMMPS fixes: argc/argv in, a typed struct or an error text out; the Euler step and the
//! PeX push on one rank's atoms (the MPI reductions stay in C++). The pair styles' words go
//! to their handle (`pair.rs`).

use std::ffi::c_char;

use dpdnl::grammar::{self, fix::PexArgs};
use dpdnl::host::{FlipLeak, flip_jump_note, flip_leak_warning, flip_wrap_y, y_crossings};
use dpdnl::host::{PexPick, PexSlabs, euler_update, pex_apply};

use crate::{Error, c_str, guard, slice, slice_mut};

/// The arguments of `fix pex/push` (from [`dpdnl_parse_fix_pex_push`]); `width` 0 means the
/// default Lx/20 of each run's box.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DpdnlPexArgs {
    /// Momentum per push.
    pub dp: f64,
    /// Slab width, or 0 for Lx/20.
    pub width: f64,
    /// Push every N steps.
    pub every: i32,
}

/// One rank's candidates of a PeX push, laid out as two MPI_DOUBLE_INT pairs: the slowest v_z
/// of slab 1 (`slow_v`, `slow_tag`; +inf and 2147483647 when the rank has none) and the fastest
/// of slab 2 (`fast_v`, `fast_tag`; −inf and 2147483647 when none). Reduce with MPI_MINLOC and
/// MPI_MAXLOC: ties go to the lowest tag, as within a rank.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DpdnlPexPick {
    /// Slowest v_z in slab 1.
    pub slow_v: f64,
    /// Its tag.
    pub slow_tag: i32,
    /// Fastest v_z in slab 2.
    pub fast_v: f64,
    /// Its tag.
    pub fast_tag: i32,
}

/// The words `arg[0..narg]` as strings.
///
/// # Safety
/// `arg` is null only when `narg == 0`, else it points to `narg` NUL-terminated strings.
pub(crate) unsafe fn words<'a>(
    narg: i32,
    arg: *const *const c_char,
) -> Result<Vec<&'a str>, Error> {
    let n =
        usize::try_from(narg).map_err(|_| Error::invalid(format!("narg = {narg} must be >= 0")))?;
    // SAFETY: `narg` pointers by the caller's contract.
    let ptrs = unsafe { slice(arg, n, "arg")? };
    ptrs.iter()
        .enumerate()
        // SAFETY: each is a NUL-terminated string by the caller's contract.
        .map(|(k, &p)| unsafe { c_str(p, &format!("arg[{k}]")) })
        .collect()
}

/// Write `value` through `out`.
///
/// # Safety
/// `out` is null or valid for writing.
pub(crate) unsafe fn put<T>(out: *mut T, value: T) -> Result<(), Error> {
    // SAFETY: null or valid for writing by the caller's contract.
    let out = unsafe { out.as_mut() }.ok_or_else(|| Error::null("out"))?;
    *out = value;
    Ok(())
}

/// Check the arguments of `fix ID group nve` or `nve/euler` (`style`; the words after it):
/// none are allowed.
///
/// # Safety
/// `style` is a NUL-terminated string; `arg` points to `narg` NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_parse_fix_integrator(
    style: *const c_char,
    narg: i32,
    arg: *const *const c_char,
) -> crate::DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (style, w) = unsafe { (c_str(style, "style")?, words(narg, arg)?) };
        grammar::fix::integrator(style, &w).map_err(Error::invalid)
    })
}

/// Parse `fix ID group pex/push dp [width W] [every N]` (the words after the style name) in a
/// box of `dimension` into `*out`.
///
/// # Safety
/// `arg` points to `narg` NUL-terminated strings; `out` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_parse_fix_pex_push(
    dimension: i32,
    narg: i32,
    arg: *const *const c_char,
    out: *mut DpdnlPexArgs,
) -> crate::DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let w = unsafe { words(narg, arg)? };
        let dim = usize::try_from(dimension).unwrap_or(0);
        let p = grammar::fix::pex_push(&w, dim).map_err(Error::invalid)?;
        let args = DpdnlPexArgs {
            dp: p.dp,
            width: p.width.unwrap_or(0.0),
            every: p.every as i32,
        };
        // SAFETY: forwarded caller's contract.
        unsafe { put(out, args) }
    })
}

fn pex_args(p: *const DpdnlPexArgs) -> Result<PexArgs, Error> {
    // SAFETY: null or valid for reading by the caller's contract (every entry point below).
    let p = unsafe { p.as_ref() }.ok_or_else(|| Error::null("args"))?;
    Ok(PexArgs {
        dp: p.dp,
        width: (p.width > 0.0).then_some(p.width),
        every: u64::try_from(p.every).unwrap_or(0),
    })
}

/// The set-up check of a `fix pex/push` against the box of a run (every `init()`): orthogonal,
/// periodic in x, width at most Lx/2.
///
/// # Safety
/// `args` is valid for reading.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pex_box_check(
    args: *const DpdnlPexArgs,
    lx: f64,
    triclinic: i32,
    x_periodic: i32,
) -> crate::DpdnlStatus {
    guard(|| {
        let p = pex_args(args)?;
        grammar::fix::pex_box_check(p.width, lx, triclinic != 0, x_periodic != 0)
            .map(|_| ())
            .map_err(Error::invalid)
    })
}

/// Per-atom arrays of one rank for the fixes: `nlocal` owned atoms, LAMMPS layout.
struct Local<'a> {
    tag: &'a [i32],
    mask: &'a [i32],
    groupbit: i32,
}

impl Local<'_> {
    fn member(&self, i: usize) -> bool {
        self.mask[i] & self.groupbit != 0
    }
}

/// `x` or `v` of `n` atoms (`&x[0][0]`) as rows.
///
/// # Safety
/// `p` is null only when `n == 0`, else valid for `3 n` doubles.
unsafe fn rows<'a>(p: *const f64, n: usize, what: &str) -> Result<&'a [[f64; 3]], Error> {
    // SAFETY: `[f64; 3]` has the layout of 3 consecutive doubles; caller's contract on size.
    unsafe { slice(p.cast::<[f64; 3]>(), n, what) }
}

/// As [`rows`], mutable.
///
/// # Safety
/// As [`rows`], and not aliased.
unsafe fn rows_mut<'a>(p: *mut f64, n: usize, what: &str) -> Result<&'a mut [[f64; 3]], Error> {
    // SAFETY: as in `rows`.
    unsafe { slice_mut(p.cast::<[f64; 3]>(), n, what) }
}

fn count(nlocal: i32) -> Result<usize, Error> {
    usize::try_from(nlocal).map_err(|_| Error::invalid(format!("nlocal = {nlocal} must be >= 0")))
}

/// This rank's candidates of a PeX push (see [`DpdnlPexPick`]) among its `nlocal` owned atoms
/// in group `groupbit`, in a box spanning `xlo..xhi`.
///
/// # Safety
/// `x`, `v` hold `3 nlocal` doubles; `tag`, `mask` `nlocal` ints; `args` and `out` valid.
#[allow(clippy::too_many_arguments)]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pex_select(
    args: *const DpdnlPexArgs,
    nlocal: i32,
    x: *const f64,
    v: *const f64,
    tag: *const i32,
    mask: *const i32,
    groupbit: i32,
    xlo: f64,
    xhi: f64,
    out: *mut DpdnlPexPick,
) -> crate::DpdnlStatus {
    guard(|| {
        let p = pex_args(args)?;
        let n = count(nlocal)?;
        // SAFETY: sizes by the caller's contract.
        let (x, v, tag, mask) = unsafe {
            (
                rows(x, n, "x")?,
                rows(v, n, "v")?,
                slice(tag, n, "tag")?,
                slice(mask, n, "mask")?,
            )
        };
        let local = Local {
            tag,
            mask,
            groupbit,
        };
        let tags: Vec<u32> = local.tag.iter().map(|&t| t as u32).collect();
        let slabs = PexSlabs::new(xlo, xhi, p.width.unwrap_or((xhi - xlo) / 20.0));
        let pick = PexPick::select(&slabs, x, v, &tags, |i| local.member(i));
        let none = i32::MAX;
        let (slow_v, slow_tag) = pick
            .slow
            .map_or((f64::INFINITY, none), |(v, t)| (v, t as i32));
        let (fast_v, fast_tag) = pick
            .fast
            .map_or((f64::NEG_INFINITY, none), |(v, t)| (v, t as i32));
        // SAFETY: forwarded caller's contract.
        unsafe {
            put(
                out,
                DpdnlPexPick {
                    slow_v,
                    slow_tag,
                    fast_v,
                    fast_tag,
                },
            )
        }
    })
}

/// Masses of the owned atoms: per atom (`rmass`, if not null) or per type (`mass[type]`).
struct Masses<'a> {
    typ: &'a [i32],
    mass: &'a [f64],
    rmass: Option<&'a [f64]>,
}

impl Masses<'_> {
    /// # Safety
    /// `typ` holds `n` ints; `rmass` is null or holds `n` doubles; else `mass` holds
    /// `ntypes + 1` doubles where every type in `typ` is at most `ntypes`.
    unsafe fn new<'a>(
        n: usize,
        typ: *const i32,
        mass: *const f64,
        rmass: *const f64,
    ) -> Result<Masses<'a>, Error> {
        // SAFETY: forwarded caller's contract.
        let typ = unsafe { slice(typ, n, "type")? };
        if !rmass.is_null() {
            return Ok(Masses {
                typ,
                mass: &[],
                // SAFETY: forwarded caller's contract.
                rmass: Some(unsafe { slice(rmass, n, "rmass")? }),
            });
        }
        let tmax = typ.iter().copied().max().unwrap_or(0);
        if typ.iter().any(|&t| t < 1) {
            return Err(Error::invalid("an atom type is < 1"));
        }
        Ok(Masses {
            typ,
            // SAFETY: `tmax + 1` doubles by the caller's contract.
            mass: unsafe { slice(mass, tmax as usize + 1, "mass")? },
            rmass: None,
        })
    }

    fn of(&self, i: usize) -> f64 {
        match self.rmass {
            Some(r) => r[i],
            None => self.mass[self.typ[i] as usize],
        }
    }
}

/// The exchange of a PeX push after the MPI reductions: v_z += dp/m on the owned atom of tag
/// `slow_tag`, −= dp/m on that of `fast_tag` (each on whichever rank owns it).
///
/// # Safety
/// `v` holds `3 nlocal` doubles; `tag` and `atom_type` `nlocal` ints; `rmass` is null or
/// `nlocal` doubles, else `mass` is indexed by type (entry 0 unused); `args` valid.
#[allow(clippy::too_many_arguments)]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pex_apply(
    args: *const DpdnlPexArgs,
    nlocal: i32,
    v: *mut f64,
    tag: *const i32,
    atom_type: *const i32,
    mass: *const f64,
    rmass: *const f64,
    slow_tag: i32,
    fast_tag: i32,
) -> crate::DpdnlStatus {
    guard(|| {
        let p = pex_args(args)?;
        let n = count(nlocal)?;
        // SAFETY: sizes by the caller's contract.
        let (v, tag, m) = unsafe {
            (
                rows_mut(v, n, "v")?,
                slice(tag, n, "tag")?,
                Masses::new(n, atom_type, mass, rmass)?,
            )
        };
        let tags: Vec<u32> = tag.iter().map(|&t| t as u32).collect();
        pex_apply(
            v,
            &tags,
            |i| m.of(i),
            p.dp,
            slow_tag as u32,
            fast_tag as u32,
        );
        Ok(())
    })
}

/// `fix nve/euler` on one rank: for each owned atom in group `groupbit`, x += dtv v(t) and
/// v += (dtf/m) f(t) (`dpdnl::host::euler_update`; dtf = δt·ftm2v).
///
/// # Safety
/// `x`, `v`, `f` hold `3 nlocal` doubles (`x` and `v` not aliased); `atom_type`, `mask`
/// `nlocal` ints; `rmass` null or `nlocal` doubles, else `mass` indexed by type.
#[allow(clippy::too_many_arguments)]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_euler_step(
    nlocal: i32,
    x: *mut f64,
    v: *mut f64,
    f: *const f64,
    atom_type: *const i32,
    mass: *const f64,
    rmass: *const f64,
    mask: *const i32,
    groupbit: i32,
    dtv: f64,
    dtf: f64,
) -> crate::DpdnlStatus {
    guard(|| {
        let n = count(nlocal)?;
        // SAFETY: sizes and aliasing by the caller's contract.
        let (x, v, f, mask, m) = unsafe {
            (
                rows_mut(x, n, "x")?,
                rows_mut(v, n, "v")?,
                rows(f, n, "f")?,
                slice(mask, n, "mask")?,
                Masses::new(n, atom_type, mass, rmass)?,
            )
        };
        for i in 0..n {
            if mask[i] & groupbit != 0 {
                euler_update(&mut x[i], &mut v[i], &f[i], dtv, dtf / m.of(i));
            }
        }
        Ok(())
    })
}

/// Parse `fix ID group flip/momentum [mode jump|check]` (the words after the style name):
/// `*jump` = 1 for `mode jump` (the default), 0 for `mode check`
/// (`dpdnl::grammar::fix::flip_momentum`).
///
/// # Safety
/// `arg` points to `narg` NUL-terminated strings; `jump` is valid for writing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_parse_fix_flip_momentum(
    narg: i32,
    arg: *const *const c_char,
    jump: *mut i32,
) -> crate::DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let w = unsafe { words(narg, arg)? };
        let j = grammar::fix::flip_momentum(&w).map_err(Error::invalid)?;
        // SAFETY: forwarded caller's contract.
        unsafe { put(jump, i32::from(j)) }
    })
}

/// The run set-up check of `fix flip/momentum` (`dpdnl::grammar::fix::flip_momentum_setup`,
/// as in the standalone engine): `deform_id` null when the run has no `fix deform`, else its
/// ID, whether it has `remap v`, whether its group is the fix's, and whether it changes the xy
/// tilt only.
///
/// # Safety
/// `deform_id` is null or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_flip_momentum_setup(
    deform_id: *const c_char,
    remap_v: i32,
    same_group: i32,
    xy_only: i32,
) -> crate::DpdnlStatus {
    guard(|| {
        let deform = if deform_id.is_null() {
            None
        } else {
            // SAFETY: NUL-terminated by the caller's contract.
            Some(unsafe { c_str(deform_id, "deform_id")? })
        };
        grammar::fix::flip_momentum_setup(
            deform.map(|id| (id, remap_v != 0, same_group != 0, xy_only != 0)),
        )
        .map_err(Error::invalid)
    })
}

/// `fix flip/momentum` at the step of a flip, before `fix deform`'s `pre_exchange` flips the
/// box and remaps the atoms: every owned atom of group `groupbit` outside `ylo..yhi` along y
/// is put through y by `dpdnl::host::flip_wrap_y` (tilt `xy`) and, with `jump`
/// nonzero, gets `remap v`'s velocity jump −n `h_rate_xy`; `ny[i]` receives its crossings n
/// (0 for the others; the caller moves its image flags), and `*atoms` and `*momentum` are
/// incremented by the atoms put through and by Σ m n h_rate_xy, the momentum relative to the
/// profile that they change without the jump. With `jump` 0 nothing is moved: the crossings are
/// only counted (LAMMPS's own remap then moves the atoms, without the jump).
///
/// # Safety
/// `x`, `v` hold `3 nlocal` doubles (not aliased); `atom_type`, `mask` and `ny` `nlocal` ints;
/// `rmass` null or `nlocal` doubles, else `mass` indexed by type; `atoms` and `momentum` valid.
#[allow(clippy::too_many_arguments)]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_flip_wrap(
    nlocal: i32,
    x: *mut f64,
    v: *mut f64,
    atom_type: *const i32,
    mass: *const f64,
    rmass: *const f64,
    mask: *const i32,
    groupbit: i32,
    ylo: f64,
    yhi: f64,
    xy: f64,
    h_rate_xy: f64,
    jump: i32,
    ny: *mut i32,
    atoms: *mut i64,
    momentum: *mut f64,
) -> crate::DpdnlStatus {
    guard(|| {
        let n = count(nlocal)?;
        // SAFETY: sizes and aliasing by the caller's contract.
        let (x, v, mask, ny, m) = unsafe {
            (
                rows_mut(x, n, "x")?,
                rows_mut(v, n, "v")?,
                slice(mask, n, "mask")?,
                slice_mut(ny, n, "ny")?,
                Masses::new(n, atom_type, mass, rmass)?,
            )
        };
        // SAFETY: valid by the caller's contract.
        let (atoms, momentum) = unsafe {
            (
                atoms.as_mut().ok_or_else(|| Error::null("atoms"))?,
                momentum.as_mut().ok_or_else(|| Error::null("momentum"))?,
            )
        };
        for i in 0..n {
            ny[i] = 0;
            if mask[i] & groupbit == 0 {
                continue;
            }
            let k = if jump != 0 {
                flip_wrap_y(&mut x[i], &mut v[i], ylo, yhi, xy, h_rate_xy, true)
            } else {
                y_crossings(x[i][1], ylo, yhi, yhi - ylo)
            };
            if k != 0 {
                ny[i] = k;
                *atoms += 1;
                *momentum += m.of(i) * f64::from(k) * h_rate_xy;
            }
        }
        Ok(())
    })
}

/// The end-of-run text of a run whose flips put `atoms` atoms through y, changing the momentum
/// relative to the profile by `momentum` (`conserved` nonzero: the jump was applied), in a
/// group of total mass `total_mass`: left for [`crate::dpdnl_last_message`], the standalone
/// engine's words (`dpdnl::engine::lees_edwards`): "WARNING: " and `flip_leak_warning`
/// without the jump, `flip_jump_note` with it, "" when no atom was put through.
#[unsafe(no_mangle)]
pub extern "C" fn dpdnl_flip_leak_warning(
    atoms: i64,
    momentum: f64,
    conserved: i32,
    total_mass: f64,
) -> crate::DpdnlStatus {
    guard(|| {
        let leak = FlipLeak {
            atoms: u64::try_from(atoms).unwrap_or(0),
            momentum,
            conserved: conserved != 0,
        };
        let text = match flip_leak_warning(&leak, total_mass) {
            Some(w) => format!("WARNING: {w}"),
            None => flip_jump_note(&leak).unwrap_or_default(),
        };
        crate::init::set_last_message(&text);
        Ok(())
    })
}
