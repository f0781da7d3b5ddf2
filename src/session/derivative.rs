//! GCON and MOTION functions with exact derivatives: the [`ExprCompiler`] the session
//! hands the multibody core. The value runs through the interpreter; ∂f/∂measure (for
//! each measure slot the function reads) and ∂f/∂t come from one IR function built by
//! [`gradient`] (forward mode on the IR, DESIGN.md "Derivatives") and run by the
//! interpreter too. A function the IR derivative cannot handle (a spline differentiated
//! twice) still gives values; asking for its derivative gives the reason.

use crate::context::Context;
use crate::interp::Program;
use crate::ir::deriv::{gradient, Input};
use crate::mbd::build::ExprCompiler;
use crate::mbd::expr::{ExprFn, Interpreted};
use crate::model::elements::Expr;

/// Compiles every expression into a [`Derived`].
pub struct IrDerivatives;

impl ExprCompiler for IrDerivatives {
    fn compile(&self, e: &Expr) -> Box<dyn ExprFn> {
        Box::new(Derived::new(&e.function))
    }
}

/// An expression with its value program and its gradient program.
pub struct Derived {
    value: Interpreted,
    /// Outputs: the n values, then for each the partials in (slots…, time) order.
    gradient: Result<Program, String>,
    outputs: usize,
    slots: Vec<u32>,
}

impl Derived {
    pub fn new(f: &crate::ir::Function) -> Self {
        let slots = f.uses.measures.clone();
        let wrt: Vec<Input> = slots
            .iter()
            .map(|&s| Input::Measure(s))
            .chain([Input::Time])
            .collect();
        Derived {
            value: Interpreted::new(f.clone()),
            gradient: gradient(f, &wrt)
                .map(Program::new)
                .map_err(|e| e.to_string()),
            outputs: f.outputs.len(),
            slots,
        }
    }
}

impl ExprFn for Derived {
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String> {
        self.value.value(t, measures)
    }

    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, String> {
        let program = self
            .gradient
            .as_ref()
            .map_err(|e| format!("the derivative of its FUNCTION is not available: {e}"))?;
        let (n, k) = (self.outputs, self.slots.len());
        let mut out = vec![0.0; n + n * (k + 1)];
        program.eval_into(&Context::new(t, &[]).with_measures(measures), &mut out);
        // The first output's partials: slots, then time.
        let partials = &out[n..n + k + 1];
        if let Some(x) = partials.iter().find(|x| !x.is_finite()) {
            return Err(format!("the derivative of its FUNCTION is {x} at time {t}"));
        }
        grad.copy_from_slice(&partials[..k]);
        Ok(partials[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DATASET: &str = "gcon\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2, QP = 1, 2, 0\n\
        GCON/1, I = 20, FUNCTION = DM(20, 10)**2 - 2*SIN(DX(20, 10)*TIME) + STEP(TIME, 0, 0, 1, 3)\n\
        END\n";

    #[test]
    fn partials_agree_with_central_differences() {
        let read = crate::model::read_model(DATASET);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let f = IrDerivatives.compile(&read.model.gcons[0].function);
        let slots = f.slots().to_vec();
        assert_eq!(slots.len(), 2);
        let mut m = vec![0.0; read.model.measures.len()];
        for (x, &s) in [2.3, 0.7].iter().zip(&slots) {
            m[s as usize] = *x;
        }
        let t = 0.4;
        let mut grad = vec![0.0; slots.len()];
        let dt = f.gradient(t, &m, &mut grad).unwrap();
        // Oracle: central differences of the value.
        let h = 1e-6;
        for (g, &s) in grad.iter().zip(&slots) {
            let (mut up, mut down) = (m.clone(), m.clone());
            up[s as usize] += h;
            down[s as usize] -= h;
            let fd = (f.value(t, &up).unwrap() - f.value(t, &down).unwrap()) / (2.0 * h);
            assert!((g - fd).abs() < 1e-7, "slot {s}: {g} vs {fd}");
        }
        let fd = (f.value(t + h, &m).unwrap() - f.value(t - h, &m).unwrap()) / (2.0 * h);
        assert!((dt - fd).abs() < 1e-7, "time: {dt} vs {fd}");
    }
}
