//! Lowers IR to the interpreter's bytecode. Registers are allocated only for the values
//! the code reaches (constants included, preloaded in the template); IF arms are laid out
//! one after another with jumps to a common end; library calls get an op per arity so no
//! argument buffer is built at run time, and constant coefficient lists of series are
//! passed straight from a pool.
//!
//! In fast mode ([`Mode::Fast`], what [`Program::new`] builds) the compiler also picks
//! superinstructions: the context's inputs are loaded before the first op (reads have no
//! effects, so an input read only in an untaken IF arm may be loaded all the same); a
//! binary operation whose value only one binary operation of the same block reads is
//! fused into that one (see [`fuse`](super::fuse)); ABS and SQRT become single
//! operations (the JIT's `fabs` and `sqrt`); STEP, STEP5, HAVSIN, IMPACT and BISTOP with
//! constant parameters call the runtime's entry points whose parameters were checked
//! once, and POLY with constant coefficients calls `poly` without gathering arguments.
//! Trace mode keeps one op per IR value, each where the IR computes it, so the fault
//! tracer sees every value.

use super::fuse::{binary, Fusion};
use super::op::{Bin, Coeffs, Input, Inputs, Op, SeriesCall, SeriesFn, Tri};
use super::Program;
use crate::ir::{Block, Function, Inst, Value};
use crate::vocab::builtins::SplineKind;
use crate::vocab::func::{Callee, Func};
use mbfx_runtime::{Bistop, Impact, StepParams};

/// Most coefficients a series call takes (spec §5.6–5.8).
pub const MAX_COEFFICIENTS: usize = 31;

const UNASSIGNED: u32 = u32::MAX;

/// What the compiled program is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Evaluation: superinstructions and inputs loaded up front.
    Fast,
    /// The fault tracer: one op per IR value, where the IR computes it.
    Trace,
}

struct Emitter<'f> {
    f: &'f Function,
    ops: Vec<Op>,
    inputs: Inputs,
    arg_regs: Vec<u32>,
    pool: Vec<f64>,
    /// Register of each IR value, or UNASSIGNED.
    reg_of: Vec<u32>,
    template: Vec<f64>,
    /// The [`Inst::IfExtra`] values of each multi-result IF, by IF value, in index order.
    extras_of: rustc_hash::FxHashMap<Value, Vec<Value>>,
    mode: Mode,
    /// Which binary operations fold into their reader (fast mode only).
    fusion: Fusion,
    /// Binary operations left out so far because their reader will compute them.
    pending: Vec<bool>,
}

pub fn compile(function: Function, mode: Mode) -> Program {
    let fusion = match mode {
        Mode::Fast => Fusion::new(&function),
        Mode::Trace => Fusion::none(),
    };
    let mut e = Emitter {
        f: &function,
        ops: Vec::new(),
        inputs: Inputs::default(),
        arg_regs: Vec::new(),
        pool: Vec::new(),
        reg_of: vec![UNASSIGNED; function.insts.len()],
        template: Vec::new(),
        extras_of: extras_of(&function),
        mode,
        fusion,
        pending: vec![false; function.insts.len()],
    };
    e.list(&function.body);
    thread_jumps(&mut e.ops);
    let outputs: Vec<u32> = function.outputs.iter().map(|&v| e.reg(v)).collect();
    let Emitter {
        ops,
        inputs,
        arg_regs,
        pool,
        template,
        reg_of,
        ..
    } = e;
    // Pad the register file to the size of a stack bucket (see Program::eval).
    let mut template = template;
    if let Some(&size) = super::STACK_SIZES.iter().find(|&&s| s >= template.len()) {
        template.resize(size, 0.0);
    }
    let uses = &function.uses;
    Program {
        ops,
        inputs,
        template,
        arg_regs,
        pool,
        outputs,
        needs: [uses.vars_len(), uses.measures_len(), uses.splines_len()],
        reg_of,
        function,
    }
}

/// The extra-result values of every multi-result IF, in index order.
fn extras_of(f: &Function) -> rustc_hash::FxHashMap<Value, Vec<Value>> {
    let mut map: rustc_hash::FxHashMap<Value, Vec<Value>> = Default::default();
    for (v, inst) in f.insts.iter().enumerate() {
        if let Inst::IfExtra { of, index } = *inst {
            let list = map.entry(of).or_default();
            if list.len() <= index as usize {
                list.resize(index as usize + 1, v as Value);
            }
            list[index as usize] = v as Value;
        }
    }
    map
}

