//! What a run's animation draws, before any file format: the model's parts as nodes, one
//! [`Item`] per GRAPHICS statement (or glyph, or placeholder) hung on a part with its
//! marker's static transform, the [`Mesh`]es they show, and the [`Frames`] a run records
//! (each part's pose at each frame time, each force arrow's vector). Lengths are in model
//! units and axes are the model's global axes; [`Scene::meters_per_length`] and
//! [`Scene::up`] say how a writer turns them into meters with +Y up (glTF).
//!
//! Built from a [`crate::model::Model`] alone (nothing here reads the core): the poses
//! come from the session's run. The glTF writer is [`crate::gltf`], the HTML page
//! [`crate::viewer`].

mod arrow;
mod build;
mod canvas;
mod colors;
mod curves;
mod geometry_map;
mod glyphs;
mod items;
mod mass;
mod mesh_files;
mod placeholder;
mod solids;
mod spring;
mod tessellate;
#[cfg(test)]
mod tests;

pub use build::{build, Options, SceneError};
pub use geometry_map::{geometry_arg, read_map};
pub use mesh_files::read as read_mesh_file;
pub use placeholder::inertia_box_of;

/// A rigid transform: a translation, then a unit quaternion `[x, y, z, w]` (glTF's order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Translation, model length units.
    pub translation: [f64; 3],
    /// Rotation as a unit quaternion `[x, y, z, w]`.
    pub rotation: [f64; 4],
}

impl Pose {
    /// No translation, no rotation.
    pub const IDENTITY: Pose = Pose {
        translation: [0.0; 3],
        rotation: [0.0, 0.0, 0.0, 1.0],
    };
}

/// Everything the animation of one model draws.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The dataset's title.
    pub title: String,
    /// Meters per model length unit (from UNITS; 1 when the dataset has none).
    pub meters_per_length: f64,
    /// The model's global "up", a unit vector in model axes: against gravity, or +Y
    /// when the model has none. A writer turns it to +Y once, at the root.
    pub up: [f64; 3],
    /// A characteristic size of the model at t = 0 (model units): the diagonal of what
    /// is drawn, for grids, glyph and arrow sizes. Never zero.
    pub extent: f64,
    /// Every part in the dataset's order (ground among them, [`PartNode::ground`]).
    pub parts: Vec<PartNode>,
    /// The meshes the items show (one mesh may be shown by several items).
    pub meshes: Vec<Mesh>,
    /// What is drawn.
    pub items: Vec<Item>,
    /// What each arrow shows, indexed by [`Motion::Arrow`]'s `arrow`.
    pub arrows: Vec<ArrowSource>,
    /// Things the user should hear once (`3 EXTERNAL graphics drawn as placeholder
    /// boxes: no --geometry given for them`).
    pub notes: Vec<String>,
}

/// A part: a node named `PART/ID` whose pose the frames animate.
#[derive(Clone, Debug, PartialEq)]
pub struct PartNode {
    /// The Adams id.
    pub id: u32,
    /// The dataset's adams_view_name, where it has one.
    pub view_name: Option<String>,
    /// Whether it is the ground part (it never moves).
    pub ground: bool,
    /// The BCS pose at the dataset's input (global): where the part is drawn when a run
    /// records no frame.
    pub input: Pose,
}

/// Why an item is drawn: a viewer may toggle each role.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    /// A GRAPHICS statement of the dataset.
    Graphic,
    /// Geometry the dataset did not give: an EXTERNAL without a mesh, drawn as a box.
    Placeholder,
    /// Derived from the model (`--glyphs`, or a part with nothing to draw): inertia
    /// ellipsoids, links, joint symbols, the ground triad.
    Glyph,
    /// A force vector (GRAPHICS FORCE).
    Arrow,
}

impl Role {
    /// The name written in a node's `extras` (`{"mbfx": {"role": "glyph"}}`).
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Graphic => "graphic",
            Role::Placeholder => "placeholder",
            Role::Glyph => "glyph",
            Role::Arrow => "arrow",
        }
    }
}

/// A point fixed on a part: where a stretching item starts or ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    /// Index into [`Scene::parts`].
    pub part: usize,
    /// The point in the part's BCS (model units).
    pub point: [f64; 3],
}

/// How an item moves.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// Fixed on [`Item::part`] at [`Item::local`].
    Rigid,
    /// Spans two points on (possibly) different parts: its mesh is drawn along local +z
    /// from z = 0 to z = 1, and a writer places local z = 0 at `from`, turns +z towards
    /// `to` and scales z by the distance (x and y unscaled). SPDP springs, OUTLINE
    /// segments between parts.
    Stretch {
        /// Where local z = 0 goes.
        from: Anchor,
        /// Where local z = 1 goes.
        to: Anchor,
    },
    /// A force vector drawn from `at`: its mesh (along local +z, unit length) turns
    /// along the force and scales z by its magnitude × a writer's scale.
    Arrow {
        /// Where the arrow starts.
        at: Anchor,
        /// Index into each frame's [`Frames::arrows`].
        arrow: usize,
    },
}

/// The force an arrow shows: element ETYPE/EID's force on the part of EMARKER
/// (GRAPHICS FORCE).
#[derive(Clone, Debug, PartialEq)]
pub struct ArrowSource {
    /// The element's statement kind, canonical (`SFORCE`).
    pub etype: &'static str,
    /// The element's id.
    pub eid: u32,
    /// The marker it is drawn at; its part is the one whose load is shown.
    pub emarker: u32,
}

/// One drawn thing: a node named [`Item::name`] showing [`Item::mesh`].
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// `GRAPHICS/12`; a glyph's or placeholder's says what it is (`glyph PART/3 inertia`).
    pub name: String,
    /// The dataset's adams_view_name, where it has one.
    pub view_name: Option<String>,
    /// Index into [`Scene::parts`]: the parent of a rigid item.
    pub part: usize,
    /// The static transform relative to the part's BCS (its marker's, for a GRAPHICS
    /// statement); identity for stretching items and arrows.
    pub local: Pose,
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Why it is drawn.
    pub role: Role,
    /// How it moves.
    pub motion: Motion,
}

/// How a mesh's indices join its vertices (glTF primitive modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topology {
    /// Triples of indices.
    Triangles,
    /// Pairs of indices.
    Lines,
    /// A polyline through the indices.
    LineStrip,
    /// A closed polyline.
    LineLoop,
}

/// Vertices and how they join, in the item's local frame (model units).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals, one per vertex (triangles only; empty for lines).
    pub normals: Vec<[f32; 3]>,
    /// Indices into the vertices.
    pub indices: Vec<u32>,
    /// How they join.
    pub topology: Topology,
    /// Linear RGBA, each in [0, 1].
    pub color: [f32; 4],
}

/// What a run recorded for the animation: at each frame time, every part's BCS pose
/// (global, model units; ground's too) and every arrow's force vector (global axes,
/// model force units).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frames {
    /// Frame times, increasing.
    pub times: Vec<f64>,
    /// `poses[k][p]`: part `p`'s pose at `times[k]`.
    pub poses: Vec<Vec<Pose>>,
    /// `arrows[k][a]`: arrow `a`'s force at `times[k]`.
    pub arrows: Vec<Vec<[f64; 3]>>,
}
