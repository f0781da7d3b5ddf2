//! Branch-free lowering of the cheap library functions, for the JIT.
//!
//! [`lower`] rebuilds a function with MIN, MAX, DIM, SIGN, STEP, STEP5, HAVSIN and POLY
//! replaced by IEEE arithmetic and [`Inst::Select`]s (every row of the piecewise
//! definition is computed, then chosen), so the machine code has no data-dependent jumps
//! for them. IMPACT and BISTOP with constant, valid parameters (the usual case) become an
//! arithmetic IF on `x - x1` (and `x - x2`): the contact arm calls `pow` and computes the
//! damping STEP and the clamp with selects; out of contact nothing but a NaN check of ẋ
//! runs. A fully branch-free form (pow and both damping steps on every evaluation)
//! measured slower than branching, even on unpredictable inputs; with other parameters
//! they stay runtime calls. Each lowering follows the operation order documented in
//! `mbfx-runtime` exactly, so it gives the runtime's bits (NaN payloads aside); the
//! interpreter keeps calling the runtime, so the interpreter ≡ JIT tests check every
//! lowering against the runtime itself. Transcendentals (`pow`, `sin`) stay calls; ABS
//! stays a call the JIT inlines as one instruction.
//!
//! The contact branches cost Cranelift far more to compile than a call (about 45 machine
//! instructions and four blocks each, against one call): a function with more than
//! [`CONTACT_INLINE_LIMIT`] IMPACT/BISTOP calls keeps them all as runtime calls, so
//! compile time and memory stay proportional to the expression (a sum of 3 000 IMPACTs
//! compiled in 0.9 s and 157 MB with every contact lowered, 0.08 s and 32 MB as calls).
//! Up to the limit each saves about 10 ns per evaluation in contact.
//!
//! An arithmetic IF whose arms are all cheap call-free arithmetic (at most
//! `SPECULATE_LIMIT` instructions together) is if-converted: every arm runs and selects
//! pick the result, as an optimising compiler speculates a cheap branch. Nothing can tell:
//! IEEE arithmetic has no side effects or traps, and the selects give exactly the picked
//! arm's bits (NaN for a NaN test). Random tests mispredict a branch about half the time
//! (measured on if3 of `shared/bench/expressions.md`, random inputs: 10.4 ns as branches,
//! 5.7 ns if-converted; on sorted inputs native branches take 3.0 ns and the
//! if-converted code still 5.7); an arm with a call, such as `IF(x: LOG(x), 0, 5)`, keeps its branches and stays
//! lazy.

use super::builder::{Arith, Builder};
use super::rebuild::{constants, copy, copy_if, if_extra};
use super::{Cmp, Function, Inst, Value};
use crate::diag::Span;
use crate::vocab::func::Func;
use core::f64::consts::{FRAC_PI_2, PI};
use rustc_hash::FxHashMap;

/// The function with its cheap library calls lowered to branch-free IR.
pub fn lower(f: &Function) -> Function {
    let count = f
        .insts
        .iter()
        .filter(|i| matches!(i, Inst::Call(Func::Impact | Func::Bistop, _)))
        .count();
    let contacts = match count <= CONTACT_INLINE_LIMIT {
        true => Contacts::Constant,
        false => Contacts::Calls,
    };
    lower_with(f, contacts)
}

/// [`lower`] for a function that will be differentiated twice
/// ([`super::deriv::hessian`]): every IMPACT and BISTOP is written out, those whose
/// parameters vary too, guarded to be NaN where the runtime's parameter check refuses
/// (k < 0, e ≤ 0, CMAX < 0, d ≤ 0, an edge not finite, x1 ≥ x2), so the second pass
/// differentiates their arithmetic.
pub fn lower_all_contacts(f: &Function) -> Function {
    lower_with(f, Contacts::All)
}

