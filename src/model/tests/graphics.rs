//! GRAPHICS statements read into `Model::graphics`: one small dataset per kind, each
//! error at its place, and a census of the corpus whose per-kind totals come from a grep
//! of the corpus files (not from this reader).

use super::corpus_files::adm_files;
use crate::diag::Diagnostic;
use crate::model::graphics::{counts_by_kind, Facets, Radius, Shape};
use crate::model::{decode, read_model, read_statements, ModelRead};
use std::collections::BTreeMap;
use std::path::Path;

const BASE: &str = "graphics\n\
PART/1, GROUND\n\
MARKER/11, PART=1\n\
MARKER/12, PART=1, QP=1,0,0\n\
PART/2, MASS=1, CM=21, IP=1,1,1\n\
MARKER/21, PART=2\n\
MARKER/22, PART=2, QP=0,1,0\n\
SFORCE/5, I=21, J=11, FUNCTION=0\n\
CURVE/7, MATRIX=1\n";

fn read(extra: &str) -> (String, ModelRead) {
    let text = format!("{BASE}{extra}\nEND\n");
    let r = read_model(&text);
    (text, r)
}

/// The one shape of a dataset whose GRAPHICS statements read without errors or warnings
/// about them.
fn shape(extra: &str) -> Shape {
    let (_, r) = read(extra);
    let about: Vec<&Diagnostic> = (r.diagnostics.iter())
        .filter(|d| d.is_error() || d.message.contains("GRAPHICS"))
        .collect();
    assert!(about.is_empty(), "{extra}: {about:#?}");
    assert_eq!(r.model.graphics.len(), 1, "{extra}");
    r.model.graphics[0].shape.clone()
}

/// The errors of a dataset as (code, message, line, text under the span).
fn errors(extra: &str) -> Vec<(String, String, usize, String)> {
    let (text, r) = read(extra);
    (r.diagnostics.iter())
        .filter(|d| d.is_error())
        .map(|d| {
            let line = text[..d.span.start].matches('\n').count() + 1;
            (
                d.code.as_str().to_string(),
                d.message.clone(),
                line,
                text[d.span.clone()].to_string(),
            )
        })
        .collect()
}

/// The line of `extra` (its first line) in the dataset.
const LINE: usize = 10;

