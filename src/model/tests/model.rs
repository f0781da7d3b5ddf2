//! Tests of the model reader on small inline datasets: REULER and ZP/XP orientations
//! against the spec's test vectors (§2.3, §2.4), the UCF table (§2.1), measure slots, and
//! a catalogue of bad datasets, each pinned to its diagnostic code and the text its span
//! covers.

use crate::diag::{Code, Severity};
use crate::model::elements::{MeasureSlot, Model, MotionLevel, MotionTarget, RequestKind};
use crate::model::{read_model, ModelRead};
use crate::vocab::elements::{ElementKind, ForceKind, JointType, ELEMENT_NAMES};
use crate::vocab::math::{Mat3, Vec3};
use nalgebra::{Rotation3, Unit};

/// Ground with a plain and a floating marker, and part 2 (`arm`) with two fixed markers
/// and a floating one. Cases append their statements.
const BASE: &str = "title\n\
PART/1, GROUND\n\
MARKER/11, PART=1\n\
MARKER/12, PART=1, FLOATING\n\
! adams_view_name='arm'\n\
PART/2, MASS=1, CM=21, IP=1,1,1\n\
MARKER/21, PART=2\n\
MARKER/22, PART=2, QP=1,0,0\n\
MARKER/23, PART=2, FLOATING\n";

fn with(extra: &str) -> String {
    format!("{BASE}{extra}\nEND\n")
}

fn read(text: &str) -> ModelRead {
    let r = read_model(text);
    for d in &r.diagnostics {
        assert!(
            d.span.end <= text.len() && text.is_char_boundary(d.span.start),
            "span {:?} outside the text: {d:?}",
            d.span
        );
    }
    r
}

fn clean(text: &str) -> Model {
    let r = read(text);
    let errors: Vec<_> = r.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    r.model
}

fn close(a: &Mat3, b: &Mat3, tol: f64) -> bool {
    (a - b).abs().max() <= tol
}

fn axis_angle(axis: Vec3, degrees: f64) -> Mat3 {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), degrees.to_radians()).into_inner()
}

#[test]
fn reuler_test_vectors_of_spec_2_4() {
    let rows: [(&str, Mat3); 6] = [
        ("180D, 90D, 180D", axis_angle(Vec3::x(), -90.0)),
        ("180D, 45D, 180D", axis_angle(Vec3::x(), -45.0)),
        ("0D, 90D, 0D", axis_angle(Vec3::x(), 90.0)),
        ("90D, 90D, -90D", axis_angle(Vec3::y(), 90.0)),
        (
            "-45D, 90D, 45D",
            axis_angle(Vec3::new(1.0, -1.0, 0.0), 90.0),
        ),
        (
            "30D, 40D, 50D",
            Mat3::new(
                0.263258, -0.909616, 0.321394, 0.829598, 0.043412, -0.556670, 0.492404, 0.413176,
                0.766044,
            ),
        ),
    ];
    for (angles, want) in rows {
        let m = clean(&with(&format!("MARKER/30, PART=2, REULER = {angles}")));
        let got = m.marker(30).expect("marker 30").orientation;
        assert!(close(&got, &want, 1e-6), "REULER {angles}: {got} != {want}");
    }
}

#[test]
fn reuler_in_radians_and_on_parts() {
    let m = clean(&with(
        "PART/3, MASS=1, CM=31, IP=1,1,1, QG=1,2,3, REULER=1.5707963267948966, 0, 0\n\
         MARKER/31, PART=3, QP=1,0,0",
    ));
    let (origin, axes) = m.marker_pose(31).expect("pose");
    // The part turns +90° about z: its x axis is global y.
    assert!(
        (origin - Vec3::new(1.0, 3.0, 3.0)).norm() < 1e-12,
        "{origin}"
    );
    assert!(close(&axes, &axis_angle(Vec3::z(), 90.0), 1e-12));
}

