//! `analyze mb`: the Maxwell–Boltzmann check of velocity histograms or dumps.

use super::*;
use dpdnl::analysis::mb::mb_pdf;
use dpdnl::report::mb::{self, MbInput, MbParams};

pub(super) fn run_mb(a: MbArgs) -> Result<(), String> {
    let mut input = MbInput::new(a.dim);
    for f in &a.files {
        input.add_text(&f.display().to_string(), &read(f)?, a.from)?;
    }
    let p = MbParams {
        temp: a.temp,
        mass: a.mass,
        bins: a.bins,
        vmax: a.vmax,
    };
    let m = mb::analyze(input, &p)?;
    let (r, dim) = (&m.result, m.dim);
    let prefix = prefix(&a.out, &a.files[0], "mb")?;
    let (v_lo, v_hi) = m.range();

    let kt_err = r.kt_fit_err_blocks.unwrap_or(r.kt_fit_err_iid);
    println!(
        "Maxwell–Boltzmann, d = {dim}: {} samples ({}; {} blocks), {} bins on [{v_lo}, {v_hi}]",
        r.n_total,
        if m.dump_frames > 0 {
            format!("{} dump frames", m.dump_frames)
        } else {
            m.hist.note.clone()
        },
        r.n_blocks,
        r.bins.len(),
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

    let table = m.table();
    let mut written = vec![write_csv(&prefix, &table)?];
    written.push(write_json(&prefix, &m.json())?);
    let col = |k: usize| table[k].1.clone();
    let (mid, pdf, err, resid) = (col(2), col(5), col(6), col(9));
    // Smooth MB curves for the figure.
    let vs: Vec<f64> = (0..=400).map(|i| v_hi * i as f64 / 400.0).collect();
    let curve = |kt: f64| {
        vs.iter()
            .map(|&v| mb_pdf(v, kt, a.mass, dim))
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
    .with(Line::points("", mid, resid))
    .with(Line::dashed("±2σ", vec![0.0, v_hi], vec![2.0, 2.0]).color(6))
    .with(Line::dashed("", vec![0.0, v_hi], vec![-2.0, -2.0]).color(6));
    save_plot(&a.out, &prefix, Figure::grid(vec![p1, p2], 2), &mut written)?;
    print_written(&written);
    Ok(())
}
