//! Measurements on a [`System`] with LAMMPS's definitions (`docs/models.md` §4.5–4.6): spatial 1-D
//! bins (`compute chunk/atom bin/1d`), mean-squared displacement (`compute msd`), histogram binning
//! (`fix ave/histo`). Pure functions of the state; the averaging over time, the file formats and
//! the per-atom values of the script language (`variable … atom`) live in `input::observe`.

use super::{SimBox, System};

/// Where the bin origin of a `bin/1d` chunk style lies (LAMMPS `lower|center|upper|value`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum BinOrigin {
    /// The lower bound of the binned extent.
    Lower,
    /// Its middle.
    Center,
    /// Its upper bound.
    Upper,
    /// A coordinate.
    Coord(f64),
}

/// What happens to atoms outside the bins (LAMMPS `discard mixed|yes|no`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Discard {
    /// Outside a bound given as a coordinate: discarded; outside the box bound: put in the end bin.
    Mixed,
    /// Discarded.
    Yes,
    /// Put in the first or last bin.
    No,
}

/// `compute ID all chunk/atom bin/1d DIM ORIGIN DELTA [units box|lattice|reduced]
/// [discard …] [bound DIM lo hi]` (LAMMPS `compute_chunk_atom.cpp`, 1-D binning only).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Bin1d {
    /// Axis 0, 1, 2 (x, y, z).
    pub axis: usize,
    /// Bin origin.
    pub origin: BinOrigin,
    /// Bin width (box units, or fraction of the box with `reduced`).
    pub delta: f64,
    /// `units reduced`: coordinates are fractions of the box length, in [0, 1).
    pub reduced: bool,
    /// Lower bound of the binned extent (None: the box's).
    pub min: Option<f64>,
    /// Upper bound (None: the box's).
    pub max: Option<f64>,
    /// Discard rule.
    pub discard: Discard,
}

/// The bins of a [`Bin1d`] in a given box.
#[derive(Clone, Debug, PartialEq)]
pub struct BinLayout {
    axis: usize,
    reduced: bool,
    offset: f64,
    delta: f64,
    inv_delta: f64,
    min_is_coord: bool,
    max_is_coord: bool,
    discard: Discard,
    lo: f64,
    len: f64,
    inv_len: f64,
    /// Bin centres (in the units of the binning).
    pub coord: Vec<f64>,
    /// The volume of one bin (area in 2-D): box volume × delta / box length, as LAMMPS.
    pub volume: f64,
}

impl Bin1d {
    /// The bins for box `bx` (LAMMPS `setup_xyz_bins` and `bin_volumes`).
    pub(crate) fn layout(&self, bx: &SimBox) -> Result<BinLayout, String> {
        let a = self.axis;
        let len = bx.len();
        let (box_lo, box_hi) = if self.reduced {
            (0.0, 1.0)
        } else {
            (bx.lo[a], bx.hi[a])
        };
        let bin_lo = self.min.unwrap_or(box_lo);
        let bin_hi = self.max.unwrap_or(box_hi);
        let delta = self.delta;
        let inv = 1.0 / delta;
        let origin = match self.origin {
            BinOrigin::Lower => bin_lo,
            BinOrigin::Upper => bin_hi,
            BinOrigin::Center => 0.5 * (bin_lo + bin_hi),
            BinOrigin::Coord(c) => c,
        };
        // The bin boundaries just below bin_lo and just above bin_hi, on the origin's lattice
        // (C truncation of the count, as LAMMPS's static_cast<int>).
        let lo = if origin < bin_lo {
            origin + ((bin_lo - origin) * inv).trunc() * delta
        } else {
            let l = origin - ((origin - bin_lo) * inv).trunc() * delta;
            if l > bin_lo { l - delta } else { l }
        };
        let hi = if origin < bin_hi {
            let h = origin + ((bin_hi - origin) * inv).trunc() * delta;
            if h < bin_hi { h + delta } else { h }
        } else {
            origin - ((origin - bin_hi) * inv).trunc() * delta
        };
        if lo > hi {
            return Err("invalid bin bounds in compute chunk/atom".into());
        }
        let n = ((hi - lo) * inv + 0.5).trunc();
        if !(1.0..1e8).contains(&n) {
            return Err(format!(
                "compute chunk/atom: {n} bins of width {delta} (need 1 to 10^8)"
            ));
        }
        let n = n as usize;
        let coord = (0..n).map(|i| lo + (i as f64 + 0.5) * delta).collect();
        let prd = if self.reduced { 1.0 } else { len[a] };
        let volume = bx.volume() * delta / prd;
        Ok(BinLayout {
            axis: a,
            reduced: self.reduced,
            offset: lo,
            delta,
            inv_delta: inv,
            min_is_coord: self.min.is_some(),
            max_is_coord: self.max.is_some(),
            discard: self.discard,
            lo: bx.lo[a],
            len: len[a],
            inv_len: 1.0 / len[a],
            coord,
            volume,
        })
    }
}

