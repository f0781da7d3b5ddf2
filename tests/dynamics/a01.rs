//! IFToMM A01 (reference-problems §4.1) as `tests/models/a01_pendulum.adm`: the dataset is
//! the problem as published, a 10 s run with error control stays within 1e-5 m of the
//! exact elliptic-function solution and conserves energy, and both methods are second order
//! in fixed-step mode.

use crate::adams::models_dir;
use crate::exact::statement;
use crate::reference::{a01_exact, A01_GRAVITY, A01_LENGTH, A01_MASS};
use crate::run::{named, run_probed, Csv};
use std::path::PathBuf;

fn dataset() -> PathBuf {
    models_dir().join("a01_pendulum.adm")
}

/// The fixed-step mode's flags; `H` follows the last one. One place to change when the CLI
/// settles (issue 8 asks for "a fixed-step mode for comparisons" without naming it).
pub const FIXED_STEP_FLAGS: &[&str] = &["--fixed-step"];

/// ERROR for the 10 s run: the issue's figure asks for max position error ≤ 1e-5 "with error
/// control"; this is the setting that run uses (tune it, not the bound).
pub const A01_ERROR: &str = "1e-10";

/// |E(t) − E(0)| allowed with positions within 1e-5 m: m·g·1e-5 (height) plus
/// m·v_max·ω₀·1e-5 (speed, v_max = √(2gL) = 4.43 m/s, ω₀ = 3.13 rad/s), about 2.4e-4 J.
pub const A01_ENERGY_TOL: f64 = 2.5e-4;

fn run_a01(args: &[&str]) -> Csv {
    let probes = named(&[
        ("x", "DX(201,101)"),
        ("y", "DY(201,101)"),
        ("vx", "VX(201,101)"),
        ("vy", "VY(201,101)"),
    ]);
    run_probed(&dataset(), args, &probes)
}

/// Largest |P1 − exact| over the rows of a run.
pub fn max_position_error(csv: &Csv) -> f64 {
    let (t, x, y) = (csv.time(), csv.col("x"), csv.col("y"));
    (0..t.len())
        .map(|k| {
            let (xe, ye) = a01_exact(t[k]);
            (x[k] - xe).hypot(y[k] - ye)
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_dataset_is_the_published_problem() {
    let text = std::fs::read_to_string(dataset()).unwrap();
    let has = |head: &str, args: &[&str]| {
        let st = statement(&text, head).unwrap_or_else(|| panic!("no {head}"));
        for a in args {
            assert!(st.contains(a), "{head}: `{a}` not in `{st}`");
        }
    };
    assert_eq!((A01_MASS, A01_LENGTH, A01_GRAVITY), (1.0, 1.0, 9.81));
    has(
        "UNITS/",
        &[
            "FORCE = NEWTON",
            "MASS = KILOGRAM",
            "LENGTH = METER",
            "TIME = SECOND",
        ],
    );
    has("PART/2", &["MASS = 1", "CM = 201", "IP = 0, 0, 0"]);
    has("MARKER/201", &["PART = 2", "QP = 1, 0, 0"]);
    has("MARKER/202", &["PART = 2", "QP = 0, 0, 0"]);
    has("MARKER/102", &["PART = 1", "QP = 0, 0, 0"]);
    has("JOINT/1", &["REVOLUTE", "I = 102, J = 202"]);
    has("ACCGRAV/", &["JGRAV = -9.81"]);
    assert!(!text.contains("REULER"), "pin axis must be global z");
    // And mbfx reads it as one degree of freedom, planar.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mbfx"))
        .arg("check")
        .arg(dataset())
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{report}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(report.contains("actual 1"), "{report}");
}

#[test]
fn a01_ten_seconds_with_error_control_within_1e_5_and_energy_kept() {
    for integrator in crate::run::INTEGRATORS {
        let csv = run_a01(&[
            "--end",
            "10",
            "--output-step",
            "0.01",
            "--integrator",
            integrator,
            "--error",
            A01_ERROR,
        ]);
        csv.assert_grid(0.01, Some(10.0));
        let err = max_position_error(&csv);
        assert!(err <= 1e-5, "{integrator}: max position error {err:e}");
        let (y, vx, vy) = (csv.col("y"), csv.col("vx"), csv.col("vy"));
        // T + V with V = m·g·y; 0 at the start (at rest, y = 0).
        let drift = (0..y.len())
            .map(|k| {
                0.5 * A01_MASS * (vx[k].powi(2) + vy[k].powi(2)) + A01_MASS * A01_GRAVITY * y[k]
            })
            .fold(0.0_f64, |m, e| m.max(e.abs()));
        assert!(
            drift <= A01_ENERGY_TOL,
            "{integrator}: energy drift {drift:e} J"
        );
    }
}

/// Observed order from the max position error over 2 s at h, h/2, h/4.
fn observed_orders(integrator: &str) -> (Vec<f64>, Vec<f64>) {
    let errors: Vec<f64> = [4e-3, 2e-3, 1e-3]
        .iter()
        .map(|h| {
            let h = format!("{h}");
            let mut args = vec![
                "--end",
                "2",
                "--output-step",
                "0.02",
                "--integrator",
                integrator,
            ];
            args.extend(FIXED_STEP_FLAGS);
            args.push(&h);
            let csv = run_a01(&args);
            csv.assert_grid(0.02, Some(2.0));
            max_position_error(&csv)
        })
        .collect();
    let slopes = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    (errors, slopes)
}

#[test]
fn hht_fixed_step_is_second_order_on_a01() {
    let (errors, slopes) = observed_orders("hht");
    for s in &slopes {
        assert!(
            (s - 2.0).abs() <= 0.3,
            "hht: errors {errors:?}, slopes {slopes:?}"
        );
    }
}

#[test]
fn galpha_fixed_step_is_second_order_on_a01() {
    let (errors, slopes) = observed_orders("galpha");
    for s in &slopes {
        assert!(
            (s - 2.0).abs() <= 0.3,
            "galpha: errors {errors:?}, slopes {slopes:?}"
        );
    }
}
