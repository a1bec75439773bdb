use super::*;
use crate::list::for_each_row;

thread_local! {
    /// Set: this thread's builds take the portable loop (to compare it with the vector one).
    pub(super) static SCALAR: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The atoms of a 3-D one-type cloud without bonds.
fn atomic<'a>(
    x: &'a [f64],
    ty: &'a [i32],
    tag: &'a [i32],
    nlocal: usize,
    newton: bool,
) -> Cloud<'a> {
    Cloud {
        x,
        ty,
        tag,
        nlocal,
        special: None,
        newton,
        dim: 3,
    }
}

/// A small periodic box of random atoms, its ghosts the images within `ghost` of the box
/// (as LAMMPS's borders make them on one rank).
fn cloud(n: usize, len: f64, ghost: f64, seed: u64) -> (Vec<f64>, Vec<i32>, usize) {
    let mut s = seed;
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let own: Vec<[f64; 3]> = (0..n)
        .map(|_| [rnd() * len, rnd() * len, rnd() * len])
        .collect();
    let mut x = Vec::new();
    let mut tag = Vec::new();
    for (k, p) in own.iter().enumerate() {
        x.extend_from_slice(p);
        tag.push(k as i32 + 1);
    }
    let range = |v: f64| -> Vec<i32> {
        let mut s = vec![];
        for m in -2i32..=2 {
            let w = v + m as f64 * len;
            if m != 0 && w > -ghost && w < len + ghost {
                s.push(m);
            }
        }
        s.push(0);
        s
    };
    for (k, p) in own.iter().enumerate() {
        for mx in range(p[0]) {
            for my in range(p[1]) {
                for mz in range(p[2]) {
                    if mx == 0 && my == 0 && mz == 0 {
                        continue;
                    }
                    x.extend_from_slice(&[
                        p[0] + mx as f64 * len,
                        p[1] + my as f64 * len,
                        p[2] + mz as f64 * len,
                    ]);
                    tag.push(k as i32 + 1);
                }
            }
        }
    }
    (x, tag, n)
}

/// Every pair of atoms (with its image) within the cut-off is listed exactly once with
/// newton on, and once per owned atom with newton off, for boxes longer and shorter than
/// twice the cut-off (an atom then meets images of its partner, and its own).
#[test]
fn every_pair_in_range_is_listed_once() {
    for (len, n, rc, margin) in [
        (5.0, 300, 1.0, 0.3),
        (1.7, 12, 1.0, 0.3),
        (1.2, 10, 1.0, 0.3),
        (3.0, 80, 1.2, 0.0),
    ] {
        let ghost = rc + margin;
        let (x, tag, nlocal) = cloud(n, len, ghost, 7);
        let nall = tag.len();
        let ty = vec![1; nall];
        for newton in [true, false] {
            let c = atomic(&x, &ty, &tag, nlocal, newton);
            let mut own = OwnList::default();
            let list = own
                .prepare(&c, 1, &[0.0, rc], margin, None)
                .unwrap_or_else(|e| panic!("{}", e.message));
            // Count, per (tag, tag, image displacement), the listed pairs in range rc.
            let mut seen = std::collections::BTreeMap::new();
            // SAFETY: the list's arrays live in `own`, sized for nlocal rows.
            unsafe {
                for_each_row(&list, nall, |i, row, mask| {
                    for &jr in row {
                        let j = jr as usize & mask;
                        let d: Vec<f64> = (0..3).map(|k| x[3 * j + k] - x[3 * i + k]).collect();
                        let r2: f64 = d.iter().map(|v| v * v).sum();
                        assert!(r2 < (rc + margin) * (rc + margin));
                        if r2 < rc * rc {
                            let (a, b, s) = if tag[i] <= tag[j] {
                                (tag[i], tag[j], 1.0)
                            } else {
                                (tag[j], tag[i], -1.0)
                            };
                            let key: Vec<i64> =
                                d.iter().map(|v| (s * v * 1e6).round() as i64).collect();
                            *seen.entry((a, b, key)).or_insert(0) += 1;
                        }
                    }
                    Ok(())
                })
                .unwrap_or_else(|e| panic!("{}", e.message));
            }
            // Brute force over the owned atoms and every image.
            let mut want = std::collections::BTreeMap::new();
            for i in 0..nlocal {
                for j in 0..nall {
                    let d: Vec<f64> = (0..3).map(|k| x[3 * j + k] - x[3 * i + k]).collect();
                    let r2: f64 = d.iter().map(|v| v * v).sum();
                    if j == i || r2 >= rc * rc {
                        continue;
                    }
                    let (a, b, s) = if tag[i] <= tag[j] {
                        (tag[i], tag[j], 1.0)
                    } else {
                        (tag[j], tag[i], -1.0)
                    };
                    let key: Vec<i64> = d.iter().map(|v| (s * v * 1e6).round() as i64).collect();
                    // With newton off an owned-owned pair is listed once, a pair with a
                    // ghost once per owned atom (the physical pair, from each side).
                    let times = if newton || j < nlocal { 1 } else { 2 };
                    want.insert((a, b, key), times);
                }
            }
            assert!(!want.is_empty());
            assert_eq!(seen, want, "len {len} newton {newton}");
            assert_eq!(own.builds(), 1);
        }
    }
}

