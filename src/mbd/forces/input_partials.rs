//! ∂Q/∂u: how the generalized forces change with a plant input u, a design variable (a
//! constant VARIABLE the expressions read through VARVAL, as Adams Controls' PINPUT
//! VARIABLEs are) — the B matrix of a linearization. Forward mode along u: each element
//! is evaluated once more over [`J2`] (a value and its derivative along one path; the
//! second derivative rides along unused) with the state held constant, each expression
//! giving ∂f/∂u from its compiled gradient in the input's slots, and the loads keeping
//! only the derivative. Solution values an expression reads (another force, a
//! reaction) are held fixed, as within any one evaluation.

use super::element::ForceElement;
use super::generalized::Generalized;
use super::inputs::{measure_value, Inputs, Scalar, Source};
use super::num::Num;
use super::set::ForceSet;
use crate::mbd::dual::{Scalar as _, J2, V};
use crate::mbd::error::MbdError;
use crate::mbd::handles::PartHandle;
use crate::mbd::measure_set::{Measure, M};
use crate::mbd::measures::{value_frame, Frame, PartSlots};
use crate::mbd::system::System;
use crate::vocab::math::DVec;

impl Num for J2 {
    fn scale(self, s: f64) -> J2 {
        J2 {
            v: self.v * s,
            d: self.d * s,
            dd: self.dd * s,
        }
    }

    fn frame(sys: &System, mk: M, _: &mut PartSlots) -> Frame<J2> {
        let f = value_frame(sys, mk);
        let c = |x: V<f64>| V(x.0.map(J2::c));
        Frame {
            r: c(f.r),
            axes: f.axes.map(c),
            vel: c(f.vel),
            w: c(f.w),
        }
    }

    fn measure(sys: &System, m: usize, _: &mut PartSlots) -> J2 {
        J2::c(measure_value(sys, m))
    }

    fn reference(sys: &System, part: PartHandle, _: &PartSlots) -> V<J2> {
        V::c(sys.part(part).r)
    }

    fn expression(
        el: &ForceElement,
        sys: &System,
        inputs: &Inputs,
        s: &Scalar,
        _: &mut PartSlots,
    ) -> Result<J2, MbdError> {
        let mut grad = vec![0.0; s.map.len()];
        let v = el.with_slot_values(sys, inputs, s, |vals| {
            s.f.value_gradient(sys.time, vals, &mut grad)
        })?;
        let reads_input = |src: &Source| match *src {
            Source::Measure(m) => {
                matches!(sys.measures.list[m], Measure::Design { id } if Some(id) == inputs.seed)
            }
            Source::Solution(_) => false,
        };
        let d = s
            .map
            .iter()
            .zip(&grad)
            .filter(|(src, _)| reads_input(src))
            .map(|(_, g)| g)
            .sum();
        Ok(J2 { v: v.0, d, dd: 0.0 })
    }

    fn load(x: &J2, row: usize, _: &System, _: &PartSlots, out: &mut Generalized) {
        out.q[row] += x.d;
    }
}

impl ForceSet {
    /// ∂Q/∂u for design variable `id` (VARIABLE/id) at the state of `sys`, over the `n`
    /// velocity-layout columns: zero where no expression reads it.
    pub fn input_partials(&self, sys: &System, id: i64, n: usize) -> Result<DVec, MbdError> {
        let inputs = Inputs {
            solved: &self.solved,
            fused: None,
            seed: Some(id),
        };
        let mut out = Generalized::new(n);
        for e in &self.elements {
            e.eval_as::<J2>(sys, &inputs, &mut out)?;
        }
        Ok(out.q)
    }
}
