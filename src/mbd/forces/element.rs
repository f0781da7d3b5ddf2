//! A force element as data: the markers it acts between and its law ([`ForceLaw`],
//! the expressions or constants it turns into loads), with the expressions and measures
//! it reads.

use super::inputs::{Scalar, Source};
use crate::mbd::handles::MarkerHandle;
use crate::mbd::measure_set::{Measure, M};
use crate::mbd::measures::PartSlots;
use crate::vocab::elements::ElementRef;
use crate::vocab::math::Vec3;

/// How an element turns its inputs into loads.
pub enum ForceLaw {
    /// SFORCE TRANSLATION: f along the line from J to I at I (f > 0 pushes apart); the
    /// reaction at J unless action-only, where f acts along z_J at I alone.
    Line {
        /// The force magnitude.
        f: Scalar,
        /// ACTIONONLY: no reaction at J.
        action_only: bool,
    },
    /// SFORCE ROTATION: torque f·z_J on I's part, −f·z_J on J's unless action-only.
    Torque {
        /// The torque magnitude.
        f: Scalar,
        /// ACTIONONLY: no reaction on J's part.
        action_only: bool,
    },
    /// VFORCE, VTORQUE, GFORCE: components in RM axes at I; the reaction at the
    /// floating marker, which sits on I (no moment arm between them).
    Vector {
        /// FX FY FZ (None for a VTORQUE).
        force: Option<Box<[Scalar; 3]>>,
        /// TX TY TZ (None for a VFORCE).
        torque: Option<Box<[Scalar; 3]>>,
        /// RM: the frame the components are resolved in.
        rm: M,
    },
    /// SPRINGDAMPER TRANSLATION: f = −c·ḋ − k·(d − length) + preload along the line.
    Spring {
        /// K: stiffness.
        k: f64,
        /// C: damping.
        c: f64,
        /// LENGTH: free length.
        length: f64,
        /// FORCE: preload.
        preload: f64,
    },
    /// SPRINGDAMPER ROTATION: t = −c·θ̇ − k·(θ − angle) + preload about z_J, θ = AZ(I, J)
    /// (the measure `angle_measure`, unwrapped).
    RotSpring {
        /// KT: rotational stiffness.
        k: f64,
        /// CT: rotational damping.
        c: f64,
        /// ANGLE: free angle.
        angle: f64,
        /// TORQUE: preload.
        preload: f64,
        /// Index of the AZ(I, J) measure in the system's measures.
        angle_measure: usize,
    },
    /// BUSHING: per component in J axes, F = −K·d − C·ḋ + F₀ and T = −KT·θ − CT·ω + T₀
    /// with θ the AX, AY, AZ measures (`angles`), applied at I; the reaction on J.
    Bushing {
        /// K: stiffness per J axis.
        k: Vec3,
        /// C: damping per J axis.
        c: Vec3,
        /// KT: rotational stiffness per J axis.
        kt: Vec3,
        /// CT: rotational damping per J axis.
        ct: Vec3,
        /// FORCE: preload force per J axis.
        force: Vec3,
        /// TORQUE: preload torque per J axis.
        torque: Vec3,
        /// Indices of the AX, AY, AZ measures of I relative to J.
        angles: [usize; 3],
    },
    /// FIELD and BEAM: (F, T) = −K·(X − L) − C·V + (F₀, T₀) in J axes on I, X the
    /// deflection of I relative to J (the AX, AY, AZ measures `angles` for its angles);
    /// the reaction on J.
    Field {
        /// K, C, L and the preload.
        law: Box<super::field::Linear6>,
        /// Indices of the AX, AY, AZ measures of I relative to J.
        angles: [usize; 3],
    },
    /// FRICTION: the friction of the joint between I and J, loaded by the joint's
    /// reaction (solution values); the reaction on J.
    Friction(Box<super::friction::JointFriction>),
}

/// One force element.
pub struct ForceElement {
    /// The Adams element, for messages and outputs.
    pub elref: ElementRef,
    /// The I marker, where the action applies.
    pub i: MarkerHandle,
    /// J, or JFLOAT for the vector forces.
    pub j: Option<MarkerHandle>,
    /// How the element computes its loads.
    pub law: ForceLaw,
    /// The parts the element's duals read (set by [`ForceSet::prepare`]).
    ///
    /// [`ForceSet::prepare`]: super::ForceSet::prepare
    pub slots: PartSlots,
}

impl ForceElement {
    /// An element whose part slots [`ForceSet::prepare`] fills later.
    ///
    /// [`ForceSet::prepare`]: super::ForceSet::prepare
    pub fn new(elref: ElementRef, i: MarkerHandle, j: Option<MarkerHandle>, law: ForceLaw) -> Self {
        ForceElement {
            elref,
            i,
            j,
            law,
            slots: PartSlots::default(),
        }
    }

    /// The element's expressions.
    pub fn expressions(&self) -> impl Iterator<Item = &Scalar> {
        let (one, three) = match &self.law {
            ForceLaw::Line { f, .. } | ForceLaw::Torque { f, .. } => (Some(f), None),
            ForceLaw::Vector { force, torque, .. } => (None, Some((force, torque))),
            _ => (None, None),
        };
        let three = three
            .into_iter()
            .flat_map(|(f, t)| f.iter().chain(t.iter()).flat_map(|b| b.iter()));
        one.into_iter().chain(three)
    }

    /// The element's expressions, mutable, in the order of [`ForceElement::expressions`].
    pub(super) fn expressions_mut(&mut self) -> impl Iterator<Item = &mut Scalar> {
        let (one, three) = match &mut self.law {
            ForceLaw::Line { f, .. } | ForceLaw::Torque { f, .. } => (Some(f), None),
            ForceLaw::Vector { force, torque, .. } => (None, Some((force, torque))),
            _ => (None, None),
        };
        let three = three
            .into_iter()
            .flat_map(|(f, t)| f.iter_mut().chain(t.iter_mut()).flat_map(|b| b.iter_mut()));
        one.into_iter().chain(three)
    }

    /// The solution values the element reads: its expressions' and its law's.
    pub(super) fn solution_reads(&self) -> Vec<usize> {
        let mut r: Vec<usize> = self
            .expressions()
            .flat_map(|s| s.solution_reads())
            .collect();
        if let ForceLaw::Friction(f) = &self.law {
            r.extend_from_slice(&f.reaction);
        }
        r.sort_unstable();
        r.dedup();
        r
    }

    /// The measures the element's expressions and laws read.
    pub(super) fn measures(&self) -> Vec<usize> {
        let mut out: Vec<usize> = self
            .expressions()
            .flat_map(|s| s.map.iter())
            .filter_map(|s| match s {
                Source::Measure(m) => Some(*m),
                Source::Solution(_) => None,
            })
            .collect();
        match &self.law {
            ForceLaw::RotSpring { angle_measure, .. } => out.push(*angle_measure),
            ForceLaw::Bushing { angles, .. } | ForceLaw::Field { angles, .. } => {
                out.extend_from_slice(angles)
            }
            _ => {}
        }
        out
    }
}

/// The angle measure a rotational element reads: AX, AY or AZ of I relative to J.
pub fn angle_of(i: MarkerHandle, j: Option<MarkerHandle>, axis: u8) -> Measure {
    Measure::Angle {
        i: Some(i),
        j,
        axis,
    }
}
