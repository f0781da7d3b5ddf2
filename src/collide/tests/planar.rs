//! The planar world (parry2d on the sections by the plane) gives the incidents and the
//! separation of the 3D world, for every kind of simple section.

use super::{incidents, model, near, world, world_with, FLOOR};
use crate::collide::Space;
use crate::vocab::math::Vec3;
use std::collections::HashMap;

/// The plane y = 0, in x and z.
fn plane() -> Space {
    Space::Plane {
        origin: Vec3::zeros(),
        a: Vec3::x(),
        b: Vec3::z(),
    }
}

/// The 3D and planar answers for GRAPHICS/2 against the floor, the planar world's
/// pair queried in the plane.
#[track_caller]
fn agree(body: &str, incidents_expected: usize) {
    agree_within(body, incidents_expected, 1e-7);
}

/// [`agree`], the points within `point_tol`: a solid that 3D holds as a hull of a
/// tessellation touches on a facet, whose centre is off the exact point by up to half
/// a facet's width.
#[track_caller]
fn agree_within(body: &str, incidents_expected: usize, point_tol: f64) {
    let m = model(&format!("{FLOOR}\n{body}"));
    let three = world(&m, &[2, 100], &[(0, 1)], Space::Three);
    let two = world(&m, &[2, 100], &[(0, 1)], plane());
    assert!(two.in_plane(0), "{body}: not queried in the plane");
    assert!(!three.in_plane(0));
    let (a, b) = (incidents(&three, 0), incidents(&two, 0));
    assert_eq!(a.len(), incidents_expected, "{body}: {a:?}");
    assert_eq!(b.len(), a.len(), "{body}: {a:?} vs {b:?}");
    for (x, y) in a.iter().zip(&b) {
        assert!((x.depth - y.depth).abs() < 1e-9, "{body}: {x:?} vs {y:?}");
        near(x.normal, y.normal, 1e-9);
        near(x.point, y.point, point_tol);
    }
    let (s3, s2) = (three.separation(0), two.separation(0));
    assert!((s3 - s2).abs() < 1e-9, "{body}: {s3} vs {s2}");
}

#[test]
fn a_sphere_is_a_circle() {
    let ball = |h: f64| {
        format!(
            "PART/2, MASS=1, CM=21, IP=1,1,1, QG=0.3,0,{h}\nMARKER/21, PART=2\n\
             GRAPHICS/2, ELLIPSOID, CM=21, XSCALE=1, YSCALE=1, ZSCALE=1"
        )
    };
    agree(&ball(0.45), 1);
    agree(&ball(0.7), 0);
}

#[test]
fn a_wheel_normal_to_the_plane_is_a_circle() {
    // REULER 0, 90D, 0: the CM marker's z is global −y; the wheel spans y ∈ [−0.1, 0.1].
    agree(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=-0.5,0.1,0.28, REULER=0,90D,0\n\
         MARKER/21, PART=2\nGRAPHICS/2, CYLINDER, CM=21, LENGTH=0.2, RADIUS=0.3",
        1,
    );
}

#[test]
fn a_cylinder_lying_in_the_plane_is_a_rectangle() {
    agree(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=-0.3,0,0.2, REULER=90D,90D,0D\n\
         MARKER/21, PART=2\nGRAPHICS/2, CYLINDER, CM=21, LENGTH=1, RADIUS=0.25",
        1,
    );
}

#[test]
fn a_frustum_lying_in_the_plane_is_a_trapezoid() {
    // Radii 0.3 at CM and 0.1 at the other end, along x: it touches at the wide end.
    // In 3D it is a hull of 64-gons: its facets are 2·0.3·sin(π/64) ≈ 0.029 wide.
    agree_within(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=-0.3,0,0.28, REULER=90D,90D,0D\n\
         MARKER/21, PART=2\nGRAPHICS/2, FRUSTUM, CM=21, LENGTH=1, BOTTOM=0.3, TOP=0.1",
        1,
        0.015,
    );
}

#[test]
fn a_box_turned_about_the_plane_normal_is_a_rectangle() {
    // Rz(90°)·Rx(30°)·Rz(−90°) turns 30° about y; the unit cube's lowest edge, along
    // y, sinks below z = 0.
    agree(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=0.2,0,0.6, REULER=90D,30D,-90D\n\
         MARKER/21, PART=2\nMARKER/22, PART=2, QP=-0.5,-0.5,-0.5\n\
         GRAPHICS/2, BOX, CORNER=22, X=1, Y=1, Z=1",
        1,
    );
}

#[test]
fn an_ellipsoid_with_an_axis_normal_to_the_plane_is_an_ellipse() {
    // Semi-axes 0.6 along x, 0.2 along y, 0.3 along z: its lowest point is 0.3 below
    // the centre, an ellipse's too; the polygon for the ellipse and the hull for the
    // ellipsoid both have a vertex there. In 3D the hull's facets near the bottom are
    // up to 0.6·π/32 ≈ 0.06 long along x.
    agree_within(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=0.1,0,0.25\nMARKER/21, PART=2\n\
         GRAPHICS/2, ELLIPSOID, CM=21, XSCALE=1.2, YSCALE=0.4, ZSCALE=0.6",
        1,
        0.06,
    );
}

#[test]
fn a_mesh_or_a_tilted_box_is_queried_in_3d() {
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG=0,0,0.6, REULER=0,0.3,0.2\n\
         MARKER/21, PART=2\nGRAPHICS/2, BOX, CORNER=21, X=1, Y=1, Z=1\n\
         MARKER/31, PART=1\nGRAPHICS/3, EXTERNAL, RM=31, FILE=t.stl"
    ));
    let tetra = crate::collide::TriMesh {
        vertices: vec![Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::z()],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        stand_in: false,
    };
    let meshes = HashMap::from([(3, tetra)]);
    let w = world_with(&m, &[2, 100, 3], &[(0, 1), (2, 1)], plane(), &meshes);
    assert!(!w.in_plane(0));
    assert!(!w.in_plane(1));
}
