//! SPDP, a spring-damper drawn between its I and J markers, as meshes along local +z from
//! 0 (I) to 1 (J) that a writer stretches ([`super::Motion::Stretch`]): the spring, a
//! helix of COILS turns of diameter DA, and the damper, a cylinder of diameter DB and
//! height LC at I and one of diameter DC and height LD at J (MotionSolve's Spdp, which
//! mirrors Adams' arguments; see docs/animation.md). Only z is stretched, so the damper
//! heights are drawn as fractions of the I–J distance at the input and grow with it.

use super::solids::frustum;
use super::tessellate::{polyline, positive, Builder};
use super::Mesh;
use crate::vocab::math::Vec3;
use std::f64::consts::TAU;

/// Turns when COILS is not given (chosen).
pub const DEFAULT_COILS: u32 = 10;
/// The most turns drawn (a huge COILS must not exhaust memory).
pub const MAX_COILS: u32 = 1000;
/// Points per turn of the helix.
const PER_TURN: u32 = 16;
/// Sides of the damper cylinders.
const DAMPER_SIDES: u32 = 16;

/// The spring's helix: `coils` turns of diameter `da` from z = 0 to z = 1; none for no
/// turn or no diameter.
pub fn helix(coils: u32, da: f64, color: [f32; 4]) -> Option<Mesh> {
    let coils = coils.min(MAX_COILS);
    if coils == 0 || !positive(da) {
        return None;
    }
    let n = coils * PER_TURN;
    let points: Vec<Vec3> = (0..=n)
        .map(|k| {
            let a = TAU * f64::from(k) / f64::from(PER_TURN);
            let z = f64::from(k) / f64::from(n);
            Vec3::new(da / 2.0 * a.cos(), da / 2.0 * a.sin(), z)
        })
        .collect();
    polyline(&points, false, color)
}

/// The damper's two cylinders, `(diameter, height)` at I (from z = 0 up) and at J (from
/// z = 1 down), heights given as fractions of the I–J distance; none when neither has a
/// positive diameter and height.
pub fn damper(at_i: (f64, f64), at_j: (f64, f64), color: [f32; 4]) -> Option<Mesh> {
    let mut b = Builder::default();
    let usable = |(d, h): (f64, f64)| d > 0.0 && h > 0.0 && d.is_finite() && h.is_finite();
    if usable(at_i) {
        let (d, h) = at_i;
        b.append(
            frustum(h.min(1.0), d / 2.0, d / 2.0, DAMPER_SIDES, TAU),
            Vec3::zeros(),
        );
    }
    if usable(at_j) {
        let (d, h) = at_j;
        let top = frustum(-h.min(1.0), d / 2.0, d / 2.0, DAMPER_SIDES, TAU);
        b.append(top, Vec3::z());
    }
    (!b.is_empty()).then(|| b.triangles(color))
}
