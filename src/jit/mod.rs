//! The Cranelift JIT: IR functions become machine code the host calls directly.
//!
//! [`Jit`] owns what compilation reuses (the target ISA, the codegen context, the
//! function-builder context). [`Jit::compile_batch`] translates many functions into one
//! `JITModule` with one finalisation; the module lives as long as any [`CompiledExpr`]
//! made from it and its memory is freed when the last one drops. Before translation each
//! function goes through [`crate::ir::lower`], so MIN, MAX, DIM, SIGN, STEP, STEP5,
//! HAVSIN and POLY run without data-dependent jumps, and IMPACT and BISTOP branch only on
//! contact. [`CompiledExpr::eval`] checks the context on each call;
//! [`CompiledExpr::bind`] checks a fixed layout once and gives a [`Bound`] whose
//! evaluation is only the call.
//!
//! Invariant: a compiled expression gives the interpreter's bits (NaN payloads aside):
//! both run the same IR, call the same runtime functions, and the lowering follows the
//! runtime's operation order (checked by the differential tests in `tests/backends/`).

mod anchor;
pub mod entry;
mod frame;
#[cfg(all(target_os = "linux", target_arch = "x86_64"))]
mod memory;
mod symbols;
mod translate;

pub use entry::{EntryFn, ENTRY_SIGNATURE};
pub use symbols::{
    lookup as runtime_symbol, names as symbol_name, params as symbol_params,
    spline as spline_symbol,
};

use crate::context::Context;
use crate::ir::Function;
use cranelift_codegen::isa::OwnedTargetIsa;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Module, ModuleReloc};
use rustc_hash::FxHashMap;
use std::mem::ManuallyDrop;
use std::sync::Arc;

/// Why compilation failed (never a user error: the checker accepted the expression).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum JitError {
    /// The host CPU is not supported by Cranelift.
    Host(String),
    /// Cranelift rejected the code or could not finalise the module.
    Module(String),
    /// A runtime symbol is missing or its signature is not what the translator passes.
    Symbol(String),
    /// The IR refers to a value before defining it (a bug in an IR pass).
    Malformed(u32),
}

impl std::fmt::Display for JitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            JitError::Host(m) => write!(f, "this CPU is not supported by the JIT: {m}"),
            JitError::Module(m) => write!(f, "code generation failed: {m}"),
            JitError::Symbol(s) => write!(
                f,
                "runtime symbol `{s}` is missing or has another signature"
            ),
            JitError::Malformed(v) => write!(f, "malformed IR: value v{v} used before definition"),
        }
    }
}

impl std::error::Error for JitError {}

/// The machine code of one batch. Dropping it frees the code.
struct Code {
    module: ManuallyDrop<JITModule>,
}

impl Drop for Code {
    fn drop(&mut self) {
        // SAFETY: `Code` lives only in the `Arc` that every `CompiledExpr` and `Bound` (the
        // only holders of pointers into this module) keeps, so when it drops none is left
        // and nothing can call the code afterwards; `module` is taken here, once, and never
        // touched again.
        unsafe { ManuallyDrop::take(&mut self.module).free_memory() };
    }
}

// SAFETY: after finalisation the module is never used again except to free it on drop;
// the code it owns is immutable, so sharing it between threads is sound.
unsafe impl Send for Code {}
// SAFETY: as above: the one use of a shared `&Code` is `get_finalized_function` in
// `compile_batch`, before the `Arc` leaves that thread, and it reads no `RefCell`.
unsafe impl Sync for Code {}

