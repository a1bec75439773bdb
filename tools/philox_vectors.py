#!/usr/bin/env python3
"""Independent reference for the keyed pair noise of src/rng.rs (algorithm version 1).

Implements Philox4x32-10 and the documented Box-Muller mapping from the written specification
(not from the Rust code), checks Random123's published known-answer vectors, and prints test
vectors for tests/rng.rs. Run: python3 tools/philox_vectors.py
"""
import math

M0, M1, W0, W1 = 0xD2511F53, 0xCD9E8D57, 0x9E3779B9, 0xBB67AE85
MASK = 0xFFFFFFFF


def philox(ctr, key):
    c0, c1, c2, c3 = ctr
    k0, k1 = key
    for r in range(10):
        if r:
            k0, k1 = (k0 + W0) & MASK, (k1 + W1) & MASK
        p0, p1 = M0 * c0, M1 * c2
        c0, c1, c2, c3 = ((p1 >> 32) ^ c1 ^ k0) & MASK, p1 & MASK, ((p0 >> 32) ^ c3 ^ k1) & MASK, p0 & MASK
    return [c0, c1, c2, c3]


assert philox([0, 0, 0, 0], [0, 0]) == [0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8]
assert philox([MASK] * 4, [MASK] * 2) == [0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd]


def pair_gaussian(seed, step, ti, tj, stream=1):
    lo, hi = min(ti, tj), max(ti, tj)
    o = philox([step & MASK, step >> 32, lo, hi], [seed, stream])
    a = ((o[0] << 32) | o[1]) >> 11
    b = ((o[2] << 32) | o[3]) >> 11
    u1 = (a + 0.5) * 2.0 ** -53
    u2 = b * 2.0 ** -53
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)


for args in [(1, 0, 1, 2), (34387, 1, 7, 3), (34387, 123456789012, 1000, 999),
             (2147483647, 5, 4294967295, 1), (42, 2**32 + 7, 12, 13)]:
    print(f"    ({args[0]}, {args[1]}, {args[2]}, {args[3]}, {pair_gaussian(*args)!r}),")
