//! Bonded terms of the standalone engine (issue 29): bond and angle forces are −∇E (finite
//! differences of the styles' own energies), momentum is conserved with bonds through periodic
//! boundaries, a bead-spring chain without thermostat conserves energy under velocity-Verlet,
//! results are bit-identical on 1 and 2 threads, `write_data` round-trips the topology (and,
//! when Debian's `lmp` is installed, LAMMPS reads it and gets the same energies).

use dpdnl::engine::System;
use dpdnl::forces::bonded::{AngleStyle, BondStyle};

mod common;

fn w(s: &str) -> Vec<String> {
    s.split_whitespace().map(String::from).collect()
}

fn data(name: &str) -> String {
    format!(
        "{}/tests/data/crosscheck/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// The polymer solution of the golden cases (harmonic bonds and angles), with `special` and
/// pair coefficients `a gamma0`, `friction`.
fn polymer(special: &str, friction: &str, a: f64, gamma0: f64, extra: &str) -> String {
    format!(
        "units lj\natom_style angle\nbond_style harmonic\nangle_style harmonic\n\
         special_bonds {special}\nread_data {}\nmass 1 1.0\nmass 2 1.5\n\
         pair_style dpd/nonlinear 1.0 1.0 7919 friction {friction}\n\
         pair_coeff * * {a} {gamma0} 0.0\nbond_coeff 1 50.0 0.85\nangle_coeff 1 5.0 150.0\n\
         neighbor 0.5 bin\ntimestep 0.01\nfix 1 all nve\n{extra}",
        data("polymer3d.data")
    )
}

/// [`polymer`] as most tests here run it: `special_bonds lj 0 1 1`, friction cross, a = 25,
/// γ0 = 4.5, then `extra`.
fn plain_polymer(extra: &str) -> String {
    polymer("lj 0 1 1", "cross", 25.0, 4.5, extra)
}

/// The path of `name` in this test process's work directory `label` (created).
fn work_file(label: &str, name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("dpdnl-bonded-{label}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The numbers of a whitespace-separated line.
fn numbers<T: std::str::FromStr>(line: &str) -> Vec<T>
where
    T::Err: std::fmt::Debug,
{
    line.split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

fn run_on(threads: usize, text: &str) -> (Vec<String>, System) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let (lines, sys) = common::run(text).unwrap_or_else(|e| panic!("{e}"));
        (lines, sys.expect("a system"))
    })
}

/// Central difference of f at x with step h.
fn diff(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (f(x + h) - f(x - h)) / (2.0 * h)
}

/// F = −dE/dr: the force on atom 1 is fbond · (x1 − x2), so fbond = −E'(r)/r. Central
/// differences with h = 1e-6 have truncation error ~h² E''' and round-off ~ε E/h ≈ 1e-10 E;
/// 1e-6 relative (plus 1e-8 absolute) is far above both and far below any wrong formula (a
/// missing factor 2 or sign).
#[test]
fn bond_forces_are_minus_the_energy_gradient() {
    let mut harmonic = BondStyle::new(&w("harmonic"), 1).unwrap();
    harmonic.set_coeff(&w("1 50.0 0.85")).unwrap();
    let mut fene = BondStyle::new(&w("fene"), 1).unwrap();
    fene.set_coeff(&w("1 30.0 1.5 1.0 1.0")).unwrap();
    // FENE: inside the WCA range (r < 2^(1/6)), beyond it, and near R0 (below the clamp).
    for (style, rs) in [
        (&harmonic, vec![0.5, 0.85, 0.9, 1.3, 2.0]),
        (&fene, vec![0.85, 0.97, 1.05, 1.2, 1.4]),
    ] {
        for r in rs {
            let (fbond, _, flag) = style.eval(1, r * r);
            assert_eq!(flag, dpdnl::forces::bonded::BondFlag::Ok);
            let de = diff(|r| style.eval(1, r * r).1, r, 1e-6);
            let want = -de / r;
            assert!(
                (fbond - want).abs() <= 1e-6 * want.abs() + 1e-8,
                "{} r = {r}: fbond {fbond}, −E'/r {want}",
                style.form.word()
            );
        }
    }
}

/// The three atoms' forces of an angle are −∂E/∂x of each coordinate (central differences, as
/// above), over random shapes; the middle atom's is −(f1 + f3).
#[test]
fn angle_forces_are_minus_the_energy_gradient() {
    let mut harmonic = AngleStyle::new(&w("harmonic"), 1).unwrap();
    harmonic.set_coeff(&w("1 5.0 110.0")).unwrap();
    let mut cosine = AngleStyle::new(&w("cosine"), 1).unwrap();
    cosine.set_coeff(&w("1 2.0")).unwrap();
    let mut s: u64 = 0x2545_f491_4f6c_dd1d;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s % 1_000_000) as f64 / 1_000_000.0 - 0.5
    };
    for style in [&harmonic, &cosine] {
        for _ in 0..50 {
            let mut x = [[0.0; 3]; 3];
            for p in x.iter_mut() {
                for c in p.iter_mut() {
                    *c = 1.5 * rnd();
                }
            }
            let energy = |x: &[[f64; 3]; 3]| {
                let d1 = [0, 1, 2].map(|c| x[0][c] - x[1][c]);
                let d2 = [0, 1, 2].map(|c| x[2][c] - x[1][c]);
                style.eval(1, d1, d2).2
            };
            let d1 = [0, 1, 2].map(|c| x[0][c] - x[1][c]);
            let d2 = [0, 1, 2].map(|c| x[2][c] - x[1][c]);
            let r1 = d1.iter().map(|v| v * v).sum::<f64>().sqrt();
            let r2 = d2.iter().map(|v| v * v).sum::<f64>().sqrt();
            let cos = d1.iter().zip(&d2).map(|(a, b)| a * b).sum::<f64>() / (r1 * r2);
            // Away from θ = 0, π (LAMMPS floors sin θ there: not differentiable) and from
            // atoms on top of each other.
            if r1 < 0.3 || r2 < 0.3 || cos.abs() > 0.98 {
                continue;
            }
            let (f1, f3, _) = style.eval(1, d1, d2);
            let f2 = [0, 1, 2].map(|c| -(f1[c] + f3[c]));
            for (atom, f) in [(0, f1), (1, f2), (2, f3)] {
                for c in 0..3 {
                    let g = diff(
                        |v| {
                            let mut y = x;
                            y[atom][c] = v;
                            energy(&y)
                        },
                        x[atom][c],
                        1e-6,
                    );
                    assert!(
                        (f[c] + g).abs() <= 1e-6 * g.abs() + 1e-7,
                        "{} atom {atom} axis {c}: force {} vs −∂E {}",
                        style.form.word(),
                        f[c],
                        -g
                    );
                }
            }
        }
    }
}

