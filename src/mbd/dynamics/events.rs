//! Events: the instants where a force law changes branch (an IMPACT or BISTOP contact
//! starts or ends, its clamp switches the force off or on again), located by the step
//! control: the accepted step that crosses one is a small fraction of the step that
//! found it, and every other accepted step stays on one branch of each law.
//!
//! Error control alone cannot do this: while the clamp holds a contact force at zero the
//! motion is free flight, the error estimate is zero and the step grows, so a step can
//! start with the force off and end after a short pulse of force is over, never having
//! seen it. Adams watches such functions and cuts the step; here every force expression
//! that calls IMPACT or BISTOP brings switching functions ([`crate::mbd::forces::contact`]),
//! signed values whose sign says which branch acts. They are evaluated at every accepted
//! state and at every candidate step that error control would accept; a sign change means
//! a switch inside the step, and then:
//!
//! 1. if the step is no longer than the location tolerance, it is accepted: the switch is
//!    located, and the next step starts on the new branch;
//! 2. otherwise the candidate is rejected and becomes the upper end of a bracket whose
//!    lower end is the accepted state, and the crossing is estimated on a continuous
//!    extension ([`Events::estimate`], `crossing.rs`: switching values at
//!    interpolated states, no integrator step): the candidate's own when error control
//!    accepted it, else (or when that shows none) the accepted state's Taylor extension,
//!    which follows the old branch (exact in free flight). The next step lands half the
//!    tolerance short of the estimate, and the one after crosses it with a step of the
//!    tolerance: a switch estimated within a quarter of the tolerance is located by
//!    these two accepted steps. A landing step that crosses is a new, shorter candidate
//!    with a new estimate; a crossing step that does not cross means the estimate was
//!    early, and the Taylor extension of the state it reached estimates again;
//! 3. with no estimate, the next step aims just short of the crossing the secant of the
//!    earliest switching function to change sign estimates (regula falsi, with the
//!    Illinois correction: a bracket end kept twice running has its value halved; and a
//!    bisection when a trial did not halve the bracket). A step landing short is still
//!    on the old branch, so it is accepted and becomes the lower end; once the bracket is
//!    within the tolerance, a step to its upper end crosses the switch.
//!
//! The switch is located by the steps taken, not by an estimate's word: a switching
//! function can be far from linear over a long step (the clamp's, near the end of a
//! contact, is), and a switch may stop being defined at the far end (the clamp's, once
//! the contact is over) and so change sign unseen. Every accepted step thus integrates
//! one branch of each law, up to the tolerance, as the error estimate assumes. The
//! tolerance is a fraction of the step that first found the switch. A switch crossed back
//! within one step (two sign changes) is not seen; the contacts' own error control keeps
//! steps in contact short enough for that.

use super::crossing::{self, switched};
use super::setup::Dynamics;

/// A switch is located when it is bracketed within this fraction of the step that first
/// found it: the step that crosses it is no longer than that.
const LOCATE_REL: f64 = 1e-3;

/// Trial steps spent on one switch before a crossing step is taken as it is, however
/// long (a safeguard: bisection alone needs log2(1/LOCATE_REL) ≈ 10).
const MAX_TRIES: usize = 40;

/// The switching values of a run and the switch being located (the default watches
/// nothing).
#[derive(Default)]
pub struct Events {
    /// At the last accepted state (NaN: not defined there).
    at: Vec<f64>,
    /// At the candidate.
    next: Vec<f64>,
    target: Option<Target>,
}

/// A switch inside the bracket (last accepted time, `t_hi`].
#[derive(Clone, Copy, Debug)]
struct Target {
    /// Its index in the switching values.
    k: usize,
    /// The earliest rejected candidate past it, and the switching value there.
    t_hi: f64,
    s_hi: f64,
    /// Located within this time.
    tol: f64,
    tries: usize,
    /// Illinois factors on the two ends' values, and which end the last trial moved
    /// (true: the lower).
    lo_scale: f64,
    hi_scale: f64,
    moved_lo: Option<bool>,
    /// The last trial shrank the bracket by less than half: bisect next.
    bisect: bool,
    /// Its time estimated on a continuous extension ([`Events::estimate`]), while that
    /// lies ahead.
    root: Option<f64>,
}

