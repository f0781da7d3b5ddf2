//! The speed-against-accuracy benches (issue 10) on the bundled scenes: every truth
//! file loads and its dataset builds, the scores against truth from outside mbfx (the
//! exact A01 and A02 solutions of reference-problems §4.1–4.2) fall as the tolerance
//! tightens, and `mbfx bench wp|stability|scaling|orders` write what they promise.

use mbfx::bench::point::{measure, variant_named, Control, Options, Point, Status};
use mbfx::bench::scene::{load_dir, Scene};
use std::path::{Path, PathBuf};
use std::process::Command;

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

fn scene(name: &str) -> Scene {
    Scene::load(&scenes_dir().join(format!("{name}.toml"))).unwrap()
}

/// `scene` (dataset `text`) run by `method` at ERROR `error`, everything else as the
/// scene says.
fn at_tolerance(scene: &Scene, text: &str, method: &str, error: f64) -> Point {
    let v = variant_named(method).unwrap_or_else(|| panic!("no method {method}"));
    measure(
        scene,
        text,
        v,
        Control::Tolerance(error),
        Options::default(),
    )
}

#[test]
fn every_scene_loads_and_its_dataset_builds() {
    let scenes = load_dir(&scenes_dir()).unwrap();
    assert!(scenes.len() >= 10, "{} scenes", scenes.len());
    for s in &scenes {
        let text = s.dataset_text().unwrap();
        // One step's worth of run: the model reads, assembles and compiles its probes.
        let mut short = s.clone();
        short.end = short.output_step * short.stride() as f64;
        short.references.retain(|r| r.row == 0);
        let p = at_tolerance(&short, &text, "gstiff", 1e-3);
        if let Status::Failed(why) = &p.status {
            // Only a scene whose truth is that the run must stop may fail, and not at build.
            assert!(
                s.source.contains("must stop") && !why.starts_with("dataset"),
                "{}: {why}",
                s.name
            );
        }
    }
}

#[test]
fn a01_error_against_the_exact_solution_falls_with_the_tolerance() {
    let s = scene("a01_pendulum");
    let text = s.dataset_text().unwrap();
    let run = |name: &str, e: f64| {
        let p = at_tolerance(&s, &text, name, e);
        assert_eq!(p.status, Status::Ok, "{name} {e}");
        p.errors.position.unwrap()
    };
    let (loose, tight) = (run("gstiff", 1e-5), run("gstiff", 1e-9));
    assert!(
        tight < 1e-6 && tight < loose / 100.0,
        "gstiff: {loose:e} → {tight:e}"
    );
    assert!(run("dopri853", 1e-9) < 1e-8);
}

#[test]
fn trees_in_joint_coordinates_meet_the_truth_as_the_cartesian_form_does() {
    // dopri853 integrates a planar tree in its joint coordinates: one revolute (A01,
    // exact), one translational with an IMPACT stop (k = 1e5, the 1-DOF equation's
    // converged truth), a translational and a revolute (the light cart-pole's first
    // second, its quadrature). Each against its truth, as the Cartesian index-1 form.
    for (name, error, bound) in [
        ("a01_pendulum", 1e-9, 1e-8),
        ("impact_block_k1e5", 1e-7, 1e-6),
        ("cart_pole", 1e-10, 1e-7),
    ] {
        let s = scene(name);
        let text = s.dataset_text().unwrap();
        for method in ["dopri853", "dopri853-cartesian"] {
            let p = at_tolerance(&s, &text, method, error);
            assert_eq!(p.status, Status::Ok, "{name} {method}");
            let e = p.errors.position.unwrap();
            assert!(e < bound, "{name} {method}: error {e:e}");
            // The joint form has no constraint to project onto.
            if method == "dopri853" {
                assert_eq!(p.stats.newton_iterations, 0, "{name}");
            }
        }
    }
}

