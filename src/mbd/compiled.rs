//! The compiled plug-in for GCON and MOTION expressions: each expression and its
//! forward-mode derivative ([`crate::ir::deriv`]) with respect to the measure slots it
//! reads and to TIME become one function, compiled to machine code by the JIT (or run by
//! the interpreter where the JIT is not available: both give the same bits). The core
//! chains ∂f/∂slot with ∂slot/∂(q, v) itself; no finite differences anywhere.

use super::build::ExprCompiler;
use super::expr::ExprFn;
use crate::context::Context;
use crate::interp::Program;
use crate::ir::deriv::{gradient, Input};
use crate::jit::{CompiledExpr, Jit};
use crate::model::elements::Expr;
use mbfx_runtime::Spline;
use std::cell::RefCell;
use std::sync::Arc;

/// Compiles expressions with their derivatives; one JIT serves them all.
pub struct CompiledExprs {
    jit: RefCell<Option<Jit>>,
    /// The model's SPLINE data, which AKISPL and CUBSPL calls read by slot.
    splines: Arc<[Spline]>,
}

impl CompiledExprs {
    /// Uses the JIT when this CPU supports it, the interpreter otherwise.
    pub fn new() -> Self {
        CompiledExprs {
            jit: RefCell::new(Jit::new().ok()),
            splines: Arc::new([]),
        }
    }

    /// Runs everything through the interpreter.
    pub fn interpreted() -> Self {
        CompiledExprs {
            jit: RefCell::new(None),
            splines: Arc::new([]),
        }
    }

    /// The same compiler with the model's splines (`Model::runtime_splines`) for the
    /// expressions to read.
    pub fn with_splines(mut self, splines: Arc<[Spline]>) -> Self {
        self.splines = splines;
        self
    }
}

impl Default for CompiledExprs {
    fn default() -> Self {
        Self::new()
    }
}

enum Code {
    Jit(CompiledExpr),
    Interp(Box<Program>),
}

/// f and its partials: outputs are f, ∂f/∂slot for each slot read, ∂f/∂t.
struct WithGradient {
    code: Code,
    slots: Vec<u32>,
    reads_time: bool,
    splines: Arc<[Spline]>,
    /// The gradient of the gradient (interpreted: it runs only where consistent
    /// accelerations are solved), or why there is none.
    hessian: Result<Box<Program>, String>,
}

/// An expression whose derivative cannot be generated: values only, and the reason.
struct ValueOnly {
    program: Program,
    slots: Vec<u32>,
    splines: Arc<[Spline]>,
    why: String,
}

impl ExprCompiler for CompiledExprs {
    fn compile(&self, e: &Expr) -> Box<dyn ExprFn> {
        let slots = e.function.uses.measures.clone();
        let wrt: Vec<Input> = slots
            .iter()
            .map(|&s| Input::Measure(s))
            .chain([Input::Time])
            .collect();
        let g = match gradient(&e.function, &wrt) {
            Ok(g) => g,
            Err(err) => {
                return Box::new(ValueOnly {
                    program: Program::new(e.function.clone()),
                    slots,
                    splines: self.splines.clone(),
                    why: format!("the derivative of its FUNCTION is not available: {err}"),
                })
            }
        };
        // The Hessian comes from the function with its piecewise library calls (STEP,
        // STEP5, MIN, MAX, …) lowered to arithmetic and selects, which differentiate
        // twice; other library calls have first-derivative companions only.
        let hessian = gradient(&crate::ir::lower::lower(&e.function), &wrt)
            .and_then(|g1| gradient(&g1, &wrt))
            .map(|h| Box::new(Program::new(h)))
            .map_err(|err| {
                format!("the second derivative of its FUNCTION is not available: {err}")
            });
        let jitted = self
            .jit
            .borrow_mut()
            .as_mut()
            .and_then(|jit| jit.compile(&g).ok());
        let code = match jitted {
            Some(c) => Code::Jit(c),
            None => Code::Interp(Box::new(Program::new(g))),
        };
        Box::new(WithGradient {
            code,
            slots,
            reads_time: e.function.uses.time,
            splines: self.splines.clone(),
            hessian,
        })
    }
}

fn finite(x: f64, t: f64) -> Result<f64, String> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("the FUNCTION evaluates to {x} at time {t}"))
    }
}

