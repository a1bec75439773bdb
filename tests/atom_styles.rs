//! `atom_style charge`, `mdpd` and `hybrid` (issue 56, item 2): their data files are read in
//! LAMMPS's columns, their extra columns carried through `write_data`, and the files each engine
//! writes are read by the other (LAMMPS: `build/lmp_dpdnl`, skipped without it unless
//! DPDNL_REQUIRE_LAMMPS is set; Debian's LAMMPS has `charge` and `hybrid`, not `mdpd`).

mod plugin_support;

use dpdnl::input::{Collect, Interpreter, Options};
use dpdnl::io::data::{AtomColumns, parse_data_columns};
use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn words(s: &str) -> Vec<String> {
    s.split_whitespace().map(String::from).collect()
}

/// A data file of 4 atoms in a 4³ box, its `Atoms` lines given (`bonds`: one bond type, bond
/// 1-2).
fn data_file(hint: &str, atoms: &str, bonds: bool) -> String {
    let (head, tail) = if bonds {
        ("1 bonds\n1 bond types\n", "\nBonds\n\n1 1 1 2\n")
    } else {
        ("", "")
    };
    format!(
        "LAMMPS data file\n\n4 atoms\n2 atom types\n{head}\n0 4 xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n\n\
         Masses\n\n1 1\n2 2\n\nAtoms # {hint}\n\n{atoms}\nVelocities\n\n1 0.5 0 0\n2 0 0.25 0\n\
         3 0 0 -0.125\n4 0 0 0\n{tail}"
    )
}

/// Runs `script` in the standalone engine, each `@` replaced by `dir/` (the tests run in
/// parallel threads: no change of the current directory); the error, if any.
fn standalone(dir: &Path, script: &str) -> Result<(), String> {
    let mut c = Collect::default();
    let mut it = Interpreter::new(&mut c, &Options::default()).map_err(|e| e.to_string())?;
    let script = script.replace('@', &format!("{}/", dir.display()));
    it.run_text(&script, "in.test").map_err(|e| e.to_string())
}

const MDPD: &str = "1 1 5.5 0.5 0.5 0.5 0 0 0\n2 2 6.25 1.5 0.5 0.5 0 0 0\n\
                    3 1 7 2.5 2.5 2.5 0 1 0\n4 2 0 3.5 3.5 3.5 0 0 0\n";
const HYBRID: &str = "1 1 0.5 0.5 0.5 1 0 0 0 0\n2 2 1.5 0.5 0.5 1 0 0 0 0\n\
                      3 1 2.5 2.5 2.5 2 0 0 1 0\n4 2 3.5 3.5 3.5 2 0 0 0 0\n";

/// `read_data` then `write_data` of an `mdpd` file (the rho column carried) and of a `hybrid
/// bond charge` one (molecules, charges, bonds): the file written reads back equal to the
/// one read, rho included; an atom created later gets rho 0.
#[test]
fn extra_columns_are_carried_through_write_data() {
    let dir = scratch("atom_styles_carried");
    for (style, atoms, bonds) in [("mdpd", MDPD, false), ("hybrid bond charge", HYBRID, true)] {
        let hint = style.split_whitespace().next().unwrap_or("");
        std::fs::write(dir.join("in.data"), data_file(hint, atoms, bonds)).expect("data");
        let bond_style = if bonds {
            "bond_style harmonic\nbond_coeff 1 10 1\n"
        } else {
            ""
        };
        standalone(
            &dir,
            &format!("atom_style {style}\nread_data @in.data\n{bond_style}write_data @out.data\n"),
        )
        .unwrap_or_else(|e| panic!("{style}: {e}"));
        let c = AtomColumns::parse(&words(style)).expect("columns");
        let read = |f: &str| {
            let text = std::fs::read_to_string(dir.join(f)).expect("file");
            let mut d = parse_data_columns(&text, f, &c).unwrap_or_else(|e| panic!("{e}\n{text}"));
            d.coeffs.clear();
            d.atoms_hint = None;
            d
        };
        let (a, b) = (read("in.data"), read("out.data"));
        assert_eq!(a.atoms, b.atoms, "{style}");
        assert_eq!(a.extra, b.extra, "{style}");
        assert_eq!(a.mol, b.mol, "{style}");
        assert_eq!(a.velocities, b.velocities, "{style}");
        assert_eq!(a.bonds, b.bonds, "{style}");
    }
    std::fs::write(dir.join("in.data"), data_file("mdpd", MDPD, false)).expect("data");
    standalone(
        &dir,
        "atom_style mdpd\nread_data @in.data\ncreate_atoms 1 single 1 1 1\nwrite_data @out.data\n",
    )
    .expect("runs");
    let c = AtomColumns::parse(&words("mdpd")).expect("columns");
    let text = std::fs::read_to_string(dir.join("out.data")).expect("file");
    let d = parse_data_columns(&text, "out.data", &c).expect("reads");
    let rho: Vec<f64> = d.extra.iter().map(|e| e.rho).collect();
    assert_eq!(rho, [5.5, 6.25, 7.0, 0.0, 0.0]);
}

