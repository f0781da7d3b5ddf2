//! Running ops: the register file and the one `match` that executes an op.
//!
//! The evaluator and the fault tracer both go through [`Program::step`]. The register
//! file is a fixed-size array on the stack for most functions: its size is a power of
//! two, so indexing with `i & (N - 1)` needs no bounds check, and every register the
//! compiler hands out is below the size (the mask never changes an index). Larger
//! functions use a heap slice with ordinary bounds checks.

use super::op::{Coeffs, Input, Op, SeriesCall, SeriesFn, Tri};
use super::Program;
use crate::context::Context;
use crate::ir::if_arm;

/// A register file.
pub(super) trait Regs {
    fn get(&self, i: u32) -> f64;
    fn set(&mut self, i: u32, v: f64);
}

impl<const N: usize> Regs for [f64; N] {
    #[inline(always)]
    fn get(&self, i: u32) -> f64 {
        const { assert!(N.is_power_of_two()) };
        self[i as usize & (N - 1)]
    }

    #[inline(always)]
    fn set(&mut self, i: u32, v: f64) {
        const { assert!(N.is_power_of_two()) };
        self[i as usize & (N - 1)] = v;
    }
}

impl Regs for [f64] {
    #[inline(always)]
    fn get(&self, i: u32) -> f64 {
        self[i as usize]
    }

    #[inline(always)]
    fn set(&mut self, i: u32, v: f64) {
        self[i as usize] = v;
    }
}

/// `d = f(a, b, c)` for a fused pair.
#[inline(always)]
fn tri<R: Regs + ?Sized>(r: &mut R, t: Tri, f: impl Fn(f64, f64, f64) -> f64) {
    r.set(t.d, f(r.get(t.a), r.get(t.b), r.get(t.c)));
}

impl Program {
    /// Runs the whole program: the inputs loaded up front (fast mode), then the ops.
    #[inline(always)]
    pub(super) fn run<R: Regs + ?Sized>(&self, ctx: &Context, r: &mut R) {
        let inputs = &self.inputs;
        let vars = ctx.vars();
        for &(d, slot) in &inputs.vars {
            r.set(d, vars[slot as usize]);
        }
        if !inputs.measures.is_empty() {
            let measures = ctx.measures();
            for &(d, slot) in &inputs.measures {
                r.set(d, measures[slot as usize]);
            }
        }
        for &d in &inputs.time {
            r.set(d, ctx.time);
        }
        for &d in &inputs.mode {
            r.set(d, ctx.mode);
        }
        let ops = &self.ops[..];
        let mut pc = 0usize;
        while let Some(op) = ops.get(pc) {
            pc = self.step(op, pc, ctx, r);
        }
    }

    /// Executes one op and returns the index of the next.
    #[inline(always)]
    pub(super) fn step<R: Regs + ?Sized>(
        &self,
        op: &Op,
        pc: usize,
        ctx: &Context,
        r: &mut R,
    ) -> usize {
        match *op {
            Op::If { d, test, arms, end } => {
                return match if_arm(r.get(test)) {
                    Some(arm) => arms[arm],
                    None => {
                        r.set(d, f64::NAN);
                        end
                    }
                } as usize;
            }
            Op::IfSub { d, a, b, arms, end } => {
                return match if_arm(r.get(a) - r.get(b)) {
                    Some(arm) => arms[arm],
                    None => {
                        r.set(d, f64::NAN);
                        end
                    }
                } as usize;
            }
            Op::Jump { to } => return to as usize,
            Op::Move { d, a } => r.set(d, r.get(a)),
            Op::Load { d, from } => r.set(d, input(ctx, from)),
            Op::Neg { d, a } => r.set(d, -r.get(a)),
            Op::Abs { d, a } => r.set(d, r.get(a).abs()),
            Op::Sqrt { d, a } => r.set(d, r.get(a).sqrt()),
            Op::Add { d, a, b } => r.set(d, r.get(a) + r.get(b)),
            Op::Sub { d, a, b } => r.set(d, r.get(a) - r.get(b)),
            Op::Mul { d, a, b } => r.set(d, r.get(a) * r.get(b)),
            Op::Div { d, a, b } => r.set(d, r.get(a) / r.get(b)),
            Op::AddAdd(t) => tri(r, t, |a, b, c| (a + b) + c),
            Op::SubAdd(t) => tri(r, t, |a, b, c| (a - b) + c),
            Op::MulAdd(t) => tri(r, t, |a, b, c| (a * b) + c),
            Op::DivAdd(t) => tri(r, t, |a, b, c| (a / b) + c),
            Op::AddMul(t) => tri(r, t, |a, b, c| (a + b) * c),
            Op::SubMul(t) => tri(r, t, |a, b, c| (a - b) * c),
            Op::MulMul(t) => tri(r, t, |a, b, c| (a * b) * c),
            Op::DivMul(t) => tri(r, t, |a, b, c| (a / b) * c),
            Op::AddSub(t) => tri(r, t, |a, b, c| (a + b) - c),
            Op::SubSub(t) => tri(r, t, |a, b, c| (a - b) - c),
            Op::MulSub(t) => tri(r, t, |a, b, c| (a * b) - c),
            Op::DivSub(t) => tri(r, t, |a, b, c| (a / b) - c),
            Op::AddRsub(t) => tri(r, t, |a, b, c| c - (a + b)),
            Op::SubRsub(t) => tri(r, t, |a, b, c| c - (a - b)),
            Op::MulRsub(t) => tri(r, t, |a, b, c| c - (a * b)),
            Op::DivRsub(t) => tri(r, t, |a, b, c| c - (a / b)),
            Op::AddDiv(t) => tri(r, t, |a, b, c| (a + b) / c),
            Op::SubDiv(t) => tri(r, t, |a, b, c| (a - b) / c),
            Op::MulDiv(t) => tri(r, t, |a, b, c| (a * b) / c),
            Op::DivDiv(t) => tri(r, t, |a, b, c| (a / b) / c),
            Op::AddRdiv(t) => tri(r, t, |a, b, c| c / (a + b)),
            Op::SubRdiv(t) => tri(r, t, |a, b, c| c / (a - b)),
            Op::MulRdiv(t) => tri(r, t, |a, b, c| c / (a * b)),
            Op::DivRdiv(t) => tri(r, t, |a, b, c| c / (a / b)),
            Op::Call1 { d, a, f } => r.set(d, f(r.get(a))),
            Op::Call2 { d, a, b, f } => r.set(d, f(r.get(a), r.get(b))),
            Op::Step { d, x, ref p } => r.set(d, p.step(r.get(x))),
            Op::StepFn { d, x, ref p, f } => r.set(d, f(p, r.get(x))),
            Op::Impact { d, x, xd, ref p } => r.set(d, p.force(r.get(x), r.get(xd))),
            Op::Bistop { d, x, xd, ref p } => r.set(d, p.force(r.get(x), r.get(xd))),
            Op::Poly {
                d,
                x,
                x0,
                ref coeffs,
            } => r.set(d, mbfx_runtime::poly(r.get(x), r.get(x0), coeffs)),
            Op::Select {
                d,
                cmp,
                a,
                b,
                then,
                otherwise,
            } => {
                let pick = if cmp.test(r.get(a), r.get(b)) {
                    then
                } else {
                    otherwise
                };
                r.set(d, r.get(pick));
            }
            Op::Call5 { .. }
            | Op::Call6 { .. }
            | Op::Call7 { .. }
            | Op::Call8 { .. }
            | Op::Series { .. }
            | Op::Spline { .. }
            | Op::Partial { .. } => self.rare(op, ctx, r),
        }
        pc + 1
    }

