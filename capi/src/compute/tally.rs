//! LAMMPS's tally conventions for the walk: where forces, energy and virial go (`ev_tally` on a
//! half list, newton on or off; `ev_tally_full` on a full list), global and per atom.

use dpdnl::PairBatch;
use dpdnl::host::lane_force;

use crate::types::*;
use crate::{Error, slice_mut};

/// The list, newton and ownership settings of a walk's sums.
#[derive(Clone, Copy)]
pub(crate) struct Flags {
    pub(crate) full: bool,
    pub(crate) newton: bool,
    pub(crate) nlocal: usize,
}

/// Where the tallies go, resolved to slices once.
pub(crate) struct Sinks<'a> {
    pub(crate) eng: Option<&'a mut f64>,
    pub(crate) virial: Option<&'a mut [f64]>,
    pub(crate) eatom: Option<&'a mut [f64]>,
    pub(crate) vatom: Option<&'a mut [f64]>,
}

impl<'a> Sinks<'a> {
    /// Whether anything is tallied.
    pub(crate) fn any(&self) -> bool {
        self.eng.is_some() || self.virial.is_some() || self.eatom.is_some() || self.vatom.is_some()
    }

    /// The tallies `tally` asks for (none without one), for `nall` atoms.
    ///
    /// # Safety
    /// Each pointer of `tally` is null or valid for its documented size and unaliased for `'a`.
    pub(crate) unsafe fn of(tally: Option<DpdnlTally>, nall: usize) -> Result<Sinks<'a>, Error> {
        let t = tally.unwrap_or(DpdnlTally {
            eflag_global: 0,
            vflag_global: 0,
            eng_vdwl: std::ptr::null_mut(),
            virial: std::ptr::null_mut(),
            eatom: std::ptr::null_mut(),
            vatom: std::ptr::null_mut(),
        });
        // SAFETY: each is null or valid for its documented size, unaliased (caller's contract).
        unsafe {
            Ok(Sinks {
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
            })
        }
    }
}

/// Adds evaluated pairs to the forces and tallies, in list order. The force on i is summed over
/// its row in `row` and added to f[i] when the next row starts (or at the end), as the
/// pair-by-pair loop did. Only atoms `lo..lo + n` are touched (`f` and the per-atom tallies hold
/// them): the single-threaded walk owns all atoms, a task of a threaded walk's phase 2 a range.
pub(crate) struct Apply<'a, 'b> {
    pub(crate) f: &'a mut [f64],
    pub(crate) lo: usize,
    pub(crate) n: usize,
    pub(crate) sinks: &'a mut Sinks<'b>,
    pub(crate) tallying: bool,
    pub(crate) flags: Flags,
    /// The row being summed: atom i and the force on it so far.
    pub(crate) row: Option<(usize, [f64; 3])>,
}

impl<'a, 'b> Apply<'a, 'b> {
    pub(crate) fn new(f: &'a mut [f64], lo: usize, sinks: &'a mut Sinks<'b>, flags: Flags) -> Self {
        Apply {
            n: f.len() / 3,
            f,
            lo,
            tallying: sinks.any(),
            sinks,
            flags,
            row: None,
        }
    }

    #[inline(always)]
    pub(crate) fn lane(&mut self, b: &PairBatch, l: usize, i: usize, j: usize) {
        let (dr, fv) = lane_force(b, l);
        self.pair(i, j, fv, b.energy[l], central(b, l), dr);
    }

    /// Pair (i, j) with force `fv` on i; `energy`, `fpair` (`None`: a non-central force, whose
    /// virial is formed from `fv`) and `dr` for the tallies.
    #[inline(always)]
    pub(crate) fn pair(
        &mut self,
        i: usize,
        j: usize,
        fv: [f64; 3],
        energy: f64,
        fpair: Option<f64>,
        dr: [f64; 3],
    ) {
        if self.row.is_some_and(|(r, _)| r != i) {
            self.finish_row();
        }
        if i.wrapping_sub(self.lo) < self.n {
            let fi = &mut self.row.get_or_insert((i, [0.0; 3])).1;
            fi[0] += fv[0];
            fi[1] += fv[1];
            fi[2] += fv[2];
        }
        let Flags {
            full,
            newton,
            nlocal,
        } = self.flags;
        let j_owned = j < nlocal;
        let lj = j.wrapping_sub(self.lo);
        if !full && (newton || j_owned) && lj < self.n {
            self.f[3 * lj] -= fv[0];
            self.f[3 * lj + 1] -= fv[1];
            self.f[3 * lj + 2] -= fv[2];
        }
        if self.tallying {
            tally_pair(
                self.sinks,
                (self.lo, self.n),
                i,
                j,
                energy,
                fpair,
                fv,
                dr,
                self.flags,
            );
        }
    }

    pub(crate) fn finish_row(&mut self) {
        if let Some((i, fi)) = self.row.take() {
            let li = i - self.lo;
            self.f[3 * li] += fi[0];
            self.f[3 * li + 1] += fi[1];
            self.f[3 * li + 2] += fi[2];
        }
    }
}

/// The central `fpair` of lane `l` for the tallies, `None` when the kernel added a non-central
/// part ([`PairBatch::transverse`]).
#[inline(always)]
pub(crate) fn central(b: &PairBatch, l: usize) -> Option<f64> {
    (!b.transverse).then_some(b.fpair[l])
}

/// LAMMPS `ev_tally` (half list) / `ev_tally_full` (full list) for one pair; the per-atom
/// tallies only for the atoms of `(lo, n)`, `lo..lo + n`, whose entries the per-atom arrays
/// start with.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn tally_pair(
    s: &mut Sinks,
    (lo, n): (usize, usize),
    i: usize,
    j: usize,
    evdwl: f64,
    fpair: Option<f64>,
    fv: [f64; 3],
    d: [f64; 3],
    Flags {
        full,
        newton,
        nlocal,
    }: Flags,
) {
    let (i_owned, j_owned) = (i < nlocal, j < nlocal);
    let v = match fpair {
        Some(fpair) => [
            d[0] * d[0] * fpair,
            d[1] * d[1] * fpair,
            d[2] * d[2] * fpair,
            d[0] * d[1] * fpair,
            d[0] * d[2] * fpair,
            d[1] * d[2] * fpair,
        ],
        // LAMMPS's `ev_tally_xyz`.
        None => [
            d[0] * fv[0],
            d[1] * fv[1],
            d[2] * fv[2],
            d[0] * fv[1],
            d[0] * fv[2],
            d[1] * fv[2],
        ],
    };
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
    let (li, lj) = (i.wrapping_sub(lo), j.wrapping_sub(lo));
    let to_i = (full || newton || i_owned) && li < n;
    let to_j = !full && (newton || j_owned) && lj < n;
    if let Some(ea) = s.eatom.as_deref_mut() {
        let half = 0.5 * evdwl;
        if to_i {
            ea[li] += half;
        }
        if to_j {
            ea[lj] += half;
        }
    }
    if let Some(va) = s.vatom.as_deref_mut() {
        for k in 0..6 {
            let half = 0.5 * v[k];
            if to_i {
                va[6 * li + k] += half;
            }
            if to_j {
                va[6 * lj + k] += half;
            }
        }
    }
}
