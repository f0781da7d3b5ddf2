//! GRAPHICS statements as the model keeps them: one [`Graphic`] per statement, its shape
//! typed by kind with the values as the dataset writes them (marker ids, lengths in model
//! units, angles in radians). Read by `read_graphics`; nothing here draws or places a
//! shape, and nothing here changes the physics. The conventions of each argument, with
//! their sources, are in `docs/models.md` ("GRAPHICS").

use super::elements::{Id, Named};

/// One GRAPHICS statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Graphic {
    /// Its id, view name and span.
    pub el: Named,
    /// What it draws.
    pub shape: Shape,
}

/// How a SIDES / SEG / RANGLE trio facets a round shape; `None` where the dataset is
/// silent (the drawing step chooses).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Facets {
    /// SIDES: flat sides of a cylinder's or frustum's mantle.
    pub sides: Option<u32>,
    /// SEG: line segments of each circle.
    pub seg: Option<u32>,
    /// RANGLE: the angle swept about the CM marker's z axis from its x axis (radians).
    pub rangle: Option<f64>,
}

/// A radius given as a number or as the distance to a marker (`RM`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Radius {
    /// RADIUS = r, in model length units.
    Value(f64),
    /// RM = id: the distance from the CM marker's z axis to this marker.
    Marker(Id),
}

/// The shape of a GRAPHICS statement, one variant per kind mbfx reads. Marker fields
/// hold Adams MARKER ids, lengths are in model units.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// BOX: one corner at the CORNER marker, extending X, Y, Z along its axes (a
    /// negative extent goes the other way).
    Box {
        /// CORNER.
        corner: Id,
        /// X, Y, Z.
        extent: [f64; 3],
    },
    /// CYLINDER: bottom centre at CM, axis along CM's z for LENGTH (negative: along -z).
    Cylinder {
        /// CM, the centre of the bottom circle.
        cm: Id,
        /// LENGTH, signed.
        length: f64,
        /// RADIUS or RM.
        radius: Radius,
        /// SIDES, SEG, RANGLE.
        facets: Facets,
    },
    /// FRUSTUM: BOTTOM radius at CM, TOP radius LENGTH along CM's z.
    Frustum {
        /// CM, the centre of the bottom circle.
        cm: Id,
        /// LENGTH, signed.
        length: f64,
        /// TOP radius.
        top: f64,
        /// BOTTOM radius.
        bottom: f64,
        /// SIDES, SEG, RANGLE.
        facets: Facets,
    },
    /// ELLIPSOID: a unit sphere at CM scaled along CM's axes.
    Ellipsoid {
        /// CM, the centre.
        cm: Id,
        /// XSCALE, YSCALE, ZSCALE as written (see docs/models.md on what they measure).
        scale: [f64; 3],
    },
    /// CIRCLE about CM in its x-y plane.
    Circle {
        /// CM, the centre.
        cm: Id,
        /// RADIUS or RM.
        radius: Radius,
        /// SEG.
        seg: Option<u32>,
    },
    /// ARC about CM in its x-y plane, from CM's x axis through RANGLE.
    Arc {
        /// CM, the centre.
        cm: Id,
        /// RADIUS or RM.
        radius: Radius,
        /// SEG and RANGLE (SIDES unused).
        facets: Facets,
    },
    /// OUTLINE: straight lines through the markers in order (on one part or several).
    Outline {
        /// The markers, two or more.
        markers: Vec<Id>,
    },
    /// SPDP: a spring-damper drawing between two markers.
    SpringDamper {
        /// I marker.
        i: Id,
        /// J marker.
        j: Id,
        /// COILS, the number of turns of the spring.
        coils: Option<u32>,
        /// DA, as written (the spring's diameter; see docs/models.md).
        da: Option<f64>,
        /// DB, as written (a damper diameter; see docs/models.md).
        db: Option<f64>,
        /// DC, as written (a damper diameter; see docs/models.md).
        dc: Option<f64>,
        /// LC, as written (a damper length; see docs/models.md).
        lc: Option<f64>,
        /// LD, as written (a damper length; see docs/models.md).
        ld: Option<f64>,
    },
    /// FORCE: the force of element ETYPE/EID drawn as a vector at EMARKER.
    Force {
        /// ETYPE, the statement kind, canonical (`SFORCE`).
        etype: &'static str,
        /// EID.
        eid: Id,
        /// EMARKER, where the vector is drawn.
        emarker: Id,
    },
    /// CURVE: the CURVE/CID drawn in the frame of marker CRM.
    Curve {
        /// CID.
        cid: Id,
        /// CRM.
        crm: Id,
        /// SEG.
        seg: Option<u32>,
    },
    /// EXTERNAL: geometry from a CAD file placed at RM; kept as data for now.
    External {
        /// RM, the reference marker.
        rm: Id,
        /// FILE as written.
        file: String,
        /// ELEMENT: the body of the file to use.
        element: Option<String>,
        /// FACETING_TOLERANCE.
        faceting_tolerance: Option<f64>,
    },
    /// PLANE: the rectangle XMIN ≤ x ≤ XMAX, YMIN ≤ y ≤ YMAX in RM's x-y plane, its
    /// normal RM's +z (a contact geometry: docs/contact.md says what it collides as).
    Plane {
        /// RM, the reference marker.
        rm: Id,
        /// XMIN, XMAX.
        x: [f64; 2],
        /// YMIN, YMAX.
        y: [f64; 2],
    },
}

impl Shape {
    /// The kind as the dataset writes it (`CYLINDER`); OUTLINE for an outline.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Box { .. } => "BOX",
            Shape::Cylinder { .. } => "CYLINDER",
            Shape::Frustum { .. } => "FRUSTUM",
            Shape::Ellipsoid { .. } => "ELLIPSOID",
            Shape::Circle { .. } => "CIRCLE",
            Shape::Arc { .. } => "ARC",
            Shape::Outline { .. } => "OUTLINE",
            Shape::SpringDamper { .. } => "SPDP",
            Shape::Force { .. } => "FORCE",
            Shape::Curve { .. } => "CURVE",
            Shape::External { .. } => "EXTERNAL",
            Shape::Plane { .. } => "PLANE",
        }
    }
}

/// Graphics per kind, the most numerous first (ties by name): `[("CYLINDER", 12), ...]`.
pub fn counts_by_kind(graphics: &[Graphic]) -> Vec<(&'static str, usize)> {
    let mut counts = std::collections::BTreeMap::new();
    for g in graphics {
        *counts.entry(g.shape.kind()).or_insert(0) += 1;
    }
    let mut out: Vec<(&'static str, usize)> = counts.into_iter().collect();
    out.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
    out
}
