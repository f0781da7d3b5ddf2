//! `include/mbfx.h` is generated from this crate by cbindgen (`capi/cbindgen.toml`): this
//! test generates it again and fails when the checked-in file differs, so the header
//! never drifts from the functions it declares. `MBFX_BLESS_HEADER=1` rewrites it.

use std::path::Path;

#[test]
fn the_header_is_what_cbindgen_makes_of_the_crate() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml"))
        .expect("capi/cbindgen.toml is a cbindgen configuration");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(crate_dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen reads capi/src");
    let mut fresh = Vec::new();
    bindings.write(&mut fresh);
    let fresh = String::from_utf8(fresh).expect("the header is UTF-8");
    let path = crate_dir.join("../include/mbfx.h");
    if std::env::var_os("MBFX_BLESS_HEADER").is_some_and(|v| v == "1") {
        std::fs::write(&path, &fresh).expect("include/mbfx.h is writable");
        return;
    }
    let old = std::fs::read_to_string(&path).unwrap_or_default();
    if old != fresh {
        let line = old
            .lines()
            .zip(fresh.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| old.lines().count().min(fresh.lines().count()));
        panic!(
            "include/mbfx.h is stale (first difference at line {}: {:?} there, {:?} generated); \
             regenerate it with `MBFX_BLESS_HEADER=1 cargo test -p mbfx-capi --test header` \
             and commit it",
            line + 1,
            old.lines().nth(line).unwrap_or("<end of file>"),
            fresh.lines().nth(line).unwrap_or("<end of file>"),
        );
    }
}