/// Signature of the generated code.
type RawFn = unsafe extern "C" fn(*const Context<'_>, *const f64, *const f64, *mut f64, f64) -> f64;

/// The minimal signature `(vars, time)` of expressions that need nothing else (see
/// `translate::is_minimal`).
type MinFn = unsafe extern "C" fn(*const f64, f64) -> f64;

/// A compiled function's entry, by signature.
#[derive(Clone, Copy)]
enum Entry {
    General(RawFn),
    Minimal(MinFn),
}

/// A compiled expression. Cloning shares the code.
#[derive(Clone)]
pub struct CompiledExpr {
    code: Entry,
    /// The frame of this leaf function was elided ([`frame`]).
    frameless: bool,
    outputs: usize,
    /// Smallest variable, measure and spline arrays a context must provide.
    needs: [usize; 3],
    /// The stable C entry ([`entry`]), when one was asked for.
    entry: Option<EntryFn>,
    _owner: Arc<Code>,
}

impl std::fmt::Debug for CompiledExpr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CompiledExpr")
            .field("outputs", &self.outputs)
            .field("needs", &self.needs)
            .field("frameless", &self.frameless)
            .finish()
    }
}

impl CompiledExpr {
    /// Number of outputs (1 for a scalar, 3 for a vector, more for a gradient).
    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// Identifies the module holding the code: equal for functions compiled together.
    pub fn module_id(&self) -> *const () {
        Arc::as_ptr(&self._owner).cast()
    }

    /// The stable C entry ([`entry`]) when it was compiled with one
    /// ([`Jit::compile_with_entry`]). Calling it is sound while `self` (or a clone)
    /// lives and under the argument rules of the [`entry`] module.
    pub fn entry(&self) -> Option<EntryFn> {
        self.entry
    }

    /// Whether this is a leaf function whose frame was elided (see `jit/frame.rs`).
    pub fn is_frameless(&self) -> bool {
        self.frameless
    }

    fn covered_by(&self, ctx: &Context) -> bool {
        ctx.covers(self.needs)
    }

    /// Evaluates the first output. NaN when the context lacks slots the expression reads
    /// (as the interpreter).
    #[inline]
    pub fn eval(&self, ctx: &Context) -> f64 {
        if self.outputs > 1 {
            let mut out = vec![0.0; self.outputs];
            self.eval_into(ctx, &mut out);
            return out[0];
        }
        if !self.covered_by(ctx) {
            return f64::NAN;
        }
        // SAFETY: the code reads only context slots below `needs` (recomputed from the
        // compiled instructions, not taken from `Function::uses`), which `covered_by`
        // checked, and with one output it never writes `out`; `_owner` keeps the code alive.
        unsafe { self.call(ctx, std::ptr::null_mut()) }
    }

    /// Runs the code.
    ///
    /// # Safety
    /// `ctx` must cover the expression's needs, and `out` must have room for every output
    /// when there are several (it is not written when there is one).
    #[inline(always)]
    unsafe fn call(&self, ctx: &Context, out: *mut f64) -> f64 {
        let (vars, measures) = ctx.arrays();
        // SAFETY: the caller's guarantees are the code's requirements; the pointer has the
        // signature the function was declared with (see `compile_batch`), and `_owner`
        // keeps the code alive. `frame::elide` changed only the frame of a leaf that never
        // addresses it (its module docs give the byte checks).
        unsafe {
            match self.code {
                Entry::General(code) => code(ctx, vars, measures, out, ctx.time),
                Entry::Minimal(code) => code(vars, ctx.time),
            }
        }
    }

    /// This expression bound to a fixed input layout: user variables in an array of `N`
    /// slots, time per call, no measures or splines, one output. The checks happen here,
    /// once, so [`Bound::eval`] is only the call (the way a solver calls a compiled force).
    /// `None` when the expression reads measures or splines, a slot at or above `N`, or
    /// has several outputs.
    pub fn bind<const N: usize>(&self) -> Option<Bound<N>> {
        let [vars, measures, splines] = self.needs;
        (self.outputs <= 1 && vars <= N && measures == 0 && splines == 0).then(|| Bound {
            code: self.code,
            ctx: Context::new(0.0, &[]),
            _owner: self._owner.clone(),
        })
    }

