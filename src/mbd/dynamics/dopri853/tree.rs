//! Joint coordinates for the planar scenes that need no more: a tree of revolute and
//! translational joints hanging from ground, one joint per moving part and no other
//! constraint. There the motion has exactly one coordinate per joint (an angle or a
//! travel, measured from the starting pose), the constraints hold by construction, and
//! the equations of motion are an ODE of that size instead of the index-1 DAE over three
//! coordinates per part (the velocity transformation of García de Jalón & Bayo,
//! *Kinematic and Dynamic Simulation of Multibody Systems*, ch. 6):
//!
//! ```text
//! Bᵀ·(M/UCF)·B·θ̈ = Bᵀ·(Q − (M/UCF)·b),   v = B(θ)·θ̇,   a = B·θ̈ + b(θ, θ̇),
//! ```
//!
//! where B maps joint rates to the parts' planar velocities (vₐ, v_b, ω per part, the 2D
//! layout) and b is the parts' acceleration with θ̈ = 0. Both come from one pass from
//! ground outwards, parent before child:
//!
//! - revolute at the point s_p of the parent, s_c of the child (in their starting axes):
//!   φ_c = φ_p + θ, r_c = r_p + R(φ_p)·s_p − R(φ_c)·s_c;
//! - translational along u (parent's starting axes), the child's centre at e₀ + θ·u from
//!   the parent's: φ_c = φ_p, r_c = r_p + R(φ_p)·(e₀ + θ·u).
//!
//! The forces are the ones the Cartesian form evaluates, at the Cartesian state the
//! joint coordinates give ([`Dynamics::set_state`]), so everything that reads the state
//! (measures, contact switches, outputs, reactions) sees the same model.
//!
//! θ̈ comes from the articulated-body algorithm (`dopri853::articulated`) in O(N): the
//! kinematics gives each joint's link (d, s, β) as it places the parts. The dense normal
//! equations above, O(N³), are kept as its check (`JointTree::accelerations_dense`, a
//! test's).

use super::articulated::{Articulated, Link};
#[cfg(test)]
use crate::mbd::dense::DenseLlt;
use crate::mbd::dynamics::blocks::Mat3Block;
use crate::mbd::dynamics::failure::{DynError, Singularity};
use crate::mbd::dynamics::setup::Dynamics;
use crate::mbd::dynamics::state::Snapshot;
use crate::mbd::rows::Row;
use crate::mbd::system::Dimension;
use crate::vocab::elements::{ElementKind, JointType};
use crate::vocab::math::DVec;

/// One joint of the tree.
#[derive(Clone, Copy, Debug)]
struct Joint {
    /// The moving part it carries (velocity-layout index) and the one it hangs from
    /// (None: ground).
    child: usize,
    parent: Option<usize>,
    kind: Kind,
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    /// The joint point from the parent's and the child's centres, starting axes.
    Revolute { sp: [f64; 2], sc: [f64; 2] },
    /// The child's centre from the parent's at θ = 0, and the unit axis, starting axes.
    Translational { e0: [f64; 2], u: [f64; 2] },
}

/// A planar tree in joint coordinates: its joints parent first, the starting pose they
/// are measured from, and the buffers of one evaluation.
pub struct JointTree {
    joints: Vec<Joint>,
    /// The starting state the Cartesian state is set from.
    origin: Snapshot,
    /// Each moving part's centre at the start (plane coordinates).
    r0: Vec<[f64; 2]>,
    /// Per part: pose (rₐ, r_b, φ), velocity and bias acceleration in the 2D layout,
    /// and B's three rows (f joint columns each).
    pose: Vec<[f64; 3]>,
    /// Per part: (sin φ, cos φ) of its angle, computed once where the angle is made.
    turn: Vec<(f64, f64)>,
    vel: Vec<[f64; 3]>,
    bias: Vec<[f64; 3]>,
    /// Per joint: its link at the current kinematics, and the O(N) solver's buffers.
    links: Vec<Link>,
    articulated: Articulated,
    /// B (3 rows per part, a column per joint) and its normal matrix's factor, for the
    /// dense check only: empty until it runs.
    b: Vec<f64>,
    #[cfg(test)]
    llt: Option<DenseLlt>,
    dx: Vec<f64>,
    v: DVec,
}

