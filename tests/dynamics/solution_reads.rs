//! Forces that read what only the solution gives (issue 8, item 4): an acceleration, a
//! joint reaction, another force. Each scene under `tests/models/solution/` is a block on
//! a slide with constant forces, so Newton's law gives the motion in closed form (the
//! formulas in each dataset's header, computed here independently); plus the two ways
//! such a dependency cannot be solved, each an E0801 naming it.

use crate::adams::models_dir;
use crate::run::{named, run_probed, run_raw};

const G: f64 = 9.81;
const MASS: f64 = 2.0;

/// Constant acceleration `a` from rest at the origin, SFORCE/1's x force `f`: the block's
/// x, vx, ax and that force over 0–1 s at 0.25 s, tight.
fn assert_uniform(file: &str, a: f64, f: f64) {
    let model = models_dir().join("solution").join(file);
    let args = ["--end", "1", "--output-step", "0.25", "--error", "1e-9"];
    let probes = named(&[
        ("x", "DX(201)"),
        ("v", "VX(201)"),
        ("a", "ACCX(201)"),
        ("f", "SFORCE(1,0,2,0)"),
    ]);
    let csv = run_probed(&model, &args, &probes);
    let t = csv.time();
    let [x, v, acc, force] = ["x", "v", "a", "f"].map(|c| csv.col(c));
    for k in 0..t.len() {
        let close = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() <= 1e-8 * (1.0 + want.abs()),
                "{file}: {what} at t = {}: {got} vs {want}",
                t[k]
            )
        };
        close(x[k], 0.5 * a * t[k] * t[k], "x");
        close(v[k], a * t[k], "vx");
        close(acc[k], a, "ax");
        close(force[k], f, "SFORCE/1 fx");
    }
}

#[test]
fn a_force_reading_the_acceleration_it_causes_acts_as_added_mass() {
    // m·a = 10 − 0.5·a.
    let a = 10.0 / (MASS + 0.5);
    assert_uniform("added_mass.adm", a, 10.0 - 0.5 * a);
}

#[test]
fn a_force_reading_the_reaction_it_changes_is_solved_with_the_motion() {
    // Pushed along (1, 1, 0)/√2 by f = 10 − 0.3·N, N = m·g − f/√2 the joint's y force.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let f = (10.0 - 0.3 * MASS * G) / (1.0 - 0.3 * s);
    assert_uniform("friction_loop.adm", f * s / MASS, f * s);
}

#[test]
fn a_force_reading_a_later_force_sees_its_value_at_the_same_state() {
    // SFORCE/2 pushes with 4, SFORCE/1 with half of it.
    assert_uniform("force_reads_force.adm", (4.0 + 2.0) / MASS, 2.0);
}

#[test]
fn an_oscillator_with_added_mass_swings_at_the_added_mass_frequency() {
    // (m + 0.5)·ẍ = −50·x from x = 0.1 at rest: x = 0.1·cos(√(50/2.5)·t). HHT's own
    // accelerations lead the physical ones by α·h: a force reading those would move the
    // frequency (1.3e-5 m off at t = 0.75 s, where the method itself is 5e-8 m off).
    let model = models_dir().join("solution/added_mass_oscillator.adm");
    let omega = (50.0 / (MASS + 0.5f64)).sqrt();
    for integrator in ["hht", "galpha"] {
        let args = [
            "--end",
            "1",
            "--output-step",
            "0.05",
            "--error",
            "1e-9",
            "--integrator",
            integrator,
        ];
        let csv = run_probed(&model, &args, &named(&[("x", "DX(201)")]));
        for (t, x) in csv.time().iter().zip(csv.col("x")) {
            let want = 0.1 * (omega * t).cos();
            assert!(
                (x - want).abs() < 1e-6,
                "{integrator}: x({t}) = {x}, exact {want}"
            );
        }
    }
}

/// The run fails at once with E0801 and a message holding every needle.
fn assert_refused(file: &str, needles: &[&str]) {
    let model = models_dir().join("solution").join(file);
    let out = run_raw(&model, &["--end", "1", "--output-step", "0.5"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{file}: {stderr}");
    for n in ["E0801"].iter().chain(needles) {
        assert!(stderr.contains(n), "{file}: no `{n}` in\n{stderr}");
    }
}

#[test]
fn forces_reading_each_other_in_a_circle_are_refused_naming_the_circle() {
    assert_refused(
        "force_cycle.adm",
        &["SFORCE/1 reads SFORCE/2 reads SFORCE/1", "circle"],
    );
}

#[test]
fn a_loop_that_amplifies_is_refused_naming_the_force_and_what_it_reads() {
    assert_refused(
        "loop_gain.adm",
        &["SFORCE/1", "ACCX(201)", "does not converge"],
    );
}
