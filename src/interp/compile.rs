//! Lowers IR to the interpreter's bytecode. Registers are allocated only for the values
//! the code reaches (constants included, preloaded in the template); IF arms are laid out
//! one after another with jumps to a common end; library calls get an op per arity so no
//! argument buffer is built at run time, and constant coefficient lists of series are
//! passed straight from a pool.

use super::{Coeffs, Op, Program, SeriesFn};
use crate::ir::{Block, Function, Inst, Value};
use crate::vocab::builtins::SplineKind;
use crate::vocab::func::{Callee, Func};

/// Most coefficients a series call takes (spec §5.6–5.8).
pub const MAX_COEFFICIENTS: usize = 31;

const UNASSIGNED: u32 = u32::MAX;

struct Emitter<'f> {
    f: &'f Function,
    ops: Vec<Op>,
    arg_regs: Vec<u32>,
    pool: Vec<f64>,
    /// Register of each IR value, or UNASSIGNED.
    reg_of: Vec<u32>,
    template: Vec<f64>,
    /// The [`Inst::IfExtra`] values of each multi-result IF, by IF value, in index order.
    extras_of: rustc_hash::FxHashMap<Value, Vec<Value>>,
}

pub fn compile(function: Function) -> Program {
    let mut e = Emitter {
        f: &function,
        ops: Vec::new(),
        arg_regs: Vec::new(),
        pool: Vec::new(),
        reg_of: vec![UNASSIGNED; function.insts.len()],
        template: Vec::new(),
        extras_of: extras_of(&function),
    };
    e.list(&function.body);
    let outputs: Vec<u32> = function.outputs.iter().map(|&v| e.reg(v)).collect();
    let Emitter {
        ops,
        arg_regs,
        pool,
        template,
        reg_of,
        ..
    } = e;
    // Pad the register file to the size of a stack bucket (see Program::eval).
    let mut template = template;
    if let Some(&size) = [8, 16, 32, 64, super::STACK_REGS]
        .iter()
        .find(|&&s| s >= template.len())
    {
        template.resize(size, 0.0);
    }
    let uses = &function.uses;
    Program {
        ops,
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
        let op = match inst {
            Inst::Const(_) | Inst::IfExtra { .. } => return,
            Inst::If { test, arms } => {
                let (test, d) = (self.reg(test), self.reg(v));
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
            Inst::Var(slot) => Op::Var {
                d: self.reg(v),
                slot,
            },
            Inst::Time => Op::Time { d: self.reg(v) },
            Inst::Mode => Op::Mode { d: self.reg(v) },
            Inst::Measure(slot) => Op::Measure {
                d: self.reg(v),
                slot,
            },
            Inst::Neg(a) => {
                let a = self.reg(a);
                Op::Neg { d: self.reg(v), a }
            }
            Inst::Sqrt(a) => {
                let a = self.reg(a);
                Op::Sqrt { d: self.reg(v), a }
            }
            Inst::Add(a, b) | Inst::Sub(a, b) | Inst::Mul(a, b) | Inst::Div(a, b) => {
                let (a, b) = (self.reg(a), self.reg(b));
                let d = self.reg(v);
                match inst {
                    Inst::Add(..) => Op::Add { d, a, b },
                    Inst::Sub(..) => Op::Sub { d, a, b },
                    Inst::Mul(..) => Op::Mul { d, a, b },
                    _ => Op::Div { d, a, b },
                }
            }
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

    fn call(&mut self, v: Value, func: Func, args: &[Value]) -> Op {
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
            coeffs,
            f,
        }
    }

    /// An IF: the arms one after another, each moving its results into the IF's registers
    /// and jumping to the end; a NaN test jumps to a tail that sets the extra results to
    /// NaN (the `If` op itself sets `d`).
    fn if_(&mut self, d: u32, test: u32, arms: &[Block; 3], extras: &[Value]) {
        let at = self.ops.len();
        self.ops.push(Op::Jump { to: 0 });
        let targets: Vec<u32> = extras.iter().map(|&x| self.reg(x)).collect();
        let mut starts = [0u32; 3];
        let mut jumps = Vec::new();
        for (i, arm) in arms.iter().enumerate() {
            starts[i] = self.here();
            self.list(&arm.insts);
            let a = self.reg(arm.result);
            self.ops.push(Op::Move { d, a });
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
        self.ops[at] = Op::If {
            d,
            test,
            arms: starts,
            end: nan_tail,
        };
    }
}
