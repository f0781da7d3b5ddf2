//! Values that cross an arithmetic IF, kept from sinking past it.
//!
//! Cranelift's egraph pass does not keep pure instructions (arithmetic, selects) where
//! the translator emitted them: it places each one where the first side-effecting
//! instruction or branch needs it. In a sum of IFs, `a1 + a2 + ... + an` where each term
//! is a real IF (an IMPACT whose contact arm calls `pow`), only the final return needs the
//! additions, so all of them sank there and every IF result stayed live to the end of the
//! function, across every later arm and call. Register allocation then took time and
//! memory quadratic in n (3 000 IMPACT terms: 9.3 s and 1.7 GB; the code itself spilled
//! every term to the stack and summed them at the end).
//!
//! [`Crossings`] finds, at each IF, the values computed before it and read after it. The
//! translator stores each of them to a stack slot before the IF's branches and reloads it
//! in the join block: the store is a side effect, so the value is computed before the IF,
//! and the reload is a fresh value, so nothing is live across the arms (around a call it
//! would be spilled and reloaded anyway). A value is anchored at most once, at the first
//! IF it crosses (afterwards it is defined in a block that dominates the rest of its
//! list), so the work is linear in the function's size. It is anchored only at an IF in
//! whose instruction list all its later reads lie: an IF nested in another IF's arm
//! reloads into a block of that arm, which the other arms and the code after the outer IF
//! do not see (anchoring there broke SSA dominance: Cranelift's egraph pass asserted).

use crate::ir::{Function, Inst, Value};
use crate::vocab::func::Func;

/// Positions of the instructions in program order and the last read of each value.
pub struct Crossings {
    /// Position of each instruction in a walk of the body, arms in place and in order.
    pos: Vec<u32>,
    /// For an IF, the position just after its last arm.
    end: Vec<u32>,
    /// For an IF, the last position of the instruction list it stands in (its arm's jump
    /// to the join, or `u32::MAX` at the top level).
    scope: Vec<u32>,
    /// Position of the last read of each value (`u32::MAX` for an output).
    last: Vec<u32>,
    /// Translated values that may still be read after a later IF.
    pending: Vec<Value>,
}

impl Crossings {
    pub fn new(f: &Function) -> Crossings {
        let n = f.insts.len();
        let mut c = Crossings {
            pos: vec![0; n],
            end: vec![0; n],
            scope: vec![u32::MAX; n],
            last: vec![0; n],
            pending: Vec::new(),
        };
        let mut at = 0;
        c.walk(f, &f.body, &mut at);
        for &o in &f.outputs {
            c.last[o as usize] = u32::MAX;
        }
        c
    }

    fn walk(&mut self, f: &Function, list: &[Value], at: &mut u32) {
        for &v in list {
            *at += 1;
            let here = *at;
            self.pos[v as usize] = here;
            let inst = f.inst(v);
            inst.each_operand(|u| self.read(u, here));
            if let Inst::If { arms, .. } = inst {
                for arm in arms.iter() {
                    self.walk(f, &arm.insts, at);
                    // The arm's results are read by its jump to the join.
                    *at += 1;
                    let jump = *at;
                    for &w in arm.insts.iter() {
                        if matches!(f.inst(w), Inst::If { .. }) {
                            self.scope[w as usize] = jump;
                        }
                    }
                    self.read(arm.result, jump);
                    for &x in &arm.extra {
                        self.read(x, jump);
                    }
                }
                *at += 1;
                self.end[v as usize] = *at;
            }
        }
    }

    fn read(&mut self, u: Value, at: u32) {
        let last = &mut self.last[u as usize];
        *last = (*last).max(at);
    }

    /// Notes that `v` has been translated.
    pub fn defined(&mut self, f: &Function, v: Value) {
        let i = v as usize;
        if sinks(f.inst(v)) && self.last[i] > self.pos[i] {
            self.pending.push(v);
        }
    }

    /// The values to anchor at IF `v`: computed before it and read after it. They, and
    /// values no longer read, leave the pending list.
    pub fn at_if(&mut self, v: Value) -> Vec<Value> {
        let i = v as usize;
        let (start, end, scope) = (self.pos[i], self.end[i], self.scope[i]);
        let last = &self.last;
        let mut crossing = Vec::new();
        self.pending.retain(|&u| {
            let l = last[u as usize];
            if l <= start {
                return false; // no longer read
            }
            if l > end && l <= scope {
                crossing.push(u);
                return false;
            }
            // Read inside this IF, or beyond the list it stands in: a later IF decides.
            true
        });
        crossing
    }
}

/// Whether `inst` becomes a pure Cranelift instruction, which the egraph pass may move
/// (calls, loads and block parameters stay where they are).
fn sinks(inst: &Inst) -> bool {
    matches!(
        inst,
        Inst::Neg(_)
            | Inst::Add(..)
            | Inst::Sub(..)
            | Inst::Mul(..)
            | Inst::Div(..)
            | Inst::Sqrt(_)
            | Inst::Select { .. }
            | Inst::Call(Func::Abs | Func::Sqrt, _)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{self, Expect, Variables};

    fn lowered(text: &str) -> Function {
        let mut scope = Variables::new();
        scope.define("x");
        let c = check::compile(text, &scope, Expect::Scalar).expect("checks");
        crate::ir::lower::lower(&c.function)
    }

    #[test]
    fn a_running_sum_crosses_each_later_if_once() {
        // Three IMPACTs, each an IF on contact: the sum of the first two is computed
        // before the third IF and read after it; the first term (an IF result, a block
        // parameter) needs no anchor.
        let f = lowered(
            "IMPACT(x,1,0,1E5,1.5,10,0.1)*2 + IMPACT(x,1,1,1E5,1.5,10,0.1) \
             + IMPACT(x,1,2,1E5,1.5,10,0.1)",
        );
        let mut c = Crossings::new(&f);
        let mut anchored = Vec::new();
        let mut ifs = 0;
        fn visit(
            f: &Function,
            c: &mut Crossings,
            list: &[Value],
            a: &mut Vec<Value>,
            n: &mut usize,
        ) {
            for &v in list {
                if let Inst::If { arms, .. } = f.inst(v) {
                    *n += 1;
                    a.extend(c.at_if(v));
                    for arm in arms.iter() {
                        visit(f, c, &arm.insts, a, n);
                    }
                }
                c.defined(f, v);
            }
        }
        visit(&f, &mut c, &f.body, &mut anchored, &mut ifs);
        assert_eq!(ifs, 3);
        // `first*2` crosses the second IF, `first*2 + second` the third.
        assert_eq!(anchored.len(), 2, "{anchored:?}");
        assert!(anchored
            .iter()
            .all(|&v| matches!(f.inst(v), Inst::Mul(..) | Inst::Add(..))));
    }
}
