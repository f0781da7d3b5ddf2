//! The unit arrow a FORCE graphic is drawn with: along local +z from 0 to 1, a shaft
//! and a cone for its head. A writer scales z by the force's magnitude (x and y are not
//! scaled), so the thickness is absolute: a fraction of the scene's extent.

use super::solids::frustum;
use super::tessellate::Builder;
use super::Mesh;
use crate::vocab::math::Vec3;
use std::f64::consts::TAU;

/// Where the head starts, as a fraction of the arrow's length.
const HEAD_AT: f64 = 0.8;
/// Sides of the shaft and head.
const SIDES: u32 = 12;

/// The arrow with a shaft of radius `radius` and a head twice as wide.
pub fn arrow(radius: f64, color: [f32; 4]) -> Mesh {
    let mut b = Builder::default();
    b.append(frustum(HEAD_AT, radius, radius, SIDES, TAU), Vec3::zeros());
    b.append(
        frustum(1.0 - HEAD_AT, 2.0 * radius, 0.0, SIDES, TAU),
        Vec3::z() * HEAD_AT,
    );
    b.triangles(color)
}
