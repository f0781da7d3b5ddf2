//! The measures a [`System`](super::system::System) holds, as data: what each one
//! measures ([`Measure`], resolved from a model slot), the set of them with its unwrapping
//! state ([`MeasureSet`]) and one measure's value with its derivatives ([`Evaluated`]).
//! Evaluating them is [`measures`](super::measures)' job; the data sits here, below it,
//! because the system owns it.

use super::dual::{D, PARTS};
use super::error::MbdError;
use super::handles::{MarkerHandle, PartHandle};
use crate::model::elements::MeasureSlot;
use crate::vocab::math::Vec3;

/// A marker, or the ground frame at the origin (None).
pub type M = Option<MarkerHandle>;

/// A resolved measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Measure {
    /// DX, DY, DZ (comp 0..3), DXYZ.
    Disp {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Resolving frame.
        k: M,
        /// Component along k's axes (0..3).
        comp: u8,
    },
    /// DM.
    Dist {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
    },
    /// AX, AY, AZ (axis 0..3), unwrapped.
    Angle {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// The axis of j the rotation is about (0..3).
        axis: u8,
    },
    /// PSI, THETA, PHI: body-fixed 3-1-3 angles of i relative to j.
    Euler313 {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// The angle: 0 PSI, 1 THETA, 2 PHI.
        which: u8,
    },
    /// YAW, PITCH, ROLL: body-fixed 3-2-1, pitch about −y.
    Euler321 {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// The angle: 0 YAW, 1 PITCH, 2 ROLL.
        which: u8,
    },
    /// MOTION B1, B2, B3: body-fixed 1-2-3 angles of i relative to j (B1, B3 unwrapped).
    Body123 {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// The angle: 0 B1, 1 B2, 2 B3.
        which: u8,
    },
    /// UVX, UVY, UVZ (axis) component `comp` in k.
    UnitVec {
        /// Measured marker.
        i: M,
        /// Resolving frame.
        k: M,
        /// The axis of i (0..3).
        axis: u8,
        /// Component along k's axes (0..3).
        comp: u8,
    },
    /// INCANG: included angle at j between j→i and j→k.
    IncAng {
        /// End of the first arm.
        i: M,
        /// Vertex.
        j: M,
        /// End of the second arm.
        k: M,
    },
    /// VX, VY, VZ, VXYZ.
    Vel {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Resolving frame.
        k: M,
        /// Frame of time differentiation.
        l: M,
        /// Component along k's axes (0..3).
        comp: u8,
    },
    /// VM.
    VelMag {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Frame of time differentiation.
        l: M,
    },
    /// VR.
    VelRad {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Frame of time differentiation.
        l: M,
    },
    /// WX, WY, WZ, WXYZ.
    AngVel {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Resolving frame.
        k: M,
        /// Component along k's axes (0..3).
        comp: u8,
    },
    /// WM.
    AngVelMag {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
    },
    /// RACKPIN: rotation of x_I about z_I measured from z_J, unwrapped.
    PinionAngle {
        /// The pinion marker.
        i: M,
        /// The rack marker.
        j: M,
    },
    /// VARVAL of a design variable (a VARIABLE whose FUNCTION is a constant): a value
    /// the compiled expressions read as an input, set per run ([`MeasureSet::set_design`])
    /// without compiling anything again. It does not depend on the state.
    Design {
        /// The VARIABLE's id.
        id: i64,
    },
    /// A state element's value (DIF, DIF1, ARYVAL of an LSE or TFSISO array): entry
    /// `channel` of [`MeasureSet::states`], which the state solve writes
    /// ([`crate::mbd::states`]); no derivative with respect to q or v.
    State {
        /// Its place in the state values ([`crate::model::states::StateElements::channel`]).
        channel: u32,
    },
}

impl Measure {
    /// The markers the measure reads (None = ground).
    pub fn markers(&self) -> [M; 4] {
        use Measure::*;
        match *self {
            Disp { i, j, k, .. } | IncAng { i, j, k } | AngVel { i, j, k, .. } => [i, j, k, None],
            Vel { i, j, k, l, .. } => [i, j, k, l],
            VelMag { i, j, l } | VelRad { i, j, l } => [i, j, l, None],
            Dist { i, j }
            | Angle { i, j, .. }
            | Euler313 { i, j, .. }
            | Euler321 { i, j, .. }
            | Body123 { i, j, .. }
            | AngVelMag { i, j }
            | PinionAngle { i, j } => [i, j, None, None],
            UnitVec { i, k, .. } => [i, k, None, None],
            Design { .. } | State { .. } => [None; 4],
        }
    }

    /// How many of [`Measure::markers`] its formula reads (the others are always None).
    pub fn frames_read(&self) -> usize {
        use Measure::*;
        match self {
            Vel { .. } => 4,
            Disp { .. } | IncAng { .. } | AngVel { .. } | VelMag { .. } | VelRad { .. } => 3,
            _ => 2,
        }
    }

    /// True for measures that accumulate turns.
    pub fn unwrapped(&self) -> bool {
        matches!(
            self,
            Measure::Angle { .. }
                | Measure::IncAng { .. }
                | Measure::PinionAngle { .. }
                | Measure::Body123 { which: 0 | 2, .. }
        )
    }

