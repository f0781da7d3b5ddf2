//! Kinematic analysis (issue 26 §2): the driven slider-crank scene
//! (`examples/scenes/slider_crank_driven.adm`, no degree of freedom) solved from its
//! constraints alone at each output time, against its closed form (the slider's
//! position, velocity and acceleration written out here; the drive torque from the
//! scene's truth file, made by mpmath from the energy balance), and a model with a
//! degree of freedom refused, naming it. Issue 41 §2: the analysis takes its own steps
//! between outputs, so a slider-crank (crank 0.1 m, rod 0.3 m, one revolution a
//! second, `tests/data/kinematics_slider_crank.adm`) reaches the end at every output
//! step against its closed form; a crank longer than its rod
//! (`tests/data/kinematics_lock_up.adm`) stops at its lock-up, named, at the
//! closed-form time; and a DIFF integrates over the internal steps, not from output to
//! output.

use mbfx::session::request::{run, RunDone, RunFailed, RunRequest};
use std::f64::consts::PI;
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn scene() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/slider_crank_driven.adm")
}

fn rows_of(r: &RunRequest) -> Result<(Vec<Vec<f64>>, RunDone), Box<RunFailed>> {
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    let done = run(r, &mut sink, None)?;
    Ok((rows, done))
}

/// The scene's truth: (time, torque, slider x) at its [[at]] rows.
fn truth() -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(scene().with_extension("toml")).expect("truth file");
    let t: toml::Table = text.parse().expect("toml");
    let rows = t["at"].as_array().expect("[[at]]");
    rows.iter()
        .map(|r| {
            let f = |k: &str| r[k].as_float().expect("a number");
            (f("time"), f("torque"), f("slider_x"))
        })
        .collect()
}

/// The driven slider-crank's slider at time t: position, velocity, acceleration.
/// θ = ω t, ω = 2π; x = r cos θ + √(l² − r² sin² θ) = r cos θ + s, and its time
/// derivatives: ẋ = −r ω sin θ − r² ω sin θ cos θ / s,
/// ẍ = −r ω² cos θ − r² ω² (cos 2θ / s + r² sin² 2θ / (4 s³)).
fn exact(t: f64) -> (f64, f64, f64) {
    let (r, l, w) = (0.1f64, 0.4f64, 2.0 * PI);
    let th = w * t;
    let s = (l * l - (r * th.sin()).powi(2)).sqrt();
    let x = r * th.cos() + s;
    let v = -r * w * th.sin() - r * r * w * th.sin() * th.cos() / s;
    let a = -r * w * w * th.cos()
        - r * r
            * w
            * w
            * ((2.0 * th).cos() / s + r * r * (2.0 * th).sin().powi(2) / (4.0 * s.powi(3)));
    (x, v, a)
}

#[test]
fn positions_and_velocities_alone_come_from_one_factorization_of_phi_q_a_step() {
    // Issue 42 §2: rows that read no acceleration or reaction leave them unsolved, and
    // the fully driven model evaluates Φ_q once a step (the saddle-point path evaluated
    // it twice: for the projection and for the reconciliation).
    let mut req = RunRequest::file(scene());
    (req.end, req.output_step, req.kinematics) = (Some(2.0), Some(0.01), true);
    req.probes = ["x=DX(401)", "v=VX(401)"]
        .iter()
        .map(|p| mbfx::session::request::parse_probe(p))
        .collect();
    let (rows, done) = rows_of(&req).expect("kinematics");
    assert_eq!(rows.len(), 201);
    let (mut ex, mut ev) = (0.0f64, 0.0f64);
    for row in &rows {
        let (x, v, _) = exact(row[0]);
        ex = ex.max((row[1] - x).abs());
        ev = ev.max((row[2] - v).abs());
    }
    assert!(ex < 2e-15, "x off by {ex:e}");
    assert!(ev < 1e-14, "v off by {ev:e}");
    let stats = done.summary.stats;
    assert!(
        stats.jacobian_evaluations <= stats.steps + stats.rejected + 2,
        "{} Jacobian evaluations over {} steps",
        stats.jacobian_evaluations,
        stats.steps
    );
}

