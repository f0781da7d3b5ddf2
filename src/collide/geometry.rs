//! One contact geometry built from a GRAPHICS statement: its solid as parry holds it, and
//! where it sits in the BCS of the part it moves with. The conventions of each kind (a
//! BOX from its CORNER, a CYLINDER from the centre of its bottom, ELLIPSOID scales as
//! diameters) are the model's (docs/models.md, "GRAPHICS"); docs/contact.md says what is
//! exact and what is approximated.

use super::convert::to_parry;
use super::{CollideError, Pose, TriMesh};
use crate::model::elements::{Id, Marker, Model};
use crate::model::graphics::{Radius, Shape};
use crate::vocab::math::{Mat3, Vec3};
use parry3d_f64::glamx::DVec3;
use parry3d_f64::shape::{SharedShape, TriMeshFlags};
use std::collections::HashMap;
use std::f64::consts::PI;

/// Rings (pole to pole) and sectors (about z) of the tessellation of an ellipsoid with
/// unequal axes: the hull's vertices lie on the surface, so its flat faces sit inside
/// by at most a·(1 − cos(π/64)) ≈ 1.2·10⁻³·a along a sector and as much along a ring,
/// a the largest semi-axis.
const ELLIPSOID_RINGS: usize = 32;
const ELLIPSOID_SECTORS: usize = 64;
/// Points on each end circle of a frustum (its hull's flats sit inside the round
/// mantle by at most r·(1 − cos(π/64)) ≈ 1.2·10⁻³·r).
const FRUSTUM_SEGMENTS: usize = 64;

/// A contact geometry: the solid of one GRAPHICS statement, in the BCS of its part.
#[derive(Clone)]
pub struct Geometry {
    /// The GRAPHICS id.
    pub graphic: Id,
    /// The PART it moves with (the part of its marker).
    pub part: Id,
    /// The solid's own frame in the part's BCS: a box's centre with the CORNER marker's
    /// axes; the middle of a cylinder's or frustum's axis with the CM marker's axes (z
    /// the axis); an ellipsoid's CM; an EXTERNAL mesh's RM marker.
    pub frame: Pose,
    /// The solid's dimensions in `frame`, as the plane sections need them.
    pub(crate) form: Form,
    /// The solid as parry holds it, at `fix` in `frame`.
    pub(crate) shape: SharedShape,
    /// Where parry's shape sits in `frame` (parry's round shapes have their axis along
    /// y; mbfx's along z).
    pub(crate) fix: Pose,
    /// For a mesh parry holds as triangles: its triangles after parry merged duplicate
    /// vertices (indices of welded vertices), to tell which touching triangles are
    /// neighbours. Empty for a convex solid (a convex mesh held as its hull).
    pub(crate) triangles: Vec<[u32; 3]>,
    /// A mesh held as triangles that is closed (each edge between two triangles): it
    /// bounds a solid, which a mesh–mesh pair queries in convex pieces.
    pub(crate) closed: bool,
    /// A placeholder mesh standing in for an EXTERNAL's file ([`TriMesh::stand_in`]).
    pub stand_in: bool,
}

impl std::fmt::Debug for Geometry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Geometry")
            .field("graphic", &self.graphic)
            .field("part", &self.part)
            .field("frame", &self.frame)
            .field("form", &self.form)
            .finish()
    }
}

/// A solid's dimensions in its own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Form {
    /// A box of these half extents, centred.
    Box { half: [f64; 3] },
    /// A cylinder or frustum along z, centred: radius `below` at z = −`half`, `above` at
    /// z = +`half`.
    Round { below: f64, above: f64, half: f64 },
    /// An ellipsoid of these semi-axes, centred.
    Ellipsoid { semi: [f64; 3] },
    /// A triangle mesh.
    Mesh,
}

