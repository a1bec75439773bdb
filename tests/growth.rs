//! How the difference between two runs grows (`dpdnl::io::growth`, the verdict of
//! `dpdnl crosscheck`), on synthetic sequences whose kind is known by construction: round-off
//! growing at a constant rate, a model difference at the first step, one that acts after it
//! (a jump, or a growth that does not come from round-off), too few points, round-off only;
//! and the per-step maxima of the exact comparison that feed it.

use dpdnl::io::dump_read::DumpFrame;
use dpdnl::io::growth::{
    Growth, MAX_RATE, Point, ROUNDOFF, classify, merged, printed_digits, resolution, table_rows,
    timeline,
};
use dpdnl::io::lammps_log::{
    StepMax, ThermoBlock, Tolerance, compare_dumps_exact, compare_exact_logs,
};

/// Thermo step maxima (block 0) with the given (step, difference) pairs.
fn thermo(points: &[(i64, f64)]) -> Vec<StepMax> {
    points
        .iter()
        .map(|&(step, d)| StepMax {
            block: 0,
            step,
            max_scaled: d,
            column: "pe".into(),
            id: None,
        })
        .collect()
}

/// Issue 41's sheared polymer: 3e-13 in the forces at step 0, then 3e-11, 2e-9, 2e-7 and
/// 1e-5 at steps 100–400. The rate is the least-squares slope of ln d over steps 100–400,
/// computed here from those four numbers independently of the code.
#[test]
fn issue_41_numbers_are_chaotic_growth_of_round_off() {
    let pts = [
        (0, 3e-13),
        (100, 3e-11),
        (200, 2e-9),
        (300, 2e-7),
        (400, 1e-5),
    ];
    let tl = timeline(&thermo(&pts), &[]);
    let (xs, ys): (Vec<f64>, Vec<f64>) = pts[1..].iter().map(|&(s, d)| (s as f64, d.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / 4.0, ys.iter().sum::<f64>() / 4.0);
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx) * (x - mx)).sum::<f64>();
    match classify(&tl, 1e-6, resolution(15)) {
        Growth::Chaotic {
            start,
            rate,
            fitted,
            reaches_rtol,
        } => {
            assert_eq!((start.step, start.diff), (0, 3e-13));
            assert!((rate - slope).abs() < 1e-12 * slope, "{rate} vs {slope}");
            assert_eq!(fitted.len(), 4);
            // The line crosses 1e-6 between steps 300 (2e-7) and 400 (1e-5).
            let t = reaches_rtol.expect("crosses rtol");
            assert!(t > 300.0 && t < 400.0, "{t}");
        }
        g => panic!("expected Chaotic, got {g:?}"),
    }
}

/// A difference above round-off at the first step is a model difference, whatever follows.
#[test]
fn a_difference_at_the_first_step_is_a_model_difference() {
    let tl = timeline(&thermo(&[(0, 2e-9), (100, 3e-9), (200, 5e-9)]), &[]);
    match classify(&tl, 1e-9, resolution(15)) {
        Growth::AtStart { start, floor } => {
            assert_eq!((start.step, start.diff), (0, 2e-9));
            assert_eq!(floor, ROUNDOFF);
        }
        g => panic!("expected AtStart, got {g:?}"),
    }
    // With 8 printed digits the floor is their resolution, 1e-7: 2e-9 is then not resolved
    // at the first step, and the 1e-3 jump by step 10 is too fast for chaos.
    let tl = timeline(&thermo(&[(0, 2e-9), (10, 1e-3), (20, 2e-3)]), &[]);
    match classify(&tl, 1e-6, resolution(8)) {
        Growth::NotRoundoff {
            needed_rate, floor, ..
        } => {
            assert_eq!(floor, 1e-7);
            assert!((needed_rate - (1e-3f64 / 1e-7).ln() / 10.0).abs() < 1e-12);
            assert!(needed_rate > MAX_RATE);
        }
        g => panic!("expected NotRoundoff, got {g:?}"),
    }
}

