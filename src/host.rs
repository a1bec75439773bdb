//! What a host engine needs, beyond the crate root, to run this library's styles and fixes on
//! its own atoms and neighbour lists: the facade of the C ABI (`capi/`, which LAMMPS's styles
//! call). The C ABI reaches the crate through this module, the root re-exports and the
//! documented modules (`grammar`, `init`, `rng`, `units`) only; the engine's and the forces
//! layer's internals stay private.
//!
//! Every item here is also what the standalone engine calls, so both engines share one rule:
//! the pair-style registry and its seam, the walk's distance filter and special-bond rule, the
//! working-list margins, the fixes' updates, the sheared box's wrapping and leak count, the box
//! and blow-up checks.

pub use crate::engine::check_atoms;
pub use crate::engine::fixes::{PexPick, PexSlabs, euler_update, pex_apply};
pub use crate::engine::lees_edwards::{
    FlipLeak, flip_jump_note, flip_leak_warning, flip_wrap_y, y_crossings,
};
pub use crate::engine::neighbor::{INNER_MARGIN, INNER_MIN_LIFE};
pub use crate::engine::simd::within_cut;
pub use crate::engine::topology::SpecialRule;
pub use crate::forces::batcher::{Batcher, lane_force};
pub use crate::forces::style::{PrePass, check_special, coverage};
pub use crate::forces::{Isa, PAIR_STYLES, PairStyleEntry, SetupNote, from_restart_lines};
pub use crate::init::{check_box_images, images_keyed};
pub use crate::rng::ImageFrame;
