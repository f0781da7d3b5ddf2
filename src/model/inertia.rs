//! Which inertia tensors a body can have, for the PART reader, and a part's mass
//! properties about its CM ([`mass_properties`]), which the core's build and the
//! animation's glyphs both read.
//!
//! The tensor of a rigid body about any point is ∫(|r|²·1 − r·rᵀ) dm. Its eigenvalues, the
//! principal moments A, B, C, are ∫(y² + z²) dm and its two cyclic variants: each is
//! non-negative and each is at most the sum of the other two (A + B − C = 2∫z² dm ≥ 0).
//! A tensor outside that set belongs to no mass distribution (issue 11 §3). A negative
//! moment makes the mass matrix indefinite, which the dynamics cannot integrate: the
//! reader's error E0608. A broken triangle inequality alone is only a warning (W0609):
//! real, Adams-run datasets have it (the FAST certification tests give a nacelle
//! IP = 0.0009999, 0.0009999, 4418.021, a yaw inertia lumped onto a point), and a
//! positive definite tensor is still one the equations of motion can use. Printed
//! datasets round their values, so both tests allow a relative tolerance of
//! [`TOLERANCE`] of the largest moment; a thin plate or rod (C = A + B exactly) passes.

use super::elements::{Model, Part};
use crate::vocab::math::{Mat3, Vec3};

/// Relative slack of the tests, against the largest principal moment.
pub const TOLERANCE: f64 = 1e-6;

/// The tensor of `IP = Ixx, Iyy, Izz, Ixy, Ixz, Iyz` (spec §2.2: Adams' products are
/// +∫xy dm, so they enter negated).
pub fn tensor(ip: &[f64; 6]) -> Mat3 {
    let [xx, yy, zz, xy, xz, yz] = *ip;
    Mat3::new(xx, -xy, -xz, -xy, yy, -yz, -xz, -yz, zz)
}

/// Why a tensor is no body's inertia.
#[derive(Debug, PartialEq)]
pub enum Impossible {
    /// A principal moment is negative: the tensor is not positive semi-definite.
    Negative {
        /// The principal moments, ascending.
        moments: [f64; 3],
    },
    /// The largest principal moment exceeds the sum of the other two.
    Triangle {
        /// The principal moments, ascending.
        moments: [f64; 3],
    },
}

impl Impossible {
    /// One sentence saying what is wrong, with the principal moments.
    pub fn describe(&self) -> String {
        match self {
            Impossible::Negative { moments: [a, b, c] } => format!(
                "its principal moments are {a}, {b} and {c}: a negative moment means the \
                 tensor is not positive semi-definite"
            ),
            Impossible::Triangle { moments: [a, b, c] } => format!(
                "its principal moments are {a}, {b} and {c}: {c} exceeds {a} + {b}, and no \
                 body has a principal moment larger than the sum of the other two"
            ),
        }
    }
}

/// Checks a symmetric inertia tensor with finite entries; the principal moments in
/// ascending order come back when it is possible.
pub fn check(tensor: &Mat3) -> Result<[f64; 3], Impossible> {
    let eigen = nalgebra::SymmetricEigen::new(*tensor);
    let mut moments = [
        eigen.eigenvalues[0],
        eigen.eigenvalues[1],
        eigen.eigenvalues[2],
    ];
    moments.sort_by(f64::total_cmp);
    let [a, b, c] = moments;
    let slack = TOLERANCE * a.abs().max(c.abs());
    if a < -slack {
        return Err(Impossible::Negative { moments });
    }
    if c > a + b + slack {
        return Err(Impossible::Triangle { moments });
    }
    Ok(moments)
}

/// Mass properties of a PART in the core's terms (multibody spec §2.2): the mass, the
/// centre of mass in BCS coordinates (the CM marker's origin) and the inertia tensor about
/// the CM in BCS axes. IP is given about the IM marker's origin in IM axes (the CM
/// marker's when IM is absent); it is moved to the CM by the parallel-axis theorem and
/// rotated into BCS axes. The core takes each part's CM as its reference point, so the
/// Newton–Euler equations have a block-diagonal mass matrix diag(m·I, R·J·Rᵀ).
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

    fn diag(a: f64, b: f64, c: f64) -> Mat3 {
        Mat3::from_diagonal(&nalgebra::Vector3::new(a, b, c))
    }

    #[test]
    fn bodies_pass_and_impossible_tensors_do_not() {
        // A unit cube of mass 6: every moment 6·(1 + 1)/12 = 1.
        assert!(check(&diag(1.0, 1.0, 1.0)).is_ok());
        // A thin square plate: C = A + B exactly.
        assert!(check(&diag(1.0, 1.0, 2.0)).is_ok());
        // A thin rod along z: A = 0, B = C.
        assert!(check(&diag(0.0, 1.0, 1.0)).is_ok());
        assert!(check(&Mat3::zeros()).is_ok());
        assert!(matches!(
            check(&diag(1.0, 1.0, 5.0)),
            Err(Impossible::Triangle { .. })
        ));
        assert!(matches!(
            check(&diag(-1.0, -1.0, -1.0)),
            Err(Impossible::Negative { .. })
        ));
        // Rounding in a printed plate (C = A + B + 1e-7 relative) passes, 1e-4 does not.
        assert!(check(&diag(1.0, 2.0, 3.0000003)).is_ok());
        assert!(check(&diag(1.0, 2.0, 3.0003)).is_err());
    }

    #[test]
    fn products_count_through_the_principal_moments() {
        // [[2, -h, 0], [-h, 2, 0], [0, 0, 3]] has principal moments 2 - h, 2 + h and 3.
        let with = |h: f64| Mat3::new(2.0, -h, 0.0, -h, 2.0, 0.0, 0.0, 0.0, 3.0);
        let m = check(&with(0.5)).expect("1.5, 2.5, 3");
        assert!(
            (m[0] - 1.5).abs() < 1e-12 && (m[2] - 3.0).abs() < 1e-12,
            "{m:?}"
        );
        // h = 3: moments -1, 3, 5: negative.
        assert!(matches!(
            check(&with(3.0)),
            Err(Impossible::Negative { .. })
        ));
        // h = 1.8: moments 0.2, 3, 3.8: 3.8 > 3.2 breaks the triangle inequality.
        assert!(matches!(
            check(&with(1.8)),
            Err(Impossible::Triangle { .. })
        ));
    }
}

#[cfg(test)]
mod mass_property_tests {
    use super::*;
    use crate::model::read_model;
    use crate::vocab::math::{Mat3, Vec3};

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
