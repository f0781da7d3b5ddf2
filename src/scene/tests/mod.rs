//! Unit tests of the scene, one file per topic: the solids' geometry against formulas
//! (`shapes`), the items a dataset gets (`items`), mesh files and the geometry map
//! (`files`), and the whole corpus drawn (`corpus`); what the scene may import is the
//! crate's `layering` test's. Shared: reading a small dataset and measuring a mesh.

mod corpus;
mod files;
mod items;
mod shapes;

use super::{build, Item, Mesh, Options, Role, Scene};
use crate::model::read_model;
use crate::vocab::math::Vec3;

/// The scene of a dataset that reads without errors (parts and markers of `body`
/// after a title), drawn with `options`.
fn scene_of(body: &str, options: &Options) -> Scene {
    let text = format!("scene test\n{body}\nEND\n");
    let read = read_model(&text);
    let errors: Vec<_> = read.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    build(&read.model, options).expect("a scene")
}

/// The one item named `name`.
fn item<'s>(s: &'s Scene, name: &str) -> &'s Item {
    let found: Vec<&Item> = s.items.iter().filter(|i| i.name == name).collect();
    assert_eq!(found.len(), 1, "{name} in {:#?}", names(s));
    found[0]
}

/// The items' names and roles.
fn names(s: &Scene) -> Vec<(String, Role)> {
    s.items.iter().map(|i| (i.name.clone(), i.role)).collect()
}

fn v(p: [f32; 3]) -> Vec3 {
    Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
}

/// The triangles of a triangle mesh, as corner positions.
fn triangles(m: &Mesh) -> Vec<[Vec3; 3]> {
    (m.indices.chunks_exact(3))
        .map(|t| [0, 1, 2].map(|k| v(m.positions[t[k] as usize])))
        .collect()
}

/// The volume a closed triangle mesh encloses, by the divergence theorem: the sum over
/// its triangles of a·(b×c)/6 (positive when the triangles wind outward).
fn volume(m: &Mesh) -> f64 {
    triangles(m)
        .iter()
        .map(|[a, b, c]| a.dot(&b.cross(c)) / 6.0)
        .sum()
}

/// Checks that every normal is a unit vector and agrees with its triangle's winding.
fn assert_normals_agree(m: &Mesh) {
    assert_eq!(m.normals.len(), m.positions.len());
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| v(m.positions[t[k] as usize]));
        let face = (b - a).cross(&(c - a));
        for k in t {
            let n = v(m.normals[*k as usize]);
            assert!((n.norm() - 1.0).abs() < 1e-5, "normal {n}");
            assert!(n.dot(&face) > 0.0, "normal {n} against face {face}");
        }
    }
}
