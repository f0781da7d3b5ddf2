//! Readers of the elements that connect two markers: JOINT, JPRIM, GCON and MOTION
//! (spec §4) and the force elements SFORCE, VFORCE, VTORQUE, GFORCE, SPRINGDAMPER and
//! BUSHING (spec §7).

use super::elements::{
    Bushing, Expr, Gcon, Joint, Jprim, Motion, MotionAxis, MotionLevel, MotionTarget, Sforce,
    SpringDamper, VectorForce, VectorForceKind,
};
use super::expected;
use super::reader::Reader;
use super::resolve::{ExprArg, MarkerUse};
use super::stmt_args::Args;
use crate::check::Expect;
use crate::diag::{Code, Diagnostic};
use crate::vocab::elements::{JointType, JprimType};
use crate::vocab::math::Vec3;

/// The shortest abbreviation of a JOINT or JPRIM type flag the reader accepts
/// (multibody spec §1.6); the full spellings come from the one table of element names.
const FLAG_MIN_LEN: usize = 3;

/// A type flag from the vocabulary's `(flag, type)` list; `E0604` naming the choices when
/// none is given.
fn type_flag<T: Copy>(a: &mut Args, flags: impl Iterator<Item = (&'static str, T)>) -> Option<T> {
    let table: Vec<(&str, T)> = flags.collect();
    let options: Vec<(&str, usize)> = table.iter().map(|&(n, _)| (n, FLAG_MIN_LEN)).collect();
    match a.choice(&options) {
        Some(k) => Some(table[k].1),
        None => {
            let names: Vec<&str> = table.iter().map(|t| t.0).collect();
            a.missing(&format!("a type, one of {}", names.join(", ")));
            None
        }
    }
}

/// The fixed I and J markers of a constraint, on different parts (spec §4.2).
fn fixed_pair(r: &mut Reader, a: &mut Args) -> Option<(u32, u32)> {
    let (i, j) = force_pair(r, a)?;
    let (i, j) = ((i, span(a, "I")), (j, span(a, "J")));
    r.distinct_parts(a, &i, &j).then_some((i.0, j.0))
}

/// The fixed I and J markers of a force element. They may share a part: an ACTIONONLY
/// SFORCE uses J only for its direction, and real files put both on one part.
fn force_pair(r: &mut Reader, a: &mut Args) -> Option<(u32, u32)> {
    let i = r.marker_ref(a, "I", 1, MarkerUse::Fixed, true);
    let j = r.marker_ref(a, "J", 1, MarkerUse::Fixed, true);
    Some((i?.0, j?.0))
}

/// The span of the value of argument `key` (for messages about a checked reference).
fn span(a: &Args, key: &str) -> crate::diag::Span {
    a.stmt
        .arg(key, key.len())
        .and_then(|arg| arg.items().first())
        .map_or(a.stmt.keyword_span.clone(), |item| item.span.clone())
}

/// `IC = disp, vel`-style pairs (one value sets the displacement only).
fn pair(a: &mut Args, full: &str, min: usize) -> Option<[f64; 2]> {
    a.numbers(full, min, 1..=2)
        .map(|v| [v[0], v.get(1).copied().unwrap_or(0.0)])
}

pub fn joint(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let kind = type_flag(a, JointType::flags());
    let markers = fixed_pair(r, a);
    let need = |a: &mut Args, key: &str| a.required_number(key, 2);
    let pd = (kind == Some(JointType::Rackpin))
        .then(|| need(a, "PD"))
        .flatten();
    let pitch = (kind == Some(JointType::Screw))
        .then(|| need(a, "PITCH"))
        .flatten();
    let ic = pair(a, "IC", 2);
    let (ic_tran, ic_rot) = if kind == Some(JointType::Cylindrical) {
        (pair(a, "ICTRAN", 3), pair(a, "ICROT", 3))
    } else {
        (None, None)
    };
    let (Some(kind), Some((i, j))) = (kind, markers) else {
        return;
    };
    if (kind == JointType::Rackpin && pd.is_none()) || (kind == JointType::Screw && pitch.is_none())
    {
        return;
    }
    r.model.joints.push(Joint {
        el,
        kind,
        i,
        j,
        pd,
        pitch,
        ic,
        ic_tran,
        ic_rot,
    });
}

pub fn jprim(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let kind = type_flag(a, JprimType::flags());
    let markers = fixed_pair(r, a);
    if let (Some(kind), Some((i, j))) = (kind, markers) {
        r.model.jprims.push(Jprim { el, kind, i, j });
    }
}

pub fn gcon(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let i = r.marker_ref(a, "I", 1, MarkerUse::Any, false);
    if let Some(function) = r.required_expr(a, "FUNCTION", 2) {
        r.model.gcons.push(Gcon {
            el,
            i: i.map(|m| m.0),
            function,
        });
    }
}

const AXES: &[(&str, usize, MotionAxis)] = &[
    ("X", 1, MotionAxis::X),
    ("Y", 1, MotionAxis::Y),
    ("Z", 1, MotionAxis::Z),
    ("B1", 2, MotionAxis::B1),
    ("B2", 2, MotionAxis::B2),
    ("B3", 2, MotionAxis::B3),
];

/// ROTATION or TRANSLATION (Adams View writes ROTATIONAL / TRANSLATIONAL): true for a
/// rotation, `None` when neither is written.
fn rotation_flag(a: &mut Args) -> Option<bool> {
    a.choice(&[("ROTATIONAL", 3), ("TRANSLATIONAL", 3)])
        .map(|k| k == 0)
}

pub fn motion(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let level = match a.choice(&[("DISPLACEMENT", 1), ("VELOCITY", 1), ("ACCELERATION", 1)]) {
        Some(1) => MotionLevel::Velocity,
        Some(2) => MotionLevel::Acceleration,
        _ => MotionLevel::Displacement,
    };
    let target = if a.stmt.arg("JOINT", 2).is_some() {
        joint_motion(r, a)
    } else {
        let pair = fixed_pair(r, a);
        let options: Vec<(&str, usize)> = AXES.iter().map(|(n, m, _)| (*n, *m)).collect();
        let axis = a.choice(&options).map(|k| AXES[k].2);
        if axis.is_none() {
            a.missing("JOINT = id, or one of X, Y, Z, B1, B2, B3 with I and J");
        }
        match (pair, axis) {
            (Some((i, j)), Some(axis)) => Some(MotionTarget::Markers { i, j, axis }),
            _ => None,
        }
    };
    let icdisp = a.number("ICDISP", 3);
    let icvel = a.number("ICVEL", 3);
    let want = target.as_ref().map(|t| {
        let rotation = match t {
            MotionTarget::Joint { rotation, .. } => *rotation,
            MotionTarget::Markers { axis, .. } => {
                matches!(axis, MotionAxis::B1 | MotionAxis::B2 | MotionAxis::B3)
            }
        };
        expected::motion(rotation, level)
    });
    let function = r.required_expr_as(a, "FUNCTION", 2, want);
    if let (Some(target), Some(function)) = (target, function) {
        r.model.motions.push(Motion {
            el,
            target,
            level,
            function,
            icdisp,
            icvel,
        });
    }
}

/// `JOINT = id` with ROTATION or TRANSLATION: the joint must be REVOLUTE, TRANSLATIONAL
/// or CYLINDRICAL, and the choice must fit it (spec §4.5).
fn joint_motion(r: &mut Reader, a: &mut Args) -> Option<MotionTarget> {
    let (joint, span) = a.id("JOINT", 2)?;
    let written = rotation_flag(a);
    let Some(kind) = r
        .model
        .joints
        .iter()
        .find(|j| j.el.id == joint)
        .map(|j| j.kind)
    else {
        if !r.scope.has("JOINT", i64::from(joint)) {
            a.diags.push(Diagnostic::error(
                Code::UndefinedElement,
                span,
                format!("JOINT/{joint} is not defined in this dataset"),
            ));
        }
        return None;
    };
    let implied = match kind {
        JointType::Revolute => Some(true),
        JointType::Translational => Some(false),
        JointType::Cylindrical => None,
        other => {
            a.diags.push(
                Diagnostic::error(
                    Code::Topology,
                    span,
                    format!("{} drives JOINT/{joint}, a {other:?} joint", a.label),
                )
                .with_help("a MOTION drives a REVOLUTE, TRANSLATIONAL or CYLINDRICAL joint"),
            );
            return None;
        }
    };
    let rotation = match (implied, written) {
        (Some(i), Some(w)) if i != w => {
            let span = a.stmt.keyword_span.clone();
            let msg = format!(
                "{} asks for a {} of a {kind:?} joint",
                a.label,
                if w { "rotation" } else { "translation" }
            );
            a.error(Code::BadArgument, span, msg);
            return None;
        }
        (Some(i), _) => i,
        (None, Some(w)) => w,
        (None, None) => {
            a.missing("ROTATION or TRANSLATION for a CYLINDRICAL joint");
            return None;
        }
    };
    Some(MotionTarget::Joint { joint, rotation })
}

pub fn sforce(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let rotation = rotation_flag(a).unwrap_or(false);
    let action_only = a.flag("ACTIONONLY", 3);
    let markers = force_pair(r, a);
    let want = Some(expected::sforce(rotation));
    let function = r.required_expr_as(a, "FUNCTION", 2, want);
    if let (Some((i, j)), Some(function)) = (markers, function) {
        r.model.sforces.push(Sforce {
            el,
            i,
            j,
            rotation,
            action_only,
            function,
        });
    }
}

/// Three component expressions, all required when any is wanted: forces, or torques.
fn components(r: &mut Reader, a: &mut Args, keys: [&str; 3], torque: bool) -> Option<[Expr; 3]> {
    let want = Some(expected::component(torque));
    let found = keys.map(|k| match r.expr_as(a, k, 2, Expect::Scalar, want) {
        ExprArg::Ok(e) => Some(e),
        ExprArg::Absent => {
            a.missing(&format!("{k} = expression"));
            None
        }
        ExprArg::Unusable => None,
    });
    let [x, y, z] = found;
    Some([x?, y?, z?])
}

pub fn vector_force(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let kind = match a.stmt.canonical {
        Some("VFORCE") => VectorForceKind::Vforce,
        Some("VTORQUE") => VectorForceKind::Vtorque,
        _ => VectorForceKind::Gforce,
    };
    let i = r.marker_ref(a, "I", 1, MarkerUse::Fixed, true);
    let jfloat = r.marker_ref(a, "JFLOAT", 2, MarkerUse::Floating, true);
    let rm = r.marker_ref(a, "RM", 2, MarkerUse::Any, true);
    match r.expr(a, "FUNCTION", 2, Expect::Scalar) {
        ExprArg::Absent => {}
        // `FUNCTION = USER(…)`: the subroutine computes every component (warned).
        ExprArg::Unusable => return,
        ExprArg::Ok(e) => {
            let msg = format!(
                "{} takes its components as FX=… TX=…, not FUNCTION",
                a.label
            );
            a.error(Code::BadArgument, e.span, msg);
            return;
        }
    }
    for key in ["FXYZ", "TXYZ"] {
        if let Some(arg) = a.find(key, 4) {
            a.diags.push(
                Diagnostic::warning(
                    Code::UnsupportedStatement,
                    arg.span.clone(),
                    format!(
                        "{key} vector expressions are not supported; {} is ignored",
                        a.label
                    ),
                )
                .with_help("write the three components FX, FY, FZ (TX, TY, TZ)"),
            );
            return;
        }
    }
    let force =
        (kind != VectorForceKind::Vtorque).then(|| components(r, a, ["FX", "FY", "FZ"], false));
    let torque =
        (kind != VectorForceKind::Vforce).then(|| components(r, a, ["TX", "TY", "TZ"], true));
    let (Some(i), Some(jfloat), Some(rm)) = (i, jfloat, rm) else {
        return;
    };
    if matches!(force, Some(None)) || matches!(torque, Some(None)) {
        return;
    }
    r.model.vector_forces.push(VectorForce {
        el,
        kind,
        i: i.0,
        jfloat: jfloat.0,
        rm: rm.0,
        force: force.flatten(),
        torque: torque.flatten(),
    });
}

pub fn spring_damper(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let rotation = rotation_flag(a).unwrap_or(false);
    let keys = if rotation {
        ["KT", "CT", "ANGLE", "TORQUE"]
    } else {
        ["K", "C", "LENGTH", "FORCE"]
    };
    let [stiffness, damping, free_length, preload] =
        keys.map(|k| a.number(k, k.len()).unwrap_or(0.0));
    if let Some((i, j)) = force_pair(r, a) {
        r.model.spring_dampers.push(SpringDamper {
            el,
            i,
            j,
            rotation,
            stiffness,
            damping,
            free_length,
            preload,
        });
    }
}

pub fn bushing(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let [k, c, kt, ct, force, torque] = ["K", "C", "KT", "CT", "FORCE", "TORQUE"]
        .map(|key| a.vec3(key, key.len()).unwrap_or_else(Vec3::zeros));
    if let Some((i, j)) = force_pair(r, a) {
        r.model.bushings.push(Bushing {
            el,
            i,
            j,
            k,
            c,
            kt,
            ct,
            force,
            torque,
        });
    }
}
