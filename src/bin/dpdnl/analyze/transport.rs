//! `analyze eh` and `analyze msd`: Einstein–Helfand viscosity and self-diffusion (with Sc).

use super::*;

pub(super) fn run_eh(a: EhArgs) -> Result<(), String> {
    let s = in_file(&a.file, parse_series(&read(&a.file)?))?.from_step(a.from);
    let dim = a.r#box.len();
    let names: Vec<String> = match &a.cols {
        Some(c) => c.clone(),
        None => {
            let want: &[&str] = if dim == 2 {
                &["pxy"]
            } else {
                &["pxy", "pxz", "pyz"]
            };
            if want.iter().all(|n| s.column_index(n).is_some()) {
                want.iter().map(|n| n.to_string()).collect()
            } else if let Some(v) = s.indexed_columns(if dim == 2 { &[4] } else { &[4, 5, 6] }) {
                v
            } else {
                return Err(format!(
                    "{}: cannot find the off-diagonal pressure columns (columns: {}); give --cols",
                    a.file.display(),
                    s.columns.join(" ")
                ));
            }
        }
    };
    let comps: Vec<&[f64]> = names
        .iter()
        .map(|n| in_file(&a.file, s.column(n)))
        .collect::<Result<_, _>>()?;
    let spacing = in_file(&a.file, step_spacing(&s.steps))?;
    let volume: f64 = a.r#box.iter().product();
    let box_len = a.r#box.iter().copied().fold(f64::INFINITY, f64::min);
    let mut o = eh::EhOptions::new(spacing * a.dt, volume, a.temp, box_len, a.density * a.mass);
    o.window_factor = a.window_factor;
    o.t_min = a.tmin;
    o.t_max = a.tmax;
    o.n_blocks = a.blocks;
    let r = in_file(&a.file, eh::analyze(&comps, &o))?;
    let prefix = prefix(&a.out, &a.file, "eh")?;

    println!(
        "Einstein–Helfand (eq. 59): {} samples every {} steps (Δ = {}), components {}",
        r.n_samples,
        spacing,
        o.dt_sample,
        names.join(" ")
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
    // Significant at 3 standard errors: the fitted slope is then biased beyond its error.
    let drifting =
        r.drift.is_finite() && r.drift_err.is_finite() && r.drift.abs() > 3.0 * r.drift_err;
    println!(
        "  linearity: mu(second half of window) - mu(first half) = {}{}",
        pm(r.drift, r.drift_err),
        if drifting {
            "  WARNING: not linear over the window (still in the transient); try a larger \
             --window-factor or a larger box"
        } else {
            ""
        }
    );
    let fitline: Vec<f64> =
        r.t.iter()
            .map(|t| r.fit.slope * t + r.fit.intercept)
            .collect();
    let mut written = vec![write_csv(
        &prefix,
        &["t", "msd_integral", "mu_running", "msd_fit"],
        &[&r.t, &r.msd, &r.running, &fitline],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "eh", "input": a.file.display().to_string(), "components": names,
            "dt": a.dt, "sample_interval": o.dt_sample, "n_samples": r.n_samples, "from_step": a.from,
            "volume": volume, "kt": a.temp, "box_len": box_len, "mass_density": o.mass_density,
            "t_min": num(r.t_min), "t_max": num(r.t_max), "tau_l": num(r.tau_l),
            "window_source": r.window_source, "window_capped": r.capped,
            "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
            "per_component": nums(&r.per_component), "blocks": nums(&r.blocks),
            "window_drift": num(r.drift), "window_drift_err": num(r.drift_err), "window_not_linear": drifting,
            "slope": num(r.fit.slope), "intercept": num(r.fit.intercept),
        }),
    )?);
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
    let text = read(&a.file)?;
    let mut o = msd::MsdOptions::new(a.dim);
    o.t_min = a.tmin;
    o.t_max = a.tmax;
    let r = if detect(&text) == FileKind::Dump {
        let frames: Vec<DumpFrame> = in_file(&a.file, parse_dump(&text))?
            .into_iter()
            .filter(|f| f.step >= a.from)
            .collect();
        let (steps, series, note) = in_file(&a.file, msd::unwrapped_series(&frames, a.dim))?;
        let st: Vec<f64> = steps.iter().map(|&k| k as f64).collect();
        let spacing = in_file(&a.file, step_spacing(&st))?;
        let mut r = in_file(
            &a.file,
            msd::from_trajectories(&series, a.dim, spacing * a.dt, &o),
        )?;
        r.method = format!("{} ({note})", r.method);
        r
    } else {
        let s = in_file(&a.file, parse_series(&text))?.from_step(a.from);
        let name = match &a.col {
            Some(c) => c.clone(),
            None => {
                let c: Vec<&String> = s
                    .columns
                    .iter()
                    .filter(|c| c.ends_with("[4]") || c.eq_ignore_ascii_case("msd"))
                    .collect();
                match c.as_slice() {
                    [one] => (*one).clone(),
                    _ => {
                        return Err(format!(
                            "{}: cannot tell the MSD column (columns: {}); give --col",
                            a.file.display(),
                            s.columns.join(" ")
                        ));
                    }
                }
            }
        };
        let m = in_file(&a.file, s.column(&name))?;
        let t: Vec<f64> = s.steps.iter().map(|k| k * a.dt).collect();
        in_file(&a.file, msd::from_series(&t, m, &o, a.atoms))?
    };
    let eta = match (&a.eta_from, a.eta) {
        (Some(p), _) => {
            let v: Value =
                serde_json::from_str(&read(p)?).map_err(|e| format!("{}: {e}", p.display()))?;
            let mu = v["viscosity"]
                .as_f64()
                .ok_or(format!("{}: no 'viscosity' number", p.display()))?;
            Some((
                mu,
                v["viscosity_err"].as_f64().unwrap_or(0.0),
                p.display().to_string(),
            ))
        }
        (None, Some(mu)) => Some((mu, a.eta_err, "--eta".to_string())),
        _ => None,
    };
    let sc = match (eta.as_ref(), a.density) {
        (Some((mu, mu_err, _)), Some(n)) => {
            Some(msd::schmidt(*mu, *mu_err, n * a.mass, r.d, r.d_err))
        }
        (Some(_), None) => return Err("the Schmidt number needs --density".into()),
        _ => None,
    };
    let prefix = prefix(&a.out, &a.file, "msd")?;
    println!(
        "MSD, d = {}: {}; window [{:.4}, {:.4}]",
        a.dim, r.method, r.t_min, r.t_max
    );
    println!("  D = {} ({})", pm(r.d, r.d_err), r.d_err_method);
    if let Some((s, e)) = sc {
        println!("  Sc = mu/(rho D) = {}", pm(s, e));
    }
    let fitline: Vec<f64> =
        r.t.iter()
            .map(|t| r.fit.slope * t + r.fit.intercept)
            .collect();
    let err = r
        .msd_err
        .clone()
        .unwrap_or_else(|| vec![f64::NAN; r.t.len()]);
    let mut written = vec![write_csv(
        &prefix,
        &["t", "msd", "msd_err", "msd_fit"],
        &[&r.t, &r.msd, &err, &fitline],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "msd", "input": a.file.display().to_string(), "dim": a.dim, "dt": a.dt,
            "method": r.method, "t_min": num(r.t_min), "t_max": num(r.t_max),
            "diffusion": num(r.d), "diffusion_err": num(r.d_err), "diffusion_err_method": r.d_err_method,
            "diffusion_groups": nums(&r.d_groups),
            "viscosity": eta.as_ref().map_or(Value::Null, |e| num(e.0)),
            "viscosity_source": eta.as_ref().map(|e| e.2.clone()),
            "schmidt": sc.map_or(Value::Null, |s| num(s.0)), "schmidt_err": sc.map_or(Value::Null, |s| num(s.1)),
        }),
    )?);
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