#[test]
fn zp_xp_and_usexp_follow_spec_2_3() {
    // From QP (1,1,1): ZP − QP = (1,1,1), XP − QP = (2,0,0).
    let pts = "QP = 1,1,1, ZP = 2,2,2, XP = 3,1,1";
    let m = clean(&with(&format!(
        "MARKER/30, PART=2, {pts}\nMARKER/31, PART=2, {pts}, USEXP"
    )));
    let s2 = 2f64.sqrt();
    let s3 = 3f64.sqrt();
    let s6 = 6f64.sqrt();
    // z exact, x the part of XP − QP orthogonal to z, y = z × x (worked by hand).
    let z_first = Mat3::from_columns(&[
        Vec3::new(2.0, -1.0, -1.0) / s6,
        Vec3::new(0.0, 1.0, -1.0) / s2,
        Vec3::new(1.0, 1.0, 1.0) / s3,
    ]);
    // USEXP: x exact, z the part of ZP − QP orthogonal to x.
    let x_first = Mat3::from_columns(&[
        Vec3::x(),
        Vec3::new(0.0, 1.0, -1.0) / s2,
        Vec3::new(0.0, 1.0, 1.0) / s2,
    ]);
    let got = |id| m.marker(id).expect("marker").orientation;
    assert!(close(&got(30), &z_first, 1e-12), "{}", got(30));
    assert!(close(&got(31), &x_first, 1e-12), "{}", got(31));
}

#[test]
fn zg_xg_place_a_part_like_zp_xp_a_marker() {
    // FAST style: z towards ZG = QG + (0,1,0), x towards XG = QG + (1,0,0): Rx(−90°).
    let m = clean(&with(
        "PART/3, MASS = 1, CM = 31, IP = 1,1,1, QG = 1,0,0, ZG = 1,1,0, XG = 2,0,0\n\
         MARKER/31, PART = 3",
    ));
    let p = m.part(3).expect("part 3");
    assert!(close(&p.orientation, &axis_angle(Vec3::x(), -90.0), 1e-12));
    assert_eq!(p.position, Vec3::new(1.0, 0.0, 0.0));
}

#[test]
fn products_of_inertia_enter_the_tensor_negated() {
    let m = clean(&with(
        "PART/3, MASS = 1, CM = 31, IP = 10, 20, 30, 1, 2, 3\nMARKER/31, PART = 3",
    ));
    let want = Mat3::new(10.0, -1.0, -2.0, -1.0, 20.0, -3.0, -2.0, -3.0, 30.0);
    assert_eq!(m.part(3).expect("part 3").inertia(), want);
}

#[test]
fn ucf_table_of_spec_2_1() {
    let rows = [
        (
            "FORCE=NEWTON, MASS=KILOGRAM, LENGTH=METER, TIME=SECOND",
            1.0,
        ),
        (
            "FORCE=NEWTON, MASS=KILOGRAM, LENGTH=MILLIMETER, TIME=SECOND",
            1000.0,
        ),
        (
            "FORCE=POUND_FORCE, MASS=POUND_MASS, LENGTH=INCH, TIME=SECOND",
            386.0886,
        ),
        (
            "FORCE=POUND_FORCE, MASS=POUND_MASS, LENGTH=FOOT, TIME=SECOND",
            32.174,
        ),
        (
            "FORCE=POUND_FORCE, MASS=SLUG, LENGTH=FOOT, TIME=SECOND",
            1.0,
        ),
        ("FORCE=DYNE, MASS=GRAM, LENGTH=CENTIMETER, TIME=SECOND", 1.0),
        ("SYSTEM=IPS", 386.0886),
        ("SYSTEM=MKS", 1.0),
        ("SYSTEM=NONE, UCF=2.5", 2.5),
        ("length = millimeter", 1000.0),
    ];
    for (units, want) in rows {
        let m = clean(&with(&format!("UNITS/{units}")));
        let rel = (m.units.ucf - want).abs() / want;
        // The spec rounds its figures to 5–7 significant digits.
        assert!(rel < 2e-6, "UNITS/{units}: UCF {} != {want}", m.units.ucf);
    }
    assert_eq!(clean(&with("")).units.ucf, 1.0);
    let twice = read(&with("UNITS/LENGTH = MILLIMETER\nUNITS/LENGTH = INCH"));
    assert_eq!(twice.model.units.length.as_deref(), Some("INCH"));
    assert!(twice.diagnostics[0]
        .message
        .contains("UNITS is given again"));
}

