//! Fuzz target: bytes read as an `.adm` dataset, with `mbfx check`'s model checks. The
//! checks live in `adm_check_body.rs`, which `tests/fuzz_seeds.rs` replays on stable
//! Rust. Run: `cargo fuzz run adm_check fuzz/corpus/adm_check -- -dict=fuzz/adm_check.dict`.

#![no_main]

#[path = "spans.rs"]
mod spans;

#[path = "adm_check_body.rs"]
mod body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| body::check_bytes(data));
