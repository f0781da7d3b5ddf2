//! What a force expression reads: each slot from a kinematic measure or from a value of
//! the solution ([`Source`]), the compiled expression with its slot map and reused
//! buffers ([`Scalar`]), and what an evaluation reads besides the state ([`Inputs`]).

use super::contact::ContactProbe;
use crate::mbd::dual::D;
use crate::mbd::expr::ExprFn;
use crate::mbd::system::System;

/// Where the value of an expression's slot comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// A kinematic measure (index into the system's measures): value and dual.
    Measure(usize),
    /// A value of the solution (index into [`ForceSet::solution`]): an acceleration, a
    /// reaction or a force, fixed within one evaluation.
    ///
    /// [`ForceSet::solution`]: super::ForceSet::solution
    Solution(usize),
}

/// An expression of the model: `map[k]` is where its k-th slot is read from.
pub struct Scalar {
    /// The compiled expression with its gradient.
    pub f: Box<dyn ExprFn>,
    /// Where each slot of `f` is read from.
    pub map: Vec<Source>,
    /// Buffers of an evaluation (measure duals, gradient), reused; the slot values live
    /// in the system's one array ([`crate::mbd::system::ExprScratch`]).
    pub(super) scratch: std::cell::RefCell<(Vec<D>, Vec<f64>)>,
    /// The switching functions of its contact calls, when it has any.
    pub(super) probe: Option<ContactProbe>,
    /// Its IR, for [`ForceSet::fuse`] (None once fused or when not given).
    ///
    /// [`ForceSet::fuse`]: super::ForceSet::fuse
    pub(super) ir: Option<crate::ir::Function>,
    /// Its output in the set's fused evaluation, and where its value and partials
    /// start in the fused gradients ([`ForceSet::fuse`]).
    ///
    /// [`ForceSet::fuse`]: super::ForceSet::fuse
    pub(super) fused: Option<usize>,
    pub(super) fused_gradient: Option<usize>,
}

impl Scalar {
    /// An expression reading its slots from `map`, with its buffers allocated.
    pub fn new(f: Box<dyn ExprFn>, map: Vec<Source>) -> Scalar {
        let n = map.len();
        Scalar {
            f,
            map,
            scratch: std::cell::RefCell::new((Vec::with_capacity(n), vec![0.0; n])),
            probe: None,
            ir: None,
            fused: None,
            fused_gradient: None,
        }
    }

    /// The same expression with its IR kept for [`ForceSet::fuse`].
    ///
    /// [`ForceSet::fuse`]: super::ForceSet::fuse
    pub fn with_ir(mut self, function: crate::ir::Function) -> Scalar {
        self.ir = Some(function);
        self
    }

    /// The same expression with the switching functions of the IMPACT and BISTOP calls
    /// in `function`, its IR.
    pub fn watching(mut self, function: &crate::ir::Function) -> Scalar {
        self.probe = ContactProbe::of(function);
        self
    }

    /// Appends the switching values at the state of `sys` (nothing without contact
    /// calls); solution values are those of the last evaluation, `solved`.
    pub(super) fn switches(&self, sys: &System, solved: &[f64], out: &mut Vec<f64>) {
        let Some(probe) = &self.probe else { return };
        let mut scratch = sys.scratch.borrow_mut();
        let vals = scratch.slots_to(self.f.slots().last().copied());
        for (&src, &slot) in self.map.iter().zip(self.f.slots()) {
            vals[slot as usize] = match src {
                Source::Measure(m) => measure_value(sys, m),
                Source::Solution(k) => solved[k],
            };
        }
        probe.eval(sys.time, vals, out);
    }

    /// The solution values it reads (indices into [`ForceSet::solution`]).
    ///
    /// [`ForceSet::solution`]: super::ForceSet::solution
    pub(super) fn solution_reads(&self) -> impl Iterator<Item = usize> + '_ {
        self.map.iter().filter_map(|s| match s {
            Source::Solution(k) => Some(*k),
            Source::Measure(_) => None,
        })
    }
}

/// Measure `m`'s value alone, unwrapped as its dual would be: plain numbers where the
/// dual carries a gradient over four parts (the same operations on the values).
pub(crate) fn measure_value(sys: &System, m: usize) -> f64 {
    sys.measures.unwrapped_value(sys, m)
}

/// What an element's expressions read besides the state: the solution values
/// ([`ForceSet::solved`]) and the set's fused values at this state, when it has them.
///
/// [`ForceSet::solved`]: super::ForceSet::solved
pub(super) struct Inputs<'a> {
    pub(super) solved: &'a [f64],
    /// The fused values, or with Jacobians the fused values and partials.
    pub(super) fused: Option<&'a [f64]>,
    /// The design variable an input-partials evaluation differentiates along
    /// ([`ForceSet::input_partials`]).
    ///
    /// [`ForceSet::input_partials`]: super::ForceSet::input_partials
    pub(super) seed: Option<i64>,
}
