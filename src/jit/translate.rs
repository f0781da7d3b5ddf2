//! IR → Cranelift IR, one method per IR instruction.
//!
//! The generated function is `extern "C" fn(ctx: *const Context, vars: *const f64,
//! measures: *const f64, out: *mut f64, time: f64) -> f64`: it returns the first output
//! and, when there are several (a vector, a gradient), writes all of them to `out`. The
//! variable and measure arrays and the time come as arguments (the caller has them in
//! registers) so the code does not load them from the context first. Arithmetic is inlined (`fadd`, `fmul`, `sqrt`, `fabs`, no
//! fused multiply-add); an arithmetic IF is real branches (only the taken arm runs); a
//! [`Inst::Select`] is a branch-free SSE compare-and-blend; library functions are calls
//! to the runtime's `extern "C"` wrappers. Constants are loaded from the function's
//! constant pool (one instruction, as compiled Rust does) rather than built in a general
//! register.

use super::anchor::Crossings;
use super::symbols;
use super::JitError;
use crate::context::layout;
use crate::ir::{Block as IrBlock, Cmp, Function, Inst, Value};
use crate::vocab::func::Func;
use cranelift_codegen::ir;
use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{
    types, AbiParam, BlockArg, Endianness, FuncRef, InstBuilder, MemFlagsData, Signature,
    StackSlotData, StackSlotKind, Type,
};
use cranelift_frontend::FunctionBuilder;
use cranelift_jit::JITModule;
use cranelift_module::{DataDescription, FuncId, Linkage, Module};
use mbfx_runtime::ffi::Param;
use rustc_hash::FxHashMap;

/// Signature of every compiled expression.
pub fn expr_signature(module: &JITModule, minimal: bool) -> Signature {
    let ptr = module.target_config().pointer_type();
    let mut sig = module.make_signature();
    if minimal {
        sig.params.push(AbiParam::new(ptr));
    } else {
        for _ in 0..4 {
            sig.params.push(AbiParam::new(ptr));
        }
    }
    sig.params.push(AbiParam::new(types::F64));
    sig.returns.push(AbiParam::new(types::F64));
    sig
}

/// Whether `f` fits the minimal signature `(vars, time) -> f64`: at most one output and
/// no read of the context (MODE), measures or splines. Fewer arguments make each call
/// cheaper (the caller sets two registers instead of five).
pub fn is_minimal(f: &Function) -> bool {
    let u = &f.uses;
    f.outputs.len() <= 1 && !u.mode && u.measures.is_empty() && u.splines.is_empty()
}

/// The constants of a straight-line arithmetic function, as a read-only data object of
/// the module: the code reads them through one base address, so Cranelift folds
/// single-use constants into the instructions as memory operands (as compiled Rust
/// does). Other functions read constants from the constant pool.
pub struct Constants {
    data: Option<cranelift_module::DataId>,
    /// Byte offset of each constant in the data object, by its bits.
    offsets: FxHashMap<u64, i32>,
}

