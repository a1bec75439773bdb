//! LAMMPS data files (`read_data` / `write_data`) for `atom_style atomic`.
//!
//! Supported: the header keywords `atoms`, `atom types`, `xlo xhi`, `ylo yhi`, `zlo zhi`,
//! `xy xz yz` (a triclinic box tilted in xy only: xz = yz = 0) (and the counts of
//! bonds/angles/… when they are 0); the sections `Masses`, `Atoms` (`id type x y z`
//! with optional image flags `ix iy iz`) and `Velocities` (`id vx vy vz`). Anything else is an
//! error naming the file and line. Real numbers (box bounds, masses, coordinates, velocities)
//! must be finite: `nan`, `inf` or `1e999` is an error naming the file, line and column.

use std::fmt::Write as _;

/// The content of a data file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DataFile {
    /// Number of atom types.
    pub ntypes: usize,
    /// Box lower corner.
    pub lo: [f64; 3],
    /// Box upper corner.
    pub hi: [f64; 3],
    /// The tilt factors `[xy, xz, yz]` of a triclinic box (xz = yz = 0), None: orthogonal.
    pub tilt: Option<[f64; 3]>,
    /// Masses by type (1-based, index 0 unused); None where the file gives none.
    pub masses: Vec<Option<f64>>,
    /// Atoms: (tag, type, x, image).
    pub atoms: Vec<(u32, u32, [f64; 3], [i32; 3])>,
    /// Velocities by tag, in file order (empty when the file has no Velocities section).
    pub velocities: Vec<(u32, [f64; 3])>,
}

fn strip_comment(line: &str) -> &str {
    match line.find('#') {
        Some(p) => &line[..p],
        None => line,
    }
}

/// Token `i` of a line read as a `T` (counts, types, ids, image flags); errors name the column.
fn num<T: std::str::FromStr>(
    toks: &[&str],
    i: usize,
    what: &str,
    ctx: &dyn Fn(String) -> String,
) -> Result<T, String> {
    toks[i].parse::<T>().map_err(|_| {
        ctx(format!(
            "column {}: expected {what}, found '{}'",
            i + 1,
            toks[i]
        ))
    })
}

/// Token `i` of a line read as a finite real number: NaN and infinities (`nan`, `inf`,
/// `1e999`) are refused.
fn real(
    toks: &[&str],
    i: usize,
    what: &str,
    ctx: &dyn Fn(String) -> String,
) -> Result<f64, String> {
    super::finite_f64(toks[i]).map_err(|e| {
        let tok = toks[i];
        ctx(match e {
            super::NumError::NotANumber => {
                format!("column {}: expected {what}, found '{tok}'", i + 1)
            }
            e => format!("column {}: expected {what}: {}", i + 1, e.describe(tok)),
        })
    })
}

