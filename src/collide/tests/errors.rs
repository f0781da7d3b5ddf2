//! Each reason a GRAPHICS statement is no contact geometry, with its message and place.

use super::model;
use crate::collide::{CollideError, Geometry};
use std::collections::HashMap;

/// The error of GRAPHICS/2 in a dataset with `graphic` as its last statement, and the
/// text its span covers.
fn error_of(graphic: &str, id: u32) -> (CollideError, String) {
    let body = format!(
        "MARKER/11, PART=1, QP=1,0,0\nPART/2, MASS=1, CM=21, IP=1,1,1\nMARKER/21, PART=2\n\
         MARKER/22, PART=2, QP=0,1,0\n{graphic}"
    );
    let m = model(&body);
    let e = Geometry::of(&m, id, &HashMap::new()).expect_err("no contact geometry");
    let text = format!("contact\nPART/1, GROUND\nMARKER/1, PART=1\n{body}\nEND\n");
    let under = text.get(e.span.clone()).unwrap_or_default().to_string();
    (e, under)
}

#[test]
fn an_outline_has_no_volume() {
    let (e, under) = error_of("GRAPHICS/2, OUTLINE = 21, 22", 2);
    assert_eq!(
        e.to_string(),
        "GRAPHICS/2 cannot be a contact geometry: an OUTLINE has no volume to collide \
         (contact geometries are BOX, CYLINDER, FRUSTUM, ELLIPSOID, EXTERNAL, PLANE)"
    );
    assert!(under.starts_with("GRAPHICS/2, OUTLINE"), "{under}");
    assert_eq!(e.diagnostic().code.as_str(), "E0605");
}

#[test]
fn a_spring_damper_drawing_and_a_circle_cannot_collide() {
    let (e, _) = error_of("GRAPHICS/2, SPDP, I=21, J=11", 2);
    assert!(e.why.starts_with("a SPDP has no volume"), "{e}");
    let (e, _) = error_of("GRAPHICS/2, CIRCLE, CM=21, RADIUS=1", 2);
    assert!(e.why.starts_with("a CIRCLE has no volume"), "{e}");
    let (e, _) = error_of("GRAPHICS/2, ARC, CM=21, RADIUS=1, RANGLE=90D", 2);
    assert!(e.why.starts_with("an ARC has no volume"), "{e}");
}

#[test]
fn an_external_without_a_mesh_asks_for_one() {
    let (e, under) = error_of("GRAPHICS/2, EXTERNAL, RM=21, FILE=part.x_t", 2);
    assert_eq!(
        e.why,
        "EXTERNAL `part.x_t` has no mesh (give one with --geometry)"
    );
    assert!(under.starts_with("GRAPHICS/2, EXTERNAL"), "{under}");
}

#[test]
fn a_box_of_no_thickness_is_refused() {
    let (e, _) = error_of("GRAPHICS/2, BOX, CORNER=21, X=1, Y=0, Z=1", 2);
    assert_eq!(
        e.why,
        "a BOX needs three non-zero extents (X, Y, Z = 1, 0, 1)"
    );
}

#[test]
fn a_flat_cylinder_and_a_flat_ellipsoid_are_refused() {
    let (e, _) = error_of("GRAPHICS/2, CYLINDER, CM=21, LENGTH=0, RADIUS=1", 2);
    assert!(
        e.why.starts_with("a round solid needs a non-zero LENGTH"),
        "{e}"
    );
    let (e, _) = error_of("GRAPHICS/2, ELLIPSOID, CM=21, XS=1, YS=0, ZS=1", 2);
    assert!(
        e.why
            .starts_with("an ELLIPSOID needs three non-zero scales"),
        "{e}"
    );
    let (e, _) = error_of("GRAPHICS/2, FRUSTUM, CM=21, LENGTH=1, TOP=0, BOTTOM=0", 2);
    assert!(e.why.starts_with("a round solid needs"), "{e}");
}

#[test]
fn an_id_with_no_graphics_statement_says_so() {
    let (e, under) = error_of("GRAPHICS/2, BOX, CORNER=21, X=1, Y=1, Z=1", 9);
    assert_eq!(
        e.to_string(),
        "GRAPHICS/9 cannot be a contact geometry: no such GRAPHICS statement"
    );
    assert_eq!(under, "");
}
