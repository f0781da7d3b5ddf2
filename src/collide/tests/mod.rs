//! Tests of the contact geometry: datasets written here, expected values from the
//! geometry of each scene (written in each test), never from what the code printed.

mod broad;
mod convex;
mod errors;
mod mesh;
mod planar;
mod plane;

use crate::collide::{Geometry, Incident, Pose, Space, TriMesh, World};
use crate::model::elements::Id;
use crate::model::{read_model, Model};
use crate::vocab::math::Vec3;
use std::collections::HashMap;

/// A dataset of `body` after a title and a ground part with MARKER/1 at its origin,
/// read without errors.
pub fn model(body: &str) -> Model {
    let text = format!("contact\nPART/1, GROUND\nMARKER/1, PART=1\n{body}\nEND\n");
    let r = read_model(&text);
    let errors: Vec<_> = r.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{text}\n{errors:#?}");
    r.model
}

/// Each part at its dataset pose (QG, REULER).
pub fn initial(model: &Model) -> impl Fn(Id) -> Pose + '_ {
    move |id| {
        let p = model.part(id).expect("a part of the model");
        Pose {
            r: p.position,
            rot: p.orientation,
        }
    }
}

/// A world of the model's GRAPHICS `ids` watching `pairs`, placed at the dataset pose.
pub fn world(model: &Model, ids: &[Id], pairs: &[(usize, usize)], space: Space) -> World {
    world_with(model, ids, pairs, space, &HashMap::new())
}

/// [`world`] with meshes for EXTERNAL graphics.
pub fn world_with(
    model: &Model,
    ids: &[Id],
    pairs: &[(usize, usize)],
    space: Space,
    meshes: &HashMap<Id, TriMesh>,
) -> World {
    let geometries = ids
        .iter()
        .map(|&id| Geometry::of(model, id, meshes).expect("a contact geometry"))
        .collect();
    let mut w = World::new(geometries, pairs.to_vec(), space);
    w.update(&initial(model));
    w
}

/// The incidents of pair `k`.
pub fn incidents(w: &World, k: usize) -> Vec<Incident> {
    let mut out = vec![Incident {
        depth: -1.0,
        normal: Vec3::zeros(),
        point: Vec3::zeros(),
    }];
    w.incidents(k, &mut out);
    out
}

/// `a` and `b` within `tol` in every component.
#[track_caller]
pub fn near(a: Vec3, b: Vec3, tol: f64) {
    assert!((a - b).amax() <= tol, "{a:?} != {b:?} (tol {tol})");
}

/// A ground box whose top face is z = 0 over x, y ∈ [−2, 2] (GRAPHICS/100).
pub const FLOOR: &str =
    "MARKER/100, PART=1, QP=-2,-2,-1\nGRAPHICS/100, BOX, CORNER=100, X=4, Y=4, Z=1";
