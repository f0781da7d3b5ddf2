//! The earliest switch along a candidate step's continuous extension: where a force
//! law's switching function first changes sign on the interpolated states between the
//! last accepted state and a candidate that crossed a switch. [`super::events`] aims its
//! next trial step there, so that a real step lands just short of the switch and the next
//! one crosses it within the location tolerance, instead of narrowing a bracket with
//! trial steps of the integrator. What counts as crossing a switch is [`switched`].
//!
//! Only switching functions are evaluated here, at interpolated states: a few dozen
//! evaluations of a small program, against a dozen force and saddle-point solves for one
//! trial step. The estimate is only a guess (the extension of a step across a switch
//! fits two laws with one polynomial): the step control still checks every step it
//! accepts, so a wrong guess costs trial steps, never accuracy.

/// Whether a switching function went from `s0` to `s1` across a switch (both defined,
/// on different branches).
pub(super) fn switched(s0: f64, s1: f64) -> bool {
    !(s0.is_nan() || s1.is_nan() || (s0 > 0.0) == (s1 > 0.0))
}

/// Evenly spaced samples of the extension searched for the first sign change: a switch
/// crossed and crossed back between two of them is not seen, as between two steps.
const SAMPLES: usize = 8;

/// Regula falsi iterations on one sample interval (a safeguard: with bisection every
/// other iteration at worst, 2·log2(1/1e-4) suffice for any resolution asked).
const MAX_ITERATIONS: usize = 60;

/// The earliest time in (`t0`, `t1`] where one of the switching functions (valued `at`
/// at `t0`) changes sign along the extension, within `resolution`; `values(t, out)`
/// appends the values at the extension's state at `t` to the emptied `out`. None when no
/// sample shows a sign change.
pub fn earliest(
    at: &[f64],
    (t0, t1): (f64, f64),
    resolution: f64,
    mut values: impl FnMut(f64, &mut Vec<f64>),
) -> Option<f64> {
    let mut eval = |t: f64, out: &mut Vec<f64>| {
        out.clear();
        values(t, out);
    };
    let (mut before, mut after) = (at.to_vec(), Vec::with_capacity(at.len()));
    let mut ta = t0;
    for i in 1..=SAMPLES {
        let tb = t0 + (t1 - t0) * i as f64 / SAMPLES as f64;
        eval(tb, &mut after);
        if before.iter().zip(&after).any(|(&sa, &sb)| switched(sa, sb)) {
            return Some(regula_falsi((ta, &before), (tb, &after), resolution, eval));
        }
        std::mem::swap(&mut before, &mut after);
        ta = tb;
    }
    None
}

/// The earliest zero between `a` and `b` of the functions whose values change sign
/// between `fa` and `fb`, within `resolution`: regula falsi with the Illinois correction
/// (a bracket end kept twice running has its values halved), bisecting after a try that
/// did not halve the bracket. All functions are narrowed together, each try one
/// evaluation of them all at the earliest secant estimate: so many switches in one step
/// (N contacts touching at once) cost as much as one. A try is the new upper end when any
/// function switched before it; a NaN value (the function not defined there) keeps that
/// function's value at its end.
fn regula_falsi(
    (mut a, fa): (f64, &[f64]),
    (mut b, fb): (f64, &[f64]),
    resolution: f64,
    mut eval: impl FnMut(f64, &mut Vec<f64>),
) -> f64 {
    let (mut fa, mut fb) = (fa.to_vec(), fb.to_vec());
    let mut ft = Vec::with_capacity(fa.len());
    let (mut kept_a, mut bisect) = (None, false);
    for _ in 0..MAX_ITERATIONS {
        let width = b - a;
        if width <= resolution {
            break;
        }
        let secant = (fa.iter().zip(&fb))
            .filter(|&(&x, &y)| switched(x, y))
            .map(|(&x, &y)| a + width * x / (x - y))
            .filter(|t| t.is_finite())
            .fold(f64::INFINITY, f64::min);
        let t = match bisect || !secant.is_finite() {
            true => a + 0.5 * width,
            // Strictly inside, so each try shrinks the bracket.
            false => secant.clamp(a + 0.01 * resolution, b - 0.01 * resolution),
        };
        eval(t, &mut ft);
        // Upper when a function switched between a and t, or is undefined at t where it
        // switched over the bracket (the switch is assumed earlier).
        let upper = (fa.iter().zip(&fb).zip(&ft))
            .any(|((&x, &y), &z)| switched(x, z) || (z.is_nan() && switched(x, y)));
        let (end, values) = match upper {
            true => (&mut b, &mut fb),
            false => (&mut a, &mut fa),
        };
        *end = t;
        for (v, &z) in values.iter_mut().zip(&ft) {
            if !z.is_nan() {
                *v = z;
            }
        }
        let lower = !upper;
        if kept_a == Some(!lower) {
            let kept = match lower {
                true => &mut fb,
                false => &mut fa,
            };
            kept.iter_mut().for_each(|v| *v *= 0.5);
        }
        kept_a = Some(!lower);
        bisect = b - a > 0.5 * width;
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_earliest_of_two_zeros_is_found_within_the_resolution() {
        // 1.3 − t vanishes at 1.3, (t − 0.7)³ earlier at 0.7; the third never does.
        let mut calls = 0;
        let r = earliest(&[1.3, -0.343, 1.0], (0.0, 2.0), 1e-9, |t, out| {
            calls += 1;
            out.extend([1.3 - t, (t - 0.7).powi(3), 1.0]);
        });
        assert!((r.unwrap() - 0.7).abs() < 1e-9, "{r:?}");
        assert!(calls < 80, "{calls} evaluations");
    }

    #[test]
    fn a_steep_one_sided_function_converges() {
        // Flat then steep: plain regula falsi would creep from the flat side.
        let g = |t: f64| ((t - 0.61) * 40.0).tanh() + 0.2 * (t - 0.61);
        let r = earliest(&[g(0.0)], (0.0, 1.0), 1e-10, |t, out| out.push(g(t)));
        assert!((r.unwrap() - 0.61).abs() < 1e-10, "{r:?}");
    }

    #[test]
    fn no_sign_change_gives_nothing_and_nan_is_no_switch() {
        let r = earliest(&[1.0, f64::NAN], (0.0, 1.0), 1e-6, |t, out| {
            out.extend([1.0 + t, -1.0]);
        });
        assert_eq!(r, None);
    }

    #[test]
    fn a_thousand_switches_at_once_cost_what_one_does() {
        // 1000 contacts landing together (t − 0.4 − k·1e-7): the earliest, 0.4, in as
        // many evaluations of them all as one switch needs, not one search each.
        let n = 1000;
        let mut calls = 0;
        let at: Vec<f64> = (0..n).map(|k| 0.4 + k as f64 * 1e-7).collect();
        let r = earliest(&at, (0.0, 1.0), 1e-9, |t, out| {
            calls += 1;
            out.extend((0..n).map(|k| 0.4 + k as f64 * 1e-7 - t));
        });
        assert!((r.unwrap() - 0.4).abs() < 1e-9, "{r:?}");
        assert!(calls < 80, "{calls} evaluations");
    }
}
