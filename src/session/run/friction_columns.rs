//! The run table's columns of each joint FRICTION (issue 40 §2): `FRICTION<id>.F` the
//! friction force's magnitude, `FRICTION<id>.T` its torque's (about I), and
//! `FRICTION<id>.V` the slip speed the friction law reads (at the pin or ball radius for
//! a rotation), written as expressions of the model's scope.

use crate::model::friction::Friction;
use crate::model::Model;
use crate::vocab::elements::JointType;

/// The (header, expression) of every friction's columns, in model order.
pub(super) fn columns(model: &Model) -> Vec<(String, String)> {
    model.frictions.iter().flat_map(|f| of(model, f)).collect()
}

fn of(model: &Model, f: &Friction) -> Vec<(String, String)> {
    let id = f.el.id;
    let mut out = vec![
        (
            format!("FRICTION{id}.F"),
            format!("FRICTION({id}, 0, 1, 0)"),
        ),
        (
            format!("FRICTION{id}.T"),
            format!("FRICTION({id}, 0, 5, 0)"),
        ),
    ];
    let Some(joint) = model.joints.iter().find(|j| j.el.id == f.joint) else {
        return out;
    };
    let (i, j) = (joint.i, joint.j);
    let spin = format!("WZ({i}, {j}, {j})");
    let slide = format!("VZ({i}, {j}, {j}, {j})");
    let rp = f.pin_radius;
    let slip = match joint.kind {
        JointType::Revolute => format!("{rp}*ABS({spin})"),
        JointType::Translational => format!("ABS({slide})"),
        JointType::Cylindrical => format!("SQRT({slide}**2 + ({rp}*{spin})**2)"),
        JointType::Spherical => format!("{}*WM({i}, {j})", f.ball_radius),
        _ => format!("{rp}*WM({i}, {j})"),
    };
    out.push((format!("FRICTION{id}.V"), slip));
    out
}