#[test]
fn the_driven_slider_crank_is_exact_to_rounding() {
    let mut req = RunRequest::file(scene());
    (req.end, req.output_step, req.kinematics) = (Some(2.0), Some(0.01), true);
    req.probes = [
        "x=DX(401)",
        "v=VX(401)",
        "a=ACCX(401)",
        "torque=MOTION(1, 0, 8, 0)",
    ]
    .iter()
    .map(|p| mbfx::session::request::parse_probe(p))
    .collect();
    let (rows, done) = rows_of(&req).expect("kinematics");
    assert_eq!(rows.len(), 201);
    assert_eq!(done.summary.integrator, "kinematics");
    let (mut ex, mut ev, mut ea) = (0.0f64, 0.0f64, 0.0f64);
    for row in &rows {
        let (x, v, a) = exact(row[0]);
        ex = ex.max((row[1] - x).abs());
        ev = ev.max((row[2] - v).abs());
        ea = ea.max((row[3] - a).abs());
    }
    eprintln!("kinematics: |x| error {ex:e} m, |v| {ev:e} m/s, |a| {ea:e} m/s²");
    // Rounding: positions to a few ulps of 0.5 m, velocities and accelerations to a few
    // ulps of their scale (|v| ≤ 0.8 m/s, |a| ≤ 5 m/s²).
    assert!(ex < 2e-15, "x off by {ex:e}");
    assert!(ev < 1e-14, "v off by {ev:e}");
    assert!(ea < 1e-13, "a off by {ea:e}");
    let mut et = 0.0f64;
    for (t, torque, x) in truth() {
        let row = rows
            .iter()
            .find(|r| (r[0] - t).abs() < 1e-12)
            .expect("a row at the truth's time");
        assert!((row[1] - x).abs() < 2e-15, "t = {t}: x {} vs {x}", row[1]);
        et = et.max((row[4] - torque).abs());
    }
    eprintln!("kinematics: drive torque within {et:e} N·m of the truth");
    assert!(et < 1e-12, "torque off by {et:e}");
}

#[test]
fn a_model_with_a_degree_of_freedom_is_refused_naming_it() {
    // The scene without its drive: the crank turns freely.
    let text = std::fs::read_to_string(scene())
        .expect("scene")
        .replace("MOTION/1, JOINT = 1, ROTATION, FUNCTION = 2*PI*TIME", "");
    let mut req = RunRequest::dataset("free.adm", text);
    (req.end, req.kinematics) = (Some(1.0), true);
    let f = refused(rows_of(&req));
    assert_eq!(f.code.as_str(), "E0808", "{}", f.cause);
    assert!(f.cause.contains("this one has 1"), "{}", f.cause);
    assert!(f.cause.contains("leaves free"), "{}", f.cause);
    assert!(f.cause.contains("JOINT/"), "{}", f.cause);
}

/// The failure of a run expected to fail.
fn refused<T>(r: Result<T, Box<RunFailed>>) -> Box<RunFailed> {
    match r {
        Ok(_) => panic!("the run was expected to fail"),
        Err(f) => f,
    }
}

/// A kinematic run of `file` to `end` at `output_step`, probing `probes`.
fn kinematic(file: &str, end: f64, output_step: f64, probes: &[&str]) -> RunRequest {
    let mut req = RunRequest::file(data(file));
    (req.end, req.output_step, req.kinematics) = (Some(end), Some(output_step), true);
    req.probes = probes
        .iter()
        .map(|p| mbfx::session::request::parse_probe(p))
        .collect();
    req
}

#[test]
fn the_output_step_never_decides_whether_kinematics_converges() {
    // θ = ω t, ω = 2π, r = 0.1, l = 0.3: x = r cos θ + s, s = √(l² − r² sin² θ),
    // ẋ = −r ω sin θ − r² ω sin θ cos θ / s. Output steps of 0.2, 0.25 and 0.3 stopped at
    // the first output when the analysis jumped from output to output.
    let (r, l, w) = (0.1f64, 0.3f64, 2.0 * PI);
    let exact = |t: f64| {
        let th = w * t;
        let s = (l * l - (r * th.sin()).powi(2)).sqrt();
        (
            r * th.cos() + s,
            -r * w * th.sin() - r * r * w * th.sin() * th.cos() / s,
        )
    };
    for step in [0.1, 0.125, 0.2, 0.25, 0.3, 0.37, 0.5, 1.0] {
        let req = kinematic(
            "kinematics_slider_crank.adm",
            1.0,
            step,
            &["x=DX(401)", "v=VX(401)"],
        );
        let (rows, done) = match rows_of(&req) {
            Ok(x) => x,
            Err(f) => panic!("output step {step}: {}", f.cause),
        };
        let last = rows.last().expect("rows")[0];
        assert!(
            (last - 1.0).abs() < 1e-12,
            "output step {step}: ends at {last}"
        );
        assert_eq!(
            rows.len(),
            (1.0f64 / step).ceil() as usize + 1,
            "output step {step}"
        );
        for row in &rows {
            let (x, v) = exact(row[0]);
            assert!(
                (row[1] - x).abs() < 1e-9,
                "step {step}, t = {}: x {} vs {x}",
                row[0],
                row[1]
            );
            assert!(
                (row[2] - v).abs() < 1e-9,
                "step {step}, t = {}: v {} vs {v}",
                row[0],
                row[2]
            );
        }
        eprintln!(
            "output step {step}: {} steps ({} rejected), {} Newton iterations",
            done.summary.stats.steps,
            done.summary.stats.rejected,
            done.summary.stats.newton_iterations
        );
    }
}

