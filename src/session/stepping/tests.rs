//! Stepping against `run`: the same rows bit for bit with the inputs held (the IMPACT
//! block, a pendulum, under GSTIFF and dopri853), an input's closed-form response, and
//! snapshots.

use super::Stepping;
use crate::session::request::{run, RunRequest};
use crate::session::run::Method;

/// A pendulum with a PINPUT torque `TORQUE` and a POUTPUT angle `ANGLE` (the file says
/// more).
const PENDULUM: &str = include_str!("../../../examples/pendulum_pinput.adm");

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

/// The calling thread's CPU seconds.
fn cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec the call writes; the clock id is a constant.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
}

/// The median of `xs`.
fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// CPU medians of a run to `end` (output step 1 ms, then END/100) against a stepping
/// advanced by 1 ms with its input changed at each advance (`u` = 1e-9·k: a new value,
/// a negligible force), on `path` with an input force on `i`, `j` added.
fn cost(path: &str, (i, j): (u32, u32), end: f64, hmin: f64) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(path).expect("the scene is there");
    let input = format!(
        "VARIABLE/901, FUNCTION = 0\nSFORCE/901, TRANSLATION, ACTIONONLY, I = {i}, J = {j}, \
         FUNCTION = VARVAL(901)\nPINPUT/901, VARIABLES = 901\nEND\n"
    );
    let text = text.replacen("\nEND", &format!("\n{input}"), 1);
    let mut request = RunRequest::dataset("scene.adm", text);
    (request.end, request.hmin) = (Some(end), Some(hmin));
    let timed = |f: &mut dyn FnMut()| {
        let t0 = cpu_seconds();
        f();
        cpu_seconds() - t0
    };
    let (mut fine, mut coarse, mut stepped) = (Vec::new(), Vec::new(), Vec::new());
    let steps = (end / 1e-3).round() as usize;
    for _ in 0..11 {
        request.output_step = Some(1e-3);
        fine.push(timed(&mut || {
            run_rows(&request);
        }));
        request.output_step = None;
        coarse.push(timed(&mut || {
            run_rows(&request);
        }));
        request.output_step = Some(1e-3);
        stepped.push(timed(&mut || {
            let mut s = Stepping::new(&request).expect("the model builds");
            for k in 1..=steps {
                s.set_input("VARIABLE/901", 1e-9 * k as f64)
                    .expect("an input");
                s.advance(k as f64 * 1e-3).expect("the stepping advances");
            }
        }));
    }
    (median(fine), median(coarse), median(stepped))
}

#[test]
#[ignore = "a measurement (docs/python.md, Stepping a model): cargo test --release -- --ignored stepping_cost"]
fn stepping_cost_by_1ms_with_a_changing_input() {
    let root = env!("CARGO_MANIFEST_DIR");
    for (name, body, end, hmin) in [
        ("impact_block_k1e5", (201, 101), 2.0, 1e-10),
        ("cart_pole", (203, 102), 2.0, 1e-14),
    ] {
        let path = format!("{root}/examples/scenes/{name}.adm");
        let (fine, coarse, stepped) = cost(&path, body, end, hmin);
        println!(
            "{name}: run (1 ms rows) {:.2} ms, run (END/100 rows) {:.2} ms, stepped by 1 ms \
             with a changed input {:.2} ms: {:.2}x and {:.2}x",
            fine * 1e3,
            coarse * 1e3,
            stepped * 1e3,
            stepped / fine,
            stepped / coarse
        );
    }
}
