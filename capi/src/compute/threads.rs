//! The threads inside a rank ([`Workers`]): row blocks evaluated in parallel, their results
//! added in list order, so every sum keeps the one-thread order and the bits do not depend on
//! the thread count. Force-only steps: `owned.rs`; tally steps: per-pair records, here.

use dpdnl::host::{Batcher, lane_force};

use super::owned::{Owners, force_only};
use super::tally::*;
use super::walk::*;
use crate::Error;
use crate::team::{DpdnlLaunch, Team};

/// Row blocks per thread of a threaded walk (the team's threads take them as they finish).
pub(crate) const BLOCKS_PER_THREAD: usize = 4;

/// Rows of a threaded walk's window: its events or records (33 pairs a row at n = 16, 32 B
/// each: about 1 MB) stay in the cache from phase 1 to phase 2. On the 2-vCPU Xeon of the
/// commit (n = 16, 20000 atoms, 2 threads) 2048 or 4096 rows were within the noise of 1024
/// (pair time −3 %), 512 rows and one window for the whole list slower.
pub(crate) const WINDOW_ROWS: usize = 1024;

/// The threads of a pair style's walk over a LAMMPS list ([`walk_pairs`]) and their buffers,
/// kept from step to step.
///
/// Force-only steps ([`force_only`]): one block of rows per thread, each adding straight into
/// its own copy of f the forces of the atoms only it touches, and events for the atoms several
/// blocks touch ([`Owners`]); phase 2 copies the former and adds the latter in list order.
///
/// Tally steps: the rows are taken in windows of [`WINDOW_ROWS`], in list order.
/// Phase 1 splits a window into contiguous row blocks, evaluated in parallel; phase 2 adds
/// their results in list order, each task to a contiguous range of atoms, so that every atom's
/// force (and per-atom tallies) is summed in the single-threaded order. The bits do not depend
/// on the thread count (tested with 1, 2 and 3). Each block
/// stores, in list order, atom i, atom j, the force on i and what the tallies need; each task
/// scans every record and adds only to its atoms, and one more task sums the global energy and
/// virial over all records.
pub(crate) struct Workers {
    pub(crate) team: Team,
    pub(crate) blocks: Vec<Block>,
    /// Which block adds to which atom on force-only steps (kept while the rows are the same).
    pub(crate) owners: Owners,
}

/// One row block's buffers (phase 1).
#[derive(Default)]
pub(crate) struct Block {
    pub(crate) bt: Batcher,
    pub(crate) near: Vec<u32>,
    pub(crate) pairs: Vec<PairRec>,
    pub(crate) tally: Vec<TallyRec>,
    /// Force events by phase-2 task (force-only steps: the shared atoms' additions).
    pub(crate) events: Vec<Vec<Event>>,
    /// Its copy of f (force-only steps: the forces of the atoms only this block adds to).
    pub(crate) own: Vec<f64>,
    /// Bit per atom: the atoms this block adds to (force-only steps, [`Owners`]).
    pub(crate) seen: Vec<u64>,
    /// The atoms of other slabs its rows near a face add to (force-only steps, [`Owners`]).
    pub(crate) foreign: Vec<usize>,
    /// Whether the block met an atom marked as another block's ([`Owners`]).
    pub(crate) stale: bool,
    pub(crate) err: Option<Error>,
}

/// A force event of phase 1: `f[atom] += v`, made by the row at list position `pos`.
#[derive(Clone, Copy)]
pub(crate) struct Event {
    pub(crate) v: [f64; 3],
    pub(crate) atom: u32,
    pub(crate) pos: u32,
}

/// An evaluated pair: atoms i and j and the force on i (−it on j).
#[derive(Clone, Copy)]
pub(crate) struct PairRec {
    pub(crate) i: u32,
    pub(crate) j: u32,
    pub(crate) f: [f64; 3],
}

/// What the tallies of an evaluated pair need: energy, fpair, r_ij.
#[derive(Clone, Copy)]
pub(crate) struct TallyRec {
    pub(crate) energy: f64,
    pub(crate) fpair: Option<f64>,
    pub(crate) dr: [f64; 3],
}

impl Workers {
    /// `threads` (≥ 2) threads: the host's through `launch` ([`crate::dpdnl_pair_launcher`]),
    /// else a pool shared by every handle with that count and created once.
    pub(crate) fn new(threads: usize, launch: DpdnlLaunch) -> Result<Workers, Error> {
        Ok(Workers {
            team: Team::new(threads, launch).map_err(Error::invalid)?,
            blocks: (0..threads * BLOCKS_PER_THREAD)
                .map(|_| Block::default())
                .collect(),
            owners: Owners::default(),
        })
    }

    /// The number of threads.
    pub(crate) fn threads(&self) -> usize {
        self.team.threads()
    }

    /// The same number of threads, now the host's through `launch` (or the pool's); the
    /// blocks' buffers are kept.
    pub(crate) fn set_launch(&mut self, launch: DpdnlLaunch) -> Result<(), Error> {
        self.team = Team::new(self.threads(), launch).map_err(Error::invalid)?;
        Ok(())
    }

