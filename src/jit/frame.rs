//! Frame-pointer elision for leaf functions on x86-64.
//!
//! Cranelift 0.135 gives every x86-64 function a frame, `push rbp; mov rbp, rsp` … `mov rsp,
//! rbp; pop rbp; ret`, also a leaf that never touches the stack (no setting turns it off).
//! In a solver's call loop the epilogue's `mov rsp, rbp` makes the stack pointer a
//! loop-carried dependency that the stack engine must synchronise on every call: measured
//! +0.6 ns on a 1.4 ns POLY call.
//!
//! For a function that makes no call and has one return, [`elide`] rewrites the prologue
//! into a 4-byte NOP and the epilogue into `ret` (followed by 4 unreachable bytes), so
//! the code's layout, branch targets and relocation offsets stay as they are. It checks
//! the bytes first and leaves the code alone unless all of these hold:
//! - the code starts with exactly the frame setup, not followed by `sub rsp, …` (a frame
//!   with spill slots or saved registers);
//! - the epilogue's five bytes occur exactly once: the one real epilogue of the one return
//!   (a second occurrence could be a constant, so the count must be exact).
//!
//! Without a `push`, the stack stays as the caller left it, which a leaf never reads. Our
//! entry signatures pass every argument in registers, so nothing addresses the frame
//! through `rbp`, which Cranelift never allocates as a general register.

/// `push rbp; mov rbp, rsp`.
const PROLOGUE: [u8; 4] = [0x55, 0x48, 0x89, 0xe5];
/// `mov rsp, rbp; pop rbp; ret`.
const EPILOGUE: [u8; 5] = [0x48, 0x89, 0xec, 0x5d, 0xc3];
/// `sub rsp, imm8` and `sub rsp, imm32` (REX.W 83 /5 and 81 /5).
const SUB_RSP: [[u8; 3]; 2] = [[0x48, 0x83, 0xec], [0x48, 0x81, 0xec]];
/// The 4-byte NOP (`nop dword [rax + 0]`).
const NOP4: [u8; 4] = [0x0f, 0x1f, 0x40, 0x00];

/// Removes the frame of a leaf function's x86-64 code in place; `leaf` says the function
/// makes no call and has exactly one return. Returns whether it did.
pub fn elide(code: &mut [u8], leaf: bool) -> bool {
    if !cfg!(target_arch = "x86_64") || !leaf || !code.starts_with(&PROLOGUE) {
        return false;
    }
    let after = &code[PROLOGUE.len()..];
    if SUB_RSP.iter().any(|sub| after.starts_with(sub)) {
        return false;
    }
    let mut epilogues = code
        .windows(EPILOGUE.len())
        .enumerate()
        .filter(|(_, w)| *w == EPILOGUE)
        .map(|(at, _)| at);
    let (Some(at), None) = (epilogues.next(), epilogues.next()) else {
        return false;
    };
    code[..4].copy_from_slice(&NOP4);
    code[at] = 0xc3;
    code[at + 1..at + 5].copy_from_slice(&NOP4);
    true
}

/// Whether the Cranelift function `f` makes no call and has exactly one return.
pub fn is_leaf(f: &cranelift_codegen::ir::Function) -> bool {
    let mut returns = 0;
    for block in f.layout.blocks() {
        for inst in f.layout.block_insts(block) {
            let op = f.dfg.insts[inst].opcode();
            if op.is_call() {
                return false;
            }
            returns += usize::from(op.is_return());
        }
    }
    returns == 1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A leaf body between Cranelift's prologue and epilogue, then a constant pool.
    fn framed(body: &[u8], pool: &[u8]) -> Vec<u8> {
        [&PROLOGUE[..], body, &EPILOGUE, pool].concat()
    }

    #[test]
    fn a_leaf_loses_its_frame_and_keeps_its_layout() {
        // vmulsd xmm0, xmm0, xmm0
        let body = [0xc5, 0xfb, 0x59, 0xc0];
        let mut code = framed(&body, &[1, 2, 3, 4, 5, 6, 7, 8]);
        let len = code.len();
        assert!(elide(&mut code, true) == cfg!(target_arch = "x86_64"));
        if cfg!(target_arch = "x86_64") {
            assert_eq!(code.len(), len);
            assert_eq!(&code[..4], &NOP4);
            assert_eq!(&code[4..8], &body);
            assert_eq!(&code[8..13], &[0xc3, 0x0f, 0x1f, 0x40, 0x00]);
            assert_eq!(&code[13..], &[1, 2, 3, 4, 5, 6, 7, 8]);
        }
    }

    #[test]
    fn anything_unusual_keeps_the_frame() {
        let body = [0xc5, 0xfb, 0x59, 0xc0];
        let keeps = |mut code: Vec<u8>, leaf: bool| {
            let before = code.clone();
            assert!(!elide(&mut code, leaf));
            assert_eq!(code, before);
        };
        // Not a leaf (calls, or several returns).
        keeps(framed(&body, &[]), false);
        // A frame with spill slots.
        keeps(framed(&[0x48, 0x83, 0xec, 0x10], &[]), true);
        keeps(framed(&[0x48, 0x81, 0xec, 0, 1, 0, 0], &[]), true);
        // The epilogue's bytes twice (say, in a constant): which one is real is unknown.
        keeps(framed(&body, &EPILOGUE), true);
        // No epilogue, or no prologue.
        keeps([&PROLOGUE[..], &body].concat(), true);
        keeps([&body[..], &EPILOGUE].concat(), true);
    }
}