/// What the lowering does with IMPACT and BISTOP calls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Contacts {
    /// Keep them runtime calls.
    Calls,
    /// Write out those with constant, valid parameters.
    Constant,
    /// Write out every one (parameters that vary are checked by selects).
    All,
}

/// [`lower`] with IMPACT and BISTOP treated as `contacts` says.
pub fn lower_with(f: &Function, contacts: Contacts) -> Function {
    let mut b = Builder::new();
    let mut m = constants(f, &mut b, None);
    let mut ifs = FxHashMap::default();
    list(f, &mut b, &mut m, &mut ifs, contacts, &f.body);
    let outputs: Vec<Value> = f.outputs.iter().map(|&o| m[o as usize]).collect();
    b.finish(&outputs)
}

fn list(
    f: &Function,
    b: &mut Builder,
    m: &mut [Value],
    ifs: &mut FxHashMap<Value, Vec<Value>>,
    contact: Contacts,
    values: &[Value],
) {
    for &v in values {
        let span = f.spans[v as usize].clone();
        let new = match f.inst(v) {
            Inst::Call(func, args) => {
                let args: Vec<Value> = args.iter().map(|&a| m[a as usize]).collect();
                inline(b, *func, &args, span, contact)
            }
            Inst::If { test, arms } if speculates(f, arms) => {
                // Every arm runs, then two selects choose: test < 0, > 0, else the zero
                // arm minus (t − t). That is +0 for a zero test, so the arm keeps its bits
                // (also −0), and NaN for a NaN test, the IF's value then.
                let mut results: Vec<Vec<Value>> = Vec::with_capacity(3);
                for arm in arms.iter() {
                    list(f, b, m, ifs, contact, &arm.insts);
                    let arm_results = std::iter::once(arm.result).chain(arm.extra.iter().copied());
                    results.push(arm_results.map(|r| m[r as usize]).collect());
                }
                let t = m[*test as usize];
                let zero = b.constant(0.0, span.clone());
                let nan_if_nan = b.arith(Arith::Sub, t, t, span.clone());
                let chosen: Vec<Value> = (0..results[0].len())
                    .map(|i| {
                        let at_zero = b.arith(Arith::Sub, results[1][i], nan_if_nan, span.clone());
                        let not_neg =
                            b.select(Cmp::Gt, t, zero, results[2][i], at_zero, span.clone());
                        b.select(Cmp::Lt, t, zero, results[0][i], not_neg, span.clone())
                    })
                    .collect();
                let first = chosen[0];
                ifs.insert(v, chosen);
                first
            }
            Inst::If { test, arms } => {
                let walk = |b: &mut Builder, m: &mut [Value], insts: &[Value]| {
                    list(f, b, m, ifs, contact, insts);
                    Ok::<(), std::convert::Infallible>(())
                };
                let Ok(results) = copy_if(b, m, *test, arms, span, walk);
                let first = results[0];
                ifs.insert(v, results);
                first
            }
            Inst::IfExtra { of, index } => if_extra(ifs, *of, *index),
            inst => copy(b, inst, span, m),
        };
        m[v as usize] = new;
    }
}

/// The most work (in instructions; see [`cost`]) the three arms of an IF may hold together
/// for the IF to be if-converted.
const SPECULATE_LIMIT: usize = 24;

/// Whether an IF is if-converted: every arm is cheap arithmetic without calls (so running
/// an arm the test does not pick is unobservable: IEEE arithmetic has no traps) and all
/// of them together cost at most [`SPECULATE_LIMIT`].
fn speculates(f: &Function, arms: &[super::Block; 3]) -> bool {
    let total: Option<usize> = arms.iter().map(|a| cost(f, &a.insts)).sum();
    total.is_some_and(|c| c <= SPECULATE_LIMIT)
}

