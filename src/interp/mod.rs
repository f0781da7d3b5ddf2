//! The interpreter: evaluates IR by running a flat register bytecode.
//!
//! [`Program::new`] turns a [`Function`] into a list of [`Op`]s over a register file in
//! which every IR value has its own register and constants are preloaded; IF arms become
//! jump targets, so only the taken arm runs. Library functions are called from
//! `mbfx-runtime`, exactly as the JIT calls them, so both back ends give the same bits.
//! Evaluation never recurses and never allocates for up to [`STACK_REGS`] registers.

mod compile;
mod trace;

use crate::context::Context;
use crate::ir::{Function, Uses};
pub use trace::Fault;

/// Which IF arm a test value selects: 0 for negative, 1 for zero (either sign), 2 for
/// positive, `None` for NaN.
#[inline(always)]
fn branch(t: f64) -> Option<usize> {
    if t < 0.0 {
        Some(0)
    } else if t == 0.0 {
        Some(1)
    } else if t > 0.0 {
        Some(2)
    } else {
        None
    }
}

/// Functions with at most this many values evaluate in a register file on the stack.
pub const STACK_REGS: usize = 48;

/// One bytecode instruction; `d` is the destination register.
#[derive(Clone, Copy, Debug)]
enum Op {
    Var {
        d: u32,
        slot: u32,
    },
    Time {
        d: u32,
    },
    Mode {
        d: u32,
    },
    Measure {
        d: u32,
        slot: u32,
    },
    Neg {
        d: u32,
        a: u32,
    },
    Add {
        d: u32,
        a: u32,
        b: u32,
    },
    Sub {
        d: u32,
        a: u32,
        b: u32,
    },
    Mul {
        d: u32,
        a: u32,
        b: u32,
    },
    Div {
        d: u32,
        a: u32,
        b: u32,
    },
    Sqrt {
        d: u32,
        a: u32,
    },
    Call1 {
        d: u32,
        a: u32,
        f: fn(f64) -> f64,
    },
    Call2 {
        d: u32,
        a: u32,
        b: u32,
        f: fn(f64, f64) -> f64,
    },
    /// A call with more arguments: their registers are `arg_regs[args..args + n]`.
    CallN {
        d: u32,
        func: crate::ir::Func,
        args: u32,
        n: u32,
    },
    Spline {
        d: u32,
        x: u32,
        z: u32,
        spline: u32,
        iord: u8,
        akima: bool,
    },
    /// Jump to `arms[0|1|2]` by the sign of register `test`; on NaN, `d` = NaN and go to `end`.
    If {
        d: u32,
        test: u32,
        arms: [u32; 3],
        end: u32,
    },
    Move {
        d: u32,
        a: u32,
    },
    Jump {
        to: u32,
    },
}

/// An expression ready for the interpreter.
#[derive(Clone, Debug)]
pub struct Program {
    ops: Vec<Op>,
    /// Initial register file: constants in place, zero elsewhere.
    template: Vec<f64>,
    arg_regs: Vec<u32>,
    outputs: Vec<u32>,
    function: Function,
}

impl Program {
    /// Compiles a function for the interpreter.
    pub fn new(function: Function) -> Self {
        compile::compile(function)
    }

    /// The IR this program runs.
    pub fn function(&self) -> &Function {
        &self.function
    }

    pub fn uses(&self) -> &Uses {
        &self.function.uses
    }

    /// Evaluates a scalar expression (the first output of a vector one). Gives NaN when
    /// the context lacks slots the expression reads.
    pub fn eval(&self, ctx: &Context) -> f64 {
        let mut out = [0.0];
        self.eval_into(ctx, &mut out);
        out[0]
    }

    /// Evaluates all outputs (1 or 3) into `out`.
    pub fn eval_into(&self, ctx: &Context, out: &mut [f64]) {
        if !ctx.covers(&self.function.uses) {
            out.fill(f64::NAN);
            return;
        }
        let n = self.template.len();
        if n <= STACK_REGS {
            let mut regs = [0.0; STACK_REGS];
            regs[..n].copy_from_slice(&self.template);
            self.run(ctx, &mut regs[..n], out);
        } else {
            let mut regs = self.template.clone();
            self.run(ctx, &mut regs, out);
        }
    }

    fn run(&self, ctx: &Context, r: &mut [f64], out: &mut [f64]) {
        let ops = &self.ops[..];
        let mut pc = 0usize;
        while let Some(op) = ops.get(pc) {
            pc += 1;
            match *op {
                Op::If { d, test, arms, end } => {
                    pc = match branch(r[test as usize]) {
                        Some(arm) => arms[arm],
                        None => {
                            r[d as usize] = f64::NAN;
                            end
                        }
                    } as usize;
                }
                Op::Jump { to } => pc = to as usize,
                ref data => self.exec(data, ctx, r),
            }
        }
        for (o, &reg) in out.iter_mut().zip(&self.outputs) {
            *o = r[reg as usize];
        }
    }

    /// Executes one data op (anything but IF and jumps).
    #[inline(always)]
    fn exec(&self, op: &Op, ctx: &Context, r: &mut [f64]) {
        match *op {
            Op::Var { d, slot } => r[d as usize] = ctx.vars()[slot as usize],
            Op::Time { d } => r[d as usize] = ctx.time,
            Op::Mode { d } => r[d as usize] = ctx.mode,
            Op::Measure { d, slot } => r[d as usize] = ctx.measures()[slot as usize],
            Op::Neg { d, a } => r[d as usize] = -r[a as usize],
            Op::Add { d, a, b } => r[d as usize] = r[a as usize] + r[b as usize],
            Op::Sub { d, a, b } => r[d as usize] = r[a as usize] - r[b as usize],
            Op::Mul { d, a, b } => r[d as usize] = r[a as usize] * r[b as usize],
            Op::Div { d, a, b } => r[d as usize] = r[a as usize] / r[b as usize],
            Op::Sqrt { d, a } => r[d as usize] = r[a as usize].sqrt(),
            Op::Call1 { d, a, f } => r[d as usize] = f(r[a as usize]),
            Op::Call2 { d, a, b, f } => r[d as usize] = f(r[a as usize], r[b as usize]),
            Op::CallN { d, func, args, n } => {
                let mut buf = [0.0; compile::MAX_CALL_ARGS];
                let regs = &self.arg_regs[args as usize..(args + n) as usize];
                for (slot, &reg) in buf.iter_mut().zip(regs) {
                    *slot = r[reg as usize];
                }
                r[d as usize] = func.eval(&buf[..n as usize]);
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
                let (x, z) = (r[x as usize], r[z as usize]);
                r[d as usize] = if akima {
                    mbfx_runtime::akispl(x, z, s, i32::from(iord))
                } else {
                    mbfx_runtime::cubspl(x, z, s, i32::from(iord))
                };
            }
            Op::Move { d, a } => r[d as usize] = r[a as usize],
            Op::If { .. } | Op::Jump { .. } => {}
        }
    }

    /// Re-evaluates step by step and reports the first subexpression that produced NaN
    /// or an infinity, or an IF whose test was NaN (decision 7). Slow; for diagnostics.
    pub fn first_fault(&self, ctx: &Context) -> Option<Fault> {
        trace::first_fault(self, ctx)
    }
}
