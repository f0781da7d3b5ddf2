//! The compiled plug-in for a model's expressions (GCON, MOTION, force magnitudes): each
//! expression and its forward-mode derivative ([`crate::ir::deriv`]) with respect to the
//! measure slots it reads and to TIME become one function, compiled to machine code by
//! the JIT (or run by the interpreter where the JIT is not available: both give the same
//! bits). The core chains ∂f/∂slot with ∂slot/∂(q, v) itself; no finite differences
//! anywhere.
//!
//! Compilation is batched: [`CompiledExprs::compile`] only records the function, and the
//! first evaluation compiles everything recorded so far into one JIT module (assembly
//! needs the constraints' code before a run records its forces). Expressions evaluated
//! together at one state are fused into one function ([`crate::ir::fuse`]) as well: the
//! force expressions' values and their partials ([`crate::mbd::forces::ForceSet::fuse`])
//! and the output columns, so one call gives every value. Once a run has recorded every
//! expression of the model (constraints, forces, output columns), [`CompiledExprs::unify`]
//! compiles all of them again into one module, which the run then uses alone. Evaluations write into buffers the function
//! keeps: no allocation per call. A JIT failure is kept ([`CompiledExprs::jit_error`])
//! and the interpreter runs those functions instead.

use super::expr::{ExprCompiler, ExprError, ExprFn, FusedFn};
use crate::context::Context;
use crate::interp::Program;
use crate::ir::deriv::{gradient, hessian, Input};
use crate::jit::{CompiledExpr, Jit};
use crate::model::elements::Expr;
use mbfx_runtime::Spline;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

/// The functions recorded for compilation and the code compiled so far.
struct Batch {
    jit: RefCell<Option<Jit>>,
    /// Every function recorded, by index (kept for [`CompiledExprs::unify`]; empty
    /// without a JIT).
    functions: RefCell<Vec<crate::ir::Function>>,
    /// The indices recorded since the last compilation.
    pending: RefCell<Vec<usize>>,
    /// Machine code by index (None: not compiled, or the JIT failed on its batch).
    code: RefCell<Vec<Option<CompiledExpr>>>,
    error: RefCell<Option<crate::jit::JitError>>,
    /// How many modules the functions in `code` live in.
    modules: std::cell::Cell<usize>,
    /// The index of the first function recorded with each value (`{:?}`, constants to
    /// the bit): a function recorded again once that one is compiled takes its code.
    seen: RefCell<std::collections::HashMap<String, usize>>,
}

impl Batch {
    /// Records `g` and returns its index. A function recorded and compiled before (a
    /// model rebuilt after a command file changed it: every expression that did not
    /// change) takes that code and is not compiled again.
    fn record(&self, g: crate::ir::Function) -> usize {
        let mut code = self.code.borrow_mut();
        code.push(None);
        let index = code.len() - 1;
        if self.jit.borrow().is_some() {
            let key = format!("{g:?}");
            let first = *self.seen.borrow_mut().entry(key).or_insert(index);
            match code[first].clone() {
                Some(compiled) if first != index => code[index] = Some(compiled),
                _ => self.pending.borrow_mut().push(index),
            }
            self.functions.borrow_mut().push(g);
        }
        index
    }

    /// Compiles every pending function in one module.
    fn flush(&self) {
        if self.pending.borrow().is_empty() {
            return;
        }
        let pending = std::mem::take(&mut *self.pending.borrow_mut());
        self.compile(&pending);
    }

