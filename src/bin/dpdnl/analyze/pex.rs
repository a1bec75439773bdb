//! `analyze nemd`: the PeX (reverse NEMD) viscosity from profiles and the pushed momentum.

use super::*;
use dpdnl::analysis::nemd::NemdReport;
use dpdnl::report::nemd::{self, NemdAnalysis, NemdParams};

pub(super) fn run_nemd(a: NemdArgs) -> Result<(), String> {
    let (lx, ly, lz) = (a.r#box[0], a.r#box[1], a.r#box[2]);
    let p = NemdParams {
        r#box: [lx, ly, lz],
        xlo: a.xlo,
        dt: a.dt,
        dp: a.dp,
        every: a.every,
        push_col: a.push_col.clone(),
        from: a.from,
        fit_fraction: a.fit_fraction,
        vz_col: a.vz_col.clone(),
        density_col: a.density_col.clone(),
        td_col: a.td_col.clone(),
    };
    let name = a.profile.display().to_string();
    let prof = nemd::profiles(&name, &read(&a.profile)?, &p)?;
    let push = match &a.push {
        Some(f) => {
            let name = f.display().to_string();
            let s = report::series_from_text(&name, &read(f)?)?;
            Some((name, s))
        }
        None => None,
    };
    let label = a
        .label
        .clone()
        .unwrap_or_else(|| report::stem(&a.profile, "nemd"));
    let n = nemd::analyze(prof, push, &p, label)?;
    let r = &n.result;
    let xlo = n.xlo;
    let prefix = prefix(&a.out, &a.profile, "nemd")?;

    print_summary(&n, lx);

    let mut written = vec![write_csv(&prefix, &n.table())?];
    written.push(write_json(&prefix, &n.json())?);

    let pv = velocity_panel(r, xlo, lx);
    let mut panels = vec![pv];
    if let Some(t) = &r.td {
        panels.push(
            Panel::new("Dynamic temperature (eq. 58)", "x", "k_B T_d")
                .with(Line::points("T_d", r.x.clone(), t.mean.clone()).errors(t.err.clone())),
        );
    }
    panels.push(
        Panel::new("Density", "x", "n")
            .with(
                Line::points("density", r.x.clone(), r.density.mean.clone())
                    .errors(r.density.err.clone()),
            )
            .legend(Legend::LowerRight),
    );
    let cols = panels.len();
    save_plot(&a.out, &prefix, Figure::grid(panels, cols), &mut written)?;
    print_written(&written);
    Ok(())
}

/// The summary lines of `analyze nemd` (box length `lx`).
fn print_summary(n: &NemdAnalysis, lx: f64) {
    let r = &n.result;
    let xlo = n.xlo;
    let (stress, stress_err) = (n.stress, n.stress_err);
    println!(
        "NEMD (PeX): {} profiles, steps {}..{}, {} bins, xlo = {xlo}, Lx = {lx}",
        r.n_outputs,
        r.first_step,
        r.last_step,
        r.x.len()
    );
    println!(
        "  Pi_xz = {} ({}){}",
        pm(stress, stress_err),
        n.stress_source,
        match (n.stress_nominal, n.measured) {
            (Some(n), true) => format!("; nominal {n:.6}"),
            _ => String::new(),
        }
    );
    for h in &r.halves {
        println!(
            "  {:7} half: window [{:.4}, {:.4}] ({} bins), slope {}",
            h.name,
            h.window.0,
            h.window.1,
            h.bins.len(),
            pm(h.slope.mean, h.slope.stderr)
        );
    }
    println!(
        "  shear rate {} ({}), viscosity mu = {}",
        pm(r.shear_rate.mean, r.shear_rate.stderr),
        blocking(&r.shear_rate),
        pm(r.viscosity, r.viscosity_err)
    );
    println!(
        "  centre: density {}{}",
        pm(r.density_centre.mean, r.density_centre.stderr),
        r.td_centre
            .map_or(" (no T_d column)".to_string(), |t| format!(
                ", T_d {}",
                pm(t.mean, t.stderr)
            ))
    );
}

/// The v_z panel of `analyze nemd`: the profile, each half's linear fit over its window (the
/// outer one on both ends of the box, from `xlo` to `xlo + lx`).
fn velocity_panel(r: &NemdReport, xlo: f64, lx: f64) -> Panel {
    let mut pv = Panel::new(
        &format!("v_z profile: μ = {}", pm(r.viscosity, r.viscosity_err)),
        "x",
        "v_z",
    )
    .with(Line::points("⟨v_z⟩", r.x.clone(), r.vz.mean.clone()).errors(r.vz.err.clone()));
    for (k, h) in r.halves.iter().enumerate() {
        let xs = vec![h.window.0, h.window.1];
        let ys: Vec<f64> = xs
            .iter()
            .map(|x| h.fit.slope * x + h.fit.intercept)
            .collect();
        // The outer window straddles the boundary: draw its fit on both ends of the box.
        if h.name == "outer" {
            let xlo_p = xlo;
            let xhi_p = xlo + lx;
            let y_at = |x: f64| h.fit.slope * x + h.fit.intercept;
            let left = (xlo_p, h.window.1);
            let right = (h.window.0 + lx, xhi_p);
            pv = pv
                .with(
                    Line::line(
                        "linear fit",
                        vec![left.0, left.1],
                        vec![y_at(left.0), y_at(left.1)],
                    )
                    .color(1),
                )
                .with(
                    Line::line(
                        "",
                        vec![right.0, right.1],
                        vec![y_at(right.0 - lx), y_at(right.1 - lx)],
                    )
                    .color(1),
                )
                .band(left.0, left.1, "")
                .band(right.0, right.1, "");
        } else {
            pv = pv
                .with(Line::line(if k == 0 { "" } else { "linear fit" }, xs.clone(), ys).color(1))
                .band(xs[0], xs[1], "fit window");
        }
    }
    pv
}

// ---------------------------------------------------------------- eh
