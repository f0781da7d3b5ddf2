//! From IR to lane nodes: every IR value gets a lane slot (constants read by arithmetic
//! stay scalars), IF arms become nested code, and the runtime calls that take constant
//! parameters (IMPACT, BISTOP) check them once.

use super::{Lanes, Source, INPUT, MAX_IF_DEPTH, MAX_SLOTS};
use crate::ir::lower::{lower_with, Contacts};
use crate::ir::{Block, Cmp, Function, Inst, Value};
use crate::vocab::func::{Callee, Func};
use mbfx_runtime::{Bistop, Impact};

/// A straight run of nodes and the slots of the values it yields (result, then extras).
#[derive(Clone, Debug, Default)]
pub(super) struct Code {
    pub nodes: Vec<Node>,
    pub results: Vec<u32>,
}

/// An operand of arithmetic: a lane slot or a scalar constant.
#[derive(Clone, Copy, Debug)]
pub(super) enum Arg {
    Slot(u32),
    Const(f64),
}

/// The four binary operations.
#[derive(Clone, Copy, Debug)]
pub(super) enum Bin {
    Add,
    Sub,
    Mul,
    Div,
}

/// One instruction over a block of lanes; `d` is the slot it writes.
#[derive(Clone, Debug)]
pub(super) enum Node {
    Neg {
        d: u32,
        a: u32,
    },
    Sqrt {
        d: u32,
        a: u32,
    },
    Bin {
        op: Bin,
        d: u32,
        a: Arg,
        b: Arg,
    },
    Select {
        cmp: Cmp,
        d: u32,
        a: u32,
        b: u32,
        then: u32,
        otherwise: u32,
    },
    /// A one-argument library function.
    Call1 {
        func: Func,
        d: u32,
        a: u32,
    },
    /// A two-argument library function.
    Call2 {
        func: Func,
        d: u32,
        a: u32,
        b: u32,
    },
    /// IMPACT or BISTOP at (x, ẋ), its constant parameters checked once.
    Contact {
        d: u32,
        x: u32,
        xd: u32,
        law: Box<Law>,
    },
    /// Any other library call, its arguments gathered lane by lane.
    Call {
        func: Func,
        d: u32,
        args: Box<[u32]>,
    },
    /// ∂func/∂(argument `wrt`) at `args`.
    Partial {
        func: Func,
        wrt: u32,
        d: u32,
        args: Box<[u32]>,
    },
    /// Arithmetic IF: `dests` take the picked arm's results lane by lane (NaN where the
    /// test is NaN).
    If {
        test: u32,
        arms: Box<[Code; 3]>,
        dests: Box<[u32]>,
    },
}

/// A contact law with checked constant parameters.
#[derive(Clone, Debug)]
pub(super) enum Law {
    Impact(Impact),
    Bistop(Bistop),
}

/// Slot of a value not yet given one.
const NONE: u32 = u32::MAX;

struct Builder<'f> {
    f: &'f Function,
    slot: Vec<u32>,
    slots: u32,
    consts: Vec<(u32, f64)>,
    /// What each input slot (`INPUT | index`) reads.
    inputs: Vec<Source>,
    /// The destination slots of each IF (by IR value), for its `IfExtra` readers.
    if_dests: Vec<(Value, Box<[u32]>)>,
}

/// See [`Lanes::new`].
pub(super) fn build(f: &Function) -> Option<Lanes> {
    let uses = &f.uses;
    if uses.mode || !uses.measures.is_empty() || !uses.splines.is_empty() {
        return None;
    }
    let lowered = lower_with(f, Contacts::Calls);
    let mut b = Builder {
        f: &lowered,
        slot: vec![NONE; lowered.insts.len()],
        slots: 0,
        consts: Vec::new(),
        inputs: Vec::new(),
        if_dests: Vec::new(),
    };
    let mut code = Code::default();
    b.list(&lowered.body, &mut code.nodes, 0)?;
    let outputs = lowered
        .outputs
        .iter()
        .map(|&o| b.slot_of(o))
        .collect::<Option<Vec<u32>>>()?;
    if b.slots as usize > MAX_SLOTS {
        return None;
    }
    Some(Lanes {
        code,
        slots: b.slots as usize,
        consts: b.consts,
        inputs: b.inputs,
        outputs,
    })
}

