//! Driven systems against their exact solutions, written out here by hand: MOTIONs on
//! DISPLACEMENT, VELOCITY and ACCELERATION (spec §4.5: the displacement is the integral of
//! the function from ICDISP, and ICVEL), a GCON on SIN of a measure, and a MOTION on an
//! IMPACT whose stiffness varies (its second derivative in the stiffness).
//!
//! Every model (`tests/models/motions/`) has no free degree of freedom, so the exact
//! trajectory is the drive itself and the reaction follows from Newton's law along the
//! driven coordinate: for the 2 kg slider on an axis rising at 30°, the MOTION's force on
//! the slider along z_J is m·a + m·g·sin 30°; for the pendulum (CM at L from the pivot),
//! its torque is (Izz + m·L²)·θ̈ + m·g·L·cos θ.

use crate::adams::models_dir;
use crate::exact::G;
use crate::run::{named, run_probed, run_raw, INTEGRATORS};
use std::f64::consts::PI;
use std::path::PathBuf;

/// A column: probe name, expression, exact value at t.
type Column = (&'static str, &'static str, fn(f64) -> f64);

fn model(file: &str) -> PathBuf {
    models_dir().join("motions").join(file)
}

/// The slider's mass and the MOTION's axial force for acceleration `a`.
const M: f64 = 2.0;
fn slider_force(a: f64) -> f64 {
    M * a + M * G * 0.5
}

/// Travel, velocity and acceleration along z_J, and the MOTION's force on the slider in
/// J axes.
const X: &str = "DZ(202, 102, 102)";
const V: &str = "VZ(202, 102, 102, 102)";
const A: &str = "ACCZ(202, 102, 102, 102)";
const F: &str = "MOTION(1, 0, 4, 102)";

/// Runs `file` 0–2 s at 0.01 s with each integrator at ERROR 1e-10 and checks every
/// column against its exact value within `rel` of the column's largest magnitude (at
/// least 1). The drives fix every coordinate, so what is left is rounding and Newton's
/// tolerance: measured errors are below 1e-13 in every column.
fn check(file: &str, columns: &[Column], rel: f64) {
    let probes: Vec<(&str, &str)> = columns.iter().map(|(n, e, _)| (*n, *e)).collect();
    for integrator in INTEGRATORS {
        let args = [
            "--end",
            "2",
            "--output-step",
            "0.01",
            "--integrator",
            integrator,
            "--error",
            "1e-10",
        ];
        let csv = run_probed(&model(file), &args, &named(&probes));
        csv.assert_grid(0.01, Some(2.0));
        let time = csv.time();
        for (name, _, exact) in columns {
            let got = csv.col(name);
            let want: Vec<f64> = time.iter().map(|&t| exact(t)).collect();
            let scale = want.iter().fold(1.0f64, |m, w| m.max(w.abs()));
            for ((t, g), w) in time.iter().zip(&got).zip(&want) {
                let err = (g - w).abs();
                assert!(
                    err <= rel * scale,
                    "{file} {integrator} {name} at t = {t}: {g} vs exact {w} (error {err:e})"
                );
            }
        }
    }
}

#[test]
fn displacement_motion_on_sin_of_time_matches_the_exact_solution() {
    let cols: [Column; 4] = [
        ("x", X, |t| 0.1 * (2.0 * PI * t).sin()),
        ("v", V, |t| 0.2 * PI * (2.0 * PI * t).cos()),
        ("a", A, |t| -0.4 * PI * PI * (2.0 * PI * t).sin()),
        ("F", F, |t| {
            slider_force(-0.4 * PI * PI * (2.0 * PI * t).sin())
        }),
    ];
    check("slider_sin.adm", &cols, 1e-10);
}

#[test]
fn velocity_motion_integrates_its_function_from_icdisp() {
    // VELOCITY = 2·TIME, ICDISP = 0.05: x = 0.05 + t² (assembly moves the slider there).
    let cols: [Column; 4] = [
        ("x", X, |t| 0.05 + t * t),
        ("v", V, |t| 2.0 * t),
        ("a", A, |_| 2.0),
        ("F", F, |_| slider_force(2.0)),
    ];
    check("slider_velocity.adm", &cols, 1e-10);
}