/// ω × r in the plane.
fn cross(w: f64, r: [f64; 2]) -> [f64; 2] {
    [-w * r[1], w * r[0]]
}

/// R(φ)·x, with (sin φ, cos φ) given.
fn rotate((s, c): (f64, f64), x: [f64; 2]) -> [f64; 2] {
    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
}

impl JointTree {
    /// The tree of `d`'s model, when it is one: planar, every kept row in a revolute or
    /// translational JOINT, one joint per moving part linking it to ground through the
    /// others, no row dropped, no force reading the solution.
    pub fn of(d: &Dynamics) -> Option<JointTree> {
        let sys = &d.sys;
        let parts = sys.moving_parts();
        if sys.dim != Dimension::Two || !d.dropped.is_empty() || d.reads_solution() || parts == 0 {
            return None;
        }
        // Each element's kind and the two parts its rows join.
        let mut elements: Vec<(usize, JointType, [Option<usize>; 2])> = Vec::new();
        let mut seen = vec![false; sys.elements.len()];
        for &(e, q) in &d.rows {
            let el = &sys.elements[e];
            let ElementKind::Joint(t @ (JointType::Revolute | JointType::Translational)) =
                el.elref.kind
            else {
                return None;
            };
            let (i, j) = match &el.eqs[q].row {
                Row::Along { i, j, .. } | Row::Dot { i, j, .. } => (*i, *j),
                _ => return None,
            };
            let index = |m| sys.part(sys.marker(m).part).index;
            if !std::mem::replace(&mut seen[e], true) {
                elements.push((e, t, [index(i), index(j)]));
            }
        }
        if elements.len() != parts || d.rows.len() != 2 * parts {
            return None;
        }
        // Parent before child, from ground outwards.
        let (a, b, _) = sys.plane_axes();
        let moving: Vec<_> = sys.parts.iter().filter(|p| p.index.is_some()).collect();
        let mut r0 = vec![[0.0; 2]; parts];
        for p in &moving {
            r0[p.index?] = [p.r[a], p.r[b]];
        }
        // The elements at each part (ground last), walked breadth first from ground.
        let node = |x: Option<usize>| x.unwrap_or(parts);
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); parts + 1];
        for (k, &(_, _, ends)) in elements.iter().enumerate() {
            if node(ends[0]) == node(ends[1]) {
                return None;
            }
            at[node(ends[0])].push(k);
            at[node(ends[1])].push(k);
        }
        let mut placed = vec![false; parts + 1];
        placed[parts] = true;
        let mut used = vec![false; elements.len()];
        let mut joints = Vec::with_capacity(parts);
        let mut queue = std::collections::VecDeque::from([parts]);
        while let Some(from) = queue.pop_front() {
            let parent = (from < parts).then_some(from);
            for &k in &at[from] {
                if std::mem::replace(&mut used[k], true) {
                    continue;
                }
                let (e, t, ends) = elements[k];
                let other = if node(ends[0]) == from {
                    ends[1]
                } else {
                    ends[0]
                };
                // A second path to a placed part: a loop.
                let child = other.filter(|&c| !placed[c])?;
                placed[child] = true;
                queue.push_back(child);
                let joint = Self::joint(sys, (a, b), &r0, (e, t), parent, child)?;
                joints.push(joint);
            }
        }
        // A part off the tree (joined to ground through nothing).
        if joints.len() != parts {
            return None;
        }
        let f = joints.len();
        Some(JointTree {
            joints,
            origin: d.snapshot(),
            r0,
            pose: vec![[0.0; 3]; parts],
            turn: vec![(0.0, 1.0); parts],
            vel: vec![[0.0; 3]; parts],
            bias: vec![[0.0; 3]; parts],
            links: vec![Link::default(); f],
            articulated: Articulated::new(parts),
            b: Vec::new(),
            #[cfg(test)]
            llt: None,
            dx: vec![0.0; 3 * parts],
            v: DVec::zeros(3 * parts),
        })
    }

    /// The joint of element `e` (of type `t`), carrying `child` from `parent` (None:
    /// ground), from the starting pose (centres `r0`, plane axes `a`, `b`).
    fn joint(
        sys: &crate::mbd::system::System,
        (a, b): (usize, usize),
        r0: &[[f64; 2]],
        (e, t): (usize, JointType),
        parent: Option<usize>,
        child: usize,
    ) -> Option<Joint> {
        {
            let centre = |x: Option<usize>| x.map_or([0.0; 2], |i| r0[i]);
            let (pc, cc) = (centre(parent), r0[child]);
            let el = &sys.elements[e];
            let first = el.eqs.iter().find(|q| q.active)?;
            let (mi, mj) = match &first.row {
                Row::Along { i, j, .. } | Row::Dot { i, j, .. } => (*i, *j),
                _ => return None,
            };
            let kind = match t {
                JointType::Revolute => {
                    let p = sys.frame(Some(mi)).r;
                    let p = [p[a], p[b]];
                    Kind::Revolute {
                        sp: [p[0] - pc[0], p[1] - pc[1]],
                        sc: [p[0] - cc[0], p[1] - cc[1]],
                    }
                }
                _ => {
                    let z = sys.frame(Some(mj)).rot.column(2).into_owned();
                    let n = (z[a] * z[a] + z[b] * z[b]).sqrt();
                    if n < 0.5 {
                        return None;
                    }
                    Kind::Translational {
                        e0: [cc[0] - pc[0], cc[1] - pc[1]],
                        u: [z[a] / n, z[b] / n],
                    }
                }
            };
            Some(Joint {
                child,
                parent,
                kind,
            })
        }
    }

    /// Number of joint coordinates.
    pub fn coordinates(&self) -> usize {
        self.joints.len()
    }

    /// The moving part joint `k` carries (velocity-layout index).
    pub fn child(&self, k: usize) -> usize {
        self.joints[k].child
    }

    /// Whether joint coordinate `k` is an angle (else a travel).
    pub fn rotational(&self, k: usize) -> bool {
        matches!(self.joints[k].kind, Kind::Revolute { .. })
    }

    /// Poses, velocities, bias accelerations and each joint's link at coordinates
    /// `theta`, rates `rate`; B too when `dense` (the check's, O(N²)).
    fn kinematics(&mut self, theta: &[f64], rate: &[f64], dense: bool) {
        let f = self.joints.len();
        if dense {
            self.b.resize(3 * self.pose.len() * f, 0.0);
        }
        for (k, jt) in self.joints.iter().enumerate() {
            let c = jt.child;
            let (pp, pv, pb) = match jt.parent {
                Some(p) => (self.pose[p], self.vel[p], self.bias[p]),
                None => ([0.0; 3], [0.0; 3], [0.0; 3]),
            };
            // B's rows of the child start as the parent's (ground: zero).
            for row in (0..3).filter(|_| dense) {
                for col in 0..f {
                    self.b[(3 * c + row) * f + col] = match jt.parent {
                        Some(p) => self.b[(3 * p + row) * f + col],
                        None => 0.0,
                    };
                }
            }
            let (w_p, a_p) = (pv[2], pb[2]);
            // The parent's turn as its joint made it; ground's is exactly (0, 1).
            let turn_p = match jt.parent {
                Some(p) => self.turn[p],
                None => (0.0, 1.0),
            };
            match jt.kind {
                Kind::Revolute { sp, sc } => {
                    let phi = pp[2] + theta[k];
                    let w = w_p + rate[k];
                    let turn = phi.sin_cos();
                    self.turn[c] = turn;
                    let (gp, gc) = (rotate(turn_p, sp), rotate(turn, sc));
                    let (vp, vc) = (cross(w_p, gp), cross(w, gc));
                    let (ap, ac) = (cross(a_p, gp), cross(a_p, gc));
                    self.pose[c] = [pp[0] + gp[0] - gc[0], pp[1] + gp[1] - gc[1], phi];
                    self.vel[c] = [pv[0] + vp[0] - vc[0], pv[1] + vp[1] - vc[1], w];
                    self.bias[c] = [
                        pb[0] + ap[0] - w_p * w_p * gp[0] - ac[0] + w * w * gc[0],
                        pb[1] + ap[1] - w_p * w_p * gp[1] - ac[1] + w * w * gc[1],
                        a_p,
                    ];
                    // The child turns about the pin: its centre moves by −θ̇ × gc.
                    self.links[k] = Link {
                        d: [gp[0] - gc[0], gp[1] - gc[1]],
                        s: [gc[1], -gc[0], 1.0],
                        beta: [
                            w * w * gc[0] - w_p * w_p * gp[0],
                            w * w * gc[1] - w_p * w_p * gp[1],
                            0.0,
                        ],
                    };
                    for col in (0..f).filter(|_| dense) {
                        let bw_p = self.b[(3 * c + 2) * f + col];
                        let bw = bw_p + if col == k { 1.0 } else { 0.0 };
                        let (tp, tc) = (cross(bw_p, gp), cross(bw, gc));
                        self.b[3 * c * f + col] += tp[0] - tc[0];
                        self.b[(3 * c + 1) * f + col] += tp[1] - tc[1];
                        self.b[(3 * c + 2) * f + col] = bw;
                    }
                }
                Kind::Translational { e0, u } => {
                    let e = rotate(turn_p, [e0[0] + theta[k] * u[0], e0[1] + theta[k] * u[1]]);
                    let ug = rotate(turn_p, u);
                    self.turn[c] = turn_p;
                    let (ve, ae) = (cross(w_p, e), cross(a_p, e));
                    let cor = cross(w_p, ug);
                    self.pose[c] = [pp[0] + e[0], pp[1] + e[1], pp[2]];
                    self.vel[c] = [
                        pv[0] + ve[0] + ug[0] * rate[k],
                        pv[1] + ve[1] + ug[1] * rate[k],
                        w_p,
                    ];
                    self.bias[c] = [
                        pb[0] + ae[0] - w_p * w_p * e[0] + 2.0 * cor[0] * rate[k],
                        pb[1] + ae[1] - w_p * w_p * e[1] + 2.0 * cor[1] * rate[k],
                        a_p,
                    ];
                    // Centripetal and Coriolis accelerations of the slide.
                    self.links[k] = Link {
                        d: e,
                        s: [ug[0], ug[1], 0.0],
                        beta: [
                            2.0 * cor[0] * rate[k] - w_p * w_p * e[0],
                            2.0 * cor[1] * rate[k] - w_p * w_p * e[1],
                            0.0,
                        ],
                    };
                    for col in (0..f).filter(|_| dense) {
                        let bw = self.b[(3 * c + 2) * f + col];
                        let t = cross(bw, e);
                        let along = if col == k { 1.0 } else { 0.0 };
                        self.b[3 * c * f + col] += t[0] + along * ug[0];
                        self.b[(3 * c + 1) * f + col] += t[1] + along * ug[1];
                    }
                }
            }
        }
    }

    /// Puts `d` at joint coordinates `theta`, rates `rate`, time `t` (its Cartesian
    /// state, satisfying every joint exactly).
    pub fn place(&mut self, d: &mut Dynamics, theta: &[f64], rate: &[f64], t: f64) {
        self.kinematics(theta, rate, false);
        self.set_cartesian(d, t);
    }

    /// `d`'s Cartesian state from the kinematics last computed, at time `t`.
    fn set_cartesian(&mut self, d: &mut Dynamics, t: f64) {
        for (i, (p, v)) in self.pose.iter().zip(&self.vel).enumerate() {
            self.dx[3 * i] = p[0] - self.r0[i][0];
            self.dx[3 * i + 1] = p[1] - self.r0[i][1];
            self.dx[3 * i + 2] = p[2];
            self.v.as_mut_slice()[3 * i..3 * i + 3].copy_from_slice(v);
        }
        d.set_state(&self.origin, &self.dx, &self.v, t);
    }

    /// The joint accelerations θ̈ into `out` at joint coordinates `theta`, rates `rate`,
    /// time `t`; leaves `d` at that state, unless `stage` (a stage of a step, whose state
    /// nothing reads afterwards) and no force element reads it: with gravity alone, in
    /// the plane, neither Q nor the mass blocks depend on where the parts are, so they
    /// are not moved, a quarter of a stage's work on a pendulum (callgrind, A01).
    pub fn accelerations(
        &mut self,
        d: &mut Dynamics,
        (theta, rate, t): (&[f64], &[f64], f64),
        out: &mut [f64],
        stage: bool,
    ) -> Result<(), DynError> {
        self.kinematics(theta, rate, false);
        if !(stage && d.forces.elements.is_empty() && d.forces.contacts.is_empty()) {
            self.set_cartesian(d, t);
        }
        d.eval_forces(false)?;
        d.check_forces()?;
        self.articulated_solve(d, t, out, true)
    }

    /// The joint rates of `d`'s current (consistent) velocities, closest in the mass
    /// metric, into `rate`, at the starting pose (θ = 0): Bᵀ·M·B·θ̇ = Bᵀ·M·v, which is
    /// the articulated-body solve with the loads M·v and no velocity products.
    pub fn rates_at_start(&mut self, d: &mut Dynamics, rate: &mut [f64]) -> Result<(), DynError> {
        let zero = vec![0.0; self.joints.len()];
        self.kinematics(&zero, &zero, false);
        let v: Vec<f64> = d.sys.v().iter().copied().collect();
        let blocks = d.mass_blocks();
        let load = |i: usize| {
            let (m, j) = planar_mass(&blocks[i]);
            [m * v[3 * i], m * v[3 * i + 1], j * v[3 * i + 2]]
        };
        let joints = &self.joints;
        let solved = self.articulated.solve(
            &self.links,
            |k| joints[k].child,
            |k| joints[k].parent,
            |i| planar_mass(&blocks[i]),
            load,
            false,
            rate,
        );
        solved.map_err(|_| singular(d.sys.time))
    }

    /// θ̈ into `out` from `d`'s Q and mass blocks at the links last computed (with their
    /// velocity products when `bias`).
    fn articulated_solve(
        &mut self,
        d: &Dynamics,
        t: f64,
        out: &mut [f64],
        bias: bool,
    ) -> Result<(), DynError> {
        let blocks = d.mass_blocks();
        let q = &d.gen.q;
        let joints = &self.joints;
        let solved = self.articulated.solve(
            &self.links,
            |k| joints[k].child,
            |k| joints[k].parent,
            |i| planar_mass(&blocks[i]),
            |i| [q[3 * i], q[3 * i + 1], q[3 * i + 2]],
            bias,
            out,
        );
        solved.map_err(|_| singular(t))
    }

    /// θ̈ as [`Self::accelerations`] gives it (with `stage` false), from the dense
    /// normal equations Bᵀ·(M/UCF)·B·θ̈ = Bᵀ·(Q − (M/UCF)·b), O(N³): the articulated-body
    /// algorithm's check.
    #[cfg(test)]
    fn accelerations_dense(
        &mut self,
        d: &mut Dynamics,
        (theta, rate, t): (&[f64], &[f64], f64),
        out: &mut [f64],
    ) -> Result<(), DynError> {
        self.kinematics(theta, rate, true);
        self.set_cartesian(d, t);
        d.eval_forces(false)?;
        d.check_forces()?;
        let bias = std::mem::take(&mut self.bias);
        let solved = self.solve_normal(d, t, out, |i, row, w| {
            d.gen.q[3 * i + row] - w * bias[i][row]
        });
        self.bias = bias;
        solved
    }

    /// Solves Bᵀ·M·B·x = Bᵀ·g into `x`, g's entry for part `i`, layout row `row` given by
    /// `g(i, row, mass weight)`, with B and `d`'s mass blocks at the current kinematics.
    #[cfg(test)]
    fn solve_normal(
        &mut self,
        d: &Dynamics,
        t: f64,
        x: &mut [f64],
        g: impl Fn(usize, usize, f64) -> f64,
    ) -> Result<(), DynError> {
        let f = self.joints.len();
        let llt = self.llt.get_or_insert_with(|| DenseLlt::new(f));
        let m = llt.matrix_mut();
        m.fill(0.0);
        x.fill(0.0);
        for (i, blk) in d.mass_blocks().iter().enumerate() {
            let (mass, inertia) = planar_mass(blk);
            for (row, w) in [mass, mass, inertia].into_iter().enumerate() {
                let r = &self.b[(3 * i + row) * f..(3 * i + row + 1) * f];
                let load = g(i, row, w);
                for (col, &bc) in r.iter().enumerate() {
                    if bc == 0.0 {
                        continue;
                    }
                    x[col] += bc * load;
                    // The lower triangle (rows from `col` down), which the Cholesky reads.
                    for (k, &bk) in r.iter().enumerate().skip(col) {
                        m[col * f + k] += w * bc * bk;
                    }
                }
            }
        }
        if llt.factor().is_err() {
            return Err(singular(t));
        }
        llt.solve(x);
        Ok(())
    }
}

