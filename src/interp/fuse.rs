//! Which binary operations the fast compiler folds into the one instruction that reads
//! them (a fused pair, [`super::op::Tri`]).
//!
//! A binary operation folds when its value is read exactly once (outputs, IF tests and
//! arm results count as reads), by a binary operation of the same block; a subtraction
//! also when that one read is the test of an IF of the same block. Its value then
//! needs no register: the reader computes it. Staying in the block keeps the order of the
//! remaining ops and lets the compiler settle every folded value before the block ends.

use super::op::Bin;
use crate::ir::{Function, Inst, Value};

const NONE: u32 = u32::MAX;

/// The binary operation an instruction is, with its operands.
pub(super) fn binary(inst: &Inst) -> Option<(Bin, Value, Value)> {
    Some(match *inst {
        Inst::Add(a, b) => (Bin::Add, a, b),
        Inst::Sub(a, b) => (Bin::Sub, a, b),
        Inst::Mul(a, b) => (Bin::Mul, a, b),
        Inst::Div(a, b) => (Bin::Div, a, b),
        _ => return None,
    })
}

/// The folding decision for every value of a function.
pub(super) struct Fusion {
    folds: Vec<bool>,
    /// How many times each value is read.
    reads: Vec<u32>,
    /// The block of each value (see [`blocks`]).
    block: Vec<u32>,
}

impl Fusion {
    /// Nothing folds (the fault tracer's programs).
    pub(super) fn none() -> Self {
        Fusion {
            folds: Vec::new(),
            reads: Vec::new(),
            block: Vec::new(),
        }
    }

    pub(super) fn new(f: &Function) -> Self {
        let n = f.insts.len();
        let mut reads = vec![0u32; n];
        // The reader of each value (meaningful when it has one read); NONE when that read
        // is not an instruction's operand.
        let mut reader = vec![NONE; n];
        for (u, inst) in f.insts.iter().enumerate() {
            inst.each_operand(|x| {
                reads[x as usize] += 1;
                reader[x as usize] = u as u32;
            });
            if let Inst::If { arms, .. } = inst {
                for arm in arms.iter() {
                    for &x in std::iter::once(&arm.result).chain(&arm.extra) {
                        reads[x as usize] += 1;
                        reader[x as usize] = NONE;
                    }
                }
            }
        }
        for &o in &f.outputs {
            reads[o as usize] += 1;
            reader[o as usize] = NONE;
        }
        let block = blocks(f);
        let folds = (0..n)
            .map(|v| {
                let u = reader[v];
                let Some(reader) = f.insts.get(u as usize) else {
                    return false;
                };
                reads[v] == 1
                    && block[v] == block[u as usize]
                    && match binary(&f.insts[v]) {
                        Some((Bin::Sub, ..)) => {
                            binary(reader).is_some() || matches!(reader, Inst::If { .. })
                        }
                        Some(_) => binary(reader).is_some(),
                        None => false,
                    }
            })
            .collect();
        Fusion {
            folds,
            reads,
            block,
        }
    }

    /// True when `v` is read exactly once (fast mode only; false when tracing).
    pub(super) fn read_once(&self, v: Value) -> bool {
        self.reads.get(v as usize) == Some(&1)
    }

    /// True when `a` and `b` are instructions of the same block (fast mode only).
    pub(super) fn same_block(&self, a: Value, b: Value) -> bool {
        match (self.block.get(a as usize), self.block.get(b as usize)) {
            (Some(&x), Some(&y)) => x != NONE && x == y,
            _ => false,
        }
    }

    /// True when the binary operation `v` is computed by its reader.
    pub(super) fn folds(&self, v: Value) -> bool {
        self.folds.get(v as usize).copied().unwrap_or(false)
    }
}

/// A number for the block of each value (the body is 0; values outside blocks, the
/// constants, get NONE).
fn blocks(f: &Function) -> Vec<u32> {
    let mut block = vec![NONE; f.insts.len()];
    let mut next = 0u32;
    let mut todo: Vec<&[Value]> = vec![&f.body];
    while let Some(list) = todo.pop() {
        for &v in list {
            block[v as usize] = next;
            if let Inst::If { arms, .. } = &f.insts[v as usize] {
                todo.extend(arms.iter().map(|a| a.insts.as_slice()));
            }
        }
        next += 1;
    }
    block
}
