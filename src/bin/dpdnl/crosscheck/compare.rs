//! Step 3 of a crosscheck: the logs and dumps compared value by value, the tables printed, and
//! dumps' periodic images matched first.

use super::engines::moved;
use super::verdict::{
    differ_verdict, engine_random_setup, flip_leak_notes, growth_table, neighbor_line, shear_notes,
};
use super::{CannotRun, CrosscheckArgs};
use crate::report::{TableStyle, c, write_exact_table};
use dpdnl::input::{FromState, StateReport};
use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use dpdnl::io::growth::{classify, merged, printed_digits, resolution, timeline};
use dpdnl::io::lammps_log::{
    ExactReport, StepMax, Tolerance, compare_dumps_exact, compare_exact_logs, neighbor_summary,
    parse_log,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Step 3: compare the thermo logs and the dumps exactly (to `--rtol`) and print the report;
/// true when they agree.
pub(super) fn compare(
    a: &CrosscheckArgs,
    lmp: &Path,
    script: &Path,
    workdir: &Path,
    (log_s, log_l): (&Path, &Path),
    dumps: &[(PathBuf, PathBuf)],
    from: Option<(&FromState, &StateReport)>,
) -> Result<bool, CannotRun> {
    // 3. Compare.
    let tol = Tolerance {
        rtol: a.rtol,
        atol: a.atol,
    };
    let read = |p: &Path| {
        std::fs::read_to_string(p)
            .map_err(|e| CannotRun(format!("cannot read {}: {e}", p.display())))
    };
    let text_s = read(log_s)?;
    let blocks_s = parse_log(&text_s).map_err(|e| format!("{}: {e}", log_s.display()))?;
    let text_l = read(log_l)?;
    let blocks_l = parse_log(&text_l).map_err(|e| format!("{}: {e}", log_l.display()))?;
    let neigh = neighbor_summary(&text_l);
    if blocks_s.is_empty() || blocks_l.is_empty() {
        return Err(CannotRun(
            "a log has no thermo block (does the script run any steps?)".into(),
        ));
    }
    println!("script: {}", script.display());
    println!("lammps: {}", lmp.display());
    println!("workdir: {}", workdir.display());
    if let Some(line) = neighbor_line(&neigh) {
        println!("{line}");
    }
    if let Some((st, r)) = from {
        for line in super::state::report_lines(r, st) {
            println!("{line}");
        }
    }
    let state_part = from.map(|(_, r)| super::state::verdict_part(r));
    let mut notes = shear_notes(&text_l, &neigh);
    notes.extend(flip_leak_notes(&text_s, &text_l));
    for n in &notes {
        println!("note: {n}");
    }
    let r = compare_exact_logs(&blocks_s, &blocks_l, None, tol)
        .map_err(|e| format!("comparing thermo logs: {e}"))?;
    let mut pass = print_report("thermo (A = standalone.log, B = lammps.log)", &r);
    // The coarsest printed precision of the compared files bounds what the comparison resolves.
    let mut digits: Vec<usize> = [&text_s, &text_l]
        .iter()
        .filter_map(|t| printed_digits(t))
        .collect();
    let mut dump_steps: Vec<(String, Vec<StepMax>)> = Vec::new();
    let mut n_dump_rows = 0;
    for (s, l) in dumps {
        let (ps, pl) = (
            moved(workdir, s, "dump.standalone"),
            moved(workdir, l, "dump.lammps"),
        );
        let (ts, tl) = (read(&ps)?, read(&pl)?);
        digits.extend(printed_digits(&ts));
        digits.extend(printed_digits(&tl));
        let fs = parse_dump(&ts).map_err(|e| format!("{}: {e}", ps.display()))?;
        let mut fl = parse_dump(&tl).map_err(|e| format!("{}: {e}", pl.display()))?;
        let shifted = minimum_image(&fs, &mut fl);
        let r = compare_dumps_exact(&fs, &fl, None, tol)
            .map_err(|e| format!("comparing dumps {} and {}: {e}", ps.display(), pl.display()))?;
        n_dump_rows += r.n_matched;
        let name = ps.file_name().unwrap_or_default().to_string_lossy();
        let title = format!(
            "dump (A = {name}, B = {})",
            pl.file_name().unwrap_or_default().to_string_lossy()
        );
        pass &= print_report(&title, &r);
        dump_steps.push((name.replace("standalone", "${engine}"), r.steps.clone()));
        if shifted > 0 {
            println!(
                "({shifted} LAMMPS atom position(s) moved by lattice vectors to the standalone \
                 image: LAMMPS wraps atoms back into the box only when it re-neighbours, and \
                 into the tilted cell of a tilted box)"
            );
        }
    }
    let what = if dumps.is_empty() {
        "thermo log".to_string()
    } else {
        format!(
            "thermo log and {} dump(s), {n_dump_rows} atom rows",
            dumps.len()
        )
    };
    if pass {
        let atol = if a.atol > 0.0 {
            format!(", atol {}", c("%g", a.atol))
        } else {
            String::new()
        };
        let state = state_part.map_or(String::new(), |p| format!("; {p}"));
        println!(
            "CROSSCHECK AGREE: {what} within rtol {}{atol}{state}",
            c("%g", a.rtol)
        );
    } else {
        let points = timeline(&r.steps, &dump_steps);
        let res = digits.iter().min().map_or(0.0, |&d| resolution(d));
        let growth = classify(&points, a.rtol, res);
        print!("{}", growth_table(&merged(&points), a.rtol));
        // From LAMMPS's state both engines start alike, whatever the set-up drew.
        let random_setup = std::fs::read_to_string(script)
            .ok()
            .filter(|_| from.is_none())
            .and_then(|t| engine_random_setup(&t));
        let mut v = differ_verdict(&what, a.rtol, &neigh, &growth, random_setup.as_ref());
        for n in &notes {
            let _ = write!(v, "; {n}");
        }
        if let Some(p) = state_part {
            let _ = write!(v, "; {p}");
        }
        println!("{v}");
    }
    Ok(pass)
}
/// Prints one comparison table; true when it passes (values and rows).
fn print_report(title: &str, r: &ExactReport) -> bool {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\n{title}: {} row(s) matched by {}",
        r.n_matched, r.key
    );
    write_exact_table(
        &mut out,
        r,
        &TableStyle {
            labels: ["standalone", "lammps"],
            value_fmt: "%.15g",
            value_width: 22,
            blank_before_header: false,
        },
    );
    print!("{out}");
    r.values_pass() && r.rows_match()
}

