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
use crate::team::Team;

/// An atom no block adds to.
const UNTOUCHED: u32 = 0;

/// An atom that several blocks add to: its additions are events.
const SHARED: u32 = u32::MAX;

/// Which block adds to each atom, and the blocks' rows, for one set of rows.
#[derive(Default)]
pub(crate) struct Owners {
    /// Per atom: [`UNTOUCHED`], [`SHARED`] or 1 + the block that alone adds to it.
    mark: Vec<u32>,
    /// Each block's rows (list positions, in list order).
    blocks: Vec<Vec<u32>>,
    /// What the marks were taken for ([`rows_key`]).
    key: Option<u64>,
    /// How far along the slabs' axis a listed j is assumed to lie from its row's atom (0: not
    /// yet set; doubled when a pair farther apart is met).
    reach: f64,
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

/// Bit `a` of a bit set.
#[inline(always)]
fn bit(bits: &[u64], a: usize) -> bool {
    bits.get(a / 64).is_some_and(|w| w >> (a % 64) & 1 != 0)
}

/// The slabs: each row's block and the faces between them, along one axis.
struct Slabs {
    axis: usize,
    /// The blocks' upper faces (`nb - 1` of them): block k holds the atoms with
    /// `faces[k - 1] <= x < faces[k]` along `axis`.
    faces: Vec<f64>,
}

impl Slabs {
    /// The slabs of `rows`' atoms (positions `x`): cut along their longest extent into `nb`
    /// equal counts.
    fn new(rows: &[(usize, &[i32])], x: &[f64], nb: usize) -> Slabs {
        let coord = |axis: usize, i: usize| x.get(3 * i + axis).copied().unwrap_or(0.0);
        let (lo, hi) = rows
            .iter()
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), &(i, _)| {
                let c = [coord(0, i), coord(1, i), coord(2, i)];
                (
                    [lo[0].min(c[0]), lo[1].min(c[1]), lo[2].min(c[2])],
                    [hi[0].max(c[0]), hi[1].max(c[1]), hi[2].max(c[2])],
                )
            });
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        // The slabs' upper faces: the coordinates of ranks n/nb, 2n/nb, ...
        let mut c: Vec<f64> = rows.iter().map(|&(i, _)| coord(axis, i)).collect();
        let faces = (1..nb)
            .map(|k| {
                let at = (k * c.len() / nb).min(c.len().saturating_sub(1));
                *c.select_nth_unstable_by(at, f64::total_cmp).1
            })
            .collect();
        Slabs { axis, faces }
    }

    /// The slab of a coordinate along the axis.
    #[inline(always)]
    fn of(&self, c: f64) -> usize {
        self.faces.partition_point(|&f| f <= c)
    }

    /// Whether `c`, in slab `k`, lies within `reach` of one of the slab's faces.
    #[inline(always)]
    fn near_face(&self, k: usize, c: f64, reach: f64) -> bool {
        let lo = k.checked_sub(1).and_then(|k| self.faces.get(k));
        let hi = self.faces.get(k);
        lo.is_some_and(|&f| c - f <= reach) || hi.is_some_and(|&f| f - c <= reach)
    }
}

