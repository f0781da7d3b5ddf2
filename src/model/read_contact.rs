//! The reader of CONTACT (issue 40 §1, the Adams Solver CONTACT statement): IGEOM and
//! JGEOM (GRAPHICS ids, lists), IFLIP_GEOMETRY, JFLIP_GEOMETRY, the normal law (IMPACT with
//! STIFFNESS, DAMPING, DMAX, EXPONENT; or POISSON with PENALTY, RESTITUTION_COEFFICIENT)
//! and COULOMB_FRICTION with MU_STATIC, MU_DYNAMIC, STICTION_TRANSITION_VELOCITY and
//! FRICTION_TRANSITION_VELOCITY. Adams takes NORMAL_FUNCTION and FRICTION_FUNCTION only as
//! `USER(…)` (the CNFSUB and CFFSUB subroutines): they, the routines, flexible bodies and
//! edges are refused by name and the CONTACT is left out, warned. Every bad value is an
//! error at its argument; arguments the reader does not ask for (STICTION,
//! MAX_STICTION_DEFORMATION, AUGMENTED_LAGRANGIAN_FORMULATION, …) are warned and ignored.

use super::contact::{Contact, Friction, FrictionMode, NormalLaw};
use super::elements::Id;
use super::reader::Reader;
use super::statement::ItemKind;
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic, Span};

/// Arguments that need a user subroutine or a geometry mbfx does not model: the CONTACT
/// is left out when one is given.
const REFUSED: &[(&str, usize, &str)] = &[
    (
        "NORMAL_FUNCTION",
        8,
        "a user normal-force subroutine (CNFSUB)",
    ),
    (
        "NORMAL_ROUTINE",
        8,
        "a user normal-force subroutine (CNFSUB)",
    ),
    (
        "FRICTION_FUNCTION",
        10,
        "a user friction subroutine (CFFSUB)",
    ),
    (
        "FRICTION_ROUTINE",
        10,
        "a user friction subroutine (CFFSUB)",
    ),
    ("GEOMETRY_ROUTINES", 8, "a user geometry library"),
    ("GEOMETRY_LIBRARY", 10, "a user geometry library"),
    ("IFLEX", 5, "a flexible body"),
    ("JFLEX", 5, "a flexible body"),
    ("IEDGE", 5, "a flexible body's edge"),
    ("JEDGE", 5, "a flexible body's edge"),
];

/// Adams' defaults of the transition velocities (model units).
const STICTION_VELOCITY: f64 = 0.1;
const FRICTION_VELOCITY: f64 = 1.0;

pub fn contact(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let mut refused = false;
    for &(key, min, why) in REFUSED {
        if let Some(arg) = a.find(key, min) {
            a.diags.push(
                Diagnostic::warning(
                    Code::UnsupportedStatement,
                    arg.span.clone(),
                    format!(
                        "{key} of {} needs {why}, which mbfx does not model; the CONTACT is left out",
                        a.label
                    ),
                )
                .with_help("use IMPACT or POISSON with COULOMB_FRICTION"),
            );
            refused = true;
        }
    }
    if let Some((kind, span)) = a.word("TYPE", 4) {
        if !kind.eq_ignore_ascii_case("SOLID_TO_SOLID") {
            let msg = format!(
                "TYPE = {kind} of {}: mbfx models SOLID_TO_SOLID contacts only; the CONTACT is left out",
                a.label
            );
            a.diags
                .push(Diagnostic::warning(Code::UnsupportedStatement, span, msg));
            refused = true;
        }
    }
    let igeom = graphics_list(r, a, "IGEOM", true);
    let jgeom = graphics_list(r, a, "JGEOM", true);
    let iflip = graphics_list(r, a, "IFLIP_GEOMETRY", false);
    let jflip = graphics_list(r, a, "JFLIP_GEOMETRY", false);
    let normal = normal_law(a);
    let friction = friction(a);
    if refused {
        return;
    }
    let (Some(igeom), Some(jgeom), Some(iflip), Some(jflip), Some(normal), Some(friction)) =
        (igeom, jgeom, iflip, jflip, normal, friction)
    else {
        return;
    };
    r.model.contacts.push(Contact {
        el,
        igeom,
        jgeom,
        iflip,
        jflip,
        normal,
        friction,
    });
}

/// A list of GRAPHICS ids (`IGEOM = 1, 2` or `1:2`), each defined; `required`: E0604
/// when absent. An absent optional list is empty.
fn graphics_list(r: &Reader, a: &mut Args, key: &str, required: bool) -> Option<Vec<Id>> {
    let Some(arg) = a.find(key, key.len().min(5)) else {
        if required {
            a.missing(&format!("{key} = GRAPHICS id(s)"));
            return None;
        }
        return Some(Vec::new());
    };
    let mut ids = Vec::new();
    let mut ok = true;
    for item in arg.items() {
        let id = match item.kind {
            ItemKind::Number { .. } => item.as_integer().and_then(|v| Id::try_from(v).ok()),
            _ => None,
        };
        match id {
            Some(id) if r.scope.has("GRAPHICS", i64::from(id)) => ids.push(id),
            Some(id) => {
                a.error(
                    Code::UndefinedElement,
                    item.span.clone(),
                    format!("{key}: GRAPHICS/{id} is not defined"),
                );
                ok = false;
            }
            None => {
                a.error(
                    Code::BadArgument,
                    item.span.clone(),
                    format!("{key}: expected a GRAPHICS id, found `{}`", item.text),
                );
                ok = false;
            }
        }
    }
    if ok && ids.is_empty() {
        a.error(
            Code::BadArgument,
            arg.span.clone(),
            format!("{key} needs a GRAPHICS id"),
        );
        return None;
    }
    ok.then_some(ids)
}

