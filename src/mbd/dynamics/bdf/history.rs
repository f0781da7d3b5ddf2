//! The accepted states a backward-difference step interpolates, newest first, with each
//! one's configuration in the chart of the newest ([`Dynamics::increment`]: positions
//! minus the newest's, rotations as rotation vectors relative to it). The chart moves
//! with every accepted step, so the past points stay a few steps' rotation away from its
//! origin where the rotation vector is smooth. Velocities live in a vector space (global
//! axes) and need no chart.
//!
//! Each point holds the state elements' x and ẋ too ([`crate::mbd::states`]: they are
//! integrated by the same formula), as the last commit left them.
//!
//! Right after a start or a restart there is one real point; the order-1 predictor then
//! uses a seed point one step back, from the newest state's Taylor expansion
//! (second order in the positions, first in the velocities, all that order 1 needs).
//! The Lagrange weights of the interpolants through them ([`lagrange`],
//! [`lagrange_weights`]).

use crate::mbd::dynamics::setup::Dynamics;
use crate::mbd::dynamics::state::{copy_into, Snapshot};
use crate::vocab::math::DVec;
use std::collections::VecDeque;

/// One accepted state.
pub struct Point {
    /// Its time.
    pub t: f64,
    /// The parts' poses.
    pub snap: Snapshot,
    /// Velocities (velocity layout, global axes).
    pub v: DVec,
    /// Multipliers.
    pub lambda: DVec,
    /// The configuration in the newest point's chart (velocity layout).
    pub x: Vec<f64>,
    /// The state elements' x and ẋ.
    pub states: Vec<f64>,
    pub rates: Vec<f64>,
    /// The estimate of its global error (`variation`): positions in the chart, then
    /// velocities; empty while none is carried (zero).
    pub e: Vec<f64>,
}

/// The committed states and rates of `d` into `x` and `rate` (empty without states).
fn committed_states(d: &Dynamics, x: &mut Vec<f64>, rate: &mut Vec<f64>) {
    x.clear();
    rate.clear();
    if let Some((cx, cr)) = d.forces.states.committed() {
        x.extend_from_slice(cx);
        rate.extend_from_slice(cr);
    }
}

/// The accepted states, newest first, at most `cap` of them.
pub struct History {
    points: VecDeque<Point>,
    cap: usize,
    /// The accelerations at the newest point (the seed's Taylor term).
    a: DVec,
    /// The seed point, built for the step size of the attempt that needs it.
    seed: Option<Point>,
}

impl History {
    /// A history holding only the current state of `d`.
    pub fn new(d: &Dynamics, cap: usize) -> History {
        let mut h = History {
            points: VecDeque::with_capacity(cap),
            cap,
            a: DVec::zeros(0),
            seed: None,
        };
        h.restart(d);
        h
    }

    /// Forgets every point but the current state of `d` (a start, or a restart after a
    /// discontinuity).
    pub fn restart(&mut self, d: &Dynamics) {
        // The state's error stays what it was: a restart forgets the steps, not the error.
        let e = self.points.front_mut().map(|p| std::mem::take(&mut p.e));
        self.points.clear();
        let mut p = Point {
            t: d.sys.time,
            snap: d.snapshot(),
            v: d.sys.v(),
            lambda: d.lambda.clone(),
            x: vec![0.0; d.n],
            states: Vec::new(),
            rates: Vec::new(),
            e: e.unwrap_or_default(),
        };
        committed_states(d, &mut p.states, &mut p.rates);
        self.points.push_front(p);
        self.a = d.a.clone();
        self.seed = None;
    }

