//! The recorder on a run: poses at every row, arrows from the force functions (checked
//! against the same forces as probes read them), frames at a rate from the continuous
//! extension, and rows that stay bit for bit what they are without any of it.

use super::*;
use crate::scene::ArrowSource;
use crate::session::run::{RunSpec, Simulation};

/// examples/slider.adm: a slider on a spring (SFORCE/1, an IMPACT in it) and a drive.
const SLIDER: &str = include_str!("../../../examples/slider.adm");

fn simulation(method: crate::session::run::Method) -> Simulation {
    let mut spec = RunSpec::new(0.5, 0.01);
    spec.method = Some(method);
    let probes = [
        ("x".to_string(), "DX(22)".to_string()),
        ("fx_j".to_string(), "SFORCE(1, 1, 2, 0)".to_string()),
        ("fy_j".to_string(), "SFORCE(1, 1, 3, 0)".to_string()),
        ("fx_i".to_string(), "SFORCE(1, 0, 2, 0)".to_string()),
    ];
    match Simulation::new(SLIDER, spec, &probes) {
        Ok(sim) => sim,
        Err(_) => panic!("the slider builds"),
    }
}

/// The rows of a run of `sim`, recording with `request` when given.
fn run(
    sim: &mut Simulation,
    request: Option<&AnimationRequest>,
) -> (Vec<Vec<f64>>, Option<Recorder>) {
    if let Some(a) = request {
        let (_, mut scene) = scene_of(a, &sim.read.model).expect("a scene");
        scene.arrows = vec![
            ArrowSource {
                etype: "SFORCE",
                eid: 1,
                emarker: 11,
            },
            ArrowSource {
                etype: "NFORCE",
                eid: 9,
                emarker: 11,
            },
        ];
        let end = sim.spec.end;
        sim.recorder = Some(recorder(a, &scene, sim, end));
    }
    let mut rows = Vec::new();
    let (_, failed) = sim.run(&mut |r: &[f64]| {
        rows.push(r.to_vec());
        Ok(())
    });
    assert!(failed.is_none());
    (rows, sim.recorder.take())
}

#[test]
fn frames_at_rows_hold_the_poses_and_forces_the_probes_read() {
    use crate::session::run::Method;
    let request = AnimationRequest::default();
    let (rows, rec) = run(&mut simulation(Method::Gstiff), Some(&request));
    let rec = rec.expect("recorded");
    assert_eq!(rec.frames.times.len(), rows.len());
    assert!(
        rec.notes.iter().any(|n| n.contains("NFORCE/9")),
        "{:?}",
        rec.notes
    );
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(rec.frames.times[k], row[0]);
        // Part 2's BCS is at the global origin at input, marker 22 at QP 0.3 on it.
        let p = rec.frames.poses[k][1];
        assert!((p.translation[0] + 0.3 - row[1]).abs() < 1e-12, "row {k}");
        let f = rec.frames.arrows[k][0];
        assert_eq!([f[0], f[1]], [row[2], row[3]], "row {k}");
        assert!(
            (f[0] + row[4]).abs() <= 1e-9 * row[4].abs().max(1.0),
            "J side = −I side"
        );
        assert!(
            rec.frames.arrows[k][1].iter().all(|f| f.is_nan()),
            "no force function"
        );
    }
    assert!(rows.iter().any(|r| r[2].abs() > 1.0), "the spring pulls");
}

#[test]
fn rows_are_the_same_bits_with_frames_at_a_rate() {
    use crate::session::run::Method;
    for method in [Method::Gstiff, Method::Hht, Method::Dopri853] {
        let (plain, _) = run(&mut simulation(method), None);
        let request = AnimationRequest {
            fps: Some(240.0),
            ..AnimationRequest::default()
        };
        let (rows, rec) = run(&mut simulation(method), Some(&request));
        assert_eq!(rows, plain, "{method:?}");
        let rec = rec.expect("recorded");
        // 0, then every 1/240 s to 0.5.
        assert_eq!(rec.frames.times.len(), 121, "{method:?}");
        for (k, t) in rec.frames.times.iter().enumerate() {
            assert!((t - k as f64 / 240.0).abs() < 1e-12);
        }
        // Where a frame meets a row (every 0.01 s = 2.4 frames: at each 0.05 s), the
        // same pose.
        for (k, row) in rows.iter().enumerate().step_by(5) {
            let f = (k / 5) * 12;
            let p = rec.frames.poses[f][1];
            assert!(
                (p.translation[0] + 0.3 - row[1]).abs() < 1e-9,
                "{method:?} row {k}: {} vs {}",
                p.translation[0] + 0.3,
                row[1]
            );
        }
    }
}

#[test]
fn a_rate_past_the_cap_is_coarsened_with_a_note() {
    let request = AnimationRequest {
        fps: Some(1e6),
        ..AnimationRequest::default()
    };
    let (step, note) = record::frame_step(&request, 10.0);
    assert!((10.0 / step.unwrap() + 1.0 - MAX_FRAMES as f64).abs() < 1e-6);
    assert!(note.unwrap().contains("10000"));
    assert_eq!(
        record::frame_step(&AnimationRequest::default(), 10.0),
        (None, None)
    );
}

#[test]
fn glyphs_or_not_the_same_frames() {
    use crate::session::request::{run, RunRequest};
    let mut request = RunRequest::dataset("slider.adm", SLIDER);
    request.end = Some(0.1);
    request.animation = Some(AnimationRequest::default());
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    let done = run(&request, &mut sink, None).expect("the slider runs");
    let a = done.animation.expect("an animation was asked for");
    assert_eq!(a.frame_count(), 101);
    let b = a.with_glyphs(true).expect("the same scene with glyphs");
    assert_eq!(b.frames(), a.frames());
    assert_eq!(b.scene().parts, a.scene().parts);
    assert_eq!(&b.glb()[0..4], b"glTF");
}

#[test]
fn a_failed_run_keeps_the_frames_before_the_failure() {
    use crate::session::request::{run, RunRequest};
    // The force turns not-a-number at t = 0.05 (a square root of a negative number).
    let adm = SLIDER.replace("VARVAL(1)", "SQRT(0.05 - TIME)");
    let mut request = RunRequest::dataset("slider.adm", adm);
    request.end = Some(0.1);
    request.animation = Some(AnimationRequest::default());
    let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
    let failed = run(&request, &mut sink, None).expect_err("the force fails");
    let a = failed.animation.expect("what was recorded");
    let last = *a.frames().times.last().expect("frames before the failure");
    assert!(
        a.frame_count() > 1 && last <= 0.05,
        "{} frames to {last}",
        a.frame_count()
    );
}