/// What the step control does with a candidate that error control accepts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// Accept it; `event`: it crosses a (located) switch.
    Accept {
        /// It crosses a located switch.
        event: bool,
    },
    /// Reject it: a switch lies inside, to be located by [`Events::aim`].
    Locate,
}

impl Target {
    /// Bookkeeping of a trial that moved one end of the bracket (`lo`: the lower one)
    /// from width `before` to `after`.
    fn moved(&mut self, lo: bool, before: f64, after: f64) {
        // Illinois: the end kept twice running has its value halved.
        if self.moved_lo == Some(lo) {
            if lo {
                self.hi_scale *= 0.5;
            } else {
                self.lo_scale *= 0.5;
            }
        } else {
            (self.lo_scale, self.hi_scale) = (1.0, 1.0);
        }
        self.moved_lo = Some(lo);
        self.bisect = after > 0.5 * before;
        self.tries += 1;
    }
}

impl Events {
    /// The switching values of `d`'s forces at its current state (none: nothing to
    /// watch, and the step control runs as without events).
    pub fn new(d: &Dynamics) -> Events {
        let mut at = Vec::new();
        d.forces.switches(&d.sys, &mut at);
        Events {
            next: Vec::with_capacity(at.len()),
            at,
            target: None,
        }
    }

    /// Whether a contact is engaged at the last accepted state (a penetration or a
    /// clamp value on its acting side).
    pub fn engaged(&self) -> bool {
        self.at.iter().any(|&v| v > 0.0)
    }

    /// The step from time `t` toward the switch being located (None: none is): onto the
    /// bracket's upper end once it is within the tolerance; else, with a crossing
    /// estimated on an extension ahead, half the tolerance short of it, or across it
    /// within the tolerance once that close; else just short of the secant's crossing
    /// (or to the middle when bisecting).
    pub fn aim(&self, t: f64) -> Option<f64> {
        let g = self.target?;
        let width = g.t_hi - t;
        if width <= 0.0 {
            return None;
        }
        if width <= g.tol {
            return Some(width);
        }
        if let Some(root) = g.root.filter(|&r| r > t) {
            let ahead = root - t;
            // Across it once within three quarters of the tolerance (a landing half a
            // tolerance short leaves half a tolerance on either side of it).
            return Some(match ahead <= 0.75 * g.tol {
                true => g.tol,
                false => ahead - 0.5 * g.tol,
            });
        }
        let (s0, s1) = (self.at[g.k] * g.lo_scale, g.s_hi * g.hi_scale);
        let root = width * s0 / (s0 - s1);
        let step = if g.bisect || !root.is_finite() {
            0.5 * width
        } else {
            root - 0.5 * g.tol
        };
        // Inside the bracket, and no shorter than the tolerance.
        Some(step.clamp(g.tol.min(0.5 * width), width - 0.5 * g.tol))
    }

    /// Judges the candidate in `d`, a step of `h` (accepted by error control) from the
    /// last accepted state; the candidate's switching values are kept for
    /// [`Events::accept`].
    pub fn check(&mut self, d: &Dynamics, h: f64, hmin: f64) -> Verdict {
        if self.at.is_empty() {
            return Verdict::Accept { event: false };
        }
        self.next.clear();
        d.forces.switches(&d.sys, &mut self.next);
        self.judge(d.sys.time, h, hmin)
    }

    /// Whether the candidate in `d` has a switching value of another sign than at the
    /// last accepted state (a switch inside the step), judging nothing; its values are
    /// kept for [`Events::judge`].
    pub fn crosses(&mut self, d: &Dynamics) -> bool {
        if self.at.is_empty() {
            return false;
        }
        self.next.clear();
        d.forces.switches(&d.sys, &mut self.next);
        self.at
            .iter()
            .zip(&self.next)
            .any(|(&s0, &s1)| switched(s0, s1))
    }

