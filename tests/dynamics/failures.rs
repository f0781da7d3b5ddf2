//! The failure kinds of `mbfx run` (issue 8, item 5), each triggered on purpose by a small
//! dataset under `tests/models/failures/` whose header says how: exit code 1, a diagnostic
//! naming the time, the cause and the element, and the CSV keeping every row before the
//! failure. Also a time-dependent GCON that must not be lost to the 2D reduction.

use crate::a01::FIXED_STEP_FLAGS;
use crate::adams::models_dir;
use crate::run::{run, Csv};

/// One deliberate failure.
struct Failure {
    file: &'static str,
    /// Whether the run is in fixed-step mode (so the step cannot shrink into another kind).
    fixed_step: bool,
    /// When it must fail, from the dataset's construction.
    window: (f64, f64),
    /// Any of these names the element at fault (case-insensitive).
    elements: &'static [&'static str],
    /// Any of these names the cause (case-insensitive).
    causes: &'static [&'static str],
}

const DT: f64 = 0.01;

/// Every number in `text` (a scanner, so `t = 0.501,` and `0.501s` both count).
fn numbers(text: &str) -> Vec<f64> {
    let mut out = Vec::new();
    let mut cur = String::new();
    for ch in text.chars().chain(std::iter::once(' ')) {
        let continues = ch.is_ascii_digit()
            || ch == '.'
            || ((ch == 'e' || ch == 'E') && !cur.is_empty())
            || ((ch == '-' || ch == '+') && (cur.is_empty() || cur.ends_with(['e', 'E'])));
        if continues {
            cur.push(ch);
        } else {
            if let Ok(v) = cur.trim_end_matches(['e', 'E', '.']).parse::<f64>() {
                out.push(v);
            }
            cur.clear();
        }
    }
    out
}

fn check(f: &Failure) {
    let model = models_dir().join("failures").join(f.file);
    let h = "1e-3";
    let mut args = vec!["--end", "1", "--output-step", "0.01", "--dim", "3"];
    if f.fixed_step {
        args.extend(FIXED_STEP_FLAGS);
        args.push(h);
    }
    let out = crate::run::run_raw(&model, &args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_lowercase();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}: exit status; stderr:\n{stderr}",
        f.file
    );
    assert!(
        f.elements
            .iter()
            .any(|e| stderr.contains(&e.to_lowercase())),
        "{}: the diagnostic names none of {:?}:\n{stderr}",
        f.file,
        f.elements
    );
    assert!(
        f.causes.iter().any(|c| stderr.contains(c)),
        "{}: the diagnostic names no cause of {:?}:\n{stderr}",
        f.file,
        f.causes
    );
    let (lo, hi) = f.window;
    assert!(
        numbers(&stderr).iter().any(|t| (lo..=hi).contains(t)),
        "{}: no time in [{lo}, {hi}] in the diagnostic:\n{stderr}",
        f.file
    );
    // The CSV keeps the rows up to the failure: all of them on the grid, the last one no
    // later than the failure and no more than one output step before the window.
    let csv = Csv::parse(&String::from_utf8(out.stdout).expect("UTF-8 CSV"));
    csv.assert_grid(DT, None);
    let last = csv.time().last().copied().expect("rows before the failure");
    assert!(
        last >= lo - DT - 1e-9 && last <= hi,
        "{}: last CSV row at {last}, failure in [{lo}, {hi}]",
        f.file
    );
}

#[test]
fn newton_divergence_is_reported() {
    check(&Failure {
        file: "newton_divergence.adm",
        fixed_step: true,
        window: (0.45, 0.56),
        elements: &["GCON/1"],
        causes: &["newton", "converge", "diverge"],
    });
}

#[test]
fn step_below_hmin_is_reported() {
    check(&Failure {
        file: "step_below_hmin.adm",
        fixed_step: false,
        window: (0.49, 0.51),
        // The error estimate that will not pass is PART/2's; its cause is SFORCE/1.
        elements: &["PART/2", "SFORCE/1"],
        causes: &["hmin"],
    });
}

#[test]
fn singular_matrix_is_reported() {
    check(&Failure {
        file: "singular_matrix.adm",
        fixed_step: true,
        window: (0.5, 0.51),
        elements: &["GCON/1"],
        causes: &["singular"],
    });
}

#[test]
fn nan_in_a_force_is_reported() {
    check(&Failure {
        file: "nan_in_force.adm",
        fixed_step: true,
        window: (0.5, 0.51),
        elements: &["SFORCE/1"],
        causes: &["nan", "not a number", "non-finite"],
    });
}

#[test]
fn a_dropped_row_violated_is_reported() {
    check(&Failure {
        file: "dropped_row_violated.adm",
        fixed_step: false,
        window: (0.5, 0.6),
        // Which of the two equal rows is dropped is the pivoting's choice (spec §5.2).
        elements: &["GCON/1", "GCON/2"],
        causes: &["conflict", "dropped", "redundant"],
    });
}

#[test]
fn the_number_scanner_finds_times() {
    assert_eq!(numbers("at t = 0.501, GCON/1: 3e-4s"), [0.501, 1.0, 3e-4]);
    assert_eq!(numbers("time 5.000e-1."), [0.5]);
}

/// A GCON satisfied at t = 0 only must keep the scene 3D (or be honoured in 2D): the slide
/// follows x = 0.1·STEP(t, 0, 0, 1, 1) exactly, whatever dimension mbfx picks.
#[test]
fn a_time_dependent_gcon_out_of_the_plane_is_not_dropped() {
    let model = models_dir().join("gcon_drives_out_of_plane.adm");
    let csv = run(
        &model,
        &[
            "--end",
            "1",
            "--output-step",
            "0.01",
            "--probe",
            "x=DX(201,101)",
        ],
    );
    csv.assert_grid(DT, Some(1.0));
    for (t, x) in csv.time().iter().zip(csv.col("x")) {
        let d = t.clamp(0.0, 1.0);
        let exact = 0.1 * d * d * (3.0 - 2.0 * d);
        assert!((x - exact).abs() < 1e-9, "t = {t}: x = {x}, exact {exact}");
    }
}

/// Integrator parameters outside their ranges are command-line errors, not clamped.
#[test]
fn integrator_parameters_out_of_range_are_refused() {
    let model = models_dir().join("a01_pendulum.adm");
    for args in [
        ["--alpha", "-0.5"],
        ["--alpha", "0.1"],
        ["--rho-inf", "1.5"],
    ] {
        let mut all = vec!["--end", "0.1"];
        all.extend(args);
        let out = crate::run::run_raw(&model, &all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("E0503") && stderr.contains(args[0]),
            "{stderr}"
        );
    }
}

#[test]
fn a_force_reading_a_user_variable_names_the_variable_and_why() {
    let model = models_dir().join("failures/user_variable.adm");
    let out = crate::run::run_raw(&model, &["--end", "1", "--output-step", "0.1"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    for needle in ["E0801", "SFORCE/1", "VARVAL(2)", "USER"] {
        assert!(stderr.contains(needle), "no `{needle}` in\n{stderr}");
    }
}
