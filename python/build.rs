//! Detects two interpreter APIs that are being added on another branch (issue 12's embeddable
//! interpreter) and turns on the code that uses them:
//!
//! - `dpdnl_console_interrupted`: `Console::interrupted(&mut self) -> bool`, checked once per
//!   step; the run then stops with the error `interrupted at step N`. Without it, Ctrl-C is
//!   answered from `Console::progress` (about once a second; see `src/sim.rs`).
//! - `dpdnl_system_mut`: `Interpreter::system_mut()`, needed to write positions and velocities.
//!
//! The core crate's sources are searched for the two signatures, so the package builds against
//! the core crate before and after that branch lands. Once it has landed, both cfgs can go.
use std::path::Path;

fn sources(dir: &Path, out: &mut String) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs")
            && let Ok(s) = std::fs::read_to_string(&p)
        {
            out.push_str(&s);
        }
    }
}

fn main() {
    println!("cargo:rustc-check-cfg=cfg(dpdnl_console_interrupted)");
    println!("cargo:rustc-check-cfg=cfg(dpdnl_system_mut)");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("src");
    println!("cargo:rerun-if-changed={}", root.display());
    let mut text = String::new();
    sources(&root, &mut text);
    let squeezed: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
    if squeezed.contains("fn interrupted(&mut self) -> bool") {
        println!("cargo:rustc-cfg=dpdnl_console_interrupted");
    }
    if squeezed.contains("pub fn system_mut(&mut self)") {
        println!("cargo:rustc-cfg=dpdnl_system_mut");
    }
}