fn momentum(sys: &System) -> [f64; 3] {
    sys.momentum()
}

/// Bonds and angles through the periodic boundaries (48 beads of the data file lie in other
/// images than their chain's first) with excluded and scaled pairs: forces are applied ± (bonds)
/// and as f1, −(f1 + f3), f3 (angles), so the total momentum after 200 steps of a thermostatted
/// run stays at its start to round-off. |p| per atom is O(1) and each step adds O(N ε) round-off;
/// 1e-9 is generous.
#[test]
fn momentum_is_conserved() {
    for special in ["lj 0 1 1", "lj 0.5 0.75 1"] {
        let text = polymer(special, "cross", 25.0, 4.5, "run 0\n");
        let (_, sys0) = run_on(2, &text);
        let p0 = momentum(&sys0);
        let text = polymer(special, "cross", 25.0, 4.5, "run 200\n");
        let (_, sys) = run_on(2, &text);
        let p = momentum(&sys);
        for c in 0..3 {
            assert!(
                (p[c] - p0[c]).abs() < 1e-9,
                "{special}: momentum {c} from {} to {}",
                p0[c],
                p[c]
            );
        }
    }
}

/// The thermo values of the last run in `lines`: (header, rows).
fn thermo(lines: &[String]) -> (Vec<String>, Vec<Vec<f64>>) {
    let h = lines
        .iter()
        .rposition(|l| l.split_whitespace().next() == Some("Step"))
        .expect("thermo header");
    let header: Vec<String> = lines[h].split_whitespace().map(String::from).collect();
    let rows = lines[h + 1..]
        .iter()
        .take_while(|l| !l.starts_with("Loop time"))
        .filter_map(|l| {
            l.split_whitespace()
                .map(|t| t.parse::<f64>().ok())
                .collect::<Option<Vec<f64>>>()
        })
        .collect();
    (header, rows)
}