/// Round-off at the first step, then a difference that did not grow from it: a constant 1e-9
/// from step 10 on (the fitted line does not grow), and a slow growth from 1e-9 whose line,
/// taken back to the first step, is 1e-9, far above round-off (1e-12 × START_SLACK = 1e-10).
#[test]
fn a_difference_that_appears_after_the_first_step_is_not_round_off() {
    let flat: Vec<(i64, f64)> = std::iter::once((0, 1e-13))
        .chain((1..=10).map(|k| (10 * k, 1e-9)))
        .chain(std::iter::once((110, 1e-2)))
        .collect();
    match classify(&timeline(&thermo(&flat), &[]), 1e-6, resolution(15)) {
        Growth::NotRoundoff { at, line_start, .. } => {
            assert_eq!(at.step, 10);
            assert_eq!(line_start, None, "a flat difference has no growth line");
        }
        g => panic!("expected NotRoundoff, got {g:?}"),
    }
    // Steps 100 apart, so that the rate from round-off to the first point, ln(2.7e3)/100 =
    // 0.08 per step, is plausible for chaos: only the line's start tells.
    let slow: Vec<(i64, f64)> = std::iter::once((0, 0.0))
        .chain((1..=20).map(|k| (100 * k, 1e-9 * (0.01 * 100.0 * k as f64).exp())))
        .collect();
    match classify(&timeline(&thermo(&slow), &[]), 1e-9, resolution(15)) {
        Growth::NotRoundoff {
            line_start: Some(l),
            needed_rate,
            ..
        } => {
            assert!((l / 1e-9 - 1.0).abs() < 1e-9, "{l}");
            assert!(needed_rate < MAX_RATE, "{needed_rate}");
        }
        g => panic!("expected NotRoundoff with a line, got {g:?}"),
    }
}

/// A growth from round-off whose points leave the line by more than LINE_SLACK (30×): a
/// steady growth with one point 1000× above it is not a constant rate.
#[test]
fn a_growth_far_off_its_line_is_not_chaos() {
    let mut pts: Vec<(i64, f64)> = (0..=8)
        .map(|k| (50 * k, 1e-13 * (0.046 * 50.0 * k as f64).exp()))
        .collect();
    let clean = classify(&timeline(&thermo(&pts), &[]), 1e-9, resolution(15));
    assert!(matches!(clean, Growth::Chaotic { .. }), "{clean:?}");
    pts[4].1 *= 1000.0;
    let kinked = classify(&timeline(&thermo(&pts), &[]), 1e-9, resolution(15));
    assert!(matches!(kinked, Growth::NotRoundoff { .. }), "{kinked:?}");
}

/// One resolvable point before saturation, reachable from round-off at a plausible rate: the
/// growth cannot be measured, and the verdict says which rate it would need.
#[test]
fn too_few_points_are_unresolved() {
    let tl = timeline(&thermo(&[(0, 1e-14), (100, 1e-6), (200, 0.5)]), &[]);
    match classify(&tl, 1e-9, resolution(15)) {
        Growth::Unresolved {
            at, needed_rate, ..
        } => {
            assert_eq!(at.step, 100);
            let want = (1e-6f64 / ROUNDOFF).ln() / 100.0;
            assert!(
                (needed_rate - want).abs() < 1e-12,
                "{needed_rate} vs {want}"
            );
        }
        g => panic!("expected Unresolved, got {g:?}"),
    }
}

/// Differences above a very tight tolerance but never above round-off: the tolerance is the
/// problem; and no difference above the tolerance is agreement.
#[test]
fn round_off_only_and_agreement() {
    let tl = timeline(&thermo(&[(0, 1e-14), (10, 3e-13), (20, 2e-13)]), &[]);
    match classify(&tl, 1e-14, resolution(15)) {
        Growth::RoundoffOnly { largest, floor } => {
            assert_eq!((largest.step, floor), (10, ROUNDOFF));
        }
        g => panic!("expected RoundoffOnly, got {g:?}"),
    }
    assert_eq!(classify(&tl, 1e-9, resolution(15)), Growth::Agree);
}

