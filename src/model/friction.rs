//! Joint FRICTION (issue 40 §2) as the model holds it and as the reader reads it: the
//! joint it acts in, the friction coefficients and their velocity transitions, what
//! loads the friction (INPUTS: preload, reaction force, bending and torsional moment)
//! and the joint's dimensions that turn loads into friction (PIN_RADIUS, BALL_RADIUS,
//! FRICTION_ARM, BENDING_REACTION_ARM, INITIAL_OVERLAP with OVERLAP_DELTA).
//!
//! Defaults are Adams Solver's. Arguments mbfx reads but does not model are warned at
//! the argument: the LuGre model (FRICTION_MODEL = LUGRE and its bristle parameters) and
//! the yokes of a Hooke or universal joint (I_YOKE, J_YOKE).

use super::elements::{Id, Named};
use super::reader::Reader;
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic};
use crate::vocab::elements::JointType;

/// Which friction effects act (EFFECT).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionEffect {
    /// ALL: stiction and sliding.
    All,
    /// STICTION: the static friction only (μ falls to zero past the transition).
    Stiction,
    /// SLIDING: the dynamic friction only (no static peak).
    Sliding,
}

/// What loads the friction (INPUTS); all on by default.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrictionInputs {
    /// PRELOAD: FRICTION_FORCE_PRELOAD.
    pub preload: bool,
    /// REACTION_FORCE: the joint's reaction force.
    pub reaction_force: bool,
    /// BENDING_MOMENT: the joint's bending reaction moment.
    pub bending_moment: bool,
    /// TORSIONAL_MOMENT: the joint's torsional reaction moment (translational joints).
    pub torsional_moment: bool,
}

/// How the overlap of a translational or cylindrical joint changes with its travel
/// (OVERLAP_DELTA).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverlapDelta {
    /// CONSTANT: the overlap stays INITIAL_OVERLAP.
    Constant,
    /// INCREASE: the overlap grows as I travels along +z_J.
    Increase,
    /// DECREASE: the overlap shrinks as I travels along +z_J.
    Decrease,
}

/// FRICTION/id: the friction of JOINT/joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Friction {
    /// Id, view name and span.
    pub el: Named,
    /// JOINT: the joint the friction acts in.
    pub joint: Id,
    /// MU_STATIC.
    pub mu_static: f64,
    /// MU_DYNAMIC.
    pub mu_dynamic: f64,
    /// STICTION_TRANSITION_VELOCITY (default 0.1).
    pub stiction_velocity: f64,
    /// TRANSITION_VELOCITY_COEFFICIENT (default 1.5): full sliding from this times the
    /// stiction transition velocity.
    pub transition_coefficient: f64,
    /// MAX_STICTION_DEFORMATION (default 0.01): the largest stiction deformation, at
    /// which the friction reaches μs·N (docs/dynamics.md "Joint friction").
    pub max_stiction_deformation: f64,
    /// FRICTION_FORCE_PRELOAD (default 0).
    pub preload: f64,
    /// MAX_FRICTION_FORCE or MAX_FRICTION_TORQUE, when given: the friction's cap.
    pub max_friction: Option<f64>,
    /// EFFECT.
    pub effect: FrictionEffect,
    /// INPUTS.
    pub inputs: FrictionInputs,
    /// PIN_RADIUS (default 1).
    pub pin_radius: f64,
    /// BALL_RADIUS (default 1).
    pub ball_radius: f64,
    /// FRICTION_ARM (default 1).
    pub friction_arm: f64,
    /// BENDING_REACTION_ARM (default 1).
    pub bending_arm: f64,
    /// INITIAL_OVERLAP (default 1000).
    pub initial_overlap: f64,
    /// OVERLAP_DELTA.
    pub overlap_delta: OverlapDelta,
    /// INACTIVE = STATIC: no friction in a static analysis.
    pub inactive_static: bool,
}

