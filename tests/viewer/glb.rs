//! Small glTF binaries built by hand for the viewer's tests, following the conventions of
//! docs/viewer.md (a root `mbfx` turning the model's +Z up to +Y, parts `PART/ID`, items
//! with `extras.mbfx.role`), independent of the project's own .glb writer.

use serde_json::{json, Value};

/// The root's rotation: −90° about X, turning the model's +Z to glTF's +Y.
pub const ROOT_ROTATION: [f64; 4] = [
    -std::f64::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f64::consts::FRAC_1_SQRT_2,
];
/// PART/2's key times (s), translations (model units) and turns about the model's z (deg).
pub const KEY_TIMES: [f32; 4] = [0.0, 1.0, 2.0, 3.0];
pub const KEY_X: [f32; 4] = [0.0, 1.0, 1.5, 1.5];
pub const KEY_DEGREES: [f64; 4] = [0.0, 90.0, 180.0, 270.0];
/// PART/2's height above the model's ground plane.
pub const PART_Z: f32 = 0.5;
/// The box's half sizes and its material (linear RGBA).
pub const BOX_HALF: [f32; 3] = [0.3, 0.15, 0.1];
pub const RED: [f32; 4] = [0.85, 0.1, 0.1, 1.0];

/// A quaternion `[x, y, z, w]` turning `degrees` about the model's z.
pub fn about_z(degrees: f64) -> [f64; 4] {
    let h = degrees.to_radians() / 2.0;
    [0.0, 0.0, h.sin(), h.cos()]
}

#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
}

