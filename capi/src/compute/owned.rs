//! The force-only step of a threaded walk (issue 58): each thread walks one block of rows, in
//! list order, and adds straight into its own copy of f the forces of the atoms that only its
//! block touches; the atoms that several blocks touch get events ([`Event`], tagged with their
//! row's list position) that phase 2 merges back into list order. Every addition is the
//! one-thread walk's ([`Sum`]), in its order, so the bits do not depend on the thread count.
//! The blocks are slabs of space (the rows' atoms cut along the longest extent into equal
//! counts), whatever the order of the list: only the atoms within a cut-off of a slab's faces
//! are shared.
//!
//! Which block touches which atom ([`Owners`]) is found from the rows' raw entries (every
//! listed pair, in range or not: a superset of the pairs evaluated) and kept while the rows stay
//! where they are. The walk checks it as it adds: a block that adds to an atom marked as
//! another block's (rows changed in place) marks its result stale, and the step is walked again
//! after the marks are taken anew, so the result never depends on that key.

use dpdnl::PairBatch;
use dpdnl::host::lane_force;

use super::tally::Flags;
use super::threads::{Block, Event, Workers};
use super::walk::{J_ALWAYS, J_NEVER, J_OWNED, Walk};
use crate::Error;

/// An atom no block adds to.
const UNTOUCHED: u32 = 0;

/// An atom that several blocks add to: its additions are events.
const SHARED: u32 = u32::MAX;

/// An atom without a row.
const NO_ROW: u32 = u32::MAX;

