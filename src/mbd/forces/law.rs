//! Evaluation by law: an element's loads from its frames and expressions (line force,
//! torque, vector force, springs, bushing), applied to the parts' generalized forces with
//! the moment of their arms, in any [`Num`].

use super::element::{ForceElement, ForceLaw};
use super::generalized::Generalized;
use super::inputs::{Inputs, Scalar};
use super::num::Num;
use crate::mbd::dual::{Scalar as ScalarT, D, V};
use crate::mbd::error::MbdError;
use crate::mbd::handles::PartHandle;
use crate::mbd::measures::{Frame, PartSlots};
use crate::mbd::system::{Dimension, System};
use crate::vocab::math::Vec3;

/// The loads one element applies at a state, global axes: force and moment about the I
/// marker's origin on I's part; force and moment about the point `j_at` on J's part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Loads {
    /// Force and moment on I's part.
    pub on_i: (Vec3, Vec3),
    /// Force and moment on J's part (about `j_at`).
    pub on_j: (Vec3, Vec3),
    /// The point J's moment is taken about, global coordinates.
    pub j_at: Vec3,
}

fn scale_v<T: ScalarT>(v: &V<T>, s: T) -> V<T> {
    V([v.0[0] * s, v.0[1] * s, v.0[2] * s])
}

fn add_v<T: ScalarT>(a: &V<T>, b: &V<T>) -> V<T> {
    V([a.0[0] + b.0[0], a.0[1] + b.0[1], a.0[2] + b.0[2]])
}

fn neg_v<T: ScalarT>(a: &V<T>) -> V<T> {
    V([-a.0[0], -a.0[1], -a.0[2]])
}

/// Σ xₖ·axisₖ: components in a frame's axes to global.
fn in_axes<T: ScalarT>(axes: &[V<T>; 3], x: [T; 3]) -> V<T> {
    let mut out = scale_v(&axes[0], x[0]);
    for k in 1..3 {
        out = add_v(&out, &scale_v(&axes[k], x[k]));
    }
    out
}

impl ForceElement {
    /// Adds the element's generalized forces to `out` (with ∂/∂q and ∂/∂v when
    /// `jacobians`) and returns its loads.
    pub(super) fn eval(
        &self,
        sys: &System,
        inputs: &Inputs,
        out: &mut Generalized,
        jacobians: bool,
    ) -> Result<Loads, MbdError> {
        match jacobians {
            true => self.eval_as::<D>(sys, inputs, out),
            false => self.eval_as::<f64>(sys, inputs, out),
        }
    }

    pub(super) fn eval_as<T: Num>(
        &self,
        sys: &System,
        inputs: &Inputs,
        out: &mut Generalized,
    ) -> Result<Loads, MbdError> {
        let mut slots = self.slots;
        let fi = T::frame(sys, Some(self.i), &mut slots);
        let fj = T::frame(sys, self.j, &mut slots);
        self.eval_framed(sys, inputs, out, (&fi, &fj), slots)
    }

