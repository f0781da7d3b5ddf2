//! One expression's value at a state, for the element that reads it: alone (from the
//! measures' values or the set's fused call), or as a dual, its compiled gradient
//! ∂f/∂measure chained with the measures' duals.

use super::element::ForceElement;
use super::inputs::{measure_value, Inputs, Scalar, Source};
use crate::mbd::dual::{D, N};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprError;
use crate::mbd::measures::PartSlots;
use crate::mbd::system::System;

/// A dual from a value and its gradient.
fn dual(v: f64, g: [f64; N]) -> D {
    D { v, g }
}

impl ForceElement {
    /// An expression's value alone: the set's fused evaluation's when there is one, else
    /// from the measures' values (no duals, no gradient; solution values from `inputs`).
    pub(super) fn scalar_value(
        &self,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
    ) -> Result<f64, MbdError> {
        if let (Some(k), Some(values)) = (s.fused, inputs.fused) {
            let v = values[k];
            return match v.is_finite() {
                true => Ok(v),
                false => Err(MbdError::Expression(
                    self.elref.clone(),
                    ExprError::NotFinite {
                        value: v,
                        time: sys.time,
                    },
                )),
            };
        }
        self.with_slot_values(sys, inputs, s, |vals| s.f.value(sys.time, vals))
    }

    /// `f` of the slot values of expression `s` from the measures' values (solution
    /// values from `inputs`), its error named after the element.
    pub(super) fn with_slot_values<R>(
        &self,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        f: impl FnOnce(&[f64]) -> Result<R, ExprError>,
    ) -> Result<R, MbdError> {
        let slot_ids = s.f.slots();
        let mut shared = sys.scratch.borrow_mut();
        let vals = shared.slots_to(slot_ids.last().copied());
        for (&src, &slot) in s.map.iter().zip(slot_ids) {
            vals[slot as usize] = match src {
                Source::Measure(m) => measure_value(sys, m),
                Source::Solution(k) => inputs.solved[k],
            };
        }
        f(vals).map_err(|why| MbdError::Expression(self.elref.clone(), why))
    }

    /// An expression's value as a dual: f with ∂f/∂measure chained through the
    /// measures' duals (solution values from `solved`, constant).
    pub(super) fn scalar_dual(
        &self,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        slots: &mut PartSlots,
    ) -> Result<D, MbdError> {
        let (solved, fused) = (inputs.solved, inputs.fused);
        let slot_ids = s.f.slots();
        let mut shared = sys.scratch.borrow_mut();
        let vals = shared.slots_to(slot_ids.last().copied());
        let err = |why| MbdError::Expression(self.elref.clone(), why);
        let mut scratch = s.scratch.borrow_mut();
        let (duals, grad) = &mut *scratch;
        duals.clear();
        for (&src, &slot) in s.map.iter().zip(slot_ids) {
            let d = match src {
                Source::Measure(m) => sys
                    .measures
                    .eval_in(sys, m, slots)
                    .ok_or_else(|| MbdError::TooManyParts(self.elref.clone()))?,
                Source::Solution(k) => D::c(solved[k]),
            };
            vals[slot as usize] = d.v;
            duals.push(d);
        }
        let v = match (s.fused_gradient, fused) {
            // The set's one call computed f and its partials at this state.
            (Some(at), Some(out)) => {
                let k = duals.len();
                let finite = |x: f64| match x.is_finite() {
                    true => Ok(x),
                    false => Err(err(ExprError::NotFinite {
                        value: x,
                        time: sys.time,
                    })),
                };
                for (g, &x) in grad.iter_mut().zip(&out[at + 1..=at + k]) {
                    *g = finite(x)?;
                }
                finite(out[at + k + 1])?;
                finite(out[at])?
            }
            _ => s.f.value_gradient(sys.time, vals, grad).map_err(err)?.0,
        };
        let mut g = [0.0; N];
        for (d, &c) in duals.iter().zip(grad.iter()) {
            if c != 0.0 {
                for (x, y) in g.iter_mut().zip(d.g.iter()) {
                    *x += c * y;
                }
            }
        }
        Ok(dual(v, g))
    }
}
