//! Reading LAMMPS logs and text dumps, and the comparison functions behind `dpdnl diff`.
//!
//! The two logs in tests/data/diff_logs imitate LAMMPS 2022 (`thermo_style one`, a WARNING
//! inside the block, the timing summary after it) and LAMMPS 2025 (two runs, the second with
//! custom columns `c_pxy[4] v_eta f_ave cpu` printed with `%20.15g`).
//!
//! Values read from text are compared exactly with the same decimal literals: both go through
//! correctly rounded decimal-to-binary conversion.
//!
//! Also here: the refusal of non-finite numbers by the data-file, dump and log readers (issue 16,
//! item 2), and the neighbour-list summary that `dpdnl crosscheck` reads from a LAMMPS log.

use dpdnl::io::data::parse_data;
use dpdnl::io::dump_read::parse_dump;
use dpdnl::io::lammps_log::{
    NeighborSettings, ThermoBlock, Tolerance, compare_dumps_exact, compare_exact,
    compare_exact_logs, compare_stats, differences, looks_like_dump, neighbor_summary, parse_log,
};

const LOG_2022: &str = include_str!("data/diff_logs/log_lammps2022.lammps");
const LOG_2025: &str = include_str!("data/diff_logs/log_lammps2025.lammps");

#[test]
fn lammps_2022_log() {
    let blocks = parse_log(LOG_2022).unwrap();
    assert_eq!(blocks.len(), 1);
    let b = &blocks[0];
    assert_eq!(
        b.columns,
        ["Step", "Temp", "E_pair", "E_mol", "TotEng", "Press"]
    );
    assert_eq!(
        b.rows.len(),
        11,
        "the WARNING line inside the block is skipped"
    );
    assert_eq!(b.rows[0], [0.0, 1.0, 25.104742, 0.0, 26.604242, 23.815478]);
    let steps = b.column("Step").unwrap();
    assert_eq!(
        steps,
        (0..=10).map(|k| 100.0 * k as f64).collect::<Vec<_>>()
    );
    assert_eq!(
        b.column("temp").unwrap()[5],
        1.0085476,
        "case-insensitive lookup"
    );
    assert!(b.column("Volume").is_none());
    assert!(!looks_like_dump(LOG_2022));
}

#[test]
fn lammps_2025_log_two_runs_wide_columns() {
    let blocks = parse_log(LOG_2025).unwrap();
    assert_eq!(blocks.len(), 2);
    assert_eq!(blocks[0].columns, ["Step", "Temp", "Press"]);
    assert_eq!(blocks[0].rows.len(), 5);
    assert_eq!(blocks[0].rows[4], [200.0, 0.99704211, 23.634182]);
    let b = &blocks[1];
    assert_eq!(
        b.columns,
        [
            "Step", "Time", "Temp", "Press", "c_myT", "c_pxy[4]", "v_eta", "f_ave", "CPU"
        ]
    );
    assert_eq!(b.rows.len(), 6);
    assert_eq!(b.column_index("c_pxy[4]"), Some(5));
    let last = b.rows.last().unwrap();
    assert_eq!(last[0], 450.0);
    assert_eq!(last[5], -0.00863709949995196);
    assert_eq!(last[6], -0.00148192789534372);
}

#[test]
fn block_boundaries() {
    let text = "\
some preamble
Step Temp
0 1.0
WARNING: something

10 1.5
ERROR: Lost atoms: original 100 current 99
Step Temp
Loop time of 0 on 1 procs
Step Temp E
20 2 nan
30 -inf 4e-3
";
    let blocks = parse_log(text).unwrap();
    assert_eq!(blocks.len(), 2, "the header with no rows is not a block");
    assert_eq!(blocks[0].rows, [[0.0, 1.0], [10.0, 1.5]]);
    assert_eq!(blocks[1].rows.len(), 2);
    assert!(blocks[1].rows[0][2].is_nan());
    assert_eq!(blocks[1].rows[1][1], f64::NEG_INFINITY);
    assert_eq!(parse_log("").unwrap(), Vec::<ThermoBlock>::new());
    assert_eq!(parse_log("Stepping stone\n1 2\n").unwrap().len(), 0);
}

#[test]
fn row_length_errors_and_unfinished_logs() {
    let e = parse_log("Step Temp\n0 1\n10 1 2\n20 1\n").unwrap_err();
    assert!(
        e.contains("line 3") && e.contains("3 values") && e.contains("2 columns"),
        "{e}"
    );
    // A log still being written: the unterminated last line is dropped.
    let blocks = parse_log("Step Temp Press\n0 1 2\n10 1.5 2.5\n20 1.").unwrap();
    assert_eq!(blocks[0].rows.len(), 2);
}

