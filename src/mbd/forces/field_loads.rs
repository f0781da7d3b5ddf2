//! The evaluation of the linear six-component law of FIELD and BEAM ([`Linear6`], its
//! formula in the `field` module): the deflection and its rate in J's axes from the
//! frames of I and J and the AX, AY, AZ measures, to the force and torque on I, in any
//! [`Num`].

use super::field::Linear6;
use super::num::Num;
use crate::mbd::dual::V;
use crate::mbd::measures::{Frame, PartSlots};
use crate::mbd::system::System;

impl Linear6 {
    /// The force and torque on I (global axes) at frames `fi`, `fj`, with `angles` the
    /// AX, AY, AZ measures of I relative to J.
    pub(super) fn loads<T: Num>(
        &self,
        sys: &System,
        fi: &Frame<T>,
        fj: &Frame<T>,
        angles: &[usize; 3],
        slots: &mut PartSlots,
    ) -> (V<T>, V<T>) {
        let d = fi.r.sub(&fj.r);
        let vel = fi.vel.sub(&fj.vel).sub(&fj.w.cross(&d));
        let w = fi.w.sub(&fj.w);
        let mut x = [T::c(0.0); 6];
        let mut v = [T::c(0.0); 6];
        for a in 0..3 {
            let ax = &fj.axes[a];
            x[a] = d.dot(ax) - T::c(self.length[a]);
            x[a + 3] = T::measure(sys, angles[a], slots) - T::c(self.length[a + 3]);
            v[a] = vel.dot(ax);
            v[a + 3] = w.dot(ax);
        }
        let mut out = [T::c(0.0); 6];
        for (r, o) in out.iter_mut().enumerate() {
            let mut s = T::c(self.preload[r]);
            for col in 0..6 {
                if self.k[r][col] != 0.0 {
                    s = s - x[col].scale(self.k[r][col]);
                }
                if self.c[r][col] != 0.0 {
                    s = s - v[col].scale(self.c[r][col]);
                }
            }
            *o = s;
        }
        let global = |c: &[T]| {
            let mut g = V::c(crate::vocab::math::Vec3::zeros());
            for (k, ax) in fj.axes.iter().enumerate() {
                g = V([
                    g.0[0] + ax.0[0] * c[k],
                    g.0[1] + ax.0[1] * c[k],
                    g.0[2] + ax.0[2] * c[k],
                ]);
            }
            g
        };
        (global(&out[..3]), global(&out[3..]))
    }
}
