//! Shared machinery of the passes that rebuild a [`Function`] through a fresh
//! [`Builder`] ([`super::lower`], [`super::deriv`]): the value map with every constant
//! pre-mapped, and the copy of one non-IF instruction with its operands mapped. Rebuilding
//! through the builder folds and shares what the rewrite exposes.

use super::builder::{Arith, Builder};
use super::{Block, Function, Inst, Value};
use crate::diag::Span;
use rustc_hash::FxHashMap;

/// Marks a value not yet rebuilt.
pub(crate) const UNSET: Value = Value::MAX;

/// A map from old values to new ones with every constant of `f` already in `b`, at its
/// own span, or at `span` when given (code inlined in place of another instruction).
pub(crate) fn constants(f: &Function, b: &mut Builder, span: Option<&Span>) -> Vec<Value> {
    f.insts
        .iter()
        .enumerate()
        .map(|(i, inst)| match inst {
            Inst::Const(c) => b.constant(*c, span.unwrap_or(&f.spans[i]).clone()),
            _ => UNSET,
        })
        .collect()
}

/// Re-emits an IF keeping its structure: each arm in a block of its own, its instructions
/// mapped into `m` by `arm` (the pass's own walk), then the IF over the new arms. Returns
/// the IF's results: its value, then the extras an `IfExtra` reads ([`if_extra`]).
pub(crate) fn copy_if<E>(
    b: &mut Builder,
    m: &mut [Value],
    test: Value,
    arms: &[Block; 3],
    span: Span,
    mut arm: impl FnMut(&mut Builder, &mut [Value], &[Value]) -> Result<(), E>,
) -> Result<Vec<Value>, E> {
    let mut new_arms: [Block; 3] = Default::default();
    for (new, old) in new_arms.iter_mut().zip(arms) {
        b.begin_block();
        arm(b, m, &old.insts)?;
        let results: Vec<Value> = std::iter::once(old.result)
            .chain(old.extra.iter().copied())
            .map(|r| m[r as usize])
            .collect();
        *new = b.end_block_multi(&results);
    }
    Ok(b.if_multi(m[test as usize], new_arms, span))
}

/// What `IfExtra { of, index }` reads: result `index + 1` of the IF `of`, from the results
/// [`copy_if`] (or a pass's own IF) gave it.
pub(crate) fn if_extra(ifs: &FxHashMap<Value, Vec<Value>>, of: Value, index: u32) -> Value {
    ifs.get(&of)
        .and_then(|r| r.get(index as usize + 1).copied())
        .unwrap_or(UNSET)
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
