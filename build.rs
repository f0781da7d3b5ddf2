//! Generates the expression parser from `grammar/function.lalrpop` at build time, so
//! generated code is never committed. The grammar is the language's grammar of record:
//! it parses every input with an error and produces every syntax diagnostic; valid input
//! takes the hand-written fast path of `src/syntax/fast.rs`, tested to build the same trees.
//!
//! The generated tables are driven by `src/syntax/driver.rs` instead of lalrpop-util's
//! driver, whose error recovery copies the parser stack for every state it tries (see
//! that module): the one call that starts the driver is redirected here.

use std::path::Path;

/// The generated call that starts lalrpop-util's driver, and ours that replaces it.
const LALRPOP_DRIVER: &str = "__state_machine::Parser::drive(";
const OUR_DRIVER: &str = "crate::syntax::driver::drive(";

fn main() {
    let out_dir = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(&out_dir)
        .process()
        .expect("LALRPOP grammar must compile");
    use_our_driver(&Path::new(&out_dir).join("function.rs"));
    println!("cargo:rerun-if-changed=grammar");
    println!("cargo:rerun-if-changed=build.rs");
}

/// Redirects the generated parser's one driver call. LALRPOP leaves an up-to-date output
/// alone, so the file may already be redirected; anything else means the generated code
/// changed shape, and the build stops rather than run the quadratic driver.
fn use_our_driver(generated: &Path) {
    let code = std::fs::read_to_string(generated).expect("generated parser is readable");
    let theirs = code.matches(LALRPOP_DRIVER).count();
    let ours = code.matches(OUR_DRIVER).count();
    match (theirs, ours) {
        (1, 0) => std::fs::write(generated, code.replace(LALRPOP_DRIVER, OUR_DRIVER))
            .expect("generated parser is writable"),
        (0, 1) => {}
        _ => panic!(
            "{}: expected one call of `{LALRPOP_DRIVER}` (found {theirs}) or of `{OUR_DRIVER}` \
             (found {ours}); has lalrpop changed?",
            generated.display()
        ),
    }
}
