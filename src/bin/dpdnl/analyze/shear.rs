//! `analyze couette` and `analyze flowcurve`: Couette viscosity and the flow curve.

use super::*;
use dpdnl::report::shear::{self, CouetteParams, FlowCurve};
use std::fmt::Write as _;

pub(super) fn run_couette(a: CouetteArgs) -> Result<(), String> {
    let name = a.file.display().to_string();
    let s = report::series_from_text(&name, &read(&a.file)?)?;
    let p = CouetteParams {
        col: a.col.clone(),
        rate: a.rate,
        v_col: a.v_col.clone(),
        y_col: a.y_col.clone(),
        y_scale: a.y_scale,
        from: a.from,
    };
    let s = shear::series(&name, s, &p)?;
    let profile = match &a.profile {
        Some(f) => Some((f.display().to_string(), read(f)?)),
        None => None,
    };
    let label = a
        .label
        .clone()
        .unwrap_or_else(|| report::stem(&a.file, "couette"));
    let c = shear::analyze(
        s,
        profile.as_ref().map(|(n, t)| (n.as_str(), t.as_str())),
        &p,
        label,
    )?;
    let r = &c.result;
    let prefix = prefix(&a.out, &a.file, "couette")?;
    println!(
        "Couette: {} samples of {}; <P_xy> = {} ({})",
        r.n_samples,
        c.column,
        pm(r.pxy.mean, r.pxy.stderr),
        blocking(&r.pxy)
    );
    let mut msg = String::new();
    if let (Some(p), Some(g)) = (&c.profile, a.rate) {
        let _ = write!(
            msg,
            " (imposed {g}, profile {})",
            pm(p.rate.mean, p.rate.stderr)
        );
    }
    println!(
        "  shear rate {} ({}){msg}; eta* = -<P_xy>/rate = {}",
        pm(c.rate, c.rate_err),
        c.rate_source,
        pm(r.viscosity, r.viscosity_err)
    );
    if let Some(p) = &c.profile
        && p.intercept.abs() > 3.0 * p.intercept_err
        && p.intercept_err > 0.0
    {
        println!(
            "  note: the fitted profile at coordinate 0 (y_lo with `units reduced`) is {}, not \
             0: the fluid moves relative to the streaming profile rate*(y - y_lo) that \
             temp/deform removes, which counts V^2/2 as heat. Box flips under plain `fix deform \
             ... remap v` leak this momentum (fix flip/momentum cures it); a `velocity ... \
             ramp` from another origin also offsets it",
            pm(p.intercept, p.intercept_err)
        );
    }
    let mut written = vec![write_csv(&prefix, &c.table())?];
    written.push(write_json(&prefix, &c.json())?);
    let (steps, pxy, running) = (c.steps.clone(), c.pxy.clone(), c.running_mean());
    let mut panels = vec![
        Panel::new(
            &format!("P_xy: η* = {}", pm(r.viscosity, r.viscosity_err)),
            "step",
            "P_xy",
        )
        .with(Line::line("P_xy", steps.clone(), pxy).color(5))
        .with(Line::line("running mean", steps, running).color(1)),
    ];
    if let (Some(p), Some(fit)) = (&c.profile, c.profile_fit()) {
        panels.push(
            Panel::new("Streaming velocity", "y", &a.v_col)
                .with(
                    Line::points("measured", p.y.clone(), p.v_mean.clone()).errors(p.v_err.clone()),
                )
                .with(Line::dashed("linear fit", p.y.clone(), fit).color(1))
                .legend(Legend::UpperLeft),
        );
    }
    let cols = panels.len();
    save_plot(&a.out, &prefix, Figure::grid(panels, cols), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- flow curve

pub(super) fn run_flow(a: FlowArgs) -> Result<(), String> {
    let mut curve = FlowCurve::default();
    for f in &a.files {
        curve.add_text(&f.display().to_string(), &read(f)?)?;
    }
    let curve = curve.sorted();
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let mut panel = Panel::new("Viscosity against shear rate", "shear rate", "viscosity")
        .log_x()
        .log_y()
        .legend(Legend::Auto);
    for (label, pts) in &curve.groups {
        println!("{label}:");
        for (r, e, err) in pts {
            println!("  rate {r:.5}  eta {}", pm(*e, *err));
        }
        panel = panel.with(
            Line::points_line(
                label,
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
            )
            .errors(pts.iter().map(|p| p.2).collect()),
        );
    }
    let csv_path = with_ext(&a.out, "csv");
    std::fs::write(&csv_path, curve.csv()).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let mut written = vec![csv_path];
    if !a.no_plot {
        written.extend(Figure::single(panel).save(&a.out)?);
    }
    print_written(&written);
    Ok(())
}