/// A bead-spring system without thermostat (γ0 = 0, friction none: only conservative pair,
/// bond and angle forces) is Hamiltonian, and velocity-Verlet keeps its energy within a
/// bounded O(δt²) oscillation. Measured: the largest excursion of etotal from its start over
/// 20 time units is 7.7e-5 of the largest kinetic energy at δt = 0.002 and 1.9e-5 at δt = 0.001
/// (the δt² law: 4.0×). Asserted: below 2e-4 at δt = 0.002 (a drift, e.g. a force that is not
/// −∇E, grows without bound and exceeds it), and at least 2.5× smaller at half the step
/// (allowing for the randomness of the few largest excursions).
#[test]
fn nve_conserves_energy_without_thermostat() {
    let drift = |dt: f64, steps: u32| {
        let text = polymer(
            "lj 0.5 0.75 1",
            "none",
            25.0,
            0.0,
            &format!(
                "timestep {dt}\nthermo 20\nthermo_style custom step ke pe etotal\n\
                 thermo_modify format float %.15g\nrun {steps}\n"
            ),
        );
        let (lines, _) = run_on(2, &text);
        let (header, rows) = thermo(&lines);
        let k = header.iter().position(|h| h == "TotEng").unwrap();
        let ke = header.iter().position(|h| h == "KinEng").unwrap();
        let e0 = rows[0][k];
        let scale = rows.iter().map(|r| r[ke]).fold(0.0, f64::max);
        rows.iter().map(|r| (r[k] - e0).abs()).fold(0.0, f64::max) / scale
    };
    let d2 = drift(0.002, 2000);
    let d1 = drift(0.001, 4000);
    eprintln!("largest |E - E0| / max KE: δt 0.002: {d2:.3e}, δt 0.001: {d1:.3e}");
    assert!(
        d2 < 1e-4,
        "energy excursion {d2:e} of the kinetic scale at δt 0.002"
    );
    assert!(
        d2 / d1 > 2.5,
        "δt 0.002: {d2:e}, δt 0.001: {d1:e}: not O(δt²)"
    );
}

/// Bonded forces are summed serially in topology order after the slab-parallel pair forces,
/// and special pairs are found per batch: the same bits on 1 and 2 threads.
#[test]
fn bit_identical_on_one_and_two_threads() {
    for (special, friction) in [("lj 0 1 1", "cross"), ("lj 0.5 0.75 1", "dot")] {
        let text = polymer(
            special,
            friction,
            25.0,
            4.5,
            "thermo 10\nthermo_style custom step temp press pe ebond eangle\n\
             thermo_modify format float %.17g\nrun 100\n",
        );
        let (l1, s1) = run_on(1, &text);
        let (l2, s2) = run_on(2, &text);
        assert_eq!(
            common::state_by_tag(&s1),
            common::state_by_tag(&s2),
            "{special}"
        );
        assert_eq!(thermo(&l1), thermo(&l2), "{special}");
    }
}

