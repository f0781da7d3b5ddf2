//! The interpreter: evaluates IR by running a flat register bytecode.
//!
//! [`Program::new`] turns a [`Function`] into a list of `Op`s over a register file in
//! which every IR value has its own register and constants are preloaded; IF arms become
//! jump targets, so only the taken arm runs. Library functions are called from
//! `mbfx-runtime`, exactly as the JIT calls them, so both back ends give the same bits.
//! Evaluation never recurses and never allocates for up to [`STACK_REGS`] registers
//! (larger functions copy their register file to the heap once per evaluation).

mod compile;
mod trace;

use crate::context::Context;
use crate::ir::{if_arm as branch, Function, Uses};
use crate::vocab::func::{Fn5, Fn6, Fn7, Fn8};
pub use trace::Fault;

/// Functions with at most this many registers evaluate in a register file on the stack.
pub const STACK_REGS: usize = 128;

/// A series function: `f(x, x0, coefficients)` or `f(x, x0, w, coefficients)`.
#[derive(Clone, Copy, Debug)]
enum SeriesFn {
    Two(fn(f64, f64, &[f64]) -> f64),
    Three(fn(f64, f64, f64, &[f64]) -> f64),
}

/// Where a series call finds its coefficients.
#[derive(Clone, Copy, Debug)]
enum Coeffs {
    /// All constant: `pool[start..start + n]`, passed without copying.
    Pool { start: u32, n: u32 },
    /// Registers `arg_regs[start..start + n]`, gathered at run time.
    Regs { start: u32, n: u32 },
}