#[test]
fn dopri853_fixed_steps_give_an_independent_dop853s_errors_on_a01() {
    // benches/orders/dop853_reference.py (DOP853's tableau as scipy 1.17.1 ships it, in
    // plain numpy, scored against the exact A01 values as the bench scores) prints these
    // errors for fixed steps of 0.25, 0.125 and 0.0625 s. The same formula on the same
    // problem must give them to the three digits printed: its slope of 8.9–9.9 on A01 is
    // then the method's, not mbfx's.
    let s = scene("a01_pendulum");
    let text = s.dataset_text().unwrap();
    let v = variant_named("dopri853-fixed").unwrap();
    for (h, want) in [(0.25, 3.399e-5), (0.125, 7.229e-8), (0.0625, 1.189e-10)] {
        let p = measure(&s, &text, v, Control::FixedStep(h), Options::default());
        assert_eq!(p.status, Status::Ok, "h = {h}");
        let got = p.errors.position.unwrap();
        assert!(
            (got / want - 1.0).abs() < 2e-3,
            "h = {h}: {got:e} vs {want:e}"
        );
    }
}

#[test]
fn orders_on_a01_are_within_0_3_of_theory_but_dopri853s_fixed_steps() {
    // Theory: HHT and generalized-α 2, Newmark (β ≠ ¼) 1, the BDF at KMAX = k order k.
    // DOP853 is 8 too, but on A01 its errors above rounding are still pre-asymptotic:
    // benches/orders/dop853_reference.py --extended (40 digits) shows the slope of the
    // error at t = 10 s within 0.3 of 8 only from h = 1/512 on, at errors of 5e-23, so
    // here it must be the independent DOP853's 9.06 (the errors checked above).
    let s = scene("a01_pendulum");
    let orders = mbfx::bench::orders::measure_orders(&s, &mut |_| {}).unwrap();
    assert_eq!(orders.len(), 10);
    for o in &orders {
        let m = o
            .measured
            .unwrap_or_else(|| panic!("{}: no slope", o.method));
        let off = if o.method == "dopri853-fixed" {
            m - 9.06
        } else {
            m - o.theory
        };
        assert!(off.abs() < 0.3, "{}: {m:.2} against {}", o.method, o.theory);
        if o.method.starts_with("gstiff") {
            assert!(
                o.points.len() >= 10,
                "{}: {} points",
                o.method,
                o.points.len()
            );
        }
    }
}

#[test]
fn a02_scene_is_scored_against_the_exact_parallelogram_solution() {
    // The 3D build keeps 3 redundant equations out, and still follows §4.2's θ(t).
    let s = scene("a02_n1_3d");
    let p = at_tolerance(&s, &s.dataset_text().unwrap(), "gstiff", 1e-10);
    assert_eq!((p.status, p.dim), (Status::Ok, 3));
    assert!(p.errors.position.unwrap() < 1e-4, "{:?}", p.errors);
}

#[test]
fn bench_stability_lists_its_cases_for_the_peers_script() {
    let out = mbfx(&[
        "bench",
        "stability",
        "--list",
        "--scenes",
        scenes_dir().to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0], "case,scene,tolerance,step,must_stop");
    assert_eq!(rows.len(), 1 + mbfx::bench::stability::CASES.len());
    // The MOTION driven into lock-up must stop; a tolerance case has no step.
    assert!(
        rows.contains(&"motion_lockup,motion_lockup,1e-6,,true"),
        "{text}"
    );
    assert!(
        rows.contains(&"cart_pole_fixed,cart_pole,1e-3,1e-3,false"),
        "{text}"
    );
}