/// Instructions `values` cost when run unconditionally, or `None` when one of them may
/// not be run speculatively (a call to anything but the branch-free MIN, MAX, DIM, SIGN
/// and ABS; a spline; a runtime partial).
fn cost(f: &Function, values: &[Value]) -> Option<usize> {
    let mut total = 0;
    for &v in values {
        total += match f.inst(v) {
            Inst::Const(_)
            | Inst::Var(_)
            | Inst::Time
            | Inst::Mode
            | Inst::Measure(_)
            | Inst::IfExtra { .. } => 0,
            Inst::Neg(_)
            | Inst::Add(..)
            | Inst::Sub(..)
            | Inst::Mul(..)
            | Inst::Div(..)
            | Inst::Sqrt(_)
            | Inst::Call(Func::Abs, _) => 1,
            Inst::Select { .. } => 2,
            Inst::Call(Func::Min | Func::Max | Func::Dim | Func::Sign, _) => 4,
            // Two subtractions, two selects of two instructions each, and the arms.
            Inst::If { arms, .. } => {
                6 + arms
                    .iter()
                    .map(|a| cost(f, &a.insts))
                    .sum::<Option<usize>>()?
            }
            Inst::Call(..) | Inst::Spline { .. } | Inst::Partial { .. } => return None,
        };
    }
    Some(total)
}

/// The most IMPACT and BISTOP calls a function may hold for their contact branches to be
/// lowered (see the module comment).
pub const CONTACT_INLINE_LIMIT: usize = 64;

/// Emits `func(args)`, branch-free when it is one of the cheap functions and not every
/// argument is constant (constant calls fold through the runtime as usual); IMPACT and
/// BISTOP branch on contact as `contact` says.
pub fn inline(b: &mut Builder, func: Func, args: &[Value], span: Span, contact: Contacts) -> Value {
    if args.iter().all(|&a| b.get_const(a).is_some()) {
        return b.call(func, args.to_vec(), span);
    }
    let mut l = Lower { b, span };
    match (func, args) {
        (Func::Min, &[a1, a2]) => {
            let sum = l.add(a1, a2);
            let r = l.sel(Cmp::Lt, a2, a1, a2, sum);
            l.sel(Cmp::Le, a1, a2, a1, r)
        }
        (Func::Max, &[a1, a2]) => {
            let sum = l.add(a1, a2);
            let r = l.sel(Cmp::Gt, a2, a1, a2, sum);
            l.sel(Cmp::Ge, a1, a2, a1, r)
        }
        (Func::Dim, &[a1, a2]) => {
            let (d, zero) = (l.sub(a1, a2), l.c(0.0));
            l.sel(Cmp::Le, a1, a2, zero, d)
        }
        (Func::Sign, &[a1, a2]) => {
            let m = l.call(Func::Abs, &[a1]);
            let (neg, zero, nan) = (l.neg(m), l.c(0.0), l.c(f64::NAN));
            let r = l.sel(Cmp::Lt, a2, zero, neg, nan);
            l.sel(Cmp::Ge, a2, zero, m, r)
        }
        (Func::Step | Func::Step5 | Func::Havsin, &[x, x0, h0, x1, h1]) => {
            let interior = |l: &mut Lower, d: Value| match func {
                Func::Step => l.cubic(h0, h1, d),
                Func::Step5 => l.quintic(h0, h1, d),
                _ => l.haversine(h0, h1, d),
            };
            let rows = l.rows(x, x0, h0, x1, h1, interior);
            let nan = l.c(f64::NAN);
            let r = l.sel(Cmp::Uno, h0, h1, nan, rows);
            l.sel(Cmp::Lt, x0, x1, r, nan)
        }
        (Func::Poly, [x, x0, coeffs @ ..])
            if (1..=super::MAX_CALL_ARGS - 3).contains(&coeffs.len()) =>
        {
            // x − (+0) is x (also for ±0 and ±∞; NaN payloads aside): skip it.
            let t = match l.b.get_const(*x0) {
                Some(c) if c.to_bits() == 0 => *x,
                _ => l.sub(*x, *x0),
            };
            let (&last, rest) = coeffs.split_last().unwrap_or((x, &[]));
            let mut acc = last;
            for &a in rest.iter().rev() {
                let p = l.mul(acc, t);
                acc = l.add(p, a);
            }
            if rest.is_empty() {
                // A lone coefficient ignores t, but POLY(NaN, ...) is still NaN.
                let nan = l.c(f64::NAN);
                acc = l.sel(Cmp::Uno, t, t, nan, acc);
            }
            acc
        }
        (Func::Impact | Func::Bistop, _) if contact == Contacts::Calls => l.call(func, args),
        (Func::Impact, &[x, xd, x1, k, e, cmax, d]) => match l.consts([x1, k, e, cmax, d]) {
            Some([c1, ck, ce, cc, cd]) if contact_valid(c1, ck, ce, cc, cd) => {
                l.contact_if(x, xd, x1, None, k, e, cmax, d)
            }
            None if contact == Contacts::All => {
                let f = l.contact_if(x, xd, x1, None, k, e, cmax, d);
                l.checked(f, &[x1], [k, e, cmax, d])
            }
            _ => l.call(func, args),
        },
        (Func::Bistop, &[x, xd, x1, x2, k, e, cmax, d]) => {
            match l.consts([x1, x2, k, e, cmax, d]) {
                Some([c1, c2, ck, ce, cc, cd])
                    if c1.is_finite() && c1 < c2 && contact_valid(c2, ck, ce, cc, cd) =>
                {
                    l.contact_if(x, xd, x1, Some(x2), k, e, cmax, d)
                }
                None if contact == Contacts::All => {
                    let f = l.contact_if(x, xd, x1, Some(x2), k, e, cmax, d);
                    let f = l.checked(f, &[x1, x2], [k, e, cmax, d]);
                    let nan = l.c(f64::NAN);
                    l.sel(Cmp::Lt, x1, x2, f, nan)
                }
                _ => l.call(func, args),
            }
        }
        _ => l.b.call(func, args.to_vec(), l.span),
    }
}

