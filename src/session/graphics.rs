//! A model's GRAPHICS statements as plain data, for shells that may name nothing of the
//! model ([`Listed`]: id, kind, view name, the part it is drawn on, its markers and its
//! kind's arguments by name). The values are the model's ([`crate::model::graphics`]) as
//! read: marker ids, lengths in model units, angles in radians; an optional argument the
//! dataset leaves out is [`Value::Absent`], so each kind always lists the same names.
//! Filled by [`super::check::check`]; the Python module shows it as `Model.graphics`.

use crate::model::graphics::{Facets, Graphic, Radius, Shape};
use crate::model::Model;

/// One argument's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A length, a scale or an angle (radians).
    Number(f64),
    /// A marker or element id, or a count (SIDES, SEG, COILS).
    Integer(u32),
    /// Marker ids in order (OUTLINE).
    Ids(Vec<u32>),
    /// A word or a file name as written (ETYPE, FILE, ELEMENT).
    Text(String),
    /// An optional argument the dataset does not give.
    Absent,
}

/// One GRAPHICS statement, listed.
#[derive(Clone, Debug, PartialEq)]
pub struct Listed {
    /// The Adams id.
    pub id: u32,
    /// The kind as Adams writes it (`CYLINDER`).
    pub kind: &'static str,
    /// The dataset's adams_view_name, where it has one.
    pub view_name: Option<String>,
    /// The part of its first marker (CORNER, CM, I, EMARKER, CRM, RM, an OUTLINE's
    /// first): where it is drawn. An OUTLINE or SPDP may reach other parts through
    /// [`Listed::markers`].
    pub part: Option<u32>,
    /// The markers it is placed by, the first one first (a RM that only sizes a radius
    /// is among [`Listed::values`], not here).
    pub markers: Vec<u32>,
    /// Its kind's arguments, named in lower case as the dataset writes them (`cm`,
    /// `length`, `radius`, `rm`, `sides`, ...), in the order of docs/models.md's table.
    pub values: Vec<(&'static str, Value)>,
}

/// The model's GRAPHICS statements in file order.
pub fn list(model: &Model) -> Vec<Listed> {
    model.graphics.iter().map(|g| listed(model, g)).collect()
}

fn listed(model: &Model, g: &Graphic) -> Listed {
    let (markers, values) = arguments(&g.shape);
    Listed {
        id: g.el.id,
        kind: g.shape.kind(),
        view_name: g.el.name.clone(),
        part: (markers.first()).and_then(|&m| model.marker(m).map(|m| m.part)),
        markers,
        values,
    }
}

fn int(x: Option<u32>) -> Value {
    x.map_or(Value::Absent, Value::Integer)
}

fn num(x: Option<f64>) -> Value {
    x.map_or(Value::Absent, Value::Number)
}

/// RADIUS or RM: the one given holds the value, the other is absent.
fn radius(r: &Radius) -> [(&'static str, Value); 2] {
    match *r {
        Radius::Value(x) => [("radius", Value::Number(x)), ("rm", Value::Absent)],
        Radius::Marker(m) => [("radius", Value::Absent), ("rm", Value::Integer(m))],
    }
}

fn facets(f: &Facets) -> [(&'static str, Value); 3] {
    [
        ("sides", int(f.sides)),
        ("seg", int(f.seg)),
        ("rangle", num(f.rangle)),
    ]
}

/// The placing markers and the named arguments of a shape.
fn arguments(shape: &Shape) -> (Vec<u32>, Vec<(&'static str, Value)>) {
    use Value::{Integer, Number, Text};
    match shape {
        Shape::Box { corner, extent } => (
            vec![*corner],
            vec![
                ("corner", Integer(*corner)),
                ("x", Number(extent[0])),
                ("y", Number(extent[1])),
                ("z", Number(extent[2])),
            ],
        ),
        Shape::Cylinder {
            cm,
            length,
            radius: r,
            facets: f,
        } => {
            let mut v = vec![("cm", Integer(*cm)), ("length", Number(*length))];
            v.extend(radius(r));
            v.extend(facets(f));
            (vec![*cm], v)
        }
        Shape::Frustum {
            cm,
            length,
            top,
            bottom,
            facets: f,
        } => {
            let mut v = vec![
                ("cm", Integer(*cm)),
                ("length", Number(*length)),
                ("top", Number(*top)),
                ("bottom", Number(*bottom)),
            ];
            v.extend(facets(f));
            (vec![*cm], v)
        }
        Shape::Ellipsoid { cm, scale } => (
            vec![*cm],
            vec![
                ("cm", Integer(*cm)),
                ("xscale", Number(scale[0])),
                ("yscale", Number(scale[1])),
                ("zscale", Number(scale[2])),
            ],
        ),
        Shape::Circle { cm, radius: r, seg } => {
            let mut v = vec![("cm", Integer(*cm))];
            v.extend(radius(r));
            v.push(("seg", int(*seg)));
            (vec![*cm], v)
        }
        Shape::Arc {
            cm,
            radius: r,
            facets: f,
        } => {
            let mut v = vec![("cm", Integer(*cm))];
            v.extend(radius(r));
            v.push(("rangle", num(f.rangle)));
            v.push(("seg", int(f.seg)));
            (vec![*cm], v)
        }
        Shape::Outline { markers } => (
            markers.clone(),
            vec![("outline", Value::Ids(markers.clone()))],
        ),
        Shape::SpringDamper {
            i,
            j,
            coils,
            da,
            db,
            dc,
            lc,
            ld,
        } => (
            vec![*i, *j],
            vec![
                ("i", Integer(*i)),
                ("j", Integer(*j)),
                ("coils", int(*coils)),
                ("da", num(*da)),
                ("db", num(*db)),
                ("dc", num(*dc)),
                ("lc", num(*lc)),
                ("ld", num(*ld)),
            ],
        ),
        Shape::Force {
            etype,
            eid,
            emarker,
        } => (
            vec![*emarker],
            vec![
                ("etype", Text((*etype).to_string())),
                ("eid", Integer(*eid)),
                ("emarker", Integer(*emarker)),
            ],
        ),
        Shape::Curve { cid, crm, seg } => (
            vec![*crm],
            vec![
                ("cid", Integer(*cid)),
                ("crm", Integer(*crm)),
                ("seg", int(*seg)),
            ],
        ),
        Shape::External {
            rm,
            file,
            element,
            faceting_tolerance,
        } => (
            vec![*rm],
            vec![
                ("rm", Integer(*rm)),
                ("file", Text(file.clone())),
                ("element", element.clone().map_or(Value::Absent, Text)),
                ("faceting_tolerance", num(*faceting_tolerance)),
            ],
        ),
        Shape::Plane { rm, x, y } => (
            vec![*rm],
            vec![
                ("rm", Integer(*rm)),
                ("xmin", Number(x[0])),
                ("xmax", Number(x[1])),
                ("ymin", Number(y[0])),
                ("ymax", Number(y[1])),
            ],
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dataset whose every line's values are read back from the text below.
    const ADM: &str = "graphics\n\
        PART/1, GROUND\n\
        MARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\n\
        MARKER/20, PART = 2\n\
        MARKER/21, PART = 2, QP = 0, 0.5, 0\n\
        SFORCE/5, TRANSLATION, I = 20, J = 10, FUNCTION = 0\n\
        GRAPHICS/1, CYLINDER, CM = 20, LENGTH = -2.5, RADIUS = 0.25, SIDES = 12\n\
        GRAPHICS/2, CIRCLE, CM = 20, RM = 21\n\
        GRAPHICS/3, OUTLINE = 10, 20, 21\n\
        GRAPHICS/4, FORCE, ETYPE = SFORCE, EID = 5, EMARKER = 20\n\
        GRAPHICS/5, EXTERNAL, RM = 10, FILE = body.x_t\n\
        END\n";

    #[test]
    fn each_kind_lists_its_arguments_as_written() {
        let read = crate::model::read_model(ADM);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let l = list(&read.model);
        assert_eq!(l.iter().map(|g| g.id).collect::<Vec<_>>(), [1, 2, 3, 4, 5]);
        assert_eq!(
            (l[0].kind, l[0].part, l[0].markers.as_slice()),
            ("CYLINDER", Some(2), &[20][..])
        );
        assert_eq!(
            l[0].values,
            [
                ("cm", Value::Integer(20)),
                ("length", Value::Number(-2.5)),
                ("radius", Value::Number(0.25)),
                ("rm", Value::Absent),
                ("sides", Value::Integer(12)),
                ("seg", Value::Absent),
                ("rangle", Value::Absent),
            ]
        );
        assert_eq!(
            l[1].values[1..3],
            [("radius", Value::Absent), ("rm", Value::Integer(21))]
        );
        // An OUTLINE drawn from ground to part 2: on the part of its first marker.
        assert_eq!(
            (l[2].part, l[2].markers.as_slice()),
            (Some(1), &[10, 20, 21][..])
        );
        assert_eq!(l[3].values[0], ("etype", Value::Text("SFORCE".into())));
        assert_eq!(l[4].values[1], ("file", Value::Text("body.x_t".into())));
        assert_eq!(l[4].values[2], ("element", Value::Absent));
    }
}
