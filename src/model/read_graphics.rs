//! The reader of GRAPHICS statements (see [`super::graphics`]): the kind flag picks the
//! shape, each argument is read with Adams' abbreviations, and the checks are those of
//! any other statement: markers and elements that exist (`E0311`), required arguments
//! (`E0604`), no negative radius or scale and an OUTLINE of two points at least
//! (`E0605`), a PLANE's minimum below its maximum (`E0605`). A GRAPHICS kind not in
//! [`KINDS`] (the contact geometry POINT, ...) stays outside the subset and is
//! summarised as such by the reader.

use super::elements::Id;
use super::graphics::{Facets, Graphic, Radius, Shape};
use super::keywords::{abbreviates, lookup_statement, Lookup};
use super::reader::Reader;
use super::resolve::MarkerUse;
use super::statement::Statement;
use super::stmt_args::Args;
use crate::diag::{Code, Diagnostic, Span};

/// The GRAPHICS kinds mbfx reads, with their shortest accepted abbreviation.
pub(super) const KINDS: &[(&str, usize)] = &[
    ("ARC", 3),
    ("BOX", 3),
    ("CIRCLE", 3),
    ("CURVE", 3),
    ("CYLINDER", 3),
    ("ELLIPSOID", 3),
    ("EXTERNAL", 3),
    ("FORCE", 3),
    ("FRUSTUM", 3),
    ("OUTLINE", 3),
    ("PLANE", 3),
    ("SPDP", 4),
];

/// True when the GRAPHICS statement names a kind of [`KINDS`].
pub(super) fn is_read(stmt: &Statement) -> bool {
    stmt.args
        .iter()
        .any(|a| KINDS.iter().any(|&(k, min)| abbreviates(&a.name, k, min)))
}

/// Reads one GRAPHICS statement of a kind in [`KINDS`] into `model.graphics`.
pub fn graphics(r: &mut Reader, a: &mut Args) {
    let el = r.named(a);
    let Some(k) = a.choice(KINDS) else {
        return;
    };
    let shape = match KINDS[k].0 {
        "ARC" => arc(r, a),
        "BOX" => box_shape(r, a),
        "CIRCLE" => circle(r, a),
        "CURVE" => curve(r, a),
        "CYLINDER" => cylinder(r, a),
        "ELLIPSOID" => ellipsoid(r, a),
        "EXTERNAL" => external(r, a),
        "FORCE" => force(r, a),
        "FRUSTUM" => frustum(r, a),
        "OUTLINE" => outline(r, a),
        "PLANE" => plane(r, a),
        _ => spring_damper(r, a),
    };
    if let Some(shape) = shape {
        r.model.graphics.push(Graphic { el, shape });
    }
}

/// A marker the statement cannot do without; any marker will do (fixed or floating).
/// A marker not on a rigid PART (a flexible body's node, ...) is warned about where it
/// is defined; the graphic keeps its id, the drawing step cannot place it.
fn marker(r: &mut Reader, a: &mut Args, full: &str, min: usize) -> Option<Id> {
    let written = (a.stmt.arg(full, min))
        .and_then(|arg| arg.items().first())
        .and_then(|item| item.as_integer());
    if written.is_some_and(|id| r.foreign_markers.contains(&id)) {
        return a.id(full, min).map(|(id, _)| id);
    }
    r.marker_ref(a, full, min, MarkerUse::Any, true)
        .map(|(id, _)| id)
}

/// Whether the dataset defines `kind`/`id` (any kind with ids, read or not).
fn defined(r: &Reader, kind: &str, id: Id) -> bool {
    r.scope.has(kind, i64::from(id))
}

/// `E0311` at the reference to `kind`/`id`, which the dataset does not define.
fn undefined(a: &mut Args, kind: &str, id: Id, span: Span, note: String) {
    let msg = format!("{kind}/{id} is not defined in this dataset");
    a.diags
        .push(Diagnostic::error(Code::UndefinedElement, span, msg).with_note(note));
}

/// A radius, diameter or scale: `E0605` at the argument when negative.
fn size(a: &mut Args, full: &str, min: usize, need: bool) -> Option<f64> {
    let arg = a.stmt.arg(full, min);
    let v = if need {
        a.required_number(full, min)?
    } else {
        a.number(full, min)?
    };
    if v < 0.0 {
        let span = arg.map_or(a.stmt.keyword_span.clone(), |arg| arg.span.clone());
        let msg = format!("{full} of {} is negative ({v})", a.label);
        a.diags.push(
            Diagnostic::error(Code::BadArgument, span, msg)
                .with_help("a radius, diameter or scale is zero or more"),
        );
        return None;
    }
    Some(v)
}

