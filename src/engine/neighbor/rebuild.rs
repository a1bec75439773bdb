//! The list's rebuild: atoms wrapped into the box, sorted by cell, the cell stencil and the
//! slabs, the rows of every atom (`build.rs`), and the working list's refresh between builds.

use super::*;

impl NeighborList {
    /// Wrap positions into the box, sort atoms by cell, and build the half list with cut-off
    /// `rc_max + skin`. Atom order changes; every per-atom array travels with the atoms.
    pub fn build(&mut self, atoms: &mut Atoms, bx: &SimBox, rc_max: f64) {
        let n = atoms.len();
        self.wrap(atoms, bx);
        self.xy_at_build = self.xy_now;
        let cutoff = rc_max + self.skin;
        let len = bx.len();
        self.tilt_allow = if self.le.is_some() {
            let life = self.evals_since_build as f64 + 2.0;
            (self.tilt_drift * life).min(0.5 * len[0] - cutoff).max(0.0)
        } else {
            0.0
        };
        let ncell = cell_grid(len, bx.dim, cutoff, n);
        self.set_stencil(ncell, bx);
        let total_cells = ncell[0] * ncell[1] * ncell[2];
        let cell_coords = CellCoords {
            lo: bx.lo,
            len,
            ncell,
            dim: bx.dim,
        };
        self.sort_by_cell(atoms, cell_coords, total_cells);
        let slab_mode = self.set_slabs(bx, ncell, total_cells);

        // Rows, slab by slab (each slab independent: parallel and deterministic).
        let rows = RowBuild {
            x: &atoms.x,
            bx,
            cells: cell_coords,
            cell_start: &self.cell_start,
            axes: &self.stencil_axes,
            xruns: &self.xruns,
            len,
            cutsq: cutoff * cutoff,
            slab_axis: if slab_mode { Some(bx.dim - 1) } else { None },
            le: self.le,
            tilt_allow: self.tilt_allow,
        };
        let isa = match self.isa {
            Some(i) if (i as u8) <= (Isa::best_supported() as u8) => i,
            Some(_) => Isa::Baseline,
            None => Isa::detect(),
        };
        self.slabs
            .par_iter_mut()
            .for_each(|s| build_rows_isa(isa, &rows, s));
        self.finish_build(atoms, cutoff, rc_max);
    }

    /// [`Self::build`], first phase: wrap positions into the box (and, under Lees–Edwards,
    /// shift the velocities of atoms through the sheared boundary).
    pub(super) fn wrap(&self, atoms: &mut Atoms, bx: &SimBox) {
        match self.le {
            None => atoms
                .x
                .par_iter_mut()
                .zip(atoms.image.par_iter_mut())
                .for_each(|(x, im)| bx.wrap(x, im)),
            // Crossing the sheared boundary also shifts x by the offset and v_x by the jump.
            Some(le) => atoms
                .x
                .par_iter_mut()
                .zip(atoms.v.par_iter_mut())
                .zip(atoms.image.par_iter_mut())
                .for_each(|((x, v), im)| {
                    bx.wrap_le(x, v, im, &le);
                }),
        }
    }

    /// [`Self::build`]: the cell stencil and the x runs of a cell grid `ncell`, when it
    /// changed.
    pub(super) fn set_stencil(&mut self, ncell: [usize; 3], bx: &SimBox) {
        if ncell != self.ncell {
            self.ncell = ncell;
            for d in 0..3 {
                let m = ncell[d];
                // (neighbour coordinate, image): the neighbour cell is reached directly (0) or
                // through the periodic boundary; then its atoms' nearest images are at x_j − L
                // (+1: the cell below 0 is m − 1) or x_j + L (−1: the cell above m − 1 is 0),
                // and x_i − image = (x_i ± L) − x_j. With fewer than 3 cells the neighbours are
                // all cells and the image is decided per pair (AMBIGUOUS).
                let periodic = d < bx.dim;
                self.stencil_axes[d] = (0..m)
                    .map(|c| {
                        if m >= 3 {
                            vec![
                                ((c + m - 1) % m, if c == 0 { 1 } else { 0 }),
                                (c, 0),
                                ((c + 1) % m, if c == m - 1 { -1 } else { 0 }),
                            ]
                        } else {
                            let img = if periodic { AMBIGUOUS } else { 0 };
                            (0..m).map(|k| (k, img)).collect()
                        }
                    })
                    .collect();
            }
            let m = ncell[0];
            self.xruns = (0..m)
                .map(|c| {
                    if m < 3 {
                        (0..m).map(|k| (k, k, AMBIGUOUS)).collect()
                    } else if c == 0 {
                        vec![(0, 1, 0), (m - 1, m - 1, 1)]
                    } else if c == m - 1 {
                        vec![(0, 0, -1), (m - 2, m - 1, 0)]
                    } else {
                        vec![(c - 1, c + 1, 0)]
                    }
                })
                .collect();
        }
    }

    /// [`Self::build`]: the counting sort of the atoms by cell, stable in the current order;
    /// leaves `cell_start`, the first atom of each cell.
    pub(super) fn sort_by_cell(
        &mut self,
        atoms: &mut Atoms,
        cell_coords: CellCoords,
        total_cells: usize,
    ) {
        let n = atoms.len();
        let ncell = cell_coords.ncell;
        // Counting sort by cell, stable in the current order.
        self.cell_of.clear();
        self.cell_of.par_extend(
            atoms
                .x
                .par_iter()
                .map(|x| cell_id(cell_coords.of(x), ncell) as u32),
        );
        self.cell_count.clear();
        self.cell_count.resize(total_cells + 1, 0);
        for &c in &self.cell_of {
            self.cell_count[c as usize + 1] += 1;
        }
        for c in 0..total_cells {
            self.cell_count[c + 1] += self.cell_count[c];
        }
        self.cell_start.clear();
        self.cell_start.extend_from_slice(&self.cell_count);
        self.perm.clear();
        self.perm.resize(n, 0);
        for (i, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut self.cell_count[c as usize];
            self.perm[*slot as usize] = i as u32;
            *slot += 1;
        }
        permute(atoms, &self.perm, &mut self.x_at_build, &mut self.cell_of);
    }

