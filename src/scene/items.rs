//! One item per GRAPHICS statement, on the part of its reference marker at that marker's
//! pose (docs/models.md "GRAPHICS" for each argument's convention): the solids, PLANE's
//! rectangle, circles and arcs; OUTLINE's segments (rigid on one part, stretching between two); SPDP as a
//! stretching spring and damper; FORCE as an arrow. CURVE and EXTERNAL are left to the
//! caller (CURVE data is not read; EXTERNAL needs `--geometry`). A graphic whose values
//! give nothing to draw (a zero radius, an unknown marker) is left out with a note.

use super::canvas::Canvas;
use super::curves::{arc, circle, segments, unit_line, DEFAULT_SEG};
use super::solids::{cuboid, ellipsoid, frustum, rectangle, DEFAULT_SIDES, ELLIPSOID_SLICES};
use super::spring::{damper, helix, DEFAULT_COILS};
use super::tessellate::{facets, finite, Builder};
use super::{Anchor, ArrowSource, Item, Mesh, Motion, Pose, Role};
use crate::model::graphics::{Facets, Graphic, Radius, Shape};
use crate::vocab::math::Vec3;
use std::collections::BTreeMap;
use std::f64::consts::TAU;

/// What drawing a graphic left for later.
pub enum Later {
    /// Nothing: it is drawn (or left out with a note).
    Nothing,
    /// A FORCE arrow at this anchor on this part, whose mesh waits for the extent.
    Arrow(Anchor),
}

/// Draws `g` (every kind but CURVE and EXTERNAL).
pub fn draw(c: &mut Canvas, g: &Graphic) -> Later {
    let name = format!("GRAPHICS/{}", g.el.id);
    let result = match &g.shape {
        Shape::Box { corner, extent } => {
            solid(c, g, *corner, |_| finite(extent).then(|| cuboid(*extent)))
        }
        Shape::Cylinder {
            cm,
            length,
            radius,
            facets: f,
        } => solid(c, g, *cm, |c| {
            let r = radius_of(c, *cm, *radius)?;
            round(*length, r, r, f)
        }),
        Shape::Frustum {
            cm,
            length,
            top,
            bottom,
            facets: f,
        } => solid(c, g, *cm, |_| round(*length, *bottom, *top, f)),
        Shape::Ellipsoid { cm, scale } => solid(c, g, *cm, |_| {
            // XSCALE.. are diameters (MotionSolve's Ellipsoid, which mirrors Adams').
            let semi = scale.map(|s| s / 2.0);
            let ok = semi.iter().all(|s| *s > 0.0 && s.is_finite());
            ok.then(|| ellipsoid(semi, ELLIPSOID_SLICES))
        }),
        Shape::Circle { cm, radius, seg } => line(c, g, *cm, |c, color| {
            let r = radius_of(c, *cm, *radius)?;
            circle(r, facets(*seg, DEFAULT_SEG), color)
        }),
        Shape::Arc {
            cm,
            radius,
            facets: f,
        } => line(c, g, *cm, |c, color| {
            let r = radius_of(c, *cm, *radius)?;
            arc(
                r,
                facets(f.seg, DEFAULT_SEG),
                f.rangle.unwrap_or(TAU),
                color,
            )
        }),
        Shape::Outline { markers } => outline(c, g, markers),
        Shape::SpringDamper {
            i,
            j,
            coils,
            da,
            db,
            dc,
            lc,
            ld,
        } => spdp(
            c,
            g,
            (*i, *j),
            coils.unwrap_or(DEFAULT_COILS),
            [*da, *db, *dc, *lc, *ld],
        ),
        Shape::Force {
            etype,
            eid,
            emarker,
        } => {
            return match c.anchor(*emarker) {
                Some(at) => {
                    c.scene.arrows.push(ArrowSource {
                        etype,
                        eid: *eid,
                        emarker: *emarker,
                    });
                    Later::Arrow(at)
                }
                None => {
                    c.note(format!(
                        "{name} (FORCE) not drawn: MARKER/{emarker} is not on a part"
                    ));
                    Later::Nothing
                }
            }
        }
        // A PLANE is drawn as its rectangle, both faces (it is seen from either side).
        Shape::Plane { rm, x, y } => solid(c, g, *rm, |_| {
            let lo = Vec3::new(x[0], y[0], 0.0);
            let hi = Vec3::new(x[1], y[1], 0.0);
            finite(&[x[0], x[1], y[0], y[1]]).then(|| rectangle(lo, hi))
        }),
        Shape::Curve { .. } | Shape::External { .. } => Ok(()),
    };
    if let Err(why) = result {
        c.note(format!("{name} ({}) not drawn: {why}", g.shape.kind()));
    }
    Later::Nothing
}

