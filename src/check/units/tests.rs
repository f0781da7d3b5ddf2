//! The rules, one test each, with expected dimensions from physics: what a DX is, what
//! IMPACT returns. Messages are tested in `tests/data/units/` (snapshots).

use super::Dim;
use crate::check::{compile, EveryIdExists, Expect};
use crate::diag::Code;

/// The inferred dimension and the W0312 messages of `src` checked as a model would.
fn infer(src: &str) -> (Option<Dim>, Vec<String>) {
    let c = compile(src, &EveryIdExists, Expect::Any)
        .unwrap_or_else(|e| panic!("{src}: {:?}", e[0].message));
    let msgs = c
        .warnings
        .iter()
        .filter(|d| d.code == Code::UnitMismatch)
        .map(|d| d.message.clone())
        .collect();
    (c.dim, msgs)
}

/// `src` is consistent and has dimension `want` (`None`: free).
#[track_caller]
fn is(src: &str, want: Option<Dim>) {
    let (d, msgs) = infer(src);
    assert!(msgs.is_empty(), "{src}: {msgs:?}");
    assert_eq!(d, want, "{src}");
}

/// `src` gives exactly one unit warning, containing `part`.
#[track_caller]
fn warns(src: &str, part: &str) {
    let (_, msgs) = infer(src);
    assert_eq!(msgs.len(), 1, "{src}: {msgs:?}");
    assert!(
        msgs[0].contains(part),
        "{src}: {:?} lacks {part:?}",
        msgs[0]
    );
}

#[test]
fn measures_have_their_physical_dimensions() {
    is("DX(1,2)", Some(Dim::LENGTH));
    is("DM(1,2)", Some(Dim::LENGTH));
    is("VZ(1,2,3,4)", Some(Dim::VELOCITY));
    is("VR(1,2)", Some(Dim::VELOCITY));
    is("ACCY(1)", Some(Dim::ACCELERATION));
    is("AZ(1,2)", Some(Dim::ANGLE));
    is("YAW(1,2)", Some(Dim::ANGLE));
    is("WX(1,2)", Some(Dim::ANGULAR_VELOCITY));
    is("WDTZ(1,2)", Some(Dim::ANGULAR_ACCELERATION));
    is("FX(1,2)", Some(Dim::FORCE));
    is("TM(1,2)", Some(Dim::TORQUE));
    is("SFORCE(1,0,2,0)", Some(Dim::FORCE));
    is("JOINT(1,0,7,0)", Some(Dim::TORQUE));
    is("TIME", Some(Dim::TIME));
    is("MAG(DXYZ(1,2))", Some(Dim::LENGTH));
    is("UVZ(1)*UVZ(2)", Some(Dim::NONE));
    // A user's number: free.
    is("ARYVAL(1,2)", None);
    is("VARVAL(3)", None);
}

#[test]
fn numbers_are_free_so_coefficients_make_terms_consistent() {
    // Both appear in the corpus (spring-damper forces, a rotating motion).
    is("-1E4*DZ(2,1) - 10*VZ(2,1)", None);
    is("30.0D*TIME", None);
    is("2*PI*TIME", None);
    is("DX(1,2) - 0.5", Some(Dim::LENGTH));
    is("0.5 + DX(1,2)", Some(Dim::LENGTH));
}

#[test]
fn sums_of_fixed_dimensions_must_agree() {
    warns(
        "DZ(2,1) + VZ(2,1)",
        "adds a length (meter) to a velocity (meter/second)",
    );
    // The sum inside is fixed even though its coefficient is free.
    warns("-1E4*(DZ(2,1) + VZ(2,1))", "adds a length");
    warns(
        "DX(1,2) - TIME",
        "subtracts a time (second) from a length (meter)",
    );
    is("DX(1,2) + DY(1,2) - DM(3,4)", Some(Dim::LENGTH));
}

