//! The single-threaded walk: the rows of a LAMMPS list, their in-range pairs in batches through
//! the style's kernel, and the sums of a force-only step.

use dpdnl::host::Isa;
use dpdnl::host::SpecialRule;
use dpdnl::host::within_cut;
use dpdnl::host::{Batcher, lane_force};
use dpdnl::{PairBatch, PairKernel};

use super::tally::*;
use crate::Error;
use crate::list::*;

/// What the walk over a LAMMPS list reads, checked once per call (shared by its threads).
pub(crate) struct Walk<'a> {
    pub(crate) kernel: &'a dyn PairKernel,
    pub(crate) cut: &'a [f64],
    pub(crate) nt: usize,
    pub(crate) special: Option<SpecialRule>,
    pub(crate) x: &'a [f64],
    pub(crate) v: &'a [f64],
    pub(crate) tag: &'a [i32],
    pub(crate) ty: &'a [i32],
    /// 1/m per atom (`per_atom`) or per type.
    pub(crate) inv_mass: Vec<f64>,
    pub(crate) per_atom: bool,
    /// The largest cut-off² of each type's row of the table.
    pub(crate) row_cutsq: Vec<f64>,
    pub(crate) isa: Isa,
    pub(crate) step: u64,
    pub(crate) mask: usize,
    pub(crate) nall: usize,
    /// The image key's frame when the box is shorter than 2 r_c (P-4b).
    pub(crate) images: Option<dpdnl::host::ImageFrame>,
}

impl Walk<'_> {
    /// Candidate j of row i (position `xi`, `row` = type(i) (ntypes + 1)), with its
    /// coefficients `extra` past its type pair's (a special class's block), written to lane `l`
    /// of `b` ([`Batcher::extend`]'s `fill`); only a pair in range is kept (the kernel checks
    /// again): with several types some candidates are beyond their pair's cut-off, and a branch
    /// would be mispredicted. The rest of the lane (velocities, masses, tags) is gathered for
    /// the kept pairs only, at the flush.
    #[inline(always)]
    pub(crate) fn offer(
        &self,
        b: &mut PairBatch,
        l: usize,
        (i, xi, row): (usize, [f64; 3], usize),
        j: usize,
        extra: usize,
    ) -> (u32, u32, bool) {
        let x = self.x;
        let k = row + self.ty[j] as usize;
        let rc = self.cut[k];
        let dr = [xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]];
        let rsq = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
        for (lane, &c) in b.dr.iter_mut().zip(&dr) {
            lane[l] = c;
        }
        b.coeff[l] = (k + extra) as u32;
        (i as u32, j as u32, rsq < rc * rc)
    }

    /// The rows `rows` (atom, raw entries), in order, each checked: every pair in range
    /// through the kernel, handed batch by batch to `apply(batch, i, j)` (lane l: atoms
    /// `i[l]`, `j[l]`) in list order; the last batch is flushed.
    #[inline(always)]
    pub(crate) fn rows<'r>(
        &self,
        rows: impl Iterator<Item = Result<(usize, &'r [i32]), Error>>,
        bt: &mut Batcher,
        near: &mut Vec<u32>,
        mut apply: impl FnMut(&PairBatch, &[u32], &[u32]),
    ) -> Result<(), Error> {
        let (x, ty, nt, mask) = (self.x, self.ty, self.nt, self.mask);
        bt.batch.images = self.images;
        let kernel = self.kernel;
        let step = self.step;
        // The lanes' v_ij, 1/m_i + 1/m_j and tags (r_ij and the coefficient index are in place).
        let (v, tag, inv_mass, per_atom) = (self.v, self.tag, &self.inv_mass[..], self.per_atom);
        let mut gather = |b: &mut PairBatch, l: usize, i: usize, j: usize| {
            debug_assert!(i < self.nall && j < self.nall && l < b.len);
            // SAFETY: i and j are below nall: i from `list_row`, j from a row `check_row`
            // passed. `v` holds 3 nall values and `tag` and `ty` nall (`walk_pairs`); every type
            // is in 1..=ntypes (checked by `walk_pairs`) and `inv_mass` holds ntypes values, or
            // nall when `per_atom`. Without the checks the gather is 10 % faster (the shim's pair
            // time at n = 16).
            unsafe {
                let inv_m = |a: usize| {
                    if per_atom {
                        *inv_mass.get_unchecked(a)
                    } else {
                        *inv_mass.get_unchecked(*ty.get_unchecked(a) as usize - 1)
                    }
                };
                for d in 0..3 {
                    b.dv[d][l] = v.get_unchecked(3 * i + d) - v.get_unchecked(3 * j + d);
                }
                b.inv_mass_sum[l] = inv_m(i) + inv_m(j);
                b.tag_i[l] = *tag.get_unchecked(i) as u32;
                b.tag_j[l] = *tag.get_unchecked(j) as u32;
            }
        };
        for r in rows {
            let (i, jlist) = r?;
            let bonded = check_row(i, jlist, mask, self.nall)?;
            let xi = [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
            let row = ty[i] as usize * (nt + 1);
            // A row with bonded neighbours: each entry with its special class, in list order
            // (rows without them take the filtered pass below).
            let at = (i, xi, row);
            if let Some(sp) = self.special
                && bonded
            {
                let kept = jlist.iter().filter(|&&jr| !sp.excludes(special_class(jr)));
                let fill = |b: &mut PairBatch, l, &jr: &i32| {
                    let extra = sp.offset(special_class(jr)) as usize;
                    self.offer(b, l, at, jr as u32 as usize & mask, extra)
                };
                bt.extend(kept, fill, kernel, step, &mut gather, &mut apply);
                continue;
            }
            let n = within_cut(
                self.isa,
                xi,
                x,
                jlist,
                mask as u32,
                self.row_cutsq[ty[i] as usize],
                near,
            );
            let fill = |b: &mut PairBatch, l, &j: &u32| self.offer(b, l, at, j as usize, 0);
            bt.extend(&near[..n], fill, kernel, step, &mut gather, &mut apply);
        }
        bt.flush(kernel, step, gather, &mut apply);
        Ok(())
    }
}

