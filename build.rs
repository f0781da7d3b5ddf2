//! Generates the expression parser from `grammar/function.lalrpop` at build time, so
//! generated code is never committed.
fn main() {
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .process()
        .expect("LALRPOP grammar must compile");
    println!("cargo:rerun-if-changed=grammar");
}
