//! Joint friction's stiction deformation (MAX_STICTION_DEFORMATION, issue 40 §2): a
//! state δ per slip component (a length on the slip surface: at the pin or ball radius
//! for a rotation) that lets a joint below its breakaway load *hold*, deflected, instead
//! of creeping. The state lives in the state elements' block
//! ([`crate::mbd::states`], whose `stiction` file carries it); this file is its law.
//!
//! With v the slip (components in J's axes), δmax MAX_STICTION_DEFORMATION, vs and vd
//! the stiction and full-sliding velocities, μs and μ(|v|) Adams' coefficients:
//!
//! ```text
//! w      = 1 for |v| ≤ vs,  STEP(|v|, vs, 1, vd, 0) between,  0 for |v| ≥ vd
//! ė      = v − α(|δ|)·⟨v·δ/|δ|⟩₊·δ/δmax        (elastoplastic: α = 0 below 0.9·δmax,
//!                                                 STEP to 1 at δmax, 0 while unloading)
//! δ̇      = w·ė − (1 − w)·(|v|/δmax)·δ
//! f      = −w·N·(μs/δmax·δ + μs/vs·ė) − (1 − w)·μ(|v|)·N·v/|v|
//! ```
//!
//! Below vs the friction is a spring of stiffness μs·N/δmax (μs·N at full deformation)
//! with the damping μs·N/vs on the deformation's rate; the deformation is purely elastic
//! up to 0.9·δmax and bounded by δmax (the single-state elastoplastic model of Dupont,
//! Hayward, Armstrong and Altpeter, IEEE TAC 47(5), 2002, with Adams' δmax as its largest
//! deformation). Between vs and vd the spring hands over to Adams' μ(|v|)·N, which
//! acts alone from vd on while δ relaxes to zero (Adams' creep is measured in the
//! stiction regime only). The law is linear in N, as the stateless one is.
//!
//! **Statics** holds the joint where statics starts: the deformation there, δc, plus the
//! slip displacement since, Δs(q) (the travel along z_J, or the small relative rotation
//! ½·Σₐ e0ₐ × eₐ of I's axes in J's times the radius), bounded by δmax; the friction is
//! then −μs·N·δ/δmax with its exact derivative by q.

use super::friction::{FrictionJoint, JointFriction, Stiction, POSE_LEN};
use super::friction_loads::scale;
use super::num::Num;
use crate::mbd::dual::V;
use crate::mbd::handles::MarkerHandle;
use crate::mbd::measures::{value_frame, Frame};
use crate::mbd::system::System;
use crate::vocab::math::Vec3;

/// The share of δmax below which the deformation is purely elastic (the elastoplastic
/// model's breakaway deformation).
const ELASTIC_SHARE: f64 = 0.9;

fn dot<T: Num>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The smooth step from 0 at s = 0 to 1 at s = 1 (Adams' STEP's cubic).
fn cubic<T: Num>(s: T) -> T {
    s * s * (T::c(3.0) - s.scale(2.0))
}

impl JointFriction {
    /// How many slip components the joint has: 1 (revolute, translational), 2
    /// (cylindrical), 3 (spherical; Hooke and universal too, whose rotation about the
    /// cross axis is the joint's to keep at zero).
    pub fn slips(&self) -> usize {
        match self.joint {
            FrictionJoint::Revolute | FrictionJoint::Translational => 1,
            FrictionJoint::Cylindrical => 2,
            FrictionJoint::Spherical | FrictionJoint::Universal => 3,
        }
    }

    /// The slip radius of the rotations (PIN_RADIUS, or BALL_RADIUS for a spherical).
    fn radius(&self) -> f64 {
        match self.joint {
            FrictionJoint::Spherical => self.ball_radius,
            _ => self.pin_radius,
        }
    }

    /// The slip components in J's axes at frames `fi`, `fj` (unused ones zero).
    fn slip<T: Num>(&self, fi: &Frame<T>, fj: &Frame<T>) -> [T; 3] {
        let d = fi.r.sub(&fj.r);
        let vel = fi.vel.sub(&fj.vel).sub(&fj.w.cross(&d));
        let w = fi.w.sub(&fj.w);
        let ax = &fj.axes;
        let r = self.radius();
        let zero = T::c(0.0);
        match self.joint {
            FrictionJoint::Revolute => [w.dot(&ax[2]).scale(r), zero, zero],
            FrictionJoint::Translational => [vel.dot(&ax[2]), zero, zero],
            FrictionJoint::Cylindrical => [vel.dot(&ax[2]), w.dot(&ax[2]).scale(r), zero],
            FrictionJoint::Spherical | FrictionJoint::Universal => {
                [0, 1, 2].map(|k| w.dot(&ax[k]).scale(r))
            }
        }
    }

