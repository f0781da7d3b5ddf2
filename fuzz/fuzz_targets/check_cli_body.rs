//! Body of the `check_cli` fuzz target, shared with the stable replay test
//! (`tests/fuzz_seeds.rs` includes this file with `#[path]`). Plain Rust: no libfuzzer
//! dependency.
//!
//! The whole `mbfx check` command, through the library entry the binary itself calls
//! ([`mbfx::cli::run`]): argument parsing, reading and decoding the file, the dataset
//! reader or the expression checker, the multibody analysis, rendering and writing.
//! The first input byte picks the command line (see [`command`]); the rest is written
//! to a file whose name ends in `.adm` or `.txt`, which is what `check` dispatches on.
//! Invariant: the command exits with 0 or 1, never panics (a panic would unwind out of
//! `run`) and never needs a process exit code of 101.
//!
//! The command writes its report and diagnostics to the process's standard output and
//! error: run the fuzzer with `-close_fd_mask=3` (libFuzzer's own messages and crash
//! reports still reach the terminal). The replay test runs the `mbfx` binary instead, so
//! `cargo test` stays quiet; both share [`command`] and [`check_exit`].

use std::path::Path;

/// The file name's extension and the options after `check` for the selector byte `b`.
pub fn command(b: u8) -> (&'static str, &'static [&'static str]) {
    match b % 6 {
        0 | 1 => ("adm", &[]),
        2 => ("adm", &["--dim", "2"]),
        3 => ("adm", &["--dim", "3"]),
        4 => ("txt", &[]),
        _ => ("txt", &["--var", "x=1", "--var", "v=-2"]),
    }
}

/// Writes `data` (after its selector byte) to a file in the temporary folder named after
/// this process, runs `run` with the full command line (`mbfx check --color never ...
/// FILE`), removes the file and checks the exit code `run` returned.
pub fn check_with(data: &[u8], run: impl FnOnce(&[String]) -> i32) {
    let Some((&selector, body)) = data.split_first() else {
        return;
    };
    let (ext, options) = command(selector);
    let name = format!("mbfx-check-cli-{}.{ext}", std::process::id());
    let path = std::env::temp_dir().join(name);
    std::fs::write(&path, body).expect("the input written");
    let args = arguments(options, &path);
    let code = run(&args);
    let _ = std::fs::remove_file(&path);
    check_exit(code, &args);
}

/// `mbfx check --color never OPTIONS FILE`.
fn arguments(options: &[&str], path: &Path) -> Vec<String> {
    ["mbfx", "check", "--color", "never"]
        .iter()
        .chain(options)
        .map(|s| s.to_string())
        .chain(std::iter::once(path.display().to_string()))
        .collect()
}

/// `check` exits 0 (no error) or 1 (errors reported); anything else is a failure.
pub fn check_exit(code: i32, args: &[String]) {
    assert!(code == 0 || code == 1, "exit code {code} from {args:?}");
}

/// The fuzz target: the command run in this process.
#[allow(dead_code)] // The replay test runs the binary instead.
pub fn check_bytes(data: &[u8]) {
    check_with(data, |args| mbfx::cli::run(args));
}
