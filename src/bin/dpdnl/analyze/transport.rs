//! `analyze eh` and `analyze msd`: Einstein–Helfand viscosity and self-diffusion (with Sc).

use super::*;
use dpdnl::report::transport::{self, EhParams, MsdParams, MsdSource};

pub(super) fn run_eh(a: EhArgs) -> Result<(), String> {
    let name = a.file.display().to_string();
    let s = report::series_from_text(&name, &read(&a.file)?)?;
    let p = EhParams {
        dt: a.dt,
        r#box: a.r#box.clone(),
        temp: a.temp,
        density: a.density,
        mass: a.mass,
        cols: a.cols.clone(),
        from: a.from,
        window_factor: a.window_factor,
        tmin: a.tmin,
        tmax: a.tmax,
        blocks: a.blocks,
    };
    let e = transport::eh(&name, s, &p)?;
    let (r, o, spacing) = (&e.result, &e.options, e.spacing);
    let prefix = prefix(&a.out, &a.file, "eh")?;

    println!(
        "Einstein–Helfand (eq. 59): {} samples every {} steps (Δ = {}), components {}",
        r.n_samples,
        spacing,
        o.dt_sample,
        e.components.join(" ")
    );
    println!(
        "  window [{:.4}, {:.4}] ({}); L²/(4π²ν) = {:.4}{}",
        r.t_min,
        r.t_max,
        r.window_source,
        r.tau_l,
        if r.capped {
            "; CAPPED by the run length (run longer for this window)"
        } else {
            ""
        }
    );
    println!(
        "  viscosity mu = {} ({} blocks); per component {}",
        pm(r.viscosity, r.viscosity_err),
        r.blocks.len(),
        r.per_component
            .iter()
            .map(|v| format!("{v:.5}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    println!(
        "  linearity: mu(second half of window) - mu(first half) = {}{}",
        pm(r.drift, r.drift_err),
        if e.not_linear {
            "  WARNING: not linear over the window (still in the transient); try a larger \
             --window-factor or a larger box"
        } else {
            ""
        }
    );
    let fitline = e.fit_line();
    let mut written = vec![write_csv(&prefix, &e.table())?];
    written.push(write_json(&prefix, &e.json())?);
    let show =
        r.t.iter()
            .position(|&t| t > 3.0 * r.t_max)
            .unwrap_or(r.t.len());
    let t = r.t[1..show].to_vec();
    let p1 = Panel::new(
        &format!(
            "EH running viscosity: μ = {}",
            pm(r.viscosity, r.viscosity_err)
        ),
        "t",
        "V ⟨(∫Π dt)²⟩ / (2 kT t)",
    )
    .with(Line::line("μ(t)", t.clone(), r.running[1..show].to_vec()))
    .with(Line::dashed("fitted μ", vec![t[0], t[t.len() - 1]], vec![r.viscosity; 2]).color(1))
    .band(r.t_min, r.t_max, "fit window")
    .legend(Legend::LowerRight);
    let p2 = Panel::new("Integrated stress", "t", "⟨(∫Π dt)²⟩")
        .with(Line::line(
            "all origins",
            t.clone(),
            r.msd[1..show].to_vec(),
        ))
        .with(Line::dashed("linear fit", t, fitline[1..show].to_vec()).color(1))
        .band(r.t_min, r.t_max, "fit window")
        .legend(Legend::UpperLeft);
    save_plot(&a.out, &prefix, Figure::grid(vec![p1, p2], 2), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- msd

pub(super) fn run_msd(a: MsdArgs) -> Result<(), String> {
    let name = a.file.display().to_string();
    let src = MsdSource::from_text(&name, &read(&a.file)?)?;
    let p = MsdParams {
        dt: a.dt,
        dim: a.dim,
        col: a.col.clone(),
        atoms: a.atoms,
        tmin: a.tmin,
        tmax: a.tmax,
        from: a.from,
    };
    let mut m = transport::msd(&name, src, &p)?;
    let eta = match (&a.eta_from, a.eta) {
        (Some(f), _) => Some(transport::viscosity_from_text(
            &f.display().to_string(),
            &read(f)?,
        )?),
        (None, Some(mu)) => Some((mu, a.eta_err, "--eta".to_string())),
        _ => None,
    };
    m.schmidt(eta, a.density, a.mass)?;
    let (r, sc) = (&m.result, m.schmidt);
    let prefix = prefix(&a.out, &a.file, "msd")?;
    println!(
        "MSD, d = {}: {}; window [{:.4}, {:.4}]",
        a.dim, r.method, r.t_min, r.t_max
    );
    println!("  D = {} ({})", pm(r.d, r.d_err), r.d_err_method);
    if let Some((s, e)) = sc {
        println!("  Sc = mu/(rho D) = {}", pm(s, e));
    }
    let fitline = m.fit_line();
    let mut written = vec![write_csv(&prefix, &m.table())?];
    written.push(write_json(&prefix, &m.json())?);
    let mut line = Line::points("MSD", r.t.clone(), r.msd.clone());
    if let Some(e) = &r.msd_err {
        line = line.errors(e.clone());
    }
    let p = Panel::new(&format!("MSD: D = {}", pm(r.d, r.d_err)), "t", "MSD")
        .with(line)
        .with(Line::dashed("linear fit", r.t.clone(), fitline).color(1))
        .band(r.t_min, r.t_max, "fit window")
        .legend(Legend::UpperLeft);
    save_plot(&a.out, &prefix, Figure::single(p), &mut written)?;
    print_written(&written);
    Ok(())
}

// ---------------------------------------------------------------- couette
