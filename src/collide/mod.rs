//! Contact geometry and collision queries for CONTACT (issue 40 §1), on dimforge's parry
//! (double precision). This layer reads only the model's GRAPHICS and plain meshes; the
//! multibody core asks it, at a state, for the incidents between pairs of geometries and
//! turns them into forces (`mbd::contacts`).
//!
//! **The contract the core relies on** (the types below; their methods live in this
//! module's files):
//! - [`Geometry::of`] builds one contact geometry from a GRAPHICS statement of the model
//!   (BOX, CYLINDER, FRUSTUM, ELLIPSOID, EXTERNAL with a [`TriMesh`], and Adams' PLANE:
//!   its rectangle with the solid behind it), held in the BCS of the part its marker is
//!   on.
//! - [`World::new`] takes every geometry and the pairs to watch, in 3D or in the plane of a
//!   planar scene (then parry2d, on the shapes' sections by the plane).
//! - [`World::update`] places each part (global pose of its BCS); [`World::incidents`]
//!   lists, for one pair, one [`Incident`] per connected intersection region (Adams'
//!   semantics: a cylinder lying on a box is one incident). A broad phase (parry's BVH)
//!   keeps pairs that cannot touch from costing a narrow-phase query.
//!
//! The signatures (written by wp-collide; the core codes against them):
//! ```text
//! Geometry::of(model: &Model, graphic: Id, meshes: &HashMap<Id, TriMesh>) -> Result<Geometry, CollideError>
//! geometry.graphic: Id; geometry.part: Id            // GRAPHICS id and the PART it moves with
//! World::new(geometries: Vec<Geometry>, pairs: Vec<(usize, usize)>, space: Space) -> World
//! world.update(part_pose: &dyn Fn(Id) -> Pose)       // global BCS pose of each part
//! world.incidents(pair: usize, out: &mut Vec<Incident>)  // cleared, then filled
//! world.candidates(out: &mut Vec<usize>)             // pairs whose bounding volumes overlap
//! CollideError: a Diagnostic-friendly error naming the GRAPHICS and why (unsupported
//!               kind for contact, missing mesh for EXTERNAL, degenerate size)
//! ```
//! - Nothing here computes a force, a velocity or a derivative: the core linearizes an
//!   incident as a fixed normal and fixed material points for the Jacobians.

mod convert;
mod error;
mod geometry;
mod planar;
mod regions;
mod world;

#[cfg(test)]
mod tests;

pub use error::CollideError;
pub use geometry::Geometry;
pub use world::{Reach, World};

use crate::vocab::math::{Mat3, Vec3};

/// A triangle mesh read from a file (`--geometry` for EXTERNAL), in the coordinates of
/// the GRAPHICS statement's marker, model length units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// A placeholder standing in for geometry the run was not given (an EXTERNAL without
    /// its file): its overlaps at the start are its own artefact (`mbd::contacts` holds
    /// such a pair out until it separates).
    pub stand_in: bool,
}

/// A global pose: the position of a frame's origin and its rotation (columns: its axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Origin, global.
    pub r: Vec3,
    /// Rotation, frame to global.
    pub rot: Mat3,
}

/// One contact region between the I and J geometries of a pair, global axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// The deepest penetration in the region, ≥ 0 (model length units).
    pub depth: f64,
    /// Unit normal of the region, pointing from J's geometry into I's: the direction
    /// the normal force pushes I.
    pub normal: Vec3,
    /// The region's centroid, global: where the force acts on both parts.
    pub point: Vec3,
}

/// Which space a world's queries run in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Space {
    /// Full 3D (parry3d).
    Three,
    /// The plane through `origin` spanned by the global unit axes `a`, `b` (parry2d on
    /// the shapes' sections by the plane); incidents are still returned in 3D.
    Plane {
        /// A point of the plane.
        origin: Vec3,
        /// First in-plane axis.
        a: Vec3,
        /// Second in-plane axis.
        b: Vec3,
    },
}
