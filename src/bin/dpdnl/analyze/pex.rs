//! `analyze nemd`: the PeX (reverse NEMD) viscosity from profiles and the pushed momentum.

use super::*;

pub(super) fn run_nemd(a: NemdArgs) -> Result<(), String> {
    let text = read(&a.profile)?;
    let chunk = in_file(&a.profile, parse_ave_chunk(&text))?;
    let (lx, ly, lz) = (a.r#box[0], a.r#box[1], a.r#box[2]);
    let cols = nemd::NemdColumns {
        x: "Coord1".into(),
        vz: a.vz_col.clone(),
        density: a.density_col.clone(),
        td: a.td_col.clone(),
    };
    let prof = in_file(
        &a.profile,
        nemd::profiles_from_chunk(&chunk, &cols, a.from, ly * lz),
    )?;
    let xlo = match a.xlo {
        Some(x) => x,
        None => {
            let n = prof.x.len();
            let dx = (prof.x[n - 1] - prof.x[0]) / (n - 1) as f64;
            if ((n as f64) * dx - lx).abs() > 1e-4 * lx {
                return Err(format!(
                    "{}: the {n} bins (width {dx}) do not tile Lx = {lx}; give --xlo",
                    a.profile.display()
                ));
            }
            prof.x[0] - 0.5 * dx
        }
    };
    let nominal =
        a.dp.map(|dp| nemd::pex_stress_nominal(dp, a.every, a.dt, ly, lz));
    let measured = match &a.push {
        Some(p) => {
            let s = in_file(p, parse_series(&read(p)?))?.from_step(a.from);
            let name = match &a.push_col {
                Some(c) => c.clone(),
                None => {
                    let f: Vec<&String> =
                        s.columns.iter().filter(|c| c.starts_with("f_")).collect();
                    match f.as_slice() {
                        [one] => (*one).clone(),
                        _ => {
                            return Err(format!(
                                "{}: cannot tell the pushed-momentum column (columns: {}); give --push-col",
                                p.display(),
                                s.columns.join(" ")
                            ));
                        }
                    }
                }
            };
            let col = in_file(p, s.column(&name))?;
            let (last, steps): (Vec<f64>, Vec<f64>) = col
                .iter()
                .zip(&s.steps)
                .filter(|(_, k)| **k <= prof.steps[prof.steps.len() - 1] as f64)
                .map(|(v, k)| (*v, *k))
                .unzip();
            Some((
                in_file(p, nemd::pex_stress_from_total(&steps, &last, a.dt, ly, lz))?,
                name,
            ))
        }
        None => None,
    };
    let (stress, stress_err, stress_source) = match (&measured, nominal) {
        (Some(((s, e), name)), _) => (*s, *e, format!("measured from {name}")),
        (None, Some(s)) => (s, 0.0, "nominal dp/(2 Ly Lz every dt)".to_string()),
        (None, None) => return Err("give --dp (nominal stress) or --push (measured)".into()),
    };
    let o = nemd::NemdOptions {
        xlo,
        lx,
        stress,
        stress_err,
        fit_fraction: a.fit_fraction,
    };
    let r = nemd::analyze(&prof, &o)?;
    let prefix = prefix(&a.out, &a.profile, "nemd")?;
    let label = a.label.clone().unwrap_or_else(|| {
        a.profile
            .file_stem()
            .map_or("nemd".into(), |s| s.to_string_lossy().into_owned())
    });

    println!(
        "NEMD (PeX): {} profiles, steps {}..{}, {} bins, xlo = {xlo}, Lx = {lx}",
        r.n_outputs,
        r.first_step,
        r.last_step,
        r.x.len()
    );
    println!(
        "  Pi_xz = {} ({stress_source}){}",
        pm(stress, stress_err),
        match (nominal, &measured) {
            (Some(n), Some(_)) => format!("; nominal {n:.6}"),
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
        "  shear rate {} (block {}x{}{}), viscosity mu = {}",
        pm(r.shear_rate.mean, r.shear_rate.stderr),
        r.shear_rate.n_blocks,
        r.shear_rate.block_len,
        if r.shear_rate.converged {
            ""
        } else {
            ", not converged"
        },
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

    let nan = vec![f64::NAN; r.x.len()];
    let fitline: Vec<f64> = (0..r.x.len())
        .map(|i| {
            r.halves
                .iter()
                .find_map(|h| {
                    h.bins
                        .iter()
                        .position(|&b| b == i)
                        .map(|k| h.fit.slope * h.x[k] + h.fit.intercept)
                })
                .unwrap_or(f64::NAN)
        })
        .collect();
    let (td_m, td_e) = r.td.as_ref().map_or((nan.clone(), nan.clone()), |t| {
        (t.mean.clone(), t.err.clone())
    });
    let mut written = vec![write_csv(
        &prefix,
        &[
            "x",
            "vz",
            "vz_err",
            "vz_fit",
            "td",
            "td_err",
            "density",
            "density_err",
        ],
        &[
            &r.x,
            &r.vz.mean,
            &r.vz.err,
            &fitline,
            &td_m,
            &td_e,
            &r.density.mean,
            &r.density.err,
        ],
    )?];
    let halves: Vec<Value> = r
        .halves
        .iter()
        .map(|h| {
            json!({
                "name": h.name, "window": [num(h.window.0), num(h.window.1)], "bins": h.bins.len(),
                "slope": num(h.slope.mean), "slope_err": num(h.slope.stderr),
                "slope_fit_mean_profile": num(h.fit.slope), "slope_fit_err_regression": num(h.fit.slope_err),
                "intercept": num(h.fit.intercept), "r2": num(h.fit.r2),
            })
        })
        .collect();
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "nemd", "label": label, "input": a.profile.display().to_string(),
            "box": [lx, ly, lz], "xlo": xlo, "dt": a.dt, "from_step": a.from,
            "n_outputs": r.n_outputs, "first_step": r.first_step, "last_step": r.last_step,
            "fit_fraction": r.fit_fraction, "halves": halves,
            "stress": num(stress), "stress_err": num(stress_err), "stress_source": stress_source,
            "stress_nominal": nominal.map_or(Value::Null, num),
            "shear_rate": num(r.shear_rate.mean), "shear_rate_err": num(r.shear_rate.stderr),
            "shear_rate_blocks": r.shear_rate.n_blocks, "shear_rate_converged": r.shear_rate.converged,
            "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
            "density_centre": num(r.density_centre.mean), "density_centre_err": num(r.density_centre.stderr),
            "td_centre": r.td_centre.map_or(Value::Null, |t| num(t.mean)),
            "td_centre_err": r.td_centre.map_or(Value::Null, |t| num(t.stderr)),
            "density_source": prof.density_source, "td_source": prof.td_source,
        }),
    )?);

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

// ---------------------------------------------------------------- eh
