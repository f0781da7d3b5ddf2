//! What an output expression reads: a measure slot of the model resolved to a
//! kinematic measure of the system ([`crate::mbd::measures`]) or to what only the
//! dynamics gives: an acceleration, an element's force function, the net load between
//! two markers, an Euler parameter ([`OutputSlot`]). Resolving needs only the model and
//! the system, so forces and the build may hold slots; their values are read from the
//! state of a dynamics (`OutputSlot::value` in `dynamics::outputs`).

use super::error::MbdError;
use super::handles::MarkerHandle;
use super::measure_set::M;
use super::system::System;
use crate::model::elements::{MeasureSlot, Model};
use crate::vocab::elements::{ElementKind, ForceKind};

/// A measure slot an output expression reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OutputSlot {
    /// A kinematic measure (index into the system's measures).
    Kinematic(usize),
    /// ACCX/Y/Z (comp 0..3) or ACCM (comp 3) of i relative to j, differentiated in l,
    /// resolved in k.
    Acc {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Resolving frame.
        k: M,
        /// Frame of time differentiation.
        l: M,
        /// ACCX, ACCY, ACCZ (0..3) or ACCM (3).
        comp: u8,
    },
    /// WDTX/Y/Z or WDTM.
    AngAcc {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// Resolving frame.
        k: M,
        /// Frame of time differentiation.
        l: M,
        /// WDTX, WDTY, WDTZ (0..3) or WDTM (3).
        comp: u8,
    },
    /// An element's force function: element index (constraint or force list), jflag,
    /// comp 1..8, rm.
    ElementForce {
        /// Whether `element` indexes the constraints (else the forces).
        constraint: bool,
        /// Index into the constraint or force list.
        element: usize,
        /// Whether the load is the one on the J marker.
        jflag: bool,
        /// Component 1..8 of the force function.
        comp: u8,
        /// The marker the components are resolved in.
        rm: M,
    },
    /// CONTACT(id, jflag, comp, rm): contact `contact` (index in the model's CONTACTs);
    /// comp 1..8 as a force function, 9..12 its normal force, friction force,
    /// penetration and slip speed.
    Contact {
        /// Index into the model's CONTACTs (and the contact set's).
        contact: usize,
        /// The load on J's part instead of I's.
        jflag: bool,
        /// Component 1..12.
        comp: u8,
        /// The marker the components are resolved in.
        rm: M,
    },
    /// FX…TZ (comp 0..6), FM (6), TM (7): net load on i from elements between i and j,
    /// resolved in k.
    MarkerForce {
        /// The marker the loads act on.
        i: MarkerHandle,
        /// The other marker (None: ground): only elements between i and j count.
        j: M,
        /// The frame the components are resolved in.
        k: M,
        /// Component: FX…TZ 0..6, FM 6, TM 7.
        comp: u8,
    },
    /// ORIENT(27, comp, i, j): Euler parameter e0..e3 (comp 0..4) of i relative to j,
    /// with e0 ≥ 0.
    EulerParameter {
        /// Measured marker.
        i: M,
        /// Reference marker.
        j: M,
        /// e0..e3 (0..4).
        comp: u8,
    },
}

fn axis_of(name: &str) -> u8 {
    match name.as_bytes().get(name.len().wrapping_sub(1)) {
        Some(b'X') => 0,
        Some(b'Y') => 1,
        Some(b'Z') => 2,
        _ => 3,
    }
}

impl OutputSlot {
    /// True when the slot reads velocities, accelerations or forces: the state the
    /// outputs reconcile. Positions and orientations do not change under it.
    pub fn reads_reconciled(&self, sys: &System) -> bool {
        match self {
            OutputSlot::Kinematic(m) => sys.measures.list[*m].reads_velocity(),
            OutputSlot::EulerParameter { .. } => false,
            _ => true,
        }
    }

