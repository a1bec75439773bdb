//! The C structs of one force call from a LAMMPS style: the atoms, the step and the tallies
//! (the neighbour list's struct is in `list.rs`).

/// Per-atom arrays of one MPI rank, owned atoms first then ghosts (LAMMPS layout).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlAtoms {
    /// Positions, `nall * 3` doubles (LAMMPS `&x[0][0]`).
    pub x: *const f64,
    /// Velocities, `nall * 3` doubles; ghost velocities must be current (`comm_modify vel yes`).
    pub v: *const f64,
    /// Global ids (LAMMPS `tagint`, 32-bit under SMALLBIG), `nall` entries, all > 0.
    pub tag: *const i32,
    /// Atom types, 1-based, `nall` entries.
    pub atom_type: *const i32,
    /// Per-type masses, 1-based: `ntypes + 1` entries (entry 0 unused). Ignored if `rmass` is set.
    pub mass: *const f64,
    /// Per-atom masses (`nall` entries), or null to use `mass`.
    pub rmass: *const f64,
    /// Number of owned atoms.
    pub nlocal: i32,
    /// Owned plus ghost atoms.
    pub nall: i32,
}

/// Step-level settings of one force evaluation.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlStep {
    /// Time step number used as the key of the pair noise (LAMMPS `update->ntimestep`), ≥ 0.
    pub step: i64,
    /// Time step δt (> 0): the random force scales as δt^(−1/2).
    pub dt: f64,
    /// LAMMPS `force->newton_pair` (half lists: 1 also updates ghost forces).
    pub newton_pair: i32,
    /// 2 or 3. Coordinates are used as given (z = 0 in 2-D under `fix enforce2d`).
    pub dimension: i32,
    /// Box lengths (LAMMPS `domain->xprd`, `yprd`, `zprd`), for the pair noise's image key:
    /// along a periodic axis shorter than 2 r_c a pair meets several images of its partner
    /// (ghosts), each keyed apart (`dpdnl::host::ImageFrame`, docs/models.md P-4b).
    pub boxlen: [f64; 3],
    /// Tilts xy, xz, yz (LAMMPS `domain->xy`, `xz`, `yz`; 0 for an orthogonal box).
    pub tilt: [f64; 3],
    /// Periodic axes (LAMMPS `domain->periodicity`). All 0: no image key (the plain key of
    /// a box at least 2 r_c long).
    pub periodic: [i32; 3],
    /// The current run's first and last step (LAMMPS `update->beginstep`, `endstep`: `run N
    /// start S stop E` sets them): a thermostat style's temperature ramp (`dpd/nonlinear/tstat`)
    /// reads them. Both 0 before any run.
    pub beginstep: i64,
    /// See `beginstep`.
    pub endstep: i64,
}

/// Energy and virial accumulators, following LAMMPS `Pair::ev_tally` / `ev_tally_full`.
/// Every pointer may be null when its flag is 0; results are added to what is there.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DpdnlTally {
    /// Nonzero: add the conservative energy to `*eng_vdwl`.
    pub eflag_global: i32,
    /// Nonzero: add the pair virial to `virial[0..6]` (xx, yy, zz, xy, xz, yz).
    pub vflag_global: i32,
    /// Global energy accumulator (LAMMPS `Pair::eng_vdwl`).
    pub eng_vdwl: *mut f64,
    /// Global virial accumulator, 6 doubles (LAMMPS `Pair::virial`).
    pub virial: *mut f64,
    /// Per-atom energy (`nall` doubles) or null.
    pub eatom: *mut f64,
    /// Per-atom virial (`nall * 6` doubles, LAMMPS `&vatom[0][0]`) or null.
    pub vatom: *mut f64,
}
