//! Mesh files for EXTERNAL graphics, written here and read back: STL (ASCII and
//! binary), OBJ, glTF with a data: URI and with a sidecar .bin; a broken file's error
//! names it; the TOML geometry map and `--geometry` arguments; ids that name no
//! EXTERNAL.

use super::{item, triangles};
use crate::scene::{build, geometry_arg, read_map, Options, Role, SceneError};
use crate::vocab::math::Vec3;
use std::path::{Path, PathBuf};

/// A fresh directory for one test's files.
fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("mbfx-scene-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Two triangles of a unit square in z = 0 and one in x = 1, counter-clockwise from
/// outside (+z, +x).
const TRIS: [[[f32; 3]; 3]; 3] = [
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]],
];

fn as_vec(t: [[f32; 3]; 3]) -> [Vec3; 3] {
    t.map(|p| Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
}

const EXTERNAL: &str = "PART/1, GROUND\nPART/2, MASS = 1, CM = 21, IP = 1, 1, 1\n\
MARKER/21, PART = 2, QP = 0, 0, 1\nGRAPHICS/9, EXTERNAL, RM = 21, FILE = part.x_t";

/// The triangles EXTERNAL GRAPHICS/9 shows when given `file`.
fn read_back(file: &Path) -> Result<Vec<[Vec3; 3]>, SceneError> {
    let read = crate::model::read_model(&format!("t\n{EXTERNAL}\nEND\n"));
    let options = Options {
        geometry: vec![(9, file.to_path_buf())],
        ..Options::default()
    };
    let s = build(&read.model, &options)?;
    let it = item(&s, "GRAPHICS/9");
    assert_eq!(
        (it.role, it.local.translation),
        (Role::Graphic, [0.0, 0.0, 1.0])
    );
    super::assert_normals_agree(&s.meshes[it.mesh]);
    assert!(!s.notes.iter().any(|n| n.contains("placeholder")));
    Ok(triangles(&s.meshes[it.mesh]))
}

fn assert_triangles(got: Vec<[Vec3; 3]>) {
    let want: Vec<[Vec3; 3]> = TRIS.iter().map(|t| as_vec(*t)).collect();
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        // Same corners in the same cyclic order (the winding kept).
        let rotations = [[0, 1, 2], [1, 2, 0], [2, 0, 1]];
        assert!(
            rotations
                .iter()
                .any(|r| r.iter().zip(w).all(|(&k, wp)| g[k] == *wp)),
            "{g:?} vs {w:?}"
        );
    }
}

#[test]
fn stl_files_ascii_and_binary_read_back_to_their_triangles() {
    let d = dir("stl");
    let mut ascii = String::from("solid test\n");
    let mut binary = vec![0u8; 80];
    binary.extend((TRIS.len() as u32).to_le_bytes());
    for t in TRIS {
        ascii.push_str("facet normal 0 0 0\nouter loop\n");
        binary.extend([0u8; 12]);
        for p in t {
            ascii.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
            p.iter().for_each(|c| binary.extend(c.to_le_bytes()));
        }
        ascii.push_str("endloop\nendfacet\n");
        binary.extend([0u8; 2]);
    }
    ascii.push_str("endsolid test\n");
    std::fs::write(d.join("a.stl"), ascii).expect("write");
    std::fs::write(d.join("b.STL"), binary).expect("write");
    assert_triangles(read_back(&d.join("a.stl")).expect("ascii STL"));
    assert_triangles(read_back(&d.join("b.STL")).expect("binary STL"));
}

#[test]
fn an_obj_file_reads_back_to_its_triangles() {
    let d = dir("obj");
    // A quad (fanned by the reader) and a triangle.
    let obj = "o part\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 1\nf 1 2 3 4\nf 2 3 5\n";
    std::fs::write(d.join("a.obj"), obj).expect("write");
    assert_triangles(read_back(&d.join("a.obj")).expect("OBJ"));
}