/// One bytecode instruction; `d` is the destination register. Calls with five or more
/// arguments find their argument registers at `arg_regs[args..]`.
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
    Call5 {
        d: u32,
        args: u32,
        f: Fn5,
    },
    Call6 {
        d: u32,
        args: u32,
        f: Fn6,
    },
    Call7 {
        d: u32,
        args: u32,
        f: Fn7,
    },
    Call8 {
        d: u32,
        args: u32,
        f: Fn8,
    },
    /// `args` holds the registers of x, x0 (and w for FORCOS/FORSIN).
    Series {
        d: u32,
        args: u32,
        coeffs: Coeffs,
        f: SeriesFn,
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
    /// `d = if cmp(a, b) { then } else { otherwise }`.
    Select {
        d: u32,
        cmp: crate::ir::Cmp,
        a: u32,
        b: u32,
        then: u32,
        otherwise: u32,
    },
    /// ∂func/∂(argument `wrt`); `arg_regs[args..args + n]` hold every argument.
    Partial {
        d: u32,
        args: u32,
        n: u32,
        wrt: u32,
        func: crate::vocab::func::Func,
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
    /// Constant coefficient lists of series calls.
    pool: Vec<f64>,
    outputs: Vec<u32>,
    /// Smallest variable, measure and spline arrays a context must provide.
    needs: [usize; 3],
    /// Register of each IR value (`u32::MAX` for values the code never reaches).
    reg_of: Vec<u32>,
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

    fn covered_by(&self, ctx: &Context) -> bool {
        ctx.covers(self.needs)
    }

    /// Evaluates a scalar expression (the first output of a vector one). Gives NaN when
    /// the context lacks slots the expression reads.
    #[inline]
    pub fn eval(&self, ctx: &Context) -> f64 {
        let mut out = [0.0];
        self.eval_into(ctx, &mut out);
        out[0]
    }

    /// Evaluates the outputs (1 or 3) into `out` (extra slots are left alone). Fills `out`
    /// with NaN when the context lacks slots the expression reads.
    #[inline]
    pub fn eval_into(&self, ctx: &Context, out: &mut [f64]) {
        if !self.covered_by(ctx) {
            out.fill(f64::NAN);
            return;
        }
        match self.template.len() {
            8 => self.eval_in::<8>(ctx, out),
            16 => self.eval_in::<16>(ctx, out),
            32 => self.eval_in::<32>(ctx, out),
            64 => self.eval_in::<64>(ctx, out),
            STACK_REGS => self.eval_in::<STACK_REGS>(ctx, out),
            _ => {
                let mut r = self.template.clone();
                self.run(ctx, &mut r);
                self.read_outputs(&r, out);
            }
        }
    }

    /// Runs in a stack register file of `N` registers. The template is padded to one of
    /// these sizes, so the file is initialised by one fixed-size copy.
    #[inline(always)]
    fn eval_in<const N: usize>(&self, ctx: &Context, out: &mut [f64]) {
        let mut r: [f64; N] = match self.template.first_chunk() {
            Some(t) => *t,
            None => [f64::NAN; N],
        };
        self.run(ctx, &mut r);
        self.read_outputs(&r, out);
    }

    #[inline(always)]
    fn read_outputs(&self, r: &[f64], out: &mut [f64]) {
        for (o, &reg) in out.iter_mut().zip(&self.outputs) {
            *o = r[reg as usize];
        }
    }

    fn run(&self, ctx: &Context, r: &mut [f64]) {
        let ops = &self.ops[..];
        let mut pc = 0usize;
        while let Some(op) = ops.get(pc) {
            pc = self.step(op, pc, ctx, r);
        }
    }

    /// Executes one op and returns the index of the next. One `match` per op: the loop
    /// above and the fault tracer both run ops through here.
    #[inline(always)]
    fn step(&self, op: &Op, pc: usize, ctx: &Context, r: &mut [f64]) -> usize {
        match *op {
            Op::If { d, test, arms, end } => {
                return match branch(r[test as usize]) {
                    Some(arm) => arms[arm],
                    None => {
                        r[d as usize] = f64::NAN;
                        end
                    }
                } as usize;
            }
            Op::Jump { to } => return to as usize,
            Op::Move { d, a } => r[d as usize] = r[a as usize],
            Op::Select {
                d,
                cmp,
                a,
                b,
                then,
                otherwise,
            } => {
                let pick = if cmp.test(r[a as usize], r[b as usize]) {
                    then
                } else {
                    otherwise
                };
                r[d as usize] = r[pick as usize];
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
                    *slot = r[reg as usize];
                }
                r[d as usize] = func.partial(wrt as usize, &buf[..regs.len()]);
            }
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
            Op::Call5 { d, args, f } => {
                let a = self.args::<5>(args, r);
                r[d as usize] = f(a[0], a[1], a[2], a[3], a[4]);
            }
            Op::Call6 { d, args, f } => {
                let a = self.args::<6>(args, r);
                r[d as usize] = f(a[0], a[1], a[2], a[3], a[4], a[5]);
            }
            Op::Call7 { d, args, f } => {
                let a = self.args::<7>(args, r);
                r[d as usize] = f(a[0], a[1], a[2], a[3], a[4], a[5], a[6]);
            }
            Op::Call8 { d, args, f } => {
                let a = self.args::<8>(args, r);
                r[d as usize] = f(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]);
            }
            Op::Series { d, args, coeffs, f } => {
                let a = self.args::<3>(args, r);
                let mut buf = [0.0; compile::MAX_COEFFICIENTS];
                let c: &[f64] = match coeffs {
                    Coeffs::Pool { start, n } => &self.pool[start as usize..(start + n) as usize],
                    Coeffs::Regs { start, n } => {
                        let regs = &self.arg_regs[start as usize..(start + n) as usize];
                        for (slot, &reg) in buf.iter_mut().zip(regs) {
                            *slot = r[reg as usize];
                        }
                        &buf[..regs.len()]
                    }
                };
                r[d as usize] = match f {
                    SeriesFn::Two(f) => f(a[0], a[1], c),
                    SeriesFn::Three(f) => f(a[0], a[1], a[2], c),
                };
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
        }
        pc + 1
    }

    /// The values of `K` argument registers listed at `arg_regs[start..]`.
    #[inline(always)]
    fn args<const K: usize>(&self, start: u32, r: &[f64]) -> [f64; K] {
        let regs = &self.arg_regs[start as usize..start as usize + K];
        std::array::from_fn(|i| r[regs[i] as usize])
    }

    /// Re-evaluates step by step and reports the first subexpression that produced NaN
    /// or an infinity, or an IF whose test was NaN (decision 7). Slow; for diagnostics.
    pub fn first_fault(&self, ctx: &Context) -> Option<Fault> {
        trace::first_fault(self, ctx)
    }
}