    /// Evaluates a scalar expression at `out.len()` points: point i reads its variables
    /// from `rows[i·width..(i + 1)·width]` and its TIME from `time(i)`, MODE 4, no
    /// measures or splines. The checks happen once, so each point costs the call alone
    /// (the vectorised path of the Python module and the C API). Returns false, leaving
    /// `out` alone, when the expression has several outputs or reads what the rows do
    /// not hold (measures, splines, a variable at or past `width`), or when `rows` is
    /// shorter than the points need.
    pub fn eval_rows(
        &self,
        rows: &[f64],
        width: usize,
        time: impl Fn(usize) -> f64,
        out: &mut [f64],
    ) -> bool {
        let [vars, measures, splines] = self.needs;
        let fits = self.outputs <= 1
            && vars <= width
            && measures == 0
            && splines == 0
            && width
                .checked_mul(out.len())
                .is_some_and(|n| n <= rows.len());
        if !fits {
            return false;
        }
        let ctx = Context::new(0.0, &[]);
        let (_, no_measures) = ctx.arrays();
        let base = rows.as_ptr();
        match self.code {
            Entry::Minimal(code) => {
                for (i, o) in out.iter_mut().enumerate() {
                    // SAFETY: the code reads variable slots below `vars` ≤ `width` (from
                    // its instructions) and nothing else; row i lies within `rows`, as
                    // checked above; `_owner` keeps the code alive.
                    *o = unsafe { code(base.add(i * width), time(i)) };
                }
            }
            Entry::General(code) => {
                for (i, o) in out.iter_mut().enumerate() {
                    // SAFETY: as above; the context (read for MODE) lives on this frame,
                    // no measure is read, and with one output `out` is never written.
                    *o = unsafe {
                        code(
                            &ctx,
                            base.add(i * width),
                            no_measures,
                            std::ptr::null_mut(),
                            time(i),
                        )
                    };
                }
            }
        }
        true
    }

    /// Evaluates every output into `out` (extra slots are left alone; a shorter `out`
    /// receives the first outputs). NaN everywhere when the context lacks slots.
    pub fn eval_into(&self, ctx: &Context, out: &mut [f64]) {
        if !self.covered_by(ctx) {
            out.fill(f64::NAN);
            return;
        }
        if self.outputs <= 1 {
            if let Some(o) = out.first_mut() {
                // SAFETY: as in `eval`.
                *o = unsafe { self.call(ctx, std::ptr::null_mut()) };
            }
            return;
        }
        if out.len() >= self.outputs {
            // SAFETY: the context is covered (see `eval`) and `out` has room for every
            // output the code writes.
            unsafe { self.call(ctx, out.as_mut_ptr()) };
        } else {
            let mut all = vec![0.0; self.outputs];
            // SAFETY: as above, with a buffer of exactly `outputs` values.
            unsafe { self.call(ctx, all.as_mut_ptr()) };
            out.copy_from_slice(&all[..out.len()]);
        }
    }
}

/// A scalar expression bound to `N` variable slots by [`CompiledExpr::bind`]: evaluation
/// needs no check, as the array type carries the layout that was checked.
#[derive(Clone)]
pub struct Bound<const N: usize> {
    code: Entry,
    /// What the code may read from a context besides the arguments: the mode (the arrays
    /// are empty, and the expression reads none of them).
    ctx: Context<'static>,
    _owner: Arc<Code>,
}

// SAFETY: the context holds only the mode and empty arrays (no pointer to shared data),
// and the code is immutable (see `Code`), so a `Bound` may move to and be shared with other
// threads as `CompiledExpr` may.
unsafe impl<const N: usize> Send for Bound<N> {}
// SAFETY: as above.
unsafe impl<const N: usize> Sync for Bound<N> {}

impl<const N: usize> std::fmt::Debug for Bound<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bound").field("slots", &N).finish()
    }
}

impl<const N: usize> Bound<N> {
    /// The same binding with analysis mode `mode` (4, dynamics, unless set).
    pub fn with_mode(mut self, mode: f64) -> Self {
        self.ctx = self.ctx.with_mode(mode);
        self
    }

