//! `analyze couette` and `analyze flowcurve`: Couette viscosity and the flow curve.

use super::*;

pub(super) fn run_couette(a: CouetteArgs) -> Result<(), String> {
    let s = in_file(&a.file, parse_series(&read(&a.file)?))?.from_step(a.from);
    let name = match &a.col {
        Some(c) => c.clone(),
        None if s.column_index("pxy").is_some() => "pxy".into(),
        None => s
            .indexed_columns(&[4])
            .map(|v| v[0].clone())
            .ok_or(format!(
                "{}: no pxy column (columns: {}); give --col",
                a.file.display(),
                s.columns.join(" ")
            ))?,
    };
    let pxy = in_file(&a.file, s.column(&name))?;
    let profile = match &a.profile {
        Some(p) => {
            let chunk = in_file(p, parse_ave_chunk(&read(p)?))?;
            if !is_pos(a.y_scale) {
                return Err(format!("--y-scale must be positive (got {})", a.y_scale));
            }
            let mut r = in_file(
                p,
                couette::rate_from_profile(&chunk, &a.y_col, &a.v_col, a.from),
            )?;
            r.y.iter_mut().for_each(|y| *y *= a.y_scale);
            r.rate.mean /= a.y_scale;
            r.rate.stderr /= a.y_scale;
            Some(r)
        }
        None => None,
    };
    let (rate, rate_err, rate_source) = match (&profile, a.rate) {
        (Some(p), _) => (
            p.rate.mean,
            p.rate.stderr,
            "measured from the profile".to_string(),
        ),
        (None, Some(g)) => (g, 0.0, "imposed".to_string()),
        (None, None) => return Err("give --rate (imposed) or --profile (measured)".into()),
    };
    let r = couette::analyze(pxy, rate, rate_err)?;
    let prefix = prefix(&a.out, &a.file, "couette")?;
    let label = a.label.clone().unwrap_or_else(|| {
        a.file
            .file_stem()
            .map_or("couette".into(), |s| s.to_string_lossy().into_owned())
    });
    println!(
        "Couette: {} samples of {name}; <P_xy> = {} (block {}x{}{})",
        r.n_samples,
        pm(r.pxy.mean, r.pxy.stderr),
        r.pxy.n_blocks,
        r.pxy.block_len,
        if r.pxy.converged {
            ""
        } else {
            ", not converged"
        }
    );
    let mut msg = String::new();
    if let (Some(p), Some(g)) = (&profile, a.rate) {
        let _ = write!(
            msg,
            " (imposed {g}, profile {})",
            pm(p.rate.mean, p.rate.stderr)
        );
    }
    println!(
        "  shear rate {} ({rate_source}){msg}; eta* = -<P_xy>/rate = {}",
        pm(rate, rate_err),
        pm(r.viscosity, r.viscosity_err)
    );
    let steps = s.steps.clone();
    let mut running = Vec::with_capacity(pxy.len());
    let mut acc = 0.0;
    for (k, v) in pxy.iter().enumerate() {
        acc += v;
        running.push(acc / (k + 1) as f64);
    }
    let mut written = vec![write_csv(
        &prefix,
        &["step", "pxy", "pxy_running_mean"],
        &[&steps, pxy, &running],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "couette", "label": label, "input": a.file.display().to_string(), "column": name,
            "n_samples": r.n_samples, "from_step": a.from,
            "pxy": num(r.pxy.mean), "pxy_err": num(r.pxy.stderr),
            "shear_rate": num(rate), "shear_rate_err": num(rate_err), "shear_rate_source": rate_source,
            "shear_rate_imposed": a.rate.map_or(Value::Null, num),
            "viscosity": num(r.viscosity), "viscosity_err": num(r.viscosity_err),
        }),
    )?);
    let mut panels = vec![
        Panel::new(
            &format!("P_xy: η* = {}", pm(r.viscosity, r.viscosity_err)),
            "step",
            "P_xy",
        )
        .with(Line::line("P_xy", steps.clone(), pxy.to_vec()).color(5))
        .with(Line::line("running mean", steps, running).color(1)),
    ];
    if let Some(p) = &profile {
        let fit: Vec<f64> = p.y.iter().map(|y| p.rate.mean * y + p.intercept).collect();
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

/// (shear rate, viscosity, its error).
type FlowPoint = (f64, f64, f64);

pub(super) fn run_flow(a: FlowArgs) -> Result<(), String> {
    let mut groups: Vec<(String, Vec<FlowPoint>)> = Vec::new();
    let mut add = |label: String, p: (f64, f64, f64)| match groups.iter_mut().find(|g| g.0 == label)
    {
        Some(g) => g.1.push(p),
        None => groups.push((label, vec![p])),
    };
    for f in &a.files {
        let text = read(f)?;
        if text.trim_start().starts_with('{') {
            let v: Value =
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", f.display()))?;
            let get = |k: &str| {
                v[k].as_f64()
                    .ok_or(format!("{}: no number '{k}'", f.display()))
            };
            let label = v["label"].as_str().unwrap_or("result").to_string();
            add(
                label,
                (
                    get("shear_rate")?.abs(),
                    get("viscosity")?,
                    v["viscosity_err"].as_f64().unwrap_or(0.0),
                ),
            );
        } else {
            let mut lines = text
                .lines()
                .enumerate()
                .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
            let (_, header) = lines.next().ok_or(format!("{}: empty CSV", f.display()))?;
            let cols: Vec<&str> = header.split(',').map(str::trim).collect();
            let idx = |n: &str| {
                cols.iter().position(|c| *c == n).ok_or(format!(
                    "{}: line 1: the CSV header has no '{n}' column",
                    f.display()
                ))
            };
            let (jl, jr, je, jerr) = (
                idx("label")?,
                idx("rate")?,
                idx("eta")?,
                idx("eta_err").ok(),
            );
            for (i, l) in lines {
                let t: Vec<&str> = l.split(',').map(str::trim).collect();
                let val = |j: usize| -> Result<f64, String> {
                    let tok = t.get(j).copied().unwrap_or("");
                    tok.parse().map_err(|_| {
                        format!(
                            "{}: line {}: cannot read '{tok}' as a number",
                            f.display(),
                            i + 1
                        )
                    })
                };
                let label = t.get(jl).copied().unwrap_or("").to_string();
                add(
                    label,
                    (
                        val(jr)?.abs(),
                        val(je)?,
                        match jerr {
                            Some(j) => val(j)?,
                            None => 0.0,
                        },
                    ),
                );
            }
        }
    }
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let mut panel = Panel::new("Viscosity against shear rate", "shear rate", "viscosity")
        .log_x()
        .log_y()
        .legend(Legend::LowerLeft);
    let mut csv = String::from("label,rate,eta,eta_err\n");
    for (label, pts) in &mut groups {
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        println!("{label}:");
        for (r, e, err) in pts.iter() {
            println!("  rate {r:.5}  eta {}", pm(*e, *err));
            let _ = writeln!(csv, "{label},{r},{e},{err}");
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
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let mut written = vec![csv_path];
    if !a.no_plot {
        written.extend(Figure::single(panel).save(&a.out)?);
    }
    print_written(&written);
    Ok(())
}
