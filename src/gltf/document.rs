//! The glTF JSON of a scene: the root node `mbfx` (turning the model's up to +Y, scaled
//! to meters), a node per part (`PART/ID`), a node per item (rigid ones under their
//! part, stretching ones and arrows under the root), one mesh per scene mesh with a
//! material per colour, and the animation `run` from the [`Tracks`].

use super::buffers::{Buffers, VERTICES};
use super::tracks::{quaternion, rotation_between, Track, Tracks};
use crate::scene::{Item, Motion, Pose, Scene, Topology};
use nalgebra::{UnitQuaternion, Vector3};
use serde_json::{json, Map, Value};

/// The document of `scene` with `tracks` (no animation when `tracks` has fewer than two
/// times or nothing moves), its binary data appended to `buffers`.
pub(super) fn document(scene: &Scene, tracks: &Tracks, buffers: &mut Buffers) -> Value {
    let (meshes, mesh_list, materials) = meshes(scene, buffers);
    // Node 0 is the root, then the parts, then the items.
    let part_node = |p: usize| 1 + p;
    let item_node = |i: usize| 1 + scene.parts.len() + i;
    let mut nodes = vec![root(scene)];
    let mut root_children: Vec<usize> = Vec::new();
    for (p, part) in scene.parts.iter().enumerate() {
        let mut node = match first(&tracks.parts[p]) {
            Some(t) => trs(t.translation[0], t.rotation[0], None),
            None => pose_trs(tracks.first[p].as_ref().unwrap_or(&part.input)),
        };
        node["name"] = json!(format!("PART/{}", part.id));
        if let Some(v) = &part.view_name {
            node["extras"] = json!({"adams_view_name": v});
        }
        let children: Vec<usize> = (scene.items.iter().enumerate())
            .filter(|(_, it)| it.motion == Motion::Rigid && it.part == p)
            .map(|(i, _)| item_node(i))
            .collect();
        if !children.is_empty() {
            node["children"] = json!(children);
        }
        root_children.push(part_node(p));
        nodes.push(node);
    }
    for (i, item) in scene.items.iter().enumerate() {
        let mut node = match (&item.motion, first(&tracks.items[i])) {
            (Motion::Rigid, _) => pose_trs(&item.local),
            (_, Some(t)) => trs(t.translation[0], t.rotation[0], Some(t.scale[0])),
            // Never recorded: drawn where the input poses put it.
            (_, None) => static_span(scene, item),
        };
        if item.motion != Motion::Rigid {
            root_children.push(item_node(i));
        }
        node["name"] = json!(item.name);
        let mut extras = json!({"mbfx": {"role": item.role.as_str()}});
        if let Some(v) = &item.view_name {
            extras["adams_view_name"] = json!(v);
        }
        node["extras"] = extras;
        if let Some(m) = meshes.get(item.mesh).copied().flatten() {
            node["mesh"] = json!(m);
        }
        nodes.push(node);
    }
    nodes[0]["children"] = json!(root_children);
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": format!("mbfx {}", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"name": scene.title, "nodes": [0]}],
        "nodes": nodes,
    });
    if !mesh_list.is_empty() {
        doc["meshes"] = json!(mesh_list);
        doc["materials"] = json!(materials);
    }
    let animated = (tracks.parts.iter().chain(&tracks.items)).any(|t| t.is_some());
    if tracks.times.len() >= 2 && animated {
        let nodes_of = (0..scene.parts.len()).map(part_node);
        let targets = nodes_of
            .zip(&tracks.parts)
            .chain((0..scene.items.len()).map(item_node).zip(&tracks.items));
        doc["animations"] = json!([animation(tracks, targets, buffers)]);
    }
    doc
}

/// The root: the model's up turned to +Y (the shortest arc; a half turn about X for
/// −Y), scaled from model lengths to meters.
fn root(scene: &Scene) -> Value {
    let up = Vector3::from(scene.up);
    let turn = if up.norm() > 0.0 && (up.normalize() + Vector3::y()).norm() < 1e-12 {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    } else if up.norm() > 0.0 {
        rotation_between(&up, &Vector3::y())
    } else {
        UnitQuaternion::identity()
    };
    let s = scene.meters_per_length as f32;
    let mut node = json!({"name": "mbfx", "scale": [s, s, s]});
    node["rotation"] = json!([turn.i as f32, turn.j as f32, turn.k as f32, turn.w as f32]);
    node
}

/// A node with translation, rotation and (when given) scale.
fn trs(t: [f32; 3], r: [f32; 4], s: Option<[f32; 3]>) -> Value {
    let mut node = json!({"translation": t, "rotation": r});
    if let Some(s) = s {
        node["scale"] = json!(s);
    }
    node
}