const DUMP: &str = "\
ITEM: TIMESTEP
100
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS pp pp pp
0.0 8.0
-1.0 7.0
0 8
ITEM: ATOMS id type x y z vx
3 1 0.5 0.5 0.5 -0.1
1 1 1.5 2.5 3.5 0.2
2 2 4.0 4.0 4.0 0.0
ITEM: TIMESTEP
200
ITEM: UNITS
lj
ITEM: TIME
2.0
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS xy xz yz pp pp pp
0.0 8.5 0.5
0.0 8.0 0.0
0.0 8.0 0.25
ITEM: ATOMS id type x y z vx
2 2 4.1 4.0 4.0 0.01
1 1 1.6 2.5 3.5 0.2
3 1 0.4 0.5 0.5 -0.1
";

#[test]
fn dump_frames() {
    assert!(looks_like_dump(DUMP));
    let frames = parse_dump(DUMP).unwrap();
    assert_eq!(frames.len(), 2);
    let f = &frames[0];
    assert_eq!(f.step, 100);
    assert_eq!(f.box_bounds, [[0.0, 8.0], [-1.0, 7.0], [0.0, 8.0]]);
    assert_eq!(f.tilt, None);
    assert_eq!(f.columns, ["id", "type", "x", "y", "z", "vx"]);
    let ids: Vec<f64> = f.rows.iter().map(|r| r[0]).collect();
    assert_eq!(ids, [1.0, 2.0, 3.0], "rows sorted by id");
    assert_eq!(f.rows[0], [1.0, 1.0, 1.5, 2.5, 3.5, 0.2]);
    let g = &frames[1];
    assert_eq!(g.step, 200);
    assert_eq!(g.tilt, Some([0.5, 0.0, 0.25]));
    assert_eq!(g.box_bounds[0], [0.0, 8.5]);
    assert_eq!(g.rows[2], [3.0, 1.0, 0.4, 0.5, 0.5, -0.1]);
}

#[test]
fn dump_errors() {
    let cases: &[(&str, &str)] = &[
        ("ITEM: TIMESTEP\nabc\n", "timestep"),
        ("hello\n", "expected 'ITEM: TIMESTEP'"),
        (
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id x\n1 0.5\n",
            "truncated",
        ),
        (
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id x\n1 C\n",
            "line 10",
        ),
        (
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x\n1 0.5\n",
            "BOX BOUNDS",
        ),
        (
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS abc origin pp pp pp\n",
            "general triclinic",
        ),
        (
            "ITEM: TIMESTEP\n0\nITEM: ATOMS id x\n1 0.5\n",
            "NUMBER OF ATOMS",
        ),
    ];
    for (text, want) in cases {
        let e = parse_dump(text).unwrap_err();
        assert!(e.contains(want), "{text:?}: {e}");
    }
}

/// The spellings of a non-finite number that Rust's `f64` parser accepts.
const NON_FINITE: [&str; 5] = ["nan", "NaN", "inf", "-inf", "1e999"];

/// A data file whose line 13 (atom 2) is `2 1 X 0.5 0.5` and line 18 (its velocity) `2 0 V 0`.
fn data_file(x: &str, v: &str, box_hi: &str) -> String {
    format!(
        "title\n\n2 atoms\n1 atom types\n\n0 {box_hi} xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n\n\
         Atoms # atomic\n\n1 1 0.5 0.5 0.5\n2 1 {x} 0.5 0.5\n\nVelocities\n\n1 0 0 0\n2 0 {v} 0\n"
    )
}

