//! [`build`]: the [`Scene`] of a model. The parts at their input poses, the units and
//! the up direction; then what is drawn, in an order that lets sizes depend on the
//! extent: the GRAPHICS items and EXTERNAL meshes or inertia boxes first, then the
//! glyphs of parts with nothing to draw, then — sized from the extent of all that —
//! joint symbols, the ground triad, the boxes and spheres of degenerate inertia, and the
//! force arrows. Why something is not drawn goes to [`Scene::notes`].

use super::canvas::{quaternion, Canvas};
use super::colors::ARROW;
use super::items::{arrow_item, draw, Later};
use super::{arrow, glyphs, mesh_files, placeholder, Motion, PartNode, Pose, Scene};
use crate::model::graphics::Shape;
use crate::model::units::{si_value, Quantity};
use crate::model::Model;
use crate::vocab::math::{Quat, Vec3};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// What to draw beyond the dataset's GRAPHICS, and the meshes given for EXTERNAL.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// `--glyphs`: glyphs for every part, not only for parts with nothing to draw.
    pub glyphs: bool,
    /// `--geometry GRAPHICS/ID=FILE`: a mesh file (STL, OBJ, glTF) per EXTERNAL id (a
    /// later entry for an id replaces an earlier one).
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

/// Joint symbols are this fraction of the extent across.
const SYMBOL: f64 = 1.0 / 25.0;
/// The side of a degenerate part's placeholder cube, as a fraction of the extent.
const CUBE: f64 = 1.0 / 20.0;
/// The radius of a massless part's glyph sphere, as a fraction of the extent.
const SPHERE: f64 = 1.0 / 60.0;
/// The ground triad's axes, as a fraction of the extent.
const TRIAD: f64 = 1.0 / 8.0;
/// The radius of a force arrow's shaft, as a fraction of the extent.
const SHAFT: f64 = 1.0 / 300.0;

/// The scene of `model` drawn with `options`.
pub fn build(model: &Model, options: &Options) -> Result<Scene, SceneError> {
    let mut c = Canvas::new(model, frame(model));
    let mut arrows = Vec::new();
    let mut curves = Vec::new();
    for g in &model.graphics {
        match (&g.shape, draw(&mut c, g)) {
            (_, Later::Arrow(at)) => arrows.push((g, at)),
            (Shape::Curve { .. }, _) => curves.push(format!("GRAPHICS/{}", g.el.id)),
            _ => {}
        }
    }
    if !curves.is_empty() {
        c.note(format!(
            "{} not drawn: mbfx does not read CURVE data (CURVE statements are ignored)",
            curves.join(", ")
        ));
    }
    let cubes = externals(&mut c, options)?;
    let pending: Vec<usize> = cubes.iter().map(|(part, ..)| *part).collect();
    let glyph_parts = glyphs::parts(&c, options.glyphs, &pending);
    let spheres: Vec<usize> = (glyph_parts.iter().copied())
        .filter(|&p| !glyphs::inertia_and_links(&mut c, p))
        .collect();

    let extent = extent(&c.scene);
    for (part, name, view_name) in cubes {
        placeholder::cube(&mut c, part, CUBE * extent, name, view_name);
    }
    for part in spheres {
        glyphs::small_sphere(&mut c, part, SPHERE * extent);
    }
    if !glyph_parts.is_empty() {
        glyphs::joint_symbols(&mut c, &glyph_parts, SYMBOL * extent);
        glyphs::ground_triad(&mut c, TRIAD * extent);
    }
    if !arrows.is_empty() {
        let mesh = c.mesh(arrow::arrow(SHAFT * extent, ARROW));
        for (k, (g, at)) in arrows.into_iter().enumerate() {
            arrow_item(&mut c, g, at, k, mesh);
        }
    }
    c.scene.extent = self::extent(&c.scene);
    Ok(c.scene)
}

