//! The scene under construction and what every drawing step asks of the model: which
//! part (by index into [`Scene::parts`]) a marker is on, a marker's pose in its part's
//! BCS, and adding an item with its mesh.

use super::{colors, Anchor, Item, Mesh, Motion, Pose, Role, Scene};
use crate::model::elements::Model;
use crate::vocab::math::{Mat3, Vec3};
use std::collections::HashMap;

/// A scene being drawn from `model`.
pub struct Canvas<'m> {
    /// The model drawn.
    pub model: &'m Model,
    /// What is drawn so far.
    pub scene: Scene,
    /// Part id → index into `scene.parts`.
    part_index: HashMap<u32, usize>,
}

/// The unit quaternion `[x, y, z, w]` of a rotation matrix (re-orthonormalised, so a
/// dataset's rounded axes still give a rotation).
pub fn quaternion(m: &Mat3) -> [f64; 4] {
    if !m.iter().all(|v| v.is_finite()) {
        return Pose::IDENTITY.rotation;
    }
    let q = nalgebra::UnitQuaternion::from_matrix_eps(
        m,
        1e-12,
        100,
        nalgebra::UnitQuaternion::identity(),
    );
    let out = [q.i, q.j, q.k, q.w];
    if out.iter().all(|v| v.is_finite()) {
        out
    } else {
        Pose::IDENTITY.rotation
    }
}

/// The pose with this origin and these axes (columns).
pub fn pose(origin: Vec3, axes: &Mat3) -> Pose {
    Pose {
        translation: [origin.x, origin.y, origin.z],
        rotation: quaternion(axes),
    }
}

impl<'m> Canvas<'m> {
    /// An empty drawing of `model` over `scene`'s parts.
    pub fn new(model: &'m Model, scene: Scene) -> Self {
        let part_index = (scene.parts.iter().enumerate())
            .map(|(i, p)| (p.id, i))
            .collect();
        Canvas {
            model,
            scene,
            part_index,
        }
    }

    /// The index of PART/`id`.
    pub fn part(&self, id: u32) -> Option<usize> {
        self.part_index.get(&id).copied()
    }

    /// The part index and the BCS origin and axes of MARKER/`id`.
    pub fn marker(&self, id: u32) -> Option<(usize, Vec3, Mat3)> {
        let m = self.model.marker(id)?;
        Some((self.part(m.part)?, m.position, m.orientation))
    }

    /// MARKER/`id`'s part and pose in the part's BCS.
    pub fn marker_pose(&self, id: u32) -> Option<(usize, Pose)> {
        let (part, origin, axes) = self.marker(id)?;
        Some((part, pose(origin, &axes)))
    }

    /// MARKER/`id`'s origin as an [`Anchor`].
    pub fn anchor(&self, id: u32) -> Option<Anchor> {
        let (part, origin, _) = self.marker(id)?;
        Some(Anchor {
            part,
            point: [origin.x, origin.y, origin.z],
        })
    }

    /// The colour of the part at `index`.
    pub fn color(&self, index: usize) -> [f32; 4] {
        let ground = self.scene.parts.get(index).is_some_and(|p| p.ground);
        colors::part(index, ground)
    }

    /// Adds `mesh` and returns its index (to show it from several items).
    pub fn mesh(&mut self, mesh: Mesh) -> usize {
        self.scene.meshes.push(mesh);
        self.scene.meshes.len() - 1
    }

    /// Adds `item`.
    pub fn item(&mut self, item: Item) {
        self.scene.items.push(item);
    }

    /// Adds a rigid item with its own mesh.
    pub fn rigid(
        &mut self,
        name: String,
        view_name: Option<String>,
        part: usize,
        local: Pose,
        mesh: Mesh,
        role: Role,
    ) {
        let mesh = self.mesh(mesh);
        self.item(Item {
            name,
            view_name,
            part,
            local,
            mesh,
            role,
            motion: Motion::Rigid,
        });
    }

    /// Something the user should hear once.
    pub fn note(&mut self, note: String) {
        self.scene.notes.push(note);
    }
}
