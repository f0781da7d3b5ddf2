//! Shared machinery of the passes that rebuild a [`Function`] through a fresh
//! [`Builder`] ([`super::lower`], [`super::deriv`]): the value map with every constant
//! pre-mapped, and the copy of one non-IF instruction with its operands mapped. Rebuilding
//! through the builder folds and shares what the rewrite exposes.

use super::builder::{Arith, Builder};
use super::{Function, Inst, Value};
use crate::diag::Span;

/// Marks a value not yet rebuilt.
pub(crate) const UNSET: Value = Value::MAX;

/// A map from old values to new ones with every constant of `f` already in `b`.
pub(crate) fn constants(f: &Function, b: &mut Builder) -> Vec<Value> {
    f.insts
        .iter()
        .enumerate()
        .map(|(i, inst)| match inst {
            Inst::Const(c) => b.constant(*c, f.spans[i].clone()),
            _ => UNSET,
        })
        .collect()
}

/// Re-emits one instruction other than `If` and `IfExtra` (which the passes handle, as
/// they own block structure) with its operands mapped through `m`.
pub(crate) fn copy(b: &mut Builder, inst: &Inst, span: Span, m: &[Value]) -> Value {
    let g = |v: &Value| m[*v as usize];
    match inst {
        Inst::Const(c) => b.constant(*c, span),
        Inst::Var(s) => b.var(*s, span),
        Inst::Time => b.time(span),
        Inst::Mode => b.mode(span),
        Inst::Measure(s) => b.measure(*s, span),
        Inst::Neg(a) => b.neg(g(a), span),
        Inst::Add(x, y) => b.arith(Arith::Add, g(x), g(y), span),
        Inst::Sub(x, y) => b.arith(Arith::Sub, g(x), g(y), span),
        Inst::Mul(x, y) => b.arith(Arith::Mul, g(x), g(y), span),
        Inst::Div(x, y) => b.arith(Arith::Div, g(x), g(y), span),
        Inst::Sqrt(a) => b.sqrt(g(a), span),
        Inst::Call(func, args) => b.call(*func, args.iter().map(g).collect(), span),
        Inst::Spline {
            kind,
            x,
            z,
            spline,
            iord,
        } => b.spline(*kind, g(x), g(z), *spline, *iord, span),
        Inst::Select {
            cmp,
            a,
            b: y,
            then,
            otherwise,
        } => b.select(*cmp, g(a), g(y), g(then), g(otherwise), span),
        Inst::Partial { func, wrt, args } => {
            let args: Vec<Value> = args.iter().map(g).collect();
            b.partial(*func, *wrt, &args, span)
        }
        // Handled by the passes; a NaN keeps a misuse visible rather than panicking.
        Inst::If { .. } | Inst::IfExtra { .. } => b.constant(f64::NAN, span),
    }
}