    /// The weight w of the stiction spring at squared slip speed `v2` (module doc).
    fn stuck_weight<T: Num>(&self, v2: T) -> T {
        let (vs, vd) = (self.vs, self.vd);
        if v2.val() <= vs * vs {
            return T::c(1.0);
        }
        if v2.val() >= vd * vd {
            return T::c(0.0);
        }
        let s = (v2.sqrt() - T::c(vs)).scale(1.0 / (vd - vs));
        T::c(1.0) - cubic(s)
    }

    /// ė, the deformation's elastoplastic rate at slip `v` and deformation `delta`.
    fn elastoplastic<T: Num>(&self, v: &[T; 3], delta: &[T; 3], max: f64) -> [T; 3] {
        let elastic = ELASTIC_SHARE * max;
        let along = dot(v, delta);
        let size2 = dot(delta, delta);
        if size2.val() <= elastic * elastic || along.val() <= 0.0 {
            return *v;
        }
        let size = size2.sqrt();
        let alpha = if size.val() >= max {
            T::c(1.0)
        } else {
            cubic((size - T::c(elastic)).scale(1.0 / (max - elastic)))
        };
        let flow = alpha * along * size.recip().scale(1.0 / max);
        [0, 1, 2].map(|c| v[c] - flow * delta[c])
    }

    /// δ̇ at slip `v` and deformation `delta` (module doc).
    fn deformation_rate<T: Num>(&self, v: &[T; 3], delta: &[T; 3], max: f64) -> [T; 3] {
        let v2 = dot(v, v);
        let w = self.stuck_weight(v2);
        let e = self.elastoplastic(v, delta, max);
        if w.val() >= 1.0 {
            return e;
        }
        let relax = (T::c(1.0) - w) * v2.sqrt().scale(1.0 / max);
        [0, 1, 2].map(|c| e[c] * w - delta[c] * relax)
    }

    /// The friction's components (force, or torque over the slip radius: the units of
    /// N) at slip `v`, deformation `delta`, load `n` (module doc).
    fn stuck_components<T: Num>(&self, v: &[T; 3], delta: &[T; 3], n: T, max: f64) -> [T; 3] {
        let v2 = dot(v, v);
        let w = self.stuck_weight(v2);
        let mut f = [T::c(0.0); 3];
        if w.val() > 0.0 {
            let e = self.elastoplastic(v, delta, max);
            let (k, c) = (self.mu_peak / max, self.mu_peak / self.vs);
            f = [0, 1, 2].map(|i| (delta[i].scale(k) + e[i].scale(c)) * w);
        }
        if w.val() < 1.0 {
            // |v| > vs here: μ(|v|)/|v| is the curve's falling branch or its tail.
            let ratio = self.mu_over_speed(v2) * (T::c(1.0) - w);
            for i in 0..3 {
                f[i] = f[i] + v[i] * ratio;
            }
        }
        f.map(|x| x * -n)
    }

    /// The friction's force and torque on I (global axes) from its components `f`, held
    /// to MAX_FRICTION_FORCE / MAX_FRICTION_TORQUE when `capped`.
    fn component_loads<T: Num>(&self, fj: &Frame<T>, f: [T; 3], capped: bool) -> (V<T>, V<T>) {
        let zero = V::c(Vec3::zeros());
        let ax = &fj.axes;
        let cap = |x: T| if capped { self.cap(x) } else { x };
        match self.joint {
            FrictionJoint::Revolute => (zero, scale(&ax[2], cap(f[0]))),
            FrictionJoint::Translational => (scale(&ax[2], cap(f[0])), zero),
            FrictionJoint::Cylindrical => (
                scale(&ax[2], cap(f[0])),
                scale(&ax[2], cap(f[1].scale(self.pin_radius))),
            ),
            FrictionJoint::Spherical | FrictionJoint::Universal => {
                let t = V([0, 1, 2].map(|c| (0..3).fold(T::c(0.0), |s, k| s + ax[k].0[c] * f[k])));
                (zero, self.cap_vector(t, capped))
            }
        }
    }