    /// [`Events::check`] with the candidate's switching values in `self.next` (as
    /// [`Events::crosses`] leaves them) and its time `t1`.
    pub fn judge(&mut self, t1: f64, h: f64, hmin: f64) -> Verdict {
        // The earliest sign change by the secant, as a fraction of the step.
        let mut first: Option<(usize, f64)> = None;
        for (k, (&s0, &s1)) in self.at.iter().zip(&self.next).enumerate() {
            if !switched(s0, s1) {
                continue;
            }
            let theta = s0 / (s0 - s1);
            if first.is_none_or(|(_, th)| theta < th) {
                first = Some((k, theta));
            }
        }
        let Some((k, _)) = first else {
            // Short of the switch: the lower end moves up.
            if let Some(g) = &mut self.target {
                let before = g.t_hi - (t1 - h);
                g.moved(true, before, g.t_hi - t1);
                if g.root.is_some_and(|r| t1 >= r) {
                    // Past the estimate without a switch: it was early. The secant from
                    // here on.
                    (g.root, g.bisect) = (None, false);
                }
                if t1 >= g.t_hi {
                    // Reached the upper end without a switch (a trial from an earlier
                    // state had seen one): nothing left to locate.
                    self.target = None;
                }
            }
            return Verdict::Accept { event: false };
        };
        let tol = self.target.map_or(LOCATE_REL * h, |g| g.tol).max(hmin);
        let tries = self.target.map_or(0, |g| g.tries);
        if h <= tol * (1.0 + 1e-9) || tries >= MAX_TRIES {
            self.target = None;
            return Verdict::Accept { event: true };
        }
        self.target = Some(match self.target {
            Some(mut g) => {
                let before = g.t_hi - (t1 - h);
                if g.k != k {
                    // Another switch comes first: the bracket is about it now.
                    (g.lo_scale, g.hi_scale, g.moved_lo) = (1.0, 1.0, None);
                }
                (g.k, g.t_hi, g.s_hi) = (k, t1, self.next[k]);
                g.moved(false, before, h);
                g.root = None;
                g
            }
            None => Target {
                k,
                t_hi: t1,
                s_hi: self.next[k],
                tol,
                tries: 1,
                lo_scale: 1.0,
                hi_scale: 1.0,
                moved_lo: None,
                bisect: false,
                root: None,
            },
        });
        Verdict::Locate
    }

    /// The span (from the last accepted time `t`) over which the switch being located
    /// has no estimate ahead: a step passed the last one, or none was made.
    pub fn unestimated(&self, t: f64) -> Option<(f64, f64)> {
        let g = self.target?;
        (g.t_hi > t && g.root.is_none_or(|r| r <= t)).then_some((t, g.t_hi))
    }

    /// Estimates where the switch being located lies between `t0` and `t1` on a
    /// continuous extension from the last accepted state (the candidate's just judged
    /// [`Verdict::Locate`], or the state's own; `crossing.rs`): `values(t, out)`
    /// appends the switching values at the extension's state at `t`. [`Events::aim`]
    /// aims at the estimate until a step passes it.
    pub fn estimate(&mut self, (t0, t1): (f64, f64), values: impl FnMut(f64, &mut Vec<f64>)) {
        let Some(g) = &mut self.target else { return };
        // Well inside the window the aim leaves on either side of the estimate.
        let resolution = 0.05 * g.tol;
        g.root = crossing::earliest(&self.at, (t0, t1), resolution, values);
    }

    /// The candidate [`Events::check`] judged was accepted: its switching values are the
    /// new reference.
    pub fn accept(&mut self) {
        if !self.at.is_empty() {
            std::mem::swap(&mut self.at, &mut self.next);
        }
    }
}

#[cfg(test)]
mod tests {
    //! The location against switching functions of time with known zeros: a step driver
    //! as `integrator::simulate` runs one, without an integrator.
    use super::*;

    /// Runs from 0 to `end` with steps of `want` (or what [`Events::aim`] asks), the
    /// switching values at t given by `s`; returns each accepted step that crossed a
    /// switch, as (start, end), and the number of rejected trials.
    fn drive(s: impl Fn(f64) -> Vec<f64>, want: f64, end: f64) -> (Vec<(f64, f64)>, usize) {
        drive_estimating(s, want, end, None)
    }

