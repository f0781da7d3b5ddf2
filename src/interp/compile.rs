//! Lowers IR to the interpreter's bytecode: registers = IR values, IF arms laid out
//! one after another with jumps to a common end.

use super::{Op, Program};
use crate::check::builtins::SplineKind;
use crate::ir::{Block, Func, Function, Inst, Value};

/// Most arguments one call can have (BISTOP's 8, or a series' 3 + 31 coefficients).
pub const MAX_CALL_ARGS: usize = 40;

struct Emitter<'f> {
    f: &'f Function,
    ops: Vec<Op>,
    arg_regs: Vec<u32>,
}

pub fn compile(function: Function) -> Program {
    let mut template = vec![0.0; function.insts.len()];
    for (i, inst) in function.insts.iter().enumerate() {
        if let Inst::Const(c) = inst {
            template[i] = *c;
        }
    }
    let mut e = Emitter {
        f: &function,
        ops: Vec::new(),
        arg_regs: Vec::new(),
    };
    e.list(&function.body);
    let (ops, arg_regs) = (e.ops, e.arg_regs);
    Program {
        ops,
        template,
        arg_regs,
        outputs: function.outputs.clone(),
        function,
    }
}

fn unary(func: Func) -> Option<fn(f64) -> f64> {
    use mbfx_runtime as rt;
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
    use mbfx_runtime as rt;
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

impl Emitter<'_> {
    fn list(&mut self, values: &[Value]) {
        for &v in values {
            self.inst(v);
        }
    }

    fn here(&self) -> u32 {
        self.ops.len() as u32
    }

    fn inst(&mut self, v: Value) {
        let d = v;
        let op = match self.f.inst(v) {
            Inst::Const(_) => return,
            Inst::Var(slot) => Op::Var { d, slot: *slot },
            Inst::Time => Op::Time { d },
            Inst::Mode => Op::Mode { d },
            Inst::Measure(slot) => Op::Measure { d, slot: *slot },
            Inst::Neg(a) => Op::Neg { d, a: *a },
            Inst::Add(a, b) => Op::Add { d, a: *a, b: *b },
            Inst::Sub(a, b) => Op::Sub { d, a: *a, b: *b },
            Inst::Mul(a, b) => Op::Mul { d, a: *a, b: *b },
            Inst::Div(a, b) => Op::Div { d, a: *a, b: *b },
            Inst::Sqrt(a) => Op::Sqrt { d, a: *a },
            Inst::Call(func, args) => match (args.len(), unary(*func), binary(*func)) {
                (1, Some(f), _) => Op::Call1 { d, a: args[0], f },
                (2, _, Some(f)) => Op::Call2 {
                    d,
                    a: args[0],
                    b: args[1],
                    f,
                },
                _ => {
                    let start = self.arg_regs.len() as u32;
                    self.arg_regs.extend_from_slice(args);
                    Op::CallN {
                        d,
                        func: *func,
                        args: start,
                        n: args.len().min(MAX_CALL_ARGS) as u32,
                    }
                }
            },
            Inst::Spline {
                kind,
                x,
                z,
                spline,
                iord,
            } => Op::Spline {
                d,
                x: *x,
                z: *z,
                spline: *spline,
                iord: *iord,
                akima: *kind == SplineKind::Akima,
            },
            Inst::If { test, arms } => {
                self.if_(d, *test, arms);
                return;
            }
        };
        self.ops.push(op);
    }

    fn if_(&mut self, d: u32, test: u32, arms: &[Block; 3]) {
        let at = self.ops.len();
        self.ops.push(Op::Jump { to: 0 });
        let mut starts = [0u32; 3];
        let mut jumps = Vec::new();
        for (i, arm) in arms.iter().enumerate() {
            starts[i] = self.here();
            self.list(&arm.insts);
            self.ops.push(Op::Move { d, a: arm.result });
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
