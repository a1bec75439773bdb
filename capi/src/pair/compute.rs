//! One force evaluation: the pre-pass (sDPD's density) and its end, and the pair forces over a
//! LAMMPS neighbour list.

use super::{DpdnlPair, handle};
use crate::compute::{atom_masses, walk_pairs};
use crate::list::{for_each_row, special_class};
use crate::ownlist::DpdnlSpecial;
use crate::styles::put;
use crate::{
    DpdnlAtoms, DpdnlNeighList, DpdnlStatus, DpdnlStep, DpdnlTally, Error, guard, slice, slice_mut,
};
use dpdnl::host::Isa;
use dpdnl::host::SpecialRule;

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

/// The atoms' per-atom masses (`nall` of them) when the set-up was for per-atom masses, `None`
/// for per-type ones ([`atom_masses`] chooses); atoms whose kind of mass differs from the
/// set-up's are an error.
///
/// # Safety
/// As [`atom_masses`].
unsafe fn masses_of<'a>(
    h: &DpdnlPair,
    a: &'a DpdnlAtoms,
    nall: usize,
) -> Result<Option<&'a [f64]>, Error> {
    // SAFETY: forwarded caller's contract.
    let m = unsafe { atom_masses(a, nall)? };
    if m.is_some() != h.per_atom_mass {
        return Err(Error::invalid(if h.per_atom_mass {
            "the set-up was for per-atom masses (rmass), but the atoms have none"
        } else {
            "the atoms have per-atom masses (rmass), but the set-up was for per-type masses"
        }));
    }
    Ok(m)
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
        // SAFETY: forwarded caller's contract.
        let mass = unsafe { masses_of(h, a, nall)? };
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
                        // i's weight with j's mass, j's with i's (per-atom masses), or one
                        // weight for both (per-type masses: the style's one mass).
                        let (wi, wj) = match mass {
                            None => {
                                let w = pp.weight(k, rsq);
                                (w, w)
                            }
                            Some(m) => (pp.weight_of(k, rsq, m[j]), pp.weight_of(k, rsq, m[i])),
                        };
                        di += wi;
                        if newton || j < nlocal {
                            rho[j] += wj;
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
        let (_, ty, nlocal, nall) = unsafe { positions_types(a, nt)? };
        // SAFETY: forwarded caller's contract.
        let mass = unsafe { masses_of(h, a, nall)? };
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
            let u = match mass {
                None => pp.energy_of(ti, d),
                Some(m) => pp.energy_of_mass(ti, d, m[i]),
            };
            let Some(u) = u else {
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
            // SAFETY: forwarded caller's contract.
            let mass = unsafe { masses_of(h, a, nall)? };
            h.typ.clear();
            h.typ.extend(ty.iter().map(|&t| t as u32));
            h.style.set_atom_values(rho, &h.typ, mass);
        } else {
            // SAFETY: forwarded caller's contract (the walk reads the masses themselves).
            unsafe { masses_of(h, a, a.nall.max(0) as usize)? };
        }
        h.style.set_timestep(st.dt);
        // Negative steps are refused by the walk (`step = … must be >= 0`).
        let run = dpdnl::RunSteps {
            begin: st.beginstep.max(0) as u64,
            end: st.endstep.max(0) as u64,
        };
        h.style.at_step(st.step.max(0) as u64, run);
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

/// The pair list the style builds for itself (issue 44, `crate::ownlist`): a half list over
/// the owned and ghost atoms of `atoms`, newton on or off as `st->newton_pair`, with pairs
/// within each type row's largest cut-off plus a margin (LAMMPS's `skin`, at most half the
/// largest cut-off) and
/// bonded neighbours flagged from `special` (null, or its pointers null, when the atom style
/// has no bonds). `*out` gets it in the layout of a LAMMPS list, for [`dpdnl_pair_prepass`] and
/// [`dpdnl_pair_compute`]: its arrays belong to the handle and stay valid until the next call
/// on it. It is built again when `build` (LAMMPS's `neighbor->ncalls`) or the atom counts
/// change, and when an atom has moved more than half the margin since it was built.
///
/// # Safety
/// `h` is a live handle; `atoms` as for [`dpdnl_pair_compute`] (x, tag and type of all `nall`
/// atoms are read); `special` null or as documented on [`DpdnlSpecial`]; `st` and `out` valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpdnl_pair_own_list(
    h: *mut DpdnlPair,
    atoms: *const DpdnlAtoms,
    special: *const DpdnlSpecial,
    st: *const DpdnlStep,
    build: i64,
    skin: f64,
    out: *mut DpdnlNeighList,
) -> DpdnlStatus {
    guard(|| {
        // SAFETY: forwarded caller's contract.
        let (h, a, st) = unsafe {
            (
                handle(h)?,
                atoms.as_ref().ok_or_else(|| Error::null("atoms"))?,
                st.as_ref().ok_or_else(|| Error::null("step"))?,
            )
        };
        ready(h)?;
        let nt = h.style.ntypes();
        // SAFETY: forwarded caller's contract.
        let (x, ty, nlocal, nall) = unsafe { positions_types(a, nt)? };
        // SAFETY: nall tags (caller's contract).
        let tag = unsafe { slice(a.tag, nall, "tag")? };
        // SAFETY: null or valid (caller's contract).
        let sp = match unsafe { special.as_ref() } {
            Some(s) if !s.nspecial.is_null() && !s.special.is_null() && s.maxspecial > 0 => {
                let stride = s.maxspecial as usize;
                // SAFETY: 3 nlocal counts and nlocal * maxspecial tags (caller's contract).
                let (ns, tags) = unsafe {
                    (
                        slice(s.nspecial, 3 * nlocal, "nspecial")?,
                        slice(s.special, stride * nlocal, "special")?,
                    )
                };
                if let Some(bad) = (0..nlocal).find(|&i| {
                    let n = &ns[3 * i..3 * i + 3];
                    !(0 <= n[0] && n[0] <= n[1] && n[1] <= n[2] && n[2] as usize <= stride)
                }) {
                    return Err(Error::invalid(format!(
                        "atom {bad}'s special-neighbour counts {:?} exceed maxspecial = {stride}",
                        &ns[3 * bad..3 * bad + 3]
                    )));
                }
                Some((ns, tags, stride))
            }
            _ => None,
        };
        // Each type's row reaches its largest cut-off (and the pre-pass's, when it has one).
        let cut = h.style.cut_table();
        let pre = h.style.prepass().map(|pp| pp.rcsq());
        let row_cut: Vec<f64> = (0..=nt)
            .map(|t| {
                let row = t * (nt + 1)..(t + 1) * (nt + 1);
                let c = cut[row.clone()].iter().copied().fold(0.0, f64::max);
                let p = pre
                    .as_ref()
                    .map_or(0.0, |p| p[row].iter().copied().fold(0.0, f64::max).sqrt());
                c.max(p)
            })
            .collect();
        let cloud = crate::ownlist::Cloud {
            x,
            ty,
            tag,
            nlocal,
            special: sp,
            newton: st.newton_pair != 0,
            dim: if st.dimension == 2 { 2 } else { 3 },
        };
        // The list's margin: LAMMPS's skin, at most half the largest cut-off. LAMMPS's ghosts
        // reach the cut-off plus its skin, so any margin up to the skin finds every pair; a
        // shorter one is built more often but walked faster (Groot–Warren, skin 1.0, δt 0.04,
        // 300 steps on one AMD EPYC core: margin 1.0 3.93 s, 0.5 3.58 s, 0.3 3.97 s).
        if !(skin.is_finite() && skin >= 0.0) {
            return Err(Error::invalid(format!(
                "skin = {skin} must be a finite number >= 0"
            )));
        }
        let rc = row_cut.iter().copied().fold(0.0, f64::max);
        let margin = skin.min(0.5 * rc);
        let team = h.workers.as_ref().map(|w| &w.team);
        let list = h.own.prepare(&cloud, build, &row_cut, margin, team)?;
        // SAFETY: valid for writing (caller's contract).
        unsafe { put(out, list) }
    })
}