#[test]
fn gravity_joints_and_forces_are_read() {
    let m = clean(&with(
        "ACCGRAV/JGRAV = -9806.65\n\
         ! adams_view_name='pin'\n\
         JOINT/4, REVOLUTE, I = 21, J = 11, IC = 0.1, 0.2\n\
         MOTION/1, JOINT = 4, VELOCITY, FUNCTION = 30.0d * time\n\
         JPRIM/4, INPLANE, I = 22, J = 11\n\
         SPRINGDAMPER/1, ROTATIONAL, I = 21, J = 11, KT = 5, CT = 0.5, ANGLE = 10D\n\
         VFORCE/1, I = 22, JFLOAT = 12, RM = 11, FX = 0\\ FY = 1\\ FZ = DX(22)\n\
         BUSHING/1, I = 22, J = 11, K = 1,2,3, C = 4,5,6",
    ));
    assert_eq!(m.gravity, Vec3::new(0.0, -9806.65, 0.0));
    let j = m.joint(4).expect("joint 4");
    assert_eq!(j.el.display("JOINT"), "JOINT/4 (pin)");
    assert_eq!(j.ic, Some([0.1, 0.2]));
    assert_eq!(m.motions.len(), 1);
    assert_eq!(m.jprims.len(), 1);
    let sd = &m.spring_dampers[0];
    assert!(sd.rotation && (sd.free_length - 10f64.to_radians()).abs() < 1e-15);
    assert_eq!(m.vector_forces[0].force.as_ref().map(|f| f.len()), Some(3));
    assert_eq!(m.bushings[0].c, Vec3::new(4.0, 5.0, 6.0));
}

#[test]
fn equal_measure_calls_share_a_slot_and_vectors_take_three() {
    let m = clean(&with(
        "VARIABLE/1, FUNCTION = DX(21,11) + DX(21,11)*DM(21,11)\n\
         VARIABLE/2, FUNCTION = DX(21, 11) + VARVAL(1)\n\
         GCON/1, I = 21, FUNCTION = UVZ(21)*UVZ(11) - 1\n\
         DIFF/9, FUNCTION = DM(22, 11)",
    ));
    // A DIFF's expression asks for its slots like the others (issue 40 §3).
    let slot = |name: &str, ids: &[i64], component: u8| MeasureSlot {
        name: name.into(),
        ids: ids.to_vec(),
        component,
    };
    let want = vec![
        slot("DX", &[21, 11], 0),
        slot("DM", &[21, 11], 0),
        slot("VARVAL", &[1], 0),
        slot("UVZ", &[21], 0),
        slot("UVZ", &[21], 1),
        slot("UVZ", &[21], 2),
        slot("UVZ", &[11], 0),
        slot("UVZ", &[11], 1),
        slot("UVZ", &[11], 2),
        slot("DM", &[22, 11], 0),
    ];
    assert_eq!(m.measures, want);
    assert_eq!(m.variables[1].function.function.uses.measures, vec![0, 2]);
    assert_eq!(
        m.gcons[0].function.function.uses.measures,
        vec![3, 4, 5, 6, 7, 8]
    );
}

/// One bad dataset: what to append to [`BASE`], the code, and the text the span covers.
struct Bad {
    extra: &'static str,
    code: Code,
    at: &'static str,
}