/// Rows of a list as (atom, entries).
fn rows_of(list: &DpdnlNeighList, nall: usize) -> Vec<(usize, Vec<i32>)> {
    let mut rows = Vec::new();
    // SAFETY: the caller's list lives in its OwnList, sized for its rows.
    unsafe {
        for_each_row(list, nall, |i, row, _| {
            rows.push((i, row.to_vec()));
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{}", e.message));
    }
    rows
}

/// A team of threads builds the same list, row for row and entry for entry.
#[test]
fn threads_build_the_same_list() {
    // Enough atoms (owned and ghosts, each over 2 CHUNK_ATOMS) that the sorts, the bins
    // and the moved check run threaded too.
    let (x, tag, nlocal) = cloud(12000, 16.0, 2.0, 11);
    let nall = tag.len();
    assert!(nlocal > 2 * CHUNK_ATOMS && nall - nlocal > 2 * CHUNK_ATOMS);
    let ty = vec![1; nall];
    for threads in [2, 3] {
        let team = Team::new(threads, None).unwrap_or_else(|e| panic!("{e}"));
        for newton in [true, false] {
            let c = atomic(&x, &ty, &tag, nlocal, newton);
            let (mut one, mut two) = (OwnList::default(), OwnList::default());
            let a = one
                .prepare(&c, 1, &[0.0, 1.0], 0.3, None)
                .unwrap_or_else(|e| panic!("{}", e.message));
            let b = two
                .prepare(&c, 1, &[0.0, 1.0], 0.3, Some(&team))
                .unwrap_or_else(|e| panic!("{}", e.message));
            assert!(two.blocks.len() > 1);
            let ra = rows_of(&a, nall);
            assert_eq!(ra.len(), nlocal);
            assert!(ra.iter().map(|r| r.1.len()).sum::<usize>() > 10 * nlocal);
            assert_eq!(ra, rows_of(&b, nall));
            for (s1, s2) in [
                (&one.grid.own, &two.grid.own),
                (&one.grid.ghost, &two.grid.ghost),
            ] {
                assert_eq!(
                    (&s1.start, &s1.order, &s1.stag),
                    (&s2.start, &s2.order, &s2.stag)
                );
                assert_eq!((&s1.sx, &s1.sy, &s1.sz), (&s2.sx, &s2.sy, &s2.sz));
            }
            assert_eq!(one.grid.bins, two.grid.bins);
        }
    }
}

/// The vector loop (AVX-512, where the CPU has it) and the portable one build the same list,
/// in a large box and in one shorter than twice the reach (images of an atom's own tag).
#[test]
fn every_instruction_set_builds_the_same_list() {
    for (n, len, seed) in [(3000, 10.0, 5), (12, 1.2, 9)] {
        let (x, tag, nlocal) = cloud(n, len, 1.3, seed);
        let nall = tag.len();
        let ty = vec![1; nall];
        for newton in [true, false] {
            let c = atomic(&x, &ty, &tag, nlocal, newton);
            let mut rows = Vec::new();
            for scalar in [false, true] {
                SCALAR.with(|s| s.set(scalar));
                let mut own = OwnList::default();
                let l = own
                    .prepare(&c, 1, &[0.0, 1.0], 0.3, None)
                    .unwrap_or_else(|e| panic!("{}", e.message));
                rows.push(rows_of(&l, nall));
            }
            SCALAR.with(|s| s.set(false));
            assert!(rows[0].iter().map(|r| r.1.len()).sum::<usize>() > nlocal);
            assert_eq!(rows[0], rows[1], "n {n} newton {newton}");
        }
    }
}

/// Built again when LAMMPS builds, or when an atom has moved more than half the margin.
#[test]
fn built_again_when_an_atom_moves_half_the_margin() {
    let (mut x, tag, nlocal) = cloud(50, 4.0, 1.3, 3);
    let ty = vec![1; tag.len()];
    let mut own = OwnList::default();
    let mut run = |x: &[f64], build| {
        let c = atomic(x, &ty, &tag, nlocal, true);
        own.prepare(&c, build, &[0.0, 1.0], 0.3, None)
            .map(|_| own.builds())
            .unwrap_or_else(|e| panic!("{}", e.message))
    };
    assert_eq!(run(&x, 1), 1);
    x[0] += 0.14;
    assert_eq!(run(&x, 1), 1);
    x[0] += 0.02;
    assert_eq!(run(&x, 1), 2);
    assert_eq!(run(&x, 2), 3);
}

/// Bonded neighbours carry their class in bits 30-31.
#[test]
fn special_neighbours_are_flagged() {
    // Atoms 1-2-3-4 on a line 0.5 apart, one owned rank, no ghosts (non-periodic).
    let x: Vec<f64> = (0..4).flat_map(|k| [0.5 * k as f64, 0.0, 0.0]).collect();
    let tag = vec![1, 2, 3, 4];
    let ty = vec![1; 4];
    // Atom 1: 1-2 neighbour 2, 1-3 neighbour 3, 1-4 neighbour 4.
    let nspecial = vec![1, 2, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    let special = vec![2, 3, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    let c = Cloud {
        x: &x,
        ty: &ty,
        tag: &tag,
        nlocal: 4,
        special: Some((&nspecial, &special, 3)),
        newton: true,
        dim: 3,
    };
    let mut own = OwnList::default();
    let list = own
        .prepare(&c, 1, &[0.0, 2.0], 0.0, None)
        .unwrap_or_else(|e| panic!("{}", e.message));
    let mut row0 = Vec::new();
    // SAFETY: the list's arrays live in `own`.
    unsafe {
        for_each_row(&list, 4, |i, row, _| {
            if i == 0 {
                row0 = row.to_vec();
            }
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{}", e.message));
    }
    let mut want = vec![1 | 1 << 30, 2 | 2 << 30, 3 | 3 << 30];
    row0.sort();
    want.sort();
    assert_eq!(row0, want);
}