#[test]
fn every_kind_reads_its_arguments() {
    assert_eq!(
        shape("GRAPHICS/1, BOX, COR = 11, X = 50, Y = -50, Z = 200"),
        Shape::Box {
            corner: 11,
            extent: [50.0, -50.0, 200.0]
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, CYLINDER, CM = 21, LENGTH = -0.6, SIDES = 3, RADIUS = 0.05, SEG = 4, RANGLE = 90D"),
        Shape::Cylinder {
            cm: 21,
            length: -0.6,
            radius: Radius::Value(0.05),
            facets: Facets {
                sides: Some(3),
                seg: Some(4),
                rangle: Some(std::f64::consts::FRAC_PI_2)
            }
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, FRUSTUM, CM = 21, LENGTH = 0.15, SIDES = 18, TOP = 0.17, BOTTOM = 0.34, SEG = 18"),
        Shape::Frustum {
            cm: 21,
            length: 0.15,
            top: 0.17,
            bottom: 0.34,
            facets: Facets {
                sides: Some(18),
                seg: Some(18),
                rangle: None
            }
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, ELLIPSOID, CM = 21, XS = 1, YS = 2, ZSCALE = 3"),
        Shape::Ellipsoid {
            cm: 21,
            scale: [1.0, 2.0, 3.0]
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, CIRCLE, CM = 21, RADIUS = 0.5, SEG = 18"),
        Shape::Circle {
            cm: 21,
            radius: Radius::Value(0.5),
            seg: Some(18)
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, CIRCLE, CM = 21, RM = 22"),
        Shape::Circle {
            cm: 21,
            radius: Radius::Marker(22),
            seg: None
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, ARC, CM = 21, RADIUS = 2, RANGLE = 180D, SEG = 9"),
        Shape::Arc {
            cm: 21,
            radius: Radius::Value(2.0),
            facets: Facets {
                sides: None,
                seg: Some(9),
                rangle: Some(std::f64::consts::PI)
            }
        }
    );
    // Markers on two parts, and back to the first point.
    assert_eq!(
        shape("GRAPHICS/1, OUTLINE = 11, 21, 22, 11"),
        Shape::Outline {
            markers: vec![11, 21, 22, 11]
        }
    );
    assert_eq!(
        shape(
            "GRAPHICS/1, SPDP, I = 21, J = 11, COILS = 0, DB = 1.7, DC = 1.4, LC = 11.8, LD = 11.9"
        ),
        Shape::SpringDamper {
            i: 21,
            j: 11,
            coils: Some(0),
            da: None,
            db: Some(1.7),
            dc: Some(1.4),
            lc: Some(11.8),
            ld: Some(11.9)
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, FORCE, ETYPE = SFORCE, EID = 5, EMARKER = 21"),
        Shape::Force {
            etype: "SFORCE",
            eid: 5,
            emarker: 21
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, CURVE, CID = 7, CRM = 21"),
        Shape::Curve {
            cid: 7,
            crm: 21,
            seg: None
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, EXTERNAL, RM = 21, FILE = test_2.x_t, ELEMENT = SOLID1, FACETING_TOLERANCE = 300.0028"),
        Shape::External {
            rm: 21,
            file: "test_2.x_t".into(),
            element: Some("SOLID1".into()),
            faceting_tolerance: Some(300.0028)
        }
    );
    assert_eq!(
        shape("GRAPHICS/1, PLANE, RM = 21, XMIN = -1, XMAX = 2.5, YMIN = -3, YMAX = 0.5"),
        Shape::Plane {
            rm: 21,
            x: [-1.0, 2.5],
            y: [-3.0, 0.5]
        }
    );
}

#[test]
fn the_report_counts_graphics_by_kind() {
    let (_, r) = read(
        "GRAPHICS/1, CYLINDER, CM = 21, LENGTH = 1, RADIUS = 1\n\
         GRAPHICS/2, BOX, CORNER = 11, X = 1, Y = 1, Z = 1\n\
         GRAPHICS/3, CYLINDER, CM = 11, LENGTH = 1, RADIUS = 1",
    );
    let lines = crate::model::report::summary(&r.model).lines;
    assert!(
        lines.iter().any(|l| l == "graphics: 2 CYLINDER, 1 BOX"),
        "{lines:#?}"
    );
}

#[test]
fn an_unknown_marker_is_an_error_at_the_id() {
    assert_eq!(
        errors("GRAPHICS/1, CYLINDER, CM = 99, LENGTH = 1, RADIUS = 1"),
        [(
            "E0311".into(),
            "MARKER/99 is not defined in this dataset".into(),
            LINE,
            "99".into()
        )]
    );
    assert_eq!(
        errors("GRAPHICS/1, OUTLINE = 11, 98, 21"),
        [(
            "E0311".into(),
            "MARKER/98 is not defined in this dataset".into(),
            LINE,
            "98".into()
        )]
    );
}

#[test]
fn a_negative_radius_or_scale_is_an_error_at_the_argument() {
    assert_eq!(
        errors("GRAPHICS/1, CIRCLE, CM = 21, RADIUS = -2"),
        [(
            "E0605".into(),
            "RADIUS of GRAPHICS/1 is negative (-2)".into(),
            LINE,
            "RADIUS = -2".into()
        )]
    );
    assert_eq!(
        errors("GRAPHICS/3, ELLIPSOID, CM = 21, XSCALE = 1, YSCALE = 1,\n, ZSCALE = -1"),
        [(
            "E0605".into(),
            "ZSCALE of GRAPHICS/3 is negative (-1)".into(),
            LINE + 1,
            "ZSCALE = -1".into()
        )]
    );
}

#[test]
fn an_outline_of_one_point_is_an_error() {
    assert_eq!(
        errors("GRAPHICS/1, OUTLINE = 11"),
        [(
            "E0605".into(),
            "the OUTLINE of GRAPHICS/1 has 1 point; an outline joins two or more markers".into(),
            LINE,
            "OUTLINE = 11".into()
        )]
    );
}

#[test]
fn a_force_graphic_of_a_missing_element_is_an_error_at_its_id() {
    assert_eq!(
        errors("GRAPHICS/1, FORCE, ETYPE = SFORCE, EID = 6, EMARKER = 21"),
        [(
            "E0311".into(),
            "SFORCE/6 is not defined in this dataset".into(),
            LINE,
            "6".into()
        )]
    );
    assert_eq!(
        errors("GRAPHICS/1, FORCE, ETYPE = BUSHING, EID = 5, EMARKER = 21"),
        [(
            "E0311".into(),
            "BUSHING/5 is not defined in this dataset".into(),
            LINE,
            "5".into()
        )]
    );
}

#[test]
fn a_missing_required_argument_is_an_error_at_the_keyword() {
    assert_eq!(
        errors("GRAPHICS/1, CYLINDER, CM = 21, RADIUS = 1"),
        [(
            "E0604".into(),
            "GRAPHICS/1 needs LENGTH = value".into(),
            LINE,
            "GRAPHICS".into()
        )]
    );
    assert_eq!(
        errors("GRAPHICS/1, CIRCLE, CM = 21"),
        [(
            "E0604".into(),
            "GRAPHICS/1 needs RADIUS = r or RM = id".into(),
            LINE,
            "GRAPHICS".into()
        )]
    );
    assert_eq!(
        errors("GRAPHICS/1, BOX, X = 1, Y = 1, Z = 1"),
        [(
            "E0604".into(),
            "GRAPHICS/1 needs CORNER = id".into(),
            LINE,
            "GRAPHICS".into()
        )]
    );
}

#[test]
fn an_argument_a_graphic_does_not_take_is_a_warning_at_it() {
    let (text, r) = read("GRAPHICS/1, CIRCLE, CM = 21, RADIUS = 1, COLOR = 3");
    assert!(!r.has_errors(), "{:#?}", r.diagnostics);
    let w: Vec<&Diagnostic> = (r.diagnostics.iter())
        .filter(|d| d.code.as_str() == "W0602" && d.message.contains("GRAPHICS"))
        .collect();
    assert_eq!(w.len(), 1, "{w:#?}");
    assert_eq!(&text[w[0].span.clone()], "COLOR");
    assert_eq!(r.model.graphics.len(), 1);
}

#[test]
fn an_unknown_graphics_kind_stays_outside_the_subset() {
    let (_, r) = read("GRAPHICS/1, POINT, RM = 21");
    assert!(r.model.graphics.is_empty());
    let ignored: Vec<_> = (r.model.ignored.iter())
        .filter(|i| i.kind == "GRAPHICS")
        .map(|i| (i.count(), i.line()))
        .collect();
    assert_eq!(ignored, [(1, LINE)]);
    assert!((r.diagnostics.iter())
        .any(|d| d.message == "GRAPHICS is outside the mbfx subset: 1 statement ignored"));
}

/// Per-kind totals of the corpus' GRAPHICS statements, counted with grep over
/// `shared/corpus/adams` (the first kind word after `GRAPHICS/id,`, or `OUTLINE =`).
const CORPUS_TOTALS: &[(&str, usize)] = &[
    ("CYLINDER", 992),
    ("BOX", 213),
    ("CIRCLE", 206),
    ("EXTERNAL", 161),
    ("FORCE", 77),
    ("ELLIPSOID", 15),
    ("FRUSTUM", 13),
    ("OUTLINE", 5),
    ("SPDP", 4),
    ("CURVE", 1),
];

/// GRAPHICS statements the grep counts that are no part of a dataset: they follow its
/// first END, which ends the dataset (`grep -n` of the file). MBDyn's a2m sample
/// `monster.adm` pastes four datasets after one another; after line 388's END come 3
/// CYLINDER (lines 684, 711, 731) and 8 FORCE (493, 496, 734-743, 1022, 1025).
const AFTER_END: &[(&str, usize)] = &[("CYLINDER", 3), ("FORCE", 8)];

#[test]
fn the_corpus_graphics_read_by_kind_with_no_error() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/adams");
    let files = adm_files(&corpus);
    assert!(files.len() >= 70, "only {} files", files.len());
    let mut totals: BTreeMap<&str, usize> = BTreeMap::new();
    let mut problems = Vec::new();
    for path in &files {
        let text = decode(&std::fs::read(path).expect("corpus file"))
            .0
            .into_owned();
        let r = read_model(&text);
        for (kind, n) in counts_by_kind(&r.model.graphics) {
            *totals.entry(kind).or_default() += n;
        }
        let (stmts, _) = read_statements(&text);
        for s in stmts.iter().filter(|s| s.canonical == Some("GRAPHICS")) {
            let inside = |d: &&Diagnostic| {
                d.is_error() && d.span.start >= s.span.start && d.span.end <= s.span.end
            };
            if let Some(d) = r.diagnostics.iter().find(inside) {
                problems.push(format!("{}: line {}: {d:?}", path.display(), s.line));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    let mut want: BTreeMap<&str, usize> = CORPUS_TOTALS.iter().copied().collect();
    for (kind, n) in AFTER_END {
        *want.get_mut(kind).expect("a corpus kind") -= n;
    }
    assert_eq!(totals, want);
}