impl Builder<'_> {
    /// The input slot reading `source` (one per source).
    fn input(&mut self, source: Source) -> u32 {
        let k = match self.inputs.iter().position(|&s| s == source) {
            Some(k) => k,
            None => {
                self.inputs.push(source);
                self.inputs.len() - 1
            }
        };
        INPUT | k as u32
    }

    fn fresh(&mut self) -> u32 {
        self.slots += 1;
        self.slots - 1
    }

    /// The slot holding `v` (a constant gets one on first use, filled once per call).
    fn slot_of(&mut self, v: Value) -> Option<u32> {
        let s = self.slot[v as usize];
        if s != NONE {
            return Some(s);
        }
        let c = self.f.constant(v)?;
        let s = self.fresh();
        self.consts.push((s, c));
        self.slot[v as usize] = s;
        Some(s)
    }

    fn arg(&mut self, v: Value) -> Option<Arg> {
        match self.f.constant(v) {
            Some(c) => Some(Arg::Const(c)),
            None => self.slot_of(v).map(Arg::Slot),
        }
    }

    fn slots_of(&mut self, values: &[Value]) -> Option<Box<[u32]>> {
        values.iter().map(|&v| self.slot_of(v)).collect()
    }

    /// Appends the nodes of `values` (a block's instructions) to `out`.
    fn list(&mut self, values: &[Value], out: &mut Vec<Node>, depth: usize) -> Option<()> {
        for &v in values {
            let f = self.f;
            let node = match f.inst(v) {
                Inst::Const(_) => continue,
                Inst::Var(k) => {
                    self.slot[v as usize] = self.input(Source::Var(*k));
                    continue;
                }
                Inst::Time => {
                    self.slot[v as usize] = self.input(Source::Time);
                    continue;
                }
                Inst::Mode | Inst::Measure(_) | Inst::Spline { .. } => return None,
                Inst::IfExtra { of, index } => {
                    let dests = &self.if_dests.iter().find(|(i, _)| i == of)?.1;
                    self.slot[v as usize] = *dests.get(*index as usize + 1)?;
                    continue;
                }
                Inst::If { test, arms } => {
                    if depth >= MAX_IF_DEPTH {
                        return None;
                    }
                    let test = self.slot_of(*test)?;
                    let mut codes: [Code; 3] = Default::default();
                    for (code, arm) in codes.iter_mut().zip(arms.iter()) {
                        *code = self.arm(arm, depth + 1)?;
                    }
                    let dests: Box<[u32]> =
                        (0..codes[0].results.len()).map(|_| self.fresh()).collect();
                    self.if_dests.push((v, dests.clone()));
                    self.slot[v as usize] = dests[0];
                    out.push(Node::If {
                        test,
                        arms: Box::new(codes),
                        dests,
                    });
                    continue;
                }
                inst => {
                    let d = self.fresh();
                    self.slot[v as usize] = d;
                    self.node(inst, d)?
                }
            };
            out.push(node);
        }
        Some(())
    }

    fn arm(&mut self, arm: &Block, depth: usize) -> Option<Code> {
        let mut code = Code::default();
        self.list(&arm.insts, &mut code.nodes, depth)?;
        let results: Vec<Value> = std::iter::once(arm.result)
            .chain(arm.extra.iter().copied())
            .collect();
        code.results = self.slots_of(&results)?.into_vec();
        Some(code)
    }

    /// The node of a plain instruction that writes slot `d`.
    fn node(&mut self, inst: &Inst, d: u32) -> Option<Node> {
        Some(match inst {
            Inst::Neg(a) => {
                let a = self.slot_of(*a)?;
                Node::Neg { d, a }
            }
            Inst::Sqrt(a) => {
                let a = self.slot_of(*a)?;
                Node::Sqrt { d, a }
            }
            Inst::Add(a, b) | Inst::Sub(a, b) | Inst::Mul(a, b) | Inst::Div(a, b) => {
                let op = match inst {
                    Inst::Add(..) => Bin::Add,
                    Inst::Sub(..) => Bin::Sub,
                    Inst::Mul(..) => Bin::Mul,
                    _ => Bin::Div,
                };
                let (a, b) = (self.arg(*a)?, self.arg(*b)?);
                Node::Bin { op, d, a, b }
            }
            Inst::Select {
                cmp,
                a,
                b,
                then,
                otherwise,
            } => {
                let cmp = *cmp;
                let (a, b) = (self.slot_of(*a)?, self.slot_of(*b)?);
                let (then, otherwise) = (self.slot_of(*then)?, self.slot_of(*otherwise)?);
                Node::Select {
                    cmp,
                    d,
                    a,
                    b,
                    then,
                    otherwise,
                }
            }
            Inst::Call(func, args) => self.call(*func, args, d)?,
            Inst::Partial { func, wrt, args } => {
                let (func, wrt) = (*func, *wrt);
                let args = self.slots_of(args)?;
                Node::Partial { func, wrt, d, args }
            }
            _ => return None,
        })
    }

    fn call(&mut self, func: Func, args: &[Value], d: u32) -> Option<Node> {
        let consts = |vs: &[Value]| {
            vs.iter()
                .map(|&v| self.f.constant(v))
                .collect::<Option<Vec<f64>>>()
        };
        match (func, args) {
            (Func::Impact, &[x, xd, ref params @ ..]) => {
                if let Some(&[x1, k, e, cmax, dd]) = consts(params).as_deref() {
                    if let Some(p) = Impact::new(x1, k, e, cmax, dd) {
                        let (x, xd) = (self.slot_of(x)?, self.slot_of(xd)?);
                        let law = Box::new(Law::Impact(p));
                        return Some(Node::Contact { d, x, xd, law });
                    }
                }
            }
            (Func::Bistop, &[x, xd, ref params @ ..]) => {
                if let Some(&[x1, x2, k, e, cmax, dd]) = consts(params).as_deref() {
                    if let Some(p) = Bistop::new(x1, x2, k, e, cmax, dd) {
                        let (x, xd) = (self.slot_of(x)?, self.slot_of(xd)?);
                        let law = Box::new(Law::Bistop(p));
                        return Some(Node::Contact { d, x, xd, law });
                    }
                }
            }
            _ => {}
        }
        let slots = self.slots_of(args)?;
        Some(match (func.callee(), &slots[..]) {
            (Callee::F1(_), &[a]) => Node::Call1 { func, d, a },
            (Callee::F2(_), &[a, b]) => Node::Call2 { func, d, a, b },
            _ => Node::Call {
                func,
                d,
                args: slots,
            },
        })
    }
}
