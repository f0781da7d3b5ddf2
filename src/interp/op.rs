//! The interpreter's instruction set: one `Op` per IR instruction (or per fused pair of
//! them), over a register file in which every IR value has its own register. `d` is the
//! destination register; every other `u32` is a register unless its doc says otherwise.
//!
//! Besides the plain forms there are superinstructions the compiler picks in fast mode:
//! a binary operation whose operand is a single-use binary operation ([`Tri`]: two
//! dispatches and a store and reload fewer), and calls whose constant parameters were
//! checked once (STEP, IMPACT, BISTOP, POLY), and an IF on a difference. Each computes exactly the IEEE operations of
//! the instructions it replaces, in the same order, so the bits do not change.

use crate::ir::Cmp;
use crate::vocab::func::{Fn5, Fn6, Fn7, Fn8, Func};
use mbfx_runtime::{Bistop, Impact, StepParams};

/// A series function: `f(x, x0, coefficients)` or `f(x, x0, w, coefficients)`.
#[derive(Clone, Copy, Debug)]
pub(super) enum SeriesFn {
    Two(fn(f64, f64, &[f64]) -> f64),
    Three(fn(f64, f64, f64, &[f64]) -> f64),
}

/// Where a series call finds its coefficients.
#[derive(Clone, Copy, Debug)]
pub(super) enum Coeffs {
    /// All constant: `pool[start..start + n]`, passed without copying.
    Pool { start: u32, n: u32 },
    /// Registers `arg_regs[start..start + n]`, gathered at run time.
    Regs { start: u32, n: u32 },
}

/// The operands of a fused pair: `d = (a ∘ b) • c` (or `c • (a ∘ b)`), where `∘` is the
/// inner operation, whose value no other instruction reads, and `•` the outer one.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tri {
    pub d: u32,
    pub a: u32,
    pub b: u32,
    pub c: u32,
}

/// An input of the context.
#[derive(Clone, Copy, Debug)]
pub(super) enum Input {
    Var(u32),
    Measure(u32),
    Time,
    Mode,
}

/// The inputs fast mode loads before the first op, by kind, so that loading them is a few
/// plain loops.
#[derive(Clone, Debug, Default)]
pub(super) struct Inputs {
    /// (register, variable slot).
    pub vars: Vec<(u32, u32)>,
    /// (register, measure slot).
    pub measures: Vec<(u32, u32)>,
    /// Registers that take TIME.
    pub time: Vec<u32>,
    /// Registers that take MODE.
    pub mode: Vec<u32>,
}

impl Inputs {
    pub(super) fn push(&mut self, d: u32, from: Input) {
        match from {
            Input::Var(slot) => self.vars.push((d, slot)),
            Input::Measure(slot) => self.measures.push((d, slot)),
            Input::Time => self.time.push(d),
            Input::Mode => self.mode.push(d),
        }
    }
}

/// A series call's function and coefficients.
#[derive(Clone, Copy, Debug)]
pub(super) struct SeriesCall {
    pub coeffs: Coeffs,
    pub f: SeriesFn,
}

