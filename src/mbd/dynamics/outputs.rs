//! What the dynamics makes measurable (multibody spec §8, expr-language §6): the
//! acceleration measures ACCX…ACCZ, ACCM, WDTX…WDTZ; the reaction of every JOINT,
//! JPRIM, MOTION and GCON from its multipliers; the element force functions
//! `JOINT(id, jflag, comp, rm)`, `SFORCE(…)`, …; and FX…TZ, FM, TM, the net force between
//! two markers. Kinematic measures stay with [`crate::mbd::measures`]; [`OutputSlot`]
//! resolves a model measure slot to either, and [`OutputSlot::value`] reads it from the
//! state of a [`Dynamics`] at an output time (after [`Dynamics::refresh_outputs`]).

use super::setup::Dynamics;
use crate::mbd::error::MbdError;
use crate::mbd::measure_set::M;
use crate::mbd::output_slot::OutputSlot;
use crate::mbd::rows::Row;
use crate::mbd::system::{MarkerHandle, PartHandle, System};
use crate::vocab::math::Vec3;

impl OutputSlot {
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
            OutputSlot::Contact {
                contact,
                jflag,
                comp,
                rm,
            } => {
                let last = &d.forces.contacts.contacts[contact].last;
                let (f, t) = match jflag {
                    false => (last.force, last.torque),
                    true => (-last.force, last.torque_j),
                };
                let v = if comp <= 4 { f } else { t };
                match comp {
                    9 => last.normal,
                    10 => last.friction,
                    11 => last.penetration,
                    12 => last.slip,
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
    pub(super) fn element_markers(&self, e: usize) -> (M, M) {
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
