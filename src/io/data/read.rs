//! Reading a data file: the header, then each section, every line checked (file and line in
//! every error).

use super::*;

/// Header counts of a molecular file.
#[derive(Default)]
struct Counts {
    atoms: Option<usize>,
    bonds: usize,
    angles: usize,
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
    crate::io::finite_f64(toks[i]).map_err(|e| {
        let tok = toks[i];
        ctx(match e {
            crate::io::NumError::NotANumber => {
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
    counts: &mut Counts,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<bool, String> {
    let rest = toks[1..].join(" ");
    let topo = |n: usize, what: &str| -> Result<usize, String> {
        if n > 0 && !d.style.molecular() {
            return Err(ctx(format!(
                "'{n} {what}': atom_style atomic has no topology (use atom_style bond, angle, \
                 molecular or full)"
            )));
        }
        if n > 0 && what.starts_with("angle") && !d.style.has_angles() {
            return Err(ctx(format!(
                "'{n} {what}': atom_style {} has no angles (use angle, molecular or full)",
                d.style.word()
            )));
        }
        Ok(n)
    };
    match rest.as_str() {
        "atoms" => counts.atoms = Some(num(toks, 0, "an atom count", ctx)?),
        "atom types" => d.ntypes = num(toks, 0, "a type count", ctx)?,
        "bonds" => counts.bonds = topo(num(toks, 0, "a bond count", ctx)?, &rest)?,
        "bond types" => d.nbondtypes = topo(num(toks, 0, "a type count", ctx)?, &rest)?,
        "angles" => counts.angles = topo(num(toks, 0, "an angle count", ctx)?, &rest)?,
        "angle types" => d.nangletypes = topo(num(toks, 0, "a type count", ctx)?, &rest)?,
        "extra bond per atom"
        | "extra angle per atom"
        | "extra dihedral per atom"
        | "extra improper per atom"
        | "extra special per atom" => {
            num::<u64>(toks, 0, "a count", ctx)?;
        }
        "dihedrals" | "impropers" | "dihedral types" | "improper types" => {
            if num::<u64>(toks, 0, "a count", ctx)? != 0 {
                return Err(ctx(format!(
                    "'{rest}' > 0: dihedrals and impropers are not supported"
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

/// One line of the `Atoms` section: the style's columns (`id [mol] type [q] x y z`), then
/// optionally `ix iy iz`.
fn atoms_line(
    d: &mut DataFile,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<(), String> {
    if !d.columns.is_plain() {
        return atoms_line_columns(d, toks, ctx);
    }
    let cols = d.style.columns();
    let n = cols.split_whitespace().count();
    if toks.len() != n && toks.len() != n + 3 {
        return Err(ctx(format!(
            "Atoms line of atom_style {} needs '{cols} [ix iy iz]' ({n} or {} values), found {}",
            d.style.word(),
            n + 3,
            toks.len()
        )));
    }
    let tag: u32 = num(toks, 0, "an atom id", ctx)?;
    // The columns after the id: [mol] type [q] x y z.
    let (tcol, xcol) = match d.style {
        AtomStyle::Atomic => (1, 2),
        AtomStyle::Full => (2, 4),
        _ => (2, 3),
    };
    if d.style.molecular() {
        let mol: u32 = num(toks, 1, "a molecule id", ctx)?;
        d.mol.push(mol);
    }
    if d.style == AtomStyle::Full {
        let q = real(toks, 3, "a charge", ctx)?;
        if q != 0.0 {
            return Err(ctx(format!(
                "atom {tag} has charge {q}: this engine has no Coulomb interactions, every \
                 charge must be 0"
            )));
        }
    }
    let t: u32 = num(toks, tcol, "an atom type", ctx)?;
    if tag == 0 {
        return Err(ctx("atom id 0 is not allowed".into()));
    }
    if t == 0 || t as usize > d.ntypes {
        return Err(ctx(format!("atom type {t} out of range 1..{}", d.ntypes)));
    }
    let mut x = [0.0; 3];
    for a in 0..3 {
        x[a] = real(toks, xcol + a, "a coordinate", ctx)?;
    }
    let mut im = [0; 3];
    if toks.len() == n + 3 {
        for a in 0..3 {
            im[a] = num(toks, n + a, "an image flag", ctx)?;
        }
    }
    d.atoms.push((tag, t, x, im));
    Ok(())
}

/// One line of the `Atoms` section of the columns of a `charge`, `mdpd`, `sphere` or `hybrid`
/// style ([`AtomColumns`]), then optionally `ix iy iz`.
fn atoms_line_columns(
    d: &mut DataFile,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<(), String> {
    let n = d.columns.count();
    if toks.len() != n && toks.len() != n + 3 {
        return Err(ctx(format!(
            "Atoms line of atom_style {} needs '{} [ix iy iz]' ({n} or {} values), found {}",
            d.columns.words.join(" "),
            d.columns.describe(),
            n + 3,
            toks.len()
        )));
    }
    let (mut tag, mut t, mut mol) = (0u32, 0u32, None);
    let mut x = [0.0; 3];
    let mut e = AtomExtra::default();
    let mut q = 0.0;
    let mut k = 0;
    for f in d.columns.atom.clone() {
        match f {
            Field::Id => tag = num(toks, k, "an atom id", ctx)?,
            Field::Type => t = num(toks, k, "an atom type", ctx)?,
            Field::Mol => mol = Some(num(toks, k, "a molecule id", ctx)?),
            Field::Q => q = real(toks, k, "a charge", ctx)?,
            Field::Rho => e.rho = real(toks, k, "a density rho", ctx)?,
            Field::Diameter => e.diameter = real(toks, k, "a diameter", ctx)?,
            Field::Density => e.density = real(toks, k, "a density", ctx)?,
            Field::X => {
                for a in 0..3 {
                    x[a] = real(toks, k + a, "a coordinate", ctx)?;
                }
                k += 2;
            }
        }
        k += 1;
    }
    if tag == 0 {
        return Err(ctx("atom id 0 is not allowed".into()));
    }
    if t == 0 || t as usize > d.ntypes {
        return Err(ctx(format!("atom type {t} out of range 1..{}", d.ntypes)));
    }
    if q != 0.0 {
        return Err(ctx(format!(
            "atom {tag} has charge {q}: this engine has no Coulomb interactions, every charge \
             must be 0"
        )));
    }
    if d.columns.per_atom_mass() && e.density <= 0.0 {
        return Err(ctx(format!(
            "Invalid density in Atoms section of data file: atom {tag} has density {} (must be \
             > 0)",
            e.density
        )));
    }
    if d.columns.per_atom_mass() && e.diameter < 0.0 {
        return Err(ctx(format!("atom {tag} has diameter {} < 0", e.diameter)));
    }
    let mut im = [0; 3];
    if toks.len() == n + 3 {
        for a in 0..3 {
            im[a] = num(toks, n + a, "an image flag", ctx)?;
        }
    }
    if let Some(m) = mol {
        d.mol.push(m);
    }
    d.atoms.push((tag, t, x, im));
    d.extra.push(e);
    Ok(())
}

/// One line of the `Velocities` section: `id vx vy vz`, and `wx wy wz` for `sphere`.
fn velocities_line(
    d: &mut DataFile,
    toks: &[&str],
    ctx: &dyn Fn(String) -> String,
) -> Result<(), String> {
    let omega = d.columns.omega;
    if toks.len() != if omega { 7 } else { 4 } {
        return Err(ctx(if omega {
            "Velocities line needs 'id vx vy vz wx wy wz'".into()
        } else {
            "Velocities line needs 'id vx vy vz'".into()
        }));
    }
    let tag: u32 = num(toks, 0, "an atom id", ctx)?;
    let mut v = [0.0; 3];
    for a in 0..3 {
        v[a] = real(toks, 1 + a, "a velocity", ctx)?;
    }
    if omega {
        let mut w = [0.0; 3];
        for a in 0..3 {
            w[a] = real(toks, 4 + a, "an angular velocity", ctx)?;
        }
        d.omega.push(w);
    }
    d.velocities.push((tag, v));
    Ok(())
}

/// One line of `Bonds` (`id type a1 a2`, n = 2) or `Angles` (`id type a1 a2 a3`, n = 3): the
/// type and atom ids (checked against the atoms at the end, [`check_topology`]).
fn topo_line(
    toks: &[&str],
    n: usize,
    ntypes: usize,
    section: &str,
    ctx: &dyn Fn(String) -> String,
) -> Result<(u32, [u32; 3]), String> {
    let what = if n == 2 { "bond" } else { "angle" };
    if toks.len() != n + 2 {
        return Err(ctx(format!(
            "Incorrect format in {section} section of data file: need 'id type {}', found {} \
             values",
            if n == 2 { "a1 a2" } else { "a1 a2 a3" },
            toks.len()
        )));
    }
    num::<u64>(toks, 0, &format!("a {what} id"), ctx)?;
    let t: u32 = num(toks, 1, &format!("a {what} type"), ctx)?;
    if t == 0 || t as usize > ntypes {
        return Err(ctx(format!(
            "Invalid {what} type in {section} section of data file: {t} (types are 1..{ntypes})"
        )));
    }
    let mut a = [0u32; 3];
    for k in 0..n {
        a[k] = num(toks, 2 + k, "an atom id", ctx)?;
    }
    Ok((t, a))
}

/// Every bond and angle names atoms of the file; `lines[k]` is the line of bond k (then of
/// angle k − bonds). Image flags are not checked here (see the module documentation).
fn check_topology(d: &DataFile, lines: &[usize], name: &str) -> Result<(), String> {
    let tags: std::collections::HashSet<u32> = d.atoms.iter().map(|a| a.0).collect();
    let members = d
        .bonds
        .iter()
        .map(|b| ("Bonds", &b.atoms[..]))
        .chain(d.angles.iter().map(|a| ("Angles", &a.atoms[..])));
    for (k, (section, ids)) in members.enumerate() {
        let line = lines.get(k).copied().unwrap_or(0);
        if let Some(id) = ids.iter().find(|id| !tags.contains(id)) {
            return Err(format!(
                "{name}:{line}: Invalid atom ID in {section} section of data file: no atom \
                 has id {id}"
            ));
        }
    }
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

/// Parse a data file's text for `atom_style atomic`. `name` is used in error messages.
pub fn parse_data(text: &str, name: &str) -> Result<DataFile, String> {
    parse_data_styled(text, name, AtomStyle::Atomic)
}

/// Parse a data file's text whose `Atoms` lines have the columns of `style`. `name` is used in
/// error messages.
pub fn parse_data_styled(text: &str, name: &str, style: AtomStyle) -> Result<DataFile, String> {
    parse_data_columns(text, name, &AtomColumns::of(style))
}

/// Parse a data file's text whose `Atoms` and `Velocities` lines have the columns `columns`
/// (any style [`AtomColumns::parse`] reads). `name` is used in error messages.
pub fn parse_data_columns(
    text: &str,
    name: &str,
    columns: &AtomColumns,
) -> Result<DataFile, String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut d = DataFile {
        style: columns.base,
        columns: columns.clone(),
        ..DataFile::default()
    };
    let mut counts = Counts::default();
    let mut k = read_header(&lines, name, &mut d, &mut counts)?;
    let natoms = check_header(&d, &counts, name)?;
    d.masses = vec![None; d.ntypes + 1];
    let mut topo = TopoLines::default();
    let mut seen = Vec::new();
    while k < lines.len() {
        if strip_comment(lines[k]).trim().is_empty() {
            k += 1;
            continue;
        }
        let head = section_head(&lines, k, name, &mut d, &counts, natoms, &mut seen)?;
        k = read_section(&lines, &head, name, &mut d, &mut topo)?;
    }
    check_atoms(&d, natoms, name)?;
    for (n, got, what) in [
        (counts.bonds, d.bonds.len(), "Bonds"),
        (counts.angles, d.angles.len(), "Angles"),
    ] {
        if n != got {
            return Err(format!(
                "{name}: header says {n} {}, the file has no {what} section",
                what.to_lowercase()
            ));
        }
    }
    topo.bonds.extend(topo.angles);
    check_topology(&d, &topo.bonds, name)?;
    Ok(d)
}

/// `m` at line `k` (0-based) of the file `name`.
fn at_line(name: &str, k: usize, m: String) -> String {
    format!("{name}:{}: {m}", k + 1)
}

/// The header's lines, from the second (the first is a title, always skipped) up to the first
/// section title: the index of that title.
fn read_header(
    lines: &[&str],
    name: &str,
    d: &mut DataFile,
    counts: &mut Counts,
) -> Result<usize, String> {
    let mut k = 1;
    while k < lines.len() {
        let line = strip_comment(lines[k]).trim();
        if line.is_empty() {
            k += 1;
            continue;
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        let ctx = |m: String| at_line(name, k, m);
        if !header_line(d, counts, &toks, &ctx)? {
            break;
        }
        k += 1;
    }
    Ok(k)
}

/// The header's counts are complete and in range: the number of atoms.
fn check_header(d: &DataFile, counts: &Counts, name: &str) -> Result<usize, String> {
    let natoms = counts
        .atoms
        .ok_or_else(|| format!("{name}: header has no 'atoms' line"))?;
    if d.ntypes == 0 {
        return Err(format!(
            "{name}: header has no 'atom types' line (or 0 types)"
        ));
    }
    crate::engine::check_ntypes(d.ntypes).map_err(|m| format!("{name}: {m}"))?;
    for (n, nt, what) in [
        (counts.bonds, d.nbondtypes, "bond"),
        (counts.angles, d.nangletypes, "angle"),
    ] {
        if n > 0 && nt == 0 {
            return Err(format!(
                "{name}: header has {n} {what}s but no '{what} types' line (or 0 types)"
            ));
        }
        crate::engine::check_ntypes(nt.max(1)).map_err(|m| format!("{name}: {what} types: {m}"))?;
    }
    Ok(natoms)
}

/// The file lines (1-based) of the bonds and of the angles, in order, for
/// [`check_topology`]'s messages.
#[derive(Default)]
struct TopoLines {
    bonds: Vec<usize>,
    angles: Vec<usize>,
}

/// A section's title line, read: its name, where its first line is and how many it has.
struct SectionHead {
    section: String,
    /// The index of its first line (after the blank line(s) below the title).
    first: usize,
    count: usize,
}

/// The section whose title is line `title`: its name checked (known, counted by the header,
/// not seen before: `seen` gets it), its coefficient section opened in `d`, its line count.
fn section_head(
    lines: &[&str],
    title: usize,
    name: &str,
    d: &mut DataFile,
    counts: &Counts,
    natoms: usize,
    seen: &mut Vec<String>,
) -> Result<SectionHead, String> {
    let section = strip_comment(lines[title]).trim().to_string();
    // The style named after `#` (write_data's hint). As LAMMPS: not for the first section,
    // whose title line ends the header, where LAMMPS has already cut the comment off.
    let hint = if seen.is_empty() {
        None
    } else {
        lines[title]
            .split_once('#')
            .map(|(_, s)| s.trim().to_string())
    };
    let mut first = title + 1;
    // A blank line follows the section title.
    while first < lines.len() && strip_comment(lines[first]).trim().is_empty() {
        first += 1;
    }
    let coeff_kind = match section.as_str() {
        "Pair Coeffs" => Some(CoeffKind::Pair),
        "PairIJ Coeffs" => Some(CoeffKind::PairIJ),
        "Bond Coeffs" => Some(CoeffKind::Bond),
        "Angle Coeffs" => Some(CoeffKind::Angle),
        _ => None,
    };
    let count = match section.as_str() {
        "Masses" | "Pair Coeffs" => d.ntypes,
        "PairIJ Coeffs" => d.ntypes * (d.ntypes + 1) / 2,
        "Atoms" | "Velocities" => natoms,
        "Bonds" => counts.bonds,
        "Angles" => counts.angles,
        "Bond Coeffs" => d.nbondtypes,
        "Angle Coeffs" => d.nangletypes,
        other => {
            return Err(at_line(
                name,
                title,
                format!("unsupported section '{other}'"),
            ));
        }
    };
    if count == 0 && section != "Atoms" && section != "Velocities" {
        return Err(at_line(
            name,
            title,
            format!("section {section}, but the header counts none (or no types)"),
        ));
    }
    if seen.contains(&section) {
        return Err(at_line(name, title, format!("second {section} section")));
    }
    seen.push(section.clone());
    if section == "Atoms" {
        d.atoms_hint = hint.clone();
    }
    if let Some(kind) = coeff_kind {
        d.coeffs.push(CoeffSection {
            kind,
            line: title + 1,
            style: hint,
            lines: Vec::with_capacity(count),
        });
    }
    Ok(SectionHead {
        section,
        first,
        count,
    })
}

/// The lines of the section `head` into `d`: the index of the line after them.
fn read_section(
    lines: &[&str],
    head: &SectionHead,
    name: &str,
    d: &mut DataFile,
    topo: &mut TopoLines,
) -> Result<usize, String> {
    let section = head.section.as_str();
    // Saturating: a header's count beyond the file ends at its last line, an error.
    let end = head.first.saturating_add(head.count);
    for k in head.first..end {
        let Some(raw) = lines.get(k) else {
            return Err(format!(
                "{name}: unexpected end of file in section {section}"
            ));
        };
        let toks: Vec<&str> = strip_comment(raw).split_whitespace().collect();
        let ctx = |m: String| at_line(name, k, m);
        match section {
            "Masses" => masses_line(d, &toks, &ctx)?,
            "Atoms" => atoms_line(d, &toks, &ctx)?,
            "Bonds" => {
                let (typ, a) = topo_line(&toks, 2, d.nbondtypes, "Bonds", &ctx)?;
                d.bonds.push(Bond {
                    typ,
                    atoms: [a[0], a[1]],
                });
                topo.bonds.push(k + 1);
            }
            "Angles" => {
                let (typ, atoms) = topo_line(&toks, 3, d.nangletypes, "Angles", &ctx)?;
                d.angles.push(Angle { typ, atoms });
                topo.angles.push(k + 1);
            }
            "Velocities" => velocities_line(d, &toks, &ctx)?,
            _ => {
                if toks.is_empty() {
                    return Err(ctx(format!("Unexpected empty line in {section} section")));
                }
                if let Some(c) = d.coeffs.last_mut() {
                    c.lines
                        .push((k + 1, toks.iter().map(|t| t.to_string()).collect()));
                }
            }
        }
    }
    Ok(end)
}
