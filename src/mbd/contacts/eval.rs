//! A contact set at a state: its loads into the generalized forces Q (with ∂Q/∂q and
//! ∂Q/∂v), its switching values for the step control, and the values its outputs read.

use super::law::{mu_over_speed, normal, unclamped};
use super::{ContactSet, ContactValues};
use crate::collide::{Incident, Pose};
use crate::mbd::handles::PartHandle;
use crate::mbd::system::System;
use crate::model::contact::FrictionMode;
use crate::vocab::math::{DVec, Mat3, Vec3};
use nalgebra::SMatrix;

/// The switching value of a pair the broad phase finds apart: negative (not touching);
/// its size only steers the first trial step toward a switch, which the steps taken
/// then locate.
pub const APART: f64 = -1.0;

/// Jacobian entries (row, column, value); repeats add up.
pub type Entries = Vec<(usize, usize, f64)>;

/// The map from a part's velocity columns (CM velocity, angular velocity) to the
/// velocity of a point at arm `a` from its reference point: [I, −[a]×].
fn point_map(a: &Vec3) -> SMatrix<f64, 3, 6> {
    let mut g = SMatrix::<f64, 3, 6>::zeros();
    g.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
    g.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-a.cross_matrix()));
    g
}

/// One incident's force on I at its point, with the 3×3 partials of that force in the
/// relative velocity (`dv`) and relative displacement (`dq`) of I's material point
/// against J's, the normal and the points held fixed.
struct Load {
    force: Vec3,
    normal: f64,
    friction: f64,
    slip: f64,
    dv: Mat3,
    dq: Mat3,
}

impl ContactSet {
    /// Places every geometry at the state of `sys`.
    pub(super) fn place(&self, sys: &System) {
        let Some(world) = &self.world else { return };
        let pose = |id| {
            self.parts.get(&id).map_or(
                Pose {
                    r: Vec3::zeros(),
                    rot: Mat3::identity(),
                },
                |&h| {
                    let p = sys.part(h);
                    Pose {
                        r: p.bcs_origin(),
                        rot: p.rotation(),
                    }
                },
            )
        };
        world.borrow_mut().update(&pose);
    }

    /// The relative velocity of I's material point at `at` against J's, and both arms.
    fn relative(sys: &System, i: PartHandle, j: PartHandle, at: &Vec3) -> (Vec3, Vec3, Vec3) {
        let (pi, pj) = (sys.part(i), sys.part(j));
        let (ai, aj) = (at - pi.r, at - pj.r);
        let v = (pi.v + pi.w.cross(&ai)) - (pj.v + pj.w.cross(&aj));
        (v, ai, aj)
    }

    /// The load of incident `inc` of contact `c` with relative velocity `v`.
    fn load(&self, c: usize, inc: &Incident, v: &Vec3) -> Load {
        let contact = &self.contacts[c];
        let n = inc.normal;
        let rate = -n.dot(v);
        let law = normal(&contact.normal, inc.depth, rate);
        let vt = v - n * n.dot(v);
        let slip = vt.norm();
        let fr = &contact.friction;
        let rubs = match fr.mode {
            FrictionMode::On => true,
            FrictionMode::DynamicsOnly => !self.statics,
            FrictionMode::Off => false,
        };
        let (phi, dphi) = if rubs && law.force > 0.0 {
            mu_over_speed(fr, slip)
        } else {
            (0.0, 0.0)
        };
        let ft = -vt * (law.force * phi);
        // F = Fn·n + Ft, Ft = −Fn·φ(s)·v_t: through Fn (ġ = −n·v, g = −n·δp) and v_t.
        let along = n - vt * phi;
        let dft_dvt = if slip > 0.0 {
            -(Mat3::identity() * phi + vt * vt.transpose() * (dphi / slip)) * law.force
        } else {
            -Mat3::identity() * (phi * law.force)
        };
        let tangent = Mat3::identity() - n * n.transpose();
        Load {
            force: n * law.force + ft,
            normal: law.force,
            friction: ft.norm(),
            slip,
            dv: along * (-n.transpose()) * law.d_rate + dft_dvt * tangent,
            dq: along * (-n.transpose()) * law.d_depth,
        }
    }

