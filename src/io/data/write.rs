//! Writing a data file as LAMMPS's `write_data` does.

use super::*;

/// Write a data file (LAMMPS `write_data` layout, 17 significant digits so it reads back
/// exactly): header, `Masses`, the `Pair Coeffs`/`PairIJ Coeffs` sections of `d.coeffs`, the
/// coefficient sections given in `coeffs` (bond, angle: the style name and the words after the
/// type of each type's line), `Atoms` in the style's
/// columns with image flags, `Velocities`, `Bonds`, `Angles`.
pub fn format_data(d: &DataFile, title: &str) -> String {
    format_data_with(d, title, &[None, None])
}

/// The style name and, by type (index 0 unused), the numbers of a coefficient section.
pub type CoeffRows = Option<(String, Vec<Vec<f64>>)>;

/// [`format_data`] with `Bond Coeffs` and `Angle Coeffs` sections.
pub fn format_data_with(d: &DataFile, title: &str, coeffs: &[CoeffRows; 2]) -> String {
    let mut s = String::new();
    let molecular = d.style.molecular();
    let _ = writeln!(s, "{title}\n");
    let _ = writeln!(s, "{} atoms", d.atoms.len());
    let _ = writeln!(s, "{} atom types", d.ntypes);
    if molecular {
        let _ = writeln!(s, "{} bonds", d.bonds.len());
        let _ = writeln!(s, "{} bond types", d.nbondtypes);
        if d.style.has_angles() {
            let _ = writeln!(s, "{} angles", d.angles.len());
            let _ = writeln!(s, "{} angle types", d.nangletypes);
        }
    }
    let _ = writeln!(s);
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
    for c in d
        .coeffs
        .iter()
        .filter(|c| matches!(c.kind, CoeffKind::Pair | CoeffKind::PairIJ))
    {
        let hint = c
            .style
            .as_deref()
            .map_or(String::new(), |h| format!(" # {h}"));
        let _ = writeln!(s, "\n{}{hint}\n", c.kind.title());
        for (_, words) in &c.lines {
            let _ = writeln!(s, "{}", words.join(" "));
        }
    }
    for (c, what) in coeffs.iter().zip(["Bond", "Angle"]) {
        if let Some((style, rows)) = c {
            let _ = writeln!(s, "\n{what} Coeffs # {style}\n");
            for (t, row) in rows.iter().enumerate().skip(1) {
                let _ = write!(s, "{t}");
                for v in row {
                    let _ = write!(s, " {v:.16e}");
                }
                let _ = writeln!(s);
            }
        }
    }
    let plain = d.columns.is_plain() || d.columns.base != d.style;
    let word = if plain {
        d.style.word()
    } else {
        d.columns.word()
    };
    let _ = writeln!(s, "\nAtoms # {word}\n");
    for (k, (tag, t, x, im)) in d.atoms.iter().enumerate() {
        let mol = d.mol.get(k).copied().unwrap_or(0);
        if !plain {
            let e = d.extra.get(k).copied().unwrap_or_default();
            let line = columns_line(&d.columns, (*tag, *t, mol), x, &e);
            let _ = writeln!(s, "{line} {} {} {}", im[0], im[1], im[2]);
            continue;
        }
        let lead = match d.style {
            AtomStyle::Atomic => format!("{tag} {t}"),
            AtomStyle::Full => format!("{tag} {mol} {t} 0"),
            _ => format!("{tag} {mol} {t}"),
        };
        let _ = writeln!(
            s,
            "{lead} {:.16e} {:.16e} {:.16e} {} {} {}",
            x[0], x[1], x[2], im[0], im[1], im[2]
        );
    }
    if !d.velocities.is_empty() {
        let _ = writeln!(s, "\nVelocities\n");
        for (k, (tag, v)) in d.velocities.iter().enumerate() {
            let _ = write!(s, "{tag} {:.16e} {:.16e} {:.16e}", v[0], v[1], v[2]);
            if d.columns.omega && !plain {
                let w = d.omega.get(k).copied().unwrap_or_default();
                let _ = write!(s, " {:.16e} {:.16e} {:.16e}", w[0], w[1], w[2]);
            }
            let _ = writeln!(s);
        }
    }
    if !d.bonds.is_empty() {
        let _ = writeln!(s, "\nBonds\n");
        for (k, b) in d.bonds.iter().enumerate() {
            let _ = writeln!(s, "{} {} {} {}", k + 1, b.typ, b.atoms[0], b.atoms[1]);
        }
    }
    if !d.angles.is_empty() {
        let _ = writeln!(s, "\nAngles\n");
        for (k, a) in d.angles.iter().enumerate() {
            let [p, q, r] = a.atoms;
            let _ = writeln!(s, "{} {} {p} {q} {r}", k + 1, a.typ);
        }
    }
    s
}

/// An `Atoms` line in the columns `c` (before the image flags): (id, type, molecule), the
/// position and the extra values; charges are 0.
fn columns_line(
    c: &AtomColumns,
    (tag, t, mol): (u32, u32, u32),
    x: &[f64; 3],
    e: &AtomExtra,
) -> String {
    let mut s = String::new();
    for (k, f) in c.atom.iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        let _ = match f {
            Field::Id => write!(s, "{tag}"),
            Field::Type => write!(s, "{t}"),
            Field::Mol => write!(s, "{mol}"),
            Field::Q => write!(s, "0"),
            Field::Rho => write!(s, "{:.16e}", e.rho),
            Field::Diameter => write!(s, "{:.16e}", e.diameter),
            Field::Density => write!(s, "{:.16e}", e.density),
            Field::X => write!(s, "{:.16e} {:.16e} {:.16e}", x[0], x[1], x[2]),
        };
    }
    s
}
