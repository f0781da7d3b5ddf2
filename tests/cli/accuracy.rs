//! `mbfx run`'s accuracy warnings (issue 25 §3), judged against a closed form: an
//! undamped spring-mass oscillator, x = 1 + 0.2 cos 10t. By default a run prints no
//! warning about its local errors; `--estimate-error` runs again at 10×ERROR and warns
//! when the answer's error is estimated past 10×ERROR, and `--strict` makes that exit 3.

use super::{mbfx, scratch_file, Run};

/// A 1 kg slider on a rail along global x, on a spring (K = 100, free length 1) to the
/// ground origin, released at rest at x = 1.2: x(t) = 1 + 0.2 cos 10t.
const OSCILLATOR: &str = "oscillator\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
    PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0\n\
    MARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
    JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
    SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 0, LENGTH = 1\nEND\n";

/// Runs the oscillator for 10 s (16 periods) with `extra` options; the run and the
/// largest error of its x column against the closed form.
fn oscillate(extra: &[&str]) -> (Run, f64) {
    let model = scratch_file("oscillator.adm", OSCILLATOR.as_bytes());
    let base = ["run", model.to_str().expect("utf-8 path"), "--end", "10"];
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
fn an_accurate_run_is_quiet_and_a_wrong_one_warns_with_the_estimate() {
    // dopri853 at ERROR 1e-3 is far within it: no warning, with or without the estimate.
    for estimate in [&[][..], &["--estimate-error", "--strict"]] {
        let (run, error) =
            oscillate(&[&["--integrator", "dopri853", "--error", "1e-3"], estimate].concat());
        assert!(error < 1e-3, "error {error:e}\n{}", run.describe());
        assert_eq!(run.code, 0, "{}", run.describe());
        assert!(!run.stderr.contains("warning:"), "{}", run.describe());
    }
    // GSTIFF at ERROR 1e-3 drifts in phase over 16 periods: more than 10×ERROR off.
    let gstiff = ["--integrator", "gstiff", "--error", "1e-3"];
    let (quiet, error) = oscillate(&gstiff);
    assert!(error > 1e-2, "error {error:e}\n{}", quiet.describe());
    // By default nothing sums the local errors into a warning any more.
    assert!(!quiet.stderr.contains("warning:"), "{}", quiet.describe());
    let (warned, again) = oscillate(&[&gstiff[..], &["--estimate-error"]].concat());
    assert_eq!(warned.code, 0, "{}", warned.describe());
    assert!(
        warned
            .stderr
            .contains("warning: the answer's error is estimated at"),
        "{}",
        warned.describe()
    );
    assert!(
        warned.stderr.contains("error estimate: "),
        "{}",
        warned.describe()
    );
    // The estimate's second run changes no row.
    assert_eq!(
        (warned.stdout.as_str(), again),
        (quiet.stdout.as_str(), error)
    );
    let (strict, _) = oscillate(&[&gstiff[..], &["--estimate-error", "--strict"]].concat());
    assert_eq!(strict.code, 3, "{}", strict.describe());
    assert_eq!(strict.stdout, quiet.stdout, "the rows are the same");
}