const BAD: &[Bad] = &[
    Bad {
        extra: "JOINT/1, REVOLUTE, I = 99, J = 11",
        code: Code::UndefinedElement,
        at: "99",
    },
    Bad {
        extra: "JOINT/1, REVOLUTE, I = 21, J = 22",
        code: Code::Topology,
        at: "22",
    },
    Bad {
        extra: "JPRIM/1, INLINE, I = 22, J = 21",
        code: Code::Topology,
        at: "21",
    },
    Bad {
        extra: "MARKER/21, PART=1",
        code: Code::DuplicateId,
        at: "21",
    },
    Bad {
        extra: "JOINT/1, HINGE, I = 21, J = 11",
        code: Code::MissingArgument,
        at: "JOINT",
    },
    Bad {
        extra: "GCON/1, FUNCTION = DM(21, 98) - 1",
        code: Code::UndefinedElement,
        at: "98",
    },
    Bad {
        extra: "PART/3, GROUND",
        code: Code::Topology,
        at: "PART/3, GROUND",
    },
    Bad {
        extra: "MARKER/5, QP = 0, 0, 0",
        code: Code::MissingArgument,
        at: "MARKER",
    },
    Bad {
        extra: "MARKER/5, PART = 7",
        code: Code::UndefinedElement,
        at: "7",
    },
    Bad {
        extra: "PART/3, MASS = heavy",
        code: Code::BadArgument,
        at: "heavy",
    },
    Bad {
        extra: "JOINT/1, SPHERICAL, I = 23, J = 11",
        code: Code::Topology,
        at: "23",
    },
    Bad {
        extra: "VTORQUE/1, I = 21, JFLOAT = 11, RM = 11, TX = 0\\TY = 0\\TZ = 1",
        code: Code::Topology,
        at: "11",
    },
    Bad {
        extra: "JOINT/1, SPHERICAL, I = 21, J = 11\nMOTION/1, JOINT = 1, FUNCTION = TIME",
        code: Code::Topology,
        at: "1",
    },
    Bad {
        extra: "SFORCE/1, I = 21, J = 11, FUNCTION = VARVAL(7)",
        code: Code::UndefinedElement,
        at: "7",
    },
    Bad {
        extra: "MOTION/1, I = 21, J = 11, X",
        code: Code::MissingArgument,
        at: "MOTION",
    },
    Bad {
        extra: "MARKER/5, PART = 2, REULER = 1, 2",
        code: Code::BadArgument,
        at: "REULER = 1, 2",
    },
    Bad {
        extra: "PART/3, MASS = 1, CM = 22, IP = 1, 1, 1",
        code: Code::Topology,
        at: "22",
    },
    Bad {
        extra: "SPLINE/1, X = 0, 1, 2, 3, Y = 0, 1",
        code: Code::BadArgument,
        at: "SPLINE",
    },
    Bad {
        extra: "SPLINE/1, X = 0, 2, 1, 3, Y = 0, 1, 2, 3",
        code: Code::BadArgument,
        at: "SPLINE",
    },
    Bad {
        extra: "UNITS/LENGTH = FURLONG",
        code: Code::BadArgument,
        at: "FURLONG",
    },
    Bad {
        extra: "MARKER/5, PART = 2, QP = 1,1,1, ZP = 1,1,1",
        code: Code::BadArgument,
        at: "MARKER",
    },
    Bad {
        extra: "JOINT/1, RACKPIN, I = 21, J = 11",
        code: Code::MissingArgument,
        at: "JOINT",
    },
    Bad {
        extra: "SFORCE/1, I = 21, J = 11, FUNCTION = 1 +* 2",
        code: Code::UnexpectedToken,
        at: "*",
    },
    Bad {
        extra: "REQUEST/1, F2 = DX(21, 77)",
        code: Code::UndefinedElement,
        at: "77",
    },
    Bad {
        extra: "REQUEST/1, DISPLACEMENT, J = 11",
        code: Code::MissingArgument,
        at: "REQUEST",
    },
    Bad {
        extra: "JOINT/1, REVOLUTE, SPHERICAL, I = 21, J = 11",
        code: Code::BadArgument,
        at: "SPHERICAL",
    },
    Bad {
        extra: "JOINT/1, CYLINDRICAL, I = 21, J = 11\nMOTION/2, JOINT = 1, FUNCTION = TIME",
        code: Code::MissingArgument,
        at: "MOTION",
    },
    Bad {
        extra: "VARIABLE/1, FUNCTION = AKISPL(TIME, 0, 5)",
        code: Code::UndefinedElement,
        at: "5",
    },
    Bad {
        extra: "PART/3, IP = 1, 2, 3, 4",
        code: Code::BadArgument,
        at: "IP = 1, 2, 3, 4",
    },
    Bad {
        extra: "PART/3, MASS = 1.0D+00",
        code: Code::BadArgument,
        at: "1.0D+00",
    },
    Bad {
        extra: "DIFF/3, FUNCTION = DX(21, 55)",
        code: Code::UndefinedElement,
        at: "55",
    },
    // Issue 11 §3: numbers past f64's range, anywhere (used or not), and mass properties
    // no body has.
    Bad {
        extra: "PART/3, MASS = 1E400, CM = 31, IP = 1, 1, 1\nMARKER/31, PART = 3",
        code: Code::NonFiniteNumber,
        at: "1E400",
    },
    Bad {
        extra: "ACCGRAV/ IGRAV = 1E400",
        code: Code::NonFiniteNumber,
        at: "1E400",
    },
    Bad {
        extra: "MARKER/30, PART = 2, QP = -1.0E+999, 0, 0",
        code: Code::NonFiniteNumber,
        at: "-1.0E+999",
    },
    Bad {
        extra: "MARKER/30, PART = 2, ZP = 0, 0, 1E400",
        code: Code::NonFiniteNumber,
        at: "1E400",
    },
    Bad {
        extra: "GRAPHICS/1, CYLINDER, CM = 21, LENGTH = 1, RADIUS = 2E308",
        code: Code::NonFiniteNumber,
        at: "2E308",
    },
    Bad {
        extra: "PART/3, MASS = -5, CM = 31, IP = 1, 1, 1\nMARKER/31, PART = 3",
        code: Code::MassProperties,
        at: "MASS = -5",
    },
    Bad {
        extra: "PART/3, MASS = 2, CM = 31, IP = -1, -1, -1\nMARKER/31, PART = 3",
        code: Code::MassProperties,
        at: "IP = -1, -1, -1",
    },
    // Products of 3 in a tensor of moments 2, 2, 3: principal moments -1, 5, 3.
    Bad {
        extra: "PART/3, MASS = 2, CM = 31, IP = 2, 2, 3, 3, 0, 0\nMARKER/31, PART = 3",
        code: Code::MassProperties,
        at: "IP = 2, 2, 3, 3, 0, 0",
    },
];

