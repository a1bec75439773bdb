//! The bonded terms' part of the driver: the set-up of bonds and angles (LAMMPS's checks and
//! warnings, the special partners, the index form of the topology, the images of bonded atoms)
//! and their forces after the pair forces. `impl System` kept apart from `engine/mod.rs`, the
//! step's sequence, as `Verlet::run` calls `force->bond` and `force->angle` apart from the pair.

use std::collections::HashMap;

use crate::engine::topology;
use crate::engine::{PairTally, SetupNote, System};
use crate::forces::bonded;

/// The bonded terms' working state: what the set-up derives from the topology and what each
/// neighbour-list build re-derives for the new atom order.
#[derive(Debug, Default)]
pub(super) struct BondedState {
    /// The special partners of every atom id, from the last set-up.
    pub(super) partners: HashMap<u32, Vec<(u32, u8)>>,
    /// The index form of the topology for the current atom order (rebuilt after each sort).
    pub(super) index: topology::BondedIndex,
    /// The per-atom virial of the bonds and of the angles of the last evaluation, when
    /// [`crate::engine::NeighborList`]'s per-atom tally is on (empty otherwise).
    pub(crate) virial_bond: Vec<[f64; 6]>,
    pub(crate) virial_angle: Vec<[f64; 6]>,
}

impl System {
    /// The set-up of the bonded terms: styles and coefficients present (LAMMPS's checks and
    /// warnings), the special partners, the index form of the topology, and LAMMPS's checks of
    /// the bonded atoms' images ([`System::check_bonded_images`]; `rc_max`: the largest pair
    /// cut-off).
    pub(crate) fn setup_topology(
        &mut self,
        rule: topology::SpecialRule,
        rc_max: f64,
    ) -> Result<(), String> {
        let Some(t) = &self.topo else { return Ok(()) };
        if !t.bonds.is_empty() {
            match &t.bond_style {
                None => {
                    self.setup_notes.push(SetupNote::Warning(
                        "Bonds are defined but no bond style is set".into(),
                    ));
                    if t.special.lj[1] != 1.0 || t.special.coul[1] != 1.0 {
                        self.setup_notes.push(SetupNote::Warning(
                            "Likewise 1-2 special neighbor interactions != 1.0".into(),
                        ));
                    }
                }
                Some(b) => {
                    if let Some(k) = b.missing() {
                        return Err(format!(
                            "Bond coeffs are not set (bond type {k} has none: bond_coeff)"
                        ));
                    }
                    if let Some(w) = b.form.special_warning(t.special.lj) {
                        self.setup_notes.push(SetupNote::Warning(w.into()));
                    }
                }
            }
        }
        if !t.angles.is_empty() {
            match &t.angle_style {
                None => self.setup_notes.push(SetupNote::Warning(
                    "Angles are defined but no angle style is set".into(),
                )),
                Some(a) => {
                    if let Some(k) = a.missing() {
                        return Err(format!(
                            "Angle coeffs are not set (angle type {k} has none: angle_coeff)"
                        ));
                    }
                }
            }
        }
        self.bonded.partners = t.special_partners();
        t.index(
            &self.atoms.tag,
            &self.bonded.partners,
            rule,
            &mut self.bonded.index,
        )?;
        self.bonded.index.build = self.neighbor.builds;
        if self.check_bonded_images(rc_max)? {
            self.setup_notes
                .push(SetupNote::Warning("Inconsistent image flags".into()));
        }
        let Some(t) = &self.topo else { return Ok(()) };
        // LAMMPS's warning when a bonded interaction, stretched by 10 %, could span half a
        // periodic box length (its `box_too_small_check`): longest bond × 1.1, × 2 with angles.
        let longest = self
            .bonded
            .index
            .bonds
            .iter()
            .map(|&[i, j, _]| {
                let (xi, xj) = (self.atoms.x[i as usize], self.atoms.x[j as usize]);
                let d = self
                    .bx
                    .min_image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
            })
            .fold(0.0, f64::max);
        let reach = longest * 1.1 * if t.angles.is_empty() { 1.0 } else { 2.0 };
        let len = self.bx.len();
        if (0..self.bx.dim).any(|k| reach > 0.5 * len[k]) {
            self.setup_notes.push(SetupNote::Warning(
                "Bond/angle/dihedral extent > half of periodic box length".into(),
            ));
        }
        Ok(())
    }