/// The item of arrow number `arrow` at `at`, showing `mesh`.
pub fn arrow_item(c: &mut Canvas, g: &Graphic, at: Anchor, arrow: usize, mesh: usize) {
    let motion = Motion::Arrow { at, arrow };
    let name = format!("GRAPHICS/{}", g.el.id);
    moving(c, g, name, at.part, mesh, Role::Arrow, motion);
}

/// A radius given as a value, or as the distance from CM's z axis to RM at the input.
fn radius_of(c: &Canvas, cm: u32, r: Radius) -> Option<f64> {
    match r {
        Radius::Value(v) => Some(v),
        Radius::Marker(rm) => {
            let (o, axes) = c.model.marker_pose(cm)?;
            let (p, _) = c.model.marker_pose(rm)?;
            let (d, z) = (p - o, axes.column(2).normalize());
            Some((d - z * d.dot(&z)).norm())
        }
    }
}

/// A cylinder or frustum mesh; `None` for no size.
fn round(length: f64, bottom: f64, top: f64, f: &Facets) -> Option<Builder> {
    // LENGTH = 0 is a disc (the corpus has such "cylinders"): its two faces.
    let ok = finite(&[length, bottom, top]) && bottom.max(top) > 0.0;
    let ok = ok && bottom >= 0.0 && top >= 0.0;
    let sweep = f.rangle.unwrap_or(TAU);
    let sweep = if sweep.is_finite() && sweep > 0.0 {
        sweep
    } else {
        TAU
    };
    ok.then(|| frustum(length, bottom, top, facets(f.sides, DEFAULT_SIDES), sweep))
}

/// A solid on `marker`'s part at its pose, its mesh from `mesh` (`None`: no size).
fn solid(
    c: &mut Canvas,
    g: &Graphic,
    marker: u32,
    mesh: impl FnOnce(&Canvas) -> Option<Builder>,
) -> Result<(), String> {
    let (part, local) = c.marker_pose(marker).ok_or_else(|| unknown(marker))?;
    let b = mesh(c)
        .filter(|b| !b.is_empty())
        .ok_or("its size is zero or not a number")?;
    let m = b.triangles(c.color(part));
    let name = format!("GRAPHICS/{}", g.el.id);
    c.rigid(name, g.el.name.clone(), part, local, m, Role::Graphic);
    Ok(())
}

/// A line shape on `marker`'s part at its pose.
fn line(
    c: &mut Canvas,
    g: &Graphic,
    marker: u32,
    mesh: impl FnOnce(&Canvas, [f32; 4]) -> Option<Mesh>,
) -> Result<(), String> {
    let (part, local) = c.marker_pose(marker).ok_or_else(|| unknown(marker))?;
    let m = mesh(c, c.color(part))
        .filter(|m| m.positions.iter().any(|p| *p != m.positions[0]))
        .ok_or("its radius is zero or not a number")?;
    let name = format!("GRAPHICS/{}", g.el.id);
    c.rigid(name, g.el.name.clone(), part, local, m, Role::Graphic);
    Ok(())
}

fn unknown(marker: u32) -> String {
    format!("MARKER/{marker} is not on a part")
}

