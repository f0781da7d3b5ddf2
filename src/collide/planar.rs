//! Contact in the plane of a planar scene (`Space::Plane`): each geometry's section by
//! the plane as a 2D shape for parry2d, where the section is a simple one — a ball, a
//! cylinder, frustum or ellipsoid whose axis is normal to the plane (a circle, an
//! ellipse), a box with an axis normal to the plane (a rectangle), a cylinder or frustum
//! whose axis lies in the plane (a rectangle, a trapezoid). A pair of which one section
//! is none of those (a mesh, a tilted box) is queried in 3D. The sections are taken at
//! the first update, from where the parts are then: planar motion keeps them.

use super::geometry::Form;
use super::regions::Touch;
use super::{Geometry, Pose};
use crate::vocab::math::Vec3;
use parry2d_f64::glamx::DVec2;
pub use parry2d_f64::math::Pose as Pose2;
use parry2d_f64::query::{
    ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher, QueryDispatcher,
};
use parry2d_f64::shape::SharedShape;
use std::f64::consts::PI;

/// Points of the polygon standing for an ellipse's section (inscribed: its sides sit
/// inside the ellipse by at most a·(1 − cos(π/128)) ≈ 3·10⁻⁴·a).
const ELLIPSE_SEGMENTS: usize = 128;
/// How close to parallel (1 − |cos|) an axis must be to count as normal to the plane.
const PARALLEL: f64 = 1e-9;

/// The plane of a planar world.
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    /// A point of it.
    pub origin: Vec3,
    /// Its first in-plane axis (2D x).
    pub a: Vec3,
    /// Its second in-plane axis (2D y).
    pub b: Vec3,
}

impl Plane {
    /// The unit normal a × b.
    fn normal(&self) -> Vec3 {
        self.a.cross(&self.b)
    }

    /// A point of space projected into the plane's 2D coordinates.
    pub fn flatten(&self, p: Vec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(&self.a), d.dot(&self.b))
    }

    /// A 2D point of the plane in space.
    pub fn lift(&self, p: DVec2) -> Vec3 {
        self.origin + self.a * p.x + self.b * p.y
    }

    /// A 2D direction of the plane in space.
    pub fn lift_direction(&self, v: DVec2) -> Vec3 {
        self.a * v.x + self.b * v.y
    }
}

/// A geometry's section by the plane: its 2D shape, centred at the projection of the
/// geometry's frame origin, with its x along the frame axis `axis`.
#[derive(Clone)]
pub struct Section {
    /// The 2D shape.
    pub shape: SharedShape,
    /// The column of the geometry's frame the shape's x follows.
    axis: usize,
}

