//! Glyphs derived from the model, for parts with nothing to draw (and every part with
//! `--glyphs`): at the CM the uniform solid ellipsoid with the part's mass and inertia
//! (I₁ = m(b² + c²)/5, so a² = 5(I₂ + I₃ − I₁)/(2m), along the principal axes), links
//! from the CM to each joint and JPRIM marker on the part, a symbol per joint type at
//! the joint's I marker, and a red-green-blue triad for ground's global axes.

use super::canvas::{pose, Canvas};
use super::colors::{AXES, GLYPH};
use super::curves::segments;
use super::mass::principal;
use super::placeholder::thick;
use super::solids::{centred_cuboid, ellipsoid, frustum};
use super::tessellate::Builder;
use super::{Item, Motion, Pose, Role};
use crate::vocab::elements::JointType;
use crate::vocab::math::Vec3;
use std::f64::consts::TAU;

/// Facets of glyph spheres and ellipsoids around their axis.
const SLICES: u32 = 24;

/// The parts that get glyphs: every part with `all`, else every moving part with no
/// graphic or placeholder item (nor a placeholder still to come, in `pending`).
pub fn parts(c: &Canvas, all: bool, pending: &[usize]) -> Vec<usize> {
    let drawn = |i: usize| {
        pending.contains(&i)
            || (c.scene.items.iter())
                .any(|it| it.part == i && matches!(it.role, Role::Graphic | Role::Placeholder))
    };
    (0..c.scene.parts.len())
        .filter(|&i| all || (!c.scene.parts[i].ground && !drawn(i)))
        .collect()
}

/// The joint and JPRIM markers `(I, J)` and the joint type (`None` for a JPRIM).
fn joints(c: &Canvas) -> Vec<(u32, u32, Option<JointType>)> {
    let joints = (c.model.joints.iter()).map(|j| (j.i, j.j, Some(j.kind)));
    joints
        .chain(c.model.jprims.iter().map(|j| (j.i, j.j, None)))
        .collect()
}

/// The inertia ellipsoid and the links of the part at `part`; `false` when its inertia
/// gives no ellipsoid (the caller draws a small sphere once the extent is known).
pub fn inertia_and_links(c: &mut Canvas, part: usize) -> bool {
    let Some(model_part) = c.model.parts.get(part) else {
        return false;
    };
    let id = model_part.el.id;
    let p = principal(c.model, model_part);
    let mut ends = Vec::new();
    for (i, j, _) in joints(c) {
        for m in [i, j] {
            if let Some((_, origin, _)) = c.marker(m).filter(|(on, ..)| *on == part) {
                ends.push((p.cm, origin));
            }
        }
    }
    if !c.scene.parts[part].ground {
        if let Some(mesh) = segments(&ends, GLYPH) {
            let name = format!("glyph PART/{id} links");
            c.rigid(name, None, part, Pose::IDENTITY, mesh, Role::Glyph);
        }
    }
    let Some(semi) = p.ellipsoid_semi_axes() else {
        return c.scene.parts[part].ground;
    };
    let mesh = ellipsoid(thick(semi), SLICES).triangles(GLYPH);
    let name = format!("glyph PART/{id} inertia");
    c.rigid(name, None, part, pose(p.cm, &p.axes), mesh, Role::Glyph);
    true
}

/// A sphere of radius `r` at the CM of the part at `part`: the glyph of a massless part.
pub fn small_sphere(c: &mut Canvas, part: usize, r: f64) {
    let Some(model_part) = c.model.parts.get(part) else {
        return;
    };
    let cm = principal(c.model, model_part).cm;
    let mesh = ellipsoid([r; 3], SLICES).triangles(GLYPH);
    let local = Pose {
        translation: [cm.x, cm.y, cm.z],
        ..Pose::IDENTITY
    };
    let name = format!("glyph PART/{} inertia (massless)", model_part.el.id);
    c.rigid(name, None, part, local, mesh, Role::Glyph);
}

/// The symbol of a joint type, `size` across, in its I marker's frame (z its axis).
pub fn symbol(kind: Option<JointType>, size: f64) -> Builder {
    let s = size;
    let along_z = |len: f64, r: f64, sides: u32| {
        let mut b = Builder::default();
        b.append(frustum(len, r, r, sides, TAU), Vec3::z() * (-len / 2.0));
        b
    };
    let slab = |h: Vec3| centred_cuboid(-h, h);
    match kind {
        Some(JointType::Revolute) => along_z(s, s / 3.0, SLICES),
        Some(JointType::Translational) => along_z(2.0 * s, s / 4.0, 4),
        Some(JointType::Cylindrical) => along_z(2.0 * s, s / 5.0, SLICES),
        Some(JointType::Spherical) => ellipsoid([s / 2.0; 3], SLICES),
        Some(JointType::Fixed) => slab(Vec3::repeat(s / 3.0)),
        Some(JointType::Planar) => slab(Vec3::new(s, s, s / 20.0)),
        Some(JointType::Universal | JointType::Hooke) => {
            let mut b = slab(Vec3::new(s / 1.5, s / 10.0, s / 10.0));
            b.append(slab(Vec3::new(s / 10.0, s / 1.5, s / 10.0)), Vec3::zeros());
            b
        }
        _ => ellipsoid([s / 4.0; 3], SLICES),
    }
}

/// The joint symbols of every joint and JPRIM touching a part in `parts`, at its I
/// marker, `size` across (one mesh per joint type, shown by all its joints).
pub fn joint_symbols(c: &mut Canvas, parts: &[usize], size: f64) {
    let mut meshes: Vec<(Option<JointType>, usize)> = Vec::new();
    for (i, j, kind) in joints(c) {
        let touches = [i, j]
            .iter()
            .any(|m| c.marker(*m).is_some_and(|(p, ..)| parts.contains(&p)));
        let Some((part, local)) = c.marker_pose(i).filter(|_| touches) else {
            continue;
        };
        let mesh = match meshes.iter().find(|(k, _)| *k == kind) {
            Some((_, mesh)) => *mesh,
            None => {
                let mesh = c.mesh(symbol(kind, size).triangles(GLYPH));
                meshes.push((kind, mesh));
                mesh
            }
        };
        let what = match kind {
            Some(k) => format!("{k:?}").to_lowercase(),
            None => "jprim".to_string(),
        };
        let name = format!("glyph {what} at MARKER/{i}");
        c.item(Item {
            name,
            view_name: None,
            part,
            local,
            mesh,
            role: Role::Glyph,
            motion: Motion::Rigid,
        });
    }
}

/// The ground triad: x, y, z of `length` from the global origin, red, green, blue.
pub fn ground_triad(c: &mut Canvas, length: f64) {
    let Some(ground) = c.scene.parts.iter().position(|p| p.ground) else {
        return;
    };
    // The triad sits at the global origin: the inverse of ground's BCS pose.
    let g = c.model.parts[ground].clone();
    let axes = g.orientation.transpose();
    let local = pose(-(axes * g.position), &axes);
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let tip = Vec3::from_fn(|i, _| if i == k { length } else { 0.0 });
        if let Some(mesh) = segments(&[(Vec3::zeros(), tip)], AXES[k]) {
            let name = format!("glyph ground triad {axis}");
            c.rigid(name, None, ground, local, mesh, Role::Glyph);
        }
    }
}