/// The joint types a FRICTION may name (Adams).
pub const FRICTION_JOINTS: [JointType; 6] = [
    JointType::Revolute,
    JointType::Translational,
    JointType::Cylindrical,
    JointType::Spherical,
    JointType::Hooke,
    JointType::Universal,
];

/// A positive number with a default; `E0605` at the value when not positive.
fn positive_or(a: &mut Args, key: &str, default: f64) -> f64 {
    let Some(v) = a.number(key, key.len().min(8)) else {
        return default;
    };
    if v > 0.0 {
        return v;
    }
    let span = a.stmt.arg(key, key.len().min(8)).map(|x| x.span.clone());
    let msg = format!("{key} of {} must be positive, found {v}", a.label);
    a.error(Code::BadArgument, span.unwrap_or_default(), msg);
    default
}

/// A number not below zero with a default.
fn not_negative_or(a: &mut Args, key: &str, default: f64) -> f64 {
    let Some(v) = a.number(key, key.len().min(8)) else {
        return default;
    };
    if v >= 0.0 {
        return v;
    }
    let span = a.stmt.arg(key, key.len().min(8)).map(|x| x.span.clone());
    let msg = format!("{key} of {} must not be negative, found {v}", a.label);
    a.error(Code::BadArgument, span.unwrap_or_default(), msg);
    default
}

/// A warning at argument `key` when present: read, not modelled.
fn not_modelled(a: &mut Args, key: &str, min: usize, why: &str) {
    if let Some(arg) = a.find(key, min) {
        let msg = format!("{} of {}: {why}", arg.name, a.label);
        a.diags.push(Diagnostic::warning(
            Code::UnsupportedStatement,
            arg.name_span.clone(),
            msg,
        ));
    }
}

fn effect(a: &mut Args) -> FrictionEffect {
    let Some((word, span)) = a.word("EFFECT", 3) else {
        return FrictionEffect::All;
    };
    match word.to_ascii_uppercase().as_str() {
        "ALL" => FrictionEffect::All,
        w if "STICTION".starts_with(w) && w.len() >= 3 => FrictionEffect::Stiction,
        w if "SLIDING".starts_with(w) && w.len() >= 3 => FrictionEffect::Sliding,
        _ => {
            let msg = format!(
                "EFFECT of {} is ALL, STICTION or SLIDING, found {word}",
                a.label
            );
            a.error(Code::BadArgument, span, msg);
            FrictionEffect::All
        }
    }
}

fn inputs(a: &mut Args) -> FrictionInputs {
    let all = FrictionInputs {
        preload: true,
        reaction_force: true,
        bending_moment: true,
        torsional_moment: true,
    };
    let Some(arg) = a.find("INPUTS", 3) else {
        return all;
    };
    let mut got = FrictionInputs {
        preload: false,
        reaction_force: false,
        bending_moment: false,
        torsional_moment: false,
    };
    for item in arg.items() {
        let word = item
            .text
            .trim_matches(|c| c == '(' || c == ')')
            .to_ascii_uppercase();
        match word.as_str() {
            "ALL" => got = all,
            "NONE" => {}
            "PRELOAD" => got.preload = true,
            "REACTION_FORCE" => got.reaction_force = true,
            "BENDING_MOMENT" => got.bending_moment = true,
            "TORSIONAL_MOMENT" => got.torsional_moment = true,
            _ => {
                let msg = format!(
                    "INPUTS of {}: expected ALL, NONE, PRELOAD, REACTION_FORCE, BENDING_MOMENT or TORSIONAL_MOMENT, found `{}`",
                    a.label, item.text
                );
                a.error(Code::BadArgument, item.span.clone(), msg);
            }
        }
    }
    got
}

fn overlap_delta(a: &mut Args) -> OverlapDelta {
    let Some((word, span)) = a.word("OVERLAP_DELTA", 9) else {
        return OverlapDelta::Constant;
    };
    match word.to_ascii_uppercase().as_str() {
        "CONSTANT" => OverlapDelta::Constant,
        "INCREASE" => OverlapDelta::Increase,
        "DECREASE" => OverlapDelta::Decrease,
        _ => {
            let msg = format!(
                "OVERLAP_DELTA of {} is INCREASE, DECREASE or CONSTANT, found {word}",
                a.label
            );
            a.error(Code::BadArgument, span, msg);
            OverlapDelta::Constant
        }
    }
}

