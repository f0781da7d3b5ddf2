//! Builds a [`Function`] instruction by instruction, folding constants and sharing
//! common subexpressions.
//!
//! Folding evaluates with the very operations the back ends execute (IEEE `+ - * /`,
//! `sqrt`, and [`Func::eval`] for library calls), so a folded constant has the bits the
//! unfolded code would produce. Sharing is scoped: a value computed inside an IF arm is
//! visible only there, never hoisted out of the arm (that would evaluate it eagerly).

use super::{Block, Cmp, Function, Inst, Uses, Value};
use crate::diag::Span;
use crate::vocab::builtins::SplineKind;
use crate::vocab::func::Func;
use rustc_hash::FxHashMap;

/// Hashable identity of an instruction, for sharing. IF is never shared.
#[derive(Clone, PartialEq, Eq, Hash)]
enum Key {
    Var(u32),
    Time,
    Mode,
    Measure(u32),
    Neg(Value),
    Add(Value, Value),
    Sub(Value, Value),
    Mul(Value, Value),
    Div(Value, Value),
    Sqrt(Value),
    Call(Func, Box<[Value]>),
    Spline(SplineKind, Value, Value, u32, u8),
    Select(Cmp, Value, Value, Value, Value),
    Partial(Func, u32, Box<[Value]>),
}

/// Incrementally builds one function.
pub struct Builder {
    f: Function,
    consts: FxHashMap<u64, Value>,
    /// Shared instructions of every open block.
    shared: FxHashMap<Key, Value>,
    /// Keys added to `shared`, with the block depth they belong to; closing a block
    /// removes its keys (a scoped table without a map per block).
    added: Vec<(usize, Key)>,
    /// Instruction list of each open block, innermost last.
    lists: Vec<Vec<Value>>,
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

impl Builder {
    /// An empty builder.
    pub fn new() -> Self {
        Builder {
            f: Function::default(),
            consts: FxHashMap::default(),
            shared: FxHashMap::default(),
            added: Vec::new(),
            lists: vec![Vec::new()],
        }
    }

    /// Starts a new function, keeping the buffers of the last one (a caller building many
    /// functions allocates only for what each function keeps).
    pub fn clear(&mut self) {
        self.f.insts.clear();
        self.f.spans.clear();
        self.f.outputs.clear();
        self.consts.clear();
        self.shared.clear();
        self.added.clear();
        self.lists.truncate(1);
        self.lists.iter_mut().for_each(Vec::clear);
        if self.lists.is_empty() {
            self.lists.push(Vec::new());
        }
    }

    fn push(&mut self, inst: Inst, span: Span) -> Value {
        let v = self.f.insts.len() as Value;
        self.f.insts.push(inst);
        self.f.spans.push(span);
        v
    }

    /// A constant (constants belong to no block).
    pub fn constant(&mut self, c: f64, span: Span) -> Value {
        if let Some(&v) = self.consts.get(&c.to_bits()) {
            return v;
        }
        let v = self.push(Inst::Const(c), span);
        self.consts.insert(c.to_bits(), v);
        v
    }

    /// The constant `v` holds, if it is one.
    pub fn get_const(&self, v: Value) -> Option<f64> {
        self.f.constant(v)
    }

    fn emit(&mut self, key: Key, inst: Inst, span: Span) -> Value {
        if let Some(&v) = self.shared.get(&key) {
            return v;
        }
        let v = self.push(inst, span);
        if let Some(list) = self.lists.last_mut() {
            list.push(v);
        }
        if self.lists.len() > 1 {
            self.added.push((self.lists.len(), key.clone()));
        }
        self.shared.insert(key, v);
        v
    }

    /// Reads user variable `slot`.
    pub fn var(&mut self, slot: u32, span: Span) -> Value {
        self.emit(Key::Var(slot), Inst::Var(slot), span)
    }

    /// Reads `TIME`.
    pub fn time(&mut self, span: Span) -> Value {
        self.emit(Key::Time, Inst::Time, span)
    }

    /// Reads `MODE`.
    pub fn mode(&mut self, span: Span) -> Value {
        self.emit(Key::Mode, Inst::Mode, span)
    }

    /// Reads measure `slot`.
    pub fn measure(&mut self, slot: u32, span: Span) -> Value {
        self.emit(Key::Measure(slot), Inst::Measure(slot), span)
    }