/// `write_data` then `read_data` gives the same system: positions (wrapped, with image flags),
/// velocities, molecule ids, bonds, angles and the coefficients of the data file's sections.
#[test]
fn write_data_round_trips_the_topology() {
    let file = work_file("round", "round.data");
    let text = plain_polymer(&format!("run 20\nwrite_data {}\n", file.display()));
    let (_, a) = run_on(2, &text);
    let again = format!(
        "units lj\natom_style angle\nbond_style harmonic\nangle_style harmonic\nread_data {}\n",
        file.display()
    );
    let (_, b) = run_on(1, &again);
    // write_data wraps positions into the box (counting the crossings in the image flags),
    // as LAMMPS does; velocities and molecule ids are written as they are.
    let by_tag = |s: &System, wrap: bool| {
        let mut v: Vec<_> = (0..s.atoms.len())
            .map(|i| {
                let (mut x, mut im) = (s.atoms.x[i], s.atoms.image[i]);
                if wrap {
                    s.bx.wrap(&mut x, &mut im);
                }
                (
                    s.atoms.tag[i],
                    s.atoms.mol_of(i),
                    x.map(f64::to_bits),
                    im,
                    s.atoms.v[i].map(f64::to_bits),
                )
            })
            .collect();
        v.sort();
        v
    };
    let (va, vb) = (by_tag(&a, true), by_tag(&b, false));
    let differ = va.iter().zip(&vb).filter(|(p, q)| p != q).count();
    assert!(va.len() == vb.len() && differ == 0, "{differ} atoms differ");
    let (ta, tb) = (a.topo.as_ref().unwrap(), b.topo.as_ref().unwrap());
    assert_eq!(ta.bonds, tb.bonds);
    assert_eq!(ta.angles, tb.angles);
    assert_eq!(ta.bonds.len(), 216);
    assert_eq!(ta.bond_style, tb.bond_style);
    assert_eq!(ta.angle_style, tb.angle_style);
    // Debian's LAMMPS reads the file: same bond and angle energies at step 0 (1e-12).
    let Ok(out) = std::process::Command::new("lmp")
        .current_dir(file.parent().expect("the work directory"))
        .args(["-log", "none"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .and_then(|mut c| {
            use std::io::Write;
            c.stdin.take().unwrap().write_all(
                b"units lj\natom_style angle\nbond_style harmonic\nangle_style harmonic\n\
                  read_data round.data\npair_style zero 1.0\npair_coeff * *\n\
                  thermo_style custom step ebond eangle\nthermo_modify format float %.17g\nrun 0\n",
            )?;
            c.wait_with_output()
        })
    else {
        eprintln!("lmp not found: LAMMPS half of the write_data check skipped");
        return;
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    let row = stdout
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("Step"))
        .nth(1)
        .unwrap_or_else(|| panic!("no thermo row from lmp:\n{stdout}"));
    let v: Vec<f64> = numbers(row);
    let n = a.atoms.len() as f64;
    let check = format!(
        "units lj\natom_style angle\nbond_style harmonic\nangle_style harmonic\nread_data {}\n\
         mass * 1.0\npair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 0.0 0.0 0.0\n\
         thermo_style custom step ebond eangle\nthermo_modify format float %.17g\nrun 0\n",
        file.display()
    );
    let (lines, _) = run_on(1, &check);
    let (_, rows) = thermo(&lines);
    for (k, what) in [(1, "ebond"), (2, "eangle")] {
        assert!(
            (rows[0][k] - v[k]).abs() <= 1e-12 * v[k].abs(),
            "{what}: standalone {} LAMMPS {} (N = {n})",
            rows[0][k],
            v[k]
        );
    }
}

/// `compute chunk/atom molecule` with `fix ave/chunk`: one chunk per molecule id 1 … 24 (the
/// solvent, molecule 0, in none), each chain's 10 beads counted, density/number over the whole
/// box (LAMMPS's volume for chunks that are not bins), mass averaged per atom 1.5; and
/// `compute gyration` is the square root of its tensor's trace, computed here from the
/// unwrapped positions.
#[test]
fn chunks_by_molecule_and_gyration() {
    let file = work_file("chunk", "chunk.out");
    let text = plain_polymer(&format!(
        "compute mol all chunk/atom molecule\ncompute rg all gyration\n\
             fix c all ave/chunk 5 2 10 mol density/number mass file {}\n\
             thermo 10\nthermo_style custom step c_rg c_rg[1] c_rg[2] c_rg[3]\n\
             thermo_modify format float %.17g\nrun 10\n",
        file.display()
    ));
    let (lines, sys) = run_on(2, &text);
    let out = std::fs::read_to_string(&file).unwrap();
    let body: Vec<&str> = out.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(body[0].split_whitespace().nth(1), Some("24"), "{out}");
    let vol = 8.0f64.powi(3);
    for (k, row) in body[1..25].iter().enumerate() {
        let v: Vec<f64> = numbers(row);
        assert_eq!(v[0], (k + 1) as f64);
        assert_eq!(v[1], 10.0, "{row}");
        // Printed with %g: 6 significant digits.
        assert!((v[2] - 10.0 / vol).abs() < 5e-6 * 10.0 / vol, "{row}");
        assert!((v[3] - 1.5).abs() < 1e-12, "{row}");
    }
    let (_, rows) = thermo(&lines);
    let last = rows.last().unwrap();
    // The tensor of the final state, independently.
    let n = sys.atoms.len();
    let mass = |i: usize| if sys.atoms.typ[i] == 2 { 1.5 } else { 1.0 };
    let u = |i: usize| sys.bx.unwrap(sys.atoms.x[i], sys.atoms.image[i]);
    let mtot: f64 = (0..n).map(mass).sum();
    let cm = [0, 1, 2].map(|c| (0..n).map(|i| mass(i) * u(i)[c]).sum::<f64>() / mtot);
    let g = [0, 1, 2].map(|c| {
        (0..n)
            .map(|i| mass(i) * (u(i)[c] - cm[c]).powi(2))
            .sum::<f64>()
            / mtot
    });
    for c in 0..3 {
        assert!(
            (last[2 + c] - g[c]).abs() < 1e-10 * g[c],
            "{c}: {last:?} {g:?}"
        );
    }
    assert!((last[1] - (g[0] + g[1] + g[2]).sqrt()).abs() < 1e-10 * last[1]);
}

/// Bonds through the sheared boundary of a Lees–Edwards box (`change_box all triclinic`, `fix
/// deform … remap v`): every bond and angle arm takes the sliding-brick minimum image, so after
/// the image has slid by more than a box length (γ̇ L_y t = 0.5 · 8 · 4.5 = 18 > L_x = 8) no
/// bond is stretched: the longest stays below 1.5 (bonds of r0 = 0.85, K = 50 at kT ≈ 1
/// fluctuate by ~0.1). A bond joined through the wrong image would be O(L) = 8 long and its
/// energy K (8 − 0.85)² ≈ 2600. Also bit-identical on 1 and 2 threads. The second run's
/// set-up, in the tilted box (xy ≠ 0, after flips), finds the image flags consistent (x + ix
/// L_x + iy xy unwraps every chain) and every bonded partner's image within LAMMPS's ghost
/// shell of the tilted cell: no "Inconsistent image flags", no "Bond atoms … missing".
#[test]
fn bonds_through_the_sheared_boundary() {
    let text = polymer(
        "lj 0.5 0.75 1",
        "cross",
        25.0,
        4.5,
        "change_box all triclinic\nfix 3 all deform 1 xy erate 0.5 remap v\n\
         thermo 50\nthermo_style custom step temp ebond eangle xy\n\
         thermo_modify format float %.17g\nrun 380\nrun 70\n",
    );
    let (l1, s1) = run_on(1, &text);
    let (l2, s2) = run_on(2, &text);
    assert!(
        !l1.iter().any(|l| l.contains("Inconsistent image flags")),
        "{l1:#?}"
    );
    assert_eq!(common::state_by_tag(&s1), common::state_by_tag(&s2));
    assert_eq!(thermo(&l1), thermo(&l2));
    let tri = s1.tri.as_ref().expect("triclinic");
    let le = tri.le;
    let idx: std::collections::HashMap<u32, usize> =
        (0..s1.atoms.len()).map(|i| (s1.atoms.tag[i], i)).collect();
    let mut longest: f64 = 0.0;
    let mut crossing = 0;
    for b in &s1.topo.as_ref().unwrap().bonds {
        let (i, j) = (idx[&b.atoms[0]], idx[&b.atoms[1]]);
        let (xi, xj) = (s1.atoms.x[i], s1.atoms.x[j]);
        let raw = [xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]];
        let (d, _) = s1.bx.min_image_le(raw, &le);
        if (raw[1] - d[1]).abs() > 1.0 {
            crossing += 1;
        }
        longest = longest.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
    }
    assert!(
        crossing > 0,
        "no bond through the y boundary: the test tests nothing"
    );
    assert!(longest < 1.5, "longest bond {longest}");
    let (header, rows) = thermo(&l1);
    let xy = header.iter().position(|h| h == "Xy").unwrap();
    assert!(
        rows[0][xy].abs() > 0.5,
        "the second run starts tilted: {rows:?}"
    );
    let eb = header.iter().position(|h| h == "E_bond").unwrap();
    // ebond per atom (norm yes): 216 bonds of ~kT/2 each over 1536 atoms ≈ 0.07.
    assert!(rows.iter().all(|r| r[eb] < 0.5), "{rows:?}");
}

/// `compute gyration/chunk` over `chunk/atom molecule`, averaged by `fix ave/time … mode
/// vector`: one R_g per chain, equal to the value computed here from the unwrapped positions
/// (a single sample, so the file holds the instantaneous values, printed with %g).
#[test]
fn gyration_per_molecule() {
    let file = work_file("rgc", "rg.out");
    let text = plain_polymer(&format!(
        "compute mol all chunk/atom molecule\ncompute rgc all gyration/chunk mol\n\
             fix r all ave/time 20 1 20 c_rgc mode vector file {}\nrun 20\n",
        file.display()
    ));
    let (_, sys) = run_on(2, &text);
    let out = std::fs::read_to_string(&file).unwrap();
    // Blocks at steps 0 and 20 ("STEP 24", then 24 rows): the last one is the final state.
    let lines: Vec<&str> = out.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 50, "{out}");
    assert_eq!(lines[25], "20 24");
    let rows: Vec<Vec<f64>> = lines[26..].iter().map(|l| numbers(l)).collect();
    let a = &sys.atoms;
    for (c, row) in rows.iter().enumerate() {
        let members: Vec<usize> = (0..a.len())
            .filter(|&i| a.mol_of(i) == c as u32 + 1)
            .collect();
        assert_eq!(members.len(), 10);
        let u: Vec<[f64; 3]> = members
            .iter()
            .map(|&i| sys.bx.unwrap(a.x[i], a.image[i]))
            .collect();
        // Equal masses within a chain: the plain centroid.
        let cm = [0, 1, 2].map(|k| u.iter().map(|p| p[k]).sum::<f64>() / 10.0);
        let rg = (u
            .iter()
            .map(|p| (0..3).map(|k| (p[k] - cm[k]).powi(2)).sum::<f64>())
            .sum::<f64>()
            / 10.0)
            .sqrt();
        assert_eq!(row[0], (c + 1) as f64);
        assert!(
            (row[1] - rg).abs() < 5e-6 * rg,
            "chain {}: {} vs {rg}",
            c + 1,
            row[1]
        );
    }
}