impl Geometry {
    /// The contact geometry of GRAPHICS/`graphic` of `model`; an EXTERNAL takes its
    /// mesh from `meshes` (keyed by GRAPHICS id, in the RM marker's coordinates).
    pub fn of(
        model: &Model,
        graphic: Id,
        meshes: &HashMap<Id, TriMesh>,
    ) -> Result<Geometry, CollideError> {
        let Some(g) = model.graphics.iter().find(|g| g.el.id == graphic) else {
            return Err(CollideError::new(
                graphic,
                0..0,
                "no such GRAPHICS statement",
            ));
        };
        let fail = |why: String| CollideError::new(graphic, g.el.span.clone(), why);
        let marker = |id: Id| {
            model
                .marker(id)
                .ok_or_else(|| fail(format!("MARKER/{id} is not in the model")))
        };
        let built = match &g.shape {
            Shape::Box { corner, extent } => solid_box(marker(*corner)?, *extent),
            Shape::Cylinder {
                cm, length, radius, ..
            } => {
                let r = radius_of(model, *cm, *radius)
                    .ok_or_else(|| fail("its RM marker is not in the model".into()))?;
                round(marker(*cm)?, *length, r, r)
            }
            Shape::Frustum {
                cm,
                length,
                top,
                bottom,
                ..
            } => round(marker(*cm)?, *length, *bottom, *top),
            Shape::Ellipsoid { cm, scale } => ellipsoid(marker(*cm)?, *scale),
            Shape::External { rm, file, .. } => {
                let mesh = meshes.get(&graphic).ok_or_else(|| {
                    fail(format!(
                        "EXTERNAL `{file}` has no mesh (give one with --geometry)"
                    ))
                })?;
                external(marker(*rm)?, mesh)
            }
            Shape::Plane { rm, x, y } => plane(marker(*rm)?, *x, *y),
            other => Err(format!(
                "a{} {} has no volume to collide (contact geometries are BOX, CYLINDER, \
                 FRUSTUM, ELLIPSOID, EXTERNAL, PLANE)",
                if other.kind().starts_with(['A', 'O']) {
                    "n"
                } else {
                    ""
                },
                other.kind()
            )),
        };
        let (part, built) = built.map_err(fail)?;
        let stand_in = matches!(g.shape, Shape::External { .. })
            && meshes.get(&graphic).is_some_and(|m| m.stand_in);
        Ok(Geometry {
            stand_in,
            closed: built.closed,
            graphic,
            part,
            frame: built.frame,
            form: built.form,
            shape: built.shape,
            fix: built.fix,
            triangles: built.triangles,
        })
    }

    /// Whether parry holds it as a triangle mesh (a surface, its touches on triangles);
    /// false for every convex solid, a convex mesh's hull included.
    pub fn is_mesh(&self) -> bool {
        !self.triangles.is_empty()
    }
}

/// What the builders of each kind hand back.
struct Built {
    frame: Pose,
    form: Form,
    shape: SharedShape,
    fix: Pose,
    triangles: Vec<[u32; 3]>,
    closed: bool,
}

impl Built {
    /// A solid with parry's frame at `frame`.
    fn plain(frame: Pose, form: Form, shape: SharedShape) -> Self {
        Built {
            frame,
            form,
            shape,
            fix: identity(),
            triangles: Vec::new(),
            closed: false,
        }
    }
}

fn identity() -> Pose {
    Pose {
        r: Vec3::zeros(),
        rot: Mat3::identity(),
    }
}

/// The marker's frame in its part's BCS, moved by `offset` along its own axes.
fn marker_frame(m: &Marker, offset: Vec3) -> Pose {
    Pose {
        r: m.position + m.orientation * offset,
        rot: m.orientation,
    }
}

/// Every value finite and positive.
fn sizes_ok(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite() && *v > 0.0)
}

fn solid_box(corner: &Marker, extent: [f64; 3]) -> Result<(Id, Built), String> {
    let half = extent.map(|e| e.abs() / 2.0);
    if !sizes_ok(&half) {
        return Err(format!(
            "a BOX needs three non-zero extents (X, Y, Z = {}, {}, {})",
            extent[0], extent[1], extent[2]
        ));
    }
    let frame = marker_frame(corner, Vec3::from(extent.map(|e| e / 2.0)));
    let shape = SharedShape::cuboid(half[0], half[1], half[2]);
    Ok((corner.part, Built::plain(frame, Form::Box { half }, shape)))
}

/// Adams' PLANE: the rectangle `x` × `y` in RM's x-y plane with the solid on its −z
/// side, a box as deep as the rectangle's longer side (a face that bounds a volume, so a
/// body sunk into it is pushed back out along +z, and one beside the rectangle is not).
fn plane(rm: &Marker, x: [f64; 2], y: [f64; 2]) -> Result<(Id, Built), String> {
    let depth = (x[1] - x[0]).max(y[1] - y[0]);
    let half = [(x[1] - x[0]) / 2.0, (y[1] - y[0]) / 2.0, depth / 2.0];
    if !sizes_ok(&half) {
        return Err(format!(
            "a PLANE needs XMIN < XMAX and YMIN < YMAX (x {} to {}, y {} to {})",
            x[0], x[1], y[0], y[1]
        ));
    }
    let centre = Vec3::new((x[0] + x[1]) / 2.0, (y[0] + y[1]) / 2.0, -depth / 2.0);
    let shape = SharedShape::cuboid(half[0], half[1], half[2]);
    let built = Built::plain(marker_frame(rm, centre), Form::Box { half }, shape);
    Ok((rm.part, built))
}

