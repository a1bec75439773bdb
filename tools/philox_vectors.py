#!/usr/bin/env python3
"""Independent reference for the keyed pair noise of src/rng.rs (generator version 1, Gaussian
mapping version 2).

Implements Philox4x32-10 and the documented Box-Muller mapping from the written specification
(not from the Rust code: Python's math.log and math.cos stand in for the engine's own fdlibm-based
ln and integer-reduced cosine), checks Random123's published known-answer vectors, and prints test
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
    a = ((o[0] << 32) | o[1]) >> 12
    b = ((o[2] << 32) | o[3]) >> 12
    u1 = 1.0 - a * 2.0 ** -52  # exact: a < 2**52
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * b * 2.0 ** -52)


for args in [(1, 0, 1, 2), (34387, 1, 7, 3), (34387, 123456789012, 1000, 999),
             (2147483647, 5, 4294967295, 1), (42, 2**32 + 7, 12, 13), (7, 99, 3, 4),
             (123, 0, 1, 5), (123, 1, 1, 5), (9, 2**40, 17, 2**31), (65535, 3, 8, 9)]:
    print(f"    ({args[0]}, {args[1]}, {args[2]}, {args[3]}, {pair_gaussian(*args)!r}),")


def gaussian_from_words(o):
    a = ((o[0] << 32) | o[1]) >> 12
    b = ((o[2] << 32) | o[3]) >> 12
    return math.sqrt(-2.0 * math.log(1.0 - a * 2.0 ** -52)) * math.cos(2.0 * math.pi * b * 2.0 ** -52)


def words(a, b):
    """Output words whose 52-bit integers are a and b (low 12 bits of each pair set to 1s, which
    the mapping discards)."""
    wa, wb = (a << 12) | 0xFFF, (b << 12) | 0xFFF
    return [wa >> 32, wa & MASK, wb >> 32, wb & MASK]


# Crafted words: every octant of the angle (b near k 2**49), both fdlibm cosine branches
# (|phi| < 0.3 and >= 0.3), both log branches, and the ends of u1 (a = 0: u1 = 1; a = 2**52 - 1:
# u1 = 2**-52).
print()
B = 2 ** 49
for a, b in [(0, 0), (2 ** 52 - 1, 3), (2 ** 51, B // 3), (12345, B), (2 ** 50, 3 * B + 17),
             (987654321, 5 * B - 1), (2 ** 52 - 2 ** 30, 7 * B), (2 ** 40, 8 * B - 5),
             (3 * 2 ** 50, 2 * B + B // 2), (2 ** 20, 6 * B - B // 3), (1234567890123, 4 * B + 99)]:
    o = words(a, b)
    print(f"    ([{', '.join(hex(w) for w in o)}], {gaussian_from_words(o)!r}),")
