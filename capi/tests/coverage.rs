//! Every function the C header declares is called by some test under `capi/tests/`: a new
//! export without a test fails here. (The header itself is checked against `src/` by
//! `tests/header.rs`.)

use std::path::Path;

/// The `dpdnl_*` function names declared in `include/dpdnl.h` (comment lines skipped).
fn declared() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(dir.join("include/dpdnl.h")).expect("include/dpdnl.h");
    let mut names = Vec::new();
    for line in header.lines() {
        let code = line.trim_start();
        if code.starts_with("//") || code.starts_with("/*") || code.starts_with('*') {
            continue;
        }
        let mut rest = code;
        while let Some(at) = rest.find("dpdnl_") {
            let tail = &rest[at..];
            let end = tail
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(tail.len());
            let starts_word = rest[..at]
                .chars()
                .next_back()
                .is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
            if starts_word && tail[end..].starts_with('(') {
                names.push(tail[..end].to_string());
            }
            rest = &tail[end..];
        }
    }
    names.sort();
    names.dedup();
    names
}

/// Every `.rs` file below `dir`, in subfolders too.
fn rs_files(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for entry in std::fs::read_dir(&d).expect("a folder of capi") {
            let path = entry.expect("a folder entry").path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out
}

#[test]
fn every_exported_function_is_called_by_a_test() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let names = declared();
    // As many declarations as exports in src/ (`#[unsafe(no_mangle)]`): the parse above missed
    // none.
    let exports: usize = rs_files(&dir.join("src"))
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).expect("a source file");
            text.matches("#[unsafe(no_mangle)]").count()
        })
        .sum();
    assert!(exports > 0, "no exports found in capi/src");
    assert_eq!(names.len(), exports, "header functions {names:?}");

    let this = Path::new(file!()).file_name().expect("this file's name");
    // The test crates and their shared modules (`common/mod.rs`).
    let tests: Vec<String> = rs_files(&dir.join("tests"))
        .iter()
        .filter(|p| p.file_name() != Some(this))
        .map(|p| std::fs::read_to_string(p).expect("a test file"))
        .collect();
    // A call: the name followed by `(` (a name only mentioned, without `(`, does not count).
    let untested: Vec<&String> = names
        .iter()
        .filter(|n| !tests.iter().any(|t| t.contains(&format!("{n}("))))
        .collect();
    assert!(
        untested.is_empty(),
        "exported C functions that no test under capi/tests/ calls: {untested:?}"
    );
}