/// The contact functions' parameter check (`contact::params_valid`) with a finite contact
/// position, so that `x - x1` has the sign of the comparison `x < x1` for every x (NaN
/// only when x is NaN).
fn contact_valid(x1: f64, k: f64, e: f64, cmax: f64, d: f64) -> bool {
    x1.is_finite() && k >= 0.0 && e > 0.0 && cmax >= 0.0 && d > 0.0
}

/// Which side of the free range a contact branch is on.
#[derive(Clone, Copy)]
enum Side {
    Below,
    Above,
}

/// Emits instructions at one span (also the second derivative's expansion,
/// `deriv::expand`, which adds its own methods).
pub(super) struct Lower<'b> {
    pub(super) b: &'b mut Builder,
    pub(super) span: Span,
}

impl Lower<'_> {
    pub(super) fn c(&mut self, x: f64) -> Value {
        self.b.constant(x, self.span.clone())
    }
    pub(super) fn op(&mut self, op: Arith, a: Value, b: Value) -> Value {
        self.b.arith(op, a, b, self.span.clone())
    }
    pub(super) fn add(&mut self, a: Value, b: Value) -> Value {
        self.op(Arith::Add, a, b)
    }
    pub(super) fn sub(&mut self, a: Value, b: Value) -> Value {
        self.op(Arith::Sub, a, b)
    }
    pub(super) fn mul(&mut self, a: Value, b: Value) -> Value {
        self.op(Arith::Mul, a, b)
    }
    pub(super) fn div(&mut self, a: Value, b: Value) -> Value {
        self.op(Arith::Div, a, b)
    }
    pub(super) fn neg(&mut self, a: Value) -> Value {
        self.b.neg(a, self.span.clone())
    }
    pub(super) fn call(&mut self, func: Func, args: &[Value]) -> Value {
        self.b.call(func, args.to_vec(), self.span.clone())
    }
    pub(super) fn sel(&mut self, cmp: Cmp, a: Value, b: Value, t: Value, o: Value) -> Value {
        self.b.select(cmp, a, b, t, o, self.span.clone())
    }

    /// The values of `vs` when all are constants.
    fn consts<const N: usize>(&self, vs: [Value; N]) -> Option<[f64; N]> {
        let mut out = [0.0; N];
        for (o, &v) in out.iter_mut().zip(&vs) {
            *o = self.b.get_const(v)?;
        }
        Some(out)
    }

    /// One arm of an IF: the instructions `body` emits, yielding its value.
    fn arm(&mut self, body: impl FnOnce(&mut Self) -> Value) -> super::Block {
        self.b.begin_block();
        let r = body(self);
        self.b.end_block(r)
    }

    /// IMPACT (`x2` None) or BISTOP written out: an arithmetic IF on x − x1 with the
    /// contact arm below, and for BISTOP one on x − x2 above it.
    #[allow(clippy::too_many_arguments)] // the contact parameters
    fn contact_if(
        &mut self,
        x: Value,
        xd: Value,
        x1: Value,
        x2: Option<Value>,
        k: Value,
        e: Value,
        cmax: Value,
        d: Value,
    ) -> Value {
        let zero = self.resting(xd);
        let test = self.sub(x, x1);
        let lower = self.arm(|l| l.contact(Side::Below, x, xd, x1, k, e, cmax, d));
        let rest = self.arm(|_| zero);
        let above = self.arm(|l| match x2 {
            None => zero,
            Some(x2) => {
                let test = l.sub(x, x2);
                let (free, free2) = (l.arm(|_| zero), l.arm(|_| zero));
                let upper = l.arm(|l| l.contact(Side::Above, x, xd, x2, k, e, cmax, d));
                l.b.if_(test, [free, free2, upper], l.span.clone())
            }
        });
        self.b.if_(test, [lower, rest, above], self.span.clone())
    }

    /// `f`, or NaN where the runtime refuses the parameters: an edge not finite, k < 0,
    /// e ≤ 0, CMAX < 0 or d ≤ 0 (a NaN fails every comparison, so it is NaN too).
    fn checked(&mut self, f: Value, edges: &[Value], [k, e, cmax, d]: [Value; 4]) -> Value {
        let (zero, nan) = (self.c(0.0), self.c(f64::NAN));
        let mut r = f;
        for (cmp, v) in [(Cmp::Gt, d), (Cmp::Ge, cmax), (Cmp::Gt, e), (Cmp::Ge, k)] {
            r = self.sel(cmp, v, zero, r, nan);
        }
        for &edge in edges {
            // edge − edge is NaN for ±∞ and NaN.
            let t = self.sub(edge, edge);
            r = self.sel(Cmp::Uno, t, t, nan, r);
        }
        r
    }

    /// A contact function out of contact: 0, or NaN when ẋ is (the runtime checks every
    /// argument for NaN first).
    fn resting(&mut self, xd: Value) -> Value {
        let (zero, nan) = (self.c(0.0), self.c(f64::NAN));
        self.sel(Cmp::Uno, xd, xd, nan, zero)
    }

    /// A contact branch, clamped: below x1 (`contact::lower_force` and `push_only`, edge
    /// x1) or above x2 (`upper_force` and `pull_only`, edge x2). The power is a call, the
    /// damping STEP and the clamp are selects.
    #[allow(clippy::too_many_arguments)] // the contact parameters
    fn contact(
        &mut self,
        side: Side,
        x: Value,
        xd: Value,
        edge: Value,
        k: Value,
        e: Value,
        cmax: Value,
        d: Value,
    ) -> Value {
        let zero = self.c(0.0);
        // In contact the base is positive (x beyond a finite edge; a NaN x fails the
        // contact test) and e a checked constant, so `**`'s NaN test cannot fire: call
        // libm's pow directly.
        let (spring, c) = match side {
            Side::Below => {
                let p = self.sub(edge, x);
                let pe = self.call(Func::PowLibm, &[p, e]);
                let x0 = self.sub(edge, d);
                let c = self.rows(x, x0, cmax, edge, zero, |l, t| l.cubic(cmax, zero, t));
                (self.mul(k, pe), c)
            }
            Side::Above => {
                let p = self.sub(x, edge);
                let pe = self.call(Func::PowLibm, &[p, e]);
                let kp = self.mul(k, pe);
                let x1 = self.add(edge, d);
                let c = self.rows(x, edge, zero, x1, cmax, |l, t| l.cubic(zero, cmax, t));
                (self.neg(kp), c)
            }
        };
        let damping = self.mul(c, xd);
        let f = self.sub(spring, damping);
        // push_only: f > 0 ? f : f <= 0 ? 0 : f (NaN stays); pull_only mirrored.
        let (keep, clamp) = match side {
            Side::Below => (Cmp::Gt, Cmp::Le),
            Side::Above => (Cmp::Lt, Cmp::Ge),
        };
        let r = self.sel(clamp, f, zero, zero, f);
        self.sel(keep, f, zero, f, r)
    }

    /// The rows of a step: h0 for x ≤ x0, h1 for x ≥ x1, `interior(Δ)` between, with
    /// Δ = (x − x0)/(x1 − x0) (`steps::step_rows`).
    fn rows(
        &mut self,
        x: Value,
        x0: Value,
        h0: Value,
        x1: Value,
        h1: Value,
        interior: impl FnOnce(&mut Self, Value) -> Value,
    ) -> Value {
        let (num, den) = (self.sub(x, x0), self.sub(x1, x0));
        let d = self.div(num, den);
        let mid = interior(self, d);
        let r = self.sel(Cmp::Ge, x, x1, h1, mid);
        self.sel(Cmp::Le, x, x0, h0, r)
    }

    /// `h0 + (h1 - h0) * d * d * (3.0 - 2.0 * d)`.
    fn cubic(&mut self, h0: Value, h1: Value, d: Value) -> Value {
        let a = self.sub(h1, h0);
        let ad = self.mul(a, d);
        let add = self.mul(ad, d);
        let (three, two) = (self.c(3.0), self.c(2.0));
        let twod = self.mul(two, d);
        let s = self.sub(three, twod);
        let p = self.mul(add, s);
        self.add(h0, p)
    }

    /// `h0 + (h1 - h0) * d * d * d * (10.0 - 15.0 * d + 6.0 * d * d)`.
    fn quintic(&mut self, h0: Value, h1: Value, d: Value) -> Value {
        let a = self.sub(h1, h0);
        let mut p = a;
        for _ in 0..3 {
            p = self.mul(p, d);
        }
        let (ten, fifteen, six) = (self.c(10.0), self.c(15.0), self.c(6.0));
        let f = self.mul(fifteen, d);
        let s = self.sub(ten, f);
        let sd = self.mul(six, d);
        let sdd = self.mul(sd, d);
        let bracket = self.add(s, sdd);
        let q = self.mul(p, bracket);
        self.add(h0, q)
    }

    /// `(h0 + h1) / 2.0 + (h1 - h0) / 2.0 * SIN(PI * d - FRAC_PI_2)`.
    fn haversine(&mut self, h0: Value, h1: Value, d: Value) -> Value {
        let two = self.c(2.0);
        let sum = self.add(h0, h1);
        let mean = self.div(sum, two);
        let diff = self.sub(h1, h0);
        let half = self.div(diff, two);
        let (pi, pi2) = (self.c(PI), self.c(FRAC_PI_2));
        let pd = self.mul(pi, d);
        let theta = self.sub(pd, pi2);
        let s = self.call(Func::Sin, &[theta]);
        let hs = self.mul(half, s);
        self.add(mean, hs)
    }
}