    /// Compiles the functions `indices` into one new module and points their code at it;
    /// the same functions compiled before on this thread reuse that module's code.
    fn compile(&self, indices: &[usize]) {
        let mut jit = self.jit.borrow_mut();
        let Some(jit) = jit.as_mut() else { return };
        let functions = self.functions.borrow();
        let fs: Vec<&crate::ir::Function> = indices.iter().map(|&i| &functions[i]).collect();
        match code_cache::compiled(jit, &fs) {
            Ok(compiled) => {
                let mut code = self.code.borrow_mut();
                for (&i, c) in indices.iter().zip(compiled) {
                    code[i] = Some(c);
                }
                // A module lives while one of its functions does.
                let live: std::collections::HashSet<*const ()> =
                    code.iter().flatten().map(CompiledExpr::module_id).collect();
                self.modules.set(live.len());
            }
            Err(e) => *self.error.borrow_mut() = Some(e),
        }
    }
}

/// Machine code of the batches this thread compiled, by their functions: a model built
/// again with other statement values (a study's variant that moves a marker) has the same
/// expressions, and takes their code instead of compiling it again.
mod code_cache {
    use crate::ir::Function;
    use crate::jit::{CompiledExpr, Jit, JitError};
    use std::cell::RefCell;
    use std::collections::HashMap;

    /// Batches kept before the cache starts again (each holds its module's code).
    const KEEP: usize = 16;

    thread_local! {
        static CODE: RefCell<HashMap<String, Vec<CompiledExpr>>> = RefCell::new(HashMap::new());
    }

    /// The code of `fs`, compiled by `jit` unless this thread holds it.
    pub(super) fn compiled(jit: &mut Jit, fs: &[&Function]) -> Result<Vec<CompiledExpr>, JitError> {
        // The functions' whole value, constants to the bit (`{:?}` of an f64 round-trips
        // and tells -0.0 from 0.0): equal keys are the same code.
        let key = format!("{fs:?}");
        if let Some(code) = CODE.with(|c| c.borrow().get(&key).cloned()) {
            return Ok(code);
        }
        let code = jit.compile_batch(fs)?;
        CODE.with(|c| {
            let mut c = c.borrow_mut();
            if c.len() >= KEEP {
                c.clear();
            }
            c.insert(key, code.clone());
        });
        Ok(code)
    }
}

/// Compiles expressions with their derivatives; one JIT serves them all. A clone shares
/// the batch.
#[derive(Clone)]
pub struct CompiledExprs {
    batch: Rc<Batch>,
    /// The model's SPLINE data, which AKISPL and CUBSPL calls read by slot.
    splines: Arc<[Spline]>,
}

impl CompiledExprs {
    /// Uses the JIT when this CPU supports it, the interpreter otherwise.
    pub fn new() -> Self {
        Self::with_jit(Jit::new().ok())
    }

    /// Runs everything through the interpreter.
    pub fn interpreted() -> Self {
        Self::with_jit(None)
    }

    fn with_jit(jit: Option<Jit>) -> Self {
        CompiledExprs {
            batch: Rc::new(Batch {
                jit: RefCell::new(jit),
                functions: RefCell::new(Vec::new()),
                pending: RefCell::new(Vec::new()),
                code: RefCell::new(Vec::new()),
                error: RefCell::new(None),
                modules: std::cell::Cell::new(0),
                seen: RefCell::new(std::collections::HashMap::new()),
            }),
            splines: Arc::new([]),
        }
    }

    /// Why the JIT could not compile a batch (its functions run in the interpreter).
    pub fn jit_error(&self) -> Option<String> {
        self.batch.error.borrow().as_ref().map(ToString::to_string)
    }

    /// Compiles every function recorded so far into one JIT module, replacing the code
    /// of earlier batches (whose modules are freed with their last function).
    pub fn unify(&self) {
        let all: Vec<usize> = (0..self.batch.functions.borrow().len()).collect();
        self.batch.pending.borrow_mut().clear();
        if !all.is_empty() {
            self.batch.compile(&all);
        }
    }

