//! The drop of `examples/droplet/` under shear: its deformation against the capillary number,
//! for friction none and cross (run by `examples/droplet/run.sh`).
//!
//! `cargo run --release --example droplet_plot -- OUT_PREFIX DIR R0 RATE…` reads, in DIR, the
//! standalone logs `log.layer` (the flat layer at rest) and `log.{none,cross}_RATE`, and the
//! dumps `dump.drop.{none,cross}_RATE`; it writes OUT_PREFIX.png/.svg (the figure) and
//! OUT_PREFIX.md (the table, also printed).
//!
//! - Interfacial tension: Γ = (L_z/2) ⟨P_zz − (P_xx + P_yy)/2⟩ over the layer run's production
//!   (two flat interfaces normal to z).
//! - Shear stress σ = −⟨P_xy⟩ and the drop's deformation D = (L − B)/(L + B) over the second
//!   half of each sheared run; L and B are the square roots of the eigenvalues of the drop's
//!   gyration tensor in the shear plane (xx, xy, yy), which are a²/5 and b²/5 for an ellipsoid
//!   of semi-axes a and b. The drop's atoms are the type-1 atoms within 2 R0 of its centre
//!   (minimum images in the sheared box, about the centre of the frame before; an atom
//!   dissolved in the other liquid is left out).
//! - Ca = R0 σ / Γ: the measured stress, so that a thinned liquid has the Ca of its own stress;
//!   Taylor's small-deformation result for equal viscosities, D = (35/32) Ca, is drawn for
//!   reference (an unbounded Newtonian drop; this one is in a periodic box of 4 R0).
//!
//! Errors: Flyvbjerg–Petersen blocking of each series (`dpdnl::stats::block_average`).

use dpdnl::io::dump_read::{DumpFrame, parse_dump};
use dpdnl::io::lammps_log::{ThermoBlock, parse_log};
use dpdnl::plot::{Figure, Legend, Panel, Series};
use dpdnl::stats::block_average;
use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The production block (the last thermo block) of a log.
fn production(path: &Path) -> Result<ThermoBlock, String> {
    let blocks = parse_log(&read(path)?).map_err(|e| format!("{}: {e}", path.display()))?;
    blocks
        .last()
        .cloned()
        .ok_or(format!("{}: no thermo block", path.display()))
}

fn column(b: &ThermoBlock, name: &str, path: &Path) -> Result<Vec<f64>, String> {
    b.column(name)
        .ok_or(format!("{}: no column {name}", path.display()))
}

/// The second half of a series.
fn second_half(v: &[f64]) -> &[f64] {
    &v[v.len() / 2..]
}

/// Γ from the flat layer's run.
fn tension(dir: &Path) -> Result<(f64, f64, f64), String> {
    let path = dir.join("log.layer");
    let b = production(&path)?;
    let (xx, yy, zz) = (
        column(&b, "Pxx", &path)?,
        column(&b, "Pyy", &path)?,
        column(&b, "Pzz", &path)?,
    );
    let frames = parse_dump(&read(&dir.join("dump.drop.layer"))?)?;
    let lz = frames
        .first()
        .map(|f| f.box_bounds[2][1] - f.box_bounds[2][0])
        .ok_or("dump.drop.layer: no frame")?;
    let g: Vec<f64> = (0..xx.len())
        .map(|k| 0.5 * lz * (zz[k] - 0.5 * (xx[k] + yy[k])))
        .collect();
    let e = block_average(&g);
    Ok((e.mean, e.stderr, lz))
}

/// The deformation of the drop in one frame, and its centre (for the next frame).
fn deformation(f: &DumpFrame, centre: [f64; 3], r0: f64) -> Result<(f64, [f64; 3]), String> {
    let col = |name: &str| {
        f.columns
            .iter()
            .position(|c| c == name)
            .ok_or(format!("dump step {}: no column {name}", f.step))
    };
    let (ct, cx, cy, cz) = (col("type")?, col("x")?, col("y")?, col("z")?);
    let xy = f.tilt.map_or(0.0, |t| t[0]);
    let b = &f.box_bounds;
    let l = [
        b[0][1] - b[0][0] - xy.abs(),
        b[1][1] - b[1][0],
        b[2][1] - b[2][0],
    ];
    // Minimum image of d in the sheared box (an image across y moves x by the tilt).
    let image = |mut d: [f64; 3]| {
        let ny = (d[1] / l[1]).round();
        d[0] -= ny * xy;
        d[1] -= ny * l[1];
        d[2] -= (d[2] / l[2]).round() * l[2];
        d[0] -= (d[0] / l[0]).round() * l[0];
        d
    };
    let rel: Vec<[f64; 3]> = f
        .rows
        .iter()
        .filter(|r| r[ct] == 1.0)
        .map(|r| image([r[cx] - centre[0], r[cy] - centre[1], r[cz] - centre[2]]))
        .filter(|d| d.iter().map(|c| c * c).sum::<f64>() < 4.0 * r0 * r0)
        .collect();
    if rel.len() < 10 {
        return Err(format!(
            "dump step {}: only {} drop atoms near the centre",
            f.step,
            rel.len()
        ));
    }
    let n = rel.len() as f64;
    let mut m = [0.0; 3];
    for d in &rel {
        for k in 0..3 {
            m[k] += d[k] / n;
        }
    }
    let (mut gxx, mut gyy, mut gxy) = (0.0, 0.0, 0.0);
    for d in &rel {
        let (x, y) = (d[0] - m[0], d[1] - m[1]);
        gxx += x * x / n;
        gyy += y * y / n;
        gxy += x * y / n;
    }
    let (tr, det) = (gxx + gyy, gxx * gyy - gxy * gxy);
    let disc = (0.25 * tr * tr - det).max(0.0).sqrt();
    let (l1, l2) = (0.5 * tr + disc, (0.5 * tr - disc).max(0.0));
    let (a, bb) = (l1.sqrt(), l2.sqrt());
    let c = [centre[0] + m[0], centre[1] + m[1], centre[2] + m[2]];
    Ok(((a - bb) / (a + bb), c))
}