impl Owners {
    /// The blocks of `rows` (slabs of their atoms' positions, one per block of `blocks`) and
    /// the marks: each row's atom, and each listed j whose side the walk adds (a half list;
    /// with newton off, an owned j). A list with an atom in two rows is one block. The slabs
    /// are cut serially (O(rows)); the marks are then taken on the team's threads, without a
    /// serial pass over every entry:
    /// - `exact`: each block sets the bits of the atoms it adds to ([`Block::seen`], every
    ///   entry of its rows) and each atom's mark is read from those bits;
    /// - else each atom is marked as its slab's, and only the rows within [`Owners::reach`] of
    ///   a face (along the axis) are read: an entry in another slab marks its atom shared. A
    ///   listed pair farther apart than the reach meets a mark of another block in the walk,
    ///   which then takes the marks again, exactly, and doubles the reach.
    fn take(
        &mut self,
        team: &Team,
        blocks: &mut [Block],
        rows: &[(usize, &[i32])],
        walk: &Walk,
        (flags, nall): (Flags, usize),
        exact: bool,
    ) {
        let (nb, x) = (blocks.len(), walk.x);
        let words = nall.div_ceil(64);
        // An atom in two rows (checked with a bit set, O(rows)).
        let mut row_bits = vec![0u64; words];
        let twice = rows.iter().any(|&(i, _)| match row_bits.get_mut(i / 64) {
            Some(w) if *w >> (i % 64) & 1 == 0 => {
                *w |= 1 << (i % 64);
                false
            }
            _ => true,
        });
        let slabs = Slabs::new(rows, x, nb);
        let coord = |i: usize| x.get(3 * i + slabs.axis).copied().unwrap_or(0.0);
        self.blocks.resize_with(nb, Vec::new);
        self.blocks.iter_mut().for_each(Vec::clear);
        for (r, &(i, _)) in rows.iter().enumerate() {
            let b = if twice { 0 } else { slabs.of(coord(i)) };
            self.blocks[b].push(r as u32);
        }
        if self.mark.len() != nall {
            self.mark.clear();
            self.mark.resize(nall, UNTOUCHED);
        }
        if self.reach == 0.0 {
            // Twice the largest cut-off: a LAMMPS list's skin up to the cut-off, the own
            // list's margin.
            self.reach = 2.0
                * walk
                    .row_cutsq
                    .iter()
                    .fold(0.0, |m: f64, &c| m.max(c))
                    .sqrt();
            if self.reach.is_nan() || self.reach <= 0.0 {
                self.reach = f64::INFINITY;
            }
        }
        // The j's whose side the walk adds.
        let sided = |jr: i32| {
            let j = jr as u32 as usize & walk.mask;
            (!flags.full && (flags.newton || j < flags.nlocal)).then_some(j)
        };
        let mine = &self.blocks[..];
        let per = 64 * words.div_ceil(nb).max(1);
        if exact || twice || nb == 1 {
            team.for_each(blocks, &|k, b: &mut Block| {
                b.seen.clear();
                b.seen.resize(words, 0);
                let seen = &mut b.seen[..];
                let mut add = |a: usize| {
                    if let Some(w) = seen.get_mut(a / 64) {
                        *w |= 1 << (a % 64);
                    }
                };
                for &r in &mine[k] {
                    let (i, js) = rows[r as usize];
                    add(i);
                    js.iter().filter_map(|&jr| sided(jr)).for_each(&mut add);
                }
            });
            let done: &[Block] = blocks;
            let mut parts: Vec<_> = self.mark.chunks_mut(per).enumerate().collect();
            team.for_each(&mut parts, &|_, (t, mark)| {
                for (k, m) in mark.iter_mut().enumerate() {
                    let a = *t * per + k;
                    *m = UNTOUCHED;
                    for (b, block) in done.iter().enumerate() {
                        if bit(&block.seen, a) {
                            *m = if *m == UNTOUCHED {
                                b as u32 + 1
                            } else {
                                SHARED
                            };
                        }
                    }
                }
            });
        } else {
            let (slabs, reach) = (&slabs, self.reach);
            let mut parts: Vec<_> = self.mark.chunks_mut(per).enumerate().collect();
            team.for_each(&mut parts, &|_, (t, mark)| {
                for (k, m) in mark.iter_mut().enumerate() {
                    *m = slabs.of(coord(*t * per + k)) as u32 + 1;
                }
            });
            team.for_each(blocks, &|k, b: &mut Block| {
                b.foreign.clear();
                for &r in &mine[k] {
                    let (i, js) = rows[r as usize];
                    if slabs.near_face(k, coord(i), reach) {
                        let far = js.iter().filter_map(|&jr| sided(jr));
                        b.foreign.extend(far.filter(|&j| slabs.of(coord(j)) != k));
                    }
                }
            });
            for b in blocks.iter() {
                for &j in &b.foreign {
                    if let Some(m) = self.mark.get_mut(j) {
                        *m = SHARED;
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
    /// The rows, this block's of them (list positions, in list order) and the one being
    /// walked (`at`, its list position `pos`): the events' tags.
    rows: &'e [(usize, &'e [i32])],
    mine: &'e [u32],
    at: usize,
    pos: u32,
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
    /// An event of the row being walked: `f[atom] += v`.
    #[inline(always)]
    fn push(&mut self, atom: usize, v: [f64; 3]) {
        let (atom, pos) = (atom as u32, self.pos);
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
            SHARED => self.push(i, fi),
            _ => self.stale = true,
        }
    }

    /// The next of this block's rows whose atom is `i` (rows without a pair in range are
    /// skipped by the walk): its list position tags the events.
    #[inline(always)]
    fn next_row(&mut self, i: usize) {
        while let Some(&r) = self.mine.get(self.at) {
            if self.rows.get(r as usize).is_some_and(|row| row.0 == i) {
                self.pos = r;
                return;
            }
            self.at += 1;
        }
        self.pos = u32::MAX;
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
                self.next_row(i);
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

/// One block's phase 1: its rows walked into its copy of `f0` (only the atoms it alone adds
/// to are copied and read) and its events; returns whether the marks were stale.
#[allow(clippy::too_many_arguments)]
fn block<const J: u8>(
    walk: &Walk,
    b: &mut Block,
    rows: &[(usize, &[i32])],
    mine: &[u32],
    f0: &[f64],
    mark: &[u32],
    me: u32,
    (ntasks, chunk): (usize, usize),
    nlocal: usize,
) -> Result<bool, Error> {
    if b.own.len() < f0.len() {
        b.own.resize(f0.len(), 0.0);
    }
    for ((own, f), _) in (b.own.chunks_exact_mut(3).zip(f0.chunks_exact(3)))
        .zip(mark)
        .filter(|&(_, &m)| m == me)
    {
        own.copy_from_slice(f);
    }
    b.events.resize_with(ntasks, Vec::new);
    b.events.iter_mut().for_each(Vec::clear);
    let mut own = Own::<J> {
        f: &mut b.own,
        mark,
        rows,
        mine,
        at: 0,
        pos: u32::MAX,
        me,
        buckets: &mut b.events,
        chunk: chunk as u32,
        nlocal,
        i: usize::MAX,
        fi: [0.0; 3],
        stale: false,
    };
    let walked = mine.iter().map(|&r| Ok(rows[r as usize]));
    walk.rows(walked, &mut b.bt, &mut b.near, |bt, is, js| {
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
    let (team, blocks, owners) = (&w.team, &mut w.blocks[..nb], &mut w.owners);
    team.scope(|| {
        if owners.key != Some(key) {
            owners.take(team, blocks, rows, walk, (flags, nall), false);
            owners.key = Some(key);
        }
        for _ in 0..2 {
            let (mark, mine) = (&owners.mark[..], &owners.blocks[..]);
            let f0: &[f64] = f;
            let j_rule = match (flags.full, flags.newton) {
                (true, _) => J_NEVER,
                (false, true) => J_ALWAYS,
                (false, false) => J_OWNED,
            };
            team.for_each(blocks, &|k, b: &mut Block| {
                let me = k as u32 + 1;
                let tasks = (ntasks, chunk);
                let m = mark;
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
                // (f is untouched until phase 2), the reach doubled for the next rows.
                owners.reach *= 2.0;
                owners.take(team, blocks, rows, walk, (flags, nall), true);
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