    /// True when the value follows the accelerations or the multipliers (an
    /// acceleration, a reaction, a net load that may include one), not only the state
    /// and the applied forces.
    pub fn reads_motion(&self) -> bool {
        match self {
            OutputSlot::Kinematic(_)
            | OutputSlot::EulerParameter { .. }
            | OutputSlot::Contact { .. }
            | OutputSlot::ElementForce {
                constraint: false, ..
            } => false,
            OutputSlot::Acc { .. }
            | OutputSlot::AngAcc { .. }
            | OutputSlot::ElementForce { .. }
            | OutputSlot::MarkerForce { .. } => true,
        }
    }

    /// True when the value is a constraint's reaction or may include one (a net load).
    pub fn reads_reaction(&self) -> bool {
        matches!(
            self,
            OutputSlot::ElementForce {
                constraint: true,
                ..
            } | OutputSlot::MarkerForce { .. }
        )
    }

    /// Resolves model slot `slot` for the dynamics: kinematic measures through the
    /// system's measure set, the rest here.
    pub fn resolve(sys: &mut System, model: &Model, slot: u32) -> Result<OutputSlot, MbdError> {
        let ms: &MeasureSlot = model
            .measures
            .get(slot as usize)
            .ok_or(MbdError::UnknownMeasureSlot(slot))?;
        let name = ms.name.as_str();
        let ids = &ms.ids;
        let marker = |n: usize| sys.marker_or_ground(ids.get(n).copied().unwrap_or(0));
        // Vector measures (…XYZ) carry their component in the slot.
        let comp = |n: &str| {
            if n.ends_with("XYZ") {
                ms.component
            } else {
                axis_of(n)
            }
        };
        let four =
            || -> Result<[M; 4], MbdError> { Ok([marker(0)?, marker(1)?, marker(2)?, marker(3)?]) };
        Ok(match name {
            "ORIENT" => {
                let code = ids.first().copied().unwrap_or(0);
                let comp = ids.get(1).copied().unwrap_or(0);
                if code != 27 || !(1..=4).contains(&comp) {
                    return Err(MbdError::OrientCode { code, comp });
                }
                OutputSlot::EulerParameter {
                    i: marker(2)?,
                    j: marker(3)?,
                    comp: comp as u8 - 1,
                }
            }
            n if n.starts_with("ACC") => {
                let [i, j, k, l] = four()?;
                OutputSlot::Acc {
                    i,
                    j,
                    k,
                    l,
                    comp: comp(n),
                }
            }
            n if n.starts_with("WDT") => {
                let [i, j, k, l] = four()?;
                OutputSlot::AngAcc {
                    i,
                    j,
                    k,
                    l,
                    comp: comp(n),
                }
            }
            "FX" | "FY" | "FZ" | "TX" | "TY" | "TZ" | "FXYZ" | "TXYZ" | "FM" | "TM" => {
                let [i, j, k, _] = four()?;
                let i = i.ok_or_else(|| MbdError::GroundForceMarker(name.to_string()))?;
                let c = match name {
                    "FM" => 6,
                    "TM" => 7,
                    n if n.starts_with('T') => 3 + comp(n),
                    n => comp(n),
                };
                OutputSlot::MarkerForce { i, j, k, comp: c }
            }
            "CONTACT" => {
                let id = ids.first().copied().unwrap_or(0);
                let c = ids.get(2).copied().unwrap_or(1);
                if !(1..=12).contains(&c) {
                    return Err(MbdError::ForceComponent {
                        name: name.to_string(),
                        id,
                        comp: c,
                    });
                }
                let contact = (model.contacts.iter().position(|k| i64::from(k.el.id) == id))
                    .ok_or_else(|| MbdError::UnknownForceElement {
                        name: name.to_string(),
                        id,
                    })?;
                OutputSlot::Contact {
                    contact,
                    jflag: ids.get(1).copied().unwrap_or(0) != 0,
                    comp: c as u8,
                    rm: marker(3)?,
                }
            }
            "JOINT" | "JPRIM" | "MOTION" | "SFORCE" | "VFORCE" | "VTORQ" | "GFORCE" | "BUSH"
            | "SPDP" | "BEAM" | "FIELD" | "FRICTION" => {
                let id = ids.first().copied().unwrap_or(0);
                let jflag = ids.get(1).copied().unwrap_or(0) != 0;
                let c = ids.get(2).copied().unwrap_or(1);
                if !(1..=8).contains(&c) {
                    return Err(MbdError::ForceComponent {
                        name: name.to_string(),
                        id,
                        comp: c,
                    });
                }
                let rm = marker(3)?;
                let want_constraint = |k: ElementKind| match name {
                    "JOINT" => matches!(k, ElementKind::Joint(_)),
                    "JPRIM" => matches!(k, ElementKind::Jprim(_)),
                    _ => k == ElementKind::Motion,
                };
                let force_kind = match name {
                    "SFORCE" => Some(ForceKind::Sforce),
                    "VFORCE" => Some(ForceKind::Vforce),
                    "VTORQ" => Some(ForceKind::Vtorque),
                    "GFORCE" => Some(ForceKind::Gforce),
                    "BUSH" => Some(ForceKind::Bushing),
                    "SPDP" => Some(ForceKind::Springdamper),
                    "BEAM" => Some(ForceKind::Beam),
                    "FIELD" => Some(ForceKind::Field),
                    "FRICTION" => Some(ForceKind::Friction),
                    _ => None,
                };
                let found = match force_kind {
                    None => sys
                        .elements
                        .iter()
                        .position(|e| e.elref.id as i64 == id && want_constraint(e.elref.kind))
                        .map(|e| (true, e)),
                    Some(fk) => model_force_index(model, fk, id).map(|e| (false, e)),
                };
                let (constraint, element) = found.ok_or_else(|| MbdError::UnknownForceElement {
                    name: name.to_string(),
                    id,
                })?;
                OutputSlot::ElementForce {
                    constraint,
                    element,
                    jflag,
                    comp: c as u8,
                    rm,
                }
            }
            _ => OutputSlot::Kinematic(sys.resolve_measure(model, ms)?),
        })
    }
}