/// read_data refuses NaN and infinite box bounds, masses, coordinates and velocities, naming
/// the file, the line and the column (issue 16, item 2).
#[test]
fn data_file_refuses_non_finite_numbers() {
    let good = parse_data(&data_file("1.5", "0.25", "4"), "in.data").unwrap();
    assert_eq!(good.atoms[1].2, [1.5, 0.5, 0.5]);
    assert_eq!(good.velocities[1].1, [0.0, 0.25, 0.0]);
    for tok in NON_FINITE {
        let e = parse_data(&data_file(tok, "0", "4"), "in.data").expect_err(tok);
        let want =
            format!("in.data:13: column 3: expected a coordinate: '{tok}' is not a finite number");
        assert!(e.contains(&want), "{tok}: {e}");
        let e = parse_data(&data_file("1", tok, "4"), "in.data").expect_err(tok);
        let want = format!("in.data:18: column 3: expected a velocity: '{tok}'");
        assert!(e.contains(&want), "{tok}: {e}");
        let e = parse_data(&data_file("1", "0", tok), "in.data").expect_err(tok);
        assert!(
            e.contains("in.data:6: column 2: expected a box bound"),
            "{tok}: {e}"
        );
        let masses = data_file("1", "0", "4")
            .replace("\n\nAtoms", &format!("\n\nMasses\n\n1 {tok}\n\nAtoms"));
        let e = parse_data(&masses, "in.data").expect_err(tok);
        assert!(
            e.contains("in.data:12: column 2: expected a mass"),
            "{tok}: {e}"
        );
    }
    let e = parse_data(&data_file("1e999", "0", "4"), "in.data").unwrap_err();
    assert!(e.contains("beyond the range of a double"), "{e}");
    let e = parse_data(&data_file("-inf", "0", "4"), "in.data").unwrap_err();
    assert!(e.contains("an infinity is refused"), "{e}");
    let e = parse_data(&data_file("1.2.3", "0", "4"), "in.data").unwrap_err();
    assert!(
        e.contains("in.data:13: column 3: expected a coordinate, found '1.2.3'"),
        "{e}"
    );
}

/// The dump reader refuses NaN and infinities in atom rows and box bounds, with line and column.
#[test]
fn dump_refuses_non_finite_numbers() {
    for tok in NON_FINITE {
        let e =
            parse_dump(&DUMP.replacen("1 1 1.5 2.5 3.5 0.2", &format!("1 1 1.5 {tok} 3.5 0.2"), 1))
                .expect_err(tok);
        let want = format!("line 11: atom line: column 4: '{tok}' is not a finite number");
        assert!(e.contains(&want), "{tok}: {e}");
        let e = parse_dump(&DUMP.replacen("-1.0 7.0", &format!("-1.0 {tok}"), 1)).expect_err(tok);
        let want = format!("line 7: box bounds: column 2: '{tok}' is not a finite number");
        assert!(e.contains(&want), "{tok}: {e}");
    }
    let e = parse_dump(&DUMP.replacen("0.0 8.5 0.5", "0.0 8.5 nan", 1)).unwrap_err();
    assert!(e.contains("box bounds: column 3: 'nan'"), "{e}");
}

/// Logs keep reading `nan`/`inf` (LAMMPS prints them after a blow-up: see `block_boundaries`),
/// but a decimal literal beyond the range of a double is refused with line and column.
#[test]
fn log_refuses_overflowing_numbers() {
    let e = parse_log("Step Temp Press\n0 1 2\n10 1e999 2\n").unwrap_err();
    assert!(
        e.contains("line 3: column 2: '1e999' is not a finite number")
            && e.contains("beyond the range of a double"),
        "{e}"
    );
    let e = parse_log("Step Temp Press\n0 1 -2e400\n").unwrap_err();
    assert!(e.contains("line 2: column 3: '-2e400'"), "{e}");
    let b = parse_log("Step Temp Press\n0 inf -Inf\n10 NaN -nan\n").unwrap();
    assert_eq!(b[0].rows[0][1..], [f64::INFINITY, f64::NEG_INFINITY]);
    assert!(b[0].rows[1][1].is_nan() && b[0].rows[1][2].is_nan());
}

#[test]
fn relative_and_absolute_differences() {
    assert_eq!(differences(2.0, 2.0), (0.0, 0.0));
    assert_eq!(differences(0.0, 0.0), (0.0, 0.0));
    assert_eq!(differences(f64::NAN, f64::NAN), (0.0, 0.0));
    assert_eq!(differences(1.0, f64::NAN).1, f64::INFINITY);
    assert_eq!(differences(f64::INFINITY, f64::INFINITY), (0.0, 0.0));
    assert_eq!(differences(4.0, -4.0), (8.0, 2.0));
    assert_eq!(differences(1.0, 0.5), (0.5, 0.5));
}

fn block(columns: &[&str], rows: &[&[f64]]) -> ThermoBlock {
    ThermoBlock {
        columns: columns.iter().map(|c| c.to_string()).collect(),
        rows: rows.iter().map(|r| r.to_vec()).collect(),
    }
}

