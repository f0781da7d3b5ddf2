//! The stable C entry of a compiled expression, for callers outside Rust: scipy's
//! `LowLevelCallable`, ctypes, and C solvers through `include/mbfx.h`.
//!
//! The expression's own code takes the JIT's internal arguments (the context, array
//! bases, an output pointer; `translate::expr_signature`), which change with what
//! the expression reads. The entry fixes one signature for every expression:
//!
//! ```c
//! double entry(int n, const double *x, void *out);
//! ```
//!
//! `x` holds the variables in their declared order, then TIME when `n` exceeds their
//! count (TIME is 0 otherwise); `out` receives every output when the expression has more
//! than one (a vector, a gradient) and may be NULL otherwise; the return value is the
//! first output. It is scipy's `double (int, double *, void *)`, so `quad` integrates over
//! the first variable with the others (and TIME) as its `args`. The entry checks what C
//! cannot: with `n` below the variable count, or a NULL `out` where outputs are written,
//! it returns NaN without reading or writing anything. It is a few instructions in front
//! of a direct call to the expression's code, in the same module.

use super::translate::expr_signature;
use super::JitError;
use crate::context::Context;
use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{types, AbiParam, BlockArg, InstBuilder, MemFlagsData};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::JITModule;
use cranelift_module::{FuncId, Module};

/// The C type of an entry (see the module docs).
pub type EntryFn = unsafe extern "C" fn(n: i32, x: *const f64, out: *mut f64) -> f64;

/// The entry's signature in C, as scipy's `LowLevelCallable` spells it.
pub const ENTRY_SIGNATURE: &str = "double (int, double *, void *)";

/// The context the entry hands to expressions of the general signature: MODE 4 and no
/// measures or splines (an entry is made only for expressions that read neither).
struct EntryContext(Context<'static>);

// SAFETY: the context's pointers are to an empty static slice and a dangling, never-read
// spline pointer; nothing writes it, so sharing it between threads is sound.
unsafe impl Sync for EntryContext {}

static ENTRY_CONTEXT: EntryContext = EntryContext(Context::new(0.0, &[]));

/// What the entry needs to know of the expression it calls.
pub struct Callee {
    /// The expression's function in the module.
    pub id: FuncId,
    /// Whether it has the minimal signature `(vars, time)`.
    pub minimal: bool,
    /// How many variables it takes (the length `x` must have at least).
    pub variables: usize,
    /// How many outputs it writes (more than one: through `out`).
    pub outputs: usize,
}

/// Declares and defines the entry of `callee` in `module`, built in `ctx`.
pub fn define(
    module: &mut JITModule,
    ctx: &mut cranelift_codegen::Context,
    fctx: &mut FunctionBuilderContext,
    callee: &Callee,
) -> Result<FuncId, JitError> {
    let ptr = module.target_config().pointer_type();
    let mut sig = module.make_signature();
    sig.params.push(AbiParam::new(types::I32));
    sig.params.push(AbiParam::new(ptr));
    sig.params.push(AbiParam::new(ptr));
    sig.returns.push(AbiParam::new(types::F64));
    let id = module
        .declare_anonymous_function(&sig)
        .map_err(|e| JitError::Module(e.to_string()))?;
    let inner_sig = expr_signature(module, callee.minimal);
    ctx.clear();
    ctx.func.signature = sig;
    let mut fb = FunctionBuilder::new(&mut ctx.func, fctx);
    let (start, bad, has_time, no_time, call) = (
        fb.create_block(),
        fb.create_block(),
        fb.create_block(),
        fb.create_block(),
        fb.create_block(),
    );
    fb.append_block_params_for_function_params(start);
    fb.append_block_param(call, types::F64);
    fb.switch_to_block(start);
    let &[n, x, out] = fb.block_params(start) else {
        return Err(JitError::Module("the entry has three parameters".into()));
    };
    let count = i64::try_from(callee.variables)
        .ok()
        .filter(|&c| c < i64::from(i32::MAX))
        .ok_or_else(|| JitError::Module("too many variables for an entry".into()))?;
    let short = fb.ins().icmp_imm_s(IntCC::SignedLessThan, n, count);
    let refused = if callee.outputs > 1 {
        let null = fb.ins().icmp_imm_s(IntCC::Equal, out, 0);
        fb.ins().bor(short, null)
    } else {
        short
    };
    let checked = fb.create_block();
    fb.ins().brif(refused, bad, &[], checked, &[]);
    fb.switch_to_block(checked);
    let timed = fb.ins().icmp_imm_s(IntCC::SignedGreaterThan, n, count);
    fb.ins().brif(timed, has_time, &[], no_time, &[]);

    fb.switch_to_block(bad);
    let nan = fb.ins().f64const(f64::NAN);
    fb.ins().return_(&[nan]);

    fb.switch_to_block(has_time);
    let offset = i32::try_from(count * 8)
        .map_err(|_| JitError::Module("too many variables for an entry".into()))?;
    let time = fb
        .ins()
        .load(types::F64, MemFlagsData::trusted(), x, offset);
    fb.ins().jump(call, &[BlockArg::Value(time)]);

    fb.switch_to_block(no_time);
    let zero = fb.ins().f64const(0.0);
    fb.ins().jump(call, &[BlockArg::Value(zero)]);

    fb.switch_to_block(call);
    let time = fb.block_params(call)[0];
    let inner = module.declare_func_in_func(callee.id, fb.func);
    let args = if callee.minimal {
        vec![x, time]
    } else {
        let context = fb
            .ins()
            .iconst(ptr, &ENTRY_CONTEXT.0 as *const Context as i64);
        let (_, measures) = ENTRY_CONTEXT.0.arrays();
        let measures = fb.ins().iconst(ptr, measures as i64);
        vec![context, x, measures, out, time]
    };
    debug_assert_eq!(args.len(), inner_sig.params.len());
    let result = fb.ins().call(inner, &args);
    let value = fb.inst_results(result)[0];
    fb.ins().return_(&[value]);
    fb.seal_all_blocks();
    let config = module.isa().frontend_config();
    fb.finalize(config);
    Ok(id)
}