impl Section {
    /// The section of `g` placed at `frame` (its frame, global), or `None` when it is
    /// not a simple shape.
    pub fn of(g: &Geometry, frame: &Pose, plane: &Plane) -> Option<Section> {
        let k = plane.normal();
        let offset = (frame.r - plane.origin).dot(&k);
        let normal_axis = (0..3).find(|&c| 1.0 - frame.rot.column(c).dot(&k).abs() < PARALLEL);
        let in_plane = |c: usize| frame.rot.column(c).dot(&k).abs() < PARALLEL;
        match g.form {
            Form::Ellipsoid { semi } if semi[0] == semi[1] && semi[1] == semi[2] => {
                let r = chord(semi[0], offset)?;
                Some(Section {
                    shape: SharedShape::ball(r),
                    axis: 0,
                })
            }
            Form::Ellipsoid { semi } => {
                let n = normal_axis?;
                let scale = chord(1.0, offset / semi[n])?;
                let (u, v) = ((n + 1) % 3, (n + 2) % 3);
                let points: Vec<DVec2> = (0..ELLIPSE_SEGMENTS)
                    .map(|s| {
                        let (sn, cs) = (2.0 * PI * s as f64 / ELLIPSE_SEGMENTS as f64).sin_cos();
                        DVec2::new(semi[u] * scale * cs, semi[v] * scale * sn)
                    })
                    .collect();
                let shape = SharedShape::convex_hull(&points)?;
                Some(Section { shape, axis: u })
            }
            Form::Box { half } => {
                let n = normal_axis?;
                if offset.abs() >= half[n] {
                    return None;
                }
                let (u, v) = ((n + 1) % 3, (n + 2) % 3);
                Some(Section {
                    shape: SharedShape::cuboid(half[u], half[v]),
                    axis: u,
                })
            }
            Form::Round { below, above, half } => {
                if normal_axis == Some(2) {
                    // Cut across the axis: a circle of the radius at that height.
                    let s = offset * frame.rot.column(2).dot(&k).signum();
                    if s.abs() >= half {
                        return None;
                    }
                    let r = below + (above - below) * (s + half) / (2.0 * half);
                    return (r > 0.0).then(|| Section {
                        shape: SharedShape::ball(r),
                        axis: 0,
                    });
                }
                if !in_plane(2) {
                    return None;
                }
                // Cut along the axis: each end's chord at the plane's offset.
                let (w0, w1) = (chord(below, offset), chord(above, offset));
                let points: Vec<DVec2> = [(-half, w0), (half, w1)]
                    .iter()
                    .flat_map(|&(x, w)| {
                        let w = w.unwrap_or(0.0);
                        [DVec2::new(x, -w), DVec2::new(x, w)]
                    })
                    .collect();
                let shape = if below == above {
                    SharedShape::cuboid(half, w0?)
                } else {
                    SharedShape::convex_hull(&points)?
                };
                Some(Section { shape, axis: 2 })
            }
            Form::Mesh => None,
        }
    }

    /// The section's 2D pose for its geometry's frame at `frame` (global).
    pub fn pose(&self, frame: &Pose, plane: &Plane) -> Pose2 {
        let x = frame.rot.column(self.axis).into_owned();
        Pose2::new(
            plane.flatten(frame.r),
            x.dot(&plane.b).atan2(x.dot(&plane.a)),
        )
    }
}

/// Half the chord of a circle of radius `r` at `offset` from its centre (`None` when
/// the line misses it).
fn chord(r: f64, offset: f64) -> Option<f64> {
    let w2 = r * r - offset * offset;
    (w2 > 0.0).then(|| w2.sqrt())
}

/// The penetrating points of two sections at their 2D poses, lifted to space (normal
/// from the second into the first).
pub fn touches(
    (s1, p1): (&Section, &Pose2),
    (s2, p2): (&Section, &Pose2),
    plane: &Plane,
    noise: f64,
) -> Vec<Touch> {
    let pos12 = p1.inv_mul(p2);
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    let mut workspace = None;
    // Sections are balls, boxes and convex polygons, which all have manifolds.
    let _ = DefaultQueryDispatcher.contact_manifolds(
        &pos12,
        &*s1.shape,
        &*s2.shape,
        0.0,
        &mut manifolds,
        &mut workspace,
    );
    let mut out = Vec::new();
    for (m, manifold) in manifolds.iter().enumerate() {
        let n1 = p1.rotation * manifold.local_n1;
        for c in manifold.points.iter().filter(|c| c.dist < -noise) {
            let at = (p1.transform_point(c.local_p1) + p2.transform_point(c.local_p2)) * 0.5;
            out.push(Touch {
                point: plane.lift(at),
                normal: -plane.lift_direction(n1),
                depth: -c.dist,
                manifold: m,
                triangle_i: None,
                triangle_j: None,
            });
        }
    }
    out
}

/// The distance between two sections (0 when they overlap).
pub fn distance((s1, p1): (&Section, &Pose2), (s2, p2): (&Section, &Pose2)) -> f64 {
    let pos12 = p1.inv_mul(p2);
    DefaultQueryDispatcher
        .distance(&pos12, &*s1.shape, &*s2.shape)
        .map_or(0.0, |d| d.distance)
}
