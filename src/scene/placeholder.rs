//! What stands in for an EXTERNAL graphic without a mesh: the uniform solid box with its
//! part's mass and principal moments (I₁ = m(b² + c²)/12, so a² = 6(I₂ + I₃ − I₁)/m),
//! centred at the CM along the principal axes. A part without mass or with a degenerate
//! inertia gets a cube of side extent/20, at its CM, once the extent is known.

use super::canvas::{pose, Canvas};
use super::mass::principal;
use super::solids::centred_cuboid;
use super::{Pose, Role};
use crate::vocab::math::Vec3;

/// The smallest side of a box or semi-axis of an ellipsoid, as a fraction of its
/// largest: a rod's or plate's zero thickness is drawn thin, not invisible.
pub const THINNEST: f64 = 0.01;

/// A box placeholder for EXTERNAL `name` on the part at `part`; `false` when the part's
/// inertia gives no box (the caller draws a cube once the extent is known).
pub fn inertia_box(c: &mut Canvas, part: usize, name: String, view_name: Option<String>) -> bool {
    let Some((cm, axes, sides)) =
        (c.model.parts.get(part)).and_then(|p| inertia_box_of(c.model, p))
    else {
        return false;
    };
    let h = Vec3::from(sides) / 2.0;
    let mesh = centred_cuboid(-h, h).triangles(c.color(part));
    c.rigid(
        name,
        view_name,
        part,
        pose(cm, &axes),
        mesh,
        Role::Placeholder,
    );
    true
}

/// The placeholder box of `part`: its centre (the CM) and axes (principal, columns) in
/// BCS coordinates, and its sides (none thinner than 1 % of the longest); None
/// when the part's inertia gives no box. The contacts of a run stand the same box in
/// for an EXTERNAL geometry without a mesh.
pub fn inertia_box_of(
    model: &crate::model::Model,
    part: &crate::model::elements::Part,
) -> Option<(Vec3, crate::vocab::math::Mat3, [f64; 3])> {
    let p = principal(model, part);
    Some((p.cm, p.axes, thick(p.box_sides()?)))
}

/// A cube of side `side` at the CM of the part at `part` (BCS axes).
pub fn cube(c: &mut Canvas, part: usize, side: f64, name: String, view_name: Option<String>) {
    let cm = (c.model.parts.get(part))
        .map(|p| principal(c.model, p).cm)
        .unwrap_or_default();
    let h = Vec3::repeat(side / 2.0);
    let mesh = centred_cuboid(-h, h).triangles(c.color(part));
    let local = Pose {
        translation: [cm.x, cm.y, cm.z],
        ..Pose::IDENTITY
    };
    c.rigid(name, view_name, part, local, mesh, Role::Placeholder);
}

/// `sizes` with none below [`THINNEST`] of the largest.
pub fn thick(sizes: [f64; 3]) -> [f64; 3] {
    let largest = sizes.iter().copied().fold(0.0, f64::max);
    sizes.map(|s| s.max(THINNEST * largest))
}