#[test]
fn exact_comparison_of_blocks() {
    let a = block(
        &["Step", "Temp", "Press", "CPU"],
        &[
            &[0.0, 1.0, 2.0, 0.0],
            &[10.0, 1.5, 2.5, 0.1],
            &[20.0, 1.25, 3.0, 0.2],
        ],
    );
    // Same values in another column order, other timings, one extra step; Press at step 10
    // differs by 4e-8 relative.
    let b = block(
        &["Step", "Press", "Temp", "CPU"],
        &[
            &[0.0, 2.0, 1.0, 0.5],
            &[10.0, 2.5 * (1.0 + 4e-8), 1.5, 0.6],
            &[20.0, 3.0, 1.25, 0.7],
            &[30.0, 3.0, 1.0, 0.8],
        ],
    );
    let r = compare_exact(&a, &b, None, Tolerance::default()).unwrap();
    assert_eq!(r.n_matched, 3);
    assert_eq!((r.n_only_in_a, r.n_only_in_b), (0, 1));
    assert_eq!(r.only_in_b, ["step 30"]);
    let names: Vec<&str> = r.columns.iter().map(|c| c.column.as_str()).collect();
    assert_eq!(names, ["Temp", "Press"], "CPU (timing) left out");
    assert_eq!(r.failing_columns(), ["Press"]);
    let p = &r.columns[1];
    assert_eq!(p.n_fail, 1);
    // |A−B| / max(|A|, |B|) = 4e-8 / (1 + 4e-8), up to rounding of the perturbed value.
    assert!((p.max_rel - 4e-8 / (1.0 + 4e-8)).abs() < 1e-14, "{p:?}");
    assert_eq!(p.worst.as_ref().map(|w| w.0.as_str()), Some("step 10"));
    // A looser tolerance passes; so does a large atol.
    let loose = Tolerance {
        rtol: 1e-7,
        atol: 0.0,
    };
    assert!(compare_exact(&a, &b, None, loose).unwrap().values_pass());
    let abs = Tolerance {
        rtol: 0.0,
        atol: 1e-6,
    };
    assert!(compare_exact(&a, &b, None, abs).unwrap().values_pass());
    // Picking columns; the timing column can be asked for by name.
    let only_temp = ["temp".to_string()];
    let r = compare_exact(&a, &b, Some(&only_temp), Tolerance::default()).unwrap();
    assert!(r.values_pass() && r.columns.len() == 1);
    let cpu = ["CPU".to_string()];
    assert!(
        !compare_exact(&a, &b, Some(&cpu), Tolerance::default())
            .unwrap()
            .values_pass()
    );
}

#[test]
fn exact_comparison_errors() {
    let a = block(&["Step", "Temp"], &[&[0.0, 1.0]]);
    let b = block(&["Step", "Temp", "Volume"], &[&[0.0, 1.0, 8.0]]);
    let e = compare_exact(&a, &b, None, Tolerance::default()).unwrap_err();
    assert!(e.contains("column mismatch") && e.contains("Volume"), "{e}");
    let vol = ["Volume".to_string()];
    let e = compare_exact(&a, &b, Some(&vol), Tolerance::default()).unwrap_err();
    assert!(e.contains("'Volume' is not in A"), "{e}");
    let c = block(&["Step", "Temp"], &[&[5.0, 1.0]]);
    let e = compare_exact(&a, &c, None, Tolerance::default()).unwrap_err();
    assert!(e.contains("no Step in common"), "{e}");
    let d = block(&["Temp"], &[&[1.0]]);
    let e = compare_exact(&d, &d, None, Tolerance::default()).unwrap_err();
    assert!(e.contains("no Step column"), "{e}");
    let dup = block(&["Step", "Temp"], &[&[0.0, 1.0], &[0.0, 2.0]]);
    let e = compare_exact(&dup, &a, None, Tolerance::default()).unwrap_err();
    assert!(e.contains("step 0 appears twice"), "{e}");
    let ragged = block(&["Step", "Temp"], &[&[0.0, 1.0], &[10.0]]);
    let e = compare_exact(&a, &ragged, None, Tolerance::default()).unwrap_err();
    assert!(e.contains("B: row 2"), "{e}");
    let e = compare_stats(&ragged, &a, None, 0, 3.0).unwrap_err();
    assert!(e.contains("A: row 2"), "{e}");
    assert!(ragged.column("Temp").unwrap()[1].is_nan());
    let e = compare_exact_logs(
        std::slice::from_ref(&a),
        &[a.clone(), a.clone()],
        None,
        Tolerance::default(),
    )
    .unwrap_err();
    assert!(e.contains("1 thermo block(s) but B has 2"), "{e}");
}

#[test]
fn multi_block_logs_compare_block_by_block() {
    let blocks = parse_log(LOG_2025).unwrap();
    let e = compare_exact_logs(&blocks, &blocks, None, Tolerance::default()).unwrap_err();
    assert!(e.contains("block 2 has different columns"), "{e}");
    let r = compare_exact_logs(&blocks[1..], &blocks[1..], None, Tolerance::default()).unwrap();
    assert!(r.values_pass() && r.rows_match());
    assert_eq!(r.n_matched, 6);
    assert!(r.columns.iter().all(|c| c.column != "CPU"));
}

