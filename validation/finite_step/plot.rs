//! Plot and tabulate the Euler finite-step sweep (`validation/finite_step/sweep.sh` CSVs):
//! measured T/T0 against eq. 22 of the finite-step paper, T_eq/T0 = 1/(1 − δt/δt_c).
//!
//! `cargo run --release --example finite_step_plot -- OUT_PREFIX SWEEP.csv…` writes
//! OUT_PREFIX.png/.svg and the markdown table OUT_PREFIX.md (also printed; the README's copy is
//! kept equal to it by `validation/sync_tables.py`). A point is "unstable" when its temperature
//! ran away (T/T0 > 3 × eq. 22's value): its block average is then not an equilibrium value; a
//! point whose run the engine's blow-up check stopped (a non-finite value, or an atom moving more
//! than half the box in one step) has T = inf in the sweep CSV and is listed as such.

use dpdnl::plot::{Figure, Legend, Panel, Series};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

struct Point {
    frac: f64,
    dt: f64,
    t: f64,
    err: f64,
    pred: f64,
}

fn read(path: &str, by_n: &mut BTreeMap<u64, (String, Vec<Point>)>) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or(format!("{path}: empty"))?
        .split(',')
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or(format!("{path}: no column '{name}'"))
    };
    let (cn, cf, cdt, ct, ce, cp) = (
        col("n")?,
        col("dt_over_dtc")?,
        col("dt")?,
        col("T_over_T0")?,
        col("err")?,
        col("eq22")?,
    );
    for (k, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> Result<f64, String> {
            f.get(i)
                .and_then(|v| v.parse().ok())
                .ok_or(format!("{path}:{}: bad field {i} in '{line}'", k + 2))
        };
        let n = num(cn)?;
        let key = (n * 1e6).round() as u64;
        let entry = by_n
            .entry(key)
            .or_insert_with(|| (f[cn].to_string(), Vec::new()));
        entry.1.push(Point {
            frac: num(cf)?,
            dt: num(cdt)?,
            t: num(ct)?,
            err: num(ce)?,
            pred: num(cp)?,
        });
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        eprintln!("usage: finite_step_plot OUT_PREFIX SWEEP.csv...");
        return ExitCode::FAILURE;
    }
    let mut by_n: BTreeMap<u64, (String, Vec<Point>)> = BTreeMap::new();
    for p in &args[1..] {
        if let Err(e) = read(p, &mut by_n) {
            eprintln!("ERROR: {e}");
            return ExitCode::FAILURE;
        }
    }
    let mut temp = Panel::new(
        "Euler, 2-D ideal fluid: T/T0 vs dt/dt_c",
        "dt / dt_c (eq. 25)",
        "T / T0",
    )
    .legend(Legend::UpperLeft);
    let mut excess = Panel::new(
        "Measured excess over eq. 22's: (T/T0 - 1) / (eq. 22 - 1)",
        "dt / dt_c (eq. 25)",
        "ratio",
    )
    .legend(Legend::LowerRight);
    let curve: Vec<f64> = (0..=144).map(|k| k as f64 * 0.005).collect();
    temp = temp.with(Series::line(
        "eq. 22: 1/(1 - dt/dt_c)",
        curve.clone(),
        curve.iter().map(|f| 1.0 / (1.0 - f)).collect(),
    ));
    excess = excess.with(Series::dashed("eq. 22", vec![0.0, 0.72], vec![1.0, 1.0]));
    let mut table = String::from(
        "## Euler: T/T0 against eq. 22 (2-D ideal fluid)\n\n\
         | n | dt | dt/dt_c | T/T0 measured | eq. 22 | (T/T0−1)/(eq.22−1) |\n|---|---|---|---|---|---|\n",
    );
    for (idx, (n, pts)) in by_n.values_mut().enumerate() {
        // Repeated points (several sweeps): keep the most precise one.
        pts.sort_by(|a, b| a.frac.total_cmp(&b.frac).then(a.err.total_cmp(&b.err)));
        pts.dedup_by(|b, a| (a.frac - b.frac).abs() < 1e-12);
        let stable: Vec<&Point> = pts.iter().filter(|p| p.t < 3.0 * p.pred).collect();
        for p in pts.iter() {
            let unstable = p.t >= 3.0 * p.pred;
            let ratio = (p.t - 1.0) / (p.pred - 1.0);
            // Writing to a String cannot fail.
            let _ = writeln!(
                table,
                "| {n} | {:.4} | {} | {} | {:.4} | {} |",
                p.dt,
                p.frac,
                if !p.t.is_finite() {
                    // sweep.sh records T = inf when the engine's blow-up check stopped the run.
                    "unstable (stopped by the blow-up check)".to_string()
                } else if unstable {
                    format!("unstable (ran away to {:.0})", p.t)
                } else {
                    format!("{:.4} ± {:.4}", p.t, p.err)
                },
                p.pred,
                if unstable {
                    "—".to_string()
                } else {
                    format!("{ratio:.2} ± {:.2}", p.err / (p.pred - 1.0))
                }
            );
        }
        let x: Vec<f64> = stable.iter().map(|p| p.frac).collect();
        temp = temp.with(
            Series::points(
                &format!("n = {n}"),
                x.clone(),
                stable.iter().map(|p| p.t).collect(),
            )
            .errors(stable.iter().map(|p| p.err).collect())
            .color(idx + 1),
        );
        excess = excess.with(
            Series::points_line(
                &format!("n = {n}"),
                x,
                stable
                    .iter()
                    .map(|p| (p.t - 1.0) / (p.pred - 1.0))
                    .collect(),
            )
            .errors(stable.iter().map(|p| p.err / (p.pred - 1.0)).collect())
            .color(idx + 1),
        );
    }
    print!("{table}");
    let md = format!("{}.md", args[0]);
    if let Err(e) = std::fs::write(&md, &table) {
        eprintln!("ERROR: {md}: {e}");
        return ExitCode::FAILURE;
    }
    let temp = temp.x_range(0.0, 0.72);
    let excess = excess.x_range(0.0, 0.72).y_range(0.4, 1.3);
    match Figure::grid(vec![temp, excess], 2).save(Path::new(&args[0])) {
        Ok([png, svg]) => {
            eprintln!("wrote {} and {}", png.display(), svg.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("ERROR: {e}");
            ExitCode::FAILURE
        }
    }
}