/// A glTF JSON with one mesh of TRIS (no indices) in buffer `uri`, on a node moved by
/// +1 in x under a parent moved by −1: the transforms must compose to none.
fn gltf_json(uri: &str, len: usize) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"translation":[-1,0,0],"children":[1]}},{{"translation":[1,0,0],"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":9,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}}],
        "bufferViews":[{{"buffer":0,"byteLength":{len}}}],
        "buffers":[{{"uri":"{uri}","byteLength":{len}}}]}}"#
    )
}

fn tri_bytes() -> Vec<u8> {
    TRIS.iter()
        .flatten()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect()
}

#[test]
fn gltf_files_read_back_with_their_buffers_embedded_or_beside() {
    use base64::Engine;
    let d = dir("gltf");
    let bytes = tri_bytes();
    let data = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    std::fs::write(d.join("inline.gltf"), gltf_json(&data, bytes.len())).expect("write");
    assert_triangles(read_back(&d.join("inline.gltf")).expect("data: URI"));
    std::fs::write(d.join("mesh.bin"), &bytes).expect("write");
    std::fs::write(d.join("side.gltf"), gltf_json("mesh.bin", bytes.len())).expect("write");
    assert_triangles(read_back(&d.join("side.gltf")).expect("sidecar .bin"));
    // The sidecar gone: an error naming the glTF and the buffer.
    std::fs::remove_file(d.join("mesh.bin")).expect("remove");
    let err = read_back(&d.join("side.gltf")).expect_err("no buffer").0;
    assert!(
        err.contains("side.gltf") && err.contains("mesh.bin"),
        "{err}"
    );
}

#[test]
fn a_broken_or_missing_file_is_an_error_naming_it() {
    let d = dir("broken");
    std::fs::write(
        d.join("bad.stl"),
        "solid x\nfacet normal 0 0 0\nouter loop\nvertex 1 2\n",
    )
    .expect("write");
    std::fs::write(d.join("bad.glb"), b"glTF\x02\x00\x00\x00garbage").expect("write");
    std::fs::write(d.join("shape.step"), "ISO-10303-21;").expect("write");
    for name in ["bad.stl", "bad.glb", "shape.step", "missing.obj"] {
        let err = read_back(&d.join(name)).expect_err(name).0;
        assert!(
            err.contains(name) && err.contains("cannot read the mesh"),
            "{err}"
        );
    }
}

#[test]
fn the_geometry_map_and_arguments_name_externals() {
    let d = dir("map");
    let toml =
        "[geometry]\n\"GRAPHICS/9\" = \"parts/link.stl\"\n\"GRAPHICS/12\" = \"/abs/crank.glb\"\n";
    std::fs::write(d.join("geo.toml"), toml).expect("write");
    let mut map = read_map(&d.join("geo.toml")).expect("map");
    map.sort();
    assert_eq!(
        map,
        [
            (9, d.join("parts/link.stl")),
            (12, PathBuf::from("/abs/crank.glb"))
        ]
    );
    assert_eq!(
        geometry_arg("GRAPHICS/9=parts/a.obj").expect("arg"),
        [(9, PathBuf::from("parts/a.obj"))]
    );
    assert_eq!(
        geometry_arg(&d.join("geo.toml").display().to_string())
            .expect("toml")
            .len(),
        2
    );
    for bad in ["JOINT/9=a.stl", "GRAPHICS/x=a.stl", "a.stl"] {
        assert!(geometry_arg(bad).is_err(), "{bad}");
    }
    std::fs::write(d.join("bad.toml"), "[geometry]\n\"GRAPHICS/9\" = 3\n").expect("write");
    let err = read_map(&d.join("bad.toml")).expect_err("not a string").0;
    assert!(err.contains("bad.toml"), "{err}");
    // An id naming no EXTERNAL graphic.
    let read = crate::model::read_model(&format!("t\n{EXTERNAL}\nEND\n"));
    let options = Options {
        geometry: vec![(10, d.join("x.stl"))],
        ..Options::default()
    };
    let err = build(&read.model, &options).expect_err("no GRAPHICS/10").0;
    assert!(err.contains("GRAPHICS/10"), "{err}");
}