    /// −a, folded when a is constant.
    pub fn neg(&mut self, a: Value, span: Span) -> Value {
        match self.get_const(a) {
            Some(x) => self.constant(-x, span),
            None => self.emit(Key::Neg(a), Inst::Neg(a), span),
        }
    }

    /// √a, folded when a is constant.
    pub fn sqrt(&mut self, a: Value, span: Span) -> Value {
        match self.get_const(a) {
            Some(x) => self.constant(x.sqrt(), span),
            None => self.emit(Key::Sqrt(a), Inst::Sqrt(a), span),
        }
    }

    /// `+ - * /` on two scalars. Operands of the commutative ones are ordered so that
    /// `a*b` and `b*a` share one instruction (IEEE `+` and `*` are commutative).
    pub fn arith(&mut self, op: Arith, a: Value, b: Value, span: Span) -> Value {
        if let (Some(x), Some(y)) = (self.get_const(a), self.get_const(b)) {
            return self.constant(op.apply(x, y), span);
        }
        let (ca, cb) = if matches!(op, Arith::Add | Arith::Mul) && a > b {
            (b, a)
        } else {
            (a, b)
        };
        let (key, inst) = match op {
            Arith::Add => (Key::Add(ca, cb), Inst::Add(ca, cb)),
            Arith::Sub => (Key::Sub(a, b), Inst::Sub(a, b)),
            Arith::Mul => (Key::Mul(ca, cb), Inst::Mul(ca, cb)),
            Arith::Div => (Key::Div(a, b), Inst::Div(a, b)),
        };
        self.emit(key, inst, span)
    }

    /// A library call; folded when every argument is constant.
    pub fn call(&mut self, func: Func, args: Vec<Value>, span: Span) -> Value {
        let consts: Option<Vec<f64>> = args.iter().map(|&a| self.get_const(a)).collect();
        if let Some(c) = consts {
            return self.constant(func.eval(&c), span);
        }
        let args = args.into_boxed_slice();
        self.emit(Key::Call(func, args.clone()), Inst::Call(func, args), span)
    }

    /// `if a <cmp> b { then } else { otherwise }`; chosen at build time when the test is
    /// constant or both choices are the same value.
    pub fn select(
        &mut self,
        cmp: Cmp,
        a: Value,
        b: Value,
        then: Value,
        otherwise: Value,
        span: Span,
    ) -> Value {
        if then == otherwise {
            return then;
        }
        if let (Some(x), Some(y)) = (self.get_const(a), self.get_const(b)) {
            return if cmp.test(x, y) { then } else { otherwise };
        }
        let inst = Inst::Select {
            cmp,
            a,
            b,
            then,
            otherwise,
        };
        self.emit(Key::Select(cmp, a, b, then, otherwise), inst, span)
    }

    /// ∂func/∂(argument `wrt`) at `args`; folded when every argument is constant.
    pub fn partial(&mut self, func: Func, wrt: u32, args: &[Value], span: Span) -> Value {
        let consts: Option<Vec<f64>> = args.iter().map(|&a| self.get_const(a)).collect();
        if let Some(c) = consts {
            return self.constant(func.partial(wrt as usize, &c), span);
        }
        let args: Box<[Value]> = args.into();
        let key = Key::Partial(func, wrt, args.clone());
        self.emit(key, Inst::Partial { func, wrt, args }, span)
    }

    /// A spline interpolation (never folded: the data belong to the host).
    pub fn spline(
        &mut self,
        kind: SplineKind,
        x: Value,
        z: Value,
        spline: u32,
        iord: u8,
        span: Span,
    ) -> Value {
        let key = Key::Spline(kind, x, z, spline, iord);
        self.emit(
            key,
            Inst::Spline {
                kind,
                x,
                z,
                spline,
                iord,
            },
            span,
        )
    }

    /// Opens a nested block (an IF arm).
    pub fn begin_block(&mut self) {
        self.lists.push(Vec::new());
    }

    /// Closes the innermost block, yielding `result`.
    pub fn end_block(&mut self, result: Value) -> Block {
        let depth = self.lists.len();
        while self.added.last().is_some_and(|(d, _)| *d == depth) {
            if let Some((_, key)) = self.added.pop() {
                self.shared.remove(&key);
            }
        }
        Block {
            insts: self.lists.pop().unwrap_or_default(),
            result,
            extra: Vec::new(),
        }
    }

