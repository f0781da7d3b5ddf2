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

use crate::mbd::dense::DenseLlt;
use crate::mbd::dynamics::blocks::Mat3Block;
use crate::mbd::dynamics::failure::{DynError, Singularity};
use crate::mbd::dynamics::setup::Dynamics;
use crate::mbd::dynamics::state::Snapshot;
use crate::mbd::rows::Row;
use crate::mbd::sparse::DENSE_MAX;
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
    b: Vec<f64>,
    llt: DenseLlt,
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
    /// others, no row dropped, no force reading the solution, at most [`DENSE_MAX`]
    /// joints.
    pub fn of(d: &Dynamics) -> Option<JointTree> {
        let sys = &d.sys;
        let parts = sys.moving_parts();
        if sys.dim != Dimension::Two
            || !d.dropped.is_empty()
            || d.reads_solution()
            || parts == 0
            || parts > DENSE_MAX
        {
            return None;
        }
        // Each element's kind and the two parts its rows join.
        let mut elements: Vec<(usize, JointType, [Option<usize>; 2])> = Vec::new();
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
            match elements.iter().position(|x| x.0 == e) {
                Some(_) => {}
                None => elements.push((e, t, [index(i), index(j)])),
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
        let mut placed = vec![false; parts];
        let mut joints = Vec::with_capacity(parts);
        let mut used = vec![false; elements.len()];
        while joints.len() < parts {
            let next = elements.iter().enumerate().find_map(|(k, &(e, t, ends))| {
                if used[k] {
                    return None;
                }
                let known = |x: Option<usize>| x.is_none_or(|i| placed[i]);
                match (known(ends[0]), known(ends[1])) {
                    (true, false) => Some((k, e, t, ends[0], ends[1]?)),
                    (false, true) => Some((k, e, t, ends[1], ends[0]?)),
                    _ => None,
                }
            });
            // Nothing joins a placed part to a new one: a loop, or a part off the tree.
            let (k, e, t, parent, child) = next?;
            used[k] = true;
            placed[child] = true;
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
            joints.push(Joint {
                child,
                parent,
                kind,
            });
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
            b: vec![0.0; 3 * parts * f],
            llt: DenseLlt::new(f),
            dx: vec![0.0; 3 * parts],
            v: DVec::zeros(3 * parts),
        })
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

    /// Poses, velocities, bias accelerations and B at coordinates `theta`, rates `rate`.
    fn kinematics(&mut self, theta: &[f64], rate: &[f64]) {
        let f = self.joints.len();
        for (k, jt) in self.joints.iter().enumerate() {
            let c = jt.child;
            let (pp, pv, pb) = match jt.parent {
                Some(p) => (self.pose[p], self.vel[p], self.bias[p]),
                None => ([0.0; 3], [0.0; 3], [0.0; 3]),
            };
            // B's rows of the child start as the parent's (ground: zero).
            for row in 0..3 {
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
                    for col in 0..f {
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
                    for col in 0..f {
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
        self.kinematics(theta, rate);
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
        if stage && d.forces.elements.is_empty() && d.forces.contacts.is_empty() {
            self.kinematics(theta, rate);
        } else {
            self.place(d, theta, rate, t);
        }
        self.accelerations_here(d, t, out)
    }

    /// θ̈ into `out` at the kinematics last computed, with `d`'s Q and mass blocks.
    fn accelerations_here(
        &mut self,
        d: &mut Dynamics,
        t: f64,
        out: &mut [f64],
    ) -> Result<(), DynError> {
        d.eval_forces(false)?;
        d.check_forces()?;
        d.stats.factorizations += 1;
        let bias = std::mem::take(&mut self.bias);
        let solved = self.solve_normal(d, t, out, |i, row, w| {
            d.gen.q[3 * i + row] - w * bias[i][row]
        });
        self.bias = bias;
        solved
    }

    /// The joint rates of `d`'s current (consistent) velocities, closest in the mass
    /// metric, into `rate`, at the starting pose (θ = 0).
    pub fn rates_at_start(&mut self, d: &mut Dynamics, rate: &mut [f64]) -> Result<(), DynError> {
        let zero = vec![0.0; self.joints.len()];
        let v = d.sys.v();
        self.kinematics(&zero, &zero);
        self.solve_normal(d, d.sys.time, rate, |i, row, w| w * v[3 * i + row])
    }

    /// Solves Bᵀ·M·B·x = Bᵀ·g into `x`, g's entry for part `i`, layout row `row` given by
    /// `g(i, row, mass weight)`, with B and `d`'s mass blocks at the current kinematics.
    fn solve_normal(
        &mut self,
        d: &Dynamics,
        t: f64,
        x: &mut [f64],
        g: impl Fn(usize, usize, f64) -> f64,
    ) -> Result<(), DynError> {
        let f = self.joints.len();
        let m = self.llt.matrix_mut();
        m.fill(0.0);
        x.fill(0.0);
        for (i, blk) in d.mass_blocks().iter().enumerate() {
            let Mat3Block::Two(mass, inertia) = *blk else {
                unreachable!("a planar tree")
            };
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
        if self.llt.factor().is_err() {
            return Err(DynError::Singular {
                time: t,
                why: Singularity::Numerical,
                culprit: None,
            });
        }
        self.llt.solve(x);
        Ok(())
    }
}
