//! Stepping against `run`: the same rows bit for bit with the inputs held (the IMPACT
//! block, a pendulum, under GSTIFF and dopri853), an input's closed-form response, and
//! snapshots.

use super::Stepping;
use crate::session::request::{run, RunRequest};
use crate::session::run::Method;

/// A pendulum with a PINPUT torque `TORQUE` and a POUTPUT angle `ANGLE` (the file says
/// more).
const PENDULUM: &str = include_str!("../../../tests/data/pendulum_pinput.adm");

/// The rows `run` gives for `request`.
fn run_rows(request: &RunRequest) -> Vec<Vec<f64>> {
    let mut rows = Vec::new();
    let mut sink = |row: &[f64]| -> std::io::Result<()> {
        rows.push(row.to_vec());
        Ok(())
    };
    run(request, &mut sink, None).expect("the run finishes");
    rows
}

/// Advances a stepping of `request` to each of `run`'s output times and checks that the
/// outputs after `skip` plant outputs equal the run's probe columns, bit for bit.
fn matches_run(request: &RunRequest, skip: usize) {
    let rows = run_rows(request);
    let mut s = Stepping::new(request).expect("the model builds");
    let probes = request.probes.len();
    assert_eq!(s.output_names().len(), skip + probes);
    for (k, row) in rows.iter().enumerate() {
        if k > 0 {
            s.advance(row[0]).expect("the stepping advances");
        }
        assert_eq!(s.time().to_bits(), row[0].to_bits(), "time of row {k}");
        for c in 0..probes {
            let (stepped, ran) = (s.outputs()[skip + c], row[1 + c]);
            assert_eq!(
                stepped.to_bits(),
                ran.to_bits(),
                "row {k} (t = {}), column {c}: {stepped} against {ran}",
                row[0]
            );
        }
    }
    assert!(rows.len() > 10, "{} rows", rows.len());
}

fn impact_block() -> RunRequest {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/impact_block_k1e5.adm"
    );
    let mut request = RunRequest::file(path);
    (request.end, request.output_step, request.hmin) = (Some(2.0), Some(0.01), Some(1e-10));
    request.probes = vec![
        ("y".into(), "DY(201, 101)".into()),
        ("vy".into(), "VY(201, 101)".into()),
    ];
    request
}

fn pendulum(method: Method) -> RunRequest {
    let mut request = RunRequest::dataset("pendulum.adm", PENDULUM);
    (request.end, request.output_step, request.method) = (Some(2.0), Some(0.02), Some(method));
    // The POUTPUT's expression as a probe too, so that the run's columns read what the
    // stepping's do (a velocity column makes every row reconcile).
    request.probes = vec![
        ("angle".into(), "AZ(21, 10)".into()),
        ("x".into(), "DX(20, 10)".into()),
        ("wz".into(), "WZ(21, 10)".into()),
    ];
    request
}

#[test]
fn stepping_the_impact_block_gives_runs_rows_bit_for_bit() {
    let mut request = impact_block();
    matches_run(&request, 0);
    request.method = Some(Method::Dopri853);
    matches_run(&request, 0);
}

#[test]
fn stepping_a_pendulum_gives_runs_rows_bit_for_bit() {
    matches_run(&pendulum(Method::Gstiff), 1);
    matches_run(&pendulum(Method::Dopri853), 1);
}

#[test]
fn a_held_torque_set_at_the_start_turns_the_pendulum_as_its_closed_form_says() {
    // Without gravity, a torque T about the pin turns the arm of inertia I = m·L² + Izz
    // at α = T/I: θ = α·t²/2.
    let text = PENDULUM.replace("ACCGRAV/JGRAV = -9.81\n", "");
    let mut request = RunRequest::dataset("pendulum.adm", text);
    (request.end, request.output_step, request.error) = (Some(1.0), Some(0.01), Some(1e-8));
    let mut s = Stepping::new(&request).expect("the model builds");
    assert_eq!(s.input_names(), ["TORQUE"]);
    assert_eq!(s.output_names(), ["ANGLE"]);
    let torque = 0.5;
    s.set_input("torque", torque).expect("TORQUE is an input");
    assert_eq!(s.input("VARIABLE/3"), Ok(torque));
    let alpha = torque / (1.0 + 1e-3);
    for k in 1..=100 {
        let t = f64::from(k) * 0.01;
        s.advance(t).expect("the stepping advances");
        let theta = 0.5 * alpha * t * t;
        assert!(
            (s.outputs()[0] - theta).abs() < 1e-6,
            "t = {t}: {} against {theta}",
            s.outputs()[0]
        );
    }
}

#[test]
fn inputs_that_cannot_be_set_are_refused_with_the_reason() {
    let request = pendulum(Method::Gstiff);
    let mut s = Stepping::new(&request).expect("the model builds");
    let refused = |r: Result<(), String>| r.expect_err("refused");
    assert!(refused(s.set_input("thrust", 1.0)).contains("TORQUE"));
    assert!(refused(s.set_input("ANGLE", 1.0)).contains("not an input"));
    assert!(refused(s.set_input("TORQUE", f64::NAN)).contains("finite"));
    // Backwards and NaN times leave the model where it is.
    s.advance(0.5).expect("the stepping advances");
    let before = s.outputs().to_vec();
    s.advance(0.25).expect("a time behind is no step");
    s.advance(f64::NAN).expect("nor is NaN");
    assert_eq!((s.time(), s.outputs()), (0.5, before.as_slice()));
}

#[test]
fn a_restored_snapshot_and_a_reset_repeat_their_bits() {
    let request = pendulum(Method::Gstiff);
    let mut s = Stepping::new(&request).expect("the model builds");
    s.set_input("TORQUE", 0.3).expect("TORQUE is an input");
    s.advance(0.5).expect("the stepping advances");
    let snap = s.state();
    assert_eq!(snap.time(), 0.5);
    let mut went_on = Vec::new();
    for _ in 0..2 {
        s.restore(&snap);
        assert_eq!(s.time(), 0.5);
        assert_eq!(s.input("TORQUE"), Ok(0.3));
        s.advance(1.0).expect("the stepping advances");
        went_on.push(s.outputs().to_vec());
    }
    assert_eq!(went_on[0], went_on[1]);
    s.reset();
    assert_eq!((s.time(), s.input("TORQUE")), (0.0, Ok(0.0)));
    let mut fresh = Stepping::new(&request).expect("the model builds");
    assert_eq!(s.outputs(), fresh.outputs());
    for t in [0.3, 0.6, 1.0] {
        s.advance(t).expect("the stepping advances");
        fresh.advance(t).expect("the stepping advances");
        assert_eq!(s.outputs(), fresh.outputs(), "t = {t}");
    }
}

#[test]
fn a_stepping_without_an_output_step_takes_the_first_interval_and_refuses_a_command_file() {
    // The first advance's interval is the output step: advancing by 0.02 is then the
    // run with output step 0.02.
    let mut request = pendulum(Method::Gstiff);
    let rows = run_rows(&request);
    (request.end, request.output_step) = (None, None);
    let mut s = Stepping::new(&request).expect("the model builds");
    for row in &rows[1..] {
        s.advance(row[0]).expect("the stepping advances");
        assert_eq!(s.outputs()[1..], row[1..4], "t = {}", row[0]);
    }
    let Err(f) = Stepping::new(&RunRequest::file("run.acf")) else {
        panic!("a command file stepped")
    };
    assert!(f.cause.contains("command file"), "{}", f.cause);
}