    /// [`ForceElement::eval_as`] from the I and J frames `(fi, fj)` already built
    /// (`slots` holding their parts): the force set's frame cache builds each once.
    pub(super) fn eval_framed<T: Num>(
        &self,
        sys: &System,
        inputs: &Inputs,
        out: &mut Generalized,
        (fi, fj): (&Frame<T>, &Frame<T>),
        mut slots: PartSlots,
    ) -> Result<Loads, MbdError> {
        let zero: V<T> = V::c(Vec3::zeros());
        // (force at I, moment on I's part, force on J's part, moment on J's part), all
        // applied at I's origin except the line forces' reaction at J's.
        let (f_i, t_i, f_j, t_j, j_at_i) = match &self.law {
            ForceLaw::Line { f, action_only } => {
                let f = T::expression(self, sys, inputs, f, &mut slots)?;
                if *action_only {
                    (scale_v(&fj.axes[2], f), zero, zero, zero, true)
                } else {
                    let d = fi.r.sub(&fj.r);
                    let u = scale_v(&d, d.norm().recip());
                    let fv = scale_v(&u, f);
                    (fv, zero, neg_v(&fv), zero, false)
                }
            }
            ForceLaw::Torque { f, action_only } => {
                let f = T::expression(self, sys, inputs, f, &mut slots)?;
                let t = scale_v(&fj.axes[2], f);
                let tj = if *action_only { zero } else { neg_v(&t) };
                (zero, t, zero, tj, true)
            }
            ForceLaw::Vector { force, torque, rm } => {
                let frm = T::frame(sys, *rm, &mut slots);
                let comps = |xs: &Option<Box<[Scalar; 3]>>, slots: &mut PartSlots| match xs {
                    None => Ok(zero),
                    Some(xs) => {
                        let mut c = [T::c(0.0); 3];
                        for (k, x) in xs.iter().enumerate() {
                            c[k] = T::expression(self, sys, inputs, x, slots)?;
                        }
                        Ok::<V<T>, MbdError>(in_axes(&frm.axes, c))
                    }
                };
                let fv = comps(force, &mut slots)?;
                let tv = comps(torque, &mut slots)?;
                (fv, tv, neg_v(&fv), neg_v(&tv), true)
            }
            ForceLaw::Spring {
                k,
                c,
                length,
                preload,
            } => {
                let d = fi.r.sub(&fj.r);
                let len = d.norm();
                let u = scale_v(&d, len.recip());
                let rate = fi.vel.sub(&fj.vel).dot(&u);
                let f = rate.scale(-c) + (len - T::c(*length)).scale(-k) + T::c(*preload);
                let fv = scale_v(&u, f);
                (fv, zero, neg_v(&fv), zero, false)
            }
            ForceLaw::RotSpring {
                k,
                c,
                angle,
                preload,
                angle_measure,
            } => {
                let th = T::measure(sys, *angle_measure, &mut slots);
                let z = fj.axes[2];
                let rate = fi.w.sub(&fj.w).dot(&z);
                let t = rate.scale(-c) + (th - T::c(*angle)).scale(-k) + T::c(*preload);
                let tv = scale_v(&z, t);
                (zero, tv, zero, neg_v(&tv), true)
            }
            ForceLaw::Bushing {
                k,
                c,
                kt,
                ct,
                force,
                torque,
                angles,
            } => {
                let d = fi.r.sub(&fj.r);
                // Velocity of I relative to J as seen in J's frame.
                let vel = fi.vel.sub(&fj.vel).sub(&fj.w.cross(&d));
                let w = fi.w.sub(&fj.w);
                let mut fc = [T::c(0.0); 3];
                let mut tc = [T::c(0.0); 3];
                for a in 0..3 {
                    let ax = &fj.axes[a];
                    let th = T::measure(sys, angles[a], &mut slots);
                    fc[a] = d.dot(ax).scale(-k[a]) + vel.dot(ax).scale(-c[a]) + T::c(force[a]);
                    tc[a] = th.scale(-kt[a]) + w.dot(ax).scale(-ct[a]) + T::c(torque[a]);
                }
                let fv = in_axes(&fj.axes, fc);
                let tv = in_axes(&fj.axes, tc);
                (fv, tv, neg_v(&fv), neg_v(&tv), true)
            }
            ForceLaw::Field { law, angles } => {
                let (fv, tv) = law.loads(sys, fi, fj, angles, &mut slots);
                (fv, tv, neg_v(&fv), neg_v(&tv), true)
            }
            ForceLaw::Friction(law) => {
                let (fv, tv) = law.loads(sys, (fi, fj), inputs.solved);
                (fv, tv, neg_v(&fv), neg_v(&tv), true)
            }
        };
        let pi = sys.marker(self.i).part;
        let pj = self.j.map_or(System::GROUND, |j| sys.marker(j).part);
        let at_j = if j_at_i { fi } else { fj };
        self.apply(sys, &slots, pi, fi, &f_i, &t_i, out);
        self.apply(sys, &slots, pj, at_j, &f_j, &t_j, out);
        Ok(Loads {
            on_i: (f_i.value(), t_i.value()),
            on_j: (f_j.value(), t_j.value()),
            j_at: at_j.r.value(),
        })
    }

    /// Adds force `f` applied at frame `at`'s origin and moment `t` to part `part`'s
    /// generalized force (moment about its reference point), with Jacobians when `T`
    /// carries them.
    #[allow(clippy::too_many_arguments)]
    fn apply<T: Num>(
        &self,
        sys: &System,
        slots: &PartSlots,
        part: PartHandle,
        at: &Frame<T>,
        f: &V<T>,
        t: &V<T>,
        out: &mut Generalized,
    ) {
        let Some(index) = sys.part(part).index else {
            return;
        };
        let arm = at.r.sub(&T::reference(sys, part, slots));
        let m = add_v(t, &arm.cross(f));
        if sys.dim == Dimension::Two {
            // The part's three columns (two in-plane translations, the rotation about
            // the normal) directly, in the order the loop below visits them.
            let (a, b, n) = sys.plane_axes();
            let base = index * 3;
            let mut cols = [(a, base), (b, base + 1), (3 + n, base + 2)];
            cols.sort_unstable_by_key(|x| x.0);
            for (c, row) in cols {
                let q = if c < 3 { f.0[c] } else { m.0[c - 3] };
                T::load(&q, row, sys, slots, out);
            }
            return;
        }
        for c in 0..6 {
            let Some(row) = sys.col(part, c) else {
                continue;
            };
            let q = if c < 3 { f.0[c] } else { m.0[c - 3] };
            T::load(&q, row, sys, slots, out);
        }
    }
}
