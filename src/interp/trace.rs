//! Finding where a non-finite value came from (decision 7): a slow re-run that checks
//! every value as it is produced and names the first one that is NaN or infinite, or the
//! first IF whose test is NaN.

use super::{branch, Op, Program};
use crate::context::Context;
use crate::diag::Span;
use crate::ir::Inst;

/// The first place an evaluation went non-finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Fault {
    /// Source span of the subexpression.
    pub span: Span,
    /// Its value (NaN for an IF with a NaN test).
    pub value: f64,
    /// True when an IF's test was NaN, so no branch could be chosen.
    pub nan_if_test: bool,
}

pub fn first_fault(p: &Program, ctx: &Context) -> Option<Fault> {
    let f = &p.function;
    if !ctx.covers(&f.uses) {
        return None;
    }
    let fault = |v: u32, value: f64, nan_if_test: bool| Fault {
        span: f.spans[v as usize].clone(),
        value,
        nan_if_test,
    };
    let mut r = p.template.clone();
    let mut pc = 0usize;
    while let Some(op) = p.ops.get(pc) {
        pc += 1;
        match *op {
            Op::If { d, test, arms, .. } => match branch(r[test as usize]) {
                Some(arm) => pc = arms[arm] as usize,
                None => return Some(fault(d, f64::NAN, true)),
            },
            Op::Jump { to } => pc = to as usize,
            Op::Move { d, a } => r[d as usize] = r[a as usize],
            ref data => {
                p.exec(data, ctx, &mut r);
                let d = dest(data);
                if !r[d as usize].is_finite() {
                    return Some(fault(d, r[d as usize], false));
                }
            }
        }
    }
    // Nothing computed went non-finite: a non-finite constant must be the culprit.
    f.outputs.iter().find_map(|&o| match f.inst(o) {
        Inst::Const(c) if !c.is_finite() => Some(fault(o, *c, false)),
        _ => None,
    })
}

/// Destination register of a data op.
fn dest(op: &Op) -> u32 {
    match *op {
        Op::Var { d, .. }
        | Op::Time { d }
        | Op::Mode { d }
        | Op::Measure { d, .. }
        | Op::Neg { d, .. }
        | Op::Add { d, .. }
        | Op::Sub { d, .. }
        | Op::Mul { d, .. }
        | Op::Div { d, .. }
        | Op::Sqrt { d, .. }
        | Op::Call1 { d, .. }
        | Op::Call2 { d, .. }
        | Op::CallN { d, .. }
        | Op::Spline { d, .. }
        | Op::Move { d, .. }
        | Op::If { d, .. } => d,
        Op::Jump { .. } => u32::MAX,
    }
}