#[test]
fn products_and_quotients_combine() {
    is("DX(1,2)/TIME", Some(Dim::VELOCITY));
    is("FX(1,2)*DY(1,2)", Some(Dim::TORQUE));
    is("WZ(1,2)*TIME", Some(Dim::ANGLE));
    is("AZ(1,2)/TIME", Some(Dim::ANGULAR_VELOCITY));
    // v = ω·r: angle counts as dimensionless where dimensions are compared.
    is("VX(1,2) + WZ(1,2)*DM(1,2)", Some(Dim::VELOCITY));
    is("DXYZ(1,2)%FXYZ(1,2)*UVZ(3)", Some(Dim::TORQUE));
    is(
        "DXYZ(1,2)*DXYZ(1,2) - DM(1,2)**2",
        Some(Dim::of(0, 2, 0, 0)),
    );
}

#[test]
fn constant_powers_scale_including_fractions() {
    is("SQRT(DX(1,2)**2 + DY(1,2)**2)", Some(Dim::LENGTH));
    is("(DM(1,2)**3)**(1/3)", Some(Dim::LENGTH));
    is("(DM(1,2)*DM(1,2))**0.5", Some(Dim::LENGTH));
    is("TIME**-1", Some(Dim::of(0, 0, -1, 0)));
    warns("DM(1,2)**2 + DM(1,2)", "adds");
}

#[test]
fn a_power_that_is_not_constant_needs_numbers() {
    warns(
        "DM(1,2)**VARVAL(1)",
        "a length (meter) raised to a power that is not a constant",
    );
    is("(DX(1,2)/DM(1,2))**VARVAL(1)", Some(Dim::NONE));
    warns("2**TIME", "the exponent of `**` is a time");
}

#[test]
fn transcendentals_need_a_number_or_an_angle() {
    warns("SIN(DX(1,2))", "the argument of SIN is a length");
    is("SIN(AZ(1,2))", Some(Dim::NONE));
    is("SIN(2*PI*TIME)", Some(Dim::NONE));
    is("EXP(-DX(1,2)/DM(1,2))", Some(Dim::NONE));
    warns("COS(TIME)", "a time");
    is("ACOS(DZ(1,2)/DM(1,2))", Some(Dim::ANGLE));
    warns("ACOS(DZ(1,2))", "the argument of ACOS is a length");
    is("ATAN2(DY(1,2), DX(1,2))", Some(Dim::ANGLE));
    warns(
        "ATAN2(DY(1,2), VX(1,2))",
        "ATAN2: y is a length (meter) but x is a velocity",
    );
    is("DM(1,2)*COS(AZ(1,2))", Some(Dim::LENGTH));
}

#[test]
fn if_arms_and_pairs_agree() {
    is("IF(TIME-1: DX(1,2), 0, DY(1,2))", Some(Dim::LENGTH));
    warns(
        "IF(TIME-1: DX(1,2), 0, VX(1,2))",
        "IF: the negative branch is a length",
    );
    warns("MAX(DX(1,2), AZ(1,2))", "MAX: a1 is a length");
    is("MIN(FX(1,2), 100)", Some(Dim::FORCE));
    is("SIGN(FX(1,2), VX(1,2))", Some(Dim::FORCE));
    is("ABS(VX(1,2))", Some(Dim::VELOCITY));
    warns("[DX(1,2), DY(1,2), AZ(1,2)]", "the z component is an angle");
}

#[test]
fn steps_take_x_with_x0_x1_and_h0_with_h1() {
    is("STEP(TIME, 0, 0, 1, 100)", None);
    is("STEP(TIME, 0, 0, 1, DX(1,2))", Some(Dim::LENGTH));
    is("STEP5(DX(1,2), 0, FX(1,2), 0.1, 0)", Some(Dim::FORCE));
    warns(
        "STEP(TIME, DX(1,2), 0, 1, 1)",
        "STEP: x is a time (second) but x0 is a length",
    );
    warns(
        "HAVSIN(TIME, 0, DX(1,2), 1, VX(1,2))",
        "HAVSIN: h0 is a length",
    );
}

