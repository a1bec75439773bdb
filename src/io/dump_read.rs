//! LAMMPS text dumps (`dump custom` and `dump atom`), read back frame by frame.
//!
//! A frame is `ITEM: TIMESTEP`, `ITEM: NUMBER OF ATOMS`, `ITEM: BOX BOUNDS …` with three lines
//! of `lo hi` (or `lo hi tilt` for an orthogonally-stored triclinic box, `ITEM: BOX BOUNDS xy xz
//! yz …`), then `ITEM: ATOMS <columns>` and that many rows. Other items (`ITEM: UNITS`,
//! `ITEM: TIME`) are skipped. Values must be finite numbers (`nan`, `inf`, `1e999` are errors
//! naming the line and column; `element` columns are not supported), and general-triclinic boxes
//! (`ITEM: BOX BOUNDS abc origin`) are refused.

/// One dump frame. `rows` are sorted by the `id` column when there is one.
#[derive(Debug, Clone, PartialEq)]
pub struct DumpFrame {
    /// The time step (`ITEM: TIMESTEP`).
    pub step: u64,
    /// `[lo, hi]` in x, y, z, as printed (for a triclinic box these are LAMMPS's bounding-box
    /// values `xlo_bound xhi_bound`, …).
    pub box_bounds: Vec<[f64; 2]>,
    /// The tilt factors `[xy, xz, yz]` of a triclinic box.
    pub tilt: Option<[f64; 3]>,
    /// The column names of `ITEM: ATOMS`.
    pub columns: Vec<String>,
    /// One row per atom, one value per column.
    pub rows: Vec<Vec<f64>>,
}

struct Lines<'a> {
    it: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
}

impl<'a> Lines<'a> {
    /// The next non-blank line and its 1-based number.
    fn next(&mut self) -> Option<(usize, &'a str)> {
        for (i, l) in self.it.by_ref() {
            if !l.trim().is_empty() {
                return Some((i + 1, l.trim()));
            }
        }
        None
    }

    fn expect(&mut self, what: &str) -> Result<(usize, &'a str), String> {
        self.next()
            .ok_or_else(|| format!("unexpected end of dump: expected {what}"))
    }

    fn peek_is_item(&mut self) -> bool {
        while let Some((_, l)) = self.it.peek() {
            if l.trim().is_empty() {
                self.it.next();
            } else {
                return l.trim_start().starts_with("ITEM:");
            }
        }
        false
    }
}

/// The `n` values of a line, each a finite number (NaN and infinities are refused).
fn numbers(line: &str, n: usize, ln: usize, what: &str) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = line
        .split_whitespace()
        .enumerate()
        .map(|(i, t)| {
            super::finite_f64(t)
                .map_err(|e| format!("line {ln}: {what}: column {}: {}", i + 1, e.describe(t)))
        })
        .collect::<Result<_, _>>()?;
    if v.len() != n {
        return Err(format!(
            "line {ln}: {what}: expected {n} values, found {} in '{line}'",
            v.len()
        ));
    }
    Ok(v)
}

fn parse_u64(line: &str, ln: usize, what: &str) -> Result<u64, String> {
    line.parse()
        .map_err(|_| format!("line {ln}: {what}: expected a non-negative integer, found '{line}'"))
}

/// All frames of a text dump, in file order.
pub fn parse_dump(text: &str) -> Result<Vec<DumpFrame>, String> {
    let mut lines = Lines {
        it: text.lines().enumerate().peekable(),
    };
    let mut frames = Vec::new();
    while let Some((ln, l)) = lines.next() {
        if l != "ITEM: TIMESTEP" {
            return Err(format!("line {ln}: expected 'ITEM: TIMESTEP', found '{l}'"));
        }
        let (ln, l) = lines.expect("the timestep")?;
        let step = parse_u64(l, ln, "timestep")?;
        let mut n_atoms = None;
        let mut box_bounds = Vec::new();
        let mut tilt = None;
        loop {
            let (ln, item) = lines.expect("ITEM: ATOMS")?;
            let Some(item) = item.strip_prefix("ITEM:").map(str::trim) else {
                return Err(format!("line {ln}: expected an ITEM line, found '{item}'"));
            };
            if item == "NUMBER OF ATOMS" {
                let (ln, l) = lines.expect("the number of atoms")?;
                n_atoms = Some(parse_u64(l, ln, "number of atoms")?);
            } else if let Some(flags) = item.strip_prefix("BOX BOUNDS") {
                let flags: Vec<&str> = flags.split_whitespace().collect();
                if flags.contains(&"abc") {
                    return Err(format!(
                        "line {ln}: general triclinic boxes ('{item}') are not supported"
                    ));
                }
                let triclinic = flags.contains(&"xy");
                let per_line = if triclinic { 3 } else { 2 };
                let mut t = [0.0; 3];
                for td in t.iter_mut() {
                    let (ln, l) = lines.expect("box bounds")?;
                    let v = numbers(l, per_line, ln, "box bounds")?;
                    box_bounds.push([v[0], v[1]]);
                    if triclinic {
                        *td = v[2];
                    }
                }
                tilt = triclinic.then_some(t);
            } else if let Some(cols) = item.strip_prefix("ATOMS") {
                let columns: Vec<String> = cols.split_whitespace().map(str::to_string).collect();
                if columns.is_empty() {
                    return Err(format!("line {ln}: 'ITEM: ATOMS' names no columns"));
                }
                let n = n_atoms.ok_or_else(|| {
                    format!("line {ln}: 'ITEM: ATOMS' before 'ITEM: NUMBER OF ATOMS'")
                })?;
                let n =
                    usize::try_from(n).map_err(|_| format!("line {ln}: too many atoms ({n})"))?;
                let mut rows = Vec::with_capacity(n.min(1 << 24));
                for k in 0..n {
                    let (ln, l) = lines.next().ok_or_else(|| {
                        format!("dump truncated: step {step} has {k} of {n} atom lines")
                    })?;
                    if l.starts_with("ITEM:") {
                        return Err(format!(
                            "line {ln}: step {step} has {k} atom lines, expected {n}"
                        ));
                    }
                    rows.push(numbers(l, columns.len(), ln, "atom line")?);
                }
                if let Some(id) = columns.iter().position(|c| c == "id") {
                    rows.sort_by(|a, b| a[id].total_cmp(&b[id]));
                }
                if box_bounds.len() != 3 {
                    return Err(format!(
                        "step {step}: no 'ITEM: BOX BOUNDS' before the atoms"
                    ));
                }
                frames.push(DumpFrame {
                    step,
                    box_bounds,
                    tilt,
                    columns,
                    rows,
                });
                break;
            } else if item == "TIMESTEP" {
                return Err(format!(
                    "line {ln}: step {step} has no 'ITEM: ATOMS' section"
                ));
            } else {
                // Unknown items (UNITS, TIME, …): skip their value lines.
                while !lines.peek_is_item() {
                    if lines.next().is_none() {
                        break;
                    }
                }
            }
        }
    }
    Ok(frames)
}
