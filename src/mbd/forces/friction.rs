//! Joint friction (FRICTION, issue 40 §2): a force element between a joint's I and J
//! markers whose load comes from the joint's own reaction. The reaction (force and
//! torque on I, J's axes) is read as six solution values ([`super::Source::Solution`]
//! slots of [`super::ForceSet::solution`]), held fixed within one evaluation; the slip
//! velocities are duals, so ∂Q/∂q and ∂Q/∂v are exact, and the law gives its derivative
//! by the reaction ([`super::Generalized::ds`]), which the dynamics chains with the
//! reaction's derivative by the multipliers into the Newton matrix: the friction–reaction
//! loop is solved by Newton.
//!
//! With the reaction force F = (Fx, Fy, Fz) and torque T = (Tx, Ty, Tz) in J's axes,
//! each term switched by INPUTS, the friction's load N and slip velocity v are
//!
//! ```text
//! revolute:      N = Rp·√(Fx²+Fy²) + Rn·|Fz| + Rp·√(Tx²+Ty²)/Rb + Rp·Fpre   v = Rp·ω_z
//! translational: N = √(Fx²+Fy²) + √(Tx²+Ty²)/Xs + |Tz|/Rn + Fpre            v = v_z
//! cylindrical:   N = √(Fx²+Fy²) + √(Tx²+Ty²)/Xs + Fpre            v = (v_z, Rp·ω_z)
//! spherical:     N = Rb·|F| + Rb·Fpre                              v = Rb·ω
//! Hooke, universal: N = Rp·|F| + Rp·|T|/Rb + Rp·Fpre                v = Rp·ω
//! ```
//!
//! (Rp PIN_RADIUS, Rb BALL_RADIUS or BENDING_REACTION_ARM, Rn FRICTION_ARM, Xs the
//! overlap, Fpre FRICTION_FORCE_PRELOAD; ω and v_z relative, J's axes). The friction
//! opposes the slip: −μ(|v|)·N along v/|v| (a torque for the rotational slips, scaled by
//! their radius), capped by MAX_FRICTION_FORCE or MAX_FRICTION_TORQUE.
//!
//! μ is Adams' stick-slip curve (`mu_over_speed` in `friction_loads`, which evaluates
//! the law): it falls from μs at the stiction transition velocity vs to μd at vd =
//! TRANSITION_VELOCITY_COEFFICIENT·vs as STEP(|v|, vs, μs, vd, μd), and stays μd beyond.
//! Below vs a joint holds with a stiction deformation δ, a state bounded by
//! MAX_STICTION_DEFORMATION (the `stiction` module); with EFFECT = SLIDING, which has no
//! stiction, there is no state and μ rises from 0 at zero slip to its peak at vs as
//! STEP(v, −vs, −μ, vs, μ), so such a loaded joint creeps.

/// The joint a friction acts in, by how it slips.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionJoint {
    /// REVOLUTE: rotation about z_J.
    Revolute,
    /// TRANSLATIONAL: sliding along z_J.
    Translational,
    /// CYLINDRICAL: sliding along and rotation about z_J.
    Cylindrical,
    /// SPHERICAL: rotation about any axis.
    Spherical,
    /// HOOKE or UNIVERSAL: rotation about the two free axes.
    Universal,
}

/// Which terms load the friction (INPUTS).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loading {
    /// FRICTION_FORCE_PRELOAD.
    pub preload: bool,
    /// The reaction force.
    pub force: bool,
    /// The bending reaction moment.
    pub bending: bool,
    /// The torsional reaction moment (translational joints).
    pub torsion: bool,
}

/// The friction of one joint (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct JointFriction {
    /// How the joint slips.
    pub joint: FrictionJoint,
    /// μ below and at the stiction transition velocity (MU_STATIC, or MU_DYNAMIC when
    /// EFFECT = SLIDING).
    pub mu_peak: f64,
    /// μ from the sliding transition velocity on (MU_DYNAMIC, or 0 when EFFECT =
    /// STICTION).
    pub mu_tail: f64,
    /// STICTION_TRANSITION_VELOCITY.
    pub vs: f64,
    /// TRANSITION_VELOCITY_COEFFICIENT × vs.
    pub vd: f64,
    /// FRICTION_FORCE_PRELOAD.
    pub preload: f64,
    /// MAX_FRICTION_FORCE / MAX_FRICTION_TORQUE.
    pub max: Option<f64>,
    /// What loads the friction.
    pub loading: Loading,
    /// PIN_RADIUS.
    pub pin_radius: f64,
    /// BALL_RADIUS.
    pub ball_radius: f64,
    /// FRICTION_ARM.
    pub friction_arm: f64,
    /// BENDING_REACTION_ARM.
    pub bending_arm: f64,
    /// INITIAL_OVERLAP.
    pub overlap: f64,
    /// How the overlap follows the travel along z_J: +1 INCREASE, −1 DECREASE, 0.
    pub overlap_sign: f64,
    /// The travel along z_J the overlap is measured from (I's at the build).
    pub travel0: f64,
    /// The reaction on I in J's axes, FX FY FZ TX TY TZ: indices into
    /// [`super::ForceSet::solution`].
    pub reaction: [usize; 6],
    /// The stiction deformation (none with EFFECT = SLIDING); its channel is set when
    /// its state joins the state elements' block.
    pub stiction: Option<Stiction>,
}

