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
    let mut scratch = Vec::with_capacity(at.len());
    let mut ta = t0;
    for i in 1..=SAMPLES {
        let tb = t0 + (t1 - t0) * i as f64 / SAMPLES as f64;
        eval(tb, &mut after);
        let mut first: Option<f64> = None;
        for (k, (&sa, &sb)) in before.iter().zip(&after).enumerate() {
            if !switched(sa, sb) {
                continue;
            }
            let root = regula_falsi((ta, sa), (tb, sb), resolution, |t| {
                eval(t, &mut scratch);
                scratch.get(k).copied().unwrap_or(f64::NAN)
            });
            first = Some(first.map_or(root, |r| r.min(root)));
        }
        if first.is_some() {
            return first;
        }
        std::mem::swap(&mut before, &mut after);
        ta = tb;
    }
    None
}

/// The zero of `f` between `a` and `b` (values of different signs) within `resolution`:
/// regula falsi with the Illinois correction (a bracket end kept twice running has its
/// value halved), bisecting after a try that did not halve the bracket. A NaN value (the
/// function not defined there) moves the upper end down: the switch is assumed earlier.
fn regula_falsi(
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    resolution: f64,
    mut f: impl FnMut(f64) -> f64,
) -> f64 {
    let (mut kept_a, mut bisect) = (None, false);
    for _ in 0..MAX_ITERATIONS {
        let width = b - a;
        if width <= resolution {
            break;
        }
        let secant = a + width * fa / (fa - fb);
        let t = match bisect || !secant.is_finite() {
            true => a + 0.5 * width,
            // Strictly inside, so each try shrinks the bracket.
            false => secant.clamp(a + 0.01 * resolution, b - 0.01 * resolution),
        };
        let ft = f(t);
        let lower = !ft.is_nan() && !switched(fa, ft);
        if lower {
            (a, fa) = (t, ft);
        } else {
            (b, fb) = (t, if ft.is_nan() { fb } else { ft });
        }
        if kept_a == Some(!lower) {
            match lower {
                true => fb *= 0.5,
                false => fa *= 0.5,
            }
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
}
