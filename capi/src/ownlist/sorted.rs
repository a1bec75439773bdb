//! Atoms sorted by bin (the counting sort of a build), owned atoms and ghosts apart.

use super::passes::par_items;
use super::{CHUNK_ATOMS, Cloud};
use crate::team::Team;

/// Atoms sorted by bin: where each bin starts, and each atom's index, position and tag in bin
/// order (structure of arrays: the distance loop reads them contiguously).
#[derive(Debug, Default)]
pub(super) struct Sorted {
    pub(super) start: Vec<u32>,
    pub(super) order: Vec<u32>,
    pub(super) sx: Vec<f64>,
    pub(super) sy: Vec<f64>,
    pub(super) sz: Vec<f64>,
    pub(super) stag: Vec<i32>,
}

/// One run of a [`Sorted`]: positions, atom indices and tags.
pub(super) type RunView<'a> = (&'a [f64], &'a [f64], &'a [f64], &'a [u32], &'a [i32]);

/// The atoms of one range of bins, placed by one thread into its range of the output.
struct Place<'o> {
    bins: std::ops::Range<usize>,
    out: &'o mut [u32],
}

/// One range of the output, gathered by one thread.
struct Gather<'o> {
    order: &'o [u32],
    sx: &'o mut [f64],
    sy: &'o mut [f64],
    sz: &'o mut [f64],
    stag: &'o mut [i32],
}

impl Sorted {
    /// The atoms `run` (in bin order).
    pub(super) fn run(&self, run: std::ops::Range<usize>) -> RunView<'_> {
        (
            &self.sx[run.clone()],
            &self.sy[run.clone()],
            &self.sz[run.clone()],
            &self.order[run.clone()],
            &self.stag[run],
        )
    }

    /// Counting sort of the atoms `atoms` by their bin `bins[a]` (of `nbins`), stable (atoms
    /// of one bin in index order). With a team, the placing and the gathering run on its
    /// threads: each thread places the atoms of one range of bins (a range of the output, so
    /// the threads write apart) and gathers one range of the output; the result is the same.
    pub(super) fn sort(
        &mut self,
        atoms: std::ops::Range<usize>,
        bins: &[u32],
        nbins: usize,
        c: &Cloud,
        team: Option<&Team>,
    ) {
        self.count(atoms.clone(), bins, nbins);
        self.place(atoms, bins, nbins, team);
        self.gather(c, team);
    }

    /// Where each bin starts: the atoms per bin, summed.
    fn count(&mut self, atoms: std::ops::Range<usize>, bins: &[u32], nbins: usize) {
        self.start.clear();
        self.start.resize(nbins + 1, 0);
        for a in atoms {
            self.start[bins[a] as usize + 1] += 1;
        }
        for b in 0..nbins {
            self.start[b + 1] += self.start[b];
        }
    }

    /// Each atom's index into `order`, in bin order (stable), by ranges of bins.
    fn place(
        &mut self,
        atoms: std::ops::Range<usize>,
        bins: &[u32],
        nbins: usize,
        team: Option<&Team>,
    ) {
        let n = atoms.len();
        self.order.clear();
        self.order.resize(n, 0);
        // The bin ranges: about n / parts atoms each.
        let parts = match team {
            Some(t) if n >= 2 * CHUNK_ATOMS => t.threads(),
            _ => 1,
        };
        let mut cuts = vec![0usize];
        for k in 1..parts {
            let want = (n * k / parts) as u32;
            let b = self.start.partition_point(|&s| s < want).min(nbins);
            if b > *cuts.last().unwrap_or(&0) {
                cuts.push(b);
            }
        }
        cuts.push(nbins);
        let mut places = Vec::with_capacity(cuts.len() - 1);
        let mut rest: &mut [u32] = &mut self.order;
        for w in cuts.windows(2) {
            let len = (self.start[w[1]] - self.start[w[0]]) as usize;
            let (head, tail) = rest.split_at_mut(len);
            places.push(Place {
                bins: w[0]..w[1],
                out: head,
            });
            rest = tail;
        }
        let start = &self.start;
        let (a0, a1) = (atoms.start, atoms.end);
        par_items(team, &mut places, &|_, p| {
            let (lo, hi) = (p.bins.start as u32, p.bins.end as u32);
            let base = start[p.bins.start];
            let mut fill: Vec<u32> = start[p.bins.clone()].iter().map(|&s| s - base).collect();
            for (a, &b) in bins[a0..a1].iter().enumerate() {
                if b >= lo && b < hi {
                    let f = &mut fill[(b - lo) as usize];
                    p.out[*f as usize] = (a0 + a) as u32;
                    *f += 1;
                }
            }
        });
    }

    /// The positions and tags of the atoms in `order`, in chunks.
    fn gather(&mut self, c: &Cloud, team: Option<&Team>) {
        let n = self.order.len();
        for v in [&mut self.sx, &mut self.sy, &mut self.sz] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.stag.clear();
        self.stag.resize(n, 0);
        let mut gathers: Vec<Gather> = self
            .order
            .chunks(CHUNK_ATOMS)
            .zip(self.sx.chunks_mut(CHUNK_ATOMS))
            .zip(self.sy.chunks_mut(CHUNK_ATOMS))
            .zip(self.sz.chunks_mut(CHUNK_ATOMS))
            .zip(self.stag.chunks_mut(CHUNK_ATOMS))
            .map(|((((order, sx), sy), sz), stag)| Gather {
                order,
                sx,
                sy,
                sz,
                stag,
            })
            .collect();
        par_items(team, &mut gathers, &|_, g| {
            for (k, &a) in g.order.iter().enumerate() {
                let a = a as usize;
                g.sx[k] = c.x[3 * a];
                g.sy[k] = c.x[3 * a + 1];
                g.sz[k] = c.x[3 * a + 2];
                g.stag[k] = c.tag[a];
            }
        });
    }
}
