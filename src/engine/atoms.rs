//! Per-atom data as contiguous arrays (structure of arrays).

/// The atoms of the system. Index order is internal (sorted by cell for locality); `tag` is the
/// global, user-visible id (LAMMPS's atom ID) that keys the pair noise.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Atoms {
    /// Positions (wrapped into the box at every neighbour-list build).
    pub x: Vec<[f64; 3]>,
    /// Velocities.
    pub v: Vec<[f64; 3]>,
    /// Forces from the last force evaluation.
    pub f: Vec<[f64; 3]>,
    /// Global ids, 1 ≤ tag < 2³².
    pub tag: Vec<u32>,
    /// Types, 1-based.
    pub typ: Vec<u32>,
    /// Periodic image counters.
    pub image: Vec<[i32; 3]>,
    /// Molecule ids (`atom_style bond|angle|molecular|full`); empty for `atomic`, else one per
    /// atom, permuted with the rest.
    pub mol: Vec<u32>,
    /// Group masks, one bit per group of [`super::groups::Groups`] (`all` is bit 0, as LAMMPS's
    /// `atom->mask`); empty while no group but `all` was ever defined (every atom's mask is
    /// then 1: [`Atoms::mask_of`]), else one per atom, permuted with the rest.
    pub mask: Vec<u32>,
    /// `fix mvv/dpd`'s estimated velocities (LAMMPS's `vest`), from its first half to its
    /// second in one step; empty without that fix, else one per atom, permuted with the rest.
    pub vest: Vec<[f64; 3]>,
}

impl Atoms {
    /// Number of atoms.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when there are no atoms.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Append one atom (zero force).
    pub fn push(&mut self, tag: u32, typ: u32, x: [f64; 3], v: [f64; 3], image: [i32; 3]) {
        if !self.mol.is_empty() {
            self.mol.push(0);
        }
        self.push_common(tag, typ, x, v, image);
    }

    /// The arrays every atom has (all but `mol`).
    fn push_common(&mut self, tag: u32, typ: u32, x: [f64; 3], v: [f64; 3], image: [i32; 3]) {
        if !self.mask.is_empty() {
            self.mask.push(1);
        }
        if !self.vest.is_empty() {
            self.vest.push([0.0; 3]);
        }
        self.x.push(x);
        self.v.push(v);
        self.f.push([0.0; 3]);
        self.tag.push(tag);
        self.typ.push(typ);
        self.image.push(image);
    }

    /// Reserve room for `n` more atoms in every array; an allocation failure is an error, not an
    /// abort.
    pub fn try_reserve(&mut self, n: usize) -> Result<(), std::collections::TryReserveError> {
        self.x.try_reserve(n)?;
        self.v.try_reserve(n)?;
        self.f.try_reserve(n)?;
        self.tag.try_reserve(n)?;
        self.typ.try_reserve(n)?;
        if !self.mol.is_empty() {
            self.mol.try_reserve(n)?;
        }
        if !self.mask.is_empty() {
            self.mask.try_reserve(n)?;
        }
        self.image.try_reserve(n)
    }

    /// Append one atom with molecule id `mol` (a system with molecule ids: every atom has one).
    pub fn push_mol(
        &mut self,
        tag: u32,
        typ: u32,
        mol: u32,
        x: [f64; 3],
        v: [f64; 3],
        image: [i32; 3],
    ) {
        self.mol.resize(self.x.len(), 0);
        self.mol.push(mol);
        self.push_common(tag, typ, x, v, image);
    }

    /// The molecule id of atom `i` (0 without molecule ids, as LAMMPS's `atomic` style).
    pub fn mol_of(&self, i: usize) -> u32 {
        self.mol.get(i).copied().unwrap_or(0)
    }

    /// The largest tag, 0 when empty.
    pub fn max_tag(&self) -> u32 {
        self.tag.iter().copied().max().unwrap_or(0)
    }

    /// Reorder every array by `perm` (new index k holds old atom `perm[k]`), using `scratch`
    /// buffers so that no allocation happens once they have grown to size.
    pub fn permute(&mut self, perm: &[u32], scratch: &mut Atoms) {
        fn apply<T: Copy>(src: &mut Vec<T>, dst: &mut Vec<T>, perm: &[u32]) {
            dst.clear();
            dst.extend(perm.iter().map(|&p| src[p as usize]));
            std::mem::swap(src, dst);
        }
        apply(&mut self.x, &mut scratch.x, perm);
        apply(&mut self.v, &mut scratch.v, perm);
        apply(&mut self.f, &mut scratch.f, perm);
        apply(&mut self.tag, &mut scratch.tag, perm);
        apply(&mut self.typ, &mut scratch.typ, perm);
        apply(&mut self.image, &mut scratch.image, perm);
        if !self.mol.is_empty() {
            apply(&mut self.mol, &mut scratch.mol, perm);
        }
        if !self.mask.is_empty() {
            apply(&mut self.mask, &mut scratch.mask, perm);
        }
        if !self.vest.is_empty() {
            apply(&mut self.vest, &mut scratch.vest, perm);
        }
    }
}
