//! Systems built from a `Model` constructed in code: dimension choice, MOTION and GCON
//! paths, initial velocities, errors.

use super::*;
use crate::check::{self, Expect, MeasureCall, MeasureValue, Scope};
use crate::diag::Diagnostic;
use crate::mbd::assembly::AssemblyOptions;
use crate::mbd::expr::ExprFn;
use crate::mbd::expr::InterpretOnly;
use crate::mbd::planar::Dim;
use crate::mbd::system::{Dimension, PartHandle, System};
use crate::model::elements::{self as el, MeasureSlot, Model, Named};
use crate::vocab::builtins::Ty;
use crate::vocab::elements::JointType;
use crate::vocab::math::{Mat3, Vec3};
use std::cell::RefCell;
use std::f64::consts::PI;

/// A model scope that gives every measure call the next slot(s).
#[derive(Default)]
struct Slots(RefCell<Vec<MeasureSlot>>);

impl Scope for Slots {
    fn variable(&self, _: &str) -> Option<u32> {
        None
    }

    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        let mut v = self.0.borrow_mut();
        let mut push = |component: u8| {
            v.push(MeasureSlot {
                name: call.builtin.name.into(),
                ids: call.ids.to_vec(),
                component,
            });
            v.len() as u32 - 1
        };
        Ok(match call.builtin.result {
            Ty::Scalar => MeasureValue::Scalar(push(0)),
            Ty::Vector => MeasureValue::Vector([push(0), push(1), push(2)]),
        })
    }
}

fn named(id: u32) -> Named {
    Named {
        id,
        name: Some(format!("el_{id}")),
        span: 0..0,
    }
}

/// An expression of time alone, checked and lowered.
fn time_expr(src: &str) -> el::Expr {
    let scope = Slots::default();
    let function = check::compile(src, &scope, Expect::Scalar)
        .unwrap()
        .function;
    el::Expr {
        span: 0..0,
        function,
    }
}

/// MOTION/3 on the ROTATION of JOINT/`joint`.
fn rotation_motion(joint: u32, level: el::MotionLevel, function: el::Expr) -> el::Motion {
    el::Motion {
        el: named(3),
        target: el::MotionTarget::Joint {
            joint,
            rotation: true,
        },
        level,
        function,
        icdisp: None,
        icvel: None,
    }
}