    /// Adds every contact's loads at the state of `sys` to `q` (with `jacobians`, their
    /// ∂/∂q and ∂/∂v to `dq`, `dv`), and records each contact's values.
    pub fn eval(
        &mut self,
        sys: &System,
        q: &mut DVec,
        dq: &mut Entries,
        dv: &mut Entries,
        jacobians: bool,
    ) {
        let Some(world) = &self.world else { return };
        for c in &mut self.contacts {
            c.last = ContactValues::default();
        }
        self.place(sys);
        let mut candidates = self.candidates.take();
        let mut incidents = self.incidents.take();
        world.borrow_mut().candidates(&mut candidates);
        // A held pair whose bounding boxes are apart is apart.
        for (k, held) in self.held.iter_mut().enumerate() {
            if *held && candidates.binary_search(&k).is_err() {
                *held = false;
            }
        }
        for &k in &candidates {
            world.borrow().incidents(k, &mut incidents);
            if self.held[k] {
                if !incidents.is_empty() {
                    continue;
                }
                // Apart: from here on the pair is like any other.
                self.held[k] = false;
            }
            let pair = self.pairs[k];
            for inc in &incidents {
                let (v, ai, aj) = Self::relative(sys, pair.i, pair.j, &inc.point);
                let load = self.load(pair.contact, inc, &v);
                let last = &mut self.contacts[pair.contact].last;
                last.normal += load.normal;
                last.friction += load.friction;
                last.penetration = last.penetration.max(inc.depth);
                last.slip = last.slip.max(load.slip);
                last.force += load.force;
                last.torque += ai.cross(&load.force);
                last.torque_j -= aj.cross(&load.force);
                let sides = [(pair.i, ai, 1.0), (pair.j, aj, -1.0)];
                for (part, a, sign) in sides {
                    let f = load.force * sign;
                    let m = a.cross(&f);
                    for c in 0..6 {
                        if let Some(col) = sys.col(part, c) {
                            q[col] += if c < 3 { f[c] } else { m[c - 3] };
                        }
                    }
                }
                if jacobians {
                    jacobian(sys, &sides, &load, dq, dv);
                }
            }
        }
        self.candidates.replace(candidates);
        self.incidents.replace(incidents);
    }

    /// Appends two switching values per watched pair at the state of `sys`: the
    /// penetration −separation (positive in contact; `APART`, −1, for a pair whose bounding
    /// boxes do not overlap, which the broad phase spares a query), and in contact the
    /// smallest unclamped normal force of its incidents (positive where the law pushes;
    /// NaN apart, or where the law has no clamp).
    pub fn switches(&self, sys: &System, out: &mut Vec<f64>) {
        let Some(world) = &self.world else { return };
        self.place(sys);
        let mut candidates = self.candidates.take();
        world.borrow_mut().candidates(&mut candidates);
        candidates.sort_unstable();
        let world = world.borrow();
        let mut incidents = self.incidents.take();
        for (k, pair) in self.pairs.iter().enumerate() {
            if self.held[k] || candidates.binary_search(&k).is_err() {
                out.extend([APART, f64::NAN]);
                continue;
            }
            let depth = -world.separation(k);
            out.push(depth);
            let mut clamp = f64::NAN;
            if depth > 0.0 {
                world.incidents(k, &mut incidents);
                for inc in &incidents {
                    let (v, _, _) = Self::relative(sys, pair.i, pair.j, &inc.point);
                    let law = &self.contacts[pair.contact].normal;
                    if let Some(f) = unclamped(law, inc.depth, -inc.normal.dot(&v)) {
                        clamp = if clamp.is_nan() { f } else { clamp.min(f) };
                    }
                }
            }
            out.push(clamp);
        }
        self.incidents.replace(incidents);
        self.candidates.replace(candidates);
    }
}

/// The Jacobian entries of one load applied on `sides` (part, arm, sign: I then J):
/// ∂Q_X/∂(v or q)_Y = σX·σY·G_Xᵀ·D·G_Y, and the turning of X's moment arm with X,
/// ∂(a × F)/∂θ = [F]×·[a]×.
fn jacobian(
    sys: &System,
    sides: &[(PartHandle, Vec3, f64); 2],
    load: &Load,
    dq: &mut Entries,
    dv: &mut Entries,
) {
    let maps = sides.map(|(_, a, _)| point_map(&a));
    for (x, &(px, ax, sx)) in sides.iter().enumerate() {
        if sys.part(px).index.is_none() {
            continue;
        }
        for (y, &(py, _, sy)) in sides.iter().enumerate() {
            if sys.part(py).index.is_none() {
                continue;
            }
            let s = sx * sy;
            let bv = maps[x].transpose() * load.dv * maps[y] * s;
            let mut bq = maps[x].transpose() * load.dq * maps[y] * s;
            if x == y {
                let turn = (load.force * sx).cross_matrix() * ax.cross_matrix();
                let mut rot = bq.fixed_view_mut::<3, 3>(3, 3);
                rot += turn;
            }
            for r in 0..6 {
                let Some(row) = sys.col(px, r) else { continue };
                for c in 0..6 {
                    let Some(col) = sys.col(py, c) else { continue };
                    if bv[(r, c)] != 0.0 {
                        dv.push((row, col, bv[(r, c)]));
                    }
                    if bq[(r, c)] != 0.0 {
                        dq.push((row, col, bq[(r, c)]));
                    }
                }
            }
        }
    }
}