/// The scene's frame: title, units, up, the parts at their input poses, nothing drawn.
fn frame(model: &Model) -> Scene {
    let meters_per_length = (model.units.length.as_deref())
        .and_then(|n| si_value(Quantity::Length, n))
        .unwrap_or(1.0);
    let g = model.gravity;
    let up = if g.norm() > 0.0 {
        let u = -g / g.norm();
        [u.x, u.y, u.z]
    } else {
        [0.0, 1.0, 0.0]
    };
    let parts = (model.parts.iter())
        .map(|p| PartNode {
            id: p.el.id,
            view_name: p.el.name.clone(),
            ground: p.ground,
            input: Pose {
                translation: [p.position.x, p.position.y, p.position.z],
                rotation: quaternion(&p.orientation),
            },
        })
        .collect();
    Scene {
        title: model.title.clone(),
        meters_per_length,
        up,
        extent: 1.0,
        parts,
        ..Scene::default()
    }
}

/// EXTERNAL graphics: the mesh `--geometry` gives, else an inertia box; the parts whose
/// inertia gives no box come back (with the item's name) for a cube once the extent is
/// known. One note counts the placeholders.
#[allow(clippy::type_complexity)]
fn externals(
    c: &mut Canvas,
    options: &Options,
) -> Result<Vec<(usize, String, Option<String>)>, SceneError> {
    let given: BTreeMap<u32, &PathBuf> = options.geometry.iter().map(|(i, p)| (*i, p)).collect();
    for id in given.keys() {
        let external = (c.model.graphics.iter())
            .any(|g| g.el.id == *id && matches!(g.shape, Shape::External { .. }));
        if !external {
            return Err(SceneError(format!(
                "--geometry GRAPHICS/{id}: the dataset has no EXTERNAL graphic GRAPHICS/{id}"
            )));
        }
    }
    let mut placeholders = 0;
    let mut cubes = Vec::new();
    for g in &c.model.graphics {
        let Shape::External { rm, .. } = g.shape else {
            continue;
        };
        let name = format!("GRAPHICS/{}", g.el.id);
        let Some((part, local)) = c.marker_pose(rm) else {
            c.note(format!(
                "{name} (EXTERNAL) not drawn: MARKER/{rm} is not on a part"
            ));
            continue;
        };
        if let Some(path) = given.get(&g.el.id) {
            let mesh = mesh_files::read(path, c.color(part))?;
            c.rigid(
                name,
                g.el.name.clone(),
                part,
                local,
                mesh,
                super::Role::Graphic,
            );
            continue;
        }
        placeholders += 1;
        if !placeholder::inertia_box(c, part, name.clone(), g.el.name.clone()) {
            cubes.push((part, name, g.el.name.clone()));
        }
    }
    if placeholders > 0 {
        c.note(match placeholders {
            1 => "1 EXTERNAL graphic drawn as a placeholder box: no --geometry given for it"
                .to_string(),
            n => format!(
                "{n} EXTERNAL graphics drawn as placeholder boxes: no --geometry given for them"
            ),
        });
    }
    Ok(cubes)
}

/// The diagonal of the bounding box, at the input poses, of every item drawn (a
/// stretching item by its two ends, an arrow by its foot); 1 when that is zero.
pub fn extent(scene: &Scene) -> f64 {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    let mut add = |p: Vec3| {
        if p.iter().all(|v| v.is_finite()) {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    };
    let global = |part: usize, p: Vec3| match scene.parts.get(part) {
        Some(node) => apply(&node.input, p),
        None => p,
    };
    for item in &scene.items {
        match &item.motion {
            Motion::Rigid => {
                let Some(mesh) = scene.meshes.get(item.mesh) else {
                    continue;
                };
                for v in &mesh.positions {
                    let p = Vec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
                    add(global(item.part, apply(&item.local, p)));
                }
            }
            Motion::Stretch { from, to } => {
                add(global(from.part, Vec3::from(from.point)));
                add(global(to.part, Vec3::from(to.point)));
            }
            Motion::Arrow { at, .. } => add(global(at.part, Vec3::from(at.point))),
        }
    }
    let d = (hi - lo).norm();
    if d > 0.0 && d.is_finite() {
        d
    } else {
        1.0
    }
}

/// `pose` applied to the point `p`.
pub fn apply(pose: &Pose, p: Vec3) -> Vec3 {
    let [x, y, z, w] = pose.rotation;
    let q = Quat::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
    q * p + Vec3::from(pose.translation)
}