    /// Evaluates the expression at user variables `vars` (slot order) and `time`.
    #[inline]
    pub fn eval(&self, vars: &[f64; N], time: f64) -> f64 {
        let (_, measures) = self.ctx.arrays();
        // SAFETY: `bind` checked that the code reads variable slots below `N` only, no
        // measure or spline, and writes no output; `vars` has `N` slots, the context
        // (read for the mode) lives in `self`, and `_owner` keeps the code alive. `needs`
        // comes from the instructions, as in `CompiledExpr::eval`.
        unsafe {
            match self.code {
                Entry::Minimal(code) => code(vars.as_ptr(), time),
                Entry::General(code) => code(
                    &self.ctx,
                    vars.as_ptr(),
                    measures,
                    std::ptr::null_mut(),
                    time,
                ),
            }
        }
    }
}

/// The JIT compiler: target, reusable contexts and options.
pub struct Jit {
    isa: OwnedTargetIsa,
    ctx: cranelift_codegen::Context,
    fctx: FunctionBuilderContext,
    /// Lower the cheap library functions to branch-free code (on by default).
    pub lower: bool,
    /// Run leaf functions without a stack frame (the `frame` module; on by default).
    pub elide_frames: bool,
    /// Seconds each function of the last batch took (lowering, translation, Cranelift),
    /// for the compile benchmark.
    times: Vec<f64>,
}

impl Jit {
    /// A compiler for the host CPU, optimising for speed.
    pub fn new() -> Result<Jit, JitError> {
        let mut flags = settings::builder();
        let set = |f: &mut settings::Builder, k, v| {
            f.set(k, v).map_err(|e| JitError::Host(e.to_string()))
        };
        set(&mut flags, "opt_level", "speed")?;
        set(&mut flags, "use_colocated_libcalls", "false")?;
        set(&mut flags, "is_pic", "false")?;
        // The JIT module registers no unwind tables, and leaves lose their frame anyway.
        set(&mut flags, "unwind_info", "false")?;
        let verify = if cfg!(debug_assertions) {
            "true"
        } else {
            "false"
        };
        set(&mut flags, "enable_verifier", verify)?;
        let isa = cranelift_native::builder()
            .map_err(|m| JitError::Host(m.to_string()))?
            .finish(settings::Flags::new(flags))
            .map_err(|e| JitError::Host(e.to_string()))?;
        Ok(Jit {
            isa,
            ctx: cranelift_codegen::Context::new(),
            fctx: FunctionBuilderContext::new(),
            lower: true,
            elide_frames: true,
            times: Vec::new(),
        })
    }

    fn module(&self) -> JITModule {
        let mut builder = JITBuilder::with_isa(self.isa.clone(), default_libcall_names());
        builder.symbol_lookup_fn(Box::new(symbols::address));
        #[cfg(all(target_os = "linux", target_arch = "x86_64"))]
        builder.memory_provider(Box::new(memory::NearMemory::new()));
        JITModule::new(builder)
    }

    /// Compiles one function.
    pub fn compile(&mut self, f: &Function) -> Result<CompiledExpr, JitError> {
        let mut v = self.compile_batch(&[f])?;
        v.pop().ok_or(JitError::Malformed(0))
    }

    /// Compiles many functions into one module with one finalisation.
    pub fn compile_batch(&mut self, fs: &[&Function]) -> Result<Vec<CompiledExpr>, JitError> {
        self.compile_module(fs, None)
    }

    /// Compiles `f`, which reads `variables` user variables and no measure or spline,
    /// with its stable C entry ([`entry`]). `None` when `f` reads measures or splines or
    /// a variable slot at or above `variables` (the entry could not give them).
    pub fn compile_with_entry(
        &mut self,
        f: &Function,
        variables: usize,
    ) -> Result<Option<CompiledExpr>, JitError> {
        let [vars, measures, splines] = needs(f);
        if vars > variables || measures > 0 || splines > 0 {
            return Ok(None);
        }
        let mut v = self.compile_module(&[f], Some(variables))?;
        Ok(v.pop())
    }

