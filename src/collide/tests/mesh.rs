//! Meshes (EXTERNAL): one incident per connected region.

use super::{model, near, world_with, FLOOR};
use crate::collide::{Space, TriMesh};
use crate::vocab::math::Vec3;
use std::collections::HashMap;

/// The outline of a U in its x-z plane: legs x ∈ [0, 1] and [2, 3] from z = 0 up,
/// joined above z = 2 up to z = 3.
const U: [[f64; 2]; 8] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [1.0, 2.0],
    [2.0, 2.0],
    [2.0, 0.0],
    [3.0, 0.0],
    [3.0, 3.0],
    [0.0, 3.0],
];

/// The U extruded along y over [−0.5, 0.5]: a closed, non-convex solid.
fn u_mesh() -> TriMesh {
    let mut vertices = Vec::new();
    for y in [-0.5, 0.5] {
        vertices.extend(U.iter().map(|p| Vec3::new(p[0], y, p[1])));
    }
    // The U's face split into triangles (their areas add up to the U's 7).
    let cap: [[u32; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 7],
        [7, 2, 3],
        [3, 6, 7],
        [3, 4, 5],
        [3, 5, 6],
    ];
    let mut triangles = Vec::new();
    for t in cap {
        triangles.push([t[0], t[2], t[1]]);
        triangles.push(t.map(|v| v + 8));
    }
    for k in 0..8u32 {
        let next = (k + 1) % 8;
        triangles.push([k, next, next + 8]);
        triangles.push([k, next + 8, k + 8]);
    }
    TriMesh {
        vertices,
        triangles,
        stand_in: false,
    }
}

#[test]
fn a_u_standing_on_a_box_on_both_legs_is_two_incidents_one_under_each_leg() {
    let d = 0.01;
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG=-1.5,0,{}\nMARKER/21, PART=2\n\
         GRAPHICS/2, EXTERNAL, RM=21, FILE=u.stl",
        -d
    ));
    let meshes = HashMap::from([(2, u_mesh())]);
    let w = world_with(&m, &[2, 100], &[(0, 1)], Space::Three, &meshes);
    let mut found = super::incidents(&w, 0);
    assert_eq!(found.len(), 2, "{found:?}");
    found.sort_by(|a, b| a.point.x.total_cmp(&b.point.x));
    // Each leg's foot, 1 × 1, sunk by d: pushed up at the middle of the foot.
    for (c, leg_x) in found.iter().zip([-1.0, 1.0]) {
        assert!((c.depth - d).abs() < 1e-9, "{c:?}");
        near(c.normal, Vec3::z(), 1e-9);
        near(c.point, Vec3::new(leg_x, 0.0, -d / 2.0), 1e-9);
    }
    assert!((w.separation(0) + d).abs() < 1e-9, "{}", w.separation(0));
}

#[test]
fn a_u_lifted_off_the_box_is_apart_by_the_gap() {
    let gap = 0.25;
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG=-1.5,0,{gap}\nMARKER/21, PART=2\n\
         GRAPHICS/2, EXTERNAL, RM=21, FILE=u.stl"
    ));
    let meshes = HashMap::from([(2, u_mesh())]);
    let w = world_with(&m, &[2, 100], &[(0, 1)], Space::Three, &meshes);
    assert!(super::incidents(&w, 0).is_empty());
    assert!((w.separation(0) - gap).abs() < 1e-9, "{}", w.separation(0));
}

