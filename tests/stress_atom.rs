//! `compute stress/atom` in the standalone engine: the per-atom stress × volume sums over the
//! atoms to −(P_ab V) of the matching pressure (kinetic part + the virial of every force), in a
//! DPD liquid and in a polymer solution with bonds and angles; the per-atom tally leaves the
//! run's bits unchanged; its refusals. (Its agreement with LAMMPS atom by atom is the golden case
//! tests/data/crosscheck/in.stress_atom_3d.)

mod common;

use dpdnl::engine::{KineticBias, StressParts, System};

fn data(name: &str) -> String {
    format!(
        "{}/tests/data/crosscheck/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn dpd_script(extra: &str) -> String {
    format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\nread_data {}\nmass 1 1.0\nmass 2 1.5\n\
         pair_style dpd/nonlinear 1.0 1.0 7919 friction dot noise corrected\n\
         pair_coeff 1 1 8.0 4.5 0.5\npair_coeff 1 2 10.0 4.0 0.5\npair_coeff 2 2 6.0 3.0 0.5\n\
         neighbor 1.0 bin\ntimestep 0.01\nfix 1 all nve\n{extra}run 50\n",
        data("dpd3d.data")
    )
}

fn polymer_script(extra: &str) -> String {
    format!(
        "units lj\natom_style angle\ncomm_modify vel yes cutoff 3.0\nbond_style harmonic\n\
         angle_style harmonic\nspecial_bonds lj 0.0 1.0 1.0\nread_data {}\nmass 1 1.0\nmass 2 1.5\n\
         pair_style dpd/nonlinear 1.0 1.0 7919 friction dot noise corrected\n\
         pair_coeff * * 25.0 4.5 0.5\nbond_coeff 1 50.0 0.85\nangle_coeff 1 5.0 150.0\n\
         neighbor 1.0 bin\ntimestep 0.01\nfix 1 all nve\n{extra}run 50\n",
        data("polymer3d.data")
    )
}

const ALL: StressParts = StressParts {
    ke: Some(KineticBias::None),
    pair: true,
    bond: true,
    angle: true,
};

fn sum(s: &[[f64; 6]]) -> [f64; 6] {
    let mut t = [0.0; 6];
    for r in s {
        for c in 0..6 {
            t[c] += r[c];
        }
    }
    t
}

/// Σ_i s_i,ab against −P_ab V of `compute temp`'s pressure: equal to round-off (the same
/// products summed in another order), checked at 1e-12 of the largest component.
fn assert_sums_to_pressure(sys: &System, parts: StressParts) {
    let s = sum(&sys.stress_atom(parts).expect("per-atom virial tallied"));
    let th = sys.thermo();
    let pv: Vec<f64> = th.p_tensor.iter().map(|p| -p * th.vol).collect();
    let scale = pv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for c in 0..6 {
        assert!(
            (s[c] - pv[c]).abs() <= 1e-12 * scale,
            "component {c}: Σ per-atom {} vs −P V {} (scale {scale})",
            s[c],
            pv[c]
        );
    }
}

#[test]
fn dpd_per_atom_stress_sums_to_the_pressure() {
    let (_, sys) = common::run(&dpd_script("compute s all stress/atom NULL\n")).unwrap();
    assert_sums_to_pressure(&sys.unwrap(), ALL);
}

#[test]
fn bonded_per_atom_stress_sums_to_the_pressure() {
    let (_, sys) = common::run(&polymer_script("compute s all stress/atom NULL\n")).unwrap();
    let sys = sys.unwrap();
    assert_sums_to_pressure(&sys, ALL);
    // The parts add up to the whole, and the bonds and angles carry a virial of their own.
    let part = |ke, pair, bond, angle| {
        sum(&sys
            .stress_atom(StressParts {
                ke,
                pair,
                bond,
                angle,
            })
            .unwrap())
    };
    let (k, p, b, a) = (
        part(Some(KineticBias::None), false, false, false),
        part(None, true, false, false),
        part(None, false, true, false),
        part(None, false, false, true),
    );
    let all = part(Some(KineticBias::None), true, true, true);
    for c in 0..6 {
        let t = k[c] + p[c] + b[c] + a[c];
        assert!((t - all[c]).abs() <= 1e-12 * all[c].abs().max(1.0), "{c}");
    }
    assert!(
        b[0].abs() > 1.0 && a[0].abs() > 1e-3,
        "bond {b:?} angle {a:?}"
    );
}

/// The kinetic part with `compute temp/partial 1 0 1`'s bias: vy left out, so the yy and xy
/// components of the per-atom stress are the virial's alone.
#[test]
fn partial_bias_removes_vy_from_the_kinetic_part() {
    let (_, sys) = common::run(&dpd_script(
        "compute tp all temp/partial 1 0 1\ncompute s all stress/atom tp\n",
    ))
    .unwrap();
    let sys = sys.unwrap();
    let with = |bias| {
        sys.stress_atom(StressParts {
            ke: Some(bias),
            ..ALL
        })
        .unwrap()
    };
    let (biased, plain) = (
        with(KineticBias::Partial([true, false, true])),
        with(KineticBias::None),
    );
    let virial = sys.stress_atom(StressParts { ke: None, ..ALL }).unwrap();
    for i in 0..sys.atoms.len() {
        assert_eq!(biased[i][1], virial[i][1]);
        assert_eq!(biased[i][3], virial[i][3]);
        assert_eq!(biased[i][0], plain[i][0]);
    }
}

/// The per-atom tally is out of the force loop: a run with a stress/atom compute has the same
/// positions and velocities, bit for bit, as one without.
#[test]
fn the_tally_leaves_the_run_unchanged() {
    let state = |s: &System| -> Vec<u64> {
        let a = &s.atoms;
        (0..a.len())
            .flat_map(|i| {
                a.x[i]
                    .iter()
                    .chain(&a.v[i])
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    for script in [dpd_script as fn(&str) -> String, polymer_script] {
        let (_, with) = common::run(&script(
            "compute s all stress/atom NULL\ncompute r all reduce sum c_s[1]\n\
             thermo_style custom step c_r\nthermo 10\n",
        ))
        .unwrap();
        let (_, without) = common::run(&script("")).unwrap();
        assert_eq!(state(&with.unwrap()), state(&without.unwrap()));
    }
}

#[test]
fn refusals_name_what_is_wrong() {
    let refused = |extra: &str| {
        common::run(&dpd_script(extra))
            .expect_err("refused")
            .to_string()
    };
    assert!(
        refused("compute s all stress/atom NULL bogus\n")
            .contains("unknown compute stress/atom keyword 'bogus'")
    );
    assert!(
        refused("compute s all stress/atom nope\n")
            .contains("temperature compute 'nope' does not exist")
    );
    assert!(refused("group g type 1\ncompute s g stress/atom NULL\n").contains("group all only"));
    assert!(
        refused("compute s all stress/atom NULL\ncompute r all reduce sum c_s\n")
            .contains("has 6 per-atom columns")
    );
    assert!(
        refused("compute s all stress/atom NULL\ncompute r all reduce sum c_s[7]\n")
            .contains("[7] is out of range")
    );
}