/// `dump custom … mol` writes each atom's molecule id (0 for the solvent), and an atomic
/// system refuses the column.
#[test]
fn dump_writes_molecule_ids() {
    let file = work_file("dump", "mol.dump");
    let text = plain_polymer(&format!(
        "dump d all custom 1 {} id mol type\ndump_modify d sort id\nrun 0\n",
        file.display()
    ));
    run_on(1, &text);
    let out = std::fs::read_to_string(&file).unwrap();
    let rows: Vec<Vec<u32>> = out
        .lines()
        .skip_while(|l| !l.starts_with("ITEM: ATOMS"))
        .skip(1)
        .map(numbers)
        .collect();
    assert_eq!(rows.len(), 1536);
    // The data file: chain k (1..24) holds atoms 10(k-1)+1 … 10k, all of type 2; then solvent.
    for r in &rows {
        let want = if r[0] <= 240 { (r[0] - 1) / 10 + 1 } else { 0 };
        assert_eq!(r[1], want, "{r:?}");
        assert_eq!(r[2], if r[0] <= 240 { 2 } else { 1 });
    }
    let atomic = "units lj\nregion b block 0 5 0 5 0 5\ncreate_box 1 b\n\
                  dump d all custom 1 x.dump id mol\n";
    let e = common::run(atomic).unwrap_err();
    assert!(e.message.contains("no molecule ids"), "{e}");
}

