//! The catalogue of single constraint elements by the equations they impose (multibody
//! spec §4.2), and how elements and equations are named in reports (the words come from
//! the one table of element names, [`crate::vocab::elements::ELEMENT_NAMES`]).
//!
//! The redundancy analysis looks an element's kept equations up here to propose a lighter
//! element: a JOINT 4 REVOLUTE whose Z Delta, Zi.Xj and Zi.Yj are redundant keeps exactly
//! the equations of a JPRIM INLINE.

use crate::mbd::equations::Equation;
use crate::vocab::elements::{ElementKind, ElementRef, JointType, JprimType};

use Equation::*;

/// Every JOINT and JPRIM of spec §4.2 with its equation set, joints first. A planar
/// scene (2D) uses [`PLANAR_CATALOGUE`] instead.
const CATALOGUE: &[(ElementKind, &[Equation])] = &[
    (
        ElementKind::Joint(JointType::Fixed),
        &[XDelta, YDelta, ZDelta, ZiXj, ZiYj, XiYj],
    ),
    (
        ElementKind::Joint(JointType::Revolute),
        &[XDelta, YDelta, ZDelta, ZiXj, ZiYj],
    ),
    (
        ElementKind::Joint(JointType::Translational),
        &[XDelta, YDelta, ZiXj, ZiYj, XiYj],
    ),
    (
        ElementKind::Joint(JointType::Cylindrical),
        &[XDelta, YDelta, ZiXj, ZiYj],
    ),
    (
        ElementKind::Joint(JointType::Hooke),
        &[XDelta, YDelta, ZDelta, XiYj],
    ),
    (
        ElementKind::Joint(JointType::Universal),
        &[XDelta, YDelta, ZDelta, ZiZj],
    ),
    (
        ElementKind::Joint(JointType::Convel),
        &[XDelta, YDelta, ZDelta, Convel],
    ),
    (
        ElementKind::Joint(JointType::Spherical),
        &[XDelta, YDelta, ZDelta],
    ),
    (ElementKind::Joint(JointType::Planar), &[ZDelta, ZiXj, ZiYj]),
    (ElementKind::Joint(JointType::Rackpin), &[Rackpin]),
    (ElementKind::Joint(JointType::Screw), &[Screw]),
    (
        ElementKind::Jprim(JprimType::Atpoint),
        &[XDelta, YDelta, ZDelta],
    ),
    (
        ElementKind::Jprim(JprimType::Orientation),
        &[ZiXj, ZiYj, XiYj],
    ),
    (ElementKind::Jprim(JprimType::Inline), &[XDelta, YDelta]),
    (ElementKind::Jprim(JprimType::ParallelAxes), &[ZiXj, ZiYj]),
    (ElementKind::Jprim(JprimType::Inplane), &[ZDelta]),
    (ElementKind::Jprim(JprimType::Perpendicular), &[ZiZj]),
];

/// In a planar scene only the in-plane equations exist: a revolute pins a point
/// (X Delta, Y Delta) and a fixed joint also locks the rotation (Xi.Yj).
const PLANAR_CATALOGUE: &[(ElementKind, &[Equation])] = &[
    (
        ElementKind::Joint(JointType::Fixed),
        &[XDelta, YDelta, XiYj],
    ),
    (ElementKind::Joint(JointType::Revolute), &[XDelta, YDelta]),
];

fn catalogue(dim: usize) -> &'static [(ElementKind, &'static [Equation])] {
    if dim == 2 {
        PLANAR_CATALOGUE
    } else {
        CATALOGUE
    }
}

/// Whether `kind` is a JOINT or JPRIM, whose equations can be traded for a lighter one.
pub(super) fn is_lowerable(kind: ElementKind) -> bool {
    matches!(kind, ElementKind::Joint(_) | ElementKind::Jprim(_))
}

/// The catalogue elements (other than `kind` itself) whose equation set is exactly `kept`.
pub(super) fn elements_with(dim: usize, kind: ElementKind, kept: &[Equation]) -> Vec<ElementKind> {
    catalogue(dim)
        .iter()
        .filter(|(k, set)| *k != kind && same_set(set, kept))
        .map(|(k, _)| *k)
        .collect()
}

/// The distinct equation sets of catalogue elements that are subsets of `available` with
/// `size` equations, in catalogue order: the kept sets worth trying for an element.
pub(super) fn candidate_sets(
    dim: usize,
    available: &[Equation],
    size: usize,
) -> Vec<&'static [Equation]> {
    let mut sets: Vec<&'static [Equation]> = Vec::new();
    for (_, set) in catalogue(dim) {
        if set.len() == size
            && set.iter().all(|e| available.contains(e))
            && !sets.iter().any(|s| same_set(s, set))
        {
            sets.push(set);
        }
    }
    sets
}

fn same_set(a: &[Equation], b: &[Equation]) -> bool {
    a.len() == b.len() && a.iter().all(|e| b.contains(e))
}

/// Position of an equation in Adams' order (X Delta … Xi.Yj, then the others): the order
/// rows of one element are offered in, and reversed in Adams' messages.
pub(super) fn equation_order(e: Equation) -> u8 {
    match e {
        XDelta => 0,
        YDelta => 1,
        ZDelta => 2,
        ZiXj => 3,
        ZiYj => 4,
        XiYj => 5,
        ZiZj => 6,
        Convel => 7,
        Rackpin => 8,
        Screw => 9,
        Gcon => 10,
        Motion => 11,
    }
}

/// The element's `adams_view_name` when it has one, else `JOINT/4`.
pub fn element_name(e: &ElementRef) -> String {
    match &e.name {
        Some(n) => n.clone(),
        None => format!("{}/{}", e.kind.keyword(), e.id),
    }
}

/// `JOINT/4 (REVOLUTE)`: the element's name with its type.
pub fn element_title(e: &ElementRef) -> String {
    match e.kind.flag() {
        Some(t) => format!("{} ({t})", element_name(e)),
        None => element_name(e),
    }
}

/// The older Adams/View wording of what an equation removes ("Rotation Between Zi and Xj",
/// multibody spec §5.1 item 4). The spec quotes only the rotation phrases; the others follow
/// the same pattern.
pub fn older_phrase(e: Equation) -> &'static str {
    match e {
        XDelta => "Translation Along X",
        YDelta => "Translation Along Y",
        ZDelta => "Translation Along Z",
        ZiXj => "Rotation Between Zi and Xj",
        ZiYj => "Rotation Between Zi and Yj",
        XiYj => "Rotation Between Xi and Yj",
        ZiZj => "Rotation Between Zi and Zj",
        Convel => "Rotation Between Xi and Yj plus Yi and Xj",
        Rackpin => "Rack and Pinion Coupling",
        Screw => "Screw Coupling",
        Gcon => "its General Constraint",
        Motion => "its Motion",
    }
}
