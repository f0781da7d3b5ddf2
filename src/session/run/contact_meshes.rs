//! The meshes of the CONTACTs' EXTERNAL geometries, handed to the core as data
//! ([`crate::collide::TriMesh`] in the RM marker's coordinates): read from the file
//! `--geometry GRAPHICS/ID=FILE` gives, else the placeholder box the scene draws for an
//! EXTERNAL without a mesh (the uniform box of its part's mass and inertia), with one
//! `W0602` per geometry that stands in for its file; and the warnings for the CONTACTs
//! the core left out or holds out at the start (a stand-in pair that overlaps there).

use crate::collide::TriMesh;
use crate::diag::{Code, Diagnostic};
use crate::model::elements::Id;
use crate::model::graphics::Shape;
use crate::model::Model;
use crate::vocab::math::Vec3;
use std::collections::HashMap;
use std::path::PathBuf;

/// Triangles of a box over its corners numbered x + 2y + 4z (0 or 1 each), wound
/// counter-clockwise seen from outside.
const BOX_TRIANGLES: [[u32; 3]; 12] = [
    [0, 4, 6],
    [0, 6, 2],
    [1, 3, 7],
    [1, 7, 5],
    [0, 1, 5],
    [0, 5, 4],
    [2, 6, 7],
    [2, 7, 3],
    [0, 2, 3],
    [0, 3, 1],
    [4, 5, 7],
    [4, 7, 6],
];

/// The mesh of every EXTERNAL geometry a CONTACT of `model` names, from `files` or a
/// placeholder box, and the warnings (placeholders) and errors (a file that cannot be
/// read) that come with them.
pub fn contact_meshes(
    model: &Model,
    files: &[(u32, PathBuf)],
) -> (HashMap<Id, TriMesh>, Vec<Diagnostic>) {
    let mut meshes = HashMap::new();
    let mut diags = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let named = (model.contacts.iter()).flat_map(|c| c.igeom.iter().chain(&c.jgeom));
    for &id in named {
        // Each geometry once, however many CONTACTs name it.
        if !seen.insert(id) {
            continue;
        }
        let Some(g) = model.graphics.iter().find(|g| g.el.id == id) else {
            continue;
        };
        let Shape::External { rm, .. } = g.shape else {
            continue;
        };
        let file = files.iter().find(|(g, _)| *g == id).map(|(_, p)| p);
        let mesh = match file {
            Some(path) => match crate::scene::read_mesh_file(path, [1.0; 4]) {
                Ok(m) => Some(TriMesh {
                    vertices: (m.positions.iter())
                        .map(|p| Vec3::new(p[0].into(), p[1].into(), p[2].into()))
                        .collect(),
                    triangles: m
                        .indices
                        .chunks_exact(3)
                        .map(|t| [t[0], t[1], t[2]])
                        .collect(),
                    stand_in: false,
                }),
                Err(e) => {
                    diags.push(Diagnostic::error(Code::Io, g.el.span.clone(), e.0));
                    None
                }
            },
            None => {
                let placeholder = placeholder(model, rm);
                let what = match &placeholder {
                    Some(_) => "the uniform box of its part's mass and inertia stands in for it",
                    None => "its part has no inertia to make a box of: it collides with nothing",
                };
                diags.push(
                    Diagnostic::warning(
                        Code::UnsupportedStatement,
                        g.el.span.clone(),
                        format!(
                            "EXTERNAL GRAPHICS/{id} is a CONTACT geometry without a mesh: {what}"
                        ),
                    )
                    .with_help(format!(
                        "give its mesh: --geometry GRAPHICS/{id}=FILE (STL, OBJ)"
                    )),
                );
                placeholder
            }
        };
        if let Some(mesh) = mesh {
            meshes.insert(id, mesh);
        }
    }
    (meshes, diags)
}

/// A W0602 at each CONTACT the core left out of `set`, saying why.
pub(super) fn left_out<'a>(
    model: &'a Model,
    set: &'a crate::mbd::contacts::ContactSet,
) -> impl Iterator<Item = Diagnostic> + 'a {
    set.left_out.iter().map(|(id, why)| {
        let span = contact_span(model, *id);
        Diagnostic::warning(
            Code::UnsupportedStatement,
            span,
            format!("CONTACT/{id} is left out: {why}"),
        )
    })
}

/// A W0602 at each CONTACT with a stand-in pair the core holds out of `set` because it
/// overlaps at the start, naming the contact and its geometries.
pub(super) fn held_out<'a>(
    model: &'a Model,
    set: &'a crate::mbd::contacts::ContactSet,
) -> impl Iterator<Item = Diagnostic> + 'a {
    set.held_out.iter().map(|h| {
        let span = contact_span(model, h.contact);
        let (i, j) = h.graphics;
        Diagnostic::warning(
            Code::UnsupportedStatement,
            span,
            format!(
                "CONTACT/{}: GRAPHICS/{i} and GRAPHICS/{j} overlap by {} at the start with \
                 a placeholder standing in for their geometry; the pair is held out until \
                 they separate",
                h.contact,
                format_depth(h.depth)
            ),
        )
        .with_help("give the EXTERNAL geometry its mesh: --geometry GRAPHICS/ID=FILE")
    })
}

/// The span of CONTACT/`id` (empty when the model has none).
fn contact_span(model: &Model, id: Id) -> crate::diag::Span {
    (model.contacts.iter())
        .find(|c| c.el.id == id)
        .map_or(0..0, |c| c.el.span.clone())
}

/// The placeholder box of the part marker `rm` is on, in `rm`'s coordinates.
fn placeholder(model: &Model, rm: Id) -> Option<TriMesh> {
    let marker = model.marker(rm)?;
    let part = model.part(marker.part)?;
    let (cm, axes, sides) = crate::scene::inertia_box_of(model, part)?;
    let h = Vec3::from(sides) / 2.0;
    let vertices = (0..8)
        .map(|k| {
            let sign = |bit: usize| if k >> bit & 1 == 1 { 1.0 } else { -1.0 };
            let bcs = cm + axes * Vec3::new(sign(0) * h.x, sign(1) * h.y, sign(2) * h.z);
            marker.orientation.transpose() * (bcs - marker.position)
        })
        .collect();
    Some(TriMesh {
        vertices,
        triangles: BOX_TRIANGLES.to_vec(),
        stand_in: true,
    })
}

/// A depth to four significant digits (`0.01234`, `1.5e-07`).
fn format_depth(d: f64) -> String {
    if d != 0.0 && !(1e-4..1e5).contains(&d.abs()) {
        return format!("{d:.3e}");
    }
    let digits = (3 - d.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{d:.digits$}");
    match s.contains('.') {
        true => s.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => s,
    }
}
