//! Finding where a non-finite value came from (decision 7): a slow re-run that checks
//! every value as it is produced and names the first IF whose test is NaN (decision 2:
//! the expression then has no value), else the first value that is NaN or infinite. A
//! NaN that reaches an IF test is reported at the IF, with the place it came from.

use super::op::Op;
use super::Program;
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
    /// For an IF with a NaN test: the first non-finite subexpression before it, when
    /// there is one (the input that made the test NaN).
    pub cause: Option<Span>,
}

/// Runs `p`, a program compiled in trace mode (one op per IR value, each where the IR
/// computes it), and reports the first fault.
pub fn first_fault(p: &Program, ctx: &Context) -> Option<Fault> {
    let f = &p.function;
    if !p.covered_by(ctx) {
        return None;
    }
    // Registers are compacted: map each back to the IR value it holds, for its span.
    let mut value_of = vec![0u32; p.template.len()];
    for (v, &reg) in p.reg_of.iter().enumerate() {
        if let Some(slot) = value_of.get_mut(reg as usize) {
            *slot = v as u32;
        }
    }
    let fault = |reg: u32, value: f64, nan_if_test: bool| Fault {
        span: f.spans[value_of[reg as usize] as usize].clone(),
        value,
        nan_if_test,
        cause: None,
    };
    // The first non-finite value; the run goes on, as a NaN may still reach an IF test.
    let mut first: Option<Fault> = None;
    let mut r = p.template.clone();
    let mut pc = 0usize;
    while let Some(op) = p.ops.get(pc) {
        if let Op::If { d, test, .. } = *op {
            if r[test as usize].is_nan() {
                let cause = first.map(|f| f.span);
                return Some(Fault {
                    cause,
                    ..fault(d, f64::NAN, true)
                });
            }
        }
        pc = p.step(op, pc, ctx, &mut r[..]);
        if let Some(d) = op.dest() {
            if first.is_none() && !r[d as usize].is_finite() {
                first = Some(fault(d, r[d as usize], false));
            }
        }
    }
    // Nothing computed went non-finite: a non-finite constant must be the culprit.
    // (Outputs are IR values, so their spans are looked up directly.)
    first.or_else(|| {
        f.outputs.iter().find_map(|&o| match f.inst(o) {
            Inst::Const(c) if !c.is_finite() => Some(Fault {
                span: f.spans[o as usize].clone(),
                value: *c,
                nan_if_test: false,
                cause: None,
            }),
            _ => None,
        })
    })
}