/// The box of a dump frame as (lo, edge lengths, xy): for a triclinic frame the bounds are
/// LAMMPS's bounding box (`xlo_bound = xlo + min(0, xy, xz, xy + xz)`, …), undone here.
fn frame_box(f: &DumpFrame) -> Option<([f64; 3], [f64; 3], f64)> {
    if f.box_bounds.len() < 3 {
        return None;
    }
    let [xy, xz, yz] = f.tilt.unwrap_or([0.0; 3]);
    let b = &f.box_bounds;
    let lo = [
        b[0][0] - 0f64.min(xy).min(xz).min(xy + xz),
        b[1][0] - 0f64.min(yz),
        b[2][0],
    ];
    let hi = [
        b[0][1] - 0f64.max(xy).max(xz).max(xy + xz),
        b[1][1] - 0f64.max(yz),
        b[2][1],
    ];
    let len = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    if xz != 0.0 || yz != 0.0 || len.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
        return None;
    }
    Some((lo, len, xy))
}

/// Maps the `x`, `y`, `z` values of `b` to the periodic image nearest `a`'s value for the same
/// atom and step, since the engines wrap atoms at different times (LAMMPS only when it
/// re-neighbours) and, in a tilted box, into different cells (LAMMPS the tilted cell, the
/// standalone engine the orthogonal one): the image is moved by whole lattice vectors
/// (L_x, 0, 0), (xy, L_y, 0), (0, 0, L_z), y first. A value is changed only when it is more than
/// half a box length away; image flags `ix iy iz`, when dumped, change with it (the unwrapped
/// position is kept). Returns how many atoms were shifted.
fn minimum_image(a: &[DumpFrame], b: &mut [DumpFrame]) -> usize {
    let mut shifted = 0;
    for fb in b.iter_mut() {
        let Some(fa) = a.iter().find(|f| f.step == fb.step) else {
            continue;
        };
        let Some((_, len, xy)) = frame_box(fb) else {
            continue;
        };
        let col = |f: &DumpFrame, name: &str| f.columns.iter().position(|c| c == name);
        let (Some(ida), Some(idb)) = (col(fa, "id"), col(fb, "id")) else {
            continue;
        };
        let by_id: std::collections::HashMap<i64, &Vec<f64>> =
            fa.rows.iter().map(|r| (r[ida] as i64, r)).collect();
        let ka: Vec<Option<usize>> = ["x", "y", "z"].iter().map(|n| col(fa, n)).collect();
        let kb: Vec<Option<usize>> = ["x", "y", "z"].iter().map(|n| col(fb, n)).collect();
        let kimg: Vec<Option<usize>> = ["ix", "iy", "iz"].iter().map(|n| col(fb, n)).collect();
        for rb in fb.rows.iter_mut() {
            let Some(ra) = by_id.get(&(rb[idb] as i64)) else {
                continue;
            };
            let nb = rb.len();
            let pair = |d: usize| match (ka[d], kb[d]) {
                (Some(i), Some(j)) if i < ra.len() && j < nb => Some((i, j)),
                _ => None,
            };
            let mut moved = false;
            // A move by n lattice vectors along d changes the image flag by +n (the unwrapped
            // position is kept).
            let flag = |rb: &mut Vec<f64>, d: usize, n: f64| {
                if let Some(k) = kimg[d].filter(|&k| k < nb) {
                    rb[k] += n;
                }
            };
            // y first: a y image also moves x by the tilt.
            if let Some((i, j)) = pair(1) {
                let n = ((rb[j] - ra[i]) / len[1]).round();
                if n != 0.0 && n.is_finite() {
                    rb[j] -= n * len[1];
                    if let Some((_, jx)) = pair(0) {
                        rb[jx] -= n * xy;
                    }
                    flag(rb, 1, n);
                    moved = true;
                }
            }
            for d in [0, 2] {
                if let Some((i, j)) = pair(d) {
                    let n = ((rb[j] - ra[i]) / len[d]).round();
                    if n != 0.0 && n.is_finite() {
                        rb[j] -= n * len[d];
                        flag(rb, d, n);
                        moved = true;
                    }
                }
            }
            shifted += usize::from(moved);
        }
    }
    shifted
}
