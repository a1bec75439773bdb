//! Helpers shared by the engine tests (each test crate includes this module and uses part of it).

use dpdnl::engine::System;
use dpdnl::input::{Collect, Interpreter, Options, ScriptError};

/// Runs a script in the standalone engine: its console lines and the final system.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn run(text: &str) -> Result<(Vec<String>, Option<System>), ScriptError> {
    let mut console = Collect::default();
    let opts = Options::default();
    let mut interp = Interpreter::new(&mut console, &opts).expect("no log file");
    interp.run_text(text, "test.in")?;
    let sys = interp.into_system();
    Ok((console.0, sys))
}

/// The pair style as `Any` (a test's downcast, by trait upcasting: the engines read styles
/// through the trait only).
fn style(sys: &System) -> Option<&dyn std::any::Any> {
    let p: &dyn dpdnl::PairStyle = sys.pair.as_deref()?;
    Some(p)
}

/// The `dpd/nonlinear` style's force field, if that is the pair style.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn dpd(sys: &System) -> Option<&dpdnl::engine::ForceField> {
    Some(
        &style(sys)?
            .downcast_ref::<dpdnl::forces::dpd::DpdPair>()?
            .ff,
    )
}

/// The `sdpd` style, if that is the pair style.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn sdpd(sys: &System) -> Option<&dpdnl::forces::sdpd::SdpdField> {
    style(sys)?.downcast_ref()
}

/// Every atom's tag, position bits and velocity bits, sorted by tag (for bit-identity checks).
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn state_by_tag(sys: &System) -> Vec<(u32, [u64; 3], [u64; 3])> {
    let a = &sys.atoms;
    let mut v: Vec<_> = (0..a.len())
        .map(|i| (a.tag[i], a.x[i].map(f64::to_bits), a.v[i].map(f64::to_bits)))
        .collect();
    v.sort_by_key(|e| e.0);
    v
}

/// Half a unit in the last digit of a printed decimal, e.g. "0.0700" -> 5e-5, "50" -> 0.5.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn half_ulp(printed: &str) -> f64 {
    let decimals = printed.split_once('.').map_or(0, |(_, f)| f.len());
    0.5 * 10f64.powi(-(decimals as i32))
}

/// `computed` agrees with `printed` at its printed precision (with room for a printed value
/// that sits exactly on a rounding tie, such as η̄ = 49.06125 printed as 49.0613).
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn agrees(computed: f64, printed: &str) -> bool {
    let p: f64 = printed.parse().expect("number");
    (computed - p).abs() <= half_ulp(printed) * (1.0 + 1e-9)
}

/// The value of a `key = value` line of a command's output (lines starting with `#` skipped).
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn value(text: &str, key: &str) -> f64 {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .find_map(|l| l.split_once(" = ").filter(|(k, _)| *k == key))
        .unwrap_or_else(|| panic!("no `{key} = ` in\n{text}"))
        .1
        .trim()
        .parse()
        .expect("number")
}

/// The weighting-function paper's 2-D fluid: n = 4, m = kT = 1, cut-off `rc`.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn paper_fluid(rc: f64) -> dpdnl::theory::Fluid {
    dpdnl::theory::Fluid::new(2, 4.0, rc, 1.0, 1.0).expect("valid fluid")
}

/// Runs a script in the standalone engine whose first thermo block has `Step` and `Temp`
/// columns, and block-averages (Flyvbjerg–Petersen) the temperatures of the steps after
/// `after_step`: the mean, its standard error and the number of samples. The temperature tests
/// of the noise schemes share it.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn mean_temperature(script: &str, name: &str, after_step: f64) -> (f64, f64, usize) {
    let mut console = Collect::default();
    let mut interp = Interpreter::new(&mut console, &Options::default()).expect("interpreter");
    interp.run_text(script, name).expect("runs");
    drop(interp);
    let blocks = dpdnl::io::lammps_log::parse_log(&console.0.join("\n")).expect("log parses");
    let b = &blocks[0];
    let (step, temp) = (
        b.column_index("Step").expect("Step"),
        b.column_index("Temp").expect("Temp"),
    );
    let series: Vec<f64> = b
        .rows
        .iter()
        .filter(|r| r[step] > after_step)
        .map(|r| r[temp])
        .collect();
    let est = dpdnl::stats::block_average(&series);
    (est.mean, est.stderr, series.len())
}

/// Runs the `dpdnl` command with `args`: its exit code (-1 when killed), stdout and stderr.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub fn dpdnl_cli(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dpdnl"))
        .args(args)
        .output()
        .expect("run dpdnl");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The design flags of the weighting paper's Table 4, first row: targets η = 49, Sc = 400 for
/// the 2-D fluid of density 4 and cut-off 2.5.
#[allow(dead_code)] // not every test crate that includes this module calls it
pub const TABLE4_DESIGN: [&str; 10] = [
    "--eta",
    "49",
    "--sc",
    "400",
    "--density",
    "4",
    "--rc",
    "2.5",
    "--dim",
    "2",
];