    /// How many JIT modules hold the compiled functions (0 without a JIT).
    pub fn modules(&self) -> usize {
        self.batch.modules.get()
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

/// f and its partials: outputs are f, ∂f/∂slot for each slot read, ∂f/∂t. (The
/// evaluations a state makes of many expressions at once go through fused functions,
/// [`FusedFn`]; one expression alone takes its value from the same function.)
struct WithGradient {
    batch: Rc<Batch>,
    /// Its place in the batch.
    index: usize,
    /// The same function for the interpreter (the interpreted engine, or a JIT failure).
    program: Box<Program>,
    /// f, the slot partials, ∂f/∂t of the last evaluation.
    out: RefCell<Vec<f64>>,
    slots: Vec<u32>,
    reads_time: bool,
    splines: Arc<[Spline]>,
    /// The gradient of the gradient (interpreted: it runs only where consistent
    /// accelerations are solved), or why there is none.
    hessian: Result<Box<Program>, String>,
}

/// Several expressions' values from one function of the batch ([`crate::ir::fuse`]).
struct Fused {
    batch: Rc<Batch>,
    index: usize,
    /// The interpreter's form (the interpreted engine, or a JIT failure).
    program: Program,
    splines: Arc<[Spline]>,
}

impl FusedFn for Fused {
    fn eval_into(&self, t: f64, measures: &[f64], out: &mut [f64]) {
        let ctx = Context::new(t, &[])
            .with_measures(measures)
            .with_splines(&self.splines);
        self.batch.flush();
        match &self.batch.code.borrow()[self.index] {
            Some(c) => c.eval_into(&ctx, out),
            None => self.program.eval_into(&ctx, out),
        }
    }
}

/// An expression whose derivative cannot be generated: values only, and the reason.
struct ValueOnly {
    program: Program,
    slots: Vec<u32>,
    splines: Arc<[Spline]>,
    why: String,
}

impl ExprCompiler for CompiledExprs {
    fn fuse(&self, functions: &[&crate::ir::Function]) -> Option<Box<dyn FusedFn>> {
        let fused = crate::ir::fuse::fuse(functions);
        Some(Box::new(Fused {
            program: Program::new(fused.clone()),
            index: self.batch.record(fused),
            batch: self.batch.clone(),
            splines: self.splines.clone(),
        }))
    }

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
        // The Hessian: lowered, differentiated, the library partials written out as IR
        // and differentiated again (`ir::deriv::hessian`).
        let hessian = hessian(&e.function, &wrt)
            .map(|h| Box::new(Program::new(h)))
            .map_err(|err| {
                format!("the second derivative of its FUNCTION is not available: {err}")
            });
        let outputs = slots.len() + 2;
        let program = Box::new(Program::new(g.clone()));
        let index = self.batch.record(g);
        Box::new(WithGradient {
            batch: self.batch.clone(),
            index,
            program,
            out: RefCell::new(vec![f64::NAN; outputs]),
            slots,
            reads_time: e.function.uses.time,
            splines: self.splines.clone(),
            hessian,
        })
    }
}

/// From the outputs (f, ∂f/∂slot for `n` slots, ∂f/∂t): writes the slot partials into
/// `grad` and returns ∂f/∂t, each checked finite.
fn partials(out: &[f64], n: usize, t: f64, grad: &mut [f64]) -> Result<f64, ExprError> {
    for (g, &d) in grad.iter_mut().zip(&out[1..=n]) {
        *g = finite(d, t)?;
    }
    finite(out[n + 1], t)
}

fn finite(x: f64, t: f64) -> Result<f64, ExprError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(ExprError::NotFinite { value: x, time: t })
    }
}

impl WithGradient {
    /// Every output at (t, measures) into `self.out`: f, the slot partials, ∂f/∂t.
    fn run(&self, t: f64, measures: &[f64]) -> std::cell::Ref<'_, Vec<f64>> {
        let ctx = Context::new(t, &[])
            .with_measures(measures)
            .with_splines(&self.splines);
        self.batch.flush();
        {
            let mut out = self.out.borrow_mut();
            match &self.batch.code.borrow()[self.index] {
                Some(c) => c.eval_into(&ctx, &mut out),
                None => self.program.eval_into(&ctx, &mut out),
            }
        }
        self.out.borrow()
    }
}