/// A count (SIDES, SEG, COILS): a whole number, zero or more.
fn count(a: &mut Args, full: &str, min: usize) -> Option<u32> {
    let arg = a.stmt.arg(full, min);
    let v = a.number(full, min)?;
    if v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) {
        return Some(v as u32);
    }
    let span = arg.map_or(a.stmt.keyword_span.clone(), |arg| arg.span.clone());
    let msg = format!(
        "{full} of {} is a count: a whole number, found {v}",
        a.label
    );
    a.error(Code::BadArgument, span, msg);
    None
}

fn facets(a: &mut Args) -> Facets {
    Facets {
        sides: count(a, "SIDES", 3),
        seg: count(a, "SEG", 3),
        rangle: a.number("RANGLE", 3),
    }
}

/// RADIUS = r, or RM = id (the distance from CM's z axis to that marker).
fn radius(r: &mut Reader, a: &mut Args) -> Option<Radius> {
    if a.stmt.arg("RADIUS", 3).is_some() {
        return size(a, "RADIUS", 3, true).map(Radius::Value);
    }
    if a.stmt.arg("RM", 2).is_some() {
        return marker(r, a, "RM", 2).map(Radius::Marker);
    }
    a.missing("RADIUS = r or RM = id");
    None
}

fn box_shape(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let corner = marker(r, a, "CORNER", 3);
    let x = a.required_number("X", 1);
    let y = a.required_number("Y", 1);
    let z = a.required_number("Z", 1);
    Some(Shape::Box {
        corner: corner?,
        extent: [x?, y?, z?],
    })
}

fn cylinder(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let cm = marker(r, a, "CM", 2);
    let length = a.required_number("LENGTH", 3);
    let radius = radius(r, a);
    let facets = facets(a);
    Some(Shape::Cylinder {
        cm: cm?,
        length: length?,
        radius: radius?,
        facets,
    })
}

fn frustum(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let cm = marker(r, a, "CM", 2);
    let length = a.required_number("LENGTH", 3);
    let top = size(a, "TOP", 2, true);
    let bottom = size(a, "BOTTOM", 2, true);
    let facets = facets(a);
    Some(Shape::Frustum {
        cm: cm?,
        length: length?,
        top: top?,
        bottom: bottom?,
        facets,
    })
}

fn ellipsoid(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let cm = marker(r, a, "CM", 2);
    let x = size(a, "XSCALE", 2, true);
    let y = size(a, "YSCALE", 2, true);
    let z = size(a, "ZSCALE", 2, true);
    Some(Shape::Ellipsoid {
        cm: cm?,
        scale: [x?, y?, z?],
    })
}

fn circle(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let cm = marker(r, a, "CM", 2);
    let radius = radius(r, a);
    let seg = count(a, "SEG", 3);
    Some(Shape::Circle {
        cm: cm?,
        radius: radius?,
        seg,
    })
}

fn arc(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let cm = marker(r, a, "CM", 2);
    let radius = radius(r, a);
    let facets = facets(a);
    Some(Shape::Arc {
        cm: cm?,
        radius: radius?,
        facets,
    })
}

/// `OUTLINE = id1, id2, ...`: every marker must exist; two at least.
fn outline(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let arg = a.stmt.arg("OUTLINE", 3)?;
    let mut markers = Vec::new();
    let mut ok = true;
    for item in arg.items() {
        let Some(id) = item.as_integer().and_then(|v| Id::try_from(v).ok()) else {
            let msg = format!("OUTLINE: expected a marker id, found `{}`", item.text);
            a.error(Code::BadArgument, item.span.clone(), msg);
            ok = false;
            continue;
        };
        if r.marker(id).is_none() && !r.foreign_markers.contains(&i64::from(id)) {
            let note = format!("OUTLINE of {} names it", a.label);
            undefined(a, "MARKER", id, item.span.clone(), note);
            ok = false;
        }
        markers.push(id);
    }
    if arg.items().len() < 2 {
        let msg = format!(
            "the OUTLINE of {} has {} point{}; an outline joins two or more markers",
            a.label,
            arg.items().len(),
            if arg.items().len() == 1 { "" } else { "s" }
        );
        a.error(Code::BadArgument, arg.span.clone(), msg);
        return None;
    }
    ok.then_some(Shape::Outline { markers })
}

