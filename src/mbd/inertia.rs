//! Mass properties of a PART in the core's terms (multibody spec §2.2): the mass, the
//! centre of mass in BCS coordinates (the CM marker's origin) and the inertia tensor about
//! the CM in BCS axes. IP is given about the IM marker's origin in IM axes (the CM
//! marker's when IM is absent); it is moved to the CM by the parallel-axis theorem and
//! rotated into BCS axes. The core then takes each part's CM as its reference point, so
//! the Newton–Euler equations have a block-diagonal mass matrix diag(m·I, R·J·Rᵀ).

use crate::model::elements::{Model, Part};
use crate::vocab::math::{Mat3, Vec3};

/// Mass, CM offset (BCS) and inertia about the CM (BCS axes) of a moving part.
#[derive(Clone, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass, model units.
    pub mass: f64,
    /// CM offset from the BCS origin, BCS coordinates.
    pub cm: Vec3,
    /// Inertia tensor about the CM, BCS axes.
    pub inertia: Mat3,
}

/// The mass properties of `part` (a massless part when it has no MASS: mass 0, inertia
/// 0, reference point the BCS origin unless a CM marker is named).
pub fn mass_properties(model: &Model, part: &Part) -> MassProperties {
    let marker = |id| model.marker(id).map(|m| (m.position, m.orientation));
    let (cm, cm_axes) = part
        .cm
        .and_then(marker)
        .unwrap_or((Vec3::zeros(), Mat3::identity()));
    let mass = part.mass.unwrap_or(0.0);
    let (im, im_axes) = part.im.and_then(marker).unwrap_or((cm, cm_axes));
    // About the IM origin in IM axes → about the CM in IM axes: J_cm = J_im − m(|d|²I − d dᵀ),
    // d the CM relative to the IM origin in IM axes.
    let d = im_axes.transpose() * (cm - im);
    let j_cm = part.inertia() - (Mat3::identity() * d.norm_squared() - d * d.transpose()) * mass;
    MassProperties {
        mass,
        cm,
        inertia: im_axes * j_cm * im_axes.transpose(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::read_model;

    #[test]
    fn inertia_moves_to_the_cm_and_into_bcs_axes() {
        // A rod of mass 2 along BCS x, IP given about an IM marker at its end whose axes
        // are the BCS axes turned +90° about z: IM x = BCS y. About the end, in IM axes,
        // the rod (along IM −y... i.e. BCS x) has I_xx(IM) = m l²/3 = 2·4/3, I_yy(IM) ≈ 0.
        let adm = "rod\nPART/1, GROUND\nPART/2, MASS = 2, CM = 20, IM = 21, IP = 2.6666666666666665, 0, 2.6666666666666665\n\
                   MARKER/20, PART = 2, QP = 1, 0, 0\nMARKER/21, PART = 2, QP = 0, 0, 0, REULER = 90D, 0, 0\nEND\n";
        let read = read_model(adm);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let p = mass_properties(&read.model, read.model.part(2).unwrap());
        assert_eq!(p.mass, 2.0);
        assert_eq!(p.cm, Vec3::new(1.0, 0.0, 0.0));
        // About the CM: m l²/12 = 2·4/12 about BCS y and z, 0 about x (the rod's axis).
        let want = Mat3::from_diagonal(&Vec3::new(0.0, 2.0 / 3.0, 2.0 / 3.0));
        assert!((p.inertia - want).norm() < 1e-12, "{}", p.inertia);
    }

    #[test]
    fn products_of_inertia_enter_negated() {
        let adm = "p\nPART/1, GROUND\nPART/2, MASS = 1, CM = 20, IP = 3, 4, 5, 0.5, 0.25, 0.125\n\
                   MARKER/20, PART = 2\nEND\n";
        let read = read_model(adm);
        let p = mass_properties(&read.model, read.model.part(2).unwrap());
        assert_eq!(p.inertia[(0, 1)], -0.5);
        assert_eq!(p.inertia[(0, 2)], -0.25);
        assert_eq!(p.inertia[(1, 2)], -0.125);
    }
}