    /// [`drive`], estimating each crossing on an extension that is `s` delayed by
    /// `late` (when given), as the driver does after a rejected candidate and after a
    /// step past the estimate.
    fn drive_estimating(
        s: impl Fn(f64) -> Vec<f64>,
        want: f64,
        end: f64,
        late: Option<f64>,
    ) -> (Vec<(f64, f64)>, usize) {
        let mut ev = Events {
            at: s(0.0),
            next: Vec::new(),
            target: None,
        };
        let (mut t, mut crossings, mut rejected) = (0.0, Vec::new(), 0);
        while t < end {
            let h = ev.aim(t).map_or(want, |a| a.min(want)).min(end - t);
            ev.next = s(t + h);
            match ev.judge(t + h, h, 1e-12) {
                Verdict::Locate => {
                    rejected += 1;
                    if let Some(late) = late {
                        ev.estimate((t, t + h), |x, out| out.extend(s(x - late)));
                    }
                }
                Verdict::Accept { event } => {
                    if event {
                        crossings.push((t, t + h));
                    }
                    ev.accept();
                    t += h;
                }
            }
            if let (Some(late), Some(span)) = (late, ev.unestimated(t)) {
                ev.estimate(span, |x, out| out.extend(s(x - late)));
            }
        }
        (crossings, rejected)
    }

    /// A contact from t = 0.1 to 0.3 whose clamp holds the force off from 0.15 until
    /// 0.2345, the clamp's function steep where it switches back, undefined off contact.
    fn contact(t: f64) -> Vec<f64> {
        let p = (t - 0.1) * (0.3 - t);
        let clamp = if p > 0.0 {
            (t - 0.15) * (0.2345 - t) * -((t - 0.2345) * 200.0).tanh().abs()
        } else {
            f64::NAN
        };
        vec![p, clamp]
    }

    #[test]
    fn every_switch_is_located_within_the_tolerance_in_order() {
        let want = 0.04;
        let (crossings, rejected) = drive(contact, want, 0.5);
        let zeros = [0.1, 0.15, 0.2345, 0.3];
        assert_eq!(crossings.len(), zeros.len(), "{crossings:?}");
        for ((a, b), z) in crossings.iter().zip(zeros) {
            assert!(*a < z && z <= *b, "{z} not in ({a}, {b})");
            assert!(b - a <= LOCATE_REL * want * (1.0 + 1e-9), "({a}, {b})");
        }
        assert!(rejected < 15 * zeros.len(), "{rejected} rejected trials");
    }

    #[test]
    fn an_estimated_switch_costs_the_rejected_step_that_found_it_alone() {
        let want = 0.04;
        let zeros = [0.1, 0.15, 0.2345, 0.3];
        // Exact estimates, and estimates a fifth of the tolerance late or early.
        for late in [0.0, 0.2e-3 * want, -0.2e-3 * want] {
            let (crossings, rejected) = drive_estimating(contact, want, 0.5, Some(late));
            assert_eq!(crossings.len(), zeros.len(), "{late}: {crossings:?}");
            for ((a, b), z) in crossings.iter().zip(zeros) {
                assert!(*a < z && z <= *b, "{late}: {z} not in ({a}, {b})");
                assert!(b - a <= LOCATE_REL * want * (1.0 + 1e-9), "({a}, {b})");
            }
            assert_eq!(rejected, zeros.len(), "{late}");
        }
        // Estimates far off still locate every switch, through more trials.
        for late in [0.01, -0.01] {
            let (crossings, rejected) = drive_estimating(contact, want, 0.5, Some(late));
            assert_eq!(crossings.len(), zeros.len(), "{late}: {crossings:?}");
            for ((a, b), z) in crossings.iter().zip(zeros) {
                assert!(*a < z && z <= *b, "{late}: {z} not in ({a}, {b})");
                assert!(b - a <= LOCATE_REL * want * (1.0 + 1e-9), "({a}, {b})");
            }
            assert!(
                rejected < 15 * zeros.len(),
                "{late}: {rejected} rejected trials"
            );
        }
    }

    #[test]
    fn a_clamp_switch_hidden_behind_the_end_of_contact_is_found() {
        // One step from 0.2 (clamped) to 0.32 (free): the clamp's sign at the far end is
        // undefined, yet its switch at 0.2345 comes first.
        let mut ev = Events {
            at: contact(0.2),
            next: contact(0.32),
            target: None,
        };
        assert_eq!(ev.judge(0.32, 0.12, 1e-12), Verdict::Locate);
        let (crossings, _) = drive(contact, 0.12, 0.5);
        assert!(crossings.iter().any(|&(a, b)| a < 0.2345 && 0.2345 <= b));
    }

    #[test]
    fn without_switches_every_step_is_accepted() {
        let (crossings, rejected) = drive(|t| vec![1.0 + t, f64::NAN], 0.1, 1.0);
        assert!(crossings.is_empty() && rejected == 0);
    }
}
