//! Generates the expression parser from `grammar/function.lalrpop` at build time, so
//! generated code is never committed. The grammar is the language's grammar of record:
//! it parses every input with an error and produces every syntax diagnostic; valid input
//! takes the hand-written fast path of `src/syntax/fast.rs`, tested to build the same trees.

fn main() {
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .process()
        .expect("LALRPOP grammar must compile");
    println!("cargo:rerun-if-changed=grammar");
    println!("cargo:rerun-if-changed=build.rs");
}