impl BinLayout {
    /// Number of bins.
    pub fn len(&self) -> usize {
        self.coord.len()
    }

    /// True when there are no bins (never, for a valid layout).
    pub fn is_empty(&self) -> bool {
        self.coord.is_empty()
    }

    /// The 0-based bin of an atom at stored position `x` (possibly outside the box by less than
    /// one box length, as between re-neighbourings), or None if the discard rule excludes it
    /// (LAMMPS `atom2bin1d`, periodic axis).
    pub fn bin_of(&self, x: &[f64; 3]) -> Option<usize> {
        let (mut c, lo, hi, prd) = if self.reduced {
            ((x[self.axis] - self.lo) * self.inv_len, 0.0, 1.0, 1.0)
        } else {
            (x[self.axis], self.lo, self.lo + self.len, self.len)
        };
        if c < lo {
            c += prd;
        }
        if c >= hi {
            c -= prd;
        }
        let mut ibin = ((c - self.offset) * self.inv_delta).trunc() as i64;
        if c < self.offset {
            ibin -= 1;
        }
        let last = self.coord.len() as i64 - 1;
        match self.discard {
            Discard::Mixed => {
                if ibin < 0 {
                    if self.min_is_coord {
                        return None;
                    }
                    ibin = 0;
                }
                if ibin > last {
                    if self.max_is_coord {
                        return None;
                    }
                    ibin = last;
                }
            }
            Discard::No => ibin = ibin.clamp(0, last),
            Discard::Yes => {
                if ibin < 0 || ibin > last {
                    return None;
                }
            }
        }
        Some(ibin as usize)
    }

    /// The bin of every atom of `sys`, in the atoms' internal order.
    pub fn assign(&self, sys: &System) -> Vec<Option<usize>> {
        sys.atoms.x.iter().map(|x| self.bin_of(x)).collect()
    }

    /// Bin width in the units of the binning.
    pub fn delta(&self) -> f64 {
        self.delta
    }
}

/// The mass of atom `i` (0 if its type has no mass yet).
pub(crate) fn mass_of(sys: &System, i: usize) -> f64 {
    sys.mass[sys.atoms.typ[i] as usize].unwrap_or(0.0)
}

/// The unwrapped position x + image · L of atom `i` (LAMMPS `domain->unmap`).
pub fn unwrapped(sys: &System, i: usize) -> [f64; 3] {
    sys.bx.unwrap(sys.atoms.x[i], sys.atoms.image[i])
}

/// The centre of mass of the unwrapped positions (LAMMPS `group->xcm`).
pub(crate) fn center_of_mass(sys: &System) -> [f64; 3] {
    let mut cm = [0.0; 3];
    let mut mtot = 0.0;
    for i in 0..sys.atoms.len() {
        let m = mass_of(sys, i);
        let u = unwrapped(sys, i);
        for k in 0..3 {
            cm[k] += u[k] * m;
        }
        mtot += m;
    }
    if mtot > 0.0 {
        for c in cm.iter_mut() {
            *c /= mtot;
        }
    }
    cm
}

/// `compute ID all msd [com yes|no]`: reference positions (unwrapped) taken when the compute
/// is defined, indexed by atom tag.
#[derive(Clone, Debug)]
pub struct Msd {
    /// Subtract the centre-of-mass drift (`com yes`).
    pub com: bool,
    reference: Vec<[f64; 3]>,
}

impl Msd {
    /// Store the current unwrapped positions (minus the centre of mass with `com`).
    pub fn new(sys: &System, com: bool) -> Msd {
        let mut reference = vec![[0.0; 3]; sys.atoms.max_tag() as usize + 1];
        let cm = if com { center_of_mass(sys) } else { [0.0; 3] };
        for i in 0..sys.atoms.len() {
            let u = unwrapped(sys, i);
            let r = &mut reference[sys.atoms.tag[i] as usize];
            for k in 0..3 {
                r[k] = u[k] - cm[k];
            }
        }
        Msd { com, reference }
    }

