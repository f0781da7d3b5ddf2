//! The CONTACT statement, typed (issue 40 §1): the GRAPHICS on either side, the normal
//! force law (IMPACT or POISSON) and Coulomb friction with Adams' velocity-dependent
//! coefficient. The multibody core turns it into forces (`mbd::contacts`); the geometry
//! queries live in `collide`.

use super::elements::{Id, Named};

/// One CONTACT statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// Id, name and span.
    pub el: Named,
    /// IGEOM: the GRAPHICS on the I side (all on one part).
    pub igeom: Vec<Id>,
    /// JGEOM: the GRAPHICS on the J side (all on one part).
    pub jgeom: Vec<Id>,
    /// IFLIP_GEOMETRY: I-side GRAPHICS whose normal is flipped (curves and planes).
    pub iflip: Vec<Id>,
    /// JFLIP_GEOMETRY: J-side GRAPHICS whose normal is flipped.
    pub jflip: Vec<Id>,
    /// The normal force law.
    pub normal: NormalLaw,
    /// COULOMB_FRICTION and its coefficients.
    pub friction: Friction,
}

/// How the normal force follows from the penetration g and its rate ġ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalLaw {
    /// IMPACT: k·g^e − STEP(g, 0, 0, DMAX, C)·(−ġ) as the IMPACT function, clamped at 0.
    Impact {
        /// STIFFNESS k.
        stiffness: f64,
        /// DAMPING C (the full damping, reached at DMAX).
        damping: f64,
        /// DMAX: the penetration where the damping is full.
        dmax: f64,
        /// EXPONENT e.
        exponent: f64,
    },
    /// POISSON: PENALTY p as a stiffness, RESTITUTION_COEFFICIENT ε: p·g while the
    /// penetration grows, ε²·p·g while it shrinks (docs/contact.md).
    Poisson {
        /// PENALTY p.
        penalty: f64,
        /// RESTITUTION_COEFFICIENT ε, 0 ≤ ε ≤ 1.
        restitution: f64,
    },
}

/// COULOMB_FRICTION: where friction acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionMode {
    /// OFF (also the default when COULOMB_FRICTION is absent).
    Off,
    /// ON: in every analysis.
    On,
    /// DYNAMICS_ONLY: not in statics.
    DynamicsOnly,
}

/// Coulomb friction of a contact: μ(v) rises from 0 to MU_STATIC over the stiction
/// transition velocity and falls to MU_DYNAMIC at the friction transition velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    /// COULOMB_FRICTION.
    pub mode: FrictionMode,
    /// MU_STATIC.
    pub mu_static: f64,
    /// MU_DYNAMIC.
    pub mu_dynamic: f64,
    /// STICTION_TRANSITION_VELOCITY vs.
    pub stiction_velocity: f64,
    /// FRICTION_TRANSITION_VELOCITY vd (> vs).
    pub friction_velocity: f64,
}
