//! The evaluation of joint friction ([`JointFriction`], its formulas in the `friction`
//! module): the load from the joint's reaction, the slip from the frames of I and J,
//! μ(|v|) from Adams' stick-slip curve (without a state for EFFECT = SLIDING; with its
//! stiction deformation, the `stiction` module, otherwise), in any [`Num`]; and the
//! friction's derivative by the reaction it reads ([`JointFriction::reaction_partials`]),
//! which closes the friction–reaction loop inside Newton.

use super::element::ForceElement;
use super::friction::{FrictionJoint, JointFriction};
use super::generalized::Generalized;
use super::num::Num;
use crate::mbd::dual::V;
use crate::mbd::measures::{value_frame, Frame};
use crate::mbd::system::System;
use mbfx_runtime::step_grad;

/// |x| and its gradient x/|x|; at x = 0, where the norm has no derivative, the gradient
/// is taken as 0 (the smallest member of its subdifferential: no load direction yet).
fn norm_grad<const K: usize>(x: [f64; K]) -> (f64, [f64; K]) {
    let size = x.iter().map(|c| c * c).sum::<f64>().sqrt();
    match size > 0.0 {
        true => (size, x.map(|c| c / size)),
        false => (0.0, [0.0; K]),
    }
}

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
        sys: &System,
        (fi, fj): (&Frame<T>, &Frame<T>),
        solved: &[f64],
    ) -> (V<T>, V<T>) {
        let (n, _) = self.normal(fi, fj, &self.reaction_in(solved));
        self.law_loads(sys, (fi, fj), n, true)
    }

    /// The friction's force and torque on I under load `n`: with its stiction
    /// deformation when it has one (the `stiction` module), else the stateless curve.
    fn law_loads<T: Num>(
        &self,
        sys: &System,
        (fi, fj): (&Frame<T>, &Frame<T>),
        n: T,
        capped: bool,
    ) -> (V<T>, V<T>) {
        match &self.stiction {
            Some(s) => self.stuck_loads(sys, s, (fi, fj), n, capped),
            None => self.slip_loads(fi, fj, n, capped),
        }
    }

    /// The reaction FX FY FZ TX TY TZ (J's axes) among the solution values `solved`.
    fn reaction_in(&self, solved: &[f64]) -> [f64; 6] {
        self.reaction.map(|k| solved.get(k).copied().unwrap_or(0.0))
    }

    /// The normal load N at frames `fi`, `fj` under the reaction `r`, and ∂N/∂r (held at
    /// the overlap's value where N divides by it).
    fn normal<T: Num>(&self, fi: &Frame<T>, fj: &Frame<T>, r: &[f64; 6]) -> (T, [f64; 6]) {
        let l = &self.loading;
        let on = |b: bool, x: f64| if b { x } else { 0.0 };
        let pre = on(l.preload, self.preload);
        let (radial, dr) = norm_grad([r[0], r[1]]);
        let (bending, db) = norm_grad([r[3], r[4]]);
        let (force, df) = norm_grad([r[0], r[1], r[2]]);
        let (moment, dm) = norm_grad([r[3], r[4], r[5]]);
        // ∂N/∂r from the terms' gradients, each with its factor (0 when switched off).
        let grad = |radial: f64, axial: f64, bending: f64, torsion: f64, force: f64, moment| {
            let mut g = [0.0; 6];
            for k in 0..2 {
                g[k] += radial * dr[k];
                g[3 + k] += bending * db[k];
            }
            g[2] += axial * r[2].signum() * f64::from(r[2] != 0.0);
            g[5] += torsion * r[5].signum() * f64::from(r[5] != 0.0);
            for k in 0..3 {
                g[k] += force * df[k];
                g[3 + k] += moment * dm[k];
            }
            g
        };
        let f_on = on(l.force, 1.0);
        let b_on = on(l.bending, 1.0);
        let (rp, rb) = (self.pin_radius, self.ball_radius);
        match self.joint {
            FrictionJoint::Revolute => {
                let (fa, ba) = (self.friction_arm, self.bending_arm);
                let n = on(l.force, rp * radial + fa * r[2].abs())
                    + on(l.bending, rp * bending / ba)
                    + rp * pre;
                let g = grad(f_on * rp, f_on * fa, b_on * rp / ba, 0.0, 0.0, 0.0);
                (T::c(n), g)
            }
            FrictionJoint::Translational | FrictionJoint::Cylindrical => {
                let xs = self.overlap_at(fi.r.sub(&fj.r).dot(&fj.axes[2]));
                let (torsion, t_on) = match self.joint {
                    FrictionJoint::Translational => (
                        on(l.torsion, r[5].abs() / self.friction_arm),
                        on(l.torsion, 1.0 / self.friction_arm),
                    ),
                    _ => (0.0, 0.0),
                };
                let n = T::c(on(l.force, radial) + torsion + pre)
                    + xs.recip().scale(on(l.bending, bending));
                let g = grad(f_on, 0.0, b_on / xs.val(), t_on, 0.0, 0.0);
                (n, g)
            }
            FrictionJoint::Spherical => {
                let n = rb * (on(l.force, force) + pre);
                (T::c(n), grad(0.0, 0.0, 0.0, 0.0, f_on * rb, 0.0))
            }
            FrictionJoint::Universal => {
                let ba = self.bending_arm;
                let n = rp * (on(l.force, force) + on(l.bending, moment / ba) + pre);
                (T::c(n), grad(0.0, 0.0, 0.0, 0.0, f_on * rp, b_on * rp / ba))
            }
        }
    }

    /// The friction's force and torque on I (global axes) at frames `fi`, `fj` under the
    /// normal load `n`, held to MAX_FRICTION_FORCE / MAX_FRICTION_TORQUE when `capped`.
    fn slip_loads<T: Num>(&self, fi: &Frame<T>, fj: &Frame<T>, n: T, capped: bool) -> (V<T>, V<T>) {
        let d = fi.r.sub(&fj.r);
        let z = &fj.axes[2];
        let vel = fi.vel.sub(&fj.vel).sub(&fj.w.cross(&d));
        let w = fi.w.sub(&fj.w);
        let zero = V::c(crate::vocab::math::Vec3::zeros());
        let along = |x: T| scale(z, x);
        let cap = |x: T| if capped { self.cap(x) } else { x };
        let rp = self.pin_radius;
        match self.joint {
            FrictionJoint::Revolute => {
                let v = w.dot(z).scale(rp);
                let t = cap(v * self.mu_over_speed(v * v) * -n);
                (zero, along(t))
            }
            FrictionJoint::Translational => {
                let v = vel.dot(z);
                let f = cap(v * self.mu_over_speed(v * v) * -n);
                (along(f), zero)
            }
            FrictionJoint::Cylindrical => {
                let (vz, vt) = (vel.dot(z), w.dot(z).scale(rp));
                let ratio = self.mu_over_speed(vz * vz + vt * vt);
                let f = cap(vz * ratio * -n);
                let t = cap((vt * ratio).scale(rp) * -n);
                (along(f), along(t))
            }
            FrictionJoint::Spherical => self.rotating(&w, self.ball_radius, n, capped),
            FrictionJoint::Universal => self.rotating(&w, rp, n, capped),
        }
    }

    /// The torque −μ(|v|)·N·v/|v| of a slip v = radius·ω about any axis.
    fn rotating<T: Num>(&self, w: &V<T>, radius: f64, n: T, capped: bool) -> (V<T>, V<T>) {
        let zero = V::c(crate::vocab::math::Vec3::zeros());
        let v = scale(w, T::c(radius));
        let ratio = self.mu_over_speed(v.dot(&v));
        let t = scale(&v, ratio * -n);
        (zero, self.cap_vector(t, capped))
    }

    /// A friction torque vector held to MAX_FRICTION_TORQUE in size when `capped` and
    /// one is given.
    pub(super) fn cap_vector<T: Num>(&self, t: V<T>, capped: bool) -> V<T> {
        match self.max {
            Some(m) if capped && t.dot(&t).val() > m * m => {
                let size = t.dot(&t).sqrt().val();
                scale(&t, T::c(m / size))
            }
            _ => t,
        }
    }

    /// A friction force or torque held to MAX_FRICTION_FORCE / MAX_FRICTION_TORQUE when
    /// one is given (a constant there: no derivative).
    pub(super) fn cap<T: Num>(&self, x: T) -> T {
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

    /// Adds ∂Q/∂r, the generalized force's derivative by each reaction component it
    /// reads, to `out.ds` as (Q's row, solution value, value): the friction is linear
    /// in N, so ∂Q/∂r = (Q at N = 1)·∂N/∂r, nothing where MAX_FRICTION_FORCE or
    /// MAX_FRICTION_TORQUE holds it (a constant there). Element `el` is the friction's,
    /// `solved` the solution values of this evaluation.
    pub(super) fn reaction_partials(
        &self,
        el: &ForceElement,
        sys: &System,
        solved: &[f64],
        out: &mut Generalized,
    ) {
        let (fi, fj) = (value_frame(sys, Some(el.i)), value_frame(sys, el.j));
        let (n, dn) = self.normal(&fi, &fj, &self.reaction_in(solved));
        if dn.iter().all(|&x| x == 0.0) {
            return;
        }
        let (f, t) = self.law_loads(sys, (&fi, &fj), 1.0, false);
        // Where the cap holds the load, it no longer follows N.
        let held = |x: &V<f64>| self.max.is_some_and(|m| n.abs() * x.dot(x).sqrt() > m);
        let keep = |x: V<f64>| {
            if held(&x) {
                V::c(crate::vocab::math::Vec3::zeros())
            } else {
                x
            }
        };
        let (f, t) = (keep(f).value(), keep(t).value());
        let pi = sys.marker(el.i).part;
        let pj = el.j.map_or(System::GROUND, |j| sys.marker(j).part);
        let at = fi.r.value();
        for (part, sign) in [(pi, 1.0), (pj, -1.0)] {
            if sys.part(part).index.is_none() {
                continue;
            }
            // Both loads act at I's origin (the reaction on J's part reversed).
            let m = t + (at - sys.part(part).r).cross(&f);
            for c in 0..6 {
                let Some(row) = sys.col(part, c) else {
                    continue;
                };
                let q = sign * if c < 3 { f[c] } else { m[c - 3] };
                if q == 0.0 {
                    continue;
                }
                for (k, &g) in dn.iter().enumerate() {
                    if g != 0.0 {
                        out.ds.push((row, self.reaction[k], q * g));
                    }
                }
            }
        }
    }
}

/// `v` times `s`.
pub(super) fn scale<T: Num>(v: &V<T>, s: T) -> V<T> {
    V([v.0[0] * s, v.0[1] * s, v.0[2] * s])
}