impl Constants {
    /// Defines the non-zero constants of `f` (zero is one register instruction) in
    /// `module`.
    pub fn define(f: &Function, module: &mut JITModule) -> Result<Constants, JitError> {
        let mut bytes = Vec::new();
        let mut offsets = FxHashMap::default();
        for inst in &f.insts {
            if let Inst::Const(c) = inst {
                let bits = c.to_bits();
                if bits != 0 && !offsets.contains_key(&bits) {
                    offsets.insert(bits, bytes.len() as i32);
                    bytes.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
        // Only straight-line arithmetic gains (measured): selects read constants as lane
        // pairs from the constant pool anyway, and across calls the base address would
        // hold a callee-saved register.
        let arithmetic = f.insts.iter().all(|i| {
            !matches!(
                i,
                Inst::Select { .. } | Inst::Call(..) | Inst::Partial { .. } | Inst::Spline { .. }
            )
        });
        if bytes.is_empty() || !arithmetic {
            return Ok(Constants {
                data: None,
                offsets,
            });
        }
        let module_error = |e: cranelift_module::ModuleError| JitError::Module(e.to_string());
        let id = module
            .declare_anonymous_data(false, false)
            .map_err(module_error)?;
        let mut desc = DataDescription::new();
        desc.define(bytes.into_boxed_slice());
        desc.set_align(8);
        module.define_data(id, &desc).map_err(module_error)?;
        Ok(Constants {
            data: Some(id),
            offsets,
        })
    }
}

/// Translates one IR function into the function `fb` builds.
pub struct Translator<'a, 'b> {
    f: &'a Function,
    fb: FunctionBuilder<'b>,
    module: &'a mut JITModule,
    /// Runtime functions declared in this module, by name.
    declared: &'a mut FxHashMap<String, FuncId>,
    /// Runtime functions imported into this function, by name.
    refs: FxHashMap<String, FuncRef>,
    ptr: Type,
    /// The context (absent in the minimal signature, see [`is_minimal`]).
    ctx: Option<ir::Value>,
    time: ir::Value,
    /// Where several outputs are written (absent in the minimal signature).
    out: Option<ir::Value>,
    /// Base pointers of the variable, measure and spline arrays (loaded once, on entry).
    bases: [Option<ir::Value>; 3],
    /// Cranelift value of each IR value translated so far.
    vals: Vec<Option<ir::Value>>,
    /// Extra results of multi-result IFs, by IF value.
    extras: FxHashMap<Value, Vec<ir::Value>>,
    /// The `f64x2` each select's result came from, so a select of a select needs no splat.
    vectors: FxHashMap<Value, ir::Value>,
    /// The function's constants and their address (set on entry when there are any).
    consts: &'a Constants,
    consts_base: Option<ir::Value>,
    /// Values computed before an IF and read after it ([`super::anchor`]).
    crossings: Crossings,
    /// Stack slots free for anchoring a value across an IF.
    free_slots: Vec<ir::StackSlot>,
}

const TRUSTED: MemFlagsData = MemFlagsData::trusted();

impl<'a, 'b> Translator<'a, 'b> {
    pub fn new(
        f: &'a Function,
        mut fb: FunctionBuilder<'b>,
        module: &'a mut JITModule,
        declared: &'a mut FxHashMap<String, FuncId>,
        consts: &'a Constants,
    ) -> Self {
        let ptr = module.target_config().pointer_type();
        let entry = fb.create_block();
        fb.append_block_params_for_function_params(entry);
        fb.switch_to_block(entry);
        let params = fb.block_params(entry).to_vec();
        // General: (ctx, vars, measures, out, time); minimal: (vars, time).
        let (ctx, vars, measures, out, time) = match params[..] {
            [vars, time] => (None, vars, None, None, time),
            [ctx, vars, measures, out, time] => (Some(ctx), vars, Some(measures), Some(out), time),
            _ => unreachable!("expr_signature has two or five parameters"),
        };
        let splines = match ctx {
            Some(ctx) if !f.uses.splines.is_empty() => {
                Some(
                    fb.ins()
                        .load(ptr, TRUSTED.with_readonly(), ctx, layout::SPLINES),
                )
            }
            _ => None,
        };
        let bases = [Some(vars), measures, splines];
        // The address is a `symbol_value`, computed once (an `iconst` would be
        // rematerialised at every use).
        let consts_base = consts.data.map(|id| {
            let gv = module.declare_data_in_func(id, fb.func);
            fb.ins().symbol_value(ptr, gv)
        });
        Translator {
            f,
            fb,
            module,
            declared,
            refs: FxHashMap::default(),
            ptr,
            ctx,
            time,
            out,
            bases,
            vals: vec![None; f.insts.len()],
            extras: FxHashMap::default(),
            vectors: FxHashMap::default(),
            consts,
            consts_base,
            crossings: Crossings::new(f),
            free_slots: Vec::new(),
        }
    }

    /// Translates the body and returns the outputs; consumes the builder.
    pub fn run(mut self) -> Result<(), JitError> {
        let body = &self.f.body;
        self.list(body)?;
        let outs: Vec<ir::Value> = self
            .f
            .outputs
            .iter()
            .map(|&o| self.value(o))
            .collect::<Result<_, _>>()?;
        if outs.len() > 1 {
            let out = self.out.ok_or(JitError::Malformed(0))?;
            for (i, &v) in outs.iter().enumerate() {
                self.fb.ins().store(TRUSTED, v, out, (i * 8) as i32);
            }
        }
        let first = match outs.first() {
            Some(&v) => v,
            None => self.fb.ins().f64const(f64::NAN),
        };
        self.fb.ins().return_(&[first]);
        self.fb.seal_all_blocks();
        let config = self.module.isa().frontend_config();
        self.fb.finalize(config);
        Ok(())
    }

    /// The Cranelift value of IR value `v` (a constant is materialised where it is used;
    /// Cranelift shares equal constants).
    fn value(&mut self, v: Value) -> Result<ir::Value, JitError> {
        if let Some(c) = self.f.constant(v) {
            return Ok(self.constant(c));
        }
        self.vals
            .get(v as usize)
            .copied()
            .flatten()
            .ok_or(JitError::Malformed(v))
    }

    /// A constant read from the function's constant pool (one RIP-relative load) rather
    /// than built in a general register and moved over (`f64const`'s two instructions).
    fn constant(&mut self, c: f64) -> ir::Value {
        if let (Some(base), Some(&at)) = (self.consts_base, self.consts.offsets.get(&c.to_bits())) {
            return self
                .fb
                .ins()
                .load(types::F64, TRUSTED.with_readonly(), base, at);
        }
        if c.to_bits() == 0 {
            return self.fb.ins().f64const(c);
        }
        let pair = self.pool(c, c);
        self.fb.ins().extractlane(pair, 0)
    }

    fn list(&mut self, values: &[Value]) -> Result<(), JitError> {
        for &v in values {
            self.inst(v)?;
        }
        Ok(())
    }

    fn inst(&mut self, v: Value) -> Result<(), JitError> {
        let f = self.f;
        let r = match f.inst(v) {
            Inst::Const(_) => return Ok(()),
            Inst::Var(s) => self.load_slot(0, *s)?,
            Inst::Measure(s) => self.load_slot(1, *s)?,
            Inst::Time => self.time,
            Inst::Mode => self.load_ctx(layout::MODE, v)?,
            Inst::Neg(a) => {
                let a = self.value(*a)?;
                self.fb.ins().fneg(a)
            }
            Inst::Add(a, b) => self.binary(*a, *b, |i, x, y| i.fadd(x, y))?,
            Inst::Sub(a, b) => self.binary(*a, *b, |i, x, y| i.fsub(x, y))?,
            Inst::Mul(a, b) => self.binary(*a, *b, |i, x, y| i.fmul(x, y))?,
            Inst::Div(a, b) => self.binary(*a, *b, |i, x, y| i.fdiv(x, y))?,
            Inst::Sqrt(a) => {
                let a = self.value(*a)?;
                self.fb.ins().sqrt(a)
            }
            Inst::Call(func, args) => self.call(*func, args)?,
            Inst::Partial { func, wrt, args } => self.partial(*func, *wrt, args)?,
            Inst::Spline {
                kind,
                x,
                z,
                spline,
                iord,
            } => {
                let (x, z) = (self.value(*x)?, self.value(*z)?);
                let base = self.bases[2].ok_or(JitError::Malformed(v))?;
                let size = std::mem::size_of::<mbfx_runtime::Spline>() as i64;
                let at = self.fb.ins().iadd_imm_s(base, size * i64::from(*spline));
                let iord = self.fb.ins().iconst(types::I32, i64::from(*iord));
                let (name, params) = symbols::spline(*kind);
                self.call_symbol(name, &params, &[x, z, at, iord])?
            }
            Inst::Select {
                cmp,
                a,
                b,
                then,
                otherwise,
            } => {
                let (a, b) = (self.lanes(*a)?, self.lanes(*b)?);
                let (t, o) = (self.lanes(*then)?, self.lanes(*otherwise)?);
                let r = self.select(*cmp, a, b, t, o);
                self.vectors.insert(v, r);
                self.fb.ins().extractlane(r, 0)
            }
            Inst::If { test, arms } => return self.if_(v, *test, arms),
            Inst::IfExtra { of, index } => self
                .extras
                .get(of)
                .and_then(|e| e.get(*index as usize).copied())
                .ok_or(JitError::Malformed(v))?,
        };
        self.vals[v as usize] = Some(r);
        self.crossings.defined(f, v);
        Ok(())
    }

    fn binary(
        &mut self,
        a: Value,
        b: Value,
        op: impl FnOnce(cranelift_frontend::FuncInstBuilder<'_, 'b>, ir::Value, ir::Value) -> ir::Value,
    ) -> Result<ir::Value, JitError> {
        let (a, b) = (self.value(a)?, self.value(b)?);
        Ok(op(self.fb.ins(), a, b))
    }

    fn load_ctx(&mut self, offset: i32, v: Value) -> Result<ir::Value, JitError> {
        let ctx = self.ctx.ok_or(JitError::Malformed(v))?;
        Ok(self
            .fb
            .ins()
            .load(types::F64, TRUSTED.with_readonly(), ctx, offset))
    }

    /// Slot `s` of the variable (0) or measure (1) array.
    fn load_slot(&mut self, array: usize, s: u32) -> Result<ir::Value, JitError> {
        let base = self.bases[array].ok_or(JitError::Malformed(s))?;
        let offset = i32::try_from(u64::from(s) * 8).map_err(|_| JitError::Malformed(s))?;
        Ok(self
            .fb
            .ins()
            .load(types::F64, TRUSTED.with_readonly(), base, offset))
    }

    /// IR value `v` in both lanes of an `f64x2`, for a select: a constant is loaded from
    /// the constant pool as a pair, another value is splat (one `pshufd`; `scalar_to_vector`
    /// would take three instructions to zero the upper lane, which is never read).
    fn lanes(&mut self, v: Value) -> Result<ir::Value, JitError> {
        if let Some(c) = self.f.constant(v) {
            return Ok(self.pool(c, c));
        }
        if let Some(&r) = self.vectors.get(&v) {
            return Ok(r);
        }
        let x = self.value(v)?;
        Ok(self.fb.ins().splat(types::F64X2, x))
    }

    /// The pair `[lo, hi]` from the function's constant pool.
    fn pool(&mut self, lo: f64, hi: f64) -> ir::Value {
        let mut bytes = lo.to_le_bytes().to_vec();
        bytes.extend_from_slice(&hi.to_le_bytes());
        let handle = self.fb.func.dfg.constants.insert(bytes.into());
        self.fb.ins().vconst(types::F64X2, handle)
    }

    /// `cmp(a, b) ? then : otherwise` without a jump, on lane 0 of `f64x2` operands: the
    /// comparison yields an all-ones or all-zeros lane mask (`cmppd`) that blends the two
    /// values bitwise. The result is lane 0 (lane 1 holds whatever the inputs' did).
    fn select(
        &mut self,
        cmp: Cmp,
        a: ir::Value,
        b: ir::Value,
        then: ir::Value,
        otherwise: ir::Value,
    ) -> ir::Value {
        let cc = match cmp {
            Cmp::Lt => FloatCC::LessThan,
            Cmp::Le => FloatCC::LessThanOrEqual,
            Cmp::Eq => FloatCC::Equal,
            Cmp::Gt => FloatCC::GreaterThan,
            Cmp::Ge => FloatCC::GreaterThanOrEqual,
            Cmp::Uno => FloatCC::Unordered,
        };
        let mask = self.fb.ins().fcmp(cc, a, b);
        let lanes = MemFlagsData::new().with_endianness(Endianness::Little);
        let mask = self.fb.ins().bitcast(types::F64X2, lanes, mask);
        self.fb.ins().bitselect(mask, then, otherwise)
    }

    /// A library call: ABS and SQRT inline (single IEEE instructions), series with their
    /// coefficients in a stack slot, everything else a call with `f64` arguments.
    fn call(&mut self, func: Func, args: &[Value]) -> Result<ir::Value, JitError> {
        let vals: Vec<ir::Value> = args
            .iter()
            .map(|&a| self.value(a))
            .collect::<Result<_, _>>()?;
        match (func, vals.as_slice()) {
            (Func::Abs, &[a]) => return Ok(self.fb.ins().fabs(a)),
            (Func::Sqrt, &[a]) => return Ok(self.fb.ins().sqrt(a)),
            _ => {}
        }
        let call_args = self.marshal(func, &vals, None)?;
        let name = symbols::names(func, false);
        self.call_symbol(&name, &symbols::params(func, false), &call_args)
    }

    /// ∂func/∂(argument `wrt`): the `_grad` companion writes every partial to a stack
    /// slot, of which one is read.
    fn partial(&mut self, func: Func, wrt: u32, args: &[Value]) -> Result<ir::Value, JitError> {
        let vals: Vec<ir::Value> = args
            .iter()
            .map(|&a| self.value(a))
            .collect::<Result<_, _>>()?;
        let slot = self.slot(vals.len());
        let out = self.fb.ins().stack_addr(self.ptr, slot, 0);
        let call_args = self.marshal(func, &vals, Some(out))?;
        let name = symbols::names(func, true);
        self.call_symbol(&name, &symbols::params(func, true), &call_args)?;
        let offset = i32::try_from(wrt * 8).map_err(|_| JitError::Malformed(wrt))?;
        Ok(self.fb.ins().stack_load(self.ptr, types::F64, slot, offset))
    }

    /// A stack slot for `n` f64.
    fn slot(&mut self, n: usize) -> ir::StackSlot {
        let size = (n.max(1) * 8) as u32;
        self.fb
            .create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, size, 3))
    }

    /// The argument list of a runtime call: the fixed arguments, then for a series its
    /// coefficients as (pointer to a stack slot, count), then the output pointer if any.
    fn marshal(
        &mut self,
        func: Func,
        vals: &[ir::Value],
        out: Option<ir::Value>,
    ) -> Result<Vec<ir::Value>, JitError> {
        let mut call_args: Vec<ir::Value>;
        if func.is_variadic() {
            let fixed = func.fixed_args().min(vals.len());
            let (head, coeffs) = vals.split_at(fixed);
            let slot = self.slot(coeffs.len());
            for (i, &c) in coeffs.iter().enumerate() {
                self.fb.ins().stack_store(self.ptr, c, slot, (i * 8) as i32);
            }
            call_args = head.to_vec();
            call_args.push(self.fb.ins().stack_addr(self.ptr, slot, 0));
            call_args.push(self.fb.ins().iconst(self.ptr, coeffs.len() as i64));
        } else {
            call_args = vals.to_vec();
        }
        call_args.extend(out);
        Ok(call_args)
    }

    /// Calls runtime symbol `name`, after checking that the table's signature is `params`.
    fn call_symbol(
        &mut self,
        name: &str,
        params: &[Param],
        args: &[ir::Value],
    ) -> Result<ir::Value, JitError> {
        let fref = match self.refs.get(name) {
            Some(&r) => r,
            None => {
                let sym =
                    symbols::lookup(name).ok_or_else(|| JitError::Symbol(name.to_string()))?;
                if sym.params != params || params.len() != args.len() {
                    return Err(JitError::Symbol(name.to_string()));
                }
                let id = match self.declared.get(name) {
                    Some(&id) => id,
                    None => {
                        let mut sig = self.module.make_signature();
                        for p in sym.params {
                            let ty = match p {
                                Param::F64 => types::F64,
                                Param::Ptr | Param::Usize => self.ptr,
                                Param::I32 => types::I32,
                            };
                            sig.params.push(AbiParam::new(ty));
                        }
                        sig.returns.push(AbiParam::new(types::F64));
                        let id = self
                            .module
                            .declare_function(name, Linkage::Import, &sig)
                            .map_err(|e| JitError::Module(e.to_string()))?;
                        self.declared.insert(name.to_string(), id);
                        id
                    }
                };
                let r = self.module.declare_func_in_func(id, self.fb.func);
                self.refs.insert(name.to_string(), r);
                r
            }
        };
        let call = self.fb.ins().call(fref, args);
        Ok(self.fb.inst_results(call)[0])
    }

    /// An arithmetic IF as branches: test < 0, = 0, > 0 each jump to their arm, NaN to a
    /// block that yields NaN for every result; the arms join in a block whose parameters
    /// are the results.
    fn if_(&mut self, v: Value, test: Value, arms: &[IrBlock; 3]) -> Result<(), JitError> {
        let t = self.value(test)?;
        // Values read after the IF go through a stack slot, so they neither sink past it
        // nor stay live across its arms ([`super::anchor`]).
        let mut anchored = Vec::new();
        for u in self.crossings.at_if(v) {
            let x = self.value(u)?;
            let slot = match self.free_slots.pop() {
                Some(s) => s,
                None => self.slot(1),
            };
            self.fb.ins().stack_store(self.ptr, x, slot, 0);
            anchored.push((u, slot));
        }
        let n = 1 + arms[0].extra.len();
        let join = self.fb.create_block();
        for _ in 0..n {
            self.fb.append_block_param(join, types::F64);
        }
        let arm_blocks: [ir::Block; 3] = std::array::from_fn(|_| self.fb.create_block());
        let (not_neg, not_zero, nan) = (
            self.fb.create_block(),
            self.fb.create_block(),
            self.fb.create_block(),
        );
        let zero = self.fb.ins().f64const(0.0);
        let lt = self.fb.ins().fcmp(FloatCC::LessThan, t, zero);
        self.fb.ins().brif(lt, arm_blocks[0], &[], not_neg, &[]);
        self.fb.switch_to_block(not_neg);
        let eq = self.fb.ins().fcmp(FloatCC::Equal, t, zero);
        self.fb.ins().brif(eq, arm_blocks[1], &[], not_zero, &[]);
        self.fb.switch_to_block(not_zero);
        let gt = self.fb.ins().fcmp(FloatCC::GreaterThan, t, zero);
        self.fb.ins().brif(gt, arm_blocks[2], &[], nan, &[]);
        self.fb.switch_to_block(nan);
        let nan_value = self.fb.ins().f64const(f64::NAN);
        let nans: Vec<BlockArg> = (0..n).map(|_| BlockArg::Value(nan_value)).collect();
        self.fb.ins().jump(join, &nans);
        for (arm, &block) in arms.iter().zip(&arm_blocks) {
            self.fb.switch_to_block(block);
            self.list(&arm.insts)?;
            let results: Vec<BlockArg> = std::iter::once(arm.result)
                .chain(arm.extra.iter().copied())
                .map(|r| self.value(r).map(BlockArg::Value))
                .collect::<Result<_, _>>()?;
            self.fb.ins().jump(join, &results);
        }
        self.fb.switch_to_block(join);
        for (u, slot) in anchored {
            let x = self.fb.ins().stack_load(self.ptr, types::F64, slot, 0);
            self.vals[u as usize] = Some(x);
            self.vectors.remove(&u);
            self.free_slots.push(slot);
        }
        let params = self.fb.block_params(join).to_vec();
        self.vals[v as usize] = params.first().copied();
        self.extras.insert(v, params[1..].to_vec());
        Ok(())
    }
}