#[test]
fn contact_takes_gap_bounds_alike_and_the_gap_rate() {
    is(
        "IMPACT(DZ(2,1), VZ(2,1), 1, 1E5, 1.5, 10, 0.1)",
        Some(Dim::FORCE),
    );
    is(
        "BISTOP(DX(2,1), VX(2,1), -1, 1, 1E5, 2, 10, 0.1)",
        Some(Dim::FORCE),
    );
    // An angular gap gives a torque (a rotational stop).
    is(
        "IMPACT(AZ(2,1), WZ(2,1), 0.5, 1E3, 1.5, 1, 0.01)",
        Some(Dim::TORQUE),
    );
    warns(
        "IMPACT(DZ(2,1), DZ(2,1), 1, 1E5, 1.5, 10, 0.1)",
        "ẋ is a length (meter) where the rate of x, a velocity",
    );
    warns(
        "IMPACT(DZ(2,1), VZ(2,1), AZ(3,1), 1E5, 1.5, 10, 0.1)",
        "x1 is an angle",
    );
    // The contact force is a force: adding a length to it is wrong.
    warns(
        "IMPACT(DZ(2,1), VZ(2,1), 1, 1E5, 1.5, 10, 0.1) + DZ(2,1)",
        "adds a force",
    );
}

#[test]
fn series_follow_their_formulas() {
    is("POLY(DX(1,2), 0, 0, 100)", None);
    is("POLY(DX(1,2), 0, FX(1,2), 100)", Some(Dim::FORCE));
    warns(
        "POLY(TIME, 0, DX(1,2), VX(1,2), DX(1,2))",
        "a2·(x − x0)^2 is a quantity",
    );
    is("POLY(TIME, 0, DX(1,2), VX(1,2))", Some(Dim::LENGTH));
    warns("CHEBY(TIME, 0, 1, 2)", "CHEBY: x − x0 is a time");
    is("FORCOS(TIME, 0, 2*PI, 1, 2)", None);
    warns("FORSIN(DX(1,2), 0, TIME, 1, 2)", "ω·(x − x0)");
    is("SHF(TIME, 0, DX(1,2), 10, 0, 0)", Some(Dim::LENGTH));
    warns(
        "SHF(TIME, 0, DX(1,2), 10, AZ(1,2)*TIME, 0)",
        "the phase ω·(x − x0) − φ is a quantity",
    );
    warns(
        "SHF(TIME, 0, DX(1,2), 10, 0, FX(1,2))",
        "SHF: a is a length",
    );
    is("SWEEP(TIME, DX(1,2), 0, 1, 10, 5, 0.5)", Some(Dim::LENGTH));
    warns(
        "SWEEP(TIME, 1, DX(1,2), 1, 10, 5, 0.5)",
        "SWEEP: x is a time",
    );
}

#[test]
fn splines_and_conversions() {
    is("AKISPL(TIME, 0, 1)", None);
    is("CUBSPL(DX(1,2), 0, 1, 1)", None);
    // DTOR and RTOD convert between units of angle: an angle stays an angle.
    is("RTOD*AZ(1,2)", Some(Dim::ANGLE));
    is("AZ(1,2) - 30*DTOR", Some(Dim::ANGLE));
}

/// The check skips a tree with nothing that fixes a dimension
/// ([`super::fixes_a_dimension`]); on every corpus expression that checks, the skipping
/// check and the full inference (`infer_text`, which never skips) give the same dimension
/// and the same messages.
#[test]
fn skipping_free_trees_changes_no_result_on_the_corpus() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/corpus/expressions.txt"
    );
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let names = crate::check::units::UnitNames::SI;
    let (mut compared, mut free) = (0, 0);
    for src in text
        .lines()
        .filter_map(|l| l.split_once('\t').map(|(_, e)| e))
    {
        let Ok(c) = compile(src, &EveryIdExists, Expect::Any) else {
            continue;
        };
        let Ok((dim, warnings)) = super::infer_text(src, &EveryIdExists, Some(&names)) else {
            panic!("{src}: checks but does not parse");
        };
        let messages = |ds: &[crate::diag::Diagnostic]| -> Vec<String> {
            (ds.iter())
                .filter(|d| d.code == Code::UnitMismatch)
                .map(|d| d.message.clone())
                .collect()
        };
        assert_eq!(
            (c.dim, messages(&c.warnings)),
            (dim, messages(&warnings)),
            "{src}"
        );
        compared += 1;
        free += usize::from(dim.is_none());
    }
    assert!(
        compared > 900 && free > 0,
        "{compared} compared, {free} free"
    );
}
