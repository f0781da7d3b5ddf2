//! Expressions with derivatives by central differences: the [`ExprCompiler`] the whole
//! model pipeline ([`super`]) uses for GCON and MOTION functions. Values come
//! from the interpreter; ∂f/∂slot and ∂f/∂t are central differences with a step of
//! ∛ε·max(1, |x|), which balances truncation (h²·f‴/6) against rounding (ε·|f|/h): about
//! 1e-10 relative on smooth functions, far below the assembly and redundancy tolerances.
//! The IR derivative (`ir::deriv`, exact) replaces this once it is on this branch.

use crate::mbd::build::ExprCompiler;
use crate::mbd::expr::{ExprFn, Interpreted};
use crate::model::elements::Expr;

/// An interpreted expression differentiated numerically.
pub struct Differenced(Interpreted);

/// Compiles every expression into a [`Differenced`].
pub struct CentralDifferences;

impl ExprCompiler for CentralDifferences {
    fn compile(&self, e: &Expr) -> Box<dyn ExprFn> {
        Box::new(Differenced(Interpreted::new(e.function.clone())))
    }
}

fn step(x: f64) -> f64 {
    f64::EPSILON.cbrt() * x.abs().max(1.0)
}

impl ExprFn for Differenced {
    fn slots(&self) -> &[u32] {
        self.0.slots()
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String> {
        self.0.value(t, measures)
    }

    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, String> {
        let mut m = measures.to_vec();
        for (g, &s) in grad.iter_mut().zip(self.0.slots()) {
            let s = s as usize;
            let x = m[s];
            let h = step(x);
            m[s] = x + h;
            let up = self.0.value(t, &m)?;
            m[s] = x - h;
            let down = self.0.value(t, &m)?;
            m[s] = x;
            *g = (up - down) / (2.0 * h);
        }
        let h = step(t);
        Ok((self.0.value(t + h, &m)? - self.0.value(t - h, &m)?) / (2.0 * h))
    }
}
