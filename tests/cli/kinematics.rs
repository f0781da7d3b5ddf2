//! `mbfx run --kinematics` (issue 41 §2): the driven slider-crank reaches its end at an
//! output step that stopped it when the analysis jumped from output to output, and a
//! crank longer than its rod stops at its lock-up with a message that names it.

use super::{mbfx, Run};

/// `mbfx run tests/data/NAME --kinematics --end END --output-step STEP`.
fn kinematic(name: &str, end: &str, step: &str) -> Run {
    let model = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    mbfx(&[
        "run",
        &model,
        "--kinematics",
        "--end",
        end,
        "--output-step",
        step,
    ])
}

#[test]
fn a_quarter_turn_output_step_reaches_the_end() {
    let run = kinematic("kinematics_slider_crank.adm", "1", "0.25");
    assert_eq!(run.code, 0, "{}", run.describe());
    let times: Vec<&str> = run.stdout.lines().skip(1).collect();
    assert_eq!(times.last().copied(), Some("1.0"), "{}", run.describe());
    assert!(!run.stderr.contains("at step 0e0"), "{}", run.describe());
}

#[test]
fn a_lock_up_is_named_with_its_time_and_elements() {
    // Crank 0.2 m, rod 0.1 m, one revolution a second: lock-up at t = asin(1/2)/2π = 1/12.
    let run = kinematic("kinematics_lock_up.adm", "0.5", "0.25");
    assert_ne!(run.code, 0, "{}", run.describe());
    assert!(run.stderr.contains("[E0802]"), "{}", run.describe());
    assert!(run.stderr.contains("at t = 0.0833"), "{}", run.describe());
    assert!(
        run.stderr
            .contains("the constraints lose rank (a lock-up or singular position)"),
        "{}",
        run.describe()
    );
    assert!(
        run.stderr.contains("PART/3 rotation about z"),
        "{}",
        run.describe()
    );
    assert!(
        run.stderr.contains("MOTION/1 cannot drive the mechanism"),
        "{}",
        run.describe()
    );
    assert!(
        !run.stderr.contains("Newton diverges"),
        "{}",
        run.describe()
    );
}