    /// True for measures that read velocities.
    pub fn reads_velocity(&self) -> bool {
        use Measure::*;
        matches!(
            self,
            Vel { .. } | VelMag { .. } | VelRad { .. } | AngVel { .. } | AngVelMag { .. }
        )
    }

    /// Resolves a measure slot of the model; `marker` maps an id (0 = ground) to a marker.
    pub fn resolve(
        slot: &MeasureSlot,
        marker: &dyn Fn(i64) -> Result<M, MbdError>,
    ) -> Result<Measure, MbdError> {
        let name = slot.name.as_str();
        let ids = &slot.ids;
        let m = |n: usize| -> Result<M, MbdError> { ids.get(n).map_or(Ok(None), |&id| marker(id)) };
        use Measure::*;
        let xyz = |s: &str| match s.as_bytes().last() {
            Some(b'X') => 0,
            Some(b'Y') => 1,
            _ => 2,
        };
        // Component of a vector measure: from the slot for DXYZ, VXYZ, WXYZ, UVX...;
        // from the name for DX, VY, WZ.
        let comp = if name.ends_with("XYZ") {
            slot.component
        } else {
            xyz(name)
        };
        let which = |names: [&str; 3]| names.iter().position(|n| *n == name).unwrap_or(0) as u8;
        Ok(match name {
            "DX" | "DY" | "DZ" | "DXYZ" => Disp {
                i: m(0)?,
                j: m(1)?,
                k: m(2)?,
                comp,
            },
            "DM" => Dist { i: m(0)?, j: m(1)? },
            "AX" | "AY" | "AZ" => Angle {
                i: m(0)?,
                j: m(1)?,
                axis: comp,
            },
            "PSI" | "THETA" | "PHI" => Euler313 {
                i: m(0)?,
                j: m(1)?,
                which: which(["PSI", "THETA", "PHI"]),
            },
            "YAW" | "PITCH" | "ROLL" => Euler321 {
                i: m(0)?,
                j: m(1)?,
                which: which(["YAW", "PITCH", "ROLL"]),
            },
            "UVX" | "UVY" | "UVZ" => UnitVec {
                i: m(0)?,
                k: m(1)?,
                axis: comp,
                comp: slot.component,
            },
            "INCANG" => IncAng {
                i: m(0)?,
                j: m(1)?,
                k: m(2)?,
            },
            "VX" | "VY" | "VZ" | "VXYZ" => Vel {
                i: m(0)?,
                j: m(1)?,
                k: m(2)?,
                l: m(3)?,
                comp,
            },
            "VM" => VelMag {
                i: m(0)?,
                j: m(1)?,
                l: m(2)?,
            },
            "VR" => VelRad {
                i: m(0)?,
                j: m(1)?,
                l: m(2)?,
            },
            "WX" | "WY" | "WZ" | "WXYZ" => AngVel {
                i: m(0)?,
                j: m(1)?,
                k: m(2)?,
                comp,
            },
            "WM" => AngVelMag { i: m(0)?, j: m(1)? },
            n if n.starts_with("ACC") || n.starts_with("WDT") => {
                return Err(MbdError::NeedsDynamics(slot.name.clone(), "accelerations"))
            }
            "FX" | "FY" | "FZ" | "FM" | "TX" | "TY" | "TZ" | "TM" | "FXYZ" | "TXYZ" | "SFORCE"
            | "VFORCE" | "VTORQ" | "GFORCE" | "BUSH" | "BEAM" | "FIELD" | "FRICTION" | "SPDP"
            | "NFORCE" | "JOINT" | "JPRIM" | "MOTION" | "CVCV" | "PTCV" | "CONTACT" => {
                return Err(MbdError::NeedsDynamics(slot.name.clone(), "forces"))
            }
            // VARIABLEs are inlined before measures resolve, except design variables: the
            // caller gives those their value ([`System::resolve_measure`]).
            "VARVAL" => Design {
                id: slot.ids.first().copied().unwrap_or(0),
            },
            _ => return Err(MbdError::NotKinematic(slot.name.clone())),
        })
    }
}

/// A measure's value and derivatives, with the parts its local directions belong to.
pub struct Evaluated {
    /// Value and derivatives over the local directions.
    pub d: D,
    /// The part each block of local directions belongs to (None: unused).
    pub parts: [Option<PartHandle>; PARTS],
}

/// The measures of a system and their unwrapping state. The unwrapping fields are open
/// to `mbd` because [`measures`](super::measures) moves and reads them.
#[derive(Clone, Debug, Default)]
pub struct MeasureSet {
    /// The measures, indexed as [`MeasureSet::add`] returned.
    pub list: Vec<Measure>,
    /// Unwrapping reference per measure (NaN: none yet).
    pub(super) refs: Vec<f64>,
    /// INCANG rotation axis fixed at the first commit.
    pub(super) axes: Vec<Option<Vec3>>,
    /// The value of each design variable the measures read, by VARIABLE id.
    pub(super) design: Vec<(i64, f64)>,
    /// The state elements' values ([`Measure::State`]), as the last state solve left them.
    pub states: Vec<f64>,
}
