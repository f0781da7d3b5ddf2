//! Stack growth for recursive passes over syntax trees.
//!
//! Trees may be as deep as [`crate::syntax::parser::MAX_TREE_DEPTH`]; a recursive pass
//! calls [`guard`] at each level, which moves onto a fresh heap-allocated stack segment
//! when less than the red zone is left, so deep input never overflows a thread's stack.
//! Checking the stack costs a little, so hot passes check only every few levels
//! ([`every_few_levels`]): the red zone is ample for the levels in between.

const RED_ZONE: usize = 64 * 1024;
const NEW_SEGMENT: usize = 2 * 1024 * 1024;

/// Runs `f`, first growing the stack if it is nearly exhausted.
#[inline]
pub fn guard<R>(f: impl FnOnce() -> R) -> R {
    stacker::maybe_grow(RED_ZONE, NEW_SEGMENT, f)
}

/// Levels of recursion between two stack checks of [`every_few_levels`]; each level of
/// the recursive passes takes well under `RED_ZONE / LEVELS_PER_CHECK` (8 KiB) of stack,
/// even unoptimised.
const LEVELS_PER_CHECK: u32 = 8;

/// Runs `f` at recursion level `level`, checking the stack (as [`guard`] does) only at
/// every [`LEVELS_PER_CHECK`]th level.
#[inline]
pub fn every_few_levels<R>(level: u32, f: impl FnOnce() -> R) -> R {
    if level.is_multiple_of(LEVELS_PER_CHECK) {
        guard(f)
    } else {
        f()
    }
}