    /// Compiles `fs` into one module; with `entries`, each also gets a C entry taking
    /// that many variables.
    fn compile_module(
        &mut self,
        fs: &[&Function],
        entries: Option<usize>,
    ) -> Result<Vec<CompiledExpr>, JitError> {
        let mut module = self.module();
        let mut declared = FxHashMap::default();
        let mut ids = Vec::with_capacity(fs.len());
        self.times.clear();
        for f in fs {
            let t0 = std::time::Instant::now();
            let lowered;
            let f = if self.lower {
                lowered = crate::ir::lower::lower(f);
                &lowered
            } else {
                f
            };
            let (id, frameless) = self.define(&mut module, &mut declared, f)?;
            let minimal = translate::is_minimal(f);
            let entry = match entries {
                Some(variables) => {
                    let callee = entry::Callee {
                        id,
                        minimal,
                        variables,
                        outputs: f.outputs.len(),
                    };
                    let at = entry::define(&mut module, &mut self.ctx, &mut self.fctx, &callee);
                    let defined = at.and_then(|at| self.emit(&mut module, at, false).map(|_| at));
                    self.ctx.clear();
                    Some(defined?)
                }
                None => None,
            };
            ids.push((id, minimal, frameless, f.outputs.len(), needs(f), entry));
            self.times.push(t0.elapsed().as_secs_f64());
        }
        module
            .finalize_definitions()
            .map_err(|e| JitError::Module(e.to_string()))?;
        let owner = Arc::new(Code {
            module: ManuallyDrop::new(module),
        });
        Ok(ids
            .into_iter()
            .map(|(id, minimal, frameless, outputs, needs, entry)| {
                let ptr = owner.module.get_finalized_function(id);
                // SAFETY: `ptr` is the finalised (non-null) code of a function declared with
                // `expr_signature(_, minimal)` in the host's default calling convention
                // (`extern "C"`), which is `MinFn`'s signature when `minimal` and `RawFn`'s
                // otherwise (`define` and this loop call `is_minimal` on the same function).
                // The `CompiledExpr` built here holds `owner`, so the code outlives the
                // pointer.
                let code = unsafe {
                    if minimal {
                        Entry::Minimal(std::mem::transmute::<*const u8, MinFn>(ptr))
                    } else {
                        Entry::General(std::mem::transmute::<*const u8, RawFn>(ptr))
                    }
                };
                // SAFETY: the entry was declared with `entry::define`'s signature, which is
                // `EntryFn`'s in the default calling convention; `owner` keeps it alive.
                let entry = entry.map(|at| unsafe {
                    std::mem::transmute::<*const u8, EntryFn>(
                        owner.module.get_finalized_function(at),
                    )
                });
                CompiledExpr {
                    code,
                    frameless,
                    outputs,
                    needs,
                    entry,
                    _owner: owner.clone(),
                }
            })
            .collect())
    }

    /// Seconds each function of the last [`Jit::compile_batch`] took to lower, translate
    /// and compile (the module's finalisation, shared by the batch, is not included).
    pub fn last_batch_times(&self) -> &[f64] {
        &self.times
    }

    /// Translates `f` into `module` and defines it (and its constants); returns its id and
    /// whether its frame was elided.
    fn define(
        &mut self,
        module: &mut JITModule,
        declared: &mut FxHashMap<String, FuncId>,
        f: &Function,
    ) -> Result<(FuncId, bool), JitError> {
        let sig = translate::expr_signature(module, translate::is_minimal(f));
        let id = module
            .declare_anonymous_function(&sig)
            .map_err(|e| JitError::Module(e.to_string()))?;
        self.ctx.clear();
        self.ctx.func.signature = sig;
        let fb = FunctionBuilder::new(&mut self.ctx.func, &mut self.fctx);
        let consts = translate::Constants::define(f, module)?;
        let result = translate::Translator::new(f, fb, module, declared, &consts).run();
        if let Err(e) = result {
            self.ctx.clear();
            return Err(e);
        }
        let leaf = frame::is_leaf(&self.ctx.func);
        let defined = self.emit(module, id, leaf);
        self.ctx.clear();
        Ok((id, defined?))
    }