    /// Whether the threads are the host's ([`crate::dpdnl_pair_launcher`]).
    pub(crate) fn on_host_threads(&self) -> bool {
        self.team.is_host()
    }
}

/// [`walk_pairs`] on the threads of `w` ([`Workers`]).
pub(crate) fn threaded(
    walk: &Walk,
    w: &mut Workers,
    rows: &[(usize, &[i32])],
    f: &mut [f64],
    sinks: &mut Sinks,
    flags: Flags,
) -> Result<(), Error> {
    if !sinks.any() {
        return force_only(walk, w, rows, f, flags);
    }
    // Phase 2's tasks: contiguous ranges of atoms, each with its part of f, eatom and vatom;
    // one more task for the global energy and virial.
    let nall = f.len() / 3;
    let tasks = w.blocks.len() / BLOCKS_PER_THREAD;
    let chunk = nall.div_ceil(tasks).max(1);
    let ntasks = nall.div_ceil(chunk);
    pub(crate) fn split(
        s: Option<&mut [f64]>,
        len: usize,
        count: usize,
    ) -> Vec<Option<&mut [f64]>> {
        match s {
            Some(s) => s.chunks_mut(len).map(Some).collect(),
            None => (0..count).map(|_| None).collect(),
        }
    }
    let eatom = split(sinks.eatom.as_deref_mut(), chunk, ntasks);
    let vatom = split(sinks.vatom.as_deref_mut(), 6 * chunk, ntasks);
    let mut parts: Vec<_> = f
        .chunks_mut(3 * chunk)
        .zip(eatom.into_iter().zip(vatom))
        .enumerate()
        .map(|(k, (f, (eatom, vatom)))| {
            let s = Sinks {
                eng: None,
                virial: None,
                eatom,
                vatom,
            };
            (k * chunk, f, s)
        })
        .collect();
    let mut global = Sinks {
        eng: sinks.eng.as_deref_mut(),
        virial: sinks.virial.as_deref_mut(),
        eatom: None,
        vatom: None,
    };
    let (team, blocks) = (&w.team, &mut w.blocks);
    let nb = blocks.len();
    // Window by window (whole rows, in list order), so that the records of a window stay in
    // the cache between the phases: one team scope per call (one pool `install`), the phases
    // inside it.
    team.scope(|| {
        for win in rows.chunks(WINDOW_ROWS) {
            // Phase 1: contiguous row blocks of the window, evaluated in parallel into their
            // records.
            let per = win.len().div_ceil(nb);
            team.for_each(blocks, &|k, b: &mut Block| {
                let part = &win[(k * per).min(win.len())..((k + 1) * per).min(win.len())];
                let rows = part.iter().map(|&r| Ok(r));
                b.pairs.clear();
                b.tally.clear();
                let (pairs, tally) = (&mut b.pairs, &mut b.tally);
                b.err = walk
                    .rows(rows, &mut b.bt, &mut b.near, |bt, is, js| {
                        for (l, (&i, &j)) in is.iter().zip(js).enumerate() {
                            let (dr, fv) = lane_force(bt, l);
                            pairs.push(PairRec { i, j, f: fv });
                            tally.push(TallyRec {
                                energy: bt.energy[l],
                                fpair: super::tally::central(bt, l),
                                dr,
                            });
                        }
                    })
                    .err();
            });
            if let Some(e) = blocks.iter_mut().find_map(|b| b.err.take()) {
                return Err(e);
            }
            let done: &[Block] = blocks;
            // Phase 2 of a tally step: every record of the window in list order, once per range
            // of atoms (forces and per-atom tallies), and once for the global energy and virial.
            let mut tasks: Vec<Replay> = global
                .any()
                .then_some(Replay::Global(&mut global))
                .into_iter()
                .chain(parts.iter_mut().map(Replay::Part))
                .collect();
            team.for_each(&mut tasks, &|_, task| match task {
                Replay::Global(g) => replay(done, &mut [], 0, g, flags),
                Replay::Part((lo, f, s)) => replay(done, f, *lo, s, flags),
            });
        }
        Ok(())
    })
}

/// A task of phase 2 of a tally step: a range of atoms (its first atom, its part of f and of
/// the per-atom tallies) or the global energy and virial.
pub(crate) enum Replay<'p, 's> {
    Part(&'p mut (usize, &'s mut [f64], Sinks<'s>)),
    Global(&'p mut Sinks<'s>),
}

/// Phase 2 of a threaded walk: every record of `blocks` in list order, added to the atoms `lo..`
/// of `f` and to `sinks` (its per-atom arrays start at atom `lo` too).
pub(crate) fn replay(blocks: &[Block], f: &mut [f64], lo: usize, sinks: &mut Sinks, flags: Flags) {
    let tallying = sinks.any();
    let mut apply = Apply::new(f, lo, sinks, flags);
    for b in blocks {
        if tallying {
            for (p, t) in b.pairs.iter().zip(&b.tally) {
                apply.pair(p.i as usize, p.j as usize, p.f, t.energy, t.fpair, t.dr);
            }
        } else {
            for p in &b.pairs {
                apply.pair(p.i as usize, p.j as usize, p.f, 0.0, Some(0.0), [0.0; 3]);
            }
        }
    }
    apply.finish_row();
}
