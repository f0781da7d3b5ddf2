//! Stack growth for recursive passes over syntax trees.
//!
//! Trees may be as deep as [`crate::syntax::parser::MAX_TREE_DEPTH`]; a recursive pass
//! calls [`guard`] at each level, which moves onto a fresh heap-allocated stack segment
//! when less than the red zone is left, so deep input never overflows a thread's stack.

const RED_ZONE: usize = 64 * 1024;
const NEW_SEGMENT: usize = 2 * 1024 * 1024;

/// Runs `f`, first growing the stack if it is nearly exhausted.
#[inline]
pub fn guard<R>(f: impl FnOnce() -> R) -> R {
    stacker::maybe_grow(RED_ZONE, NEW_SEGMENT, f)
}
