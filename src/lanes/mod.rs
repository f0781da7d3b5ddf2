//! The lane evaluator: one expression over many points, one instruction at a time over a
//! block of [`LANES`] points.
//!
//! The JIT's machine code computes a whole expression for one point, then the next. Over
//! a million points that spends most of its time in call overhead and in libm's range
//! reductions mispredicting branches that another function just trained. Here each IR
//! instruction runs over a block of points before the next one starts: arithmetic and
//! selects become tight loops the compiler vectorises, so do SIN, COS and ATAN2 (the
//! runtime's own, written for it), and a libm function such as `EXP` runs 128 times in
//! a row through a direct call. The IR is the JIT's (the branch-free lowering of
//! [`crate::ir::lower`]) and library calls go to `mbfx-runtime`, so the bits are the
//! interpreter's and the JIT's, point for point; `tests/backends` checks it.
//!
//! An arithmetic IF computes the sign of its test at every lane, runs each arm some lane
//! picks over the whole block (IEEE arithmetic and the runtime's functions have no traps,
//! so the lanes an arm does not own cannot be observed) and merges by lane. An arm no lane
//! picks does not run.
//!
//! Pieces: `build` (IR to nodes over lane slots), `run` (the kernels).

mod build;
mod run;

use crate::ir::Function;

/// Points a block holds: 128 × 8 bytes a slot, so the slots of a long expression stay
/// in L1.
pub const LANES: usize = 128;

/// Most lane slots a function may need (4 MiB of blocks): a larger one, such as a
/// generated expression of many thousand terms, runs point by point instead of
/// allocating its slots on every call.
pub const MAX_SLOTS: usize = 4096;

/// Deepest nesting of arithmetic IFs the lane evaluator takes (it recurses per IF);
/// deeper functions use a point-at-a-time engine.
pub const MAX_IF_DEPTH: usize = 32;

/// Slot numbers with this bit name an input ([`Source`]), not a computed slot.
const INPUT: u32 = 1 << 31;

/// What an input slot reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Source {
    /// A variable (its column).
    Var(u32),
    /// TIME.
    Time,
}

/// One input of [`Lanes::eval`]: a value for every point, or one for all.
#[derive(Clone, Copy, Debug)]
pub enum Column<'a> {
    /// The same value at every point (a broadcast scalar).
    Const(f64),
    /// One value per point.
    Values(&'a [f64]),
}

impl Column<'_> {
    /// The number of points this column fixes (None for a constant).
    pub fn points(&self) -> Option<usize> {
        match self {
            Column::Const(_) => None,
            Column::Values(v) => Some(v.len()),
        }
    }

    /// The value at point `i`.
    #[inline(always)]
    pub fn at(&self, i: usize) -> f64 {
        match self {
            Column::Const(x) => *x,
            Column::Values(v) => v[i],
        }
    }
}

/// A function ready for the lane evaluator.
#[derive(Clone, Debug)]
pub struct Lanes {
    code: build::Code,
    /// Lane slots the code needs.
    slots: usize,
    /// Slots holding a constant (filled once per call).
    consts: Vec<(u32, f64)>,
    /// What each input slot reads: slot `INPUT | k` is `inputs[k]`, read where the
    /// column lies.
    inputs: Vec<Source>,
    /// Slot of each output.
    outputs: Vec<u32>,
}

impl Lanes {
    /// Compiles `f` for the lane evaluator. None when it reads what a column cannot give
    /// (measures, splines, MODE), nests IFs deeper than [`MAX_IF_DEPTH`] or needs more
    /// than [`MAX_SLOTS`] slots.
    pub fn new(f: &Function) -> Option<Lanes> {
        build::build(f)
    }

    /// Values per point.
    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Evaluates at `n` points: `columns` holds the function's variables in slot order,
    /// each a constant or `n` values, and `time` TIME. `out` receives n·outputs values,
    /// point after point. False, with nothing written, when a column is too short, a
    /// variable slot has no column or `out` has the wrong length.
    pub fn eval(&self, columns: &[Column], time: Column, n: usize, out: &mut [f64]) -> bool {
        let fits = |c: &Column| c.points().is_none_or(|len| len >= n);
        let covered = self.inputs.iter().all(|source| match source {
            Source::Var(k) => columns.get(*k as usize).is_some_and(fits),
            Source::Time => true,
        });
        if !covered || !fits(&time) || out.len() != n * self.outputs.len() {
            return false;
        }
        self.run(columns, time, n, out);
        true
    }
}

#[cfg(test)]
mod tests;
