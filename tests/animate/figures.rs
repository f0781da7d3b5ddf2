//! The figures docs/gltf.md reports (`cargo test --release --test animate -- --ignored
//! --nocapture`): what recording and writing the .glb cost against the run, on the
//! chain of 100 rods over 10 s at 100 frames a second (`mbfx bench generate chain 100`),
//! and the size of the slider-crank's file for 10 s at 100 frames a second.

use mbfx::session::animation::AnimationRequest;
use mbfx::session::request::{run, RunRequest};
use std::process::Command;

/// This thread's CPU time, seconds.
fn cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid timespec the call writes into.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "the thread's CPU clock");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// CPU of a run of `request` (with rows dropped), and the animation it recorded.
fn timed(request: &RunRequest) -> (f64, Option<mbfx::session::animation::Animation>) {
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    let start = cpu();
    let done = run(request, &mut sink, None).expect("the run finishes");
    (cpu() - start, done.animation)
}

#[test]
#[ignore = "figures: run with --ignored --nocapture"]
fn writing_costs_little_against_the_run() {
    let out = Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .args(["bench", "generate", "chain", "100"])
        .output()
        .expect("mbfx runs");
    let chain = String::from_utf8(out.stdout).expect("a dataset");
    let mut request = RunRequest::dataset("chain100.adm", chain);
    (request.end, request.output_step) = (Some(10.0), Some(0.01));
    // The second run reuses the simulation the first kept (compiled once), as the
    // run with the animation does: the difference between them is the recording.
    let _ = timed(&request);
    let (plain, _) = timed(&request);
    request.animation = Some(AnimationRequest::default());
    let (recording, animation) = timed(&request);
    let animation = animation.expect("recorded");
    let start = cpu();
    let glb = animation.glb();
    let write = cpu() - start;
    println!(
        "chain of 100, 10 s, {} frames: run {plain:.3} s CPU, with recording {recording:.3} s, writing the .glb {write:.3} s ({:.1} % of the run), {} bytes",
        animation.frame_count(),
        100.0 * write / recording,
        glb.len()
    );
    assert_eq!(animation.frame_count(), 1001);
    assert!(
        write <= 0.1 * recording,
        "writing {write} s against a run of {recording} s"
    );

    let crank = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes/slider_crank_driven.adm");
    let mut request = RunRequest::file(crank);
    request.end = Some(10.0);
    request.animation = Some(AnimationRequest {
        fps: Some(100.0),
        ..AnimationRequest::default()
    });
    let (_, animation) = timed(&request);
    let animation = animation.expect("recorded");
    let glb = animation.glb();
    println!(
        "slider-crank, 10 s at 100 frames a second: {} frames, {} bytes of .glb ({} as base64)",
        animation.frame_count(),
        glb.len(),
        glb.len().div_ceil(3) * 4
    );
    assert_eq!(animation.frame_count(), 1001);
    assert!(
        glb.len().div_ceil(3) * 4 < 1_500_000,
        "room for the page under 2 MB"
    );
}