fn spring_damper(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let i = marker(r, a, "I", 1);
    let j = marker(r, a, "J", 1);
    let coils = count(a, "COILS", 2);
    let da = size(a, "DA", 2, false);
    let db = size(a, "DB", 2, false);
    let dc = size(a, "DC", 2, false);
    let lc = size(a, "LC", 2, false);
    let ld = size(a, "LD", 2, false);
    Some(Shape::SpringDamper {
        i: i?,
        j: j?,
        coils,
        da,
        db,
        dc,
        lc,
        ld,
    })
}

/// `ETYPE = kind, EID = id, EMARKER = id`: the element must exist in the dataset (of any
/// kind with ids, read or not).
fn force(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let present = a.stmt.arg("ETYPE", 2).is_some();
    let etype = a.word("ETYPE", 2);
    if !present {
        a.missing("ETYPE = kind");
    }
    let eid = a.required_id("EID", 2);
    let emarker = marker(r, a, "EMARKER", 2);
    let (written, etype_span) = etype?;
    let kind = match lookup_statement(written) {
        Lookup::Known(k) if k.has_id => k.keyword.name,
        _ => {
            let msg = format!("ETYPE of {}: `{written}` is not an element kind", a.label);
            a.error(Code::BadArgument, etype_span, msg);
            return None;
        }
    };
    let (eid, span) = eid?;
    if !defined(r, kind, eid) {
        let note = format!("the FORCE graphic {} draws it", a.label);
        undefined(a, kind, eid, span, note);
        return None;
    }
    Some(Shape::Force {
        etype: kind,
        eid,
        emarker: emarker?,
    })
}

/// `CID = id, CRM = id`: CURVE/CID drawn in the frame of marker CRM.
fn curve(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let cid = a.required_id("CID", 3);
    let crm = marker(r, a, "CRM", 3);
    let seg = count(a, "SEG", 3);
    let (cid, span) = cid?;
    if !defined(r, "CURVE", cid) {
        let note = format!("CID of {} names it", a.label);
        undefined(a, "CURVE", cid, span, note);
        return None;
    }
    Some(Shape::Curve {
        cid,
        crm: crm?,
        seg,
    })
}

/// `RM = id, FILE = name[, ELEMENT = name][, FACETING_TOLERANCE = r]`: kept as written.
fn external(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let rm = marker(r, a, "RM", 2);
    let file = a.find("FILE", 3).and_then(|arg| {
        let (first, last) = (arg.items().first()?, arg.items().last()?);
        r.text
            .get(first.span.start..last.span.end)
            .map(|t| t.trim().trim_matches('"').to_string())
    });
    if file.is_none() {
        a.missing("FILE = name");
    }
    let element = a.word("ELEMENT", 3).map(|(w, _)| w.to_string());
    let faceting_tolerance = a.number("FACETING_TOLERANCE", 3);
    Some(Shape::External {
        rm: rm?,
        file: file?,
        element,
        faceting_tolerance,
    })
}

/// `RM = id, XMIN = r, XMAX = r, YMIN = r, YMAX = r`: a rectangle in RM's x-y plane; each
/// minimum below its maximum (`E0605` at the maximum).
fn plane(r: &mut Reader, a: &mut Args) -> Option<Shape> {
    let rm = marker(r, a, "RM", 2);
    let mut range = |lo: &str, hi: &str| {
        let (min, max) = (a.required_number(lo, 4), a.required_number(hi, 4));
        let (min, max) = (min?, max?);
        if min < max {
            return Some([min, max]);
        }
        let span = (a.stmt.arg(hi, 4)).map_or(a.stmt.keyword_span.clone(), |arg| arg.span.clone());
        let msg = format!("{hi} of {} is not above {lo} ({max} ≤ {min})", a.label);
        a.error(Code::BadArgument, span, msg);
        None
    };
    let x = range("XMIN", "XMAX");
    let y = range("YMIN", "YMAX");
    Some(Shape::Plane {
        rm: rm?,
        x: x?,
        y: y?,
    })
}
