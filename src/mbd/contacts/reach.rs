//! The longest step after which no watched pair can have passed through the other
//! unseen (continuous collision's conservative bound). Onset is a switch the step
//! control sees only at the ends of a step; a long step of free flight (dopri853 takes
//! 0.3 s ones) can carry a ball from above a floor to below it, apart at both ends.
//!
//! Over a step of h from the current state, a material point of part P moves by at
//! most |v|·h + ½·|a|·h² plus, for a point at arm R, (|ω|·h + ½·(|α| + |ω|²)·h²)·R (the
//! rotation's arc and its growth). A pair whose relative motion stays within the gap
//! between its bounding boxes plus its two half-thicknesses ([`crate::collide::Reach`])
//! either stays apart or ends overlapping, where the switch sees it. The bound is taken
//! from the accelerations of the accepted state: a force that changes a lot inside the
//! step (a contact's own) is left to the error control, which already keeps such steps
//! short.

use super::ContactSet;
use crate::mbd::system::System;

/// The fraction of the allowance a step may use: the accelerations are those of the
/// step's start.
const SAFETY: f64 = 0.5;

impl ContactSet {
    /// The longest step (at most `h`) from the state of `sys` over which no pair can
    /// pass through another unseen.
    pub fn step_bound(&self, sys: &System, h: f64) -> f64 {
        let Some(world) = &self.world else { return h };
        self.place(sys);
        let world = world.borrow();
        let mut bound = h;
        for (k, pair) in self.pairs.iter().enumerate() {
            let (Some(reach), Some((gi, gj))) = (world.reach(k), world.pair_geometries(k)) else {
                continue;
            };
            let (pi, pj) = (sys.part(pair.i), sys.part(pair.j));
            let (ri, rj) = (world.arm(gi, &pi.r), world.arm(gj, &pj.r));
            let speed = (pi.v - pj.v).norm() + pi.w.norm() * ri + pj.w.norm() * rj;
            let accel = (pi.acc - pj.acc).norm()
                + (pi.alpha.norm() + pi.w.norm_squared()) * ri
                + (pj.alpha.norm() + pj.w.norm_squared()) * rj;
            let allowance = SAFETY * (reach.gap + reach.thickness);
            // speed·t + ½·accel·t² = allowance, in the form without cancellation.
            let root = speed + (speed * speed + 2.0 * accel * allowance).sqrt();
            if root > 0.0 && root.is_finite() {
                bound = bound.min(2.0 * allowance / root);
            }
        }
        bound
    }
}
