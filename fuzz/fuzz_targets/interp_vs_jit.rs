//! Fuzz target: expressions through both back ends, which must agree bit for bit. The
//! checks live in `interp_vs_jit_body.rs`, which `tests/fuzz_seeds.rs` replays on stable
//! Rust. Run: `cargo +nightly fuzz run interp_vs_jit fuzz/corpus/interp_vs_jit --
//! -dict=fuzz/interp_vs_jit.dict`.

#![no_main]

#[path = "interp_vs_jit_body.rs"]
mod body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| body::check_bytes(data));
