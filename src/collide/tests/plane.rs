//! Adams' PLANE as a contact geometry: the rectangle in RM's x-y plane with the solid
//! behind it (−z), pushing along RM's +z; nothing beside the rectangle.

use super::{incidents, model, near, world};
use crate::collide::{Geometry, Space};
use crate::vocab::math::Vec3;
use std::collections::HashMap;

/// A ball of radius r on PART/2 centred at (x, y, z), and a PLANE on ground at
/// MARKER/100 (at `at`, turned by `reuler`) over x ∈ [−1, 3], y ∈ [−2, 2].
fn scene(centre: [f64; 3], r: f64, at: [f64; 3], reuler: &str) -> String {
    let [x, y, z] = centre;
    let [px, py, pz] = at;
    format!(
        "MARKER/100, PART=1, QP={px},{py},{pz}, REULER={reuler}\n\
         GRAPHICS/100, PLANE, RM=100, XMIN=-1, XMAX=3, YMIN=-2, YMAX=2\n\
         PART/2, MASS=1, CM=21, IP=1,1,1, QG={x},{y},{z}\nMARKER/21, PART=2\n\
         GRAPHICS/2, ELLIPSOID, CM=21, XSCALE={d}, YSCALE={d}, ZSCALE={d}",
        d = 2.0 * r
    )
}

#[test]
fn a_ball_sunk_into_a_plane_is_pushed_out_along_its_normal() {
    let (r, h) = (0.5, 0.4);
    let m = model(&scene([0.5, 0.3, 1.0 + h], r, [0.0, 0.0, 1.0], "0,0,0"));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!((found[0].depth - (r - h)).abs() < 1e-9, "{found:?}");
    near(found[0].normal, Vec3::z(), 1e-9);
    // Midway between the ball's lowest point and the plane, under its centre.
    near(
        found[0].point,
        Vec3::new(0.5, 0.3, 1.0 + (h - r) / 2.0),
        1e-9,
    );
}

#[test]
fn a_tilted_plane_pushes_along_its_markers_z() {
    // REULER 0, 90D, 0 turns RM's z to global −y... (a quarter turn about x: z → −y).
    // The ball sits on the −y side of the plane through the origin, sunk by 0.1.
    let (r, h) = (0.5, 0.4);
    let m = model(&scene([0.0, -h, 1.0], r, [0.0, 0.0, 0.0], "0,90D,0"));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!((found[0].depth - (r - h)).abs() < 1e-9, "{found:?}");
    near(found[0].normal, -Vec3::y(), 1e-9);
}

#[test]
fn nothing_beside_the_rectangle_touches_it() {
    // Level with the plane but past XMAX = 3 by more than the radius.
    let m = model(&scene([3.6, 0.0, 0.2], 0.5, [0.0, 0.0, 0.0], "0,0,0"));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    assert!(incidents(&w, 0).is_empty());
    assert!(w.separation(0) > 0.0);
}

#[test]
fn a_plane_needs_its_minimum_below_its_maximum() {
    let r = crate::model::read_model(
        "t\nPART/1, GROUND\nMARKER/1, PART=1\n\
         GRAPHICS/5, PLANE, RM=1, XMIN=1, XMAX=1, YMIN=-1, YMAX=1\nEND\n",
    );
    let e = (r.diagnostics.iter())
        .find(|d| d.is_error())
        .expect("an error");
    assert_eq!(e.code.as_str(), "E0605");
    assert!(e.message.contains("XMAX"), "{}", e.message);
    assert!(Geometry::of(&r.model, 5, &HashMap::new()).is_err());
}
