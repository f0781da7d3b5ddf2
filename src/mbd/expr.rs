//! What GCON and MOTION need from an expression: its value and its partial derivatives
//! with respect to the measure slots it reads and to time. The compiled derivative of the
//! IR plugs in here through [`ExprFn`]; [`Interpreted`] gives values through the
//! interpreter alone, and [`Closure`] takes hand-written functions (tests, library users).

use crate::context::Context;
use crate::interp::Program;
use crate::ir::Function;

/// An expression f(t, m) of time and measure slots m.
pub trait ExprFn {
    /// Measure slots read, sorted (the model's slot numbers).
    fn slots(&self) -> &[u32];
    /// f at time `t`; `measures[s]` holds slot s (only the slots read are filled).
    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String>;
    /// Writes ∂f/∂m for each slot of [`ExprFn::slots`] (same order) into `grad` and
    /// returns ∂f/∂t.
    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, String>;
    /// (f, ∂f/∂t), with ∂f/∂slot written into `grad` (one evaluation where the
    /// implementation computes them together).
    fn value_gradient(
        &self,
        t: f64,
        measures: &[f64],
        grad: &mut [f64],
    ) -> Result<(f64, f64), String> {
        let dt = self.gradient(t, measures, grad)?;
        Ok((self.value(t, measures)?, dt))
    }

    /// Whether the expression reads TIME (true unless the implementation knows).
    fn reads_time(&self) -> bool {
        true
    }

    /// The second derivative along the direction `dir` (one entry per slot, in the
    /// order of [`ExprFn::slots`]) with time advancing at rate 1: dᵀ·H·d with
    /// d = (dir, 1) and H the Hessian in (slots, t).
    fn second(&self, _t: f64, _measures: &[f64], _dir: &[f64]) -> Result<f64, String> {
        Err("the second derivative of its FUNCTION is not available".into())
    }
}

/// Values through the interpreter; derivatives are not available until the IR
/// derivative is plugged in.
pub struct Interpreted {
    program: Program,
    slots: Vec<u32>,
    reads_time: bool,
}

impl Interpreted {
    pub fn new(function: Function) -> Self {
        let slots = function.uses.measures.clone();
        let reads_time = function.uses.time;
        Interpreted {
            program: Program::new(function),
            slots,
            reads_time,
        }
    }
}

impl ExprFn for Interpreted {
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn reads_time(&self) -> bool {
        self.reads_time
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String> {
        let x = self
            .program
            .eval(&Context::new(t, &[]).with_measures(measures));
        if x.is_finite() {
            Ok(x)
        } else {
            Err(format!("the FUNCTION evaluates to {x} at time {t}"))
        }
    }

    fn gradient(&self, _: f64, _: &[f64], _: &mut [f64]) -> Result<f64, String> {
        Err(
            "the derivative of its FUNCTION is not available: it needs the compiled IR \
             derivative, which this build does not plug in yet"
                .into(),
        )
    }
}

/// Hand-written value and gradient: `f(t, m)` and `g(t, m, grad) -> ∂f/∂t`, where `m`
/// holds the slots' values in the order of `slots`.
pub struct Closure<F, G> {
    pub slots: Vec<u32>,
    pub f: F,
    pub g: G,
}

impl<F, G> ExprFn for Closure<F, G>
where
    F: Fn(f64, &[f64]) -> f64,
    G: Fn(f64, &[f64], &mut [f64]) -> f64,
{
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String> {
        let m: Vec<f64> = self.slots.iter().map(|&s| measures[s as usize]).collect();
        Ok((self.f)(t, &m))
    }

    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, String> {
        let m: Vec<f64> = self.slots.iter().map(|&s| measures[s as usize]).collect();
        Ok((self.g)(t, &m, grad))
    }
}
