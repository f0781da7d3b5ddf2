//! The runtime functions machine code may call: one table, from `mbfx_runtime::ffi`,
//! looked up by name, and the parameter list the translator passes to each, so a wrong
//! signature is an error at compile time (and a test checks every builtin).

use crate::vocab::builtins::SplineKind;
use crate::vocab::func::{Callee, Func};
use mbfx_runtime::ffi::{self, Param, Symbol};
use rustc_hash::FxHashMap;
use std::sync::OnceLock;

/// Every runtime symbol by name.
fn table() -> &'static FxHashMap<&'static str, SymbolEntry> {
    static TABLE: OnceLock<FxHashMap<&'static str, SymbolEntry>> = OnceLock::new();
    TABLE.get_or_init(|| {
        ffi::symbols()
            .into_iter()
            .map(|s| (s.name, SymbolEntry(s)))
            .collect()
    })
}

/// A [`Symbol`] in a static table: its address is a function's, valid for the program's
/// life and never written through.
struct SymbolEntry(Symbol);
// SAFETY: the address is an immutable function pointer; sharing it across threads is sound.
unsafe impl Sync for SymbolEntry {}
// SAFETY: as above.
unsafe impl Send for SymbolEntry {}

/// The runtime symbol called `name`.
pub fn lookup(name: &str) -> Option<&'static Symbol> {
    table().get(name).map(|e| &e.0)
}

/// Address of the runtime symbol called `name` (the JIT's symbol resolver).
pub fn address(name: &str) -> Option<*const u8> {
    lookup(name).map(|s| s.addr)
}

/// Name of the value function of `func` and of its derivative companion.
pub fn names(func: Func, grad: bool) -> String {
    if grad {
        format!("{}_grad", func.symbol())
    } else {
        func.symbol().to_string()
    }
}

/// The parameters the translator passes to `func` (or its `_grad` companion): every
/// argument as `f64`, except the coefficients of a series, passed as (pointer, count);
/// a companion then takes the output pointer.
pub fn params(func: Func, grad: bool) -> Vec<Param> {
    let fixed = match func.callee() {
        Callee::F1(_) => 1,
        Callee::F2(_) => 2,
        Callee::F5(_) => 5,
        Callee::F6(_) => 6,
        Callee::F7(_) => 7,
        Callee::F8(_) => 8,
        Callee::Series2(_) => 2,
        Callee::Series3(_) => 3,
    };
    let mut p = vec![Param::F64; fixed];
    if func.is_variadic() {
        p.extend([Param::Ptr, Param::Usize]);
    }
    if grad {
        p.push(Param::Ptr);
    }
    p
}

/// Name and parameters of a spline interpolation.
pub fn spline(kind: SplineKind) -> (&'static str, [Param; 4]) {
    let name = match kind {
        SplineKind::Akima => "mbfx_akispl",
        SplineKind::Cubic => "mbfx_cubspl",
    };
    (name, [Param::F64, Param::F64, Param::Ptr, Param::I32])
}
