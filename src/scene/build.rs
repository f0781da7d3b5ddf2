//! A [`Scene`] from a model: its parts as nodes at their input poses, the units and the
//! up direction. (Items, meshes and glyphs: to come.)

use super::{PartNode, Pose, Scene};
use crate::model::units::{si_value, Quantity};
use crate::model::Model;
use std::path::PathBuf;

/// What to draw beyond the dataset's GRAPHICS, and the meshes given for EXTERNAL.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// `--glyphs`: glyphs for every part, not only for parts with nothing to draw.
    pub glyphs: bool,
    /// `--geometry GRAPHICS/ID=FILE`: a mesh file (STL, OBJ, glTF) per EXTERNAL id.
    pub geometry: Vec<(u32, PathBuf)>,
}

/// Why a scene cannot be built: a mesh file that cannot be read, named.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError(pub String);

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SceneError {}

/// The scene of `model` drawn with `options`.
pub fn build(model: &Model, options: &Options) -> Result<Scene, SceneError> {
    let _ = options;
    let meters_per_length = model
        .units
        .length
        .as_deref()
        .and_then(|n| si_value(Quantity::Length, n))
        .unwrap_or(1.0);
    let g = model.gravity;
    let up = if g.norm() > 0.0 {
        let u = -g / g.norm();
        [u.x, u.y, u.z]
    } else {
        [0.0, 1.0, 0.0]
    };
    let parts = model
        .parts
        .iter()
        .map(|p| {
            let q = nalgebra::UnitQuaternion::from_rotation_matrix(
                &nalgebra::Rotation3::from_matrix_unchecked(p.orientation),
            );
            PartNode {
                id: p.el.id,
                view_name: p.el.name.clone(),
                ground: p.ground,
                input: Pose {
                    translation: [p.position.x, p.position.y, p.position.z],
                    rotation: [q.i, q.j, q.k, q.w],
                },
            }
        })
        .collect();
    Ok(Scene {
        title: model.title.clone(),
        meters_per_length,
        up,
        extent: 1.0,
        parts,
        ..Scene::default()
    })
}