/// One instruction. Calls with five or more arguments find their argument registers at
/// `arg_regs[args..]`. A plain `u8` tag (no niche in a field) keeps the dispatch to one
/// table lookup.
#[derive(Clone, Debug)]
#[repr(u8)]
pub(super) enum Op {
    /// An input read where the IR reads it (trace mode; fast mode loads inputs up front).
    Load {
        d: u32,
        from: Input,
    },
    Neg {
        d: u32,
        a: u32,
    },
    Abs {
        d: u32,
        a: u32,
    },
    Sqrt {
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
    // Fused pairs, named inner then outer: `MulAdd` is (a × b) + c. Addition and
    // multiplication commute exactly in IEEE arithmetic, so an inner operation on the
    // right of `+` or `×` is stored on the left; `Rsub` and `Rdiv` have it on the right.
    AddAdd(Tri),
    SubAdd(Tri),
    MulAdd(Tri),
    DivAdd(Tri),
    AddMul(Tri),
    SubMul(Tri),
    MulMul(Tri),
    DivMul(Tri),
    AddSub(Tri),
    SubSub(Tri),
    MulSub(Tri),
    DivSub(Tri),
    /// c − (a + b), and so on.
    AddRsub(Tri),
    SubRsub(Tri),
    MulRsub(Tri),
    DivRsub(Tri),
    AddDiv(Tri),
    SubDiv(Tri),
    MulDiv(Tri),
    DivDiv(Tri),
    /// c / (a + b), and so on.
    AddRdiv(Tri),
    SubRdiv(Tri),
    MulRdiv(Tri),
    DivRdiv(Tri),
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
    // The data of the specialised calls sits behind a box in the op rather than in a
    // table of the program: the dispatch loop then reaches it through the op alone, and
    // sets up no table pointers on entry (which would cost every evaluation, also of the
    // many expressions that have no such call).
    /// STEP at x with the checked constant parameters `p`.
    Step {
        d: u32,
        x: u32,
        p: Box<StepParams>,
    },
    /// STEP5 or HAVSIN (`f`) at x with the checked constant parameters `p`.
    StepFn {
        d: u32,
        x: u32,
        p: Box<StepParams>,
        f: fn(&StepParams, f64) -> f64,
    },
    /// IMPACT at (x, ẋ) with the checked constant parameters `p`.
    Impact {
        d: u32,
        x: u32,
        xd: u32,
        p: Box<Impact>,
    },
    /// BISTOP at (x, ẋ) with the checked constant parameters `p`.
    Bistop {
        d: u32,
        x: u32,
        xd: u32,
        p: Box<Bistop>,
    },
    /// POLY at x, x0 with the constant coefficients `coeffs`.
    Poly {
        d: u32,
        x: u32,
        x0: u32,
        coeffs: Box<[f64]>,
    },
    /// `args` holds the registers of x, x0 (and w for FORCOS/FORSIN).
    Series {
        d: u32,
        args: u32,
        call: Box<SeriesCall>,
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
    /// [`Op::If`] on the test `a − b`, a subtraction no other op reads (fast mode).
    IfSub {
        d: u32,
        a: u32,
        b: u32,
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
        cmp: Cmp,
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
        func: Func,
    },
    Jump {
        to: u32,
    },
}

impl Op {
    /// The register an op computes a value into (not IF, jumps or moves, whose values were
    /// computed by other ops).
    pub(super) fn dest(&self) -> Option<u32> {
        use Op::*;
        Some(match *self {
            Load { d, .. }
            | Neg { d, .. }
            | Abs { d, .. }
            | Sqrt { d, .. }
            | Add { d, .. }
            | Sub { d, .. }
            | Mul { d, .. }
            | Div { d, .. }
            | Call1 { d, .. }
            | Call2 { d, .. }
            | Call5 { d, .. }
            | Call6 { d, .. }
            | Call7 { d, .. }
            | Call8 { d, .. }
            | Step { d, .. }
            | StepFn { d, .. }
            | Impact { d, .. }
            | Bistop { d, .. }
            | Poly { d, .. }
            | Series { d, .. }
            | Spline { d, .. }
            | Select { d, .. }
            | Partial { d, .. } => d,
            AddAdd(t) | SubAdd(t) | MulAdd(t) | DivAdd(t) | AddMul(t) | SubMul(t) | MulMul(t)
            | DivMul(t) | AddSub(t) | SubSub(t) | MulSub(t) | DivSub(t) | AddRsub(t)
            | SubRsub(t) | MulRsub(t) | DivRsub(t) | AddDiv(t) | SubDiv(t) | MulDiv(t)
            | DivDiv(t) | AddRdiv(t) | SubRdiv(t) | MulRdiv(t) | DivRdiv(t) => t.d,
            Move { .. } | If { .. } | IfSub { .. } | Jump { .. } => return None,
        })
    }
}

/// The four binary operations of the IR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Bin {
    Add,
    Sub,
    Mul,
    Div,
}

impl Bin {
    /// The plain op `d = a • b`.
    pub(super) fn op(self, d: u32, a: u32, b: u32) -> Op {
        match self {
            Bin::Add => Op::Add { d, a, b },
            Bin::Sub => Op::Sub { d, a, b },
            Bin::Mul => Op::Mul { d, a, b },
            Bin::Div => Op::Div { d, a, b },
        }
    }

    /// The fused op `d = (a ∘ b) • c` (`inner_left`) or `d = c • (a ∘ b)`, with `self` as
    /// the outer operation `•` and `inner` as `∘`.
    pub(super) fn fused(self, inner: Bin, inner_left: bool, t: Tri) -> Op {
        use Bin::*;
        match (self, inner_left, inner) {
            (Add, _, Add) => Op::AddAdd(t),
            (Add, _, Sub) => Op::SubAdd(t),
            (Add, _, Mul) => Op::MulAdd(t),
            (Add, _, Div) => Op::DivAdd(t),
            (Mul, _, Add) => Op::AddMul(t),
            (Mul, _, Sub) => Op::SubMul(t),
            (Mul, _, Mul) => Op::MulMul(t),
            (Mul, _, Div) => Op::DivMul(t),
            (Sub, true, Add) => Op::AddSub(t),
            (Sub, true, Sub) => Op::SubSub(t),
            (Sub, true, Mul) => Op::MulSub(t),
            (Sub, true, Div) => Op::DivSub(t),
            (Sub, false, Add) => Op::AddRsub(t),
            (Sub, false, Sub) => Op::SubRsub(t),
            (Sub, false, Mul) => Op::MulRsub(t),
            (Sub, false, Div) => Op::DivRsub(t),
            (Div, true, Add) => Op::AddDiv(t),
            (Div, true, Sub) => Op::SubDiv(t),
            (Div, true, Mul) => Op::MulDiv(t),
            (Div, true, Div) => Op::DivDiv(t),
            (Div, false, Add) => Op::AddRdiv(t),
            (Div, false, Sub) => Op::SubRdiv(t),
            (Div, false, Mul) => Op::MulRdiv(t),
            (Div, false, Div) => Op::DivRdiv(t),
        }
    }
}