#[test]
fn acceleration_motion_integrates_its_function_twice_from_icdisp_and_icvel() {
    // ACCELERATION = 3·cos 2t, ICDISP = 0.02, ICVEL = −0.1.
    let cols: [Column; 4] = [
        ("x", X, |t| 0.02 - 0.1 * t + 0.75 * (1.0 - (2.0 * t).cos())),
        ("v", V, |t| -0.1 + 1.5 * (2.0 * t).sin()),
        ("a", A, |t| 3.0 * (2.0 * t).cos()),
        ("F", F, |t| slider_force(3.0 * (2.0 * t).cos())),
    ];
    check("slider_acceleration.adm", &cols, 1e-10);
}

#[test]
fn acceleration_motion_turns_a_pendulum_past_half_a_turn() {
    // θ = 0.3 + 2t + (1 − cos t): CM at L = 0.5, torque (Izz + m L²)·θ̈ + m g L cos θ.
    fn theta(t: f64) -> f64 {
        0.3 + 2.0 * t + 1.0 - t.cos()
    }
    let cols: [Column; 5] = [
        ("x", "DX(201, 101)", |t| 0.5 * theta(t).cos()),
        ("y", "DY(201, 101)", |t| 0.5 * theta(t).sin()),
        ("w", "WZ(201)", |t| 2.0 + t.sin()),
        ("wd", "WDTZ(201)", |t| t.cos()),
        ("T", "MOTION(1, 0, 8, 0)", |t| {
            (0.02 + 1.5 * 0.25) * t.cos() + 1.5 * G * 0.5 * theta(t).cos()
        }),
    ];
    check("pendulum_acceleration.adm", &cols, 1e-10);
}

#[test]
fn gcon_on_sin_of_a_measure_starts_and_follows_its_solution() {
    // sin x = s(t) = 0.5·sin 2t: x = asin s, ẋ = ṡ/c, ẍ = s̈/c + s·ṡ²/c³, c = √(1 − s²).
    fn parts(t: f64) -> (f64, f64, f64, f64) {
        let s = 0.5 * (2.0 * t).sin();
        (
            s,
            (2.0 * t).cos(),
            -2.0 * (2.0 * t).sin(),
            (1.0 - s * s).sqrt(),
        )
    }
    let cols: [Column; 3] = [
        ("x", X, |t| parts(t).0.asin()),
        ("v", V, |t| {
            let (_, sd, _, c) = parts(t);
            sd / c
        }),
        ("a", A, |t| {
            let (s, sd, sdd, c) = parts(t);
            sdd / c + s * sd * sd / (c * c * c)
        }),
    ];
    check("slider_gcon_sin.adm", &cols, 1e-10);
}

#[test]
fn integrated_motions_give_the_same_bits_in_both_engines() {
    let file = model("slider_acceleration.adm");
    let args = [
        "--end",
        "1",
        "--output-step",
        "0.05",
        "--probe",
        &format!("F={F}"),
    ];
    let outs: Vec<Vec<u8>> = ["jit", "interp"]
        .iter()
        .map(|engine| {
            let mut a = args.to_vec();
            a.extend(["--engine", engine]);
            let out = run_raw(&file, &a);
            assert!(out.status.success(), "{engine}");
            out.stdout
        })
        .collect();
    assert_eq!(outs[0], outs[1]);
}

#[test]
fn motion_on_an_impact_with_a_varying_stiffness_follows_its_travel() {
    // x = (100 + t)(1 − t)² below t = 1, 0 after: v = (1 − t)² − 2(100 + t)(1 − t),
    // a = 2(100 + t) − 4(1 − t); the MOTION's force is m·a (no gravity). At t = 1 the
    // travel's acceleration jumps from 202 to 0 (the contact ends).
    fn part(t: f64, f: fn(f64) -> f64) -> f64 {
        if t < 1.0 {
            f(t)
        } else {
            0.0
        }
    }
    let cols: [Column; 4] = [
        ("x", X, |t| part(t, |t| (100.0 + t) * (1.0 - t).powi(2))),
        ("v", V, |t| {
            part(t, |t| (1.0 - t).powi(2) - 2.0 * (100.0 + t) * (1.0 - t))
        }),
        ("a", A, |t| part(t, |t| 2.0 * (100.0 + t) - 4.0 * (1.0 - t))),
        ("F", F, |t| {
            M * part(t, |t| 2.0 * (100.0 + t) - 4.0 * (1.0 - t))
        }),
    ];
    check("slider_impact_varying_stiffness.adm", &cols, 1e-10);
}
