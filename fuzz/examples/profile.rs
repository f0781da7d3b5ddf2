//! Runs a fuzz target's body over corpus folders without libFuzzer or a sanitizer, and
//! reports what one input costs: inputs per second, heap allocations and bytes
//! allocated per input, the largest single allocation and the resident set after each
//! pass. Allocation counts matter most under the fuzzer: AddressSanitizer records a
//! stack trace for every allocation and keeps freed bytes in its quarantine.
//!
//! `cargo run --release --example profile -- parse_check [--passes N] DIR...`

#[path = "../fuzz_targets/spans.rs"]
mod spans;

#[path = "../fuzz_targets/adm_check_body.rs"]
mod adm_check;
#[path = "../fuzz_targets/check_cli_body.rs"]
mod check_cli;
#[path = "../fuzz_targets/interp_vs_jit_body.rs"]
mod interp_vs_jit;
#[path = "../fuzz_targets/parse_check_body.rs"]
mod parse_check;

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write as _;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::Instant;

/// The system allocator, counting calls and bytes.
struct Counting;

static CALLS: AtomicUsize = AtomicUsize::new(0);
static BYTES: AtomicUsize = AtomicUsize::new(0);
static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every method forwards to `System` with the caller's arguments unchanged; the
// counters are plain atomics.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        // SAFETY: same contract as ours.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        // SAFETY: same contract as ours.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as ours.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size);
        // SAFETY: same contract as ours.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

fn count(size: usize) {
    CALLS.fetch_add(1, Relaxed);
    BYTES.fetch_add(size, Relaxed);
    LARGEST.fetch_max(size, Relaxed);
}

/// `println!` without its panic on a closed pipe (`profile ... | head`).
macro_rules! say {
    ($($arg:tt)*) => {
        let _ = writeln!(std::io::stdout(), $($arg)*);
    };
}

#[global_allocator]
static ALLOC: Counting = Counting;

fn rss_kib() -> usize {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        })
        .unwrap_or(0)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let target = args.next().unwrap_or_default();
    let check: fn(&[u8]) = match target.as_str() {
        "parse_check" => parse_check::check_bytes,
        "interp_vs_jit" => interp_vs_jit::check_bytes,
        "adm_check" => adm_check::check_bytes,
        "check_cli" => check_cli::check_bytes,
        _ => {
            eprintln!(
                "usage: profile parse_check|interp_vs_jit|adm_check|check_cli [--passes N] DIR..."
            );
            std::process::exit(2);
        }
    };
    let mut passes = 3;
    let mut inputs: Vec<(String, Vec<u8>)> = Vec::new();
    while let Some(a) = args.next() {
        if a == "--passes" {
            passes = args.next().and_then(|n| n.parse().ok()).unwrap_or(3);
            continue;
        }
        let dir = std::fs::read_dir(&a).unwrap_or_else(|e| panic!("{a}: {e}"));
        for e in dir.flatten() {
            if e.path().is_file() {
                if let Ok(bytes) = std::fs::read(e.path()) {
                    inputs.push((e.path().display().to_string(), bytes));
                }
            }
        }
    }
    inputs.sort();
    let n = inputs.len().max(1);
    // The slowest and the most allocating inputs of the first pass.
    let mut worst: Vec<(f64, usize, usize, &str)> = Vec::new();
    for pass in 0..passes {
        let (c0, b0) = (CALLS.load(Relaxed), BYTES.load(Relaxed));
        let start = Instant::now();
        for (name, bytes) in &inputs {
            let (c, b, t) = (CALLS.load(Relaxed), BYTES.load(Relaxed), Instant::now());
            check(bytes);
            if pass == 0 {
                worst.push((
                    t.elapsed().as_secs_f64(),
                    CALLS.load(Relaxed) - c,
                    BYTES.load(Relaxed) - b,
                    name,
                ));
            }
        }
        let secs = start.elapsed().as_secs_f64();
        say!(
            "pass {pass}: {} inputs, {:.0} inputs/s, {:.0} allocations and {:.0} bytes per input, largest {} bytes, rss {} KiB",
            inputs.len(),
            inputs.len() as f64 / secs,
            (CALLS.load(Relaxed) - c0) as f64 / n as f64,
            (BYTES.load(Relaxed) - b0) as f64 / n as f64,
            LARGEST.load(Relaxed),
            rss_kib(),
        );
    }
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    say!("slowest inputs (s, allocations, bytes):");
    for w in worst.iter().take(5) {
        say!("  {:.6} {} {} {}", w.0, w.1, w.2, w.3);
    }
    worst.sort_by(|a, b| b.2.cmp(&a.2));
    say!("most bytes allocated:");
    for w in worst.iter().take(5) {
        say!("  {:.6} {} {} {}", w.0, w.1, w.2, w.3);
    }
}