/// A cylinder (`bottom` = `top`) or frustum from CM's origin along its z for `length`.
fn round(cm: &Marker, length: f64, bottom: f64, top: f64) -> Result<(Id, Built), String> {
    let ok = length.is_finite() && length != 0.0 && bottom >= 0.0 && top >= 0.0;
    if !ok || !sizes_ok(&[bottom.max(top)]) {
        return Err(format!(
            "a round solid needs a non-zero LENGTH and a radius (LENGTH = {length}, \
             radii {bottom}, {top})"
        ));
    }
    let half = length.abs() / 2.0;
    // The bottom circle (at CM) is below the middle when LENGTH > 0, above when < 0.
    let (below, above) = if length > 0.0 {
        (bottom, top)
    } else {
        (top, bottom)
    };
    let frame = marker_frame(cm, Vec3::new(0.0, 0.0, length / 2.0));
    let form = Form::Round { below, above, half };
    let built = if below == above {
        Built {
            fix: y_to_z(1.0),
            ..Built::plain(frame, form, SharedShape::cylinder(half, below))
        }
    } else if below == 0.0 || above == 0.0 {
        // parry's cone has its apex at +y: turn +y to the apex's end of z.
        let (r, apex) = if below == 0.0 {
            (above, -1.0)
        } else {
            (below, 1.0)
        };
        Built {
            fix: y_to_z(apex),
            ..Built::plain(frame, form, SharedShape::cone(half, r))
        }
    } else {
        let mut points = Vec::with_capacity(2 * FRUSTUM_SEGMENTS);
        for k in 0..FRUSTUM_SEGMENTS {
            let (s, c) = (2.0 * PI * k as f64 / FRUSTUM_SEGMENTS as f64).sin_cos();
            points.push(DVec3::new(below * c, below * s, -half));
            points.push(DVec3::new(above * c, above * s, half));
        }
        let hull = SharedShape::convex_hull(&points)
            .ok_or_else(|| "its frustum has no hull (degenerate sizes)".to_string())?;
        Built::plain(frame, form, hull)
    };
    Ok((cm.part, built))
}

/// The rotation that takes parry's +y axis to `sign`·z (a quarter turn about x).
fn y_to_z(sign: f64) -> Pose {
    Pose {
        r: Vec3::zeros(),
        rot: Mat3::from_columns(&[
            Vec3::x(),
            Vec3::new(0.0, 0.0, sign),
            Vec3::new(0.0, -sign, 0.0),
        ]),
    }
}

/// An ellipsoid of diameters `scale` (docs/models.md) about CM.
fn ellipsoid(cm: &Marker, scale: [f64; 3]) -> Result<(Id, Built), String> {
    let semi = scale.map(|s| s / 2.0);
    if !sizes_ok(&semi) {
        return Err(format!(
            "an ELLIPSOID needs three non-zero scales (XSCALE, YSCALE, ZSCALE = {}, {}, {})",
            scale[0], scale[1], scale[2]
        ));
    }
    let frame = marker_frame(cm, Vec3::zeros());
    let form = Form::Ellipsoid { semi };
    if semi[0] == semi[1] && semi[1] == semi[2] {
        let ball = SharedShape::ball(semi[0]);
        return Ok((cm.part, Built::plain(frame, form, ball)));
    }
    let mut points = Vec::with_capacity(ELLIPSOID_RINGS * ELLIPSOID_SECTORS + 2);
    points.push(DVec3::new(0.0, 0.0, semi[2]));
    points.push(DVec3::new(0.0, 0.0, -semi[2]));
    for i in 1..ELLIPSOID_RINGS {
        let (st, ct) = (PI * i as f64 / ELLIPSOID_RINGS as f64).sin_cos();
        for k in 0..ELLIPSOID_SECTORS {
            let (sp, cp) = (2.0 * PI * k as f64 / ELLIPSOID_SECTORS as f64).sin_cos();
            points.push(DVec3::new(
                semi[0] * st * cp,
                semi[1] * st * sp,
                semi[2] * ct,
            ));
        }
    }
    let hull = SharedShape::convex_hull(&points)
        .ok_or_else(|| "its ellipsoid has no hull (degenerate sizes)".to_string())?;
    Ok((cm.part, Built::plain(frame, form, hull)))
}

