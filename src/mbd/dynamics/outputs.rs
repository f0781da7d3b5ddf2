//! What the dynamics makes measurable (multibody spec §8, expr-language §6): the
//! acceleration measures ACCX…ACCZ, ACCM, WDTX…WDTZ; the reaction of every JOINT,
//! JPRIM, MOTION and GCON from its multipliers; the element force functions
//! `JOINT(id, jflag, comp, rm)`, `SFORCE(…)`, …; and FX…TZ, FM, TM, the net force between
//! two markers. Kinematic measures stay with [`crate::mbd::measures`]; [`OutputSlot`]
//! resolves a model measure slot to either, and [`OutputSlot::value`] reads it from the
//! state of a [`Dynamics`] at an output time (after [`Dynamics::refresh_outputs`]).

use super::Dynamics;
use crate::mbd::constraints::Row;
use crate::mbd::error::MbdError;
use crate::mbd::measures::M;
use crate::mbd::system::{MarkerHandle, PartHandle, System};
use crate::model::elements::{MeasureSlot, Model};
use crate::vocab::elements::{ElementKind, ForceKind};
use crate::vocab::math::Vec3;

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
            "JOINT" | "JPRIM" | "MOTION" | "SFORCE" | "VFORCE" | "VTORQ" | "GFORCE" | "BUSH"
            | "SPDP" => {
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

    /// The value at the state of `d` (after [`Dynamics::refresh_outputs`]).
    pub fn value(&self, d: &Dynamics) -> f64 {
        let sys = &d.sys;
        match *self {
            // The value alone: a row needs no derivatives (a dual frame is 7 KB, and
            // building them was most of an output row's cost).
            OutputSlot::Kinematic(m) => sys.measures.unwrapped_value(sys, m),
            OutputSlot::Acc { i, j, k, l, comp } => {
                let (ri, vi, ai) = marker_motion(sys, i);
                let (rj, vj, aj) = marker_motion(sys, j);
                let (dd, dv, da) = (ri - rj, vi - vj, ai - aj);
                let (wl, al) = frame_rates(sys, l);
                let acc = da - al.cross(&dd) - 2.0 * wl.cross(&dv) + wl.cross(&wl.cross(&dd));
                resolve(sys, acc, k, comp)
            }
            OutputSlot::AngAcc { i, j, k, l, comp } => {
                let (wi, ai) = frame_rates(sys, i);
                let (wj, aj) = frame_rates(sys, j);
                let (wl, _) = frame_rates(sys, l);
                resolve(sys, (ai - aj) - wl.cross(&(wi - wj)), k, comp)
            }
            OutputSlot::ElementForce {
                constraint,
                element,
                jflag,
                comp,
                rm,
            } => {
                let (f, t) = if constraint {
                    d.constraint_load(element, jflag)
                } else {
                    force_load(d, element, jflag)
                };
                let v = if comp <= 4 { f } else { t };
                match comp {
                    1 | 5 => v.norm(),
                    c => resolve(sys, v, rm, c - if c <= 4 { 2 } else { 6 }),
                }
            }
            OutputSlot::EulerParameter { i, j, comp } => {
                let (ri, rj) = (sys.frame(i).rot, sys.frame(j).rot);
                let rel = nalgebra::Rotation3::from_matrix_unchecked(rj.transpose() * ri);
                let q = nalgebra::UnitQuaternion::from_rotation_matrix(&rel);
                let s = if q.w < 0.0 { -1.0 } else { 1.0 };
                s * [q.w, q.i, q.j, q.k][comp as usize]
            }
            OutputSlot::MarkerForce { i, j, k, comp } => {
                let (f, t) = d.marker_load(i, j);
                match comp {
                    6 => f.norm(),
                    7 => t.norm(),
                    c if c < 3 => resolve(sys, f, k, c),
                    c => resolve(sys, t, k, c - 3),
                }
            }
        }
    }
}

/// The index of force element `id` of kind `fk` in the order [`System::forces_from_model`]
/// builds them (SFORCE, then VFORCE/VTORQUE/GFORCE, SPRINGDAMPER, BUSHING).
fn model_force_index(model: &Model, fk: ForceKind, id: i64) -> Option<usize> {
    use crate::model::elements::VectorForceKind;
    let sf = model.sforces.len();
    let vf = model.vector_forces.len();
    let sd = model.spring_dampers.len();
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
    }
}

/// Position, velocity and acceleration of a marker's origin (ground origin for None).
fn marker_motion(sys: &System, m: M) -> (Vec3, Vec3, Vec3) {
    let f = sys.frame(m);
    let p = sys.part(f.part);
    (
        f.r,
        p.v + p.w.cross(&f.a),
        p.acc + p.alpha.cross(&f.a) + p.w.cross(&p.w.cross(&f.a)),
    )
}

/// Angular velocity and acceleration of a marker's part.
fn frame_rates(sys: &System, m: M) -> (Vec3, Vec3) {
    let p = sys.part(sys.frame(m).part);
    (p.w, p.alpha)
}