/// Read one non-blank header line into `d` / `natoms`. Returns `Ok(false)` when the line is
/// not a header line but the first section title.
fn header_line(
    d: &mut DataFile,
    natoms: &mut Option<usize>,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<bool, String> {
    let rest = toks[1..].join(" ");
    match rest.as_str() {
        "atoms" => *natoms = Some(num(toks, 0, "an atom count", ctx)?),
        "atom types" => d.ntypes = num(toks, 0, "a type count", ctx)?,
        "bonds" | "angles" | "dihedrals" | "impropers" | "bond types" | "angle types"
        | "dihedral types" | "improper types" => {
            if num::<u64>(toks, 0, "a count", ctx)? != 0 {
                return Err(ctx(format!(
                    "'{rest}' > 0: atom_style atomic has no topology"
                )));
            }
        }
        _ => {
            if toks.len() == 4
                && ["xlo xhi", "ylo yhi", "zlo zhi"].contains(&toks[2..].join(" ").as_str())
            {
                let a = match toks[2] {
                    "xlo" => 0,
                    "ylo" => 1,
                    _ => 2,
                };
                d.lo[a] = real(toks, 0, "a box bound", ctx)?;
                d.hi[a] = real(toks, 1, "a box bound", ctx)?;
            } else if toks.len() == 6 && toks[3..] == ["xy", "xz", "yz"] {
                let mut t = [0.0; 3];
                for (a, v) in t.iter_mut().enumerate() {
                    *v = real(toks, a, "a tilt factor", ctx)?;
                }
                for (a, name) in [(1, "xz"), (2, "yz")] {
                    if t[a] != 0.0 {
                        return Err(ctx(format!(
                            "column {}: tilt {name} = '{}': only boxes tilted in xy are \
                             supported (xz = yz = 0; Lees–Edwards shear along x, gradient y)",
                            a + 1,
                            toks[a]
                        )));
                    }
                }
                if d.tilt.is_some() {
                    return Err(ctx("a second 'xy xz yz' line".into()));
                }
                d.tilt = Some(t);
            } else if toks[0].parse::<f64>().is_ok() {
                return Err(ctx(format!("unknown header keyword '{rest}'")));
            } else {
                return Ok(false); // first section
            }
        }
    }
    Ok(true)
}

/// One line of the `Masses` section: `type mass`.
fn masses_line(
    d: &mut DataFile,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<(), String> {
    if toks.len() < 2 {
        return Err(ctx("Masses line needs 'type mass'".into()));
    }
    let t: usize = num(toks, 0, "a type", ctx)?;
    let m = real(toks, 1, "a mass", ctx)?;
    if t == 0 || t > d.ntypes {
        return Err(ctx(format!("type {t} out of range 1..{}", d.ntypes)));
    }
    if !(m > 0.0 && m.is_finite()) {
        return Err(ctx(format!("mass {m} must be > 0")));
    }
    d.masses[t] = Some(m);
    Ok(())
}

/// One line of the `Atoms` section: `id type x y z [ix iy iz]`.
fn atoms_line(
    d: &mut DataFile,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<(), String> {
    if toks.len() != 5 && toks.len() != 8 {
        return Err(ctx(format!(
            "Atoms line needs 'id type x y z [ix iy iz]' (5 or 8 values), found {}",
            toks.len()
        )));
    }
    let tag: u32 = num(toks, 0, "an atom id", ctx)?;
    let t: u32 = num(toks, 1, "an atom type", ctx)?;
    if tag == 0 {
        return Err(ctx("atom id 0 is not allowed".into()));
    }
    if t == 0 || t as usize > d.ntypes {
        return Err(ctx(format!("atom type {t} out of range 1..{}", d.ntypes)));
    }
    let mut x = [0.0; 3];
    for a in 0..3 {
        x[a] = real(toks, 2 + a, "a coordinate", ctx)?;
    }
    let mut im = [0; 3];
    if toks.len() == 8 {
        for a in 0..3 {
            im[a] = num(toks, 5 + a, "an image flag", ctx)?;
        }
    }
    d.atoms.push((tag, t, x, im));
    Ok(())
}

/// One line of the `Velocities` section: `id vx vy vz`.
fn velocities_line(
    d: &mut DataFile,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<(), String> {
    if toks.len() != 4 {
        return Err(ctx("Velocities line needs 'id vx vy vz'".into()));
    }
    let tag: u32 = num(toks, 0, "an atom id", ctx)?;
    let mut v = [0.0; 3];
    for a in 0..3 {
        v[a] = real(toks, 1 + a, "a velocity", ctx)?;
    }
    d.velocities.push((tag, v));
    Ok(())
}

/// The checks made once the whole file is read: the atom count matches the header and no atom
/// id repeats.
fn check_atoms(d: &DataFile, natoms: usize, name: &str) -> Result<(), String> {
    if d.atoms.len() != natoms {
        return Err(format!(
            "{name}: header says {natoms} atoms, Atoms section has {}",
            d.atoms.len()
        ));
    }
    let mut tags: Vec<u32> = d.atoms.iter().map(|a| a.0).collect();
    tags.sort_unstable();
    if tags.windows(2).any(|w| w[0] == w[1]) {
        return Err(format!("{name}: duplicate atom ids in the Atoms section"));
    }
    Ok(())
}

/// Parse a data file's text. `name` is used in error messages.
pub fn parse_data(text: &str, name: &str) -> Result<DataFile, String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut d = DataFile::default();
    let mut natoms: Option<usize> = None;
    let mut k = 1; // the first line is a title, always skipped
    let err_at = |k: usize, m: String| format!("{name}:{}: {m}", k + 1);
    // Header.
    while k < lines.len() {
        let line = strip_comment(lines[k]).trim();
        if line.is_empty() {
            k += 1;
            continue;
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        let ctx = |m: String| err_at(k, m);
        if !header_line(&mut d, &mut natoms, &toks, &ctx)? {
            break;
        }
        k += 1;
    }
    let natoms = natoms.ok_or_else(|| format!("{name}: header has no 'atoms' line"))?;
    if d.ntypes == 0 {
        return Err(format!(
            "{name}: header has no 'atom types' line (or 0 types)"
        ));
    }
    crate::engine::check_ntypes(d.ntypes).map_err(|m| format!("{name}: {m}"))?;
    d.masses = vec![None; d.ntypes + 1];
    // Sections.
    while k < lines.len() {
        let line = strip_comment(lines[k]).trim();
        if line.is_empty() {
            k += 1;
            continue;
        }
        let section = line.to_string();
        let style = lines[k].split_once('#').map(|(_, s)| s.trim().to_string());
        k += 1;
        // A blank line follows the section title.
        while k < lines.len() && strip_comment(lines[k]).trim().is_empty() {
            k += 1;
        }
        let count = match section.as_str() {
            "Masses" => d.ntypes,
            "Atoms" | "Velocities" => natoms,
            other => return Err(err_at(k - 1, format!("unsupported section '{other}'"))),
        };
        if section == "Atoms"
            && let Some(s) = &style
            && s != "atomic"
        {
            return Err(err_at(
                k - 1,
                format!("Atoms section style '{s}': only 'atomic' is supported"),
            ));
        }
        for _ in 0..count {
            let Some(raw) = lines.get(k) else {
                return Err(format!(
                    "{name}: unexpected end of file in section {section}"
                ));
            };
            let toks: Vec<&str> = strip_comment(raw).split_whitespace().collect();
            let ctx = |m: String| err_at(k, m);
            match section.as_str() {
                "Masses" => masses_line(&mut d, &toks, &ctx)?,
                "Atoms" => atoms_line(&mut d, &toks, &ctx)?,
                _ => velocities_line(&mut d, &toks, &ctx)?,
            }
            k += 1;
        }
    }
    check_atoms(&d, natoms, name)?;
    Ok(d)
}

/// Write a data file (LAMMPS `write_data` layout, 17 significant digits so it reads back exactly).
pub fn format_data(d: &DataFile, title: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{title}\n");
    let _ = writeln!(s, "{} atoms", d.atoms.len());
    let _ = writeln!(s, "{} atom types\n", d.ntypes);
    for (a, n) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(s, "{:.16e} {:.16e} {n}lo {n}hi", d.lo[a], d.hi[a]);
    }
    if let Some(t) = d.tilt {
        let _ = writeln!(s, "{:.16e} {:.16e} {:.16e} xy xz yz", t[0], t[1], t[2]);
    }
    if d.masses.iter().skip(1).any(|m| m.is_some()) {
        let _ = writeln!(s, "\nMasses\n");
        for (t, m) in d.masses.iter().enumerate().skip(1) {
            if let Some(m) = m {
                let _ = writeln!(s, "{t} {m:.16e}");
            }
        }
    }
    let _ = writeln!(s, "\nAtoms # atomic\n");
    for (tag, t, x, im) in &d.atoms {
        let _ = writeln!(
            s,
            "{tag} {t} {:.16e} {:.16e} {:.16e} {} {} {}",
            x[0], x[1], x[2], im[0], im[1], im[2]
        );
    }
    if !d.velocities.is_empty() {
        let _ = writeln!(s, "\nVelocities\n");
        for (tag, v) in &d.velocities {
            let _ = writeln!(s, "{tag} {:.16e} {:.16e} {:.16e}", v[0], v[1], v[2]);
        }
    }
    s
}