/// OUTLINE: the segments between markers on one part as one rigid item per part (in
/// its BCS), each segment between two parts as a stretching unit line.
fn outline(c: &mut Canvas, g: &Graphic, markers: &[u32]) -> Result<(), String> {
    let mut on_part: BTreeMap<usize, Vec<(Vec3, Vec3)>> = BTreeMap::new();
    let mut across = Vec::new();
    for (k, pair) in markers.windows(2).enumerate() {
        let a = c.marker(pair[0]).ok_or_else(|| unknown(pair[0]))?;
        let b = c.marker(pair[1]).ok_or_else(|| unknown(pair[1]))?;
        if a.0 == b.0 {
            on_part.entry(a.0).or_default().push((a.1, b.1));
        } else {
            let end = |(part, p, _): (usize, Vec3, _)| Anchor {
                part,
                point: [p.x, p.y, p.z],
            };
            across.push((k + 1, pair, end(a), end(b)));
        }
    }
    let base = format!("GRAPHICS/{}", g.el.id);
    let alone = across.is_empty() && on_part.len() == 1;
    for (part, segs) in on_part {
        let Some(mesh) = segments(&segs, c.color(part)) else {
            continue;
        };
        let name = match alone {
            true => base.clone(),
            false => format!("{base} on PART/{}", c.scene.parts[part].id),
        };
        c.rigid(
            name,
            g.el.name.clone(),
            part,
            Pose::IDENTITY,
            mesh,
            Role::Graphic,
        );
    }
    for (k, pair, from, to) in across {
        let mesh = c.mesh(unit_line(c.color(from.part)));
        let name = format!(
            "{base} segment {k} (MARKER/{} to MARKER/{})",
            pair[0], pair[1]
        );
        let motion = Motion::Stretch { from, to };
        moving(c, g, name, from.part, mesh, Role::Graphic, motion);
    }
    Ok(())
}

/// SPDP: the helix and the damper as stretching items from I to J.
fn spdp(
    c: &mut Canvas,
    g: &Graphic,
    (i, j): (u32, u32),
    coils: u32,
    [da, db, dc, lc, ld]: [Option<f64>; 5],
) -> Result<(), String> {
    let from = c.anchor(i).ok_or_else(|| unknown(i))?;
    let to = c.anchor(j).ok_or_else(|| unknown(j))?;
    let (pi, _) = c.model.marker_pose(i).ok_or_else(|| unknown(i))?;
    let (pj, _) = c.model.marker_pose(j).ok_or_else(|| unknown(j))?;
    let length = (pj - pi).norm();
    // DA when absent: a tenth of the input length (chosen).
    let da = da.unwrap_or(length / 10.0);
    let fraction = |h: Option<f64>| match length > 0.0 {
        true => h.unwrap_or(0.0) / length,
        false => 0.0,
    };
    let color = c.color(from.part);
    let spring = helix(coils, da, color);
    let dampers = damper(
        (db.unwrap_or(0.0), fraction(lc)),
        (dc.unwrap_or(0.0), fraction(ld)),
        color,
    );
    if spring.is_none() && dampers.is_none() {
        return Err("no coil and no damper of positive size".into());
    }
    let base = format!("GRAPHICS/{}", g.el.id);
    for (mesh, name) in [(spring, base.clone()), (dampers, format!("{base} damper"))] {
        if let Some(mesh) = mesh {
            let mesh = c.mesh(mesh);
            let motion = Motion::Stretch { from, to };
            moving(c, g, name, from.part, mesh, Role::Graphic, motion);
        }
    }
    Ok(())
}

/// Adds an item of `g` that moves by `motion` (not with its part alone).
fn moving(
    c: &mut Canvas,
    g: &Graphic,
    name: String,
    part: usize,
    mesh: usize,
    role: Role,
    motion: Motion,
) {
    c.item(Item {
        name,
        view_name: g.el.name.clone(),
        part,
        local: Pose::IDENTITY,
        mesh,
        role,
        motion,
    });
}