/// Component `comp` of global vector `v` in the axes of marker `k` (ground for None).
fn resolve(sys: &System, v: Vec3, k: M, comp: u8) -> f64 {
    if comp == 3 {
        return v.norm();
    }
    let axes = sys.frame(k).rot;
    axes.column(comp as usize).dot(&v)
}

/// Load (force, moment about the marker) of force element `e` on its I side (jflag
/// false) or J side.
fn force_load(d: &Dynamics, e: usize, jflag: bool) -> (Vec3, Vec3) {
    let l = d.forces.loads[e];
    if !jflag {
        return l.on_i;
    }
    let el = &d.forces.elements[e];
    let rj = d.sys.frame(el.j).r;
    // Moment about J's origin of the J-side load applied at `j_at`.
    (l.on_j.0, l.on_j.1 + (l.j_at - rj).cross(&l.on_j.0))
}

impl Dynamics {
    /// Re-evaluates constraints (with Φ_q) and forces at the current state so reactions
    /// and force functions read it exactly.
    pub fn refresh_outputs(&mut self) -> Result<(), MbdError> {
        self.eval_constraints(true)?;
        self.eval_forces(false)
    }

    /// The generalized force (F at the reference point, moment about it) the kept rows
    /// of constraint element `e` apply to part `p`: −Φ_qᵀλ restricted to them.
    fn element_on_part(&self, e: usize, p: PartHandle) -> (Vec3, Vec3) {
        let mut g = [0.0; 6];
        let cols: Vec<Option<usize>> = (0..6).map(|c| self.sys.col(p, c)).collect();
        for (r, c, x) in self.jac.entries() {
            if self.rows[r].0 != e {
                continue;
            }
            if let Some(k) = cols.iter().position(|&cc| cc == Some(c)) {
                g[k] -= x * self.lambda[r];
            }
        }
        (Vec3::new(g[0], g[1], g[2]), Vec3::new(g[3], g[4], g[5]))
    }

    /// The I and J markers of constraint element `e` (from its first equation).
    fn element_markers(&self, e: usize) -> (M, M) {
        match self.sys.elements[e].eqs.first().map(|q| &q.row) {
            Some(Row::Along { i, j, .. }) | Some(Row::Dot { i, j, .. }) => (Some(*i), Some(*j)),
            Some(Row::Measured { terms, .. }) => terms.first().map_or((None, None), |&(_, m)| {
                let mk = self.sys.measures.list[m].markers();
                (mk[0], mk[1])
            }),
            Some(Row::Gcon { map, .. }) => map.first().map_or((None, None), |&m| {
                let mk = self.sys.measures.list[m].markers();
                (mk[0], mk[1])
            }),
            None => (None, None),
        }
    }

    /// The reaction of constraint element `e` on its I marker's part (jflag false) or its
    /// J marker's part, as force and moment about that marker's origin, global axes.
    /// Where that part is ground (no columns), the other side's load reversed.
    pub fn constraint_load(&self, e: usize, jflag: bool) -> (Vec3, Vec3) {
        let (i, j) = self.element_markers(e);
        let (me, other) = if jflag { (j, i) } else { (i, j) };
        let at = self.sys.frame(me).r;
        let about = |p: PartHandle, (f, t): (Vec3, Vec3)| -> (Vec3, Vec3) {
            (f, t + (self.sys.part(p).r - at).cross(&f))
        };
        let pm = self.sys.frame(me).part;
        if self.sys.part(pm).index.is_some() {
            return about(pm, self.element_on_part(e, pm));
        }
        let po = self.sys.frame(other).part;
        let (f, t) = about(po, self.element_on_part(e, po));
        (-f, -t)
    }

    /// The net load on marker `i` from every element acting between markers `i` and `j`
    /// (forces and constraints, either way round), moment about `i`'s origin.
    pub fn marker_load(&self, i: MarkerHandle, j: M) -> (Vec3, Vec3) {
        let (mut f, mut t) = (Vec3::zeros(), Vec3::zeros());
        let ri = self.sys.frame(Some(i)).r;
        let same = |a: M, b: M| self.sys.frame(a).part == self.sys.frame(b).part && a == b;
        for e in 0..self.sys.elements.len() {
            let (ei, ej) = self.element_markers(e);
            let side = if same(ei, Some(i)) && same(ej, j) {
                Some(false)
            } else if same(ej, Some(i)) && same(ei, j) {
                Some(true)
            } else {
                None
            };
            if let Some(jflag) = side {
                let (ff, tt) = self.constraint_load(e, jflag);
                f += ff;
                t += tt;
            }
        }
        for (k, el) in self.forces.elements.iter().enumerate() {
            let side = if el.i == i && el.j == j {
                Some(false)
            } else if el.j == Some(i) && j == Some(el.i) {
                Some(true)
            } else {
                None
            };
            if let Some(jflag) = side {
                let (ff, tt) = force_load(self, k, jflag);
                let at = if jflag { self.sys.frame(el.j).r } else { ri };
                f += ff;
                t += tt + (at - ri).cross(&ff);
            }
        }
        (f, t)
    }
}