/// The refusals: a non-zero charge (file and line), `sphere` at `atom_style`, a sub-style named
/// twice.
#[test]
fn atom_style_refusals() {
    let dir = scratch("atom_styles_refused");
    let charged = "1 1 0 0.5 0.5 0.5\n2 2 0.5 1.5 0.5 0.5\n3 1 0 2.5 2.5 2.5\n4 2 0 3.5 3.5 3.5\n";
    std::fs::write(dir.join("q.data"), data_file("charge", charged, false)).expect("data");
    let e = standalone(&dir, "atom_style charge\nread_data @q.data\n").unwrap_err();
    assert!(e.contains("q.data:18: atom 2 has charge 0.5"), "{e}");
    let e = standalone(&dir, "atom_style sphere\n").unwrap_err();
    assert!(
        e.contains("in.test:1: atom_style: atom_style sphere: per-atom masses"),
        "{e}"
    );
    let e = standalone(&dir, "atom_style hybrid charge charge\n").unwrap_err();
    assert!(
        e.contains("cannot use same atom style twice ('charge')"),
        "{e}"
    );
}

/// The files of `charge` and `hybrid bond charge` the standalone engine writes are read by
/// LAMMPS, and LAMMPS's `write_data` of them reads back here to the same atoms, molecules,
/// velocities and bonds.
#[test]
fn lammps_reads_what_the_standalone_engine_writes() {
    let Some(lmp) = plugin_support::lmp_dpdnl("atom style data files") else {
        return;
    };
    let dir = scratch("atom_styles_lammps");
    let charge = "1 1 0 0.5 0.5 0.5 0 0 0\n2 2 0 1.5 0.5 0.5 0 0 0\n\
                  3 1 0 2.5 2.5 2.5 0 1 0\n4 2 0 3.5 3.5 3.5 0 0 0\n";
    for (style, atoms, bonds) in [
        ("charge", charge, false),
        ("hybrid bond charge", HYBRID, true),
    ] {
        let hint = style.split_whitespace().next().unwrap_or("");
        std::fs::write(dir.join("in.data"), data_file(hint, atoms, bonds)).expect("data");
        let bond_style = if bonds {
            "bond_style harmonic\nbond_coeff 1 10 1\n"
        } else {
            ""
        };
        standalone(
            &dir,
            &format!("atom_style {style}\nread_data @in.data\n{bond_style}write_data @s.data\n"),
        )
        .unwrap_or_else(|e| panic!("{style}: {e}"));
        let script = format!(
            "atom_style {style}\n{bond_style_pre}read_data s.data\n{bond_coeff}write_data l.data nocoeff\n",
            bond_style_pre = if bonds { "bond_style harmonic\n" } else { "" },
            bond_coeff = if bonds { "bond_coeff 1 10 1\n" } else { "" },
        );
        std::fs::write(dir.join("in.lmp"), script).expect("script");
        let out = Command::new(&lmp)
            .current_dir(&dir)
            .args(["-in", "in.lmp", "-log", "none", "-screen", "none"])
            .output()
            .expect("run LAMMPS");
        assert!(
            out.status.success() && dir.join("l.data").is_file(),
            "{style}: LAMMPS failed: {}",
            String::from_utf8_lossy(&out.stdout)
        );
        let c = AtomColumns::parse(&words(style)).expect("columns");
        let read = |f: &str| {
            let text = std::fs::read_to_string(dir.join(f)).expect("file");
            let mut d = parse_data_columns(&text, f, &c).unwrap_or_else(|e| panic!("{e}\n{text}"));
            let mut order: Vec<usize> = (0..d.atoms.len()).collect();
            order.sort_by_key(|&k| d.atoms[k].0);
            d.atoms = order.iter().map(|&k| d.atoms[k]).collect();
            if !d.mol.is_empty() {
                d.mol = order.iter().map(|&k| d.mol[k]).collect();
            }
            d.velocities.sort_by_key(|v| v.0);
            d
        };
        let (a, b) = (read("s.data"), read("l.data"));
        assert_eq!(a.atoms, b.atoms, "{style}");
        assert_eq!(a.mol, b.mol, "{style}");
        assert_eq!(a.velocities, b.velocities, "{style}");
        assert_eq!(a.bonds, b.bonds, "{style}");
        let _ = std::fs::remove_file(dir.join("l.data"));
    }
}