/// Thermo and dump maxima share one axis: the larger difference per step in the merged view,
/// the fit on one source (the dump here sits 30× above the thermo values at its steps, as
/// per-atom values do, and would make a sawtooth of a merged fit); a `reset_timestep` between
/// runs continues the elapsed count.
#[test]
fn timeline_merges_sources_and_continues_across_a_reset() {
    let rate = 0.04;
    let th: Vec<(i64, f64)> = (0..=20)
        .map(|k| (20 * k, 1e-14 * (rate * 20.0 * k as f64).exp()))
        .collect();
    let dump: Vec<StepMax> = (0..=4)
        .map(|k| StepMax {
            block: 0,
            step: 100 * k,
            max_scaled: 3e-13 * (rate * 100.0 * k as f64).exp(),
            column: "fx".into(),
            id: Some(7),
        })
        .collect();
    let tl = timeline(&thermo(&th), &[("dump.x".into(), dump)]);
    assert_eq!(tl.len(), 21 + 5);
    let m = merged(&tl);
    assert_eq!(m.len(), 21);
    assert_eq!(m[5].what, "fx (id 7, dump.x)");
    assert!((m[5].diff - 3e-13 * (rate * 100.0f64).exp()).abs() < 1e-25);
    assert_eq!(m[4].what, "pe");
    match classify(&tl, 1e-9, resolution(15)) {
        Growth::Chaotic {
            start,
            rate: r,
            fitted,
            ..
        } => {
            // Step 0: the dump's 3e-13 is the larger difference.
            assert_eq!(start.diff, 3e-13);
            assert!(
                fitted.iter().all(|&i| tl[i].source == 0),
                "fitted on thermo"
            );
            assert!((r - rate).abs() < 1e-9, "{r}");
        }
        g => panic!("expected Chaotic, got {g:?}"),
    }
    // Two runs, the second after reset_timestep 0: steps 0..100 then 0..100 again.
    let two: Vec<StepMax> = [(0, 0), (0, 100), (1, 0), (1, 100)]
        .iter()
        .map(|&(block, step)| StepMax {
            block,
            step,
            max_scaled: 0.0,
            column: String::new(),
            id: None,
        })
        .collect();
    let e: Vec<i64> = timeline(&two, &[]).iter().map(|p| p.elapsed).collect();
    assert_eq!(e, vec![0, 100, 100, 200]);
}

#[test]
fn printed_digits_and_table_rows() {
    let log = "Step Temp Press\n0 1.00000000000000 -0.123456789012345\n10 0.99 1e-5\n\
               Loop time of 0.1 on 1 procs\n";
    assert_eq!(printed_digits(log), Some(15));
    assert_eq!(printed_digits("Step Temp\n0 1.2345678\n5 0.5\n"), Some(8));
    assert_eq!(printed_digits("Step\n0\n10\n"), None);
    assert_eq!(resolution(15), 1e-14);
    let pts: Vec<Point> = timeline(
        &thermo(
            &(0..100)
                .map(|k| (k, 1e-13 * 1.1f64.powi(k as i32)))
                .collect::<Vec<_>>(),
        ),
        &[],
    );
    let rows = table_rows(&pts, 1e-9, 12);
    assert!(rows.len() <= 12 + 1, "{rows:?}");
    assert_eq!(rows.first(), Some(&0));
    assert_eq!(rows.last(), Some(&99));
    // The first point above rtol: 1e-13 · 1.1^k > 1e-9 from k = 97.
    assert!(rows.contains(&97), "{rows:?}");
}

/// The per-step maxima of the exact comparisons: thermo values against the largest |value|
/// of their column over the run, dump values against the largest of their column in the
/// frame; numbers chosen so that each quotient is exact in binary.
#[test]
fn per_step_maxima_are_scaled_by_column_and_frame() {
    let cols: Vec<String> = ["Step", "Temp", "Pxy"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let a = ThermoBlock {
        columns: cols.clone(),
        rows: vec![vec![0.0, 1.0, 4.0], vec![10.0, 2.0, -0.5]],
    };
    let b = ThermoBlock {
        columns: cols,
        rows: vec![vec![0.0, 1.0, 4.0], vec![10.0, 2.25, -0.25]],
    };
    let r = compare_exact_logs(&[a], &[b], None, Tolerance::default()).unwrap();
    let got: Vec<(i64, f64, &str)> = r
        .steps
        .iter()
        .map(|m| (m.step, m.max_scaled, m.column.as_str()))
        .collect();
    // Step 10: Temp 0.25 / 2.25, Pxy 0.25 / 4 (its largest |value| is at step 0).
    assert_eq!(got, vec![(0, 0.0, ""), (10, 0.25 / 2.25, "Temp")]);
    let frame = |step, fx: [f64; 2]| DumpFrame {
        step,
        box_bounds: vec![[0.0, 1.0]; 3],
        tilt: None,
        columns: vec!["id".into(), "fx".into()],
        rows: vec![vec![1.0, fx[0]], vec![2.0, fx[1]]],
    };
    let da = vec![frame(0, [8.0, 0.5]), frame(100, [1.0, 2.0])];
    let db = vec![frame(0, [8.0, 0.25]), frame(100, [1.5, 2.0])];
    let r = compare_dumps_exact(&da, &db, None, Tolerance::default()).unwrap();
    let got: Vec<(i64, f64, Option<i64>)> = r
        .steps
        .iter()
        .map(|m| (m.step, m.max_scaled, m.id))
        .collect();
    // Step 0: atom 2's 0.25 against the frame's 8 (not against its own 0.5); step 100: atom
    // 1's 0.5 against 2.
    assert_eq!(got, vec![(0, 0.25 / 8.0, Some(2)), (100, 0.25, Some(1))]);
}