    /// [`Self::build`]: the slabs over the sorted atoms; true when
    /// the box has slabs (3 layers or more), false when it runs as one task.
    pub(super) fn set_slabs(&mut self, bx: &SimBox, ncell: [usize; 3], total_cells: usize) -> bool {
        // Slabs: layers of cells along the last periodic axis (contiguous in the cell order).
        let axis = bx.dim - 1;
        let layers = ncell[axis];
        let slab_mode = layers >= 3;
        let nslabs = if slab_mode { layers } else { 1 };
        let cells_per_slab = total_cells / nslabs;
        self.slabs.resize_with(nslabs, Slab::default);
        for (k, s) in self.slabs.iter_mut().enumerate() {
            s.start = self.cell_start[k * cells_per_slab] as usize;
            s.end = self.cell_start[(k + 1) * cells_per_slab] as usize;
            s.next_start = if slab_mode {
                self.cell_start[((k + 1) % nslabs) * cells_per_slab] as usize
            } else {
                s.end
            };
        }
        slab_mode
    }

    /// [`Self::build`], last phase: the positions at build, the counters, and the working
    /// list's switch.
    pub(super) fn finish_build(&mut self, atoms: &Atoms, cutoff: f64, rc_max: f64) {
        self.x_at_build.clear();
        self.x_at_build.extend_from_slice(&atoms.x);
        self.builds += 1;
        self.last_life = self.evals_since_build;
        self.evals_since_build = 0;
        self.cutoff = cutoff;
        self.rc_max = rc_max;
        self.inner_on = self.skin > 0.0
            && self
                .inner_override
                .unwrap_or(self.last_life >= INNER_MIN_LIFE);
        self.inner_stale = true;
        if !self.inner_on {
            for s in self.slabs.iter_mut() {
                s.in_row_start = Vec::new();
                s.in_nbr = Vec::new();
            }
            self.x_at_inner = Vec::new();
        }
    }

    /// Rebuild the working list if it is in use and stale or an atom moved margin/2 since.
    pub(super) fn refresh_inner(&mut self, atoms: &Atoms, bx: &SimBox) {
        if !self.inner_on
            && self.inner_override.is_none()
            && self.skin > 0.0
            && self.evals_since_build >= INNER_MIN_LIFE
        {
            // This list lives long: switch the working list on.
            self.inner_on = true;
            self.inner_stale = true;
        }
        if !self.inner_on {
            return;
        }
        let margin = INNER_MARGIN * self.skin;
        if !self.inner_stale {
            // Under Lees–Edwards the tilt's change since the refresh moves the pairs through
            // the y boundary by as much: it takes its part of the margin first.
            let room = if self.le.is_some() {
                margin - (self.xy_now - self.xy_at_inner).abs()
            } else {
                margin
            };
            let limit = 0.25 * room * room;
            let moved = atoms
                .x
                .par_iter()
                .zip(self.x_at_inner.par_iter())
                .any(|(x, x0)| {
                    let d = [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]];
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
                });
            if !moved && room > 0.0 {
                return;
            }
        }
        self.xy_at_inner = self.xy_now;
        let cut = self.rc_max + margin;
        let cutsq = cut * cut;
        let len = bx.len();
        let quarter = [0.25 * len[0], 0.25 * len[1], 0.25 * len[2]];
        let x = &atoms.x;
        let le = self.le;
        let short_y = le.is_some() && len[1] < 2.0 * self.rc_max;
        self.slabs.par_iter_mut().for_each(|s| {
            s.in_row_start.clear();
            s.in_nbr.clear();
            s.in_row_start.push(0);
            let mut len = 0usize;
            for (r, i) in (s.start..s.end).enumerate() {
                let row = &s.nbr[s.row_start[r] as usize..s.row_start[r + 1] as usize];
                let xi = x[i];
                // Branch-free append of the entries within the cut (a subsequence of the row).
                if s.in_nbr.len() < len + row.len() {
                    grow_buffer(&mut s.in_nbr, len + row.len());
                }
                if short_y {
                    for &j in row {
                        let xj = x[j as usize];
                        let d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                        s.in_nbr[len] = j;
                        len += usize::from(nearest_sq(bx, le.as_ref(), d, 0.0) < cutsq);
                    }
                } else {
                    for &j in row {
                        let xj = x[j as usize];
                        let mut d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                        if (d[0].abs() >= quarter[0])
                            | (d[1].abs() >= quarter[1])
                            | (d[2].abs() >= quarter[2])
                        {
                            d = pair_image(bx, le.as_ref(), d);
                        }
                        s.in_nbr[len] = j;
                        len += usize::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutsq);
                    }
                }
                s.in_row_start.push(len as u32);
            }
            // `in_nbr` is a buffer longer than the rows while they are appended (cut to the
            // data once, here: cut per row, every next row grew it again and zeroed a quarter
            // of it, 2 % of an n = 16 run's time).
            s.in_nbr.truncate(len);
            trim_buffer(&mut s.in_nbr);
        });
        self.x_at_inner.clear();
        self.x_at_inner.extend_from_slice(x);
        self.inner_stale = false;
    }
}
