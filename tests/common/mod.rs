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