    /// ⟨dx²⟩, ⟨dy²⟩, ⟨dz²⟩ and ⟨|dr|²⟩ over the atoms (LAMMPS `compute msd` vector).
    pub fn compute(&self, sys: &System) -> Result<[f64; 4], String> {
        let cm = if self.com {
            center_of_mass(sys)
        } else {
            [0.0; 3]
        };
        let mut s = [0.0; 4];
        for i in 0..sys.atoms.len() {
            let tag = sys.atoms.tag[i] as usize;
            let r = self.reference.get(tag).ok_or_else(|| {
                format!("compute msd: atom {tag} did not exist when the compute was defined")
            })?;
            let u = unwrapped(sys, i);
            let dx = u[0] - cm[0] - r[0];
            let dy = u[1] - cm[1] - r[1];
            let dz = u[2] - cm[2] - r[2];
            s[0] += dx * dx;
            s[1] += dy * dy;
            s[2] += dz * dz;
            s[3] += dx * dx + dy * dy + dz * dz;
        }
        let n = sys.atoms.len();
        if n > 0 {
            for v in s.iter_mut() {
                *v /= n as f64;
            }
        }
        Ok(s)
    }
}

/// What a histogram does with values outside [lo, hi] (LAMMPS `beyond ignore|end|extra`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Beyond {
    /// Counted as missing.
    Ignore,
    /// Put in the first or last bin.
    End,
    /// Put in two extra bins at the ends (coordinates lo and hi).
    Extra,
}

/// The bins of `fix ave/histo`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HistoBins {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Out-of-range rule.
    pub beyond: Beyond,
    /// Number of bins, including the two extra ones with `beyond extra`.
    pub nbins: usize,
    inv: f64,
    /// Bin centres (lo and hi for the extra bins).
    pub coord: Vec<f64>,
}

/// One histogram sample: counts per bin and [in range, missing, min, max].
#[derive(Clone, Debug, PartialEq)]
pub struct HistoSample {
    /// Counts per bin.
    pub bins: Vec<f64>,
    /// Values counted, values missing (beyond ignore), smallest, largest value seen.
    pub stats: [f64; 4],
}

/// The initial min/max of a histogram sample (LAMMPS's BIG).
pub(crate) const HISTO_BIG: f64 = 1.0e20;

impl HistoBins {
    /// `nbins` bins on [lo, hi] (plus two with `beyond extra`).
    pub(crate) fn new(lo: f64, hi: f64, nbins: usize, beyond: Beyond) -> HistoBins {
        let n = if beyond == Beyond::Extra {
            nbins + 2
        } else {
            nbins
        };
        let size = (hi - lo) / nbins as f64;
        let coord = (0..n)
            .map(|i| match beyond {
                Beyond::Extra if i == 0 => lo,
                Beyond::Extra if i == n - 1 => hi,
                Beyond::Extra => lo + (i as f64 - 1.0 + 0.5) * size,
                _ => lo + (i as f64 + 0.5) * size,
            })
            .collect();
        HistoBins {
            lo,
            hi,
            beyond,
            nbins: n,
            inv: 1.0 / size,
            coord,
        }
    }

    /// An empty sample.
    pub(crate) fn empty(&self) -> HistoSample {
        HistoSample {
            bins: vec![0.0; self.nbins],
            stats: [0.0, 0.0, HISTO_BIG, -HISTO_BIG],
        }
    }

    /// Add one value (LAMMPS `bin_one`).
    pub(crate) fn add(&self, s: &mut HistoSample, value: f64) {
        s.stats[2] = s.stats[2].min(value);
        s.stats[3] = s.stats[3].max(value);
        let n = self.nbins;
        if value < self.lo {
            if self.beyond == Beyond::Ignore {
                s.stats[1] += 1.0;
                return;
            }
            s.bins[0] += 1.0;
        } else if value > self.hi {
            if self.beyond == Beyond::Ignore {
                s.stats[1] += 1.0;
                return;
            }
            s.bins[n - 1] += 1.0;
        } else {
            // As LAMMPS: truncate, clamp to the last bin of the whole array, then shift past
            // the lower extra bin (so with `extra` a value equal to hi lands in the upper one).
            let mut ibin = (((value - self.lo) * self.inv) as i64).clamp(0, n as i64 - 1);
            if self.beyond == Beyond::Extra {
                ibin += 1;
            }
            s.bins[(ibin as usize).min(n - 1)] += 1.0;
        }
        s.stats[0] += 1.0;
    }
}

