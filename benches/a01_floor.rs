//! A01's physical floor (issue 42 §5): what one right-hand side of the pendulum costs
//! written by hand in Rust, against what mbfx's run of A01 at the bench's headline
//! setting costs (dopri853 in joint coordinates at ERROR 3e-7, 10 s, rows every 0.5 s:
//! `mbfx bench wp a01_pendulum`'s run for the 1e-6 level).
//!
//! The hand-written pendulum is A01 in its one minimal coordinate: φ, the link's angle
//! from the downward vertical, φ'' = −(g/L) sin φ with g = 9.81, L = 1. Its right-hand
//! side is one `sin` and two multiplications, the least any simulator of this model can
//! do per stage; the run's floor is mbfx's count of right-hand sides times this. The
//! count itself comes from callgrind (docs/performance.md, "A01 against its floor").
//!
//! Run: `cargo bench --bench a01_floor`.

use mbfx::session::run::{Method, RunSpec, Simulation};
use mbfx::session::DimRequest;
use std::hint::black_box;

/// g/L of A01.
const G_OVER_L: f64 = 9.81;

/// The pendulum's right-hand side: (φ, ω) → (ω, −(g/L) sin φ).
#[inline(never)]
fn rhs(state: [f64; 2]) -> [f64; 2] {
    [state[1], -G_OVER_L * state[0].sin()]
}

/// The calling thread's CPU time in seconds: the clock mbfx's run summary reads, so that
/// the other processes of a shared machine do not inflate either figure.
fn thread_cpu() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec the call writes; the clock id is a constant.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    assert!(ok, "the thread's CPU clock is readable");
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// Median of `rounds` timings of `calls` chained right-hand sides (each call's input is
/// the last one's output nudged, so none can be hoisted or skipped, and each waits for
/// the last, as an integrator's stages do), CPU ns a call.
fn native_ns(calls: usize, rounds: usize) -> f64 {
    let mut times: Vec<f64> = (0..rounds)
        .map(|_| {
            let mut s = black_box([0.5_f64, 0.0]);
            let start = thread_cpu();
            for _ in 0..calls {
                let d = rhs(s);
                // A tiny explicit Euler step: keeps φ in range and each call dependent.
                s = [s[0] + 1e-9 * d[0], s[1] + 1e-9 * d[1]];
            }
            black_box(s);
            (thread_cpu() - start) * 1e9 / calls as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[rounds / 2]
}

/// mbfx's run of A01 as the bench makes it: (integration CPU seconds, steps, rejected).
fn mbfx_run(text: &str) -> (f64, usize, usize) {
    let mut spec = RunSpec::new(10.0, 0.5);
    spec.method = Some(Method::Dopri853);
    spec.error = Some(3e-7);
    spec.dim = DimRequest::Two; // the scene's `dim = 2`
    let probes = [
        ("x".to_string(), "DX(201)".to_string()),
        ("y".to_string(), "DY(201)".to_string()),
    ];
    let mut sim = Simulation::new(text, spec, &probes).unwrap_or_else(|_| panic!("A01 builds"));
    let (summary, failure) = sim.run(&mut |_: &[f64]| Ok(()));
    assert!(failure.is_none(), "A01 runs to its end");
    (
        summary.cpu_seconds,
        summary.stats.steps,
        summary.stats.rejected,
    )
}

fn main() {
    let text = std::fs::read_to_string("examples/scenes/a01_pendulum.adm")
        .expect("run from the repository's root: examples/scenes/a01_pendulum.adm");
    let native = native_ns(10_000_000, 21);
    let mut runs: Vec<(f64, usize, usize)> = (0..51).map(|_| mbfx_run(&text)).collect();
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (cpu, steps, rejected) = runs[runs.len() / 2];
    // dopri853 evaluates 11 stages an attempt, accepted or rejected, and the 12th of an
    // accepted step (the next one's first), and 1 to start: callgrind counts
    // `JointTree::accelerations` so (1 018 calls for 71 steps and 15 rejected).
    let stages = 11 * (steps + rejected) + steps + 1;
    println!("native pendulum right-hand side: {native:.2} ns a call (median of 21 × 10^7)");
    println!(
        "mbfx A01, dopri853 at ERROR 3e-7, 10 s: {:.4} ms integration CPU (median of 51), \
         {steps} steps, {rejected} rejected, {stages} right-hand sides",
        cpu * 1e3
    );
    let floor = stages as f64 * native * 1e-9;
    println!(
        "floor: {stages} right-hand sides × {native:.2} ns = {:.4} ms; mbfx / floor = {:.1}×",
        floor * 1e3,
        cpu / floor
    );
}
