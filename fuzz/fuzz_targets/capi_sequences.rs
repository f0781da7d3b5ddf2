//! Fuzz target: sequences of C API calls (compile, gradient, evaluate one point and
//! many, the C entry, the accessors, free) decoded from the input bytes and made through
//! the exported `extern "C"` functions, as a C program makes them. The checks live in
//! `capi_sequences_body.rs`, which `tests/fuzz_seeds.rs` replays on stable Rust. Run:
//! `cargo +nightly fuzz run capi_sequences fuzz/corpus/capi_sequences --
//! -dict=fuzz/capi_sequences.dict`.

#![no_main]

#[path = "capi_sequences_body.rs"]
mod body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| body::check_bytes(data));