/// Add w v_a v_b (xx yy zz xy xz yz) to the symmetric tensor `t`: one atom's m v_a v_b of a
/// kinetic tensor (temp, temp/deform, temp/partial, stress/atom), or its m d_a d_b of
/// `compute gyration`.
#[inline]
pub(crate) fn add_outer(t: &mut [f64; 6], w: f64, v: [f64; 3]) {
    t[0] += w * v[0] * v[0];
    t[1] += w * v[1] * v[1];
    t[2] += w * v[2] * v[2];
    t[3] += w * v[0] * v[1];
    t[4] += w * v[0] * v[2];
    t[5] += w * v[1] * v[2];
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bx() -> SimBox {
        SimBox::new(3, [-2.5, 0.0, 0.0], [2.5, 4.0, 2.0]).unwrap()
    }

    #[test]
    fn bins_from_the_lower_bound() {
        let b = Bin1d {
            axis: 0,
            origin: BinOrigin::Lower,
            delta: 0.5,
            reduced: false,
            min: None,
            max: None,
            discard: Discard::Mixed,
        };
        let l = b.layout(&bx()).unwrap();
        assert_eq!(l.len(), 10);
        assert_eq!(l.coord[0], -2.25);
        assert_eq!(l.coord[9], 2.25);
        assert_eq!(l.volume, 5.0 * 4.0 * 2.0 * 0.5 / 5.0);
        assert_eq!(l.bin_of(&[-2.5, 0.0, 0.0]), Some(0));
        assert_eq!(l.bin_of(&[-0.01, 0.0, 0.0]), Some(4));
        assert_eq!(l.bin_of(&[0.0, 0.0, 0.0]), Some(5));
        // Slightly outside the box (between re-neighbourings): remapped periodically.
        assert_eq!(l.bin_of(&[2.6, 0.0, 0.0]), Some(0));
        assert_eq!(l.bin_of(&[-2.6, 0.0, 0.0]), Some(9));
    }

    #[test]
    fn bins_from_an_origin_that_does_not_divide_the_box() {
        // origin 0.1, delta 0.25 on [-2.5, 2.5): boundaries ... -2.65, -2.4, ..., 2.35, 2.6.
        let b = Bin1d {
            axis: 0,
            origin: BinOrigin::Coord(0.1),
            delta: 0.25,
            reduced: false,
            min: None,
            max: None,
            discard: Discard::Yes,
        };
        let l = b.layout(&bx()).unwrap();
        assert_eq!(l.len(), 21);
        assert!((l.coord[0] - -2.525).abs() < 1e-12);
        assert_eq!(l.bin_of(&[-2.45, 0.0, 0.0]), Some(0));
        assert_eq!(l.bin_of(&[2.45, 0.0, 0.0]), Some(20));
    }

    #[test]
    fn reduced_centered_bins() {
        let b = Bin1d {
            axis: 1,
            origin: BinOrigin::Center,
            delta: 0.7,
            reduced: true,
            min: None,
            max: None,
            discard: Discard::Mixed,
        };
        let l = b.layout(&bx()).unwrap();
        // boundaries -0.2, 0.5, 1.2: two bins centred at 0.15 and 0.85
        assert_eq!(l.len(), 2);
        assert!((l.coord[0] - 0.15).abs() < 1e-15 && (l.coord[1] - 0.85).abs() < 1e-15);
        assert_eq!(l.bin_of(&[0.0, 1.0, 0.0]), Some(0)); // y/Ly = 0.25
        assert_eq!(l.bin_of(&[0.0, 3.0, 0.0]), Some(1)); // 0.75
        assert!((l.volume - 40.0 * 0.7).abs() < 1e-12);
    }

    #[test]
    fn histogram_rules() {
        let h = HistoBins::new(0.0, 2.0, 4, Beyond::Ignore);
        let mut s = h.empty();
        for v in [-1.0, 0.0, 0.49, 0.5, 2.0, 2.5] {
            h.add(&mut s, v);
        }
        assert_eq!(s.bins, vec![2.0, 1.0, 0.0, 1.0]);
        assert_eq!(s.stats, [4.0, 2.0, -1.0, 2.5]);
        let h = HistoBins::new(0.0, 2.0, 4, Beyond::Extra);
        assert_eq!(h.coord, vec![0.0, 0.25, 0.75, 1.25, 1.75, 2.0]);
        let mut s = h.empty();
        for v in [-1.0, 0.1, 3.0] {
            h.add(&mut s, v);
        }
        assert_eq!(s.bins, vec![1.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
    }
}