#[test]
fn a_u_over_a_u_is_apart_by_the_gap_between_their_legs() {
    // A second U upside down on ground, its legs' ends at z = 0 under the first's legs,
    // which end at z = gap: mesh against mesh, which parry measures on the surfaces.
    let gap = 0.05;
    let m = model(&format!(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=-1.5,0,{gap}\nMARKER/21, PART=2\n\
         GRAPHICS/2, EXTERNAL, RM=21, FILE=u.stl\n\
         MARKER/31, PART=1, REULER=0,180D,0, QP=-1.5,0,0\n\
         GRAPHICS/3, EXTERNAL, RM=31, FILE=u.stl"
    ));
    let meshes = HashMap::from([(2, u_mesh()), (3, u_mesh())]);
    let w = world_with(&m, &[2, 3], &[(0, 1)], Space::Three, &meshes);
    assert!(super::incidents(&w, 0).is_empty());
    assert!((w.separation(0) - gap).abs() < 1e-9, "{}", w.separation(0));
}

#[test]
fn a_u_sunk_into_a_u_is_two_incidents_as_deep_as_the_legs_overlap() {
    // The U over U above with its legs pushed d into the lower U's: two closed
    // non-convex meshes, queried in their convex pieces. Each pair of legs overlaps
    // d deep over a 1 × 1 foot: two regions, pushed apart along z.
    let d = 0.02;
    let m = model(&format!(
        "PART/2, MASS=1, CM=21, IP=1,1,1, QG=-1.5,0,{}\nMARKER/21, PART=2\n\
         GRAPHICS/2, EXTERNAL, RM=21, FILE=u.stl\n\
         MARKER/31, PART=1, REULER=0,180D,0, QP=-1.5,0,0\n\
         GRAPHICS/3, EXTERNAL, RM=31, FILE=u.stl",
        -d
    ));
    let meshes = HashMap::from([(2, u_mesh()), (3, u_mesh())]);
    let w = world_with(&m, &[2, 3], &[(0, 1)], Space::Three, &meshes);
    let mut found = super::incidents(&w, 0);
    assert_eq!(found.len(), 2, "{found:?}");
    found.sort_by(|a, b| a.point.x.total_cmp(&b.point.x));
    for (c, leg_x) in found.iter().zip([-1.0, 1.0]) {
        assert!((c.depth - d).abs() < 1e-9, "{c:?}");
        near(c.normal, Vec3::z(), 1e-9);
        near(c.point, Vec3::new(leg_x, 0.0, -d / 2.0), 1e-9);
    }
    assert!((w.separation(0) + d).abs() < 1e-9, "{}", w.separation(0));
}

#[test]
fn a_closed_convex_mesh_is_held_as_its_hull_and_overlaps_as_deep_as_it_goes() {
    // A unit cube mesh sunk 0.3 into a box: its hull measures the whole depth (a
    // surface alone would see the cube's bottom face inside the box and no crossing).
    let mut vertices = Vec::new();
    for k in 0..8 {
        let bit = |b: usize| f64::from((k >> b) & 1);
        vertices.push(Vec3::new(bit(0) - 0.5, bit(1) - 0.5, bit(2)));
    }
    let triangles = vec![
        [0, 2, 6],
        [0, 6, 4],
        [1, 5, 7],
        [1, 7, 3],
        [0, 4, 5],
        [0, 5, 1],
        [2, 3, 7],
        [2, 7, 6],
        [0, 1, 3],
        [0, 3, 2],
        [4, 6, 7],
        [4, 7, 5],
    ];
    let cube = TriMesh {
        vertices,
        triangles,
        stand_in: false,
    };
    let m = model(&format!(
        "{FLOOR}\nPART/2, MASS=1, CM=21, IP=1,1,1, QG=0,0,-0.3\nMARKER/21, PART=2\n\
         GRAPHICS/2, EXTERNAL, RM=21, FILE=cube.stl"
    ));
    let meshes = HashMap::from([(2, cube)]);
    let w = world_with(&m, &[2, 100], &[(0, 1)], Space::Three, &meshes);
    let found = super::incidents(&w, 0);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!((found[0].depth - 0.3).abs() < 1e-9, "{found:?}");
    near(found[0].normal, Vec3::z(), 1e-9);
    near(found[0].point, Vec3::new(0.0, 0.0, -0.15), 1e-9);
}