/// The rows of a walk: LAMMPS's list, or the working copy of it.
pub(crate) enum Rows<L, C> {
    List(L),
    Copy(C),
}

impl<'r, L, C> Iterator for Rows<L, C>
where
    L: Iterator<Item = Result<(usize, &'r [i32]), Error>>,
    C: Iterator<Item = Result<(usize, &'r [i32]), Error>>,
{
    type Item = Result<(usize, &'r [i32]), Error>;

    #[inline(always)]
    fn next(&mut self) -> Option<Self::Item> {
        match self {
            Rows::List(l) => l.next(),
            Rows::Copy(c) => c.next(),
        }
    }
}

/// When [`Sum`] subtracts a pair's force from atom j: never (a full list), always (a half
/// list with newton on), or when j is owned (a half list with newton off).
pub(crate) const J_NEVER: u8 = 0;

pub(crate) const J_ALWAYS: u8 = 1;

pub(crate) const J_OWNED: u8 = 2;

/// The sums of a single-threaded force-only step: what [`Apply`] does without tallies, thread
/// ranges or run-time flags (the same additions in the same order, so the same bits), its
/// j-side rule a constant ([`J_NEVER`], [`J_ALWAYS`], [`J_OWNED`]). Apply's per-lane tests
/// were a tenth of the walk's time.
pub(crate) struct Sum<'a, const J: u8> {
    pub(crate) f: &'a mut [f64],
    pub(crate) nlocal: usize,
    /// The row being summed (`usize::MAX` before the first) and the force on it so far.
    pub(crate) i: usize,
    pub(crate) fi: [f64; 3],
}

impl<'a, const J: u8> Sum<'a, J> {
    /// Walk `rows` with `walk`, adding each pair's force to `f`.
    pub(crate) fn walk<'r>(
        walk: &Walk,
        rows: impl Iterator<Item = Result<(usize, &'r [i32]), Error>>,
        f: &'a mut [f64],
        flags: Flags,
        bt: &mut Batcher,
        near: &mut Vec<u32>,
    ) -> Result<(), Error> {
        let mut sum = Sum::<J> {
            f,
            nlocal: flags.nlocal,
            i: usize::MAX,
            fi: [0.0; 3],
        };
        walk.rows(rows, bt, near, |b, is, js| sum.batch(b, is, js))?;
        let (i, fi) = (sum.i, sum.fi);
        add_row(sum.f, i, fi);
        Ok(())
    }

    /// The lanes of a batch, in order (the row's running force in locals).
    #[inline(always)]
    pub(crate) fn batch(&mut self, b: &PairBatch, is: &[u32], js: &[u32]) {
        let f = &mut *self.f;
        let (mut cur, mut fi) = (self.i, self.fi);
        for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (_, fv) = lane_force(b, l);
            if i != cur {
                add_row(f, cur, fi);
                (cur, fi) = (i, [0.0; 3]);
            }
            fi[0] += fv[0];
            fi[1] += fv[1];
            fi[2] += fv[2];
            if J == J_ALWAYS || (J == J_OWNED && j < self.nlocal) {
                let fj = &mut f[3 * j..3 * j + 3];
                fj[0] -= fv[0];
                fj[1] -= fv[1];
                fj[2] -= fv[2];
            }
        }
        (self.i, self.fi) = (cur, fi);
    }
}

/// A finished row of [`Sum`]: `f[i] += fi` (nothing before the first row, `i = usize::MAX`).
#[inline(always)]
pub(crate) fn add_row(f: &mut [f64], i: usize, fi: [f64; 3]) {
    if i != usize::MAX {
        let fi_ = &mut f[3 * i..3 * i + 3];
        fi_[0] += fi[0];
        fi_[1] += fi[1];
        fi_[2] += fi[2];
    }
}
