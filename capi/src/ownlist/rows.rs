//! The rows of the list: built in blocks of consecutive rows, on the pair style's threads
//! when it has them (each block by one thread, alone, so the list is the same for any count),
//! then laid out as a LAMMPS list.

use super::candidates::{Keep, push_run};
use super::grid::Grid;
use super::passes::par_items;
use super::{BLOCK_ROWS, Cloud, OwnList};
use crate::Error;
use crate::team::Team;

/// The rows `rows` of the list: their entries one after another, and where each row starts.
#[derive(Debug, Default)]
pub(super) struct Block {
    pub(super) rows: std::ops::Range<usize>,
    pub(super) nbr: Vec<i32>,
    pub(super) offsets: Vec<usize>,
}

impl OwnList {
    /// The rows of every owned atom into `blocks`, and LAMMPS's `ilist`, `numneigh` and
    /// `firstneigh` over them.
    pub(super) fn build_rows(&mut self, c: &Cloud, team: Option<&Team>) -> Result<(), Error> {
        // The rows, in blocks of consecutive rows: on the team's threads when there is one
        // (each block is built by one thread, alone, so the list is the same for any count).
        self.ilist.clear();
        self.ilist.extend(0..c.nlocal as i32);
        let nblocks = match team {
            Some(t) if t.threads() > 1 => c.nlocal.div_ceil(BLOCK_ROWS),
            _ => 1,
        }
        .max(1);
        self.blocks.resize_with(nblocks, Block::default);
        let per = c.nlocal.div_ceil(nblocks);
        for (k, blk) in self.blocks.iter_mut().enumerate() {
            blk.rows = (k * per).min(c.nlocal)..((k + 1) * per).min(c.nlocal);
        }
        let grid = &self.grid;
        par_items(team, &mut self.blocks, &|_, blk| fill_rows(grid, c, blk));
        self.numneigh.clear();
        self.first.clear();
        for blk in &self.blocks {
            let base = blk.nbr.as_ptr();
            for (r, &o) in blk.offsets.iter().enumerate() {
                let end = blk.offsets.get(r + 1).copied().unwrap_or(blk.nbr.len());
                self.numneigh.push(
                    i32::try_from(end - o).map_err(|_| {
                        Error::invalid("a row of the pair list exceeds 2^31 entries")
                    })?,
                );
                // SAFETY: o <= blk.nbr.len(): within (or one past) the block's allocation.
                self.first.push(unsafe { base.add(o) });
            }
        }
        Ok(())
    }
}

/// The bins of a stencil entry from bin `bc`: (first bin of the row of bins, first x, last x),
/// or None when the row is outside the grid.
#[inline(always)]
fn bin_run(
    nb: [usize; 3],
    bc: [usize; 3],
    oy: i64,
    oz: i64,
    ox: i64,
) -> Option<(usize, usize, usize)> {
    let (ky, kz) = (bc[1] as i64 + oy, bc[2] as i64 + oz);
    if ky < 0 || ky >= nb[1] as i64 || kz < 0 || kz >= nb[2] as i64 {
        return None;
    }
    let x0 = (bc[0] as i64 - ox).max(0) as usize;
    let x1 = (bc[0] as i64 + ox).min(nb[0] as i64 - 1) as usize;
    Some(((kz as usize * nb[1] + ky as usize) * nb[0], x0, x1))
}

/// The rows `blk.rows` of the list (module docs) into `blk`.
fn fill_rows(g: &Grid, c: &Cloud, blk: &mut Block) {
    let nb = g.nb;
    let newton = c.newton;
    blk.nbr.clear();
    blk.offsets.clear();
    for i in blk.rows.clone() {
        let first = blk.nbr.len();
        blk.offsets.push(first);
        let (xi, yi, zi) = (c.x[3 * i], c.x[3 * i + 1], c.x[3 * i + 2]);
        let csq = g.row_sq[c.ty[i] as usize];
        let ti = c.tag[i];
        let b = g.bins[i] as usize;
        let bc = [b % nb[0], (b / nb[0]) % nb[1], b / (nb[0] * nb[1])];
        // Owned partners: each pair once, from the atom whose bin comes first (z, then y,
        // then x), or from the earlier of two in one bin.
        for &(oy, oz, ox) in &g.stencil {
            if (oz, oy) < (0, 0) {
                continue;
            }
            let Some((row, x0, x1)) = bin_run(nb, bc, oy, oz, ox) else {
                continue;
            };
            let s = if (oz, oy) == (0, 0) {
                g.pos[i] as usize + 1
            } else {
                g.own.start[row + x0] as usize
            };
            let e = g.own.start[row + x1 + 1] as usize;
            push_run(&mut blk.nbr, &g.own, s..e, [xi, yi, zi], csq, Keep::All);
        }
        // Ghost partners: with newton on, a pair is kept on the rank (or from the image) whose
        // atom has the smaller ID (module docs).
        let keep = if newton {
            Keep::AboveTag(ti)
        } else {
            Keep::All
        };
        let ghost_stencil: &[(i64, i64, i64)] = if g.ghost_near[b] { &g.stencil } else { &[] };
        for &(oy, oz, ox) in ghost_stencil {
            let Some((row, x0, x1)) = bin_run(nb, bc, oy, oz, ox) else {
                continue;
            };
            let (s, e) = (
                g.ghost.start[row + x0] as usize,
                g.ghost.start[row + x1 + 1] as usize,
            );
            push_run(&mut blk.nbr, &g.ghost, s..e, [xi, yi, zi], csq, keep);
        }
        // Bonded neighbours: their class in bits 30-31.
        if let Some((ns, sp, stride)) = c.special {
            let n = [ns[3 * i], ns[3 * i + 1], ns[3 * i + 2]];
            if n[2] > 0 {
                let tags = &sp[stride * i..stride * i + n[2] as usize];
                for e in &mut blk.nbr[first..] {
                    let class = match tags.iter().position(|&t| t == c.tag[*e as usize]) {
                        Some(p) if (p as i32) < n[0] => 1,
                        Some(p) if (p as i32) < n[1] => 2,
                        Some(_) => 3,
                        None => 0,
                    };
                    *e |= class << 30;
                }
            }
        }
    }
}
