//! Generates the expression parsers from `grammar/function.lalrpop` at build time, so
//! generated code is never committed.
//!
//! Two parsers come from the one grammar: the grammar as written (with LALRPOP error
//! recovery, reporting every syntax error), and a copy without the error-recovery
//! production. The copy's parser-stack entries need not hold an `ErrorRecovery`, which
//! makes it several times cheaper; the front end runs it first and falls back to the
//! recovering parser only when the input has an error.
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(&out)
        .process()
        .expect("LALRPOP grammar must compile");

    let grammar = std::fs::read_to_string("grammar/function.lalrpop").expect("read grammar");
    let recovery: Vec<&str> = grammar.lines().filter(|l| l.contains("<e:!>")).collect();
    assert_eq!(
        recovery.len(),
        1,
        "the grammar must have exactly one `!` production"
    );
    let fast: String = grammar
        .lines()
        .filter(|l| !l.contains("<e:!>"))
        .map(|l| format!("{l}\n"))
        .collect();
    let fast_dir = out.join("fast_grammar");
    std::fs::create_dir_all(&fast_dir).expect("create dir");
    std::fs::write(fast_dir.join("function_fast.lalrpop"), fast).expect("write grammar copy");
    lalrpop::Configuration::new()
        .set_in_dir(&fast_dir)
        .set_out_dir(&out)
        .process()
        .expect("LALRPOP grammar copy must compile");
    println!("cargo:rerun-if-changed=grammar");
    println!("cargo:rerun-if-changed=build.rs");
}
