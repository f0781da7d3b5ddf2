//! Meshes given for EXTERNAL graphics (`--geometry`), read from STL (ASCII or binary,
//! `stl_io`), OBJ (`tobj`) or glTF (`.gltf` or `.glb`, the `gltf` crate; its buffers read
//! here: the .glb's binary chunk, `data:` URIs, or files beside it). The triangles come
//! back flat-shaded, in the file's units (taken as the model's length units), wound as
//! the file winds them (counter-clockwise seen from outside, as all three formats say).
//! A file that cannot be read is an error naming it and why.

use super::tessellate::Builder;
use super::{Mesh, SceneError};
use crate::vocab::math::Vec3;
use base64::Engine;
use std::path::Path;

/// The triangles of the mesh file `path` in `color`.
pub fn read(path: &Path, color: [f32; 4]) -> Result<Mesh, SceneError> {
    let fail = |why: String| SceneError(format!("{}: cannot read the mesh: {why}", path.display()));
    let ext = (path.extension())
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let triangles = match ext.as_str() {
        "stl" => stl(path),
        "obj" => obj(path),
        "gltf" | "glb" => gltf_file(path),
        _ => Err(format!(
            "`.{ext}` is not a mesh format mbfx reads (STL, OBJ, glTF, GLB)"
        )),
    }
    .map_err(fail)?;
    let mut b = Builder::default();
    for t in &triangles {
        b.flat(t, (t[1] - t[0]).cross(&(t[2] - t[0])));
    }
    if b.is_empty() {
        return Err(fail("it holds no triangle of positive area".into()));
    }
    Ok(b.triangles(color))
}

type Triangles = Vec<[Vec3; 3]>;

fn v3(p: [f32; 3]) -> Vec3 {
    Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
}

fn stl(path: &Path) -> Result<Triangles, String> {
    let mut file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mesh = stl_io::read_stl(&mut file).map_err(|e| e.to_string())?;
    let at = |i: usize| mesh.vertices.get(i).map(|v| v3(v.0));
    (mesh.faces.iter())
        .map(|f| match f.vertices.map(at) {
            [Some(a), Some(b), Some(c)] => Ok([a, b, c]),
            _ => Err("a face names a vertex it does not hold".to_string()),
        })
        .collect()
}

fn obj(path: &Path) -> Result<Triangles, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for m in &models {
        let p = &m.mesh.positions;
        let at = |i: u32| {
            let i = i as usize * 3;
            p.get(i..i + 3).map(|s| v3([s[0], s[1], s[2]]))
        };
        for t in m.mesh.indices.chunks_exact(3) {
            match [at(t[0]), at(t[1]), at(t[2])] {
                [Some(a), Some(b), Some(c)] => out.push([a, b, c]),
                _ => {
                    return Err(format!(
                        "object `{}` names a vertex it does not hold",
                        m.name
                    ))
                }
            }
        }
    }
    Ok(out)
}

fn gltf_file(path: &Path) -> Result<Triangles, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| e.to_string())?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut buffers = Vec::new();
    for buffer in gltf.document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => (gltf.blob.clone())
                .ok_or_else(|| "a buffer is the binary chunk, which it lacks".to_string())?,
            gltf::buffer::Source::Uri(uri) => buffer_at(uri, dir)?,
        };
        // The reader trusts the declared length (validated against the accessors).
        if data.len() < buffer.length() {
            return Err(format!(
                "buffer {} holds {} bytes, not the {} it declares",
                buffer.index(),
                data.len(),
                buffer.length()
            ));
        }
        buffers.push(data);
    }
    let scene = (gltf.document.default_scene())
        .or_else(|| gltf.document.scenes().next())
        .ok_or("it has no scene")?;
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node, nalgebra::Matrix4<f64>)> = (scene.nodes())
        .map(|n| (n, nalgebra::Matrix4::identity()))
        .collect();
    // A node met twice means a cycle (invalid glTF): it is not walked again.
    let mut seen = std::collections::HashSet::new();
    while let Some((node, parent)) = stack.pop() {
        if !seen.insert(node.index()) {
            continue;
        }
        let local = nalgebra::Matrix4::from(node.transform().matrix()).cast::<f64>();
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
                let Some(positions) = reader.read_positions() else {
                    continue;
                };
                let points: Vec<Vec3> = positions
                    .map(|p| (world * nalgebra::Vector4::new(p[0], p[1], p[2], 1.0).cast()).xyz())
                    .collect();
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..points.len() as u32).collect(),
                };
                for t in indices.chunks_exact(3) {
                    let at = |i: u32| points.get(i as usize).copied();
                    if let [Some(a), Some(b), Some(c)] = [at(t[0]), at(t[1]), at(t[2])] {
                        out.push([a, b, c]);
                    }
                }
            }
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    Ok(out)
}

/// A glTF buffer's bytes from a `data:` URI or a file beside the glTF.
fn buffer_at(uri: &str, dir: &Path) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = (rest.split_once(";base64,")).ok_or("a data: URI that is not base64")?;
        return (base64::engine::general_purpose::STANDARD.decode(payload))
            .map_err(|e| format!("a data: URI: {e}"));
    }
    let file = dir.join(uri.replace("%20", " "));
    std::fs::read(&file).map_err(|e| format!("its buffer {}: {e}", file.display()))
}
