//! Lowers IR to the interpreter's bytecode. Registers are allocated only for the values
//! the code reaches (constants included, preloaded in the template); IF arms are laid out
//! one after another with jumps to a common end; library calls get an op per arity so no
//! argument buffer is built at run time, and constant coefficient lists of series are
//! passed straight from a pool.

use super::{Coeffs, Op, Program, SeriesFn};
use crate::check::builtins::SplineKind;
use crate::ir::{Block, Func, Function, Inst, Value};
use mbfx_runtime as rt;

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
}

pub fn compile(function: Function) -> Program {
    let mut e = Emitter {
        f: &function,
        ops: Vec::new(),
        arg_regs: Vec::new(),
        pool: Vec::new(),
        reg_of: vec![UNASSIGNED; function.insts.len()],
        template: Vec::new(),
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

fn unary(func: Func) -> Option<fn(f64) -> f64> {
    Some(match func {
        Func::Abs => rt::abs,
        Func::Acos => rt::acos,
        Func::Asin => rt::asin,
        Func::Atan => rt::atan,
        Func::Cos => rt::cos,
        Func::Sin => rt::sin,
        Func::Tan => rt::tan,
        Func::Cosh => rt::cosh,
        Func::Sinh => rt::sinh,
        Func::Tanh => rt::tanh,
        Func::Exp => rt::exp,
        Func::Log => rt::log,
        Func::Log10 => rt::log10,
        Func::Sqrt => rt::sqrt,
        Func::Aint => rt::aint,
        Func::Anint => rt::anint,
        _ => return None,
    })
}

fn binary(func: Func) -> Option<fn(f64, f64) -> f64> {
    Some(match func {
        Func::Atan2 => rt::atan2,
        Func::Mod => rt::amod,
        Func::Sign => rt::sign,
        Func::Dim => rt::dim,
        Func::Max => rt::max,
        Func::Min => rt::min,
        Func::Pow => rt::pow,
        _ => return None,
    })
}

fn series(func: Func) -> Option<SeriesFn> {
    Some(match func {
        Func::Poly => SeriesFn::Two(rt::poly),
        Func::Cheby => SeriesFn::Two(rt::cheby),
        Func::Forcos => SeriesFn::Three(rt::forcos),
        Func::Forsin => SeriesFn::Three(rt::forsin),
        _ => return None,
    })
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
            Inst::Const(_) => return,
            Inst::If { test, arms } => {
                let (test, d) = (self.reg(test), self.reg(v));
                self.if_(d, test, &arms);
                return;
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
        if let Some(f) = series(func) {
            let fixed = func.fixed_args();
            let (head, coeffs) = args.split_at(fixed.min(args.len()));
            // x, x0 and (for FORCOS/FORSIN) w; POLY and CHEBY repeat x0 in the third slot.
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
            return Op::Series {
                d: self.reg(v),
                args: start,
                coeffs,
                f,
            };
        }
        let regs: Vec<u32> = args.iter().map(|&a| self.reg(a)).collect();
        let d = self.reg(v);
        if let (Some(f), [a]) = (unary(func), regs.as_slice()) {
            return Op::Call1 { d, a: *a, f };
        }
        if let (Some(f), [a, b]) = (binary(func), regs.as_slice()) {
            return Op::Call2 { d, a: *a, b: *b, f };
        }
        let start = self.arg_regs.len() as u32;
        self.arg_regs.extend(&regs);
        match func {
            Func::Step => Op::Call5 {
                d,
                args: start,
                f: rt::step,
            },
            Func::Step5 => Op::Call5 {
                d,
                args: start,
                f: rt::step5,
            },
            Func::Havsin => Op::Call5 {
                d,
                args: start,
                f: rt::havsin,
            },
            Func::Shf => Op::Call6 {
                d,
                args: start,
                f: rt::shf,
            },
            Func::Impact => Op::Call7 {
                d,
                args: start,
                f: rt::impact,
            },
            Func::Sweep => Op::Call7 {
                d,
                args: start,
                f: rt::sweep,
            },
            Func::Bistop => Op::Call8 {
                d,
                args: start,
                f: rt::bistop,
            },
            // Every function has an arity above; the checker never builds another call.
            _ => Op::Call5 {
                d,
                args: start,
                f: |_, _, _, _, _| f64::NAN,
            },
        }
    }

    fn if_(&mut self, d: u32, test: u32, arms: &[Block; 3]) {
        let at = self.ops.len();
        self.ops.push(Op::Jump { to: 0 });
        let mut starts = [0u32; 3];
        let mut jumps = Vec::new();
        for (i, arm) in arms.iter().enumerate() {
            starts[i] = self.here();
            self.list(&arm.insts);
            let a = self.reg(arm.result);
            self.ops.push(Op::Move { d, a });
            if i < 2 {
                jumps.push(self.ops.len());
                self.ops.push(Op::Jump { to: 0 });
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
            end,
        };
    }
}