#[test]
fn dump_comparison_matches_step_and_id() {
    let a = parse_dump(DUMP).unwrap();
    // Same frames with the atom lines shuffled differently and one x moved at step 200, id 1.
    let shuffled = DUMP
        .replace(
            "3 1 0.5 0.5 0.5 -0.1\n1 1 1.5 2.5 3.5 0.2\n",
            "1 1 1.5 2.5 3.5 0.2\n3 1 0.5 0.5 0.5 -0.1\n",
        )
        .replace("1 1 1.6 2.5", "1 1 1.6000001 2.5");
    let b = parse_dump(&shuffled).unwrap();
    let r = compare_dumps_exact(&a, &a, None, Tolerance::default()).unwrap();
    assert!(r.values_pass() && r.rows_match());
    assert_eq!(r.n_matched, 6);
    let r = compare_dumps_exact(&a, &b, None, Tolerance::default()).unwrap();
    assert_eq!(r.failing_columns(), ["x"]);
    let x = r.columns.iter().find(|c| c.column == "x").unwrap();
    assert_eq!(
        x.worst.as_ref().map(|w| w.0.as_str()),
        Some("step 200 id 1")
    );
    assert_eq!(x.n_fail, 1);
}

#[test]
fn stats_comparison() {
    // Two alternating series with the same mean 1 and a third shifted by 0.5: blocks of two
    // values average to exactly 1, so the blocked errors are tiny and the shift is obvious.
    let n = 256;
    let mk = |shift: f64| -> ThermoBlock {
        ThermoBlock {
            columns: vec!["Step".into(), "Temp".into()],
            rows: (0..n)
                .map(|i| {
                    vec![
                        i as f64,
                        1.0 + shift + if i % 2 == 0 { 0.25 } else { -0.25 },
                    ]
                })
                .collect(),
        }
    };
    let r = compare_stats(&mk(0.0), &mk(0.0), None, 10, 3.0).unwrap();
    assert!(r.pass());
    assert_eq!((r.n_a, r.n_b), (246, 246));
    assert_eq!(r.columns[0].z, 0.0);
    let r = compare_stats(&mk(0.0), &mk(0.5), None, 0, 3.0).unwrap();
    assert_eq!(r.failing_columns(), ["Temp"]);
    assert!(r.columns[0].z < -3.0);
    let e = compare_stats(&mk(0.0), &mk(0.0), None, 255, 3.0).unwrap_err();
    assert!(e.contains("fewer than 2"), "{e}");
}

/// The neighbour-list settings and "Dangerous builds" counts of LAMMPS logs, in both layouts
/// (29Sep2021/2022 and later), as `dpdnl crosscheck` reads them (issue 16, item 11).
#[test]
fn neighbor_summary_of_lammps_logs() {
    let old = neighbor_summary(LOG_2022);
    let delay10 = NeighborSettings {
        every: 1,
        delay: 10,
        check: true,
    };
    assert_eq!(old.settings, [delay10]);
    assert_eq!(old.dangerous, [Some(0)]);
    assert_eq!(delay10.keywords(), "every 1 delay 10 check yes");
    assert!(!delay10.checks_every_step());

    let text = "\
Neighbor list info ...
  update: every = 1 steps, delay = 0 steps, check = yes
  max neighbors/atom: 2000, page size: 100000
Step Temp
0 1
Loop time of 0.1 on 1 procs for 100 steps with 10 atoms
Neighbor list builds = 12
Dangerous builds = 2
Neighbor list info ...
  update: every = 20 steps, delay = 0 steps, check = no
Neighbor list builds = 5
Dangerous builds not checked
Total wall time: 0:00:01
";
    let n = neighbor_summary(text);
    assert_eq!(
        n.settings,
        [
            NeighborSettings {
                every: 1,
                delay: 0,
                check: true
            },
            NeighborSettings {
                every: 20,
                delay: 0,
                check: false
            }
        ]
    );
    assert!(n.settings[0].checks_every_step());
    assert_eq!(n.dangerous, [Some(2), None]);
    assert_eq!((n.dangerous_total(), n.unchecked_runs()), (2, 1));
    // This project's engine prints neither line.
    let engine = neighbor_summary("Step Temp\n0 1\nLoop time of 0.1 on 2 procs for 10 steps\n");
    assert!(engine.settings.is_empty() && engine.dangerous.is_empty());
}