    /// The friction's force and torque on I with its stiction deformation `s` (read
    /// from `sys`'s state values, or, while statics holds the joint, from its pose)
    /// under load `n`.
    pub(super) fn stuck_loads<T: Num>(
        &self,
        sys: &System,
        s: &Stiction,
        (fi, fj): (&Frame<T>, &Frame<T>),
        n: T,
        capped: bool,
    ) -> (V<T>, V<T>) {
        let d = self.slips();
        let values = &sys.measures.states;
        let read = |k: usize| values.get(k).copied().unwrap_or(0.0);
        let delta = match read(s.flag(d)) == 1.0 {
            true => {
                let anchor: Vec<f64> = (0..d + POSE_LEN).map(|k| read(s.anchor(d) + k)).collect();
                self.held(fi, fj, &anchor, s.max)
            }
            false => [0, 1, 2].map(|c| T::c(if c < d { read(s.x(c)) } else { 0.0 })),
        };
        let v = self.slip(fi, fj);
        let f = self.stuck_components(&v, &delta, n, s.max);
        self.component_loads(fj, f, capped)
    }

    /// The deformation statics holds at frames `fi`, `fj` from `anchor` (δc, travel,
    /// I's axes in J's at statics' start), bounded by `max`.
    fn held<T: Num>(&self, fi: &Frame<T>, fj: &Frame<T>, anchor: &[f64], max: f64) -> [T; 3] {
        let d = self.slips();
        let ax = &fj.axes;
        let travel = fi.r.sub(&fj.r).dot(&ax[2]) - T::c(anchor[d]);
        // φ = ½·Σₐ e0ₐ × eₐ, eₐ I's axis a in J's axes: the small rotation since.
        let mut phi = [T::c(0.0); 3];
        for a in 0..3 {
            let e: [T; 3] = [0, 1, 2].map(|b| fi.axes[a].dot(&ax[b]));
            let e0: [f64; 3] = [0, 1, 2].map(|b| anchor[d + 1 + 3 * a + b]);
            phi[0] = phi[0] + (e[2].scale(e0[1]) - e[1].scale(e0[2])).scale(0.5);
            phi[1] = phi[1] + (e[0].scale(e0[2]) - e[2].scale(e0[0])).scale(0.5);
            phi[2] = phi[2] + (e[1].scale(e0[0]) - e[0].scale(e0[1])).scale(0.5);
        }
        let r = self.radius();
        let zero = T::c(0.0);
        let moved = match self.joint {
            FrictionJoint::Revolute => [phi[2].scale(r), zero, zero],
            FrictionJoint::Translational => [travel, zero, zero],
            FrictionJoint::Cylindrical => [travel, phi[2].scale(r), zero],
            FrictionJoint::Spherical | FrictionJoint::Universal => phi.map(|p| p.scale(r)),
        };
        let delta = [0, 1, 2].map(|c| match c < d {
            true => moved[c] + T::c(anchor[c]),
            false => zero,
        });
        let size2 = dot(&delta, &delta);
        if size2.val() <= max * max {
            return delta;
        }
        let shrink = size2.sqrt().recip().scale(max);
        delta.map(|x| x * shrink)
    }

    /// δ̇ of stiction deformation `s` at `sys`'s state, markers `i` and `j`, the
    /// deformation `delta` (d components): the state's equation.
    pub fn deformation_rate_at(
        &self,
        sys: &System,
        s: &Stiction,
        (i, j): (MarkerHandle, MarkerHandle),
        delta: &[f64],
    ) -> [f64; 3] {
        let (fi, fj) = (value_frame(sys, Some(i)), value_frame(sys, Some(j)));
        let delta = [0, 1, 2].map(|c| delta.get(c).copied().unwrap_or(0.0));
        self.deformation_rate(&self.slip(&fi, &fj), &delta, s.max)
    }

    /// The pose statics holds the joint from (the travel along z_J, I's axes in J's) at
    /// `sys`'s state, appended to `anchor`.
    pub fn pose_at(
        &self,
        sys: &System,
        (i, j): (MarkerHandle, MarkerHandle),
        anchor: &mut Vec<f64>,
    ) {
        let (fi, fj) = (value_frame(sys, Some(i)), value_frame(sys, Some(j)));
        anchor.push(fi.r.sub(&fj.r).dot(&fj.axes[2]));
        for a in 0..3 {
            anchor.extend((0..3).map(|b| fi.axes[a].dot(&fj.axes[b])));
        }
    }

    /// The deformation statics holds at `sys`'s state from `anchor` (δc, then
    /// [`JointFriction::pose_at`]'s pose).
    pub fn held_at(
        &self,
        sys: &System,
        s: &Stiction,
        (i, j): (MarkerHandle, MarkerHandle),
        anchor: &[f64],
    ) -> [f64; 3] {
        let (fi, fj) = (value_frame(sys, Some(i)), value_frame(sys, Some(j)));
        self.held(&fi, &fj, anchor, s.max)
    }
}
