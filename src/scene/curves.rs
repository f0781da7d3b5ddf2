//! CIRCLE and ARC as lines in their CM marker's x-y plane, and OUTLINE's polylines:
//! a circle is a closed loop of SEG chords, an arc an open strip from the x axis through
//! RANGLE about z.

use super::tessellate::{polyline, Builder};
use super::Mesh;
use crate::vocab::math::Vec3;
use std::f64::consts::TAU;

/// Chords of a circle or arc when SEG is not given (chosen).
pub const DEFAULT_SEG: u32 = 32;

/// The circle of `radius` about the origin in the x-y plane, `seg` chords.
pub fn circle(radius: f64, seg: u32, color: [f32; 4]) -> Option<Mesh> {
    let points: Vec<Vec3> = (0..seg)
        .map(|k| on_circle(radius, TAU * f64::from(k) / f64::from(seg)))
        .collect();
    polyline(&points, true, color)
}

/// The arc of `radius` from +x through `sweep` radians about +z (clamped to a full
/// turn; negative sweeps turn the other way), `seg` chords.
pub fn arc(radius: f64, seg: u32, sweep: f64, color: [f32; 4]) -> Option<Mesh> {
    let sweep = sweep.clamp(-TAU, TAU);
    let points: Vec<Vec3> = (0..=seg)
        .map(|k| on_circle(radius, sweep * f64::from(k) / f64::from(seg)))
        .collect();
    polyline(&points, false, color)
}

fn on_circle(radius: f64, angle: f64) -> Vec3 {
    Vec3::new(radius * angle.cos(), radius * angle.sin(), 0.0)
}

/// Separate segments `(a, b)` as one mesh of lines.
pub fn segments(pairs: &[(Vec3, Vec3)], color: [f32; 4]) -> Option<Mesh> {
    let mut b = Builder::default();
    for &(p, q) in pairs {
        b.segment(p, q);
    }
    (!b.is_empty()).then(|| b.lines(color))
}

/// The unit segment (0,0,0)–(0,0,1) a stretching line is drawn with.
pub fn unit_line(color: [f32; 4]) -> Mesh {
    segments(&[(Vec3::zeros(), Vec3::z())], color).expect("a finite segment")
}