    /// Compiles the function in `self.ctx`, elides a leaf's frame ([`frame`]) and defines
    /// the code as `id`'s. Returns whether the frame was elided.
    fn emit(&mut self, module: &mut JITModule, id: FuncId, leaf: bool) -> Result<bool, JitError> {
        self.ctx
            .compile(&*self.isa, &mut Default::default())
            .map_err(|e| JitError::Module(format!("{:?}", e.inner)))?;
        let (func, code) = (&self.ctx.func, self.ctx.compiled_code());
        let code = code.ok_or_else(|| JitError::Module("no compiled code".into()))?;
        let mut bytes = code.code_buffer().to_vec();
        let relocs: Vec<ModuleReloc> = code
            .buffer
            .relocs()
            .iter()
            .map(|r| ModuleReloc::from_mach_reloc(r, func, id))
            .collect();
        let alignment = u64::from(code.buffer.alignment);
        let elided = self.elide_frames && frame::elide(&mut bytes, leaf);
        module
            .define_function_bytes(id, alignment, &bytes, &relocs)
            .map_err(|e| JitError::Module(format!("{e:?}")))?;
        Ok(elided)
    }

    /// The Cranelift IR of `f` (after lowering, before Cranelift's optimisations), for the
    /// REPL's `:clif`.
    pub fn clif(&mut self, f: &Function) -> Result<String, JitError> {
        self.listing(f, |jit| Ok(jit.ctx.func.display().to_string()))
    }

    /// The machine instructions Cranelift emits for `f` (its VCode listing, after
    /// register allocation), for the REPL's `:asm`, with a last line saying whether the
    /// loaded code drops the listed frame (the `frame` module). `listing` turns the listing flag
    /// off again.
    pub fn asm(&mut self, f: &Function) -> Result<String, JitError> {
        self.listing(f, |jit| {
            let leaf = frame::is_leaf(&jit.ctx.func);
            jit.ctx.set_disasm(true);
            let compiled = jit.ctx.compile(&*jit.isa, &mut Default::default());
            let (mut text, mut bytes) = match compiled {
                Ok(code) => (
                    code.vcode.clone().unwrap_or_default(),
                    code.code_buffer().to_vec(),
                ),
                Err(e) => return Err(JitError::Module(format!("{:?}", e.inner))),
            };
            if jit.elide_frames && frame::elide(&mut bytes, leaf) {
                text += "; leaf: the loaded code replaces the frame setup with a NOP and \
                         returns without restoring a frame\n";
            }
            Ok(text)
        })
    }

    /// Translates `f` (lowered when [`Jit::lower`] is on) into `self.ctx` within a
    /// throw-away module, and returns what `show` makes of it.
    fn listing(
        &mut self,
        f: &Function,
        show: impl FnOnce(&mut Self) -> Result<String, JitError>,
    ) -> Result<String, JitError> {
        let mut module = self.module();
        let mut declared = FxHashMap::default();
        let lowered;
        let f = if self.lower {
            lowered = crate::ir::lower::lower(f);
            &lowered
        } else {
            f
        };
        let sig = translate::expr_signature(&module, translate::is_minimal(f));
        self.ctx.clear();
        self.ctx.func.signature = sig;
        let fb = FunctionBuilder::new(&mut self.ctx.func, &mut self.fctx);
        let consts = translate::Constants::define(f, &mut module)?;
        let text = translate::Translator::new(f, fb, &mut module, &mut declared, &consts)
            .run()
            .and_then(|()| show(self));
        self.ctx.set_disasm(false);
        self.ctx.clear();
        // SAFETY: nothing was finalised, so no pointer into the module exists.
        unsafe { module.free_memory() };
        text
    }
}

/// Smallest variable, measure and spline arrays `f` may be given, from the instructions
/// themselves: `Function::uses` is public and a hand-made function's may be wrong, and
/// the compiled code's bounds rest on these (one linear pass, next to compiling).
fn needs(f: &Function) -> [usize; 3] {
    let u = crate::ir::builder::collect_uses(f);
    [u.vars_len(), u.measures_len(), u.splines_len()]
}