fn part(id: u32, ground: bool, at: Vec3) -> el::Part {
    el::Part {
        el: named(id),
        ground,
        mass: Some(1.0),
        cm: None,
        im: None,
        ip: [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        position: at,
        orientation: Mat3::identity(),
        velocity: [None; 3],
        angular_velocity: [None; 3],
        vm: None,
        wm: None,
        exact: [false; 6],
    }
}

fn marker(id: u32, part: u32, at: Vec3) -> el::Marker {
    el::Marker {
        el: named(id),
        part,
        position: at,
        orientation: Mat3::identity(),
        floating: false,
    }
}

/// The IFToMM A01 pendulum (reference-problems §4.1): unit link from the origin to
/// P1 = (1, 0), gravity −y; the dataset places the part slightly off.
fn pendulum() -> Model {
    let mut m = Model {
        parts: vec![
            part(1, true, Vec3::zeros()),
            part(2, false, Vec3::new(1.05, 0.1, 0.0)),
        ],
        markers: vec![
            marker(10, 1, Vec3::zeros()),
            marker(20, 2, Vec3::new(-1.0, 0.0, 0.0)),
        ],
        gravity: Vec3::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    m.joints.push(el::Joint {
        el: named(1),
        kind: JointType::Revolute,
        i: 20,
        j: 10,
        pd: None,
        pitch: None,
        ic: None,
        ic_tran: None,
        ic_rot: None,
    });
    m
}

#[test]
fn pendulum_model_builds_in_2d_and_assembles() {
    let model = pendulum();
    let mut sys = System::from_model(&model, Dim::Auto, &InterpretOnly).unwrap();
    assert_eq!(sys.dim, Dimension::Two);
    assert!(sys.dim_reason.starts_with("2D"), "{}", sys.dim_reason);
    // REVOLUTE in 2D: X Delta and Y Delta only.
    assert_eq!(sys.labels().len(), 2);
    sys.assemble(&AssemblyOptions::default()).unwrap();
    let p = sys.part(PartHandle(1));
    assert!((p.r.norm() - 1.0).abs() < 1e-12 && p.id == Some(2));
    let sys = System::from_model(&model, Dim::Three, &InterpretOnly).unwrap();
    assert_eq!((sys.dim, sys.labels().len()), (Dimension::Three, 5));
    // Gravity out of the plane makes it 3D, with the reason.
    let mut tilted = pendulum();
    tilted.gravity = Vec3::new(0.0, -9.81, 1.0);
    let sys = System::from_model(&tilted, Dim::Auto, &InterpretOnly).unwrap();
    assert!(sys.dim_reason.contains("gravity"), "{}", sys.dim_reason);
}

#[test]
fn a_slide_along_the_first_planes_normal_is_built_in_a_plane_that_contains_it() {
    // A translational joint whose axis (global x) the plane vote takes for a normal: the
    // YZ plane passes the row test but leaves the slide free along its normal; the XY
    // (or ZX) plane holds every out-of-plane freedom and is the one built.
    let read = crate::model::read_model(
        "slide\nPART/1, GROUND\nMARKER/11, PART = 1, REULER = 90D, 90D, 0D\n\
         PART/2, MASS = 2, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
         MARKER/21, PART = 2, REULER = 90D, 90D, 0D\n\
         JOINT/1, TRANSLATIONAL, I = 21, J = 11\nEND\n",
    );
    assert!(!read.has_errors(), "{:?}", read.diagnostics);
    let sys = crate::mbd::planar::build(&read.model, Dim::Auto, &InterpretOnly).unwrap();
    assert_eq!(sys.dim, Dimension::Two, "{}", sys.dim_reason);
    assert_ne!(sys.normal, 0, "{}", sys.dim_reason);
}

#[test]
fn gcon_without_a_derivative_says_what_is_missing() {
    let scope = Slots::default();
    let f = check::compile("DM(20, 10) - 1", &scope, Expect::Scalar)
        .unwrap()
        .function;
    let mut model = pendulum();
    model.joints.clear();
    model.measures = scope.0.into_inner();
    model.gcons.push(el::Gcon {
        el: named(5),
        i: Some(20),
        function: el::Expr {
            span: 0..0,
            function: f,
        },
    });
    let mut sys = System::from_model(&model, Dim::Three, &InterpretOnly).unwrap();
    // The value comes through the interpreter: DM = |(0.05, 0.1, 0)| at the input.
    let r = sys.residual().unwrap();
    assert!((r[0] - ((0.05f64.powi(2) + 0.01).sqrt() - 1.0)).abs() < 1e-14);
    let err = sys
        .assemble(&AssemblyOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("GCON/5 'el_5'") && err.contains("derivative"),
        "{err}"
    );
}

/// Every expression becomes g(t) = 0.5 + t (stands in for the compiled derivative).
struct Ramp;

impl crate::mbd::expr::ExprCompiler for Ramp {
    fn compile(&self, _: &el::Expr) -> Box<dyn ExprFn> {
        time_fn(0.5, 1.0)
    }
}

#[test]
fn motions_of_a_model_drive_joint_and_marker_angles() {
    let expr = el::Expr {
        span: 0..0,
        function: Default::default(),
    };
    let motion = |target| el::Motion {
        el: named(3),
        target,
        level: el::MotionLevel::Displacement,
        function: expr.clone(),
        icdisp: None,
        icvel: None,
    };
    // JOINT ROTATION and the marker form B3 both drive the pendulum angle to 0.5 rad
    // (relative to the input angle 0, about z).
    for target in [
        el::MotionTarget::Joint {
            joint: 1,
            rotation: true,
        },
        el::MotionTarget::Markers {
            i: 20,
            j: 10,
            axis: el::MotionAxis::B3,
        },
    ] {
        let mut model = pendulum();
        model.motions.push(motion(target));
        let mut sys = System::from_model(&model, Dim::Auto, &Ramp).unwrap();
        sys.assemble(&AssemblyOptions::default()).unwrap();
        let p = sys.part(PartHandle(1));
        let x = p.rot * Vec3::x();
        assert!((x.y.atan2(x.x) - 0.5).abs() < 1e-10 && (p.w.z - 1.0).abs() < 1e-10);
        // The link hangs from the pivot: r = −R·(−1, 0, 0).
        assert!((p.r - x).norm() < 1e-10);
    }
}

#[test]
fn part_velocities_are_given_at_the_cm_in_cm_axes() {
    // CM marker 21 at (0.5, 0, 0) on part 2, turned 90° about z: WX = 2 about the CM
    // x axis is ω = (0, 2, 0) globally; VX = 1 is the CM velocity, which is the part's
    // reference point, and the BCS origin moves with
    // v_cm − ω × (r_cm − r_origin) = (1, 0, 0) − (0, 2, 0) × (0.5, 0, 0) = (1, 0, 1).
    let mut model = pendulum();
    model.joints.clear();
    let mut cm = marker(21, 2, Vec3::new(0.5, 0.0, 0.0));
    cm.orientation = rz(PI / 2.0);
    model.markers.push(cm);
    model.parts[1].cm = Some(21);
    model.parts[1].velocity = [Some(1.0), None, None];
    model.parts[1].angular_velocity = [Some(2.0), None, None];
    let sys = System::from_model(&model, Dim::Auto, &InterpretOnly).unwrap();
    assert!(
        sys.dim_reason.contains("velocity out of the XY plane"),
        "{}",
        sys.dim_reason
    );
    let p = sys.part(PartHandle(1));
    assert!((p.w - Vec3::new(0.0, 2.0, 0.0)).norm() < 1e-15);
    assert!((p.v - Vec3::new(1.0, 0.0, 0.0)).norm() < 1e-15, "{}", p.v);
    let origin = p.v + p.w.cross(&(p.bcs_origin() - p.r));
    assert!(
        (origin - Vec3::new(1.0, 0.0, 1.0)).norm() < 1e-15,
        "{origin}"
    );
}

#[test]
fn unknown_markers_and_joints_are_errors() {
    let mut model = pendulum();
    model.joints[0].i = 99;
    let err = System::from_model(&model, Dim::Auto, &InterpretOnly)
        .err()
        .unwrap();
    assert_eq!(err.to_string(), "MARKER/99 does not exist");
    let mut model = pendulum();
    let motion = rotation_motion(8, el::MotionLevel::Displacement, time_expr("0"));
    model.motions.push(motion);
    let err = System::from_model(&model, Dim::Auto, &Ramp).err().unwrap();
    assert_eq!(err.to_string(), "MOTION/3: JOINT/8 does not exist");
}

#[test]
fn motion_function_is_evaluated_by_the_interpreter() {
    // MOTION/3, JOINT=1, ROTATION, FUNCTION = 30D*TIME + 0.5: the row is AZ − g(t), with
    // AZ = 0 at the input pose.
    let mut model = pendulum();
    let f = time_expr("30D*TIME + 0.5");
    model
        .motions
        .push(rotation_motion(1, el::MotionLevel::Displacement, f));
    let mut sys = System::from_model(&model, Dim::Three, &InterpretOnly).unwrap();
    let last = sys.labels().len() - 1;
    assert!((sys.residual().unwrap()[last] + 0.5).abs() < 1e-15);
    sys.time = 2.0;
    assert!((sys.residual().unwrap()[last] + 0.5 + PI / 3.0).abs() < 1e-15);
}

#[test]
fn velocity_and_acceleration_motions_integrate_their_function() {
    // spec §4.5: g(0) = ICDISP; ġ(0) = f(0) for VELOCITY, ICVEL for ACCELERATION.
    // The FUNCTION goes through the interpreter: 2 + TIME, so f(0) = 2.
    let f = time_expr("2 + TIME");
    // g(0.5) by hand: 0.4 + ∫₀^0.5 (2 + s) ds = 1.525; 0.4 − 0.7·0.5 +
    // ∫₀^0.5 (0.5 − s)(2 + s) ds = 0.05 + 0.5 − 0.1875 − 0.125/3.
    for (level, rate, later) in [
        (el::MotionLevel::Velocity, 2.0, 1.525),
        (
            el::MotionLevel::Acceleration,
            -0.7,
            0.05 + 0.5 - 0.1875 - 0.125 / 3.0,
        ),
    ] {
        let mut model = pendulum();
        model.motions.push(el::Motion {
            icdisp: Some(0.4),
            icvel: Some(-0.7),
            ..rotation_motion(1, level, f.clone())
        });
        let mut sys = System::from_model(&model, Dim::Auto, &InterpretOnly).unwrap();
        sys.assemble(&AssemblyOptions::default()).unwrap();
        let p = sys.part(PartHandle(1));
        let x = p.rot * Vec3::x();
        assert!((x.y.atan2(x.x) - 0.4).abs() < 1e-10, "{level:?}");
        assert!((p.w.z - rate).abs() < 1e-10, "{level:?}: {}", p.w.z);
        // Later, the row is AZ − g(t) with g the integral of f.
        sys.time = 0.5;
        let last = sys.labels().len() - 1;
        let r = sys.residual().unwrap()[last];
        assert!((r - (0.4 - later)).abs() < 1e-14, "{level:?}: {r}");
    }
}
