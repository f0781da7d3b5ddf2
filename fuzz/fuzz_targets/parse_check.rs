//! Fuzz target: arbitrary bytes through the lexer, parser, checker and interpreter.
//! The checks live in `parse_check_body.rs`, which `tests/fuzz_seeds.rs` replays on
//! stable Rust. Run: `cargo +nightly fuzz run parse_check -- -dict=fuzz/parse_check.dict`.

#![no_main]

#[path = "spans.rs"]
mod spans;

#[path = "parse_check_body.rs"]
mod body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| body::check_bytes(data));