/// Mass properties bodies have pass (issue 11 §3): `MASS = 0` makes a massless part
/// (needing no CM), a thin plate meets the triangle inequality with equality, products
/// of inertia that keep the principal moments of a box (1.5, 2.5, 3) are fine, and a
/// massless part may have zero inertia.
#[test]
fn possible_mass_properties_read_clean() {
    let m = clean(&with(
        "PART/3, MASS = 0\n\
         PART/4, MASS = 1, CM = 41, IP = 1, 2, 3\nMARKER/41, PART = 4\n\
         PART/5, MASS = 1, CM = 51, IP = 2, 2, 3, 0.5, 0, 0\nMARKER/51, PART = 5\n\
         PART/6, IP = 0, 0, 0",
    ));
    assert_eq!(m.part(3).expect("part 3").mass, None);
    assert_eq!(m.part(4).expect("part 4").mass, Some(1.0));
}

/// The one W0609 warning a part `PART/3, MASS = 2, CM = 31, IP = <ip>` gives, at its IP.
fn assert_inertia_warning(ip: &str) {
    let text = with(&format!(
        "PART/3, MASS = 2, CM = 31, IP = {ip}\nMARKER/31, PART = 3"
    ));
    let r = read(&text);
    let found: Vec<_> = r
        .diagnostics
        .iter()
        .map(|d| (d.code, d.severity, &text[d.span.clone()]))
        .collect();
    let at = format!("IP = {ip}");
    assert_eq!(
        found,
        [(Code::ImplausibleInertia, Severity::Warning, at.as_str())]
    );
}

