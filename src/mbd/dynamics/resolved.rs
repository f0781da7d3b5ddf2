//! The kept rows' primitive equations resolved once, with the Jacobian slots of their
//! two parts ([`ResolvedRow`]), so the rows are evaluated without looking anything up;
//! and the point coincidences whose rows are all kept frozen along J's axes as they are
//! at the start ([`freeze_point_rows`], why: [`super::stiffness`]).

use crate::mbd::constraints::{PointAxis, Primitive};
use crate::mbd::rows::Row;
use crate::mbd::system::System;
use crate::vocab::math::Vec3;
use std::collections::HashMap;

/// A kept row's primitive with the Jacobian slots of its two parts.
pub(super) type ResolvedRow = Option<(Primitive, [Option<usize>; 2])>;

/// Turns the `Along` rows of every fully kept point coincidence into `Fixed` rows along
/// J's axes as they are now.
pub(super) fn freeze_point_rows(sys: &System, rows: &[(usize, usize)], prims: &mut [ResolvedRow]) {
    let full = sys.dim.axes();
    // (element, I, J) → the kept rows and their distinct directions.
    let mut groups: HashMap<_, (Vec<usize>, Vec<Vec3>)> = HashMap::new();
    for (r, &(e, q)) in rows.iter().enumerate() {
        if let (Row::Along { i, j, dir, .. }, Some((Primitive::Along(_), _))) =
            (&sys.elements[e].eqs[q].row, &prims[r])
        {
            let (members, dirs) = groups.entry((e, *i, *j)).or_default();
            members.push(r);
            if !dirs.contains(dir) {
                dirs.push(*dir);
            }
        }
    }
    for (members, dirs) in groups.into_values() {
        if dirs.len() != full || members.len() != full {
            continue;
        }
        for r in members {
            if let Some((Primitive::Along(p), slots)) = prims[r] {
                let axis = sys.part(p.pj).rotation() * p.axis;
                prims[r] = Some((Primitive::Fixed(PointAxis { axis, ..p }), slots));
            }
        }
    }
}