    /// Makes the state of `d` the newest point and moves the chart to it.
    pub fn push(&mut self, d: &Dynamics) {
        // The oldest point's buffers are reused when the history is full.
        let snap = d.snapshot();
        let mut p = match self.points.len() >= self.cap {
            true => {
                let mut p = self.points.pop_back().expect("cap > 0");
                p.snap = snap;
                p.e.clear();
                p
            }
            false => Point {
                t: 0.0,
                snap,
                v: DVec::zeros(d.n),
                lambda: DVec::zeros(d.m),
                x: vec![0.0; d.n],
                states: Vec::new(),
                rates: Vec::new(),
                e: Vec::new(),
            },
        };
        p.t = d.sys.time;
        committed_states(d, &mut p.states, &mut p.rates);
        copy_into(&mut p.v, d.sys.v().as_slice());
        copy_into(&mut p.lambda, d.lambda.as_slice());
        self.points.push_front(p);
        copy_into(&mut self.a, d.a.as_slice());
        self.seed = None;
        let (newest, rest) = self
            .points
            .make_contiguous()
            .split_first_mut()
            .expect("pushed");
        newest.x.fill(0.0);
        for q in rest {
            d.increment(&newest.snap, &q.snap, &mut q.x);
        }
    }

    /// Real points held.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// The accelerations at the newest point.
    pub fn accelerations(&self) -> &DVec {
        &self.a
    }

    /// The newest point.
    pub fn newest(&self) -> &Point {
        &self.points[0]
    }

    /// The newest point's global error estimate, to fill after [`History::push`].
    pub fn newest_error_mut(&mut self) -> &mut Vec<f64> {
        &mut self.points[0].e
    }

    /// Builds the seed for a first step of `h` when only one real point is held.
    pub fn seed_for(&mut self, h: f64) {
        if self.points.len() > 1 {
            return;
        }
        let p = &self.points[0];
        let x: Vec<f64> =
            p.v.iter()
                .zip(self.a.iter())
                .map(|(v, a)| -h * v + 0.5 * h * h * a)
                .collect();
        self.seed = Some(Point {
            t: p.t - h,
            snap: p.snap.clone(),
            v: &p.v - &self.a * h,
            lambda: p.lambda.clone(),
            x,
            // First order in the states, all that order 1 needs.
            states: (p.states.iter().zip(&p.rates))
                .map(|(x, r)| x - h * r)
                .collect(),
            rates: p.rates.clone(),
            // The seed is the newest point's expansion: its error, to first order.
            e: p.e.clone(),
        });
    }

    /// The `j`-th point back (0: the newest), the seed standing in behind a lone point.
    pub fn point(&self, j: usize) -> &Point {
        match (self.points.get(j), &self.seed) {
            (Some(p), _) => p,
            (None, Some(s)) if j == 1 => s,
            _ => panic!("history point {j} of {} requested", self.points.len()),
        }
    }
}

/// Lagrange weights at `tau` of the interpolant through the nodes `ts`: the value's in
/// `l`, the derivative's in `dl` (`tau` is not a node).
pub fn lagrange(ts: &[f64], tau: f64, l: &mut [f64], dl: &mut [f64]) {
    for j in 0..ts.len() {
        let (mut w, mut s) = (1.0, 0.0);
        for (m, &tm) in ts.iter().enumerate() {
            if m != j {
                w *= (tau - tm) / (ts[j] - tm);
                s += 1.0 / (tau - tm);
            }
        }
        l[j] = w;
        dl[j] = w * s;
    }
}

/// Lagrange weights at `tau` of the interpolant through the nodes `ts` (value only; `tau`
/// may be a node).
pub fn lagrange_weights(ts: &[f64], tau: f64, l: &mut [f64]) {
    for j in 0..ts.len() {
        l[j] = ts
            .iter()
            .enumerate()
            .filter(|&(m, _)| m != j)
            .map(|(_, &tm)| (tau - tm) / (ts[j] - tm))
            .product();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_weights_reproduce_a_cubic_through_four_nodes() {
        let p = |t: f64| 2.0 - t + 0.5 * t * t - 0.25 * t * t * t;
        let ts = [0.0, -0.1, -0.25, -0.3];
        let mut l = [0.0; 4];
        for tau in [-0.05, -0.2, 0.0, -0.3] {
            lagrange_weights(&ts, tau, &mut l);
            let value: f64 = ts.iter().zip(&l).map(|(&t, w)| w * p(t)).sum();
            assert!((value - p(tau)).abs() < 1e-14, "{tau}: {value}");
        }
    }
}