/// Which block adds to each atom, and the blocks' rows, for one set of rows.
#[derive(Default)]
pub(crate) struct Owners {
    /// Per atom: [`UNTOUCHED`], [`SHARED`] or 1 + the block that alone adds to it.
    mark: Vec<u32>,
    /// Per atom: the list position of its row ([`NO_ROW`] for none).
    pos: Vec<u32>,
    /// Each block's rows (list positions, in list order).
    blocks: Vec<Vec<u32>>,
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
    /// The blocks of `rows` (slabs of their atoms' positions `x`, `nb` of them) and the marks:
    /// each row's atom, and each listed j whose side the walk adds (a half list; with newton
    /// off, an owned j). A list with an atom in two rows is one block.
    #[allow(clippy::too_many_arguments)]
    fn take(
        &mut self,
        rows: &[(usize, &[i32])],
        x: &[f64],
        flags: Flags,
        mask: usize,
        nall: usize,
        nb: usize,
    ) {
        self.pos.clear();
        self.pos.resize(nall, NO_ROW);
        let mut twice = false;
        for (r, &(i, _)) in rows.iter().enumerate() {
            match self.pos.get_mut(i) {
                Some(p) if *p == NO_ROW => *p = r as u32,
                _ => twice = true,
            }
        }
        let coord = |axis: usize, i: usize| x.get(3 * i + axis).copied().unwrap_or(0.0);
        let extent = |axis: usize| {
            let (lo, hi) = rows.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &(i, _)| {
                (lo.min(coord(axis, i)), hi.max(coord(axis, i)))
            });
            hi - lo
        };
        let axis = (0..3)
            .max_by(|&a, &b| extent(a).total_cmp(&extent(b)))
            .unwrap_or(0);
        // The slabs' upper faces: the coordinates of ranks n/nb, 2n/nb, ...
        let mut c: Vec<f64> = rows.iter().map(|&(i, _)| coord(axis, i)).collect();
        let faces: Vec<f64> = (1..nb)
            .map(|k| {
                let at = (k * c.len() / nb).min(c.len().saturating_sub(1));
                *c.select_nth_unstable_by(at, f64::total_cmp).1
            })
            .collect();
        self.blocks.resize_with(nb, Vec::new);
        self.blocks.iter_mut().for_each(Vec::clear);
        for (r, &(i, _)) in rows.iter().enumerate() {
            let b = if twice {
                0
            } else {
                faces.partition_point(|&f| f <= coord(axis, i))
            };
            self.blocks[b].push(r as u32);
        }
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
        for (b, block) in self.blocks.iter().enumerate() {
            let me = b as u32 + 1;
            for &r in block {
                let (i, js) = rows[r as usize];
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
    /// The list position of each atom's row.
    pos: &'e [u32],
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
    /// An event of row `i`'s: `f[atom] += v`.
    #[inline(always)]
    fn push(&mut self, i: usize, atom: usize, v: [f64; 3]) {
        let (atom, pos) = (atom as u32, self.pos[i]);
        self.buckets[(atom / self.chunk) as usize].push(Event { v, atom, pos });
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
            SHARED => self.push(i, i, fi),
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
                    SHARED => self.push(i, j, [-fv[0], -fv[1], -fv[2]]),
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
    mine: &[u32],
    f0: &[f64],
    (mark, pos): (&[u32], &[u32]),
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
        pos,
        me,
        buckets: &mut b.events,
        chunk: chunk as u32,
        nlocal,
        i: usize::MAX,
        fi: [0.0; 3],
        stale: false,
    };
    let rows = mine.iter().map(|&r| Ok(rows[r as usize]));
    walk.rows(rows, &mut b.bt, &mut b.near, |bt, is, js| {
        own.batch(bt, is, js)
    })?;
    own.add_row();
    Ok(own.stale)
}

/// A force-only step of [`super::threaded`]: phase 1 walks one block of rows per thread
/// ([`Own`]); phase 2, per range of atoms, copies each atom's force from the copy of the block
/// that alone added to it and adds the shared atoms' events merged into list order.
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
        owners.take(rows, walk.x, flags, walk.mask, nall, nb);
        owners.key = Some(key);
    }
    let (team, blocks) = (&w.team, &mut w.blocks[..nb]);
    team.scope(|| {
        for _ in 0..2 {
            let (mark, pos, mine) = (&owners.mark[..], &owners.pos[..], &owners.blocks[..]);
            let f0: &[f64] = f;
            let j_rule = match (flags.full, flags.newton) {
                (true, _) => J_NEVER,
                (false, true) => J_ALWAYS,
                (false, false) => J_OWNED,
            };
            team.for_each(blocks, &|k, b: &mut Block| {
                let me = k as u32 + 1;
                let tasks = (ntasks, chunk);
                let m = (mark, pos);
                let nl = flags.nlocal;
                let r = match j_rule {
                    J_NEVER => block::<J_NEVER>(walk, b, rows, &mine[k], f0, m, me, tasks, nl),
                    J_ALWAYS => block::<J_ALWAYS>(walk, b, rows, &mine[k], f0, m, me, tasks, nl),
                    _ => block::<J_OWNED>(walk, b, rows, &mine[k], f0, m, me, tasks, nl),
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
                owners.take(rows, walk.x, flags, walk.mask, nall, nb);
                continue;
            }
            let done: &[Block] = blocks;
            let mut parts: Vec<_> = f.chunks_mut(3 * chunk).enumerate().collect();
            team.for_each(&mut parts, &|_, (t, f)| {
                let lo = *t * chunk;
                gather(done, &mark[lo..lo + f.len() / 3], f, lo);
                merge_events(done, *t, f, lo);
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

/// Phase 2's events: bucket `t` of every block (each in list order), merged by list position
/// and added to the atoms `lo..` of `f`: a block's events are taken as a run up to the next
/// position of another block's (a per-event choice between the blocks cost 25 ns an event,
/// n = 16, 2 threads).
fn merge_events(blocks: &[Block], t: usize, f: &mut [f64], lo: usize) {
    let mut add = |e: &Event| {
        let k = 3 * (e.atom as usize - lo);
        let fa = &mut f[k..k + 3];
        fa[0] += e.v[0];
        fa[1] += e.v[1];
        fa[2] += e.v[2];
    };
    // The first block's run up to the next event of any other, then that block's run, ...
    let streams: Vec<&[Event]> = blocks.iter().map(|b| &b.events[t][..]).collect();
    let mut at = vec![0usize; streams.len()];
    loop {
        let heads = streams.iter().zip(&at).enumerate();
        let mut order = heads.filter_map(|(b, (s, &k))| s.get(k).map(|e| (e.pos, b)));
        let Some(first) = order.next() else { break };
        let (mut lo_pos, mut b) = first;
        let mut bound = u32::MAX;
        for (p, c) in order {
            if p < lo_pos {
                bound = bound.min(lo_pos);
                (lo_pos, b) = (p, c);
            } else {
                bound = bound.min(p);
            }
        }
        let run = &streams[b][at[b]..];
        let n = run.iter().take_while(|e| e.pos < bound).count();
        run[..n].iter().for_each(&mut add);
        at[b] += n;
    }
}
