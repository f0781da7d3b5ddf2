//! The number types a force law runs on, behind one trait ([`Num`]): each reads a frame,
//! a measure and an expression, and adds itself to Q (the ∂Q/∂u one is in
//! `input_partials`).

use super::element::ForceElement;
use super::generalized::Generalized;
use super::inputs::{measure_value, Inputs, Scalar};
use crate::mbd::dual::{Scalar as ScalarT, D, PER_PART, V};
use crate::mbd::error::MbdError;
use crate::mbd::handles::PartHandle;
use crate::mbd::measure_set::M;
use crate::mbd::measures::{dual_frame, value_frame, Frame, PartSlots};
use crate::mbd::system::System;

/// The numbers a force element is evaluated in: duals over its part slots (value and
/// ∂/∂q, ∂/∂v) when the Jacobians are asked for, plain values otherwise. Both run the
/// same operations on the values, so they agree bit for bit.
pub(super) trait Num: ScalarT {
    fn scale(self, s: f64) -> Self;
    /// Marker `mk`'s frame (ground when None), extending `slots` with its part.
    fn frame(sys: &System, mk: M, slots: &mut PartSlots) -> Frame<Self>;
    /// Measure `m` (in the parts of `slots`, which it extends).
    fn measure(sys: &System, m: usize, slots: &mut PartSlots) -> Self;
    /// The reference point of `part`.
    fn reference(sys: &System, part: PartHandle, slots: &PartSlots) -> V<Self>;
    /// Expression `s` of element `el` (solution and fused values from `inputs`).
    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        slots: &mut PartSlots,
    ) -> Result<Self, MbdError>;
    /// Adds `x` to row `row` of Q (and its derivatives to Q's Jacobians).
    fn load(x: &Self, row: usize, sys: &System, slots: &PartSlots, out: &mut Generalized);
}

impl Num for D {
    fn scale(self, s: f64) -> D {
        D::scale(self, s)
    }

    fn frame(sys: &System, mk: M, slots: &mut PartSlots) -> Frame<D> {
        dual_frame(sys, mk, slots).expect("prepared")
    }

    fn measure(sys: &System, m: usize, slots: &mut PartSlots) -> D {
        sys.measures.eval_in(sys, m, slots).expect("prepared")
    }

    fn reference(sys: &System, part: PartHandle, slots: &PartSlots) -> V<D> {
        let mut p: V = V::c(sys.part(part).r);
        if let Some(s) = slots.parts.iter().position(|x| *x == Some(part)) {
            for c in 0..3 {
                p.0[c].g[PER_PART * s + c] = 1.0;
            }
        }
        p
    }

    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        slots: &mut PartSlots,
    ) -> Result<D, MbdError> {
        el.scalar_dual(sys, inputs, s, slots)
    }

    fn load(x: &D, row: usize, sys: &System, slots: &PartSlots, out: &mut Generalized) {
        out.q[row] += x.v;
        slots.scatter(
            sys,
            &x.g,
            &mut |col, g| out.dq.push((row, col, g)),
            &mut |col, g| out.dv.push((row, col, g)),
        );
    }
}

impl Num for f64 {
    fn scale(self, s: f64) -> f64 {
        self * s
    }

    fn frame(sys: &System, mk: M, _: &mut PartSlots) -> Frame<f64> {
        value_frame(sys, mk)
    }

    fn measure(sys: &System, m: usize, _: &mut PartSlots) -> f64 {
        measure_value(sys, m)
    }

    fn reference(sys: &System, part: PartHandle, _: &PartSlots) -> V<f64> {
        V::c(sys.part(part).r)
    }

    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        _: &mut PartSlots,
    ) -> Result<f64, MbdError> {
        el.scalar_value(sys, inputs, s)
    }

    fn load(x: &f64, row: usize, _: &System, _: &PartSlots, out: &mut Generalized) {
        out.q[row] += x;
    }
}
