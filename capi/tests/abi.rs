//! The C ABI's free functions against the Rust they wrap: the pair Gaussian bit for bit. (The
//! pair handle, the API of the LAMMPS styles, is tested in `pair_handle.rs`; the former
//! low-level per-table API, `DpdnlParams` and `dpdnl_compute`, was removed in issue 45.)

use dpdnl::rng::pair_gaussian;
use dpdnl_capi::*;

const SEED: u32 = 4242;

#[test]
fn gaussian_matches_rng() {
    for k in 0..50u32 {
        let (a, b, step) = (k * 7 + 1, k * 13 + 2, u64::from(k) << 33 | 5);
        assert_eq!(
            dpdnl_pair_gaussian(SEED, step, a, b).to_bits(),
            pair_gaussian(SEED, step, a, b).to_bits()
        );
    }
}