struct Point {
    rate: f64,
    sigma: (f64, f64),
    d: (f64, f64),
}

fn sheared(dir: &Path, name: &str, rate: f64, r0: f64) -> Result<Point, String> {
    let path = dir.join(format!("log.{name}"));
    let b = production(&path)?;
    let pxy = column(&b, "Pxy", &path)?;
    let s: Vec<f64> = second_half(&pxy).iter().map(|p| -p).collect();
    let frames = parse_dump(&read(&dir.join(format!("dump.drop.{name}")))?)?;
    let mut centre = [0.0; 3];
    let mut ds = Vec::new();
    for f in &frames {
        let (d, c) = deformation(f, centre, r0)?;
        centre = c;
        ds.push(d);
    }
    let (es, ed) = (block_average(&s), block_average(second_half(&ds)));
    Ok(Point {
        rate,
        sigma: (es.mean, es.stderr),
        d: (ed.mean, ed.stderr),
    })
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err("usage: droplet_plot OUT_PREFIX DIR R0 RATE…".into());
    }
    let (out, dir) = (Path::new(&args[0]), Path::new(&args[1]));
    let r0: f64 = args[2].parse().map_err(|_| format!("R0 '{}'", args[2]))?;
    let rates: Vec<f64> = args[3..]
        .iter()
        .map(|r| r.parse().map_err(|_| format!("rate '{r}'")))
        .collect::<Result<_, _>>()?;
    let (gamma, gamma_err, lz) = tension(dir)?;
    if gamma.is_nan() || gamma <= 0.0 {
        return Err(format!(
            "interfacial tension {gamma} ± {gamma_err} is not positive: the liquids mix"
        ));
    }
    let mut md = format!(
        "Interfacial tension Γ = {gamma:.3} ± {gamma_err:.3} (flat layer at rest, L_z = {lz}); \
         R0 = {r0}.\n\n| γ̇ | friction | σ = −⟨P_xy⟩ | Ca = R0 σ / Γ | D |\n|---|---|---|---|---|\n"
    );
    let mut fig_series = Vec::new();
    let mut ca_max: f64 = 0.0;
    for (friction, label) in [("none", "friction none"), ("cross", "friction cross")] {
        let (mut ca, mut d, mut err) = (Vec::new(), Vec::new(), Vec::new());
        for &rate in &rates {
            let p = sheared(dir, &format!("{friction}_{}", args[3 + ca.len()]), rate, r0)?;
            let c = r0 * p.sigma.0 / gamma;
            let _ = writeln!(
                md,
                "| {} | {friction} | {:.4} ± {:.4} | {:.3} | {:.3} ± {:.3} |",
                p.rate, p.sigma.0, p.sigma.1, c, p.d.0, p.d.1
            );
            ca_max = ca_max.max(c);
            ca.push(c);
            d.push(p.d.0);
            err.push(p.d.1);
        }
        fig_series.push(Series::points(label, ca, d).errors(err));
    }
    let xs: Vec<f64> = (0..=20).map(|k| ca_max * 1.1 * k as f64 / 20.0).collect();
    let taylor: Vec<f64> = xs.iter().map(|c| 35.0 / 32.0 * c).collect();
    let mut panel = Panel::new(
        "Sheared mDPD drop (R0 = 2.5, box 10)",
        "Ca = R0 σ / Γ",
        "D = (L − B)/(L + B)",
    );
    for s in fig_series {
        panel = panel.with(s);
    }
    panel = panel
        .with(Series::dashed("Taylor, D = 35 Ca / 32", xs, taylor))
        .legend(Legend::UpperLeft);
    Figure::single(panel).save(out)?;
    std::fs::write(out.with_extension("md"), &md).map_err(|e| format!("{}: {e}", out.display()))?;
    print!("{md}");
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("droplet_plot: {e}");
            ExitCode::FAILURE
        }
    }
}
