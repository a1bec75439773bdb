//! The force-only step of a threaded walk (issue 58): each thread walks one contiguous block of
//! rows and adds straight into its own copy of f the forces of the atoms that only its block
//! touches; the atoms that several blocks touch (a thin layer where the blocks meet, in a list
//! whose atoms are ordered in space) get events ([`Event`]) that phase 2 adds in list order.
//! Every addition is the one-thread walk's ([`Sum`]), in its order, so the bits do not depend
//! on the thread count.
//!
//! Which block touches which atom ([`Owners`]) is found from the rows' raw entries (every
//! listed pair, in range or not: a superset of the pairs evaluated) and kept while the rows stay
//! where they are. The walk checks it as it adds: a block that adds to an atom marked as
//! another block's (rows changed in place) marks its result stale, and the step is walked again
//! after the marks are taken anew, so the result never depends on that key.

use dpdnl::PairBatch;
use dpdnl::host::lane_force;

use super::tally::Flags;
use super::threads::{Block, Event, Workers, add_events};
use super::walk::{J_ALWAYS, J_NEVER, J_OWNED, Walk};
use crate::Error;

/// An atom no block adds to.
const UNTOUCHED: u32 = 0;

/// An atom that several blocks add to: its additions are events.
const SHARED: u32 = u32::MAX;

/// Which block adds to each atom, and the blocks' rows, for one set of rows.
#[derive(Default)]
pub(crate) struct Owners {
    /// Per atom: [`UNTOUCHED`], [`SHARED`] or 1 + the block that alone adds to it.
    mark: Vec<u32>,
    /// The blocks' first rows, and the end (`blocks + 1` entries).
    bounds: Vec<usize>,
    /// What the marks were taken for ([`rows_key`]).
    key: Option<u64>,
    /// Times the marks were taken (for tests and benchmarks).
    pub(crate) taken: u64,
}

/// A key of the rows (atom, address and length of each), the list's settings and the block
/// count: when it changes, the marks are taken again. Rows changed in place keep their key;
/// the walk's check catches them.
fn rows_key(rows: &[(usize, &[i32])], flags: Flags, mask: usize, nall: usize, nb: usize) -> u64 {
    let mix = |h: u64, x: u64| (h ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29);
    let head = [
        rows.len(),
        nall,
        flags.nlocal,
        mask,
        nb,
        usize::from(flags.full) | usize::from(flags.newton) << 1,
    ];
    let h = head.iter().fold(0, |h, &x| mix(h, x as u64));
    rows.iter().fold(h, |h, &(i, js)| {
        mix(mix(mix(h, i as u64), js.as_ptr() as u64), js.len() as u64)
    })
}

impl Owners {
    /// The marks of `rows` split into `nb` blocks of about equal entries: each row's atom, and
    /// each listed j whose side the walk adds (a half list; with newton off, an owned j).
    fn take(
        &mut self,
        rows: &[(usize, &[i32])],
        flags: Flags,
        mask: usize,
        nall: usize,
        nb: usize,
    ) {
        let total: usize = rows.iter().map(|r| r.1.len() + 1).sum();
        self.bounds.clear();
        self.bounds.push(0);
        let mut acc = 0;
        for (r, row) in rows.iter().enumerate() {
            acc += row.1.len() + 1;
            while self.bounds.len() < nb && acc * nb >= self.bounds.len() * total {
                self.bounds.push(r + 1);
            }
        }
        self.bounds.resize(nb + 1, rows.len());
        self.bounds[nb] = rows.len();
        self.mark.clear();
        self.mark.resize(nall, UNTOUCHED);
        let mark = &mut self.mark;
        let mut add = |a: usize, me: u32| {
            if let Some(m) = mark.get_mut(a) {
                *m = if *m == UNTOUCHED || *m == me {
                    me
                } else {
                    SHARED
                };
            }
        };
        for (b, w) in self.bounds.windows(2).enumerate() {
            let me = b as u32 + 1;
            for &(i, js) in &rows[w[0]..w[1]] {
                add(i, me);
                if !flags.full {
                    for &jr in js {
                        let j = jr as u32 as usize & mask;
                        if flags.newton || j < flags.nlocal {
                            add(j, me);
                        }
                    }
                }
            }
        }
        self.taken += 1;
    }
}

/// Phase 1 of a force-only step for one block: [`Sum`]'s additions, in its order, each made
/// to the block's copy of f when the atom is the block's alone, pushed as an event to the
/// bucket of the phase-2 task owning the atom when it is shared; any other atom marks the
/// result stale.
struct Own<'e, const J: u8> {
    f: &'e mut [f64],
    mark: &'e [u32],
    me: u32,
    buckets: &'e mut [Vec<Event>],
    chunk: u32,
    nlocal: usize,
    /// The row being summed (`usize::MAX` before the first) and the force on it so far.
    i: usize,
    fi: [f64; 3],
    stale: bool,
}