fn mbfx(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn bench_wp_writes_points_chart_and_summary() {
    let out = std::env::temp_dir().join(format!("mbfx-bench-wp-{}", std::process::id()));
    let dir = scenes_dir();
    let o = mbfx(&[
        "bench",
        "wp",
        "a01_pendulum",
        "--scenes",
        dir.to_str().unwrap(),
        "--integrators",
        "gstiff,hht-fixed",
        "--errors",
        "1e-3,1e-6",
        "--halvings",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = mbfx::bench::wp::read_csv(&out.join("a01_pendulum.csv")).unwrap();
    assert_eq!(rows.len(), 5);
    assert!(rows
        .iter()
        .all(|r| r.scene == "a01_pendulum" && r.cpu > 0.0));
    let gstiff: Vec<_> = rows.iter().filter(|r| r.method == "gstiff").collect();
    assert!(gstiff[1].error_position.unwrap() < gstiff[0].error_position.unwrap());
    let svg = std::fs::read_to_string(out.join("a01_pendulum.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("gstiff") && svg.contains("hht-fixed"));
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("| 1e-2 |"), "{md}");
    // An unknown scene or method is a diagnostic, not a panic.
    for bad in [["wp", "nope"], ["wp", "--integrators=rk4"]] {
        let o = mbfx(&[
            "bench",
            bad[0],
            bad[1],
            "--scenes",
            dir.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr).to_lowercase();
        assert!(
            err.contains("error") && err.contains(bad[1].trim_start_matches("--integrators=")),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bench_generate_prints_a_dataset_that_runs() {
    let o = mbfx(&["bench", "generate", "chain", "3"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    assert_eq!(text.matches("REVOLUTE").count(), 3);
    assert_eq!(
        mbfx(&["bench", "generate", "pendulum", "3"]).status.code(),
        Some(1)
    );
}

#[test]
fn a_motion_driven_into_its_dead_centre_stops_there_named_as_a_lock_up() {
    // The slider reaches its outer dead centre at t = 1 exactly (the scene's geometry).
    let s = scene("motion_lockup");
    let p = at_tolerance(&s, &s.dataset_text().unwrap(), "gstiff", 1e-9);
    let Status::Failed(why) = &p.status else {
        panic!("ran through the lock-up: {:?}", p.errors)
    };
    assert!(
        why.contains("singular position") && why.contains("MOTION/1"),
        "{why}"
    );
    let time: f64 = why["at time ".len()..]
        .split(':')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((time - 1.0).abs() < 1e-6, "{why}");
}

#[test]
fn a_stiff_contact_at_a_loose_tolerance_keeps_bouncing() {
    // k = 1e9: index 3 now holds velocities to ERROR while in contact; at ERROR 1e-3 the
    // block used to come to rest on the stop (0.1 m off the exact bounces by t = 2).
    let s = scene("impact_stiff_k1e9");
    let text = s.dataset_text().unwrap();
    for name in ["gstiff", "wstiff"] {
        let p = at_tolerance(&s, &text, name, 1e-3);
        assert_eq!(p.status, Status::Ok, "{name}");
        assert!(p.errors.position.unwrap() < 1e-2, "{name}: {:?}", p.errors);
    }
}

#[test]
fn a_run_whose_local_errors_add_up_past_ten_errors_says_so() {
    // HHT with fixed steps of 1e-2 on A01 ends 2e-2 off at ERROR 1e-3 (exact solution).
    let s = scene("a01_pendulum");
    let o = Options {
        error: Some(1e-3),
        ..Options::default()
    };
    let p = measure(
        &s,
        &s.dataset_text().unwrap(),
        variant_named("hht-fixed").unwrap(),
        Control::FixedStep(1e-2),
        o,
    );
    assert_eq!(p.status, Status::Ok);
    assert!(p.errors.position.unwrap() > 1e-2);
    assert!(
        p.warnings.iter().any(|w| w.contains("add up to")),
        "{:?}",
        p.warnings
    );
    // ERROR per run: the answer's error follows ERROR (dopri853 on A01, exact truth).
    let p = at_tolerance(&s, &s.dataset_text().unwrap(), "dopri853-run", 1e-6);
    assert!(
        p.errors.position.unwrap() < 1e-6 && p.warnings.is_empty(),
        "{:?} {:?}",
        p.errors,
        p.warnings
    );
}