impl Emitter<'_> {
    /// The register of value `v`, allocating one (and preloading a constant) on first use.
    fn reg(&mut self, v: Value) -> u32 {
        let slot = &mut self.reg_of[v as usize];
        if *slot == UNASSIGNED {
            *slot = self.template.len() as u32;
            let init = match self.f.inst(v) {
                Inst::Const(c) => *c,
                _ => 0.0,
            };
            self.template.push(init);
        }
        *slot
    }

    fn list(&mut self, values: &[Value]) {
        for &v in values {
            self.inst(v);
        }
    }

    fn here(&self) -> u32 {
        self.ops.len() as u32
    }

    /// Registers of `args`, appended to `arg_regs`; returns where they start.
    fn arg_list(&mut self, args: &[Value]) -> u32 {
        let regs: Vec<u32> = args.iter().map(|&a| self.reg(a)).collect();
        let start = self.arg_regs.len() as u32;
        self.arg_regs.extend(regs);
        start
    }

    fn inst(&mut self, v: Value) {
        let inst = self.f.inst(v).clone();
        if let Some((bin, a, b)) = binary(&inst) {
            self.binary(v, bin, a, b);
            return;
        }
        let op = match inst {
            Inst::Const(_) | Inst::IfExtra { .. } => return,
            Inst::If { test, arms } => {
                let test = match binary(self.f.inst(test)) {
                    Some((Bin::Sub, a, b)) if self.pending[test as usize] => {
                        self.pending[test as usize] = false;
                        Test::Sub(self.reg(a), self.reg(b))
                    }
                    _ => Test::Reg(self.reg(test)),
                };
                let d = self.reg(v);
                let extras = self.extras_of.get(&v).cloned().unwrap_or_default();
                self.if_(d, test, &arms, &extras);
                return;
            }
            Inst::Select {
                cmp,
                a,
                b,
                then,
                otherwise,
            } => {
                let (a, b) = (self.reg(a), self.reg(b));
                let (then, otherwise) = (self.reg(then), self.reg(otherwise));
                Op::Select {
                    d: self.reg(v),
                    cmp,
                    a,
                    b,
                    then,
                    otherwise,
                }
            }
            Inst::Partial {
                func,
                wrt,
                ref args,
            } => {
                let start = self.arg_list(args);
                Op::Partial {
                    d: self.reg(v),
                    args: start,
                    n: args.len().min(crate::ir::MAX_CALL_ARGS) as u32,
                    wrt,
                    func,
                }
            }
            Inst::Var(slot) => return self.load(v, Input::Var(slot)),
            Inst::Time => return self.load(v, Input::Time),
            Inst::Mode => return self.load(v, Input::Mode),
            Inst::Measure(slot) => return self.load(v, Input::Measure(slot)),
            Inst::Neg(a) => {
                let a = self.reg(a);
                Op::Neg { d: self.reg(v), a }
            }
            Inst::Sqrt(a) => {
                let a = self.reg(a);
                Op::Sqrt { d: self.reg(v), a }
            }
            // Handled above.
            Inst::Add(..) | Inst::Sub(..) | Inst::Mul(..) | Inst::Div(..) => return,
            Inst::Call(func, args) => self.call(v, func, &args),
            Inst::Spline {
                kind,
                x,
                z,
                spline,
                iord,
            } => {
                let (x, z) = (self.reg(x), self.reg(z));
                Op::Spline {
                    d: self.reg(v),
                    x,
                    z,
                    spline,
                    iord,
                    akima: kind == SplineKind::Akima,
                }
            }
        };
        self.ops.push(op);
    }

    /// An input of the context: an op where the IR reads it (trace mode), or a load
    /// before the first op (fast mode).
    fn load(&mut self, v: Value, from: Input) {
        let d = self.reg(v);
        match self.mode {
            Mode::Fast => self.inputs.push(d, from),
            Mode::Trace => self.ops.push(Op::Load { d, from }),
        }
    }

    /// A binary operation: left out when its one reader will compute it, fused with an
    /// operand left out so, or plain.
    fn binary(&mut self, v: Value, bin: Bin, a: Value, b: Value) {
        let inner = [a, b]
            .into_iter()
            .enumerate()
            .find(|&(_, x)| self.pending[x as usize]);
        let Some((side, x)) = inner else {
            if self.fusion.folds(v) {
                self.pending[v as usize] = true;
            } else {
                self.plain(v, bin, a, b);
            }
            return;
        };
        self.pending[x as usize] = false;
        let other = if side == 0 { b } else { a };
        if self.pending[other as usize] {
            // Both operands were left out: the right one is computed on its own first
            // (none of its operands was left out, or it would not have been).
            self.pending[other as usize] = false;
            if let Some((ob, oa, obb)) = binary(self.f.inst(other)) {
                self.plain(other, ob, oa, obb);
            }
        }
        // Only binary operations are ever left out.
        let (inner_bin, xa, xb) = binary(self.f.inst(x)).unwrap_or((Bin::Add, x, x));
        let t = Tri {
            a: self.reg(xa),
            b: self.reg(xb),
            c: self.reg(other),
            d: self.reg(v),
        };
        self.ops.push(bin.fused(inner_bin, side == 0, t));
    }

    /// `v = a • b` as one op.
    fn plain(&mut self, v: Value, bin: Bin, a: Value, b: Value) {
        let (a, b) = (self.reg(a), self.reg(b));
        let op = bin.op(self.reg(v), a, b);
        self.ops.push(op);
    }

    fn call(&mut self, v: Value, func: Func, args: &[Value]) -> Op {
        if let Some(op) = self.bound_call(v, func, args) {
            return op;
        }
        let callee = func.callee();
        if let Callee::Series2(_) | Callee::Series3(_) = callee {
            return self.series(v, func, callee, args);
        }
        let regs: Vec<u32> = args.iter().map(|&a| self.reg(a)).collect();
        let d = self.reg(v);
        let start = self.arg_regs.len() as u32;
        match (callee, regs.as_slice()) {
            (Callee::F1(f), &[a]) => Op::Call1 { d, a, f },
            (Callee::F2(f), &[a, b]) => Op::Call2 { d, a, b, f },
            (callee, _) => {
                self.arg_regs.extend(&regs);
                match callee {
                    Callee::F5(f) => Op::Call5 { d, args: start, f },
                    Callee::F6(f) => Op::Call6 { d, args: start, f },
                    Callee::F7(f) => Op::Call7 { d, args: start, f },
                    Callee::F8(f) => Op::Call8 { d, args: start, f },
                    // The checker builds every call with its function's arity.
                    _ => Op::Call5 {
                        d,
                        args: start,
                        f: |_, _, _, _, _| f64::NAN,
                    },
                }
            }
        }
    }

    /// The specialised forms of a call: ABS and SQRT as single operations, the steps and
    /// contact functions with constant parameters checked once. `None` for a plain call.
    fn bound_call(&mut self, v: Value, func: Func, args: &[Value]) -> Option<Op> {
        let consts =
            |vs: &[Value]| -> Option<Vec<f64>> { vs.iter().map(|&c| self.f.constant(c)).collect() };
        let op = match (func, args) {
            (Func::Abs, &[a]) => Op::Abs {
                a: self.reg(a),
                d: self.reg(v),
            },
            (Func::Sqrt, &[a]) => Op::Sqrt {
                a: self.reg(a),
                d: self.reg(v),
            },
            (Func::Step | Func::Step5 | Func::Havsin, &[x, ref params @ ..]) => {
                let &[x0, h0, x1, h1] = consts(params)?.as_slice() else {
                    return None;
                };
                let params = StepParams::new(x0, h0, x1, h1)?;
                let p = Box::new(params);
                let (x, d) = (self.reg(x), self.reg(v));
                match func {
                    Func::Step => Op::Step { d, x, p },
                    Func::Step5 => Op::StepFn {
                        d,
                        x,
                        p,
                        f: StepParams::step5,
                    },
                    _ => Op::StepFn {
                        d,
                        x,
                        p,
                        f: StepParams::havsin,
                    },
                }
            }
            (Func::Impact, &[x, xd, ref params @ ..]) => {
                let &[x1, k, e, cmax, dd] = consts(params)?.as_slice() else {
                    return None;
                };
                let params = Impact::new(x1, k, e, cmax, dd)?;
                let p = Box::new(params);
                let (x, xd, d) = (self.reg(x), self.reg(xd), self.reg(v));
                Op::Impact { d, x, xd, p }
            }
            (Func::Bistop, &[x, xd, ref params @ ..]) => {
                let &[x1, x2, k, e, cmax, dd] = consts(params)?.as_slice() else {
                    return None;
                };
                let params = Bistop::new(x1, x2, k, e, cmax, dd)?;
                let p = Box::new(params);
                let (x, xd, d) = (self.reg(x), self.reg(xd), self.reg(v));
                Op::Bistop { d, x, xd, p }
            }
            (Func::Poly, &[x, x0, ref coeffs @ ..]) if coeffs.len() <= MAX_COEFFICIENTS => {
                let coeffs = consts(coeffs)?.into_boxed_slice();
                let (x, x0, d) = (self.reg(x), self.reg(x0), self.reg(v));
                Op::Poly { d, x, x0, coeffs }
            }
            _ => return None,
        };
        Some(op)
    }

    /// A series call: x, x0 (and w for FORCOS/FORSIN) as registers, and the coefficients
    /// from the constant pool when all are constant.
    fn series(&mut self, v: Value, func: Func, callee: Callee, args: &[Value]) -> Op {
        let (head, coeffs) = args.split_at(func.fixed_args().min(args.len()));
        // POLY and CHEBY repeat x0 in the third slot.
        let mut head = head.to_vec();
        while head.len() < 3 {
            head.push(head.last().copied().unwrap_or(0));
        }
        let start = self.arg_list(&head);
        let constants: Option<Vec<f64>> = coeffs.iter().map(|&c| self.f.constant(c)).collect();
        let n = coeffs.len().min(MAX_COEFFICIENTS) as u32;
        let coeffs = match constants {
            Some(values) => {
                let at = self.pool.len() as u32;
                self.pool.extend(values);
                Coeffs::Pool { start: at, n }
            }
            None => Coeffs::Regs {
                start: self.arg_list(coeffs),
                n,
            },
        };
        let f = match callee {
            Callee::Series3(f) => SeriesFn::Three(f),
            Callee::Series2(f) => SeriesFn::Two(f),
            _ => SeriesFn::Two(|_, _, _| f64::NAN),
        };
        Op::Series {
            d: self.reg(v),
            args: start,
            call: Box::new(SeriesCall { coeffs, f }),
        }
    }

    /// An IF: the arms one after another, each moving its results into the IF's registers
    /// and jumping to the end; a NaN test jumps to a tail that sets the extra results to
    /// NaN (the `If` op itself sets `d`).
    ///
    /// In fast mode an arm's result that an op of the arm computes and nothing else reads
    /// is computed straight into the IF's register (the arms exclude each other, and nothing
    /// inside them reads the IF's own value), which saves the move.
    fn if_(&mut self, d: u32, test: Test, arms: &[Block; 3], extras: &[Value]) {
        let at = self.ops.len();
        self.ops.push(Op::Jump { to: 0 });
        let targets: Vec<u32> = extras.iter().map(|&x| self.reg(x)).collect();
        let mut starts = [0u32; 3];
        let mut jumps = Vec::new();
        for (i, arm) in arms.iter().enumerate() {
            starts[i] = self.here();
            let r = arm.result as usize;
            // Not an input (loaded before the first op, not in the arm) nor an IF's extra
            // result (written by that IF's moves).
            let computed = !matches!(
                self.f.inst(arm.result),
                Inst::Var(_) | Inst::Time | Inst::Mode | Inst::Measure(_) | Inst::IfExtra { .. }
            );
            let in_arm = arm
                .insts
                .first()
                .is_some_and(|&first| self.fusion.same_block(first, arm.result));
            if computed
                && in_arm
                && self.fusion.read_once(arm.result)
                && self.reg_of[r] == UNASSIGNED
            {
                self.reg_of[r] = d;
            }
            self.list(&arm.insts);
            let a = self.reg(arm.result);
            if a != d {
                self.ops.push(Op::Move { d, a });
            }
            for (&t, &x) in targets.iter().zip(&arm.extra) {
                let a = self.reg(x);
                self.ops.push(Op::Move { d: t, a });
            }
            if i < 2 || !targets.is_empty() {
                jumps.push(self.ops.len());
                self.ops.push(Op::Jump { to: 0 });
            }
        }
        let nan_tail = self.here();
        if !targets.is_empty() {
            let nan = self.template.len() as u32;
            self.template.push(f64::NAN);
            for &t in &targets {
                self.ops.push(Op::Move { d: t, a: nan });
            }
        }
        let end = self.here();
        for j in jumps {
            self.ops[j] = Op::Jump { to: end };
        }
        self.ops[at] = match test {
            Test::Reg(test) => Op::If {
                d,
                test,
                arms: starts,
                end: nan_tail,
            },
            Test::Sub(a, b) => Op::IfSub {
                d,
                a,
                b,
                arms: starts,
                end: nan_tail,
            },
        };
    }
}

/// The test of an IF: a register, or a difference computed by the IF op.
#[derive(Clone, Copy)]
enum Test {
    Reg(u32),
    Sub(u32, u32),
}

/// Points every jump and IF target that lands on a jump at that jump's own target, so a
/// nested IF's arm leaves all its IFs at once.
fn thread_jumps(ops: &mut [Op]) {
    let resolve = |ops: &[Op], mut to: u32| {
        // Jumps only go forward, so the chain ends.
        while let Some(&Op::Jump { to: next }) = ops.get(to as usize) {
            to = next;
        }
        to
    };
    for i in 0..ops.len() {
        let new = match ops[i] {
            Op::Jump { to } => Op::Jump {
                to: resolve(ops, to),
            },
            Op::If { d, test, arms, end } => Op::If {
                d,
                test,
                arms: arms.map(|a| resolve(ops, a)),
                end: resolve(ops, end),
            },
            Op::IfSub { d, a, b, arms, end } => Op::IfSub {
                d,
                a,
                b,
                arms: arms.map(|t| resolve(ops, t)),
                end: resolve(ops, end),
            },
            _ => continue,
        };
        ops[i] = new;
    }
}
