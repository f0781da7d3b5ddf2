//! The dimension each dataset statement expects of its expressions (issue 24), for the
//! units check: an SFORCE's FUNCTION and the force components of VFORCE and GFORCE are
//! forces, torques for a rotational SFORCE and the T components; a MOTION's FUNCTION is a
//! length or an angle, their rates for VELOCITY and ACCELERATION motions.
//!
//! GCON, VARIABLE, DIFF, REQUEST, SENSOR and probe expressions are free: only their own
//! consistency is checked. SPRINGDAMPER and BUSHING take numbers, not expressions.

use super::elements::MotionLevel;
use crate::check::units::{Dim, Expected};

/// An SFORCE's FUNCTION: a force, or a torque for ROTATION.
pub fn sforce(rotation: bool) -> Expected {
    force_or_torque(
        rotation,
        &[(Dim::TORQUE, "for a torque, make it a ROTATION SFORCE")],
        &[(Dim::FORCE, "for a force, make it a TRANSLATION SFORCE")],
    )
}

/// A force component (FX, FY, FZ) or a torque component (TX, TY, TZ) of VFORCE, VTORQUE
/// or GFORCE.
pub fn component(torque: bool) -> Expected {
    force_or_torque(
        torque,
        &[(Dim::TORQUE, "a torque belongs in TX, TY or TZ")],
        &[(Dim::FORCE, "a force belongs in FX, FY or FZ")],
    )
}

/// A torque (with the help of `for_torque`) or a force (with `for_force`).
fn force_or_torque(
    torque: bool,
    for_force: &'static [(Dim, &'static str)],
    for_torque: &'static [(Dim, &'static str)],
) -> Expected {
    match torque {
        true => Expected {
            dim: Dim::TORQUE,
            alternatives: for_torque,
        },
        false => Expected {
            dim: Dim::FORCE,
            alternatives: for_force,
        },
    }
}

/// A MOTION's FUNCTION: the coordinate it drives (a length, or an angle for a rotation)
/// or its first or second rate for VELOCITY and ACCELERATION.
pub fn motion(rotation: bool, level: MotionLevel) -> Expected {
    const TRANSLATION: &[(Dim, &str)] = &[
        (
            Dim::LENGTH,
            "for a displacement, write DISPLACEMENT (the default)",
        ),
        (Dim::VELOCITY, "for a velocity, write VELOCITY"),
        (Dim::ACCELERATION, "for an acceleration, write ACCELERATION"),
        (Dim::ANGLE, "an angle drives a rotation: write ROTATION"),
    ];
    const ROTATION: &[(Dim, &str)] = &[
        (Dim::ANGLE, "for an angle, write DISPLACEMENT (the default)"),
        (
            Dim::ANGULAR_VELOCITY,
            "for an angular velocity, write VELOCITY",
        ),
        (
            Dim::ANGULAR_ACCELERATION,
            "for an angular acceleration, write ACCELERATION",
        ),
        (
            Dim::LENGTH,
            "a length drives a translation: write TRANSLATION",
        ),
    ];
    let (table, k) = match level {
        MotionLevel::Displacement => (if rotation { ROTATION } else { TRANSLATION }, 0),
        MotionLevel::Velocity => (if rotation { ROTATION } else { TRANSLATION }, 1),
        MotionLevel::Acceleration => (if rotation { ROTATION } else { TRANSLATION }, 2),
    };
    Expected {
        dim: table[k].0,
        alternatives: table,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motions_expect_the_coordinate_or_its_rates() {
        let m = |r, l| motion(r, l).dim;
        assert_eq!(m(false, MotionLevel::Displacement), Dim::LENGTH);
        assert_eq!(m(false, MotionLevel::Velocity), Dim::VELOCITY);
        assert_eq!(m(false, MotionLevel::Acceleration), Dim::ACCELERATION);
        assert_eq!(m(true, MotionLevel::Displacement), Dim::ANGLE);
        assert_eq!(m(true, MotionLevel::Velocity), Dim::ANGULAR_VELOCITY);
        assert_eq!(
            m(true, MotionLevel::Acceleration),
            Dim::ANGULAR_ACCELERATION
        );
        assert_eq!(sforce(true).dim, Dim::TORQUE);
        assert_eq!(component(false).dim, Dim::FORCE);
    }
}