fn pose_trs(p: &Pose) -> Value {
    let q = quaternion(p.rotation);
    trs(
        p.translation.map(|x| x as f32),
        [q.i, q.j, q.k, q.w].map(|x| x as f32),
        None,
    )
}

/// A stretching item or arrow with no frame: its span at the input poses (an arrow
/// drawn with no length).
fn static_span(scene: &Scene, item: &Item) -> Value {
    let at = |a: &crate::scene::Anchor| {
        let p = &scene.parts[a.part].input;
        quaternion(p.rotation) * Vector3::from(a.point) + Vector3::from(p.translation)
    };
    let (from, d) = match &item.motion {
        Motion::Stretch { from, to } => (at(from), at(to) - at(from)),
        Motion::Arrow { at: a, .. } => (at(a), Vector3::zeros()),
        Motion::Rigid => (Vector3::zeros(), Vector3::z()),
    };
    let q = match d.norm() > 0.0 {
        true => rotation_between(&Vector3::z(), &d),
        false => UnitQuaternion::identity(),
    };
    let len = d.norm().max(1e-6 * scene.extent) as f32;
    trs(
        [from.x, from.y, from.z].map(|x| x as f32),
        [q.i, q.j, q.k, q.w].map(|x| x as f32),
        Some([1.0, 1.0, len]),
    )
}

/// The glTF meshes of the scene's meshes and their materials (one per distinct colour),
/// their data appended to `buffers`; per scene mesh, its glTF index (None for a mesh
/// with no vertex or index, which glTF cannot hold).
fn meshes(scene: &Scene, buffers: &mut Buffers) -> (Vec<Option<usize>>, Vec<Value>, Vec<Value>) {
    let mut colours: Vec<[u32; 4]> = Vec::new();
    let mut list = Vec::new();
    let mut index = Vec::new();
    for m in &scene.meshes {
        if m.positions.is_empty() || m.indices.is_empty() {
            index.push(None);
            continue;
        }
        let key = m.color.map(f32::to_bits);
        let material = colours.iter().position(|c| *c == key).unwrap_or_else(|| {
            colours.push(key);
            colours.len() - 1
        });
        let mut attributes = Map::new();
        attributes.insert(
            "POSITION".into(),
            json!(buffers.floats(&m.positions, Some(VERTICES))),
        );
        if m.topology == Topology::Triangles && m.normals.len() == m.positions.len() {
            attributes.insert(
                "NORMAL".into(),
                json!(buffers.floats(&m.normals, Some(VERTICES))),
            );
        }
        let mode = match m.topology {
            Topology::Triangles => 4,
            Topology::Lines => 1,
            Topology::LineStrip => 3,
            Topology::LineLoop => 2,
        };
        list.push(json!({"primitives": [{
            "attributes": attributes, "indices": buffers.indices(&m.indices), "mode": mode,
            "material": material,
        }]}));
        index.push(Some(list.len() - 1));
    }
    let materials = (colours.iter())
        .map(|c| {
            let rgba = c.map(f32::from_bits).map(|x| x.clamp(0.0, 1.0));
            let mut m = json!({
                "pbrMetallicRoughness": {"baseColorFactor": rgba, "metallicFactor": 0.0, "roughnessFactor": 0.8},
                "doubleSided": true,
            });
            // A colour seen through is blended, as its alpha asks.
            if rgba[3] < 1.0 {
                m["alphaMode"] = json!("BLEND");
            }
            m
        })
        .collect();
    (index, list, materials)
}

/// The animation `run`: one input accessor (the times), and per track its channels.
fn animation<'a>(
    tracks: &Tracks,
    targets: impl Iterator<Item = (usize, &'a Option<Track>)>,
    buffers: &mut Buffers,
) -> Value {
    let times: Vec<[f32; 1]> = tracks.times.iter().map(|&t| [t]).collect();
    let input = buffers.floats(&times, None);
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    let mut channel = |node: usize, path: &str, output: usize| {
        samplers.push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
        channels
            .push(json!({"sampler": samplers.len() - 1, "target": {"node": node, "path": path}}));
    };
    for (node, track) in targets {
        let Some(t) = track else { continue };
        channel(node, "translation", buffers.floats(&t.translation, None));
        channel(node, "rotation", buffers.floats(&t.rotation, None));
        if !t.scale.is_empty() {
            channel(node, "scale", buffers.floats(&t.scale, None));
        }
    }
    json!({"name": "run", "samplers": samplers, "channels": channels})
}

/// A track's first key, if it has one.
fn first(t: &Option<Track>) -> Option<&Track> {
    t.as_ref().filter(|t| !t.translation.is_empty())
}
