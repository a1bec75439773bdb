//! Reading LAMMPS log text: the thermo blocks, and telling a log from a text dump.

/// One thermo block: the header's column names and the rows under it.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermoBlock {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl ThermoBlock {
    /// Index of column `name`: an exact match, else the only case-insensitive match
    /// (`temp` finds `Temp`).
    pub fn column_index(&self, name: &str) -> Option<usize> {
        column_index(&self.columns, name)
    }

    /// The values of column `name`, one per row.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.column_index(name)?;
        Some(
            self.rows
                .iter()
                .map(|r| r.get(i).copied().unwrap_or(f64::NAN))
                .collect(),
        )
    }
}

pub(super) fn column_index(columns: &[String], name: &str) -> Option<usize> {
    if let Some(i) = columns.iter().position(|c| c == name) {
        return Some(i);
    }
    let mut it = columns
        .iter()
        .enumerate()
        .filter(|(_, c)| c.eq_ignore_ascii_case(name));
    match (it.next(), it.next()) {
        (Some((i, _)), None) => Some(i),
        _ => None,
    }
}

/// The values of a line whose tokens are all numbers, else `None`. `nan` and `inf` (any sign
/// and case) are read as such: LAMMPS prints them when a run blows up. A decimal literal beyond
/// the range of a double (`1e999`), which LAMMPS never prints, is an error: `(column, token)`.
fn parse_numbers(line: &str) -> Result<Option<Vec<f64>>, (usize, &str)> {
    let toks: Vec<&str> = line.split_whitespace().collect();
    let Some(values) = toks
        .iter()
        .map(|t| t.parse::<f64>().ok())
        .collect::<Option<Vec<f64>>>()
    else {
        return Ok(None);
    };
    match values
        .iter()
        .zip(&toks)
        .position(|(v, t)| v.is_infinite() && !crate::io::spelled_infinity(t))
    {
        Some(i) => Err((i + 1, toks[i])),
        None => Ok(Some(values)),
    }
}

/// All thermo blocks of a log, in order.
///
/// Values `nan`, `inf` and `-inf` (as LAMMPS prints them after a blow-up) are read as NaN and
/// infinities, not refused: a log that blew up can still be read and compared (two NaNs compare
/// equal in [`differences`](super::differences)).
///
/// Errors: a row whose number of values differs from its header (with the line number); a
/// number beyond the range of a double, such as `1e999` (with the line and column). The
/// last line of the text is exempt from the first check when it does not end in a newline (a
/// log still being written): it is dropped.
pub fn parse_log(text: &str) -> Result<Vec<ThermoBlock>, String> {
    let mut blocks = Vec::new();
    let mut current: Option<ThermoBlock> = None;
    let lines: Vec<&str> = text.lines().collect();
    let unterminated_last = !text.is_empty() && !text.ends_with('\n');
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim();
        if let Some(block) = current.as_mut() {
            if trimmed.is_empty() || trimmed.starts_with("WARNING") {
                continue;
            }
            let parsed = parse_numbers(trimmed).map_err(|(col, tok)| {
                format!(
                    "line {}: column {col}: {}; LAMMPS prints an infinite thermo value as 'inf'",
                    i + 1,
                    crate::io::NumError::Overflow.describe(tok)
                )
            })?;
            if let Some(values) = parsed {
                if values.len() == block.columns.len() {
                    block.rows.push(values);
                    continue;
                }
                if unterminated_last && i + 1 == lines.len() {
                    continue;
                }
                return Err(format!(
                    "line {}: thermo row has {} values but the header has {} columns ({})",
                    i + 1,
                    values.len(),
                    block.columns.len(),
                    block.columns.join(" ")
                ));
            }
            if let Some(b) = current.take().filter(|b| !b.rows.is_empty()) {
                blocks.push(b);
            }
        }
        let mut tokens = trimmed.split_whitespace();
        if tokens.next() == Some("Step") {
            current = Some(ThermoBlock {
                columns: trimmed.split_whitespace().map(str::to_string).collect(),
                rows: Vec::new(),
            });
        }
    }
    if let Some(b) = current.filter(|b| !b.rows.is_empty()) {
        blocks.push(b);
    }
    Ok(blocks)
}

/// Whether `text` looks like a LAMMPS text dump (its first non-blank line is `ITEM: TIMESTEP`)
/// rather than a log.
pub fn looks_like_dump(text: &str) -> bool {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .is_some_and(|l| l.starts_with("ITEM: TIMESTEP"))
}
