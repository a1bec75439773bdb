//! Keyed pair noise: known-answer vectors, symmetry, key sensitivity, distribution.

use dpdnl::rng::{
    STREAM_PAIR_NOISE, gaussian_from_bits, keyed_bits, ordered_tags, pair_gaussian, philox4x32_10,
};

/// Random123's published known-answer vectors for Philox4x32-10 (kat_vectors).
#[test]
fn philox_known_answers() {
    assert_eq!(
        philox4x32_10([0, 0, 0, 0], [0, 0]),
        [0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8]
    );
    assert_eq!(
        philox4x32_10([u32::MAX; 4], [u32::MAX; 2]),
        [0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd]
    );
    assert_eq!(
        philox4x32_10(
            [0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344],
            [0xa4093822, 0x299f31d0]
        ),
        [0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1]
    );
}