/// A planar part's mass and centroidal inertia (over UCF, as the mass blocks hold them);
/// NaN for a 3D block, which a planar tree never has, so the solve reports it singular.
fn planar_mass(blk: &Mat3Block) -> (f64, f64) {
    match *blk {
        Mat3Block::Two(m, j) => (m, j),
        _ => (f64::NAN, f64::NAN),
    }
}

/// The failure of a joint-space solve at time `t`.
fn singular(t: f64) -> DynError {
    DynError::Singular {
        time: t,
        why: Singularity::Numerical,
        culprit: None,
    }
}

#[cfg(test)]
mod tests {
    //! The articulated-body θ̈ against the dense normal equations' (two algorithms over
    //! the same kinematics and loads) on random states of random planar trees.
    use super::*;
    use crate::mbd::compiled::CompiledExprs;
    use crate::mbd::planar::Dim;
    use crate::mbd::system::System;
    use crate::model::read_model;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};
    use std::fmt::Write as _;

    /// A planar tree of `n` parts (PART/2..): joint k carries part k+1 from part
    /// `parent(k)` (0: ground); revolute or translational at random, with random masses,
    /// inertias, centres, pins and slide axes; gravity and a spring-damper from ground
    /// to the last part, so Q depends on the state.
    fn random_tree(rng: &mut StdRng, n: usize, chain: bool) -> String {
        let mut s = String::from("random tree\nPART/1, GROUND\nMARKER/1, PART = 1\n");
        let mut centre = vec![[0.0, 0.0]];
        for k in 1..=n {
            let p = k + 1;
            let c = [rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0)];
            centre.push(c);
            let (m, izz) = (rng.random_range(0.1..3.0), rng.random_range(0.01..1.0));
            let _ = writeln!(
                s,
                "PART/{p}, MASS = {m}, CM = {p}01, IP = 1, 1, {izz}\n\
                 MARKER/{p}01, PART = {p}, QP = {}, {}, 0",
                c[0], c[1]
            );
        }
        for (k, &c) in centre.iter().enumerate().skip(1) {
            let parent = if chain { k - 1 } else { rng.random_range(0..k) };
            let (pp, cp) = (parent + 1, k + 1);
            let (mi, mj) = (100_000 + 10 * k + 1, 100_000 + 10 * k + 2);
            if rng.random_bool(0.6) {
                let pin = [rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0)];
                let _ = writeln!(
                    s,
                    "MARKER/{mi}, PART = {cp}, QP = {}, {}, 0\n\
                     MARKER/{mj}, PART = {pp}, QP = {}, {}, 0\n\
                     JOINT/{k}, REVOLUTE, I = {mi}, J = {mj}",
                    pin[0], pin[1], pin[0], pin[1]
                );
            } else {
                let psi = rng.random_range(0.0..360.0);
                let _ = writeln!(
                    s,
                    "MARKER/{mi}, PART = {cp}, QP = {}, {}, 0, REULER = {psi}D, 90D, 0D\n\
                     MARKER/{mj}, PART = {pp}, QP = {}, {}, 0, REULER = {psi}D, 90D, 0D\n\
                     JOINT/{k}, TRANSLATIONAL, I = {mi}, J = {mj}",
                    c[0], c[1], c[0], c[1]
                );
            }
        }
        let _ = writeln!(
            s,
            "SPRINGDAMPER/1, TRANSLATION, I = {}01, J = 1, K = 50, C = 3, LENGTH = 1\n\
             ACCGRAV/JGRAV = -9.81\nEND",
            n + 1
        );
        s
    }

    fn dynamics(text: &str) -> Dynamics {
        let read = read_model(text);
        assert!(!read.has_errors(), "{:?}\n{text}", read.diagnostics);
        let exprs = CompiledExprs::new();
        let mut sys = System::from_model(&read.model, Dim::Auto, &exprs).unwrap();
        let forces = sys.forces_from_model(&read.model, &exprs).unwrap();
        Dynamics::new(sys, forces, &[]).unwrap()
    }

    #[test]
    fn articulated_body_matches_the_dense_normal_equations_on_random_trees() {
        let mut rng = StdRng::seed_from_u64(42);
        let mut checked = 0;
        for (n, chain) in [(1, true), (2, true), (7, true), (15, true), (25, true)]
            .into_iter()
            .chain([(3, false), (8, false), (16, false), (30, false)])
        {
            for _ in 0..3 {
                let text = random_tree(&mut rng, n, chain);
                let mut d = dynamics(&text);
                let mut tree = JointTree::of(&d).unwrap_or_else(|| panic!("not a tree:\n{text}"));
                assert_eq!(tree.coordinates(), n);
                for _ in 0..4 {
                    let theta: Vec<f64> = (0..n)
                        .map(|k| match tree.rotational(k) {
                            true => rng.random_range(-3.0..3.0),
                            false => rng.random_range(-1.0..1.0),
                        })
                        .collect();
                    let rate: Vec<f64> = (0..n).map(|_| rng.random_range(-3.0..3.0)).collect();
                    let (mut fast, mut dense) = (vec![0.0; n], vec![0.0; n]);
                    tree.accelerations(&mut d, (&theta, &rate, 0.0), &mut fast, false)
                        .unwrap();
                    tree.accelerations_dense(&mut d, (&theta, &rate, 0.0), &mut dense)
                        .unwrap();
                    let scale = dense.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                    let worst = fast
                        .iter()
                        .zip(&dense)
                        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    assert!(
                        worst <= 1e-10 * scale && scale > 0.0,
                        "N = {n}, chain {chain}: |Δθ̈| {worst:e} against {scale:e}\n\
                         fast {fast:?}\ndense {dense:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 9 * 3 * 4);
    }

    #[test]
    fn rates_at_start_recover_the_joint_rates_of_consistent_velocities() {
        // Velocities B·θ̇ for a known θ̇ (set through the tree's own placing at θ = 0),
        // then projected back: the projection of a velocity already in B's range is
        // that velocity, so the rates come back.
        let mut rng = StdRng::seed_from_u64(7);
        for chain in [true, false] {
            let n = 12;
            let text = random_tree(&mut rng, n, chain);
            let mut d = dynamics(&text);
            let mut tree = JointTree::of(&d).unwrap();
            let zero = vec![0.0; n];
            let want: Vec<f64> = (0..n).map(|_| rng.random_range(-2.0..2.0)).collect();
            tree.place(&mut d, &zero, &want, 0.0);
            let mut got = vec![0.0; n];
            tree.rates_at_start(&mut d, &mut got).unwrap();
            for (g, w) in got.iter().zip(&want) {
                assert!(
                    (g - w).abs() <= 1e-10 * (1.0 + w.abs()),
                    "{got:?}\n{want:?}"
                );
            }
        }
    }
}
