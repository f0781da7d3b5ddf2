//! The units check of a dataset (issue 24): what each statement expects of its
//! expressions, the dataset's unit names in the messages, VARVAL through its VARIABLE
//! (wherever it stands), and the VARIABLEs a controller sets.

use crate::diag::{Code, Severity};
use crate::model::read_model;

/// Ground, a part with a translational joint along z: markers 11 (ground), 21 and 22.
fn dataset(extra: &str) -> String {
    format!(
        "units\nPART/1, GROUND\nMARKER/11, PART=1\nPART/2, MASS=1, CM=21, IP=1,1,1\n\
         MARKER/21, PART=2\nMARKER/22, PART=2\nJOINT/1, TRANSLATIONAL, I=21, J=11\n{extra}\nEND\n"
    )
}

/// The W0312 warnings of a dataset without errors: (message, help, the text the span
/// covers).
fn unit_warnings(extra: &str) -> Vec<(String, Option<String>, String)> {
    let text = dataset(extra);
    assert!(!read_model(&text).has_errors(), "{extra}");
    unit_warnings_beside_errors(extra)
}

/// The W0312 warnings of a dataset, whatever errors it has beside them.
fn unit_warnings_beside_errors(extra: &str) -> Vec<(String, Option<String>, String)> {
    let text = dataset(extra);
    let read = read_model(&text);
    read.diagnostics
        .iter()
        .filter(|d| d.code == Code::UnitMismatch)
        .inspect(|d| assert_eq!(d.severity, Severity::Warning))
        .map(|d| {
            (
                d.message.clone(),
                d.help.clone(),
                text[d.span.clone()].to_string(),
            )
        })
        .collect()
}

#[test]
fn forces_expect_forces_and_torques() {
    let w = unit_warnings("SFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = AZ(21,11)");
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(
        w[0].0,
        "this SFORCE's FUNCTION is an angle (radian) where a force (newton) is expected"
    );
    assert_eq!(w[0].2, "AZ(21,11)");
    // A torque in a translational SFORCE: the help says how to make it rotational.
    let w = unit_warnings("SFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = FX(21)*DZ(21,11)");
    assert_eq!(
        w[0].1.as_deref(),
        Some("for a torque, make it a ROTATION SFORCE")
    );
    // Consistent ones: a spring-damper law, a rotational spring, free coefficients.
    for ok in [
        "SFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = -1E4*DZ(21,11) - 10*VZ(21,11)",
        "SFORCE/1, ROTATION, I=21, J=11, FUNCTION = -100*AZ(21,11) - WZ(21,11)*2",
        "SFORCE/1, ROTATION, I=21, J=11, FUNCTION = FX(21)*DY(21,11)",
        "SFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = IMPACT(DZ(21,11), VZ(21,11), 1, 1E5, 1.5, 10, 0.1)",
    ] {
        assert_eq!(unit_warnings(ok), [], "{ok}");
    }
}

#[test]
fn vector_force_components_expect_forces_then_torques() {
    let w = unit_warnings(
        "MARKER/23, PART=1, FLOATING\n\
         GFORCE/1, I=21, JFLOAT=23, RM=11, FX=0, FY=FZ(21), FZ=0, TX=0, TY=0, TZ=FZ(21)",
    );
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(
        w[0].0,
        "this GFORCE's TZ is a force (newton) where a torque (newton-meter) is expected"
    );
    assert_eq!(w[0].1.as_deref(), Some("a force belongs in FX, FY or FZ"));
}

