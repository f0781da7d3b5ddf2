//! Partial derivatives of an expression, generated as IR (forward mode).
//!
//! [`gradient`] rebuilds a function together with the tangent of every value with respect
//! to each chosen [`Input`], and returns one function whose outputs are the values, then
//! the partials. Library calls differentiate through the runtime's analytic derivative
//! companions ([`Inst::Partial`] → `mbfx_<name>_grad`); `+ − × ÷ √` by the usual rules.
//! The result is ordinary IR: both back ends run it, and the JIT compiles value and
//! gradient into one function.
//!
//! Kinks take the derivative of the active branch: an IF's partials are those of the arm
//! its test selects (the test itself contributes nothing), a [`Inst::Select`] passes on
//! the tangent of the value it picks, and MIN, MAX, ABS, DIM, SIGN, STEP's ends, IMPACT's
//! and BISTOP's contact edges follow the companions' documented branch choices. An IF
//! whose test is NaN gives NaN for the value and every partial.
//!
//! Second derivatives ([`hessian`]): the function is lowered first (STEP, MIN, … become
//! arithmetic), then differentiated with the companions' partials written out as IR
//! (`expand`), and differentiated again.

mod expand;
#[cfg(test)]
mod tests;

use super::builder::{Arith, Builder};
use super::rebuild::{constants, copy, UNSET};
use super::{Function, Inst, Value};
use crate::diag::Span;
use crate::vocab::func::Func;
use rustc_hash::FxHashMap;

/// What a partial derivative is taken with respect to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Input {
    /// User variable slot `n` ([`Inst::Var`]).
    Var(u32),
    /// Measure slot `n` ([`Inst::Measure`]); the multibody core chains ∂expr/∂measure with
    /// ∂measure/∂q itself.
    Measure(u32),
    /// `TIME`.
    Time,
}

/// Why a derivative could not be generated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DerivError {
    /// A second derivative of this library function is needed: of an [`Inst::Partial`]
    /// (which [`gradient`] cannot differentiate), or in [`hessian`], where mbfx has no
    /// formula for its partials.
    SecondOrder(Func),
    /// A spline's third derivative in x, or its derivative in z, is needed.
    Spline,
}

impl std::fmt::Display for DerivError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DerivError::SecondOrder(func) => {
                write!(f, "mbfx has no second derivative of {}", func_name(*func))
            }
            DerivError::Spline => f.write_str(
                "a spline is differentiated at most twice, and only in x (AKISPL/CUBSPL iord 0 to 2)",
            ),
        }
    }
}

/// The Adams name of a library function (`**` for the power operator).
pub fn func_name(func: Func) -> String {
    match func {
        Func::Pow | Func::PowLibm => "**".into(),
        _ => func.symbol().trim_start_matches("mbfx_").to_uppercase(),
    }
}

/// `f`'s second partials with respect to `wrt` (k inputs): the outputs of
/// [`gradient`]`(gradient(f))`, so for a scalar f, ∂²f/∂xᵢ∂xⱼ is output
/// `(1 + k) + (1 + i)·k + j`. Fails naming the library function whose second derivative
/// mbfx does not have (SWEEP in arguments other than x and its amplitude). Every IMPACT
/// and BISTOP is written out first ([`super::lower::lower_all_contacts`]), those with
/// varying parameters too.
pub fn hessian(f: &Function, wrt: &[Input]) -> Result<Function, DerivError> {
    let g = differentiate(&super::lower::lower_all_contacts(f), wrt, true)?;
    gradient(&g, wrt)
}

/// A tangent known to be zero (never emitted).
const ZERO: Value = Value::MAX - 1;

/// `f` and its partials with respect to `wrt`: outputs are f's outputs, then for each
/// output in order its partials in `wrt` order (`n + n·k` outputs).
pub fn gradient(f: &Function, wrt: &[Input]) -> Result<Function, DerivError> {
    differentiate(f, wrt, false)
}

/// [`gradient`], with library partials from the companions ([`Inst::Partial`]) or, when
/// `written_out`, as IR that can be differentiated again.
fn differentiate(f: &Function, wrt: &[Input], written_out: bool) -> Result<Function, DerivError> {
    let mut b = Builder::new();
    let m = constants(f, &mut b, None);
    let k = wrt.len();
    let mut d = Diff {
        f,
        wrt,
        k,
        m,
        t: vec![ZERO; f.insts.len() * k],
        ifs: FxHashMap::default(),
        b,
        written_out,
    };
    d.list(&f.body)?;
    let mut outputs: Vec<Value> = f.outputs.iter().map(|&o| d.m[o as usize]).collect();
    for &o in &f.outputs {
        for i in 0..k {
            let t = d.tangent(o, i);
            outputs.push(d.materialize(t, f.spans[o as usize].clone()));
        }
    }
    Ok(d.b.finish(&outputs))
}