/// INACTIVE = STATIC (Adams C++) or INACTIVE_DURING = STATIC (as datasets write it).
fn inactive_static(a: &mut Args) -> bool {
    let found = a
        .word("INACTIVE_DURING", 15)
        .or_else(|| a.word("INACTIVE", 8));
    match found {
        Some((w, _)) if w.eq_ignore_ascii_case("STATIC") => true,
        Some((w, span)) => {
            let msg = format!("INACTIVE of {} takes STATIC, found {w}", a.label);
            a.error(Code::BadArgument, span, msg);
            false
        }
        None => false,
    }
}

/// FRICTION/id, JOINT = id, MU_STATIC, MU_DYNAMIC [, …].
pub(super) fn friction(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let joint = a.required_id("JOINT", 3);
    let mu_static = a.required_number("MU_STATIC", 6);
    let mu_dynamic = a.required_number("MU_DYNAMIC", 6);
    let stiction_velocity = positive_or(a, "STICTION_TRANSITION_VELOCITY", 0.1);
    let transition_coefficient = positive_or(a, "TRANSITION_VELOCITY_COEFFICIENT", 1.5);
    let max_stiction_deformation = positive_or(a, "MAX_STICTION_DEFORMATION", 0.01);
    let preload = not_negative_or(a, "FRICTION_FORCE_PRELOAD", 0.0);
    let max_force = a.number("MAX_FRICTION_FORCE", 14);
    let max_torque = a.number("MAX_FRICTION_TORQUE", 14);
    let effect = effect(a);
    let inputs = inputs(a);
    let pin_radius = positive_or(a, "PIN_RADIUS", 1.0);
    let ball_radius = positive_or(a, "BALL_RADIUS", 1.0);
    let friction_arm = positive_or(a, "FRICTION_ARM", 1.0);
    let bending_arm = positive_or(a, "BENDING_REACTION_ARM", 1.0);
    let initial_overlap = positive_or(a, "INITIAL_OVERLAP", 1000.0);
    let overlap_delta = overlap_delta(a);
    let inactive_static = inactive_static(a);
    if let Some((model, span)) = a.word("FRICTION_MODEL", 10) {
        if !model.eq_ignore_ascii_case("STICK_SLIP") {
            let msg = format!(
                "FRICTION_MODEL = {model} of {}: mbfx models the stick-slip friction",
                a.label
            );
            a.diags
                .push(Diagnostic::warning(Code::UnsupportedStatement, span, msg));
        }
    }
    for key in [
        "BRISTLE_STIFFNESS",
        "BRISTLE_DAMPING",
        "VISCOUS_COEFFICIENT",
        "STRIBECK_VELOCITY",
    ] {
        not_modelled(
            a,
            key,
            key.len(),
            "a LuGre parameter; mbfx models the stick-slip friction",
        );
    }
    for key in ["I_YOKE", "J_YOKE"] {
        not_modelled(
            a,
            key,
            key.len(),
            "mbfx opposes the whole relative rotation of a Hooke or universal joint",
        );
    }
    let (Some((joint, span)), Some(mu_static), Some(mu_dynamic)) = (joint, mu_static, mu_dynamic)
    else {
        return;
    };
    let defined = (r.scope.ids.get("JOINT")).is_some_and(|ids| ids.contains(&i64::from(joint)));
    if !defined {
        a.diags.push(Diagnostic::error(
            Code::UndefinedElement,
            span,
            format!("JOINT/{joint} is not defined in this dataset"),
        ));
        return;
    }
    // A joint read before the friction is checked here; the core checks the others.
    let joint_type = r
        .model
        .joints
        .iter()
        .find(|j| j.el.id == joint)
        .map(|j| j.kind);
    if let Some(joint_type) = joint_type.filter(|t| !FRICTION_JOINTS.contains(t)) {
        let flag = crate::vocab::elements::ElementKind::Joint(joint_type).flag();
        let msg = format!(
            "{} names a {} joint; friction acts in revolute, translational, cylindrical, spherical, Hooke and universal joints",
            a.label,
            flag.unwrap_or_default()
        );
        a.error(Code::BadArgument, span, msg);
        return;
    }
    for (key, v) in [("MU_STATIC", mu_static), ("MU_DYNAMIC", mu_dynamic)] {
        if v < 0.0 {
            let span = a.stmt.arg(key, 6).map(|x| x.span.clone());
            let msg = format!("{key} of {} must not be negative, found {v}", a.label);
            a.error(Code::BadArgument, span.unwrap_or_default(), msg);
            return;
        }
    }
    r.model.frictions.push(Friction {
        el,
        joint,
        mu_static,
        mu_dynamic,
        stiction_velocity,
        transition_coefficient,
        max_stiction_deformation,
        preload,
        max_friction: max_force.or(max_torque).filter(|m| *m > 0.0),
        effect,
        inputs,
        pin_radius,
        ball_radius,
        friction_arm,
        bending_arm,
        initial_overlap,
        overlap_delta,
        inactive_static,
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::read_model;

    const HEAD: &str = "fr\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
        JOINT/1, REVOLUTE, I = 20, J = 10\nJOINT/2, FIXED, I = 20, J = 10\n";

    #[test]
    fn arguments_read_with_adams_defaults() {
        let read = read_model(&format!(
            "{HEAD}FRICTION/1, JOINT = 1, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, \
             INPUTS = (PRELOAD:REACTION_FORCE), EFFECT = SLIDING, OVERLAP_DELTA = INCREASE\n\
             FRICTION/2, JOINT = 1, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, INACTIVE_DURING = STATIC\nEND\n"
        ));
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let f = &read.model.frictions[0];
        assert_eq!(
            (f.mu_static, f.mu_dynamic, f.effect),
            (0.3, 0.2, FrictionEffect::Sliding)
        );
        assert_eq!(
            (
                f.inputs.preload,
                f.inputs.reaction_force,
                f.inputs.bending_moment
            ),
            (true, true, false)
        );
        assert_eq!(f.overlap_delta, OverlapDelta::Increase);
        // Adams' defaults.
        assert_eq!((f.stiction_velocity, f.transition_coefficient), (0.1, 1.5));
        assert_eq!(
            (f.pin_radius, f.friction_arm, f.bending_arm),
            (1.0, 1.0, 1.0)
        );
        assert!(read.model.frictions[1].inactive_static);
        assert!(read.model.ignored.is_empty(), "{:?}", read.model.ignored);
    }

    #[test]
    fn a_fixed_or_missing_joint_or_a_negative_mu_is_an_error_at_its_value() {
        for (text, what) in [
            (
                "FRICTION/1, JOINT = 2, MU_STATIC = 0.3, MU_DYNAMIC = 0.2",
                "names a FIXED joint",
            ),
            (
                "FRICTION/1, JOINT = 7, MU_STATIC = 0.3, MU_DYNAMIC = 0.2",
                "JOINT/7 is not defined",
            ),
            (
                "FRICTION/1, JOINT = 1, MU_STATIC = 0.3, MU_DYNAMIC = -0.2",
                "must not be negative",
            ),
            ("FRICTION/1, JOINT = 1, MU_STATIC = 0.3", "needs MU_DYNAMIC"),
        ] {
            let full = format!("{HEAD}{text}\nEND\n");
            let read = read_model(&full);
            let e = (read.diagnostics.iter())
                .find(|d| d.severity == crate::diag::Severity::Error)
                .unwrap_or_else(|| panic!("{text}: no error"));
            assert!(e.message.contains(what), "{text}: {}", e.message);
            assert!(read.model.frictions.is_empty(), "{text}");
            assert!(
                e.span.end <= full.len() && e.span.start >= HEAD.len() - 60,
                "{text}"
            );
        }
    }
}
