//! The committed C header must be what cbindgen generates from `src/lib.rs` today.
//! Regenerate with `DPDNL_BLESS_HEADER=1 cargo test -p dpdnl-capi --test header`.

use std::path::Path;

fn generate() -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen failed on src/lib.rs");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("header is UTF-8")
}

#[test]
fn committed_header_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/dpdnl.h");
    let fresh = generate();
    if std::env::var_os("DPDNL_BLESS_HEADER").is_some() {
        std::fs::write(&path, &fresh).expect("write include/dpdnl.h");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "capi/include/dpdnl.h is stale: run `DPDNL_BLESS_HEADER=1 cargo test -p dpdnl-capi --test header` and commit it"
    );
}
