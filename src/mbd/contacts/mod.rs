//! CONTACT forces (issue 40 §1): per CONTACT, the pairs of its I and J geometries; at
//! each evaluation of the forces the geometry layer ([`crate::collide`]) gives each
//! touching pair its incidents (one per connected intersection region: depth, normal,
//! centroid), and each incident becomes a normal force by the contact's law ([`law`]:
//! IMPACT or POISSON) plus Coulomb friction in the tangent plane, applied at the centroid
//! on I's part and reacted on J's.
//!
//! The Jacobians ∂Q/∂q and ∂Q/∂v are the exact derivatives of the laws with the normal
//! and the material points held fixed at the evaluation (the geometry's own change of
//! normal and centroid is left out), plus the turning of each force's moment arm with its
//! part. Onset, separation and the clamp of a damped law pulling are switches for the
//! step control ([`ContactSet::switches`]), which the event machinery of IMPACT locates.
//! A pair with a stand-in geometry (the placeholder of an EXTERNAL without its mesh) that
//! overlaps at the assembled start is held out until it first separates
//! ([`ContactSet::held_out`]).
//!
//! The files, one job each: `law` (the normal laws and the friction coefficient),
//! `build` (a model's CONTACTs into a set and its world), `eval` (loads, Jacobians,
//! switches and the values an output reads), `reach` (the step no pair can pass
//! through another in).

mod build;
mod eval;
pub mod law;
mod reach;

use crate::collide::{Incident, World};
use crate::mbd::handles::PartHandle;
use crate::model::contact::{Friction, NormalLaw};
use crate::model::elements::Id;
use std::cell::RefCell;
use std::collections::HashMap;

/// The model's contacts and the world their geometries live in (empty: no CONTACT).
#[derive(Default)]
pub struct ContactSet {
    /// One per CONTACT, in model order.
    pub contacts: Vec<ContactForce>,
    /// One per watched pair of geometries (the world's pair index).
    pairs: Vec<Pair>,
    /// The geometries and their queries (None: no CONTACT).
    world: Option<RefCell<World>>,
    /// The system part of each Adams PART id a geometry moves with.
    parts: HashMap<Id, PartHandle>,
    /// Scratch: one pair's incidents, and the pairs that may touch.
    incidents: RefCell<Vec<Incident>>,
    candidates: RefCell<Vec<usize>>,
    /// The CONTACTs left out of the set (their ids) and why (`GRAPHICS/10 cannot be a
    /// contact geometry: …`), for the run to warn about.
    pub left_out: Vec<(Id, String)>,
    /// Set while statics runs: a DYNAMICS_ONLY contact then has no friction.
    pub statics: bool,
    /// Per watched pair: held out (no force, no switch) until it is first found apart. A
    /// pair with a stand-in geometry (a placeholder for an EXTERNAL without its mesh)
    /// that overlaps at the assembled start is: the overlap is the stand-in's artefact.
    held: Vec<bool>,
    /// `held` as built, for a run started again ([`ContactSet::forget_state`]).
    held_at_start: Vec<bool>,
    /// The pairs held out at the start, for the run to warn about.
    pub held_out: Vec<HeldOut>,
}

/// A pair with a stand-in geometry that overlaps at the start, held out until it
/// separates.
#[derive(Clone, Debug, PartialEq)]
pub struct HeldOut {
    /// The CONTACT id.
    pub contact: Id,
    /// The GRAPHICS ids of its I and J geometries.
    pub graphics: (Id, Id),
    /// The deepest overlap at the start (model length units).
    pub depth: f64,
}

/// One CONTACT: its id, laws, and its values at the last evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactForce {
    /// The CONTACT id.
    pub id: Id,
    /// The normal law.
    pub normal: NormalLaw,
    /// Friction (mode OFF: none).
    pub friction: Friction,
    /// The values at the last evaluation.
    pub last: ContactValues,
}

/// What a contact did at the last evaluation, summed over its incidents.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactValues {
    /// Σ normal force magnitudes.
    pub normal: f64,
    /// Σ friction force magnitudes.
    pub friction: f64,
    /// The deepest penetration (0 apart).
    pub penetration: f64,
    /// The fastest slip speed at an incident (0 apart).
    pub slip: f64,
    /// The total force on I's part, global axes.
    pub force: crate::vocab::math::Vec3,
    /// The total moment on I's part about its reference point, global axes.
    pub torque: crate::vocab::math::Vec3,
    /// The total moment on J's part about its reference point, global axes.
    pub torque_j: crate::vocab::math::Vec3,
}

/// A watched pair: the CONTACT it belongs to and the system parts of its I and J sides.
#[derive(Clone, Copy, Debug)]
struct Pair {
    contact: usize,
    i: PartHandle,
    j: PartHandle,
}

impl ContactSet {
    /// Whether the set holds no contact.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    /// The pairs of system parts a contact may couple (I's, J's), for the Newton
    /// matrix's pattern; repeats possible.
    pub fn coupled_parts(&self) -> impl Iterator<Item = (PartHandle, PartHandle)> + '_ {
        self.pairs.iter().map(|p| (p.i, p.j))
    }

    /// Back to the start of a run: the pairs held out at the start are held again.
    pub fn forget_state(&mut self) {
        self.held.clone_from(&self.held_at_start);
    }

    /// How many switching values [`ContactSet::switches`] gives: two per pair.
    pub fn switch_count(&self) -> usize {
        2 * self.pairs.len()
    }
}