    /// Closes the innermost block yielding several results (the first is its `result`).
    pub fn end_block_multi(&mut self, results: &[Value]) -> Block {
        let mut block = self.end_block(results.first().copied().unwrap_or(0));
        block.extra = results.iter().skip(1).copied().collect();
        block
    }

    /// An IF whose arms yield several results (see [`Builder::end_block_multi`]): the IF's
    /// value, then an [`Inst::IfExtra`] for each further result.
    pub fn if_multi(&mut self, test: Value, arms: [Block; 3], span: Span) -> Vec<Value> {
        let n = arms[0].extra.len() as u32;
        if let Some(i) = self.get_const(test).and_then(super::if_arm) {
            let [a, b, c] = arms;
            let arm = [a, b, c].into_iter().nth(i).unwrap_or_default();
            if let Some(list) = self.lists.last_mut() {
                list.extend_from_slice(&arm.insts);
            }
            return std::iter::once(arm.result).chain(arm.extra).collect();
        }
        let first = self.if_(test, arms, span.clone());
        let mut all = vec![first];
        for index in 0..n {
            let v = self.push(Inst::IfExtra { of: first, index }, span.clone());
            if let Some(list) = self.lists.last_mut() {
                list.push(v);
            }
            all.push(v);
        }
        all
    }

    /// An arithmetic IF over three finished arms. A constant test selects its arm at
    /// build time: the arm's instructions join the current block.
    pub fn if_(&mut self, test: Value, arms: [Block; 3], span: Span) -> Value {
        if let Some(t) = self.get_const(test) {
            let pick = super::if_arm(t);
            if let Some(i) = pick {
                let [a, b, c] = arms;
                let arm = [a, b, c].into_iter().nth(i).unwrap_or_default();
                if let Some(list) = self.lists.last_mut() {
                    list.extend_from_slice(&arm.insts);
                }
                return arm.result;
            }
        }
        let v = self.push(
            Inst::If {
                test,
                arms: Box::new(arms),
            },
            span,
        );
        if let Some(list) = self.lists.last_mut() {
            list.push(v);
        }
        v
    }

    /// Finishes the function with its outputs. The function gets buffers of its own, of
    /// exactly its size; the builder keeps its buffers for the next function ([`clear`]).
    ///
    /// [`clear`]: Builder::clear
    pub fn finish(&mut self, outputs: &[Value]) -> Function {
        /// Moves the elements into a vector of exactly their number (one copy, no growth).
        fn exact<T>(from: &mut Vec<T>) -> Vec<T> {
            let mut to = Vec::with_capacity(from.len());
            to.append(from);
            to
        }
        let mut f = Function {
            insts: exact(&mut self.f.insts),
            spans: exact(&mut self.f.spans),
            body: self.lists.first().cloned().unwrap_or_default(),
            outputs: outputs.to_vec(),
            uses: Uses::default(),
        };
        f.uses = collect_uses(&f);
        self.clear();
        f
    }
}

/// The four arithmetic operators, with the IEEE operation each denotes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arith {
    /// x + y.
    Add,
    /// x − y.
    Sub,
    /// x × y.
    Mul,
    /// x ÷ y.
    Div,
}

impl Arith {
    /// The operation on `x` and `y`, IEEE rounded.
    pub fn apply(self, x: f64, y: f64) -> f64 {
        match self {
            Arith::Add => x + y,
            Arith::Sub => x - y,
            Arith::Mul => x * y,
            Arith::Div => x / y,
        }
    }
}

/// What a finished function reads, walking only reachable instructions.
pub(crate) fn collect_uses(f: &Function) -> Uses {
    let mut uses = Uses::default();
    // Arms of IFs still to walk; most functions have none, so this rarely allocates.
    let mut stack: Vec<&[Value]> = Vec::new();
    let mut next: Option<&[Value]> = Some(&f.body);
    while let Some(list) = next {
        for &v in list {
            match f.inst(v) {
                Inst::Time => uses.time = true,
                Inst::Mode => uses.mode = true,
                Inst::Var(s) => uses.vars.push(*s),
                Inst::Measure(s) => uses.measures.push(*s),
                Inst::Spline { spline, .. } => uses.splines.push(*spline),
                Inst::If { arms, .. } => stack.extend(arms.iter().map(|a| a.insts.as_slice())),
                _ => {}
            }
        }
        next = stack.pop();
    }
    for list in [&mut uses.vars, &mut uses.measures, &mut uses.splines] {
        list.sort_unstable();
        list.dedup();
    }
    uses
}
