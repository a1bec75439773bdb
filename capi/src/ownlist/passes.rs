//! The threaded passes over all atoms before the rows: the bounding box, each atom's bin and
//! the moved-half-margin check, in pieces of [`CHUNK_ATOMS`] whose outputs do not overlap, so
//! the result does not depend on the team.

use super::grid::Geometry;
use super::{CHUNK_ATOMS, Cloud};
use crate::list::moved_half_margin;
use crate::team::Team;

/// `f(k, &mut items[k])` for every item: on the team's threads when there is a team of more
/// than one and more than one item, else in order on this thread. Every item is processed
/// once, by one thread, so results do not depend on the team.
pub(super) fn par_items<T: Send>(
    team: Option<&Team>,
    items: &mut [T],
    f: &(dyn Fn(usize, &mut T) + Sync),
) {
    match team {
        Some(t) if t.threads() > 1 && items.len() > 1 => t.scope(|| t.for_each(items, f)),
        _ => items.iter_mut().enumerate().for_each(|(k, it)| f(k, it)),
    }
}

/// Whether any atom has moved more than half the margin since `x0` ([`moved_half_margin`]),
/// in chunks on the team's threads.
pub(super) fn moved_half_margin_par(
    x: &[f64],
    x0: &[f64],
    margin: f64,
    team: Option<&Team>,
) -> bool {
    if x0.len() != x.len() {
        return true;
    }
    let n = 3 * CHUNK_ATOMS;
    let mut parts: Vec<(&[f64], &[f64], bool)> = x
        .chunks(n)
        .zip(x0.chunks(n))
        .map(|(a, b)| (a, b, false))
        .collect();
    par_items(team, &mut parts, &|_, p| {
        p.2 = moved_half_margin(p.0, p.1, margin);
    });
    parts.iter().any(|p| p.2)
}

/// The atoms' bounding box (lo, hi) along the cloud's `dim` axes (0 along the others; ±∞ when
/// there is no atom).
pub(super) fn bounding_box(c: &Cloud, team: Option<&Team>) -> ([f64; 3], [f64; 3]) {
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    for d in 0..c.dim {
        lo[d] = f64::INFINITY;
        hi[d] = f64::NEG_INFINITY;
    }
    let mut boxes: Vec<(&[f64], [f64; 3], [f64; 3])> =
        c.x.chunks(3 * CHUNK_ATOMS).map(|x| (x, lo, hi)).collect();
    par_items(team, &mut boxes, &|_, (x, lo, hi)| {
        for p in x.chunks_exact(3) {
            for d in 0..c.dim {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
    });
    for (_, l, h) in &boxes {
        for d in 0..c.dim {
            lo[d] = lo[d].min(l[d]);
            hi[d] = hi[d].max(h[d]);
        }
    }
    (lo, hi)
}

/// Each atom's bin into `bins` (resized to the atoms).
pub(super) fn bin_atoms(c: &Cloud, geo: &Geometry, bins: &mut Vec<u32>, team: Option<&Team>) {
    bins.clear();
    bins.resize(c.ty.len(), 0);
    let mut chunks: Vec<(&[f64], &mut [u32])> =
        c.x.chunks(3 * CHUNK_ATOMS)
            .zip(bins.chunks_mut(CHUNK_ATOMS))
            .collect();
    par_items(team, &mut chunks, &|_, (x, out)| {
        for (p, b) in x.chunks_exact(3).zip(out.iter_mut()) {
            *b = geo.bin_of(p) as u32;
        }
    });
}