struct Diff<'f> {
    f: &'f Function,
    wrt: &'f [Input],
    k: usize,
    /// New value of each old value.
    m: Vec<Value>,
    /// Tangent `i` of old value `v` at `t[v * k + i]` (new value, or ZERO).
    t: Vec<Value>,
    /// New results of each old IF: value, extras, then tangents of each (see `if_`).
    ifs: FxHashMap<Value, Vec<Value>>,
    b: Builder,
    /// Library partials as IR (`expand`) rather than [`Inst::Partial`].
    written_out: bool,
}

impl Diff<'_> {
    fn tangent(&self, v: Value, i: usize) -> Value {
        self.t[v as usize * self.k + i]
    }

    fn materialize(&mut self, t: Value, span: Span) -> Value {
        if t == ZERO {
            self.b.constant(0.0, span)
        } else {
            t
        }
    }

    fn list(&mut self, values: &[Value]) -> Result<(), DerivError> {
        for &v in values {
            self.inst(v)?;
        }
        Ok(())
    }

    fn inst(&mut self, v: Value) -> Result<(), DerivError> {
        let f = self.f;
        let span = f.spans[v as usize].clone();
        let inst = f.inst(v);
        let (k, at) = (self.k, v as usize * self.k);
        match inst {
            Inst::If { test, arms } => return self.if_(v, *test, arms, span),
            Inst::IfExtra { of, index } => {
                let r = self.ifs.get(of).cloned().unwrap_or_default();
                let n = arms_results(f, *of);
                let slot = 1 + *index as usize;
                self.m[v as usize] = r.get(slot).copied().unwrap_or(UNSET);
                for i in 0..k {
                    self.t[at + i] = r.get(n + slot * k + i).copied().unwrap_or(ZERO);
                }
                return Ok(());
            }
            Inst::Partial { func, .. } => return Err(DerivError::SecondOrder(*func)),
            _ => {}
        }
        let new = copy(&mut self.b, inst, span.clone(), &self.m);
        self.m[v as usize] = new;
        let seed = |input: Input| {
            let hit = |i: usize| self.wrt[i] == input;
            (0..k).map(hit).collect::<Vec<bool>>()
        };
        let g = |me: &Self, a: &Value, i: usize| me.tangent(*a, i);
        for i in 0..k {
            let t = match inst {
                Inst::Var(s) => self.one_if(seed(Input::Var(*s))[i], &span),
                Inst::Measure(s) => self.one_if(seed(Input::Measure(*s))[i], &span),
                Inst::Time => self.one_if(seed(Input::Time)[i], &span),
                Inst::Const(_) | Inst::Mode => ZERO,
                Inst::Neg(a) => self.neg(g(self, a, i), &span),
                Inst::Add(x, y) => {
                    let (tx, ty) = (g(self, x, i), g(self, y, i));
                    self.add(tx, ty, &span)
                }
                Inst::Sub(x, y) => {
                    let (tx, ty) = (g(self, x, i), g(self, y, i));
                    let nty = self.neg(ty, &span);
                    match (tx, ty) {
                        (_, ZERO) => tx,
                        (ZERO, _) => nty,
                        _ => self.arith(Arith::Sub, tx, ty, &span),
                    }
                }
                Inst::Mul(x, y) => {
                    let (tx, ty) = (g(self, x, i), g(self, y, i));
                    let (nx, ny) = (self.m[*x as usize], self.m[*y as usize]);
                    let a = self.scale(tx, ny, &span);
                    let b = self.scale(ty, nx, &span);
                    self.add(a, b, &span)
                }
                Inst::Div(x, y) => {
                    // (tx − q·ty) / y with q = x / y, the value itself.
                    let (tx, ty) = (g(self, x, i), g(self, y, i));
                    let ny = self.m[*y as usize];
                    let qty = self.scale(ty, new, &span);
                    let num = match (tx, qty) {
                        (_, ZERO) => tx,
                        (ZERO, _) => self.neg(qty, &span),
                        _ => self.arith(Arith::Sub, tx, qty, &span),
                    };
                    if num == ZERO {
                        ZERO
                    } else {
                        self.arith(Arith::Div, num, ny, &span)
                    }
                }
                Inst::Sqrt(a) => {
                    // d√a = ta · (0.5 / √a), the companion's formula.
                    let ta = g(self, a, i);
                    if ta == ZERO {
                        ZERO
                    } else {
                        let half = self.b.constant(0.5, span.clone());
                        let r = self.arith(Arith::Div, half, new, &span);
                        self.arith(Arith::Mul, ta, r, &span)
                    }
                }
                Inst::Call(func, args) => {
                    let new_args: Vec<Value> = args.iter().map(|&a| self.m[a as usize]).collect();
                    let mut sum = ZERO;
                    for (j, a) in args.iter().enumerate() {
                        let ta = g(self, a, i);
                        if ta != ZERO {
                            let p = if self.written_out {
                                let (b, at) = (&mut self.b, span.clone());
                                expand::partial(b, *func, j as u32, &new_args, at)?
                            } else {
                                self.b.partial(*func, j as u32, &new_args, span.clone())
                            };
                            let term = self.scale(ta, p, &span);
                            sum = self.add(sum, term, &span);
                        }
                    }
                    sum
                }
                Inst::Spline {
                    kind,
                    x,
                    z,
                    spline,
                    iord,
                } => {
                    let (tx, tz) = (g(self, x, i), g(self, z, i));
                    if tz != ZERO || (tx != ZERO && *iord >= 2) {
                        return Err(DerivError::Spline);
                    }
                    if tx == ZERO {
                        ZERO
                    } else {
                        let (nx, nz) = (self.m[*x as usize], self.m[*z as usize]);
                        let dv = self
                            .b
                            .spline(*kind, nx, nz, *spline, iord + 1, span.clone());
                        self.scale(tx, dv, &span)
                    }
                }
                Inst::Select {
                    cmp,
                    a,
                    b,
                    then,
                    otherwise,
                } => {
                    let (tt, to) = (g(self, then, i), g(self, otherwise, i));
                    if tt == ZERO && to == ZERO {
                        ZERO
                    } else {
                        let tt = self.materialize(tt, span.clone());
                        let to = self.materialize(to, span.clone());
                        let (na, nb) = (self.m[*a as usize], self.m[*b as usize]);
                        self.b.select(*cmp, na, nb, tt, to, span.clone())
                    }
                }
                Inst::If { .. } | Inst::IfExtra { .. } | Inst::Partial { .. } => ZERO,
            };
            self.t[at + i] = t;
        }
        Ok(())
    }

    /// An IF yielding, per arm: the value, the old extras, then the tangents of the value
    /// and of each extra (k each).
    fn if_(
        &mut self,
        v: Value,
        test: Value,
        arms: &[super::Block; 3],
        span: Span,
    ) -> Result<(), DerivError> {
        let k = self.k;
        let mut new_arms = Vec::with_capacity(3);
        for arm in arms.iter() {
            self.b.begin_block();
            self.list(&arm.insts)?;
            let olds: Vec<Value> = std::iter::once(arm.result)
                .chain(arm.extra.iter().copied())
                .collect();
            let mut results: Vec<Value> = olds.iter().map(|&o| self.m[o as usize]).collect();
            for &o in &olds {
                for i in 0..k {
                    let t = self.tangent(o, i);
                    results.push(self.materialize(t, span.clone()));
                }
            }
            new_arms.push(self.b.end_block_multi(&results));
        }
        let [a0, a1, a2]: [super::Block; 3] = new_arms.try_into().unwrap_or_default();
        let results = self.b.if_multi(self.m[test as usize], [a0, a1, a2], span);
        let n = arms[0].extra.len() + 1;
        self.m[v as usize] = results[0];
        for i in 0..k {
            self.t[v as usize * k + i] = results.get(n + i).copied().unwrap_or(ZERO);
        }
        self.ifs.insert(v, results);
        Ok(())
    }

    fn one_if(&mut self, hit: bool, span: &Span) -> Value {
        if hit {
            self.b.constant(1.0, span.clone())
        } else {
            ZERO
        }
    }

    fn arith(&mut self, op: Arith, a: Value, b: Value, span: &Span) -> Value {
        self.b.arith(op, a, b, span.clone())
    }

    fn neg(&mut self, t: Value, span: &Span) -> Value {
        if t == ZERO {
            ZERO
        } else {
            self.b.neg(t, span.clone())
        }
    }

    fn add(&mut self, a: Value, b: Value, span: &Span) -> Value {
        match (a, b) {
            (ZERO, _) => b,
            (_, ZERO) => a,
            _ => self.arith(Arith::Add, a, b, span),
        }
    }

    /// `t · x`, with a zero tangent staying zero and a unit tangent giving x.
    fn scale(&mut self, t: Value, x: Value, span: &Span) -> Value {
        if t == ZERO {
            return ZERO;
        }
        if self.b.get_const(t) == Some(1.0) {
            return x;
        }
        self.arith(Arith::Mul, t, x, span)
    }
}

/// Number of results (value and extras) of the IF `of`.
fn arms_results(f: &Function, of: Value) -> usize {
    match f.inst(of) {
        Inst::If { arms, .. } => arms[0].extra.len() + 1,
        _ => 1,
    }
}
