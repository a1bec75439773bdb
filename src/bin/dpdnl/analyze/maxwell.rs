//! `analyze mb`: the Maxwell–Boltzmann check of velocity histograms or dumps.

use super::*;

pub(super) fn run_mb(a: MbArgs) -> Result<(), String> {
    let mut hist: Option<mb::SpeedHistogram> = None;
    let mut dim = a.dim;
    let mut speeds: Vec<Vec<f64>> = Vec::new();
    let mut dump_frames = 0;
    for f in &a.files {
        let text = read(f)?;
        match detect(&text) {
            FileKind::AveHisto => {
                let h = in_file(f, parse_ave_histo(&text))?;
                let h = in_file(f, mb::SpeedHistogram::from_ave_histo(&h, a.from))?;
                hist = Some(match hist {
                    None => h,
                    Some(mut acc) => {
                        if acc.edges != h.edges {
                            return Err(format!(
                                "{}: bins differ from those of the first histogram file",
                                f.display()
                            ));
                        }
                        for (x, y) in acc.counts.iter_mut().zip(&h.counts) {
                            *x += y;
                        }
                        acc.outside += h.outside;
                        acc.blocks.extend(h.blocks);
                        acc.note = format!("{}; + {}", acc.note, h.note);
                        acc
                    }
                });
            }
            FileKind::Dump => {
                let frames = in_file(f, parse_dump(&text))?;
                for fr in frames.iter().filter(|fr| fr.step >= a.from) {
                    let (v, d) = in_file(f, mb::frame_speeds(fr, dim))?;
                    dim.get_or_insert(d);
                    speeds.push(v);
                    dump_frames += 1;
                }
            }
            other => {
                return Err(format!(
                    "{}: expected a fix ave/histo file or a dump, found {other:?}",
                    f.display()
                ));
            }
        }
    }
    let dim = dim.unwrap_or(3);
    let vmax = a.vmax.unwrap_or(2.0 * (10.0 * a.temp / a.mass).sqrt());
    if !speeds.is_empty() {
        if hist.is_some() {
            return Err("give either fix ave/histo files or dumps, not both".into());
        }
        if a.bins == 0 || !is_pos(vmax) {
            return Err("--bins and --vmax must be positive".into());
        }
        hist = Some(mb::SpeedHistogram::from_samples(
            &speeds,
            mb::uniform_edges(0.0, vmax, a.bins),
        )?);
    }
    let h = hist.ok_or("no histogram or dump frame to analyse")?;
    let o = mb::MbOptions {
        kt: a.temp,
        mass: a.mass,
        dim,
        min_expected: 5.0,
    };
    let r = mb::analyze(&h, &o)?;
    let prefix = prefix(&a.out, &a.files[0], "mb")?;

    let kt_err = r.kt_fit_err_blocks.unwrap_or(r.kt_fit_err_iid);
    println!(
        "Maxwell–Boltzmann, d = {dim}: {} samples ({}; {} blocks), {} bins on [{}, {}]",
        r.n_total,
        if dump_frames > 0 {
            format!("{dump_frames} dump frames")
        } else {
            h.note.clone()
        },
        r.n_blocks,
        r.bins.len(),
        h.edges[0],
        h.edges[h.edges.len() - 1]
    );
    println!(
        "  kT fitted {} (set {}; error {}), outside range {} (expected {:.1})",
        pm(r.kt_fit, kt_err),
        a.temp,
        if r.kt_fit_err_blocks.is_some() {
            "from blocks"
        } else {
            "iid"
        },
        r.outside,
        r.outside_expected
    );
    println!(
        "  chi2 = {:.2} for {} dof (p = {:.3e}{}); KS D = {:.3e} (p = {:.3e})",
        r.chi2,
        r.dof,
        r.p_value,
        match (r.inefficiency, r.p_value_corrected) {
            (Some(g), Some(p)) => format!("; inefficiency g = {g:.2}, corrected p = {p:.3e}"),
            _ => String::new(),
        },
        r.ks_d,
        r.ks_p
    );

    let lo: Vec<f64> = r.bins.iter().map(|b| b.lo).collect();
    let hi: Vec<f64> = r.bins.iter().map(|b| b.hi).collect();
    let mid: Vec<f64> = r.bins.iter().map(|b| 0.5 * (b.lo + b.hi)).collect();
    let count: Vec<f64> = r.bins.iter().map(|b| b.count).collect();
    let pdf: Vec<f64> = r.bins.iter().map(|b| b.pdf).collect();
    let err: Vec<f64> = r.bins.iter().map(|b| b.pdf_err).collect();
    let set: Vec<f64> = r.bins.iter().map(|b| b.pdf_set).collect();
    let fit: Vec<f64> = r.bins.iter().map(|b| b.pdf_fit).collect();
    let expected: Vec<f64> = r.bins.iter().map(|b| b.expected).collect();
    let resid: Vec<f64> = (0..r.bins.len())
        .map(|i| {
            if err[i] > 0.0 {
                (pdf[i] - set[i]) / err[i]
            } else {
                f64::NAN
            }
        })
        .collect();
    let mut written = vec![write_csv(
        &prefix,
        &[
            "v_lo",
            "v_hi",
            "v_mid",
            "count",
            "expected_count",
            "pdf",
            "pdf_err",
            "pdf_mb_set",
            "pdf_mb_fit",
            "residual_sigma",
        ],
        &[
            &lo, &hi, &mid, &count, &expected, &pdf, &err, &set, &fit, &resid,
        ],
    )?];
    written.push(write_json(
        &prefix,
        &json!({
            "analysis": "mb",
            "inputs": a.files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            "dim": dim, "mass": a.mass, "kt_set": a.temp,
            "n_samples": num(r.n_total), "n_blocks": r.n_blocks, "source": h.note,
            "v_lo": num(h.edges[0]), "v_hi": num(h.edges[h.edges.len() - 1]), "bins": r.bins.len(),
            "outside": num(r.outside), "outside_expected": num(r.outside_expected),
            "kt_fit": num(r.kt_fit), "kt_fit_err_iid": num(r.kt_fit_err_iid),
            "kt_fit_err_blocks": r.kt_fit_err_blocks.map_or(Value::Null, num),
            "inefficiency": r.inefficiency.map_or(Value::Null, num),
            "chi2": num(r.chi2), "dof": r.dof, "p_value": num(r.p_value),
            "p_value_corrected": r.p_value_corrected.map_or(Value::Null, num),
            "chi2_fit": num(r.chi2_fit), "dof_fit": r.dof_fit, "p_value_fit": num(r.p_value_fit),
            "ks_d": num(r.ks_d), "ks_p": num(r.ks_p),
        }),
    )?);
    // Smooth MB curves for the figure.
    let vmax_plot = h.edges[h.edges.len() - 1];
    let vs: Vec<f64> = (0..=400).map(|i| vmax_plot * i as f64 / 400.0).collect();
    let curve = |kt: f64| {
        vs.iter()
            .map(|&v| mb::mb_pdf(v, kt, a.mass, dim))
            .collect::<Vec<_>>()
    };
    let p1 = Panel::new(&format!("Speed distribution, d = {dim}"), "speed v", "P(v)")
        .with(Line::points("measured", mid.clone(), pdf).errors(err))
        .with(Line::dashed(
            &format!("Maxwell–Boltzmann, kT = {}", a.temp),
            vs.clone(),
            curve(a.temp),
        ))
        .with(Line::line(
            &format!("MB at fitted kT = {:.5}", r.kt_fit),
            vs.clone(),
            curve(r.kt_fit),
        ));
    let p2 = Panel::new(
        &match r.p_value_corrected {
            Some(pc) => format!(
                "χ² = {:.1} / {} dof, p = {:.2e} (corrected for correlation: {:.2e})",
                r.chi2, r.dof, r.p_value, pc
            ),
            None => format!("χ² = {:.1} / {} dof, p = {:.2e}", r.chi2, r.dof, r.p_value),
        },
        "speed v",
        "(measured − MB) / error",
    )
    .with(Line::points("", mid.clone(), resid))
    .with(Line::dashed("±2σ", vec![0.0, vmax_plot], vec![2.0, 2.0]).color(6))
    .with(Line::dashed("", vec![0.0, vmax_plot], vec![-2.0, -2.0]).color(6));
    save_plot(&a.out, &prefix, Figure::grid(vec![p1, p2], 2), &mut written)?;
    print_written(&written);
    Ok(())
}
