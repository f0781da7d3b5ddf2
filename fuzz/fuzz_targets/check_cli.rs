//! Fuzz target: the whole `mbfx check` command on a dataset or expression file. The
//! checks live in `check_cli_body.rs`; `tests/fuzz_seeds.rs` replays the seeds through
//! the `mbfx` binary on stable Rust. Run (the command's output discarded):
//! `cargo fuzz run check_cli fuzz/corpus/check_cli -- -dict=fuzz/adm_check.dict -close_fd_mask=3`.

#![no_main]

#[path = "check_cli_body.rs"]
mod body;

libfuzzer_sys::fuzz_target!(|data: &[u8]| body::check_bytes(data));