    /// LAMMPS's checks of the bonded atoms' images at a run's set-up (`Verlet::setup`), on the
    /// topology's index form of this set-up:
    ///
    /// - `Domain::image_check`: returns true when the two atoms of some bond, unwrapped by
    ///   their image flags (x + ix L_x + iy xy, LAMMPS's `unmap`), lie more than half a box
    ///   length apart along a periodic axis: LAMMPS's warning "Inconsistent image flags" (a data
    ///   file with wrapped coordinates and zero image flags, as many generators write, has
    ///   them). The bonds and angles use the minimum image all the same, in LAMMPS as here.
    /// - LAMMPS finds a bonded partner as the closest image it holds (`closest_image`) of the
    ///   atom that stores the interaction (the first atom of a bond, the vertex of an angle):
    ///   the atoms in the box and their ghost images within the ghost cut-off (the largest
    ///   pair cut-off + the neighbour skin, or `comm_modify cutoff`) beyond its faces. When the
    ///   partner's minimum image lies outside that shell no rank holds it: with several ranks
    ///   LAMMPS stops ("Bond atoms I J missing"), on one it takes a farther image, so its
    ///   numbers are not the minimum-image bond's. Such a bond or angle is an error here, with
    ///   the same meaning.
    fn check_bonded_images(&self, rc_max: f64) -> Result<bool, String> {
        let a = &self.atoms;
        let (len, dim, lo) = (self.bx.len(), self.bx.dim, self.bx.lo);
        // The tilt of the image flags (x + ix L_x + iy xy) and LAMMPS's tilt of its cell.
        let (xy_flags, xy_cell) = match &self.tri {
            Some(t) => (t.xy, t.reported_xy(&self.bx)),
            None => (0.0, 0.0),
        };
        let unwrap = |i: usize| self.bx.unwrap_tilted(a.x[i], a.image[i], xy_flags);
        let inconsistent = self.bonded.index.bonds.iter().any(|&[i, j, _]| {
            let (ui, uj) = (unwrap(i as usize), unwrap(j as usize));
            (0..dim).any(|k| (ui[k] - uj[k]).abs() > 0.5 * len[k])
        });
        let cut = (rc_max + self.neighbor.skin).max(self.comm_cutoff);
        // The ghost shell in LAMMPS's fractional coordinates (`CommBrick::setup`: cut × the
        // norms of the rows of h⁻¹).
        let shell = [
            cut * (1.0 / (len[0] * len[0]) + (xy_cell / (len[0] * len[1])).powi(2)).sqrt(),
            cut / len[1],
            cut / len[2],
        ];
        let le = self.tri.as_ref().map(|t| t.le);
        let bx = &self.bx;
        // Is the minimum image of `p` relative to `h` (h in LAMMPS's cell) in the shell?
        let held = |h: usize, p: usize| -> (bool, f64) {
            let mut x = a.x[h];
            let mut im = a.image[h];
            match &le {
                None => bx.wrap(&mut x, &mut im),
                Some(_) => self.to_tilted_cell(&mut x, &mut im, xy_cell),
            }
            let r = [0, 1, 2].map(|k| a.x[p][k] - a.x[h][k]);
            let d = match &le {
                None => bx.min_image(r),
                Some(le) => bx.min_image_le(r, le).0,
            };
            let y = [0, 1, 2].map(|k| x[k] + d[k]);
            let l1 = (y[1] - lo[1]) / len[1];
            let lambda = [
                (y[0] - lo[0] - xy_cell * l1) / len[0],
                l1,
                (y[2] - lo[2]) / len[2],
            ];
            let inside = (0..dim).all(|k| lambda[k] >= -shell[k] && lambda[k] <= 1.0 + shell[k]);
            (inside, (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
        };
        let why = |p: u32, h: u32, r: f64, what: &str| {
            format!(
                "the nearest image of atom {p} to atom {h} ({what}, {} apart) is outside the \
                 box and its ghost cut-off {} (the largest pair cut-off + neighbor skin, or \
                 comm_modify cutoff), so LAMMPS cannot resolve this interaction: on several \
                 ranks it stops with this error, on one it takes a farther image; bring the \
                 atoms closer together in the data file or raise comm_modify cutoff",
                eight_digits(r),
                eight_digits(cut)
            )
        };
        for &[i, j, _] in &self.bonded.index.bonds {
            let (i, j) = (i as usize, j as usize);
            if let (false, r) = held(i, j) {
                let (ti, tj) = (a.tag[i], a.tag[j]);
                return Err(format!(
                    "Bond atoms {ti} {tj} missing at step {}: {}",
                    self.step,
                    why(tj, ti, r, "which stores the bond")
                ));
            }
        }
        for &[i, j, k, _] in &self.bonded.index.angles {
            let (i, j, k) = (i as usize, j as usize, k as usize);
            for p in [i, k] {
                if let (false, r) = held(j, p) {
                    return Err(format!(
                        "Angle atoms {} {} {} missing at step {}: {}",
                        a.tag[i],
                        a.tag[j],
                        a.tag[k],
                        self.step,
                        why(a.tag[p], a.tag[j], r, "the vertex, which stores the angle")
                    ));
                }
            }
        }
        Ok(inconsistent)
    }

    /// The bond and angle forces of the current positions, added to `atoms.f` in topology
    /// order (bonds, then angles: LAMMPS's order), with their energies and virial. Minimum
    /// images as the pair loop's (periodic, or the sliding brick of a sheared box).
    pub(crate) fn bonded_forces(&mut self) -> PairTally {
        let mut tb = PairTally::default();
        let mut ta = PairTally::default();
        let Some(t) = &self.topo else { return tb };
        let le = self.tri.as_ref().map(|t| t.le);
        let bx = &self.bx;
        let image = |d: [f64; 3]| match &le {
            None => bx.min_image(d),
            Some(le) => bx.min_image_le(d, le).0,
        };
        let a = &mut self.atoms;
        // The per-atom virial (`compute stress/atom`): ½ of a bond's to each atom, ⅓ of an
        // angle's to each of its three (LAMMPS's `ev_tally`s).
        let on = self.neighbor.virial_atom_on;
        let (vb, vang) = (&mut self.bonded.virial_bond, &mut self.bonded.virial_angle);
        vb.clear();
        vang.clear();
        if on {
            vb.resize(a.len(), [0.0; 6]);
            vang.resize(a.len(), [0.0; 6]);
        }
        if let Some(style) = &t.bond_style {
            for &[i, j, typ] in &self.bonded.index.bonds {
                let (i, j) = (i as usize, j as usize);
                let (xi, xj) = (a.x[i], a.x[j]);
                let d = image([xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]]);
                let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let (fbond, e, flag) = style.eval(typ as usize, rsq);
                if flag != bonded::BondFlag::Ok {
                    let (ti, tj) = (a.tag[i], a.tag[j]);
                    if self.warnings.len() < 100 {
                        self.warnings.push(format!(
                            "FENE bond too long: {} {ti} {tj} {}",
                            self.step,
                            eight_digits(rsq.sqrt())
                        ));
                    }
                    if flag == bonded::BondFlag::Bad && self.pair_fault.is_none() {
                        self.pair_fault = Some(format!(
                            "Bad FENE bond: atoms {ti} {tj} at step {} are {} apart, \
                             (r/R0)² − 1 ≥ 3 (bond_coeff R0 of type {typ})",
                            self.step,
                            eight_digits(rsq.sqrt())
                        ));
                    }
                }
                let fv = [d[0] * fbond, d[1] * fbond, d[2] * fbond];
                for k in 0..3 {
                    a.f[i][k] += fv[k];
                    a.f[j][k] -= fv[k];
                }
                tb.add_pair(d, fv, e);
                if on {
                    add_share(vb, &[i, j], outer_sym(d, fv), 0.5);
                }
            }
        }
        if let Some(style) = &t.angle_style {
            for &[i, j, k, typ] in &self.bonded.index.angles {
                let (i, j, k) = (i as usize, j as usize, k as usize);
                let (x1, x2, x3) = (a.x[i], a.x[j], a.x[k]);
                let d1 = image([x1[0] - x2[0], x1[1] - x2[1], x1[2] - x2[2]]);
                let d2 = image([x3[0] - x2[0], x3[1] - x2[1], x3[2] - x2[2]]);
                let (f1, f3, e) = style.eval(typ as usize, d1, d2);
                for c in 0..3 {
                    a.f[i][c] += f1[c];
                    a.f[j][c] -= f1[c] + f3[c];
                    a.f[k][c] += f3[c];
                }
                ta.energy += e;
                ta.virial[0] += d1[0] * f1[0] + d2[0] * f3[0];
                ta.virial[1] += d1[1] * f1[1] + d2[1] * f3[1];
                ta.virial[2] += d1[2] * f1[2] + d2[2] * f3[2];
                ta.virial[3] += d1[0] * f1[1] + d2[0] * f3[1];
                ta.virial[4] += d1[0] * f1[2] + d2[0] * f3[2];
                ta.virial[5] += d1[1] * f1[2] + d2[1] * f3[2];
                if on {
                    let (w1, w2) = (outer_sym(d1, f1), outer_sym(d2, f3));
                    let w = std::array::from_fn(|c| w1[c] + w2[c]);
                    add_share(vang, &[i, j, k], w, 1.0 / 3.0);
                }
            }
        }
        self.energies.ebond = tb.energy;
        self.energies.eangle = ta.energy;
        for c in 0..6 {
            tb.virial[c] += ta.virial[c];
        }
        tb
    }
}

/// r_a F_b in LAMMPS's order xx yy zz xy xz yz.
fn outer_sym(d: [f64; 3], f: [f64; 3]) -> [f64; 6] {
    [
        d[0] * f[0],
        d[1] * f[1],
        d[2] * f[2],
        d[0] * f[1],
        d[0] * f[2],
        d[1] * f[2],
    ]
}

/// `share` × `w` added to the per-atom virial of each atom of `atoms`.
fn add_share(va: &mut [[f64; 6]], atoms: &[usize], w: [f64; 6], share: f64) {
    for &i in atoms {
        for c in 0..6 {
            va[i][c] += share * w[c];
        }
    }
}

/// A length with 8 significant digits in its shortest form (LAMMPS's `{:.8}` of a double in its
/// FENE warning: 3.3, 1.4999999).
fn eight_digits(x: f64) -> String {
    let rounded: f64 = format!("{x:.7e}").parse().unwrap_or(x);
    format!("{rounded}")
}
