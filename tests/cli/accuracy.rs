//! `mbfx run`'s accuracy warnings (issue 25 §3), judged against a closed form: an
//! undamped spring-mass oscillator, x = 1 + 0.2 cos 10t. By default a run warns when its
//! local errors add up past 10×ERROR; `--estimate-error` runs again at ERROR/10 and warns
//! instead when the answer's error is estimated past 10×ERROR, and `--strict` makes a
//! warning exit 3.

use super::{mbfx, Run};

/// Runs the oscillator for 10 s (16 periods) with `extra` options; the run and the
/// largest error of its x column against the closed form.
fn oscillate(extra: &[&str]) -> (Run, f64) {
    // A 1 kg slider on a rail along global x, on a spring (K = 100, free length 1) to
    // the ground origin, released at rest at x = 1.2: x(t) = 1 + 0.2 cos 10t.
    let model = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/models/oscillator.adm");
    let base = ["run", model, "--end", "10"];
    let probe = [
        "--output-step",
        "0.1",
        "--probe",
        "x=DX(20, 10)",
        "--csv",
        "-",
    ];
    let run = mbfx(&[&base[..], &probe, extra].concat());
    assert!(run.code == 0 || run.code == 3, "{}", run.describe());
    let mut worst: f64 = 0.0;
    for line in run.stdout.lines().skip(1) {
        let row: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("a number"))
            .collect();
        let exact = 1.0 + 0.2 * (10.0 * row[0]).cos();
        worst = worst.max((row[1] - exact).abs());
    }
    assert_eq!(run.stdout.lines().count(), 102, "{}", run.describe());
    (run, worst)
}

#[test]
fn an_accurate_run_is_quiet_with_the_estimate_and_a_wrong_one_warns() {
    // dopri853 at ERROR 1e-3 is far within it: no warning with the estimate.
    let dopri = ["--integrator", "dopri853", "--error", "1e-3"];
    let (run, error) = oscillate(&[&dopri[..], &["--estimate-error", "--strict"]].concat());
    assert!(error < 1e-3, "error {error:e}\n{}", run.describe());
    assert_eq!(run.code, 0, "{}", run.describe());
    assert!(!run.stderr.contains("warning:"), "{}", run.describe());
    assert!(
        run.stderr.contains("error estimate: "),
        "{}",
        run.describe()
    );
    // GSTIFF at ERROR 1e-3 drifts in phase over 16 periods: more than 10×ERROR off.
    let gstiff = ["--integrator", "gstiff", "--error", "1e-3"];
    let (summed, error) = oscillate(&gstiff);
    assert!(error > 1e-2, "error {error:e}\n{}", summed.describe());
    assert!(summed.stderr.contains("add up to"), "{}", summed.describe());
    let (warned, again) = oscillate(&[&gstiff[..], &["--estimate-error"]].concat());
    assert_eq!(warned.code, 0, "{}", warned.describe());
    assert!(
        warned
            .stderr
            .contains("warning: the answer's error is estimated at"),
        "{}",
        warned.describe()
    );
    // The estimate judges the run instead of the sum.
    assert!(
        !warned.stderr.contains("add up to"),
        "{}",
        warned.describe()
    );
    // The estimate's second run changes no row.
    assert_eq!(
        (warned.stdout.as_str(), again),
        (summed.stdout.as_str(), error)
    );
    let (strict, _) = oscillate(&[&gstiff[..], &["--estimate-error", "--strict"]].concat());
    assert_eq!(strict.code, 3, "{}", strict.describe());
    assert_eq!(strict.stdout, summed.stdout, "the rows are the same");
}

/// The estimate follows the error of the output column against the closed form: within
/// a factor 3 either way for a BDF, HHT and dopri853 (a true error from outside the
/// code: x = 1 + 0.2 cos 10t).
#[test]
fn the_estimate_follows_the_closed_form_error() {
    for (method, error) in [("gstiff", "1e-5"), ("hht", "1e-4"), ("dopri853", "1e-6")] {
        let args = ["--integrator", method, "--error", error, "--estimate-error"];
        let (run, actual) = oscillate(&args);
        let tolerance: f64 = error.parse().expect("a number");
        let line = run
            .stderr
            .lines()
            .find_map(|l| l.strip_prefix("error estimate: "))
            .unwrap_or_else(|| panic!("no estimate\n{}", run.describe()));
        let estimate: f64 = line
            .split('×')
            .next()
            .and_then(|x| x.parse().ok())
            .unwrap_or_else(|| panic!("{line}"));
        // The column's size is its largest magnitude, 1.2 (at t = 0).
        let ratio = estimate * tolerance * 1.2 / actual;
        assert!(
            (1.0 / 3.0..3.0).contains(&ratio),
            "{method} at {error}: estimate {estimate}×ERROR, error {actual:e}"
        );
    }
}