/// A data file as structure generators write it (issue 42): the polymer solution of
/// `polymer3d.data` with wrapped coordinates and no image flags (`polymer3d_wrapped.data`, the
/// chains through the boundaries). Every run's set-up warns "Inconsistent image flags", as
/// LAMMPS's `Domain::image_check` does (never for the file with the flags that unwrap the
/// chains), and the bonds and angles use the minimum image: the two files give the same
/// trajectory, bit for bit, and the same thermo apart from what reads the image flags
/// (`compute gyration`, which unwraps the chains by them, as LAMMPS's does).
#[test]
fn generator_style_data_file_warns_and_bonds_by_the_minimum_image() {
    let script = |file: &str| {
        polymer("lj 0 1 1", "dot", 25.0, 4.5, "").replace("polymer3d.data", file)
            + "compute rg all gyration\nthermo 10\n\
               thermo_style custom step temp press pxy pe ebond eangle c_rg\n\
               thermo_modify format float %.17g\nrun 20\nrun 20\n"
    };
    let (lines_w, sys_w) = run_on(2, &script("polymer3d_wrapped.data"));
    let (lines_f, sys_f) = run_on(2, &script("polymer3d.data"));
    let warned = |lines: &[String]| {
        lines
            .iter()
            .filter(|l| *l == "WARNING: Inconsistent image flags")
            .count()
    };
    assert_eq!(warned(&lines_w), 2, "one warning per run:\n{lines_w:#?}");
    assert_eq!(warned(&lines_f), 0, "{lines_f:#?}");
    assert_eq!(common::state_by_tag(&sys_w), common::state_by_tag(&sys_f));
    let (head, rows_w) = thermo(&lines_w);
    let (_, rows_f) = thermo(&lines_f);
    let rg = head.iter().position(|h| h == "c_rg").expect("c_rg");
    assert_eq!(rows_w.len(), 3);
    for (w, f) in rows_w.iter().zip(&rows_f) {
        assert_eq!(w[..rg], f[..rg], "thermo before c_rg");
        assert_ne!(w[rg], f[rg], "R_g reads the image flags");
    }
}