impl WithGradient {
    /// Every output at (t, measures): f, the slot partials, ∂f/∂t.
    fn run(&self, t: f64, measures: &[f64]) -> Vec<f64> {
        let ctx = Context::new(t, &[])
            .with_measures(measures)
            .with_splines(&self.splines);
        let mut out = vec![f64::NAN; self.slots.len() + 2];
        match &self.code {
            Code::Jit(c) => c.eval_into(&ctx, &mut out),
            Code::Interp(p) => p.eval_into(&ctx, &mut out),
        }
        out
    }
}

impl ExprFn for WithGradient {
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn reads_time(&self) -> bool {
        self.reads_time
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String> {
        finite(self.run(t, measures)[0], t)
    }

    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, String> {
        let out = self.run(t, measures);
        let n = self.slots.len();
        for (g, &d) in grad.iter_mut().zip(&out[1..=n]) {
            *g = finite(d, t)?;
        }
        finite(out[n + 1], t)
    }

    fn second(&self, t: f64, measures: &[f64], dir: &[f64]) -> Result<f64, String> {
        let h = self.hessian.as_ref().map_err(Clone::clone)?;
        // Inputs x = (slots…, t), k of them; the gradient function has 1 + k outputs and
        // its gradient appends k partials of each: ∂²f/∂xᵢ∂xⱼ at (1 + k) + (1 + i)·k + j.
        let k = self.slots.len() + 1;
        let ctx = Context::new(t, &[])
            .with_measures(measures)
            .with_splines(&self.splines);
        let mut out = vec![f64::NAN; (1 + k) * (1 + k)];
        h.eval_into(&ctx, &mut out);
        let d = |i: usize| if i + 1 == k { 1.0 } else { dir[i] };
        let mut sum = 0.0;
        for i in 0..k {
            for j in 0..k {
                sum += d(i) * out[(1 + k) + (1 + i) * k + j] * d(j);
            }
        }
        finite(sum, t)
    }
}

impl ExprFn for ValueOnly {
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, String> {
        finite(
            self.program.eval(
                &Context::new(t, &[])
                    .with_measures(measures)
                    .with_splines(&self.splines),
            ),
            t,
        )
    }

    fn gradient(&self, _: f64, _: &[f64], _: &mut [f64]) -> Result<f64, String> {
        Err(self.why.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{compile, EveryIdExists, Expect};

    /// Every measure of this scope reads slot 0, which is all these tests need.
    fn expr(text: &str) -> Expr {
        let f = compile(text, &EveryIdExists, Expect::Scalar)
            .expect("valid")
            .function;
        Expr {
            span: 0..text.len(),
            function: f,
        }
    }

    #[test]
    fn distance_constraint_has_its_analytic_gradient() {
        // f = DM² − 4 + 3·TIME: ∂f/∂DM = 2·DM, ∂f/∂t = 3.
        for engine in [CompiledExprs::new(), CompiledExprs::interpreted()] {
            let f = engine.compile(&expr("DM(2,1)**2 - 4 + 3*TIME"));
            assert_eq!(f.slots(), &[0]);
            let mut g = [0.0];
            let dt = f.gradient(0.5, &[1.5], &mut g).unwrap();
            assert_eq!(g, [3.0]);
            assert_eq!(dt, 3.0);
            assert_eq!(f.value(0.5, &[1.5]).unwrap(), 1.5f64 * 1.5 - 4.0 + 1.5);
        }
    }

    #[test]
    fn step_of_time_differentiates_through_the_runtime_companion() {
        // STEP(t, 0, 0, 1, 2) = 2·(3t² − 2t³) on the ramp: d/dt = 2·(6t − 6t²).
        let f = CompiledExprs::new().compile(&expr("STEP(TIME, 0, 0, 1, 2)"));
        let t = 0.25;
        let dt = f.gradient(t, &[], &mut []).unwrap();
        assert!((dt - 2.0 * (6.0 * t - 6.0 * t * t)).abs() < 1e-14);
    }

    #[test]
    fn non_finite_values_are_errors() {
        let f = CompiledExprs::new().compile(&expr("1/(DM(2,1) - 1)"));
        assert!(f.value(0.0, &[1.0]).is_err());
        assert!(f.gradient(0.0, &[1.0], &mut [0.0]).is_err());
    }

    const DATASET: &str = "gcon\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2, QP = 1, 2, 0\n\
        GCON/1, I = 20, FUNCTION = DM(20, 10)**2 - 2*SIN(DX(20, 10)*TIME) + STEP(TIME, 0, 0, 1, 3)\n\
        END\n";

    #[test]
    fn partials_agree_with_central_differences() {
        let read = crate::model::read_model(DATASET);
        assert!(!read.has_errors(), "{:?}", read.diagnostics);
        let f = CompiledExprs::new().compile(&read.model.gcons[0].function);
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
