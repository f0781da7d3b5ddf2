//! GSTIFF and WSTIFF (issue 9) on the IFToMM A01 pendulum against its exact
//! elliptic-function solution (reference-problems §4.1): the 10 s run within 1e-6 m in
//! both formulations, and the measured order of each BDF order (KMAX = k) matching k.
//! The chrono, A02, contact and motion tests run GSTIFF too, through
//! [`crate::run::INTEGRATORS`].

use crate::a01::max_position_error;
use crate::adams::models_dir;
use crate::run::{named, run_raw, Csv};

/// Runs A01 with `args`, returning the rows and the summary's step count.
fn run_a01(args: &[&str]) -> (Csv, usize) {
    let probes = named(&[("x", "DX(201,101)"), ("y", "DY(201,101)")]);
    let mut all: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    for (name, expr) in &probes {
        all.push("--probe".into());
        all.push(format!("{name}={expr}"));
    }
    let all: Vec<&str> = all.iter().map(String::as_str).collect();
    let out = run_raw(&models_dir().join("a01_pendulum.adm"), &all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?}: {stderr}");
    let steps = stderr
        .lines()
        .find_map(|l| l.split_once(" steps (").map(|(a, _)| a.to_string()))
        .and_then(|a| a.rsplit(' ').next().and_then(|n| n.parse().ok()))
        .unwrap_or_else(|| panic!("no step count in {stderr}"));
    (Csv::parse(&String::from_utf8_lossy(&out.stdout)), steps)
}

#[test]
fn a01_ten_seconds_within_1e_6_in_both_formulations() {
    for (integrator, formulation) in [("gstiff", "i3"), ("gstiff", "si2"), ("wstiff", "i3")] {
        let (csv, steps) = run_a01(&[
            "--end",
            "10",
            "--output-step",
            "0.1",
            "--integrator",
            integrator,
            "--formulation",
            formulation,
            "--error",
            "1e-9",
        ]);
        csv.assert_grid(0.1, Some(10.0));
        let err = max_position_error(&csv);
        eprintln!("A01 10 s {integrator} {formulation}: {steps} steps, max error {err:.3e} m");
        assert!(err <= 1e-6, "{integrator} {formulation}: {err:e}");
    }
}

/// The order k observed with KMAX = k: the slope of log(error) against log(steps) between
/// a loose and a tight ERROR (rows every 1 s, so error control alone sets the steps;
/// a run's global error is about its steps' local errors, each O(h^(k+1)), so it falls as
/// steps^(−k)).
fn observed_order(k: u32, end: &str, errors: [&str; 2]) -> (f64, [(usize, f64); 2]) {
    let kmax = k.to_string();
    let runs = errors.map(|e| {
        let (csv, steps) = run_a01(&[
            "--end",
            end,
            "--output-step",
            "1",
            "--integrator",
            "gstiff",
            "--kmax",
            &kmax,
            "--error",
            e,
            // An order-1 start at ERROR 1e-11 needs steps of about 1e-6 s, HMIN's default.
            "--hmin",
            "1e-10",
        ]);
        (steps, max_position_error(&csv))
    });
    let slope = (runs[0].1 / runs[1].1).ln() / (runs[1].0 as f64 / runs[0].0 as f64).ln();
    (slope, runs)
}

#[test]
fn each_bdf_order_shows_its_order_on_a01() {
    let mut bad = Vec::new();
    // End time, loose and tight ERROR per order: 10 s dilutes the start (orders 1 to k
    // at small steps); order 1 runs 2 s, as over 10 s its damping leaves the pendulum
    // off by the swing itself at both ERRORs; the tight runs stay above rounding.
    for (k, end, errors) in [
        (1, "2", ["1e-3", "1e-5"]),
        (2, "10", ["1e-5", "1e-8"]),
        (3, "10", ["1e-5", "1e-9"]),
        (4, "10", ["1e-5", "1e-10"]),
        (5, "10", ["1e-6", "1e-11"]),
        (6, "10", ["1e-6", "1e-11"]),
    ] {
        let (slope, runs) = observed_order(k, end, errors);
        eprintln!("KMAX = {k}: (steps, error) {runs:?}, slope {slope:.2}");
        if (slope - k as f64).abs() > 0.6 {
            bad.push(format!("KMAX = {k}: slope {slope:.2} from {runs:?}"));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
