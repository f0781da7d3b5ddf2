//! The evaluation of joint friction ([`JointFriction`], its formulas in the `friction`
//! module): the load from the joint's reaction, the slip from the frames of I and J,
//! μ(|v|) from Adams' stick-slip curve without its state, in any [`Num`].

use super::friction::{FrictionJoint, JointFriction};
use super::num::Num;
use crate::mbd::dual::V;
use crate::mbd::measures::Frame;
use mbfx_runtime::step_grad;

impl JointFriction {
    /// μ(|v|)/|v| as a function of the squared slip speed `v2` (smooth through zero
    /// slip, where μ/|v| → 3·μs/(2·vs)): the friction is then −(μ/|v|)·v·N.
    pub(super) fn mu_over_speed<T: Num>(&self, v2: T) -> T {
        let (vs, vd) = (self.vs, self.vd);
        if v2.val() < vs * vs {
            // STEP(v, −vs, −μs, vs, μs) = μs·s·(3 − s²)/2 with s = v/vs.
            return (T::c(3.0) - v2.scale(1.0 / (vs * vs))).scale(self.mu_peak / (2.0 * vs));
        }
        let v = v2.sqrt();
        let (m, dm) = if v.val() < vd {
            // (This branch is reached only with vs ≤ v < vd, so the runtime's STEP is
            // defined.)
            let (m, grad) = step_grad(v.val(), vs, self.mu_peak, vd, self.mu_tail);
            (m, grad[0])
        } else {
            (self.mu_tail, 0.0)
        };
        // μ(v) to first order in v's derivatives, over v.
        let mu = T::c(m) + (v - T::c(v.val())).scale(dm);
        mu * v.recip()
    }

    /// The friction's force and torque on I (global axes) at frames `fi`, `fj`, with the
    /// reaction `solved` (the solution values).
    pub(super) fn loads<T: Num>(
        &self,
        fi: &Frame<T>,
        fj: &Frame<T>,
        solved: &[f64],
    ) -> (V<T>, V<T>) {
        let r: [f64; 6] = self.reaction.map(|k| solved.get(k).copied().unwrap_or(0.0));
        let on = |b: bool, x: f64| if b { x } else { 0.0 };
        let l = &self.loading;
        let radial = r[0].hypot(r[1]);
        let force = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let bending = r[3].hypot(r[4]);
        let moment = (r[3] * r[3] + r[4] * r[4] + r[5] * r[5]).sqrt();
        let pre = on(l.preload, self.preload);
        let d = fi.r.sub(&fj.r);
        let z = &fj.axes[2];
        let vel = fi.vel.sub(&fj.vel).sub(&fj.w.cross(&d));
        let w = fi.w.sub(&fj.w);
        let zero = V::c(crate::vocab::math::Vec3::zeros());
        let along = |x: T| scale(z, x);
        let (rp, rb) = (self.pin_radius, self.ball_radius);
        match self.joint {
            FrictionJoint::Revolute => {
                let n = on(l.force, rp * radial + self.friction_arm * r[2].abs())
                    + on(l.bending, rp * bending / self.bending_arm)
                    + rp * pre;
                let v = w.dot(z).scale(rp);
                let t = self.cap((v * self.mu_over_speed(v * v)).scale(-n));
                (zero, along(t))
            }
            FrictionJoint::Translational => {
                let xs = self.overlap_at(d.dot(z));
                let n =
                    T::c(on(l.force, radial) + on(l.torsion, r[5].abs() / self.friction_arm) + pre)
                        + xs.recip().scale(on(l.bending, bending));
                let v = vel.dot(z);
                let f = self.cap(v * self.mu_over_speed(v * v) * -n);
                (along(f), zero)
            }
            FrictionJoint::Cylindrical => {
                let xs = self.overlap_at(d.dot(z));
                let n = T::c(on(l.force, radial) + pre) + xs.recip().scale(on(l.bending, bending));
                let (vz, vt) = (vel.dot(z), w.dot(z).scale(rp));
                let ratio = self.mu_over_speed(vz * vz + vt * vt);
                let f = self.cap(vz * ratio * -n);
                let t = self.cap((vt * ratio).scale(rp) * -n);
                (along(f), along(t))
            }
            FrictionJoint::Spherical => {
                let n = rb * (on(l.force, force) + pre);
                self.rotating(&w, rb, n, zero)
            }
            FrictionJoint::Universal => {
                let n = rp * (on(l.force, force) + on(l.bending, moment / self.bending_arm) + pre);
                self.rotating(&w, rp, n, zero)
            }
        }
    }

    /// The torque −μ(|v|)·N·v/|v| of a slip v = radius·ω about any axis.
    fn rotating<T: Num>(&self, w: &V<T>, radius: f64, n: f64, zero: V<T>) -> (V<T>, V<T>) {
        let v = scale(w, T::c(radius));
        let ratio = self.mu_over_speed(v.dot(&v));
        let t = scale(&v, ratio.scale(-n));
        let t = match self.max {
            Some(m) if t.dot(&t).val() > m * m => {
                let size = t.dot(&t).sqrt().val();
                scale(&t, T::c(m / size))
            }
            _ => t,
        };
        (zero, t)
    }

    /// A friction force or torque held to MAX_FRICTION_FORCE / MAX_FRICTION_TORQUE when
    /// one is given (a constant there: no derivative).
    fn cap<T: Num>(&self, x: T) -> T {
        match self.max {
            Some(m) if x.val().abs() > m => T::c(m.copysign(x.val())),
            _ => x,
        }
    }

    /// The overlap Xs of a translational or cylindrical joint at travel `dz` along z_J
    /// (kept above a thousandth of INITIAL_OVERLAP, where the bending term would blow up).
    fn overlap_at<T: Num>(&self, dz: T) -> T {
        let xs = (dz - T::c(self.travel0)).scale(self.overlap_sign) + T::c(self.overlap);
        if xs.val() < 1e-3 * self.overlap {
            T::c(1e-3 * self.overlap)
        } else {
            xs
        }
    }
}

fn scale<T: Num>(v: &V<T>, s: T) -> V<T> {
    V([v.0[0] * s, v.0[1] * s, v.0[2] * s])
}
