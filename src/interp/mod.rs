//! The interpreter: evaluates IR by running a flat register bytecode.
//!
//! [`Program::new`] turns a [`Function`] into a list of ops over a register file in
//! which every IR value has its own register and constants are preloaded; IF arms become
//! jump targets, so only the taken arm runs. Library functions are called from
//! `mbfx-runtime`, exactly as the JIT calls them, so both back ends give the same bits.
//! Evaluation never recurses and never allocates for up to [`STACK_REGS`] registers
//! (larger functions copy their register file to the heap once per evaluation).
//!
//! Pieces: `op` (the instruction set), `compile` (IR to ops, with the superinstructions
//! of fast mode), `fuse` (which operations fold into their reader), `run` (the register
//! file and the dispatch loop), `trace` (where a non-finite value came from).

mod compile;
mod fuse;
mod op;
mod run;
#[cfg(test)]
mod tests;
mod trace;

use crate::context::Context;
use crate::ir::{Function, Uses};
use compile::Mode;
use op::{Inputs, Op};
pub use trace::Fault;

/// Functions with at most this many registers evaluate in a register file on the stack.
pub const STACK_REGS: usize = 128;

/// The sizes of the stack register files, each a power of two (see `run`).
const STACK_SIZES: [usize; 5] = [8, 16, 32, 64, STACK_REGS];

/// An expression ready for the interpreter.
#[derive(Clone, Debug)]
pub struct Program {
    ops: Vec<Op>,
    /// Inputs loaded before the first op (fast mode).
    inputs: Inputs,
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
        compile::compile(function, Mode::Fast)
    }

    /// The IR this program runs.
    pub fn function(&self) -> &Function {
        &self.function
    }

    /// What the program reads from the context.
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
            _ => self.eval_on_heap(ctx, out),
        }
    }

    /// Runs in a register file on the heap (functions with more than [`STACK_REGS`]
    /// registers). Not inlined, as [`Program::eval_in`].
    #[inline(never)]
    fn eval_on_heap(&self, ctx: &Context, out: &mut [f64]) {
        let mut r = self.template.clone();
        self.run(ctx, &mut r[..]);
        self.read_outputs(&r, out);
    }

    /// Runs in a stack register file of `N` registers. The template is padded to one of
    /// these sizes, so the file is initialised by one fixed-size copy. Not inlined: each
    /// size is one copy of the dispatch loop, which callers share.
    #[inline(never)]
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
        match (&self.outputs[..], out) {
            (&[reg], [o]) => *o = r[reg as usize],
            (outputs, out) => {
                for (o, &reg) in out.iter_mut().zip(outputs) {
                    *o = r[reg as usize];
                }
            }
        }
    }

    /// Re-evaluates step by step and reports the first subexpression that produced NaN
    /// or an infinity, or an IF whose test was NaN (decision 7). Slow; for diagnostics.
    pub fn first_fault(&self, ctx: &Context) -> Option<Fault> {
        let plain = compile::compile(self.function.clone(), Mode::Trace);
        trace::first_fault(&plain, ctx)
    }
}