/// The index of force element `id` of kind `fk` in the order [`System::forces_from_model`]
/// builds them (SFORCE, then VFORCE/VTORQUE/GFORCE, SPRINGDAMPER, BUSHING, BEAM, FIELD,
/// FRICTION).
fn model_force_index(model: &Model, fk: ForceKind, id: i64) -> Option<usize> {
    use crate::model::elements::VectorForceKind;
    let sf = model.sforces.len();
    let vf = model.vector_forces.len();
    let sd = model.spring_dampers.len();
    let bu = model.bushings.len();
    let (be, fi) = (model.beams.len(), model.fields.len());
    let id_is = |x: u32| x as i64 == id;
    match fk {
        ForceKind::Sforce => model.sforces.iter().position(|f| id_is(f.el.id)),
        ForceKind::Vforce | ForceKind::Vtorque | ForceKind::Gforce => {
            let want = match fk {
                ForceKind::Vforce => VectorForceKind::Vforce,
                ForceKind::Vtorque => VectorForceKind::Vtorque,
                _ => VectorForceKind::Gforce,
            };
            model
                .vector_forces
                .iter()
                .position(|f| f.kind == want && id_is(f.el.id))
                .map(|k| sf + k)
        }
        ForceKind::Springdamper => model
            .spring_dampers
            .iter()
            .position(|f| id_is(f.el.id))
            .map(|k| sf + vf + k),
        ForceKind::Bushing => model
            .bushings
            .iter()
            .position(|f| id_is(f.el.id))
            .map(|k| sf + vf + sd + k),
        ForceKind::Beam => model
            .beams
            .iter()
            .position(|f| id_is(f.el.id))
            .map(|k| sf + vf + sd + bu + k),
        ForceKind::Field => model
            .fields
            .iter()
            .position(|f| id_is(f.el.id))
            .map(|k| sf + vf + sd + bu + be + k),
        ForceKind::Friction => model
            .frictions
            .iter()
            .position(|f| id_is(f.el.id))
            .map(|k| sf + vf + sd + bu + be + fi + k),
    }
}
