//! The report of `dpdnl bench`: one table per reference system, the scaling table.

use super::*;

/// The table of reference system `key` and the lines under it (cost ratios, memory).
pub(super) fn system(
    out: &mut String,
    key: &str,
    cases: &[Case],
    threads: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let rows: Vec<&Case> = cases.iter().filter(|c| c.sys.key == key).collect();
    let Some(first) = rows.first() else {
        return Ok(());
    };
    // A reference that failed gives no ratio ("–"), not NaN.
    let ok = |c: &&&Case| c.error.is_none() && !c.rates.is_empty();
    let reference = rows
        .iter()
        .filter(ok)
        .find(|c| matches!(c.engine, Engine::Lammps(_, t) if t > 0))
        .map(|c| median(&c.rates));
    let serial = rows
        .iter()
        .filter(ok)
        .find(|c| matches!(c.engine, Engine::Lammps(_, 0)))
        .map(|c| median(&c.rates));
    let cpu_median = |c: &Case| (!c.cpu_rates.is_empty()).then(|| median(&c.cpu_rates));
    let serial_cpu = rows
        .iter()
        .filter(ok)
        .find(|c| matches!(c.engine, Engine::Lammps(_, 0)))
        .and_then(|c| cpu_median(c));
    writeln!(
        out,
        "## {}: {} (N = {}, {} steps)\n",
        first.sys.key, first.sys.title, first.natoms, first.steps
    )?;
    writeln!(
        out,
        "| engine | friction/noise | M atom-steps/s (median) | range | × LAMMPS dpd/omp | × LAMMPS dpd (1 thread) | M atom-steps per CPU-s (median) | per CPU-s × LAMMPS dpd |"
    )?;
    writeln!(out, "|---|---|---:|---:|---:|---:|---:|---:|")?;
    for c in &rows {
        if let Some(e) = &c.error {
            writeln!(
                out,
                "| {} | {} | failed: {} | | | | | |",
                c.engine.label(),
                c.variant.label(),
                e.replace('|', "/").replace('\n', " ")
            )?;
            continue;
        }
        let m = median(&c.rates);
        let (lo, hi) = range(&c.rates);
        let ratio = |r: Option<f64>| r.map_or("–".to_string(), |r| format!("{:.2}", m / r));
        let cpu = cpu_median(c);
        let cpu_ratio = match (cpu, serial_cpu) {
            (Some(a), Some(b)) => format!("{:.2}", a / b),
            _ => "–".to_string(),
        };
        writeln!(
            out,
            "| {} | {} | {:.3} | {:.3}–{:.3} | {} | {} | {} | {cpu_ratio} |",
            c.engine.label(),
            c.variant.label(),
            m / 1e6,
            lo / 1e6,
            hi / 1e6,
            ratio(reference),
            ratio(serial),
            cpu.map_or("–".to_string(), |x| format!("{:.3}", x / 1e6)),
        )?;
    }
    writeln!(out)?;
    notes(out, &rows, threads)
}

/// The lines under a system's table: each variant's cost against plain DPD on the same engine,
/// the standalone engine's memory.
fn notes(
    out: &mut String,
    rows: &[&Case],
    threads: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let ok = |c: &&&Case| c.error.is_none() && !c.rates.is_empty();
    // Each variant against plain DPD on the same engine: (case, plain median / its median).
    let against_plain = |v: Variant| -> Vec<(&Case, f64)> {
        rows.iter()
            .filter(|c| c.variant == v)
            .filter(ok)
            .filter_map(|c| {
                rows.iter()
                    .filter(ok)
                    .find(|d| d.engine == c.engine && d.variant == Variant::Plain)
                    .map(|d| (*c, median(&d.rates) / median(&c.rates)))
            })
            .collect()
    };
    // The sheared (Lees–Edwards) path against the periodic one, per engine.
    for (c, cost) in against_plain(Variant::Sheared) {
        writeln!(
            out,
            "sheared (γ̇ = {SHEAR_RATE}) / periodic atom-steps/s, {}: {:.2}{}\n",
            c.engine.label(),
            1.0 / cost,
            if matches!(c.engine, Engine::Standalone(_)) {
                " (target >= 0.8)"
            } else {
                ""
            }
        )?;
    }
    // The sDPD step's cost against the DPD step's (plain), per engine.
    for (c, cost) in against_plain(Variant::Sdpd) {
        writeln!(
            out,
            "sdpd step cost / dpd step cost, {}: {:.2} (target <= 1.6)\n",
            c.engine.label(),
            cost
        )?;
    }
    for c in rows {
        if let (Some(m), Engine::Standalone(t)) = (c.memory, &c.engine)
            && *t == threads
            && matches!(c.variant, Variant::Plain | Variant::Sheared)
        {
            let n = c.natoms as f64;
            let lists = 4.0 * (m.pairs + m.working_pairs) as f64 / n;
            writeln!(
                out,
                "memory (standalone, {}): {:.0} B/atom atom data + {:.0} B/atom neighbour structures, of which {lists:.0} B/atom the lists ({:.1} listed pairs/atom, {:.1} in the working list); {} list builds in {} steps\n",
                c.variant.label(),
                m.atom as f64 / n,
                m.neighbor as f64 / n,
                m.pairs as f64 / n,
                m.working_pairs as f64 / n,
                m.builds,
                c.steps
            )?;
        }
    }
    Ok(())
}

/// The `--scaling` table: time per step against N.
pub(super) fn scaling(
    out: &mut String,
    scaling: &[ScalingPoint],
    threads: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    writeln!(
        out,
        "## scaling: standalone engine, {threads} thread{}, ideal DPD n = 16 (create_atoms random)\n",
        plural(threads)
    )?;
    writeln!(
        out,
        "| N | steps | time/step (ms) | ns per atom-step (median) | range | CPU ns per atom-step (median, all threads) | B/atom (data + neighbour) |"
    )?;
    writeln!(out, "|---:|---:|---:|---:|---:|---:|---:|")?;
    for pt in scaling {
        let (n, steps) = (pt.n, pt.steps);
        let m = median(&pt.rates);
        let (lo, hi) = range(&pt.rates);
        let bytes = pt.memory.map_or("–".to_string(), |m| {
            format!(
                "{:.0} + {:.0}",
                m.atom as f64 / n as f64,
                m.neighbor as f64 / n as f64
            )
        });
        let cpu = if pt.cpu_rates.is_empty() {
            "–".to_string()
        } else {
            format!("{:.1}", 1e9 / median(&pt.cpu_rates))
        };
        writeln!(
            out,
            "| {n} | {steps} | {:.3} | {:.1} | {:.1}–{:.1} | {cpu} | {bytes} |",
            1e3 * n as f64 / m,
            1e9 / m,
            1e9 / hi,
            1e9 / lo
        )?;
    }
    writeln!(out)?;
    Ok(())
}