impl<const J: u8> Own<'_, J> {
    #[inline(always)]
    fn push(&mut self, atom: usize, v: [f64; 3]) {
        let atom = atom as u32;
        self.buckets[(atom / self.chunk) as usize].push(Event { v, atom });
    }

    /// A finished row: `f[i] += fi` (nothing before the first row).
    #[inline(always)]
    fn add_row(&mut self) {
        let (i, fi) = (self.i, self.fi);
        if i == usize::MAX {
            return;
        }
        match self.mark[i] {
            m if m == self.me => {
                let f = &mut self.f[3 * i..3 * i + 3];
                f[0] += fi[0];
                f[1] += fi[1];
                f[2] += fi[2];
            }
            SHARED => self.push(i, fi),
            _ => self.stale = true,
        }
    }

    /// The lanes of a batch, in order (as [`Sum::batch`]).
    #[inline(always)]
    fn batch(&mut self, b: &PairBatch, is: &[u32], js: &[u32]) {
        for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (_, fv) = lane_force(b, l);
            if i != self.i {
                self.add_row();
                (self.i, self.fi) = (i, [0.0; 3]);
            }
            self.fi[0] += fv[0];
            self.fi[1] += fv[1];
            self.fi[2] += fv[2];
            if J == J_ALWAYS || (J == J_OWNED && j < self.nlocal) {
                match self.mark[j] {
                    m if m == self.me => {
                        let fj = &mut self.f[3 * j..3 * j + 3];
                        fj[0] -= fv[0];
                        fj[1] -= fv[1];
                        fj[2] -= fv[2];
                    }
                    SHARED => self.push(j, [-fv[0], -fv[1], -fv[2]]),
                    _ => self.stale = true,
                }
            }
        }
    }
}

/// One block's phase 1: its rows walked into its copy of `f0` and its events; returns whether
/// the marks were stale.
#[allow(clippy::too_many_arguments)]
fn block<const J: u8>(
    walk: &Walk,
    b: &mut Block,
    rows: &[(usize, &[i32])],
    f0: &[f64],
    mark: &[u32],
    me: u32,
    (ntasks, chunk): (usize, usize),
    nlocal: usize,
) -> Result<bool, Error> {
    b.own.clear();
    b.own.extend_from_slice(f0);
    b.events.resize_with(ntasks, Vec::new);
    b.events.iter_mut().for_each(Vec::clear);
    let mut own = Own::<J> {
        f: &mut b.own,
        mark,
        me,
        buckets: &mut b.events,
        chunk: chunk as u32,
        nlocal,
        i: usize::MAX,
        fi: [0.0; 3],
        stale: false,
    };
    let rows = rows.iter().map(|&r| Ok(r));
    walk.rows(rows, &mut b.bt, &mut b.near, |bt, is, js| {
        own.batch(bt, is, js)
    })?;
    own.add_row();
    Ok(own.stale)
}

/// A force-only step of [`super::threaded`]: phase 1 walks one block of rows per thread
/// ([`Own`]); phase 2, per range of atoms, copies each atom's force from the copy of the block
/// that alone added to it and adds the shared atoms' events in block order (list order).
pub(crate) fn force_only(
    walk: &Walk,
    w: &mut Workers,
    rows: &[(usize, &[i32])],
    f: &mut [f64],
    flags: Flags,
) -> Result<(), Error> {
    let nall = f.len() / 3;
    let nb = w.threads();
    let chunk = nall.div_ceil(nb).max(1);
    let ntasks = nall.div_ceil(chunk);
    let key = rows_key(rows, flags, walk.mask, nall, nb);
    let owners = &mut w.owners;
    if owners.key != Some(key) {
        owners.take(rows, flags, walk.mask, nall, nb);
        owners.key = Some(key);
    }
    let (team, blocks) = (&w.team, &mut w.blocks[..nb]);
    team.scope(|| {
        for _ in 0..2 {
            let (mark, bounds) = (&owners.mark[..], &owners.bounds[..]);
            let f0: &[f64] = f;
            let j_rule = match (flags.full, flags.newton) {
                (true, _) => J_NEVER,
                (false, true) => J_ALWAYS,
                (false, false) => J_OWNED,
            };
            team.for_each(blocks, &|k, b: &mut Block| {
                let rows = &rows[bounds[k]..bounds[k + 1]];
                let me = k as u32 + 1;
                let tasks = (ntasks, chunk);
                let r = match j_rule {
                    J_NEVER => block::<J_NEVER>(walk, b, rows, f0, mark, me, tasks, flags.nlocal),
                    J_ALWAYS => block::<J_ALWAYS>(walk, b, rows, f0, mark, me, tasks, flags.nlocal),
                    _ => block::<J_OWNED>(walk, b, rows, f0, mark, me, tasks, flags.nlocal),
                };
                (b.stale, b.err) = match r {
                    Ok(stale) => (stale, None),
                    Err(e) => (false, Some(e)),
                };
            });
            if let Some(e) = blocks.iter_mut().find_map(|b| b.err.take()) {
                return Err(e);
            }
            if blocks.iter().any(|b| b.stale) {
                // The rows changed in place: take the marks again and walk the step again
                // (f is untouched until phase 2).
                owners.take(rows, flags, walk.mask, nall, nb);
                continue;
            }
            let done: &[Block] = blocks;
            let mut parts: Vec<_> = f.chunks_mut(3 * chunk).enumerate().collect();
            team.for_each(&mut parts, &|_, (t, f)| {
                let lo = *t * chunk;
                gather(done, &mark[lo..lo + f.len() / 3], f, lo);
                add_events(done, *t, f, lo);
            });
            return Ok(());
        }
        Err(Error::invalid(
            "internal: the threaded walk's blocks changed during the step",
        ))
    })
}

/// Phase 2's copies: each atom `lo + k` of `f` that one block alone added to gets that block's
/// result.
fn gather(blocks: &[Block], mark: &[u32], f: &mut [f64], lo: usize) {
    for (k, (&m, fa)) in mark.iter().zip(f.chunks_exact_mut(3)).enumerate() {
        if m != UNTOUCHED && m != SHARED {
            let a = 3 * (lo + k);
            fa.copy_from_slice(&blocks[m as usize - 1].own[a..a + 3]);
        }
    }
}