/// A bonded partner LAMMPS cannot resolve (issue 42): the first atom of a bond holds the atoms
/// of the box and their ghost images within the ghost cut-off (pair cut-off + skin = 1.3)
/// beyond its faces, and atom 4's nearest image to atom 3 (2.4 apart) lies 1.4 beyond x_hi.
/// The standalone engine refuses the bond ("Bond atoms 3 4 missing"), and accepts it with
/// `comm_modify cutoff 2.5`, where the image is a ghost. LAMMPS (`build/lmp_dpdnl`, when
/// built): on one rank it takes the atom itself, 7.6 away, for the bond (E_bond of 2.4 and 7.6
/// told apart), on two ranks split along x it stops with "Bond atom missing", and with the
/// larger cut-off it bonds by the minimum image, with the standalone engine's energy.
#[test]
fn unresolvable_bond_is_lammps_bond_atoms_missing() {
    let file = format!(
        "{}/tests/data/bad_input/bond_unresolved.data",
        env!("CARGO_MANIFEST_DIR")
    );
    let script = |extra: &str| {
        format!(
            "units lj\natom_style angle\ncomm_modify vel yes\n{extra}read_data {file}\n\
             mass * 1.0\npair_style dpd/nonlinear 1.0 1.0 5\npair_coeff * * 25.0 4.5 0.0\n\
             bond_style harmonic\nbond_coeff 1 50.0 0.9\nangle_style harmonic\n\
             angle_coeff 1 5.0 150.0\nthermo_style custom step ebond\nthermo_modify norm no \
             format float %.17g\nrun 0\n"
        )
    };
    // E_bond = 50 (r − 0.9)² over the bonds 0.9, 1.0 and 2.4 (minimum image) or 7.6.
    let ebond = |r: f64| 50.0 * (0.1f64.powi(2) + (r - 0.9f64).powi(2));
    let e = common::run(&script("")).expect_err("refused");
    assert!(
        e.message
            .starts_with("Bond atoms 3 4 missing at step 0: the nearest image of atom 4")
            && e.message.contains("ghost cut-off 1.3"),
        "{e}"
    );
    let (lines, _) = common::run(&script("comm_modify cutoff 2.5\n")).expect("runs");
    let (_, rows) = thermo(&lines);
    assert!((rows[0][1] - ebond(2.4)).abs() < 1e-9, "{rows:?}");
    let lmp = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("build/lmp_dpdnl");
    if !lmp.is_file() {
        assert!(
            std::env::var_os("DPDNL_REQUIRE_LAMMPS").is_none(),
            "DPDNL_REQUIRE_LAMMPS is set but {} is missing",
            lmp.display()
        );
        eprintln!("SKIPPED: LAMMPS half: {} not built", lmp.display());
        return;
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bond_unresolved");
    std::fs::create_dir_all(&dir).unwrap();
    let lammps = |name: &str, text: String, ranks: u32| {
        std::fs::write(dir.join(name), text).unwrap();
        let mut cmd = if ranks == 1 {
            std::process::Command::new(&lmp)
        } else {
            let mut c = std::process::Command::new("mpirun");
            c.args(["--oversubscribe", "--allow-run-as-root", "-np", "2"])
                .arg(&lmp);
            c
        };
        let out = cmd
            .current_dir(&dir)
            .env("OMP_NUM_THREADS", "1")
            .args(["-in", name, "-log", "none"])
            .output()
            .expect("LAMMPS starts");
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    };
    let ebond_of = |out: &str| -> f64 {
        let lines: Vec<String> = out.lines().map(String::from).collect();
        thermo(&lines).1[0][1]
    };
    let one = lammps("in.one", script(""), 1);
    assert!(!one.contains("ERROR"), "{one}");
    assert!((ebond_of(&one) - ebond(7.6)).abs() < 1e-9, "{one}");
    let big = lammps("in.big", script("comm_modify cutoff 2.5\n"), 1);
    assert_eq!(ebond_of(&big), rows[0][1], "{big}");
    let two = lammps("in.two", script("processors 2 1 1\n"), 2);
    assert!(
        two.contains("ERROR") && two.contains("Bond atom") && two.contains("missing"),
        "{two}"
    );
}