    /// The ops that are rare in hot expressions (calls with five to eight arguments that
    /// were not specialised, series with computed coefficients, splines, partials), out
    /// of line: their tables then cost the dispatch loop no registers or set-up.
    #[inline(never)]
    fn rare<R: Regs + ?Sized>(&self, op: &Op, ctx: &Context, r: &mut R) {
        match *op {
            Op::Call5 { d, args, f } => {
                let a = self.args::<5, R>(args, r);
                r.set(d, f(a[0], a[1], a[2], a[3], a[4]));
            }
            Op::Call6 { d, args, f } => {
                let a = self.args::<6, R>(args, r);
                r.set(d, f(a[0], a[1], a[2], a[3], a[4], a[5]));
            }
            Op::Call7 { d, args, f } => {
                let a = self.args::<7, R>(args, r);
                r.set(d, f(a[0], a[1], a[2], a[3], a[4], a[5], a[6]));
            }
            Op::Call8 { d, args, f } => {
                let a = self.args::<8, R>(args, r);
                r.set(d, f(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]));
            }
            Op::Series { d, args, ref call } => {
                let SeriesCall { coeffs, f } = **call;
                let a = self.args::<3, R>(args, r);
                let mut buf = [0.0; super::compile::MAX_COEFFICIENTS];
                let c: &[f64] = match coeffs {
                    Coeffs::Pool { start, n } => &self.pool[start as usize..(start + n) as usize],
                    Coeffs::Regs { start, n } => {
                        let regs = &self.arg_regs[start as usize..(start + n) as usize];
                        for (slot, &reg) in buf.iter_mut().zip(regs) {
                            *slot = r.get(reg);
                        }
                        &buf[..regs.len()]
                    }
                };
                r.set(
                    d,
                    match f {
                        SeriesFn::Two(f) => f(a[0], a[1], c),
                        SeriesFn::Three(f) => f(a[0], a[1], a[2], c),
                    },
                );
            }
            Op::Spline {
                d,
                x,
                z,
                spline,
                iord,
                akima,
            } => {
                let s = &ctx.splines()[spline as usize];
                let (x, z) = (r.get(x), r.get(z));
                r.set(
                    d,
                    if akima {
                        mbfx_runtime::akispl(x, z, s, i32::from(iord))
                    } else {
                        mbfx_runtime::cubspl(x, z, s, i32::from(iord))
                    },
                );
            }
            Op::Partial {
                d,
                args,
                n,
                wrt,
                func,
            } => {
                let mut buf = [0.0; crate::ir::MAX_CALL_ARGS];
                let regs = &self.arg_regs[args as usize..(args + n) as usize];
                for (slot, &reg) in buf.iter_mut().zip(regs) {
                    *slot = r.get(reg);
                }
                r.set(d, func.partial(wrt as usize, &buf[..regs.len()]));
            }
            _ => {}
        }
    }

    /// The values of `K` argument registers listed at `arg_regs[start..]`.
    #[inline(always)]
    fn args<const K: usize, R: Regs + ?Sized>(&self, start: u32, r: &R) -> [f64; K] {
        let regs = &self.arg_regs[start as usize..start as usize + K];
        std::array::from_fn(|i| r.get(regs[i]))
    }
}

/// The value of an input of the context. The caller checked that the context covers
/// every slot the function reads (`Program::eval_into`).
#[inline(always)]
fn input(ctx: &Context, from: Input) -> f64 {
    match from {
        Input::Var(slot) => ctx.vars()[slot as usize],
        Input::Measure(slot) => ctx.measures()[slot as usize],
        Input::Time => ctx.time,
        Input::Mode => ctx.mode,
    }
}
