//! The script interpreter on arbitrary text: every script ends in Ok or in a `ScriptError`,
//! never in a panic. `Options::max_steps`/`max_atoms` keep a fuzz input from asking for a long
//! run (a `run` over 200 steps or a system over 400 atoms is an error), so a slow input means
//! a real hang. Run it in a scratch directory as an unprivileged user: scripts may write files
//! (dump, write_data, log, print, restart) — see fuzz/README.md.
#![no_main]

use dpdnl::input::{Collect, Interpreter, Options};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return;
    };
    let opts = Options {
        max_steps: Some(200),
        max_atoms: Some(400),
        ..Options::default()
    };
    let mut console = Collect::default();
    let mut interp = Interpreter::new(&mut console, &opts).expect("no log file");
    let r = interp.run_text(text, "fuzz.in");
    drop(interp);
    if std::env::var_os("DPDNL_FUZZ_VERBOSE").is_some() {
        // Replaying one input by hand: what the script printed and how it ended.
        for line in &console.0 {
            eprintln!("{line}");
        }
        eprintln!("=> {r:?}");
    }
});