#[test]
fn a_lock_up_stops_the_analysis_naming_the_elements_and_the_time() {
    // Crank r = 0.2 longer than rod l = 0.1: the pin rises as r sin θ and the rod reaches
    // it only while r sin θ ≤ l, to θ = asin(l/r) = π/6, t = θ/ω = 1/12 s.
    let t_lock = (0.1f64 / 0.2).asin() / (2.0 * PI);
    for step in [0.05, 0.3] {
        let req = kinematic("kinematics_lock_up.adm", 0.5, step, &[]);
        let f = refused(rows_of(&req));
        assert_eq!(f.code.as_str(), "E0802", "{}", f.cause);
        assert!(f.cause.contains("lose rank"), "{}", f.cause);
        assert!(f.cause.contains("lock-up"), "{}", f.cause);
        // The rod's rotation is what the constraints no longer fix; the drive cannot
        // move the mechanism on.
        assert!(f.cause.contains("PART/3 rotation about z"), "{}", f.cause);
        assert!(f.cause.contains("MOTION/1 cannot drive"), "{}", f.cause);
        let element = f.element.clone().expect("an element named");
        assert!(element.starts_with("JOINT/"), "{element}");
        let time = f.time.expect("a time");
        assert!(
            (time - t_lock).abs() < 1e-3,
            "stopped at {time}, lock-up at {t_lock}"
        );
        assert!(f.cause.contains(&format!("at t = {time}")), "{}", f.cause);
    }
}

#[test]
fn a_diff_integrates_over_the_internal_steps() {
    // ẏ = DX(203), the crank pin's x = r cos ωt: y = r sin(ωt)/ω. Trapezoids from output to
    // output at 0.25 s would miss by r/ω − 0.25·r/2 = 3.4e-3 at t = 0.25; over the
    // internal steps the miss is far below 5e-4.
    let text = std::fs::read_to_string(data("kinematics_slider_crank.adm"))
        .expect("dataset")
        .replace("END", "DIFF/1, IC = 0, FUNCTION = DX(203)\nEND");
    let mut req = RunRequest::dataset("diff.adm", text);
    (req.end, req.output_step, req.kinematics) = (Some(1.0), Some(0.25), true);
    req.probes = vec![mbfx::session::request::parse_probe("y=DIF(1)")];
    let (rows, _) = rows_of(&req).expect("kinematics");
    assert_eq!(rows.len(), 5);
    let (r, w) = (0.1f64, 2.0 * PI);
    for row in &rows {
        let exact = r * (w * row[0]).sin() / w;
        assert!(
            (row[1] - exact).abs() < 5e-4,
            "t = {}: y {} vs {exact}",
            row[0],
            row[1]
        );
    }
}

#[test]
fn the_kinematics_statement_bounds_the_steps_by_hmax() {
    // KINEMATICS/HMAX = 0.01 over 1 s: at least 100 steps, whatever the output step and
    // the prediction allow (without it the prediction alone takes fewer).
    let base = std::fs::read_to_string(data("kinematics_slider_crank.adm")).expect("dataset");
    let steps = |text: String| {
        let mut req = RunRequest::dataset("hmax.adm", text);
        (req.end, req.output_step, req.kinematics) = (Some(1.0), Some(0.25), true);
        rows_of(&req).expect("kinematics").1.summary.stats.steps
    };
    let free = steps(base.clone());
    let bounded = steps(base.replace("END", "KINEMATICS/HMAX = 0.01\nEND"));
    assert!(free < 100, "{free} steps without HMAX");
    assert!(bounded >= 100, "{bounded} steps under HMAX = 0.01");
}