/// A number of the statement checked against `ok` (E0605 at the argument, naming
/// `range`); `default` when absent.
fn checked(
    a: &mut Args,
    key: &str,
    min: usize,
    default: Option<f64>,
    ok: impl Fn(f64) -> bool,
    range: &str,
) -> Option<f64> {
    let span = arg_span(a, key, min);
    match a.number(key, min) {
        Some(v) if ok(v) => Some(v),
        Some(v) => {
            let msg = format!("{key} = {v} of {}: {key} must be {range}", a.label);
            a.error(
                Code::BadArgument,
                span.unwrap_or(a.stmt.keyword_span.clone()),
                msg,
            );
            None
        }
        None if span.is_some() => None,
        None => {
            if default.is_none() {
                a.missing(&format!("{key} = value"));
            }
            default
        }
    }
}

/// The span of argument `key`'s value, if it is written.
fn arg_span(a: &Args, key: &str, min: usize) -> Option<Span> {
    a.stmt.arg(key, min).map(|arg| arg.span.clone())
}

/// IMPACT or POISSON with their parameters (IMPACT when neither flag is written).
fn normal_law(a: &mut Args) -> Option<NormalLaw> {
    let poisson = a.choice(&[("IMPACT", 3), ("POISSON", 3)]) == Some(1);
    if poisson {
        let penalty = checked(a, "PENALTY", 3, None, |v| v > 0.0, "> 0");
        let restitution = checked(
            a,
            "RESTITUTION_COEFFICIENT",
            3,
            None,
            |v| (0.0..=1.0).contains(&v),
            "between 0 and 1",
        );
        return Some(NormalLaw::Poisson {
            penalty: penalty?,
            restitution: restitution?,
        });
    }
    let stiffness = checked(a, "STIFFNESS", 3, None, |v| v > 0.0, "> 0");
    let damping = checked(a, "DAMPING", 3, None, |v| v >= 0.0, ">= 0");
    let dmax = checked(a, "DMAX", 2, None, |v| v > 0.0, "> 0");
    let exponent = checked(a, "EXPONENT", 3, None, |v| v >= 1.0, ">= 1");
    Some(NormalLaw::Impact {
        stiffness: stiffness?,
        damping: damping?,
        dmax: dmax?,
        exponent: exponent?,
    })
}

/// COULOMB_FRICTION = ON | OFF | DYNAMICS_ONLY with its coefficients (OFF when absent).
fn friction(a: &mut Args) -> Option<Friction> {
    let mode = match a.word("COULOMB_FRICTION", 3) {
        None => FrictionMode::Off,
        Some((w, span)) => match w.to_ascii_uppercase().as_str() {
            "ON" => FrictionMode::On,
            "OFF" => FrictionMode::Off,
            "DYNAMICS_ONLY" | "DYNAMICSONLY" | "DYNAMIC_ONLY" => FrictionMode::DynamicsOnly,
            _ => {
                let msg = format!(
                    "COULOMB_FRICTION = {w} of {}: expected ON, OFF or DYNAMICS_ONLY",
                    a.label
                );
                a.error(Code::BadArgument, span, msg);
                return None;
            }
        },
    };
    let on = mode != FrictionMode::Off;
    let required = |v: f64| (!on).then_some(v);
    let mu_static = checked(a, "MU_STATIC", 4, required(0.0), |v| v >= 0.0, ">= 0");
    let mu_dynamic = checked(a, "MU_DYNAMIC", 4, required(0.0), |v| v >= 0.0, ">= 0");
    let vs = checked(
        a,
        "STICTION_TRANSITION_VELOCITY",
        10,
        Some(STICTION_VELOCITY),
        |v| v > 0.0,
        "> 0",
    );
    let vd = checked(
        a,
        "FRICTION_TRANSITION_VELOCITY",
        10,
        Some(FRICTION_VELOCITY),
        |v| v > 0.0,
        "> 0",
    );
    let (mu_static, mu_dynamic, vs, vd) = (mu_static?, mu_dynamic?, vs?, vd?);
    if on && vd <= vs {
        let span =
            arg_span(a, "FRICTION_TRANSITION_VELOCITY", 10).unwrap_or(a.stmt.keyword_span.clone());
        let msg = format!(
            "FRICTION_TRANSITION_VELOCITY ({vd}) of {} must exceed STICTION_TRANSITION_VELOCITY ({vs})",
            a.label
        );
        a.error(Code::BadArgument, span, msg);
        return None;
    }
    Some(Friction {
        mode,
        mu_static,
        mu_dynamic,
        stiction_velocity: vs,
        friction_velocity: vd,
    })
}