impl ExprFn for WithGradient {
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn reads_time(&self) -> bool {
        self.reads_time
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, ExprError> {
        finite(self.run(t, measures)[0], t)
    }

    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, ExprError> {
        partials(&self.run(t, measures), self.slots.len(), t, grad)
    }

    fn value_gradient(
        &self,
        t: f64,
        measures: &[f64],
        grad: &mut [f64],
    ) -> Result<(f64, f64), ExprError> {
        let out = self.run(t, measures);
        let dt = partials(&out, self.slots.len(), t, grad)?;
        Ok((finite(out[0], t)?, dt))
    }

    fn second(&self, t: f64, measures: &[f64], dir: &[f64]) -> Result<f64, ExprError> {
        let h = (self.hessian.as_ref()).map_err(|why| ExprError::NoDerivative(why.clone()))?;
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

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, ExprError> {
        finite(
            self.program.eval(
                &Context::new(t, &[])
                    .with_measures(measures)
                    .with_splines(&self.splines),
            ),
            t,
        )
    }

    fn gradient(&self, _: f64, _: &[f64], _: &mut [f64]) -> Result<f64, ExprError> {
        Err(ExprError::NoDerivative(self.why.clone()))
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

    /// The module of the code of function `k` of `e`, once compiled.
    fn module_of(e: &CompiledExprs, k: usize) -> *const () {
        e.batch.code.borrow()[k]
            .as_ref()
            .map(CompiledExpr::module_id)
            .expect("compiled")
    }

    #[test]
    fn the_same_functions_take_the_code_compiled_before_on_the_thread() {
        let text = "DM(2,1)**2 - 4 + 3.25*TIME";
        let (a, b, c) = (
            CompiledExprs::new(),
            CompiledExprs::new(),
            CompiledExprs::new(),
        );
        let fa = a.compile(&expr(text));
        let fb = b.compile(&expr(text));
        // -3.25 differs from 3.25 in one bit of one constant: other code.
        let fc = c.compile(&expr("DM(2,1)**2 - 4 + -3.25*TIME"));
        assert_eq!(fa.value(1.0, &[1.5]).unwrap(), 1.5f64 * 1.5 - 4.0 + 3.25);
        assert_eq!(fb.value(1.0, &[1.5]).unwrap(), 1.5f64 * 1.5 - 4.0 + 3.25);
        assert_eq!(fc.value(1.0, &[1.5]).unwrap(), 1.5f64 * 1.5 - 4.0 - 3.25);
        assert_eq!(module_of(&a, 0), module_of(&b, 0));
        assert_ne!(module_of(&a, 0), module_of(&c, 0));
    }

    #[test]
    fn a_function_recorded_again_takes_the_code_compiled_for_it() {
        let e = CompiledExprs::new();
        let f = e.compile(&expr("DM(2,1)**2 + 5.5*TIME"));
        assert_eq!(f.value(1.0, &[2.0]).unwrap(), 9.5);
        // Compiled: the same function again is not; another one is.
        let again = e.compile(&expr("DM(2,1)**2 + 5.5*TIME"));
        let other = e.compile(&expr("DM(2,1)**2 + 6.5*TIME"));
        if e.batch.jit.borrow().is_some() {
            assert!(e.batch.code.borrow()[1].is_some());
            assert_eq!(*e.batch.pending.borrow(), [2]);
        }
        assert_eq!(again.value(1.0, &[2.0]).unwrap(), 9.5);
        assert_eq!(other.value(1.0, &[2.0]).unwrap(), 10.5);
        if e.batch.jit.borrow().is_some() {
            assert_eq!(module_of(&e, 0), module_of(&e, 1));
            assert_ne!(module_of(&e, 0), module_of(&e, 2));
        }
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