/// A mass with zero inertia is a point mass (IFToMM A01's bob): a warning (W0609) at the
/// IP, since only constraints can hold its rotations; `mbfx run` checks they do.
#[test]
fn a_point_mass_is_a_warning() {
    assert_inertia_warning("0, 0, 0");
}

/// Principal moments 1, 1, 5 break the triangle inequality (5 > 1 + 1): no real body has
/// them, but the tensor is positive definite, so it is a warning (W0609) at the IP.
#[test]
fn an_inertia_breaking_the_triangle_inequality_is_a_warning() {
    assert_inertia_warning("1, 1, 5");
}

#[test]
fn bad_datasets_give_their_code_at_their_place() {
    let mut problems = Vec::new();
    for bad in BAD {
        let text = with(bad.extra);
        let r = read(&text);
        let errors: Vec<_> = r
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .collect();
        let hit = errors.iter().any(|d| {
            d.code == bad.code && text[d.span.clone()] == *bad.at && d.span.start >= BASE.len()
        });
        if !hit || errors.len() != 1 {
            let got: Vec<_> = errors
                .iter()
                .map(|d| {
                    format!(
                        "{} {:?} `{}`",
                        d.code.as_str(),
                        d.message,
                        &text[d.span.clone()]
                    )
                })
                .collect();
            problems.push(format!(
                "{:?}: want one {} at `{}`, got {got:#?}",
                bad.extra,
                bad.code.as_str(),
                bad.at
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(BAD.len() >= 15);
}

#[test]
fn no_ground_is_an_error() {
    let r = read("title\nPART/2, MASS = 1, CM = 21\nMARKER/21, PART = 2\nEND\n");
    let codes: Vec<Code> = r.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, vec![Code::Topology]);
}

#[test]
fn messages_name_elements_by_view_name() {
    let text = with("! adams_view_name='Joint_4'\nJOINT/4, REVOLUTE, I = 21, J = 99");
    let r = read(&text);
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("an error");
    assert!(
        d.notes.iter().any(|n| n.contains("JOINT/4 (Joint_4)")),
        "{d:?}"
    );
}

#[test]
fn unsupported_things_are_warnings_that_name_statement_id_and_line() {
    let text = with(
        "JOINT/1, REVOLUTE, I = 21, J = 11, MU_DYN_ROT = 0.1\n\
         GRAPHICS/5, POINT, RM = 21\n\
         SFORCE/2, I = 21, J = 11, FUNCTION = USER(1, 2)\n\
         DIFF/3, FUNCTION = TIME\n\
         GSE/8, NS = 1\n\
         VARIABLE/4, FUNCTION = DIF(3)\n\
         VARIABLE/5, FUNCTION = USER(1)\n\
         VARIABLE/6, FUNCTION = VARVAL(5) + SFORCE(2, 0, 2, 0)",
    );
    let r = read(&text);
    assert!(!r.has_errors(), "{:#?}", r.diagnostics);
    let warnings: Vec<&str> = r.diagnostics.iter().map(|d| d.message.as_str()).collect();
    let expect = [
        "MU_DYN_ROT of JOINT/1 (line 10)",
        "GRAPHICS is outside the mbfx subset: 1 statement ignored",
        "USER(...)",
        "GSE is outside the mbfx subset",
        "GSE/8: a GSE's equations come from compiled user subroutines",
        "VARVAL reads VARIABLE/5, which calls a USER subroutine",
        "SFORCE reads SFORCE/2, which calls a USER subroutine",
    ];
    for e in expect {
        assert!(warnings.iter().any(|w| w.contains(e)), "{e}: {warnings:#?}");
    }
    let graphics = r
        .diagnostics
        .iter()
        .find(|d| d.message.starts_with("GRAPHICS"))
        .expect("GRAPHICS warning");
    assert!(graphics
        .notes
        .iter()
        .any(|n| n.contains("GRAPHICS/5 (line 11)")));
    assert_eq!(r.model.sforces.len(), 0);
    assert_eq!(r.model.joints.len(), 1);
}

#[test]
fn settings_are_kept_as_written() {
    let m = clean(&with(
        "INTEGRATOR/GSTIFF, ERROR = 1.0E-04, HMAX = 0.01\nOUTPUT/REQSAVE",
    ));
    let s = &m.settings[0];
    assert_eq!(s.statement, "INTEGRATOR");
    assert_eq!(
        s.args,
        vec![
            ("GSTIFF".to_string(), String::new()),
            ("ERROR".to_string(), "1.0E-04".to_string()),
            ("HMAX".to_string(), "0.01".to_string()),
        ]
    );
    assert_eq!(m.settings[1].statement, "OUTPUT");
}

/// One statement of every element kind a dataset can hold, written with the spellings of
/// the one table of element names: the reader reads each as that kind and counts it under
/// that keyword, so what the core prints is what the reader accepts.
#[test]
fn every_element_kind_reads_back_under_its_table_name() {
    use ElementKind::*;
    for n in ELEMENT_NAMES.iter().filter(|n| n.kind.in_dataset()) {
        let (keyword, flag) = (n.keyword, n.flag.unwrap_or_default());
        let statement = match n.kind {
            Joint(JointType::Rackpin) => format!("{keyword}/1, {flag}, I = 21, J = 11, PD = 2"),
            Joint(JointType::Screw) => format!("{keyword}/1, {flag}, I = 21, J = 11, PITCH = 2"),
            Joint(_) | Jprim(_) => format!("{keyword}/1, {flag}, I = 21, J = 11"),
            Gcon => format!("{keyword}/1, I = 21, FUNCTION = DX(21)"),
            Motion => format!("JOINT/1, REVOLUTE, I = 21, J = 11\n{keyword}/1, JOINT = 1, FUNCTION = TIME"),
            Force(ForceKind::Sforce) => format!("{keyword}/1, I = 21, J = 11, FUNCTION = 1"),
            Force(ForceKind::Vforce) => {
                format!("{keyword}/1, I = 22, JFLOAT = 12, RM = 11, FX = 0\\ FY = 0\\ FZ = 1")
            }
            Force(ForceKind::Vtorque) => {
                format!("{keyword}/1, I = 22, JFLOAT = 12, RM = 11, TX = 0\\ TY = 0\\ TZ = 1")
            }
            Force(ForceKind::Gforce) => format!(
                "{keyword}/1, I = 22, JFLOAT = 12, RM = 11, FX = 0\\ FY = 0\\ FZ = 1\\ TX = 0\\ TY = 0\\ TZ = 1"
            ),
            Force(ForceKind::Springdamper) => {
                format!("{keyword}/1, TRANSLATIONAL, I = 21, J = 11, K = 1, C = 0")
            }
            Force(ForceKind::Bushing) => {
                format!("{keyword}/1, I = 22, J = 11, K = 1, 2, 3, C = 4, 5, 6")
            }
            Force(ForceKind::Beam) => format!(
                "{keyword}/1, I = 22, J = 11, LENGTH = 1, AREA = 1, IXX = 1, IYY = 1, IZZ = 1, EMODULUS = 1, GMODULUS = 1"
            ),
            Force(ForceKind::Field) => format!(
                "{keyword}/1, I = 22, J = 11, KMATRIX = {}",
                ["1"; 36].join(", ")
            ),
            Force(ForceKind::Friction) => format!(
                "JOINT/1, REVOLUTE, I = 21, J = 11\n{keyword}/1, JOINT = 1, MU_STATIC = 0.2, MU_DYNAMIC = 0.1"
            ),
            Prismatic2d => unreachable!("no dataset statement makes a 2D prismatic joint"),
        };
        let m = clean(&with(&statement));
        let counts = m.element_counts();
        let count = counts.iter().find(|(k, _)| *k == keyword);
        assert_eq!(count, Some(&(keyword, 1)), "{statement}");
        match n.kind {
            Joint(t) => assert_eq!(m.joints[0].kind, t, "{statement}"),
            Jprim(t) => assert_eq!(m.jprims[0].kind, t, "{statement}"),
            _ => {}
        }
    }
}

#[test]
fn abbreviated_and_lower_case_keywords_read_the_same() {
    let full = clean(&with(
        "JOINT/1, CYLINDRICAL, I = 21, J = 11, ICTRAN = 0.5, 1\n\
         MOTION/1, JOINT = 1, ROTATIONAL, VELOCITY, FUNCTION = 30D*TIME\n\
         REQUEST/1, DISPLACEMENT, I = 21, J = 11, RM = 11, COMMENT = a note",
    ));
    let short = clean(&with(
        "joi/1, cyl, i = 21, j = 11, ictran = 0.5, 1\n\
         mot/1, joint = 1, rot, v, fun = 30d*time\n\
         req/1, d, i = 21, j = 11, rm = 11, c = a note",
    ));
    for m in [&full, &short] {
        let j = m.joint(1).expect("joint 1");
        assert_eq!((j.kind, j.i, j.j), (JointType::Cylindrical, 21, 11));
        assert_eq!(j.ic_tran, Some([0.5, 1.0]));
        let mo = &m.motions[0];
        assert_eq!(
            mo.target,
            MotionTarget::Joint {
                joint: 1,
                rotation: true
            }
        );
        assert_eq!(mo.level, MotionLevel::Velocity);
        let r = &m.requests[0];
        assert_eq!(
            r.standard,
            Some((RequestKind::Displacement, 21, Some(11), Some(11)))
        );
        assert_eq!(r.comment.as_deref(), Some("a note"));
    }
}

#[test]
fn the_report_lists_counts_units_and_gravity_in_sections() {
    let m = clean(&with("ACCGRAV/KGRAV = -9.80665\nUNITS/LENGTH = MILLIMETER"));
    let summary = crate::model::report::summary(&m);
    let extra = crate::model::report::ReportSection {
        title: "degrees of freedom".into(),
        lines: vec!["6".into()],
    };
    let text = crate::model::report::format_report("m.adm", &[summary, extra]);
    let want = "m.adm\n  model:\n    title: title\n    elements: PART 2, MARKER 5\n    \
                units: force (SI), mass (SI), length MILLIMETER, time (SI); UCF = 1000\n    \
                gravity: (0, 0, -9.80665)\n    measures read by expressions: 0\n  \
                degrees of freedom:\n    6\n";
    assert_eq!(text, want);
}

/// The errors of `text`, as (code, the text they point at, message).
fn errors_of(text: &str) -> Vec<(Code, String, String)> {
    read(text)
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| (d.code, text[d.span.clone()].to_string(), d.message.clone()))
        .collect()
}

/// A MOTION's FUNCTION may depend on time only: one that reads a measure, directly or
/// through a VARIABLE, is refused at the FUNCTION naming the measure; a VARIABLE of time
/// alone is fine.
#[test]
fn a_motion_of_the_state_is_refused_at_its_function() {
    let joint = "JOINT/1, TRANSLATIONAL, I = 21, J = 11\n";
    let direct = with(&format!(
        "{joint}MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = 0.1*AZ(21, 11)"
    ));
    assert_eq!(
        errors_of(&direct),
        [(
            Code::BadArgument,
            "0.1*AZ(21, 11)".to_string(),
            "MOTION/1: its FUNCTION reads AZ(21, 11); a MOTION's FUNCTION may depend on time only"
                .to_string()
        )]
    );
    let through = with(&format!(
        "{joint}VARIABLE/3, FUNCTION = DX(21, 11)\nVARIABLE/4, FUNCTION = 2*VARVAL(3)\n\
         MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = VARVAL(4)*TIME"
    ));
    let found = errors_of(&through);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0]
            .2
            .contains("reads DX(21, 11) through VARVAL(3) through VARVAL(4)"),
        "{found:?}"
    );
    let of_time = with(&format!(
        "{joint}VARIABLE/3, FUNCTION = 0.5*SIN(TIME)\n\
         MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = VARVAL(3)"
    ));
    assert_eq!(errors_of(&of_time), []);
}
