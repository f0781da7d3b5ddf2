//! `mbfx run --linear` and LINEAR commands (issue 26 §3) as a user meets them: the modes
//! table on stderr, the files FILE names, and a malformed LINEAR command refused at its
//! place. The frequencies themselves are checked against closed forms in
//! `tests/dynamics/linear.rs`.

use super::{mbfx, scratch_dir};

/// A compound pendulum: m = 2, CM 1.5 below the pin, I = 0.5 about the CM, so
/// ω = √(m·g·d/(I + m·d²)) = 2.4261079942986874 rad/s (0.38612707976740 Hz).
const PENDULUM: &str = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
    PART/2, MASS = 2, CM = 20, IP = 0.5, 0.5, 0.5\nMARKER/20, PART = 2, QP = 0, -1.5, 0\n\
    MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -9.81\nEND\n";

#[test]
fn linear_prints_the_modes_and_writes_them() {
    let dir = scratch_dir("linear");
    let model = dir.join("pendulum.adm");
    std::fs::write(&model, PENDULUM).expect("dataset");
    let base = dir.join("modes").join("pendulum");
    let r = mbfx(&[
        "run".as_ref(),
        model.as_os_str(),
        "--statics".as_ref(),
        format!("--linear={}", base.display()).as_ref(),
        "--csv".as_ref(),
        dir.join("out.csv").as_os_str(),
    ]);
    assert_eq!(r.code, 0, "{}", r.describe());
    assert!(
        r.stderr
            .contains("linear analysis at time 0: 1 degree(s) of freedom"),
        "{}",
        r.describe()
    );
    assert!(r.stderr.contains("natural (Hz)"), "{}", r.describe());
    assert!(r.stderr.contains("3.861270798e-1"), "{}", r.describe());
    let modes = std::fs::read_to_string(format!("{}_modes.csv", base.display())).expect("modes");
    let hz: f64 = modes
        .lines()
        .nth(1)
        .expect("a mode")
        .split(',')
        .nth(1)
        .expect("hz")
        .parse()
        .expect("a number");
    let want =
        (2.0 * 9.81 * 1.5 / (0.5 + 2.0 * 1.5 * 1.5f64)).sqrt() / (2.0 * std::f64::consts::PI);
    assert!((hz - want).abs() < 1e-12 * want, "{hz} vs {want}");
    assert!(std::path::Path::new(&format!("{}_shapes.csv", base.display())).is_file());
}

#[test]
fn a_malformed_linear_command_is_refused_at_its_place() {
    let dir = scratch_dir("linear-bad");
    std::fs::write(dir.join("pendulum.adm"), PENDULUM).expect("dataset");
    let acf = dir.join("bad.acf");
    std::fs::write(
        &acf,
        "pendulum\nout\nSIMULATE/STATICS\nLINEAR/EIGENSOL, COORDS = 2, 1\nSTOP\n",
    )
    .expect("command file");
    let r = mbfx(&[
        "run".as_ref(),
        "--color".as_ref(),
        "never".as_ref(),
        acf.as_os_str(),
    ]);
    assert_eq!(r.code, 1, "{}", r.describe());
    assert!(
        r.stderr.contains("COORDS takes one or two mode numbers"),
        "{}",
        r.describe()
    );
    assert!(r.stderr.contains("bad.acf:4:18"), "{}", r.describe());
    assert!(!r.stderr.contains("panicked"));
}