/// A triangle mesh in RM's coordinates.
fn external(rm: &Marker, mesh: &TriMesh) -> Result<(Id, Built), String> {
    if mesh.triangles.is_empty() {
        return Err("its mesh has no triangles".into());
    }
    let n = mesh.vertices.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .find(|t| t.iter().any(|&v| v as usize >= n))
    {
        return Err(format!(
            "its mesh has a triangle {t:?} past its {n} vertices"
        ));
    }
    if mesh
        .vertices
        .iter()
        .any(|v| !v.iter().all(|c| c.is_finite()))
    {
        return Err("its mesh has a vertex that is not a finite number".into());
    }
    let vertices = mesh.vertices.iter().map(to_parry).collect();
    let flags = TriMeshFlags::MERGE_DUPLICATE_VERTICES | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES;
    let shape = SharedShape::trimesh_with_flags(vertices, mesh.triangles.clone(), flags)
        .map_err(|e| format!("its mesh is not a usable triangle mesh ({e:?})"))?;
    let (welded, triangles) = shape
        .as_trimesh()
        .map(|t| (t.vertices().to_vec(), t.indices().to_vec()))
        .unwrap_or_default();
    let frame = marker_frame(rm, Vec3::zeros());
    let closed = is_closed(&triangles);
    // A closed convex mesh (a placeholder box, a convex part) is its hull, exactly: a
    // solid, whose overlap with anything parry measures as deep as it goes. It is convex
    // when it encloses its hull's volume (to 10⁻⁹): O(n log n), not a plane test per
    // face and vertex.
    if closed {
        // A box (a placeholder's, a block's) is parry's cuboid: its contacts with
        // other boxes come from exact separating axes, where a general hull's face
        // normal carries GJK's round-off and a box resting on a box jitters.
        if let Some(cuboid) = box_of(&welded) {
            return Ok((
                rm.part,
                Built {
                    fix: cuboid.0,
                    ..Built::plain(frame, Form::Mesh, cuboid.1)
                },
            ));
        }
        if let Some(hull) = SharedShape::convex_hull(&welded) {
            let full = hull.mass_properties(1.0).mass();
            if (full - enclosed_volume(&welded, &triangles)).abs() <= 1e-9 * full {
                return Ok((rm.part, Built::plain(frame, Form::Mesh, hull)));
            }
        }
    }
    Ok((
        rm.part,
        Built {
            triangles,
            closed,
            ..Built::plain(frame, Form::Mesh, shape)
        },
    ))
}

/// Whether every edge of `triangles` is shared by exactly two of them.
fn is_closed(triangles: &[[u32; 3]]) -> bool {
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    !edges.is_empty() && edges.values().all(|&n| n == 2)
}

/// When the 8 `vertices` are a box's corners: its centre and axes (a rotation) and
/// the cuboid of its half extents there.
fn box_of(vertices: &[DVec3]) -> Option<(Pose, SharedShape)> {
    if vertices.len() != 8 {
        return None;
    }
    let v0 = vertices[0];
    let d: Vec<DVec3> = vertices[1..].iter().map(|v| *v - v0).collect();
    let size = d.iter().map(|e| e.length()).fold(0.0, f64::max);
    let tol = 1e-9 * size;
    for a in 0..7 {
        for b in a + 1..7 {
            for c in b + 1..7 {
                let e = [d[a], d[b], d[c]];
                let square = e[0].dot(e[1]).abs() <= tol * size
                    && e[1].dot(e[2]).abs() <= tol * size
                    && e[0].dot(e[2]).abs() <= tol * size;
                let corners = (0..8).all(|k| {
                    let corner = v0
                        + (0..3)
                            .filter(|i| k >> i & 1 == 1)
                            .map(|i| e[i])
                            .fold(DVec3::ZERO, |s, x| s + x);
                    vertices.iter().any(|v| (*v - corner).length() <= tol)
                });
                if !square || !corners || e.iter().any(|x| x.length() <= tol) {
                    continue;
                }
                let axis = |x: DVec3| Vec3::new(x.x, x.y, x.z).normalize();
                let (x, y) = (axis(e[0]), axis(e[1]));
                let centre = v0 + (e[0] + e[1] + e[2]) * 0.5;
                let fix = Pose {
                    r: Vec3::new(centre.x, centre.y, centre.z),
                    rot: Mat3::from_columns(&[x, y, x.cross(&y)]),
                };
                let half = e.map(|x| x.length() / 2.0);
                return Some((fix, SharedShape::cuboid(half[0], half[1], half[2])));
            }
        }
    }
    None
}

/// The volume `triangles` enclose (the divergence theorem; either winding), for a
/// closed mesh.
fn enclosed_volume(vertices: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    let six = triangles.iter().fold(0.0, |sum, t| {
        let [a, b, c] = t.map(|k| vertices[k as usize]);
        sum + a.dot(b.cross(c))
    });
    (six / 6.0).abs()
}

/// A radius given as a value, or as the distance from CM's z axis to RM (in the
/// dataset's initial configuration, as the model reads it).
fn radius_of(model: &Model, cm: Id, r: Radius) -> Option<f64> {
    match r {
        Radius::Value(v) => Some(v),
        Radius::Marker(rm) => {
            let (o, axes) = model.marker_pose(cm)?;
            let (p, _) = model.marker_pose(rm)?;
            let (d, z) = (p - o, axes.column(2).normalize());
            Some((d - z * d.dot(&z)).norm())
        }
    }
}
