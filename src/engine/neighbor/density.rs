//! A scalar sum over the pairs of the list, Σ_j w(r_ij) added to both atoms (sDPD's density
//! pass, `docs/models.md` §3.7), with the slab decomposition of the force pass: task k adds
//! into its own slab's entries and into the next slab's, so every atom's sum is `own + next`,
//! the same bits for any number of threads.

use super::*;

impl NeighborList {
    /// `out[i] = Σ_j w(k_ij, r_ij²)` over every listed pair (i, j) in range of its type pair,
    /// added to both atoms, with `k_ij` the dense type-pair index `typ_i · (ntypes + 1) + typ_j`
    /// and `rcsq` the squared cut-offs by that index. With one atom type, `w_lanes(k, rsq, out)`
    /// (the same function on a row of squared distances, 0 beyond the cut-off) is used instead,
    /// a row at a time. Requires a current list (as [`NeighborList::compute_forces`]); `out` is
    /// resized to the number of atoms. `special`: bonded pairs of a class left out (factor 0)
    /// add nothing (their weight is replaced by +0, which leaves every sum's bits as they would
    /// be without the pair).
    #[allow(clippy::too_many_arguments)]
    pub fn pair_sum<W, L>(
        &mut self,
        atoms: &Atoms,
        bx: &SimBox,
        rcsq: &[f64],
        ntypes: usize,
        w: W,
        w_lanes: L,
        out: &mut Vec<f64>,
        special: Option<&crate::engine::topology::SpecialPairs>,
    ) where
        W: Fn(usize, f64) -> f64 + Sync,
        L: Fn(usize, &[f64], &mut [f64]) + Sync,
    {
        assert_eq!(
            atoms.len(),
            self.x_at_build.len(),
            "neighbour list built for a different number of atoms"
        );
        let n = atoms.len();
        if let Some(sp) = special {
            assert_eq!(sp.start.len(), n + 1, "special partners of another order");
        }
        let nt = ntypes + 1;
        self.refresh_inner(atoms, bx);
        out.clear();
        out.resize(n, 0.0);
        let inner = self.inner_on;
        let len = bx.len();
        let quarter = [0.25 * len[0], 0.25 * len[1], 0.25 * len[2]];
        let (x, typ) = (&atoms.x, &atoms.typ);
        let one_type = ntypes == 1;
        let le = self.le;
        let short = self.short_axes(bx).map(|(s, _)| s);
        let row_sum = |s: &Slab, own: &mut [f64], next: &mut [f64]| {
            own.fill(0.0);
            next.fill(0.0);
            let (row_start, nbr) = if inner {
                (&s.in_row_start, &s.in_nbr)
            } else {
                (&s.row_start, &s.nbr)
            };
            let (mut rsq, mut wv) = (Vec::new(), Vec::new());
            let mut images = Vec::new();
            for i in s.start..s.end {
                let r = i - s.start;
                let xi = x[i];
                let ti = typ[i] as usize * nt;
                let row = &nbr[row_start[r] as usize..row_start[r + 1] as usize];
                if let Some(short) = short {
                    // A box shorter than 2 r_c: every image of j in range adds its weight
                    // (P-4b), in image order, to both atoms.
                    let mut di = 0.0;
                    for &j in row {
                        let ju = j as usize;
                        if let Some(sp) = special
                            && sp.rule.excludes(sp.class_of(i, atoms.tag[ju]))
                        {
                            continue;
                        }
                        let xj = x[ju];
                        let k = ti + typ[ju] as usize;
                        images.clear();
                        bx.images_within(
                            [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]],
                            le.as_ref(),
                            short,
                            rcsq[k],
                            0.0,
                            &mut images,
                        );
                        let mut wj = 0.0;
                        for &(d, _) in &images {
                            wj += w(k, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                        }
                        di += wj;
                        match own.get_mut(ju.wrapping_sub(s.start)) {
                            Some(o) => *o += wj,
                            None => next[ju - s.next_start] += wj,
                        }
                    }
                    own[r] += di;
                    continue;
                }
                // Squared minimum-image distances of the row (images only near the boundary).
                rsq.clear();
                rsq.extend(row.iter().map(|&j| {
                    let xj = x[j as usize];
                    let mut d = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
                    if (d[0].abs() >= quarter[0])
                        | (d[1].abs() >= quarter[1])
                        | (d[2].abs() >= quarter[2])
                    {
                        d = pair_image(bx, le.as_ref(), d);
                    }
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
                }));
                wv.clear();
                wv.resize(row.len(), 0.0);
                if one_type {
                    w_lanes(ti + 1, &rsq, &mut wv);
                } else {
                    for ((wk, &q), &j) in wv.iter_mut().zip(&rsq).zip(row) {
                        let k = ti + typ[j as usize] as usize;
                        *wk = if q < rcsq[k] { w(k, q) } else { 0.0 };
                    }
                }
                if let Some(sp) = special
                    && sp.start[i] != sp.start[i + 1]
                {
                    for (wk, &j) in wv.iter_mut().zip(row) {
                        if sp.rule.excludes(sp.class_of(i, atoms.tag[j as usize])) {
                            *wk = 0.0;
                        }
                    }
                }
                // Out-of-range entries add +0: the sums are those of the in-range pairs.
                let mut di = 0.0;
                for (&wij, &j) in wv.iter().zip(row) {
                    let j = j as usize;
                    di += wij;
                    match own.get_mut(j.wrapping_sub(s.start)) {
                        Some(o) => *o += wij,
                        None => next[j - s.next_start] += wij,
                    }
                }
                own[r] += di;
            }
        };
        if self.slabs.len() == 1 {
            row_sum(&self.slabs[0], &mut out[..], &mut []);
            return;
        }
        self.next_d.clear();
        self.next_d.resize(n, 0.0);
        let (own, next) = own_next_slices(&self.slabs, out, &mut self.next_d);
        self.slabs
            .par_iter()
            .zip(own.into_par_iter().zip(next.into_par_iter()))
            .for_each(|(s, (own, next))| row_sum(s, own, next));
        out.par_iter_mut()
            .zip(self.next_d.par_iter())
            .for_each(|(o, n)| *o += n);
    }
}