impl Builder {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    fn floats(&mut self, values: &[f32], kind: &str, target: Option<u32>) -> usize {
        let n = match kind {
            "SCALAR" => 1,
            "VEC3" => 3,
            _ => 4,
        };
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let mut a = json!({"bufferView": view, "componentType": 5126, "count": values.len() / n, "type": kind});
        if kind != "VEC4" {
            let col = |k: usize| values.iter().skip(k).step_by(n).copied();
            let min: Vec<f32> = (0..n)
                .map(|k| col(k).fold(f32::INFINITY, f32::min))
                .collect();
            let max: Vec<f32> = (0..n)
                .map(|k| col(k).fold(f32::NEG_INFINITY, f32::max))
                .collect();
            a["min"] = json!(min);
            a["max"] = json!(max);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// Indices as u8, u16 or u32 (`width` bytes each).
    fn indices(&mut self, values: &[u32], width: usize) -> usize {
        let bytes: Vec<u8> = match width {
            1 => values.iter().map(|&v| v as u8).collect(),
            2 => values
                .iter()
                .flat_map(|&v| (v as u16).to_le_bytes())
                .collect(),
            _ => values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        };
        let view = self.view(&bytes, Some(34963));
        let ct = [0, 5121, 5123, 0, 5125][width];
        self.accessors.push(json!({"bufferView": view, "componentType": ct, "count": values.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    fn material(&mut self, rgba: [f32; 4]) -> usize {
        self.materials.push(json!({"pbrMetallicRoughness": {"baseColorFactor": rgba, "metallicFactor": 0.0}, "doubleSided": true}));
        self.materials.len() - 1
    }

    /// A mesh of one primitive; `normals` for triangles, `indices` with their byte width.
    fn mesh(
        &mut self,
        mode: u32,
        positions: &[f32],
        normals: Option<&[f32]>,
        indices: Option<(&[u32], usize)>,
        rgba: [f32; 4],
    ) -> usize {
        let mut attributes = json!({"POSITION": self.floats(positions, "VEC3", Some(34962))});
        if let Some(n) = normals {
            attributes["NORMAL"] = json!(self.floats(n, "VEC3", Some(34962)));
        }
        let material = self.material(rgba);
        let mut p = json!({"attributes": attributes, "mode": mode, "material": material});
        if let Some((idx, width)) = indices {
            p["indices"] = json!(self.indices(idx, width));
        }
        self.meshes.push(json!({"primitives": [p]}));
        self.meshes.len() - 1
    }

    /// A box from `lo` to `hi`: 24 vertices with face normals, 12 triangles.
    fn cuboid(&mut self, lo: [f32; 3], hi: [f32; 3], width: usize, rgba: [f32; 4]) -> usize {
        let (mut pos, mut nor, mut idx) = (Vec::new(), Vec::new(), Vec::new());
        for axis in 0..3 {
            for side in [0usize, 1] {
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let base = (pos.len() / 3) as u32;
                for (a, b) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                    let mut p = [0f32; 3];
                    p[axis] = if side == 1 { hi[axis] } else { lo[axis] };
                    p[u] = if a == 1 { hi[u] } else { lo[u] };
                    p[v] = if b == 1 { hi[v] } else { lo[v] };
                    let mut n = [0f32; 3];
                    n[axis] = if side == 1 { 1.0 } else { -1.0 };
                    pos.extend(p);
                    nor.extend(n);
                }
                idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            }
        }
        self.mesh(4, &pos, Some(&nor), Some((&idx, width)), rgba)
    }

    fn glb(self, nodes: Vec<Value>, animation: Option<Value>) -> Vec<u8> {
        let mut doc = json!({
            "asset": {"version": "2.0", "generator": "mbfx viewer tests"},
            "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
            "meshes": self.meshes, "materials": self.materials,
            "accessors": self.accessors, "bufferViews": self.views,
            "buffers": [{"byteLength": self.bin.len()}],
        });
        if let Some(a) = animation {
            doc["animations"] = json!([a]);
        }
        container(&doc.to_string(), &self.bin)
    }
}

/// The GLB container: a 12-byte header, a JSON chunk padded with spaces, a BIN chunk
/// padded with zeros (glTF 2.0 §4.4).
fn container(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

fn role(r: &str) -> Value {
    json!({"mbfx": {"role": r}})
}

/// A mechanism: ground (PART/1) with a line outline and a circle, PART/2 carrying a red
/// box (GRAPHICS/1) and a green inertia glyph, moved along the model's x and turned about
/// its z by a LINEAR animation; a force arrow under the root with STEP scale keys.
/// Without `animated`, the same nodes and no animation at all.
pub fn mechanism(animated: bool) -> Vec<u8> {
    let mut b = Builder::default();
    let boxm = b.cuboid([-BOX_HALF[0], -BOX_HALF[1], -BOX_HALF[2]], BOX_HALF, 4, RED);
    let glyph = b.cuboid(
        [-0.05, -0.05, -0.05],
        [0.05, 0.05, 0.05],
        2,
        [0.1, 0.7, 0.2, 1.0],
    );
    let arrow = b.cuboid(
        [-0.02, -0.02, 0.0],
        [0.02, 0.02, 1.0],
        4,
        [0.9, 0.5, 0.0, 1.0],
    );
    // Ground outline: four segments, no indices (drawArrays), in the model's z = 0 plane.
    let square = [[-1.0, -1.0], [2.5, -1.0], [2.5, 1.0], [-1.0, 1.0]];
    let mut seg = Vec::new();
    for k in 0..4 {
        let (p, q) = (square[k], square[(k + 1) % 4]);
        seg.extend([p[0], p[1], 0.0, q[0], q[1], 0.0]);
    }
    let outline = b.mesh(1, &seg, None, None, [0.1, 0.2, 0.6, 1.0]);
    // A circle as a line loop with u8 indices, and a line strip (a zigzag) with u16 ones.
    let circle: Vec<f32> = (0..24)
        .flat_map(|k| {
            let a = k as f32 / 24.0 * std::f32::consts::TAU;
            [0.4 * a.cos(), 0.4 * a.sin(), 0.0]
        })
        .collect();
    let loop_idx: Vec<u32> = (0..24).collect();
    let circle = b.mesh(2, &circle, None, Some((&loop_idx, 1)), [0.2, 0.2, 0.2, 1.0]);
    let zig = [0.0, 0.0, 0.0, 0.2, 0.0, 0.3, 0.4, 0.0, 0.0, 0.6, 0.0, 0.3];
    let zig = b.mesh(
        3,
        &zig,
        None,
        Some((&[0, 1, 2, 3], 2)),
        [0.3, 0.3, 0.3, 1.0],
    );
    let nodes = vec![
        json!({"name": "mbfx", "rotation": ROOT_ROTATION, "scale": [1.0, 1.0, 1.0], "children": [1, 2, 7]}),
        json!({"name": "PART/1", "extras": {"adams_view_name": "ground"}, "children": [3, 4, 8]}),
        json!({"name": "PART/2", "extras": {"adams_view_name": "crank"}, "translation": [0.0, 0.0, PART_Z], "children": [5, 6]}),
        json!({"name": "GRAPHICS/3", "mesh": outline, "extras": role("graphic")}),
        json!({"name": "GRAPHICS/4", "mesh": circle, "translation": [-0.5, 0.0, 0.0], "extras": role("graphic")}),
        json!({"name": "GRAPHICS/1", "mesh": boxm, "extras": {"adams_view_name": "crank_box", "mbfx": {"role": "graphic"}}}),
        json!({"name": "glyph PART/2 inertia", "mesh": glyph, "translation": [0.0, 0.0, 0.2], "extras": role("glyph")}),
        json!({"name": "GRAPHICS/9", "mesh": arrow, "translation": [0.0, 0.8, 0.2], "extras": role("arrow")}),
        json!({"name": "GRAPHICS/5", "mesh": zig, "translation": [1.0, -0.8, 0.0], "extras": role("graphic")}),
    ];
    if !animated {
        return b.glb(nodes, None);
    }
    let times = b.floats(&KEY_TIMES, "SCALAR", None);
    let tr: Vec<f32> = KEY_X.iter().flat_map(|&x| [x, 0.0, PART_Z]).collect();
    let tr = b.floats(&tr, "VEC3", None);
    let rot: Vec<f32> = KEY_DEGREES
        .iter()
        .flat_map(|&d| about_z(d).map(|v| v as f32))
        .collect();
    let rot = b.floats(&rot, "VEC4", None);
    let along_x = [
        0.0,
        std::f32::consts::FRAC_1_SQRT_2,
        0.0,
        std::f32::consts::FRAC_1_SQRT_2,
    ];
    let arrow_times = b.floats(&[0.0, 1.5, 3.0], "SCALAR", None);
    let arrow_rot = b.floats(&[along_x, along_x, along_x].concat(), "VEC4", None);
    let arrow_scale = b.floats(&[1.0, 1.0, 1.0, 1.0, 1.0, 2.0, 1.0, 1.0, 0.5], "VEC3", None);
    let arrow_tr = b.floats(&[0.0, 0.8, 0.2, 0.0, 0.8, 0.2, 0.0, 0.8, 0.2], "VEC3", None);
    let animation = json!({
        "name": "run",
        "samplers": [
            {"input": times, "output": tr, "interpolation": "LINEAR"},
            {"input": times, "output": rot, "interpolation": "LINEAR"},
            {"input": arrow_times, "output": arrow_tr, "interpolation": "LINEAR"},
            {"input": arrow_times, "output": arrow_rot, "interpolation": "LINEAR"},
            {"input": arrow_times, "output": arrow_scale, "interpolation": "STEP"},
        ],
        "channels": [
            {"sampler": 0, "target": {"node": 2, "path": "translation"}},
            {"sampler": 1, "target": {"node": 2, "path": "rotation"}},
            {"sampler": 2, "target": {"node": 7, "path": "translation"}},
            {"sampler": 3, "target": {"node": 7, "path": "rotation"}},
            {"sampler": 4, "target": {"node": 7, "path": "scale"}},
        ],
    });
    b.glb(nodes, Some(animation))
}

/// A chain of `parts` links (PART/2 …), each a box, swinging for `frames` key times at
/// 100 per second: the load of the chain of 100 for the frame-rate hook.
pub fn chain(parts: usize, frames: usize) -> Vec<u8> {
    let mut b = Builder::default();
    let link = b.cuboid([-0.01, -0.01, -0.045], [0.01, 0.01, 0.045], 4, RED);
    let mut nodes = vec![
        json!({"name": "mbfx", "rotation": ROOT_ROTATION, "children": (1..=parts).collect::<Vec<_>>()}),
    ];
    for k in 0..parts {
        nodes.push(json!({"name": format!("PART/{}", k + 2), "children": [parts + 1 + k]}));
    }
    for k in 0..parts {
        nodes.push(
            json!({"name": format!("GRAPHICS/{}", k + 1), "mesh": link, "extras": role("graphic")}),
        );
    }
    let times: Vec<f32> = (0..frames).map(|i| i as f32 / 100.0).collect();
    let input = b.floats(&times, "SCALAR", None);
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    for k in 0..parts {
        let (mut tr, mut rot) = (Vec::new(), Vec::new());
        for &t in &times {
            // Each link hangs from the one above, turned about the model's x.
            let (mut y, mut z, mut angle) = (0.0f64, 0.0f64, 0.0f64);
            for j in 0..=k {
                angle = 0.4 * (2.0 * t as f64 + j as f64 * 0.05).sin();
                y += 0.1 * angle.sin();
                z -= 0.1 * angle.cos();
            }
            tr.extend([0.0, y as f32, z as f32]);
            let h = (angle / 2.0) as f32;
            rot.extend([h.sin(), 0.0, 0.0, h.cos()]);
        }
        let (tr, rot) = (b.floats(&tr, "VEC3", None), b.floats(&rot, "VEC4", None));
        for (output, path) in [(tr, "translation"), (rot, "rotation")] {
            channels
                .push(json!({"sampler": samplers.len(), "target": {"node": k + 1, "path": path}}));
            samplers.push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
        }
    }
    b.glb(
        nodes,
        Some(json!({"name": "run", "samplers": samplers, "channels": channels})),
    )
}
