//! Convex solids on a box: depth, normal and point of the one incident each scene has,
//! and the separation of shapes apart.

use super::{incidents, model, near, world, FLOOR};
use crate::collide::Space;
use crate::vocab::math::Vec3;

/// A ball of radius r (ELLIPSOID of equal diameters) centred at (x, y, h).
fn ball(x: f64, y: f64, h: f64, r: f64) -> String {
    format!(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG={x},{y},{h}\nMARKER/21, PART=2\n\
         GRAPHICS/2, ELLIPSOID, CM=21, XSCALE={d}, YSCALE={d}, ZSCALE={d}",
        d = 2.0 * r
    )
}

#[test]
fn a_sphere_sunk_into_a_box_top_gives_depth_r_minus_h_under_its_centre() {
    let (x, y, h, r) = (0.2, 0.3, 0.4, 0.5);
    let m = model(&format!("{FLOOR}\n{}", ball(x, y, h, r)));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    let c = found[0];
    assert!((c.depth - (r - h)).abs() < 1e-9, "{c:?}");
    near(c.normal, Vec3::z(), 1e-9);
    // Midway between the sphere's lowest point (z = h − r) and the box top (z = 0).
    near(c.point, Vec3::new(x, y, (h - r) / 2.0), 1e-9);
    assert!((w.separation(0) + (r - h)).abs() < 1e-9);
}

#[test]
fn the_normal_points_from_j_into_i_whichever_is_listed_first() {
    let m = model(&format!("{FLOOR}\n{}", ball(0.0, 0.0, 0.4, 0.5)));
    let w = world(&m, &[2, 100], &[(1, 0)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    // I is the floor now: the force on it pushes down.
    near(found[0].normal, -Vec3::z(), 1e-9);
    assert!((found[0].depth - 0.1).abs() < 1e-9);
}

#[test]
fn two_shapes_apart_have_no_incident_and_the_gap_as_separation() {
    let (h, r) = (0.8, 0.5);
    let m = model(&format!("{FLOOR}\n{}", ball(0.1, -0.2, h, r)));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    assert!(incidents(&w, 0).is_empty());
    assert!(
        (w.separation(0) - (h - r)).abs() < 1e-9,
        "{}",
        w.separation(0)
    );
}

#[test]
fn a_cylinder_lying_on_a_box_is_one_incident_at_the_middle_of_its_line() {
    // REULER 90D, 90D, 0: the CM marker's z is global x, so the cylinder lies along x
    // from x0 for LENGTH; its axis at height h.
    let (x0, len, y, h, r) = (-0.3, 1.0, 0.25, 0.2, 0.25);
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG={x0},{y},{h}, REULER=90D,90D,0D\n\
         MARKER/21, PART=2\nGRAPHICS/2, CYLINDER, CM=21, LENGTH={len}, RADIUS={r}"
    ));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    let c = found[0];
    assert!((c.depth - (r - h)).abs() < 1e-9, "{c:?}");
    near(c.normal, Vec3::z(), 1e-9);
    // parry finds the cylinder's lowest line to 5·10⁻⁹ across it (its support
    // direction comes from an iteration): 10⁻⁷ is well inside what a force needs.
    near(c.point, Vec3::new(x0 + len / 2.0, y, (h - r) / 2.0), 1e-7);
}

#[test]
fn a_cylinder_standing_on_its_end_pushes_at_the_centre_of_its_base() {
    let (x, y, d, r) = (0.5, -0.4, 0.03, 0.3);
    // CM at the bottom centre, LENGTH up; sunk by d.
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG={x},{y},{}\nMARKER/21, PART=2\n\
         GRAPHICS/2, CYLINDER, CM=21, LENGTH=0.8, RADIUS={r}",
        -d
    ));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!((found[0].depth - d).abs() < 1e-9, "{found:?}");
    near(found[0].normal, Vec3::z(), 1e-9);
    near(found[0].point, Vec3::new(x, y, -d / 2.0), 1e-9);
}

#[test]
fn a_box_standing_on_a_corner_sinks_by_its_half_diagonal_minus_its_height() {
    // A unit cube on part 2 whose diagonal (1,1,1) points down: REULER's third row is
    // (sin θ sin φ, sin θ cos φ, cos θ) = −(1,1,1)/√3.
    let theta = (-1.0 / 3f64.sqrt()).acos();
    let (x, y, c) = (0.1, 0.2, 0.8);
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG={x},{y},{c}, REULER=0,{theta},{}\n\
         MARKER/21, PART=2\nMARKER/22, PART=2, QP=-0.5,-0.5,-0.5\n\
         GRAPHICS/2, BOX, CORNER=22, X=1, Y=1, Z=1",
        225f64.to_radians()
    ));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    let depth = 3f64.sqrt() / 2.0 - c;
    assert!((found[0].depth - depth).abs() < 1e-9, "{found:?}");
    near(found[0].normal, Vec3::z(), 1e-9);
    near(found[0].point, Vec3::new(x, y, -depth / 2.0), 1e-9);
    assert!((w.separation(0) + depth).abs() < 1e-9);
}

#[test]
fn a_box_flat_on_a_box_pushes_at_the_centre_of_the_overlap() {
    // A 1 × 1 box over the floor's edge at x = 2: only x ∈ [1.6, 2] overlaps.
    let (x0, d) = (1.6, 0.02);
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG={x0},0,{}\nMARKER/21, PART=2\n\
         GRAPHICS/2, BOX, CORNER=21, X=1, Y=1, Z=1",
        -d
    ));
    let w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let found = incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!((found[0].depth - d).abs() < 1e-9, "{found:?}");
    near(found[0].normal, Vec3::z(), 1e-9);
    near(
        found[0].point,
        Vec3::new((x0 + 2.0) / 2.0, 0.5, -d / 2.0),
        1e-9,
    );
}

#[test]
fn a_pose_with_a_nan_leaves_the_geometry_where_it_was() {
    use crate::collide::Pose;
    let m = model(&format!("{FLOOR}\n{}", ball(0.0, 0.0, 0.4, 0.5)));
    let mut w = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let before = incidents(&w, 0);
    w.update(&|id| {
        let p = m.part(id).unwrap();
        Pose {
            r: if id == 2 {
                Vec3::new(f64::NAN, 0.0, 0.0)
            } else {
                p.position
            },
            rot: p.orientation,
        }
    });
    let mut found = Vec::new();
    w.candidates(&mut found);
    assert_eq!(found, vec![0]);
    assert_eq!(incidents(&w, 0), before);
}