impl JointFriction {
    /// The friction of FRICTION `f` in a joint that slips as `joint`, reading the
    /// joint's reaction from solution values `reaction`, its travel along z_J at the
    /// build `travel0`.
    pub fn new(
        f: &crate::model::friction::Friction,
        joint: FrictionJoint,
        reaction: [usize; 6],
        travel0: f64,
    ) -> JointFriction {
        use crate::model::friction::{FrictionEffect, OverlapDelta};
        let (mu_peak, mu_tail) = match f.effect {
            FrictionEffect::All => (f.mu_static, f.mu_dynamic),
            FrictionEffect::Stiction => (f.mu_static, 0.0),
            FrictionEffect::Sliding => (f.mu_dynamic, f.mu_dynamic),
        };
        let i = &f.inputs;
        JointFriction {
            joint,
            mu_peak,
            mu_tail,
            vs: f.stiction_velocity,
            vd: f.stiction_velocity * f.transition_coefficient.max(1.0 + 1e-9),
            preload: f.preload,
            max: f.max_friction,
            loading: Loading {
                preload: i.preload,
                force: i.reaction_force,
                bending: i.bending_moment,
                torsion: i.torsional_moment,
            },
            pin_radius: f.pin_radius,
            ball_radius: f.ball_radius,
            friction_arm: f.friction_arm,
            bending_arm: f.bending_arm,
            overlap: f.initial_overlap,
            overlap_sign: match f.overlap_delta {
                OverlapDelta::Constant => 0.0,
                OverlapDelta::Increase => 1.0,
                OverlapDelta::Decrease => -1.0,
            },
            travel0,
            reaction,
            stiction: (f.effect != FrictionEffect::Sliding).then_some(Stiction {
                max: f.max_stiction_deformation,
                channel: 0,
            }),
        }
    }
}

/// The numbers statics holds a joint from: the deformation at its start, then the
/// travel along z_J and I's axes in J's (9) there.
pub const POSE_LEN: usize = 10;

/// A friction's stiction deformation: its largest value and where its state's values
/// are (the state element block's channels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stiction {
    /// MAX_STICTION_DEFORMATION.
    pub max: f64,
    /// The first of its channels: δ (d), δ̇ (d), the statics flag (1), the statics
    /// anchor (d + [`POSE_LEN`]).
    pub channel: usize,
}

impl Stiction {
    /// How many channels a friction of `d` slip components takes.
    pub fn channels(d: usize) -> usize {
        3 * d + 1 + POSE_LEN
    }

    /// The channel of δ's component `c`.
    pub fn x(&self, c: usize) -> usize {
        self.channel + c
    }

    /// The channel of δ̇'s component `c` among `d`.
    pub fn rate(&self, d: usize, c: usize) -> usize {
        self.channel + d + c
    }

    /// The channel that is 1 while statics holds the joint, 0 in a run.
    pub fn flag(&self, d: usize) -> usize {
        self.channel + 2 * d
    }

    /// The first channel of the statics anchor: δc (d), the travel, I's axes in J's.
    pub fn anchor(&self, d: usize) -> usize {
        self.channel + 2 * d + 1
    }
}

impl FrictionJoint {
    /// How a joint of type `t` slips, when friction acts in it.
    pub fn of(t: crate::vocab::elements::JointType) -> Option<FrictionJoint> {
        use crate::vocab::elements::JointType as J;
        Some(match t {
            J::Revolute => FrictionJoint::Revolute,
            J::Translational => FrictionJoint::Translational,
            J::Cylindrical => FrictionJoint::Cylindrical,
            J::Spherical => FrictionJoint::Spherical,
            J::Hooke | J::Universal => FrictionJoint::Universal,
            _ => return None,
        })
    }
}