#[test]
fn motions_expect_their_coordinate_or_its_rates() {
    let w = unit_warnings("MOTION/1, JOINT=1, TRANSLATION, FUNCTION = 0.1*SIN(2*PI*TIME)");
    assert_eq!(w, []);
    let w = unit_warnings("MOTION/1, JOINT=1, VELOCITY, FUNCTION = TIME");
    assert_eq!(
        w[0].0,
        "this MOTION's FUNCTION is a time (second) where a velocity (meter/second) is expected"
    );
    // A MOTION that reads the model's state is an error (E0605); its units are still
    // checked, and the help names the form a length would fit.
    let w = unit_warnings_beside_errors("MOTION/1, JOINT=1, VELOCITY, FUNCTION = DZ(22,11)");
    assert_eq!(
        w[0].0,
        "this MOTION's FUNCTION is a length (meter) where a velocity (meter/second) is expected"
    );
    assert_eq!(
        w[0].1.as_deref(),
        Some("for a displacement, write DISPLACEMENT (the default)")
    );
    // `30.0D*TIME` drives a rotation: free, so it fits.
    let w = unit_warnings("MOTION/1, I=21, J=11, B3, FUNCTION = 30.0D*TIME");
    assert_eq!(w, []);
    let w = unit_warnings_beside_errors("MOTION/1, I=21, J=11, B3, FUNCTION = DX(22,11)");
    assert_eq!(
        w[0].1.as_deref(),
        Some("a length drives a translation: write TRANSLATION")
    );
}

#[test]
fn messages_use_the_dataset_units_wherever_units_stands() {
    let w = unit_warnings(
        "GCON/1, I=21, FUNCTION = DZ(21,11) + VZ(21,11)\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = MILLIMETER, TIME = SECOND",
    );
    assert_eq!(
        w[0].0,
        "`DZ(21,11) + VZ(21,11)` adds a length (millimeter) to a velocity (millimeter/second)"
    );
    let w = unit_warnings(
        "UNITS/SYSTEM = IPS\nSFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = DZ(21,11)",
    );
    assert!(
        w[0].0
            .ends_with("a length (inch) where a force (pound_force) is expected"),
        "{w:?}"
    );
}

#[test]
fn varval_takes_its_variables_dimension_before_or_after_it() {
    // VARIABLE/2 stands after its use, VARIABLE/3 before; VARIABLE/2 reads VARIABLE/3.
    let w = unit_warnings(
        "VARIABLE/3, FUNCTION = AZ(21,11)\n\
         SFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = VARVAL(2)\n\
         VARIABLE/2, FUNCTION = 2*VARVAL(3) + AZ(22,11)",
    );
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].0.starts_with("this SFORCE's FUNCTION is an angle"),
        "{w:?}"
    );
    // A VARIABLE that reads itself is free where the loop closes: 0.5·v + t is a time.
    let w = unit_warnings(
        "VARIABLE/1, FUNCTION = 0.5*VARVAL(1) + TIME\n\
         MOTION/1, JOINT=1, FUNCTION = VARVAL(1)",
    );
    assert!(
        w[0].0.contains("is a time (second) where a length"),
        "{w:?}"
    );
}

#[test]
fn variables_a_controller_sets_are_free() {
    // Adams Controls: PINPUT lists the plant inputs; their FUNCTION only stands in.
    let w = unit_warnings(
        "VARIABLE/1, FUNCTION = AZ(21,11)\n\
         PINPUT/1, VARIABLES = 1\n\
         SFORCE/1, TRANSLATION, I=21, J=11, FUNCTION = VARVAL(1)",
    );
    assert_eq!(w, []);
}

#[test]
fn state_element_expressions_are_checked_like_the_others() {
    // A DIFF's FUNCTION adding a length to a velocity is flagged where it stands.
    let w = unit_warnings("DIFF/1, IC = 0, FUNCTION = DZ(21,11) + VZ(21,11)");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].0.contains("adds a length"), "{w:?}");
    assert_eq!(w[0].2, "DZ(21,11) + VZ(21,11)");
    // And an IMPLICIT one's residual; a consistent law stays quiet.
    let w = unit_warnings("DIFF/1, IMPLICIT, IC = 0, FUNCTION = DIF1(1) - AZ(21,11) - VZ(21,11)");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(unit_warnings("DIFF/1, IC = 0, FUNCTION = -2*DIF(1) + DZ(21,11)").is_empty());
}
