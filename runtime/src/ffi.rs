//! C ABI layer: an `extern "C"` wrapper `mbfx_<name>` for every runtime function and its
//! derivative companion, and the symbol table the JIT registers them from.
//!
//! Scalar functions take and return `f64` (`mbfx_step(x, x0, h0, x1, h1) -> f64`).
//! Gradient wrappers take the same arguments plus `out: *mut f64`, return the value and
//! write the partials to `out` (`mbfx_step_grad(x, x0, h0, x1, h1, out) -> f64` writes
//! 5). Variadic series take `(…, coeffs: *const f64, n: usize)`, splines
//! `(x, z, spline: *const Spline, iord: i32)`. A null pointer, `n == 0` or
//! `n > MAX_COEFFS` gives NaN and writes nothing; nothing panics across the boundary.
//!
//! The wrappers are not `#[no_mangle]`: the JIT registers them by address from
//! [`symbols`], which also states each signature so a test can check every builtin.

use core::{ptr, slice};

use crate::series::MAX_COEFFS;
use crate::spline::Spline;

/// C ABI type of one parameter of a runtime symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Param {
    /// `f64` (Cranelift `F64`).
    F64,
    /// A pointer (`*const f64`, `*mut f64` or `*const Spline`; Cranelift pointer type).
    Ptr,
    /// `usize` (Cranelift pointer-sized integer).
    Usize,
    /// `i32` (Cranelift `I32`).
    I32,
}

/// C ABI return type of a runtime symbol. Every runtime function returns one `f64`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ret {
    /// `f64`.
    F64,
}

/// One runtime function as the JIT registers it: name, address and signature.
#[derive(Debug, Clone, Copy)]
pub struct Symbol {
    /// Symbol name, `mbfx_<name>` (lower case Adams name, `_grad` / `_d2` for companions).
    pub name: &'static str,
    /// Address of the `extern "C"` function.
    pub addr: *const u8,
    /// Parameter types in order.
    pub params: &'static [Param],
    /// Return type.
    pub ret: Ret,
}

/// Writes `partials` to `out` and returns `value`; returns NaN and writes nothing when
/// `out` is null.
///
/// # Safety
/// `out` must be null or valid and aligned for writing `N` `f64`.
#[inline]
unsafe fn write_partials<const N: usize>(out: *mut f64, value: f64, partials: &[f64; N]) -> f64 {
    if out.is_null() {
        return f64::NAN;
    }
    // SAFETY: `out` is non-null and the caller guarantees it is valid for N writes; the
    // source is a local array, so the regions cannot overlap.
    unsafe { ptr::copy_nonoverlapping(partials.as_ptr(), out, N) };
    value
}

/// The coefficient slice behind `(ptr, n)`, or `None` for a null pointer, `n == 0` or
/// `n > MAX_COEFFS`.
///
/// # Safety
/// `ptr` must be null or valid and aligned for reading `n` `f64` for the lifetime `'a`.
#[inline]
unsafe fn coeff_slice<'a>(ptr: *const f64, n: usize) -> Option<&'a [f64]> {
    if ptr.is_null() || n == 0 || n > MAX_COEFFS {
        return None;
    }
    // SAFETY: non-null, and the caller guarantees `n` readable, aligned f64 (n ≤ 31, so
    // the byte length cannot overflow isize).
    Some(unsafe { slice::from_raw_parts(ptr, n) })
}

/// `Param::F64` for each macro argument.
macro_rules! f64_param {
    ($a:ident) => {
        Param::F64
    };
}

/// Defines `pub extern "C" fn $name(args: f64…) -> f64` calling `$f`, the gradient
/// wrapper `$grad` calling `$g`, and `scalar_symbols` listing both.
macro_rules! scalar_wrappers {
    ($($name:ident, $grad:ident ($($a:ident),+) => $f:path, $g:path;)*) => {
        $(
            #[doc = concat!("C ABI wrapper of [`", stringify!($f), "`].")]
            pub extern "C" fn $name($($a: f64),+) -> f64 {
                $f($($a),+)
            }

            #[doc = concat!(
                "C ABI wrapper of [`", stringify!($g), "`]: returns the value and writes the ",
                "partial derivatives (one per argument, in argument order) to `out`.\n\n",
                "# Safety\n\n`out` must be null (the call then returns NaN and writes ",
                "nothing) or valid and aligned for writing one `f64` per argument."
            )]
            pub unsafe extern "C" fn $grad($($a: f64,)+ out: *mut f64) -> f64 {
                let (value, partials) = $g($($a),+);
                // SAFETY: the caller guarantees `out` is null or valid for one write per
                // argument, which is the length of `partials`.
                unsafe { write_partials(out, value, &partials) }
            }
        )*

        /// Appends the symbols of the scalar wrappers and their gradients.
        fn scalar_symbols(table: &mut Vec<Symbol>) {
            $(
                table.push(Symbol {
                    name: stringify!($name),
                    addr: $name as *const u8,
                    params: &[$(f64_param!($a)),+],
                    ret: Ret::F64,
                });
                table.push(Symbol {
                    name: stringify!($grad),
                    addr: $grad as *const u8,
                    params: &[$(f64_param!($a),)+ Param::Ptr],
                    ret: Ret::F64,
                });
            )*
        }
    };
}

/// Defines `pub extern "C" fn $name(args: f64…) -> f64` calling `$f` (functions without
/// a gradient wrapper: the second derivatives), and `plain_symbols` listing them.
macro_rules! plain_wrappers {
    ($($name:ident ($($a:ident),+) => $f:path;)*) => {
        $(
            #[doc = concat!("C ABI wrapper of [`", stringify!($f), "`].")]
            pub extern "C" fn $name($($a: f64),+) -> f64 {
                $f($($a),+)
            }
        )*

        /// Appends the symbols of the plain wrappers.
        fn plain_symbols(table: &mut Vec<Symbol>) {
            $(
                table.push(Symbol {
                    name: stringify!($name),
                    addr: $name as *const u8,
                    params: &[$(f64_param!($a)),+],
                    ret: Ret::F64,
                });
            )*
        }
    };
}

scalar_wrappers! {
    mbfx_abs, mbfx_abs_grad(a) => crate::math::abs, crate::math::abs_grad;
    mbfx_acos, mbfx_acos_grad(a) => crate::math::acos, crate::math::acos_grad;
    mbfx_asin, mbfx_asin_grad(a) => crate::math::asin, crate::math::asin_grad;
    mbfx_atan, mbfx_atan_grad(a) => crate::math::atan, crate::math::atan_grad;
    mbfx_atan2, mbfx_atan2_grad(a1, a2) => crate::math::atan2, crate::math::atan2_grad;
    mbfx_cos, mbfx_cos_grad(a) => crate::math::cos, crate::math::cos_grad;
    mbfx_sin, mbfx_sin_grad(a) => crate::math::sin, crate::math::sin_grad;
    mbfx_tan, mbfx_tan_grad(a) => crate::math::tan, crate::math::tan_grad;
    mbfx_cosh, mbfx_cosh_grad(a) => crate::math::cosh, crate::math::cosh_grad;
    mbfx_sinh, mbfx_sinh_grad(a) => crate::math::sinh, crate::math::sinh_grad;
    mbfx_tanh, mbfx_tanh_grad(a) => crate::math::tanh, crate::math::tanh_grad;
    mbfx_exp, mbfx_exp_grad(a) => crate::math::exp, crate::math::exp_grad;
    mbfx_log, mbfx_log_grad(a) => crate::math::log, crate::math::log_grad;
    mbfx_log10, mbfx_log10_grad(a) => crate::math::log10, crate::math::log10_grad;
    mbfx_sqrt, mbfx_sqrt_grad(a) => crate::math::sqrt, crate::math::sqrt_grad;
    mbfx_aint, mbfx_aint_grad(a) => crate::math::aint, crate::math::aint_grad;
    mbfx_anint, mbfx_anint_grad(a) => crate::math::anint, crate::math::anint_grad;
    mbfx_mod, mbfx_mod_grad(a1, a2) => crate::math::amod, crate::math::amod_grad;
    mbfx_sign, mbfx_sign_grad(a1, a2) => crate::math::sign, crate::math::sign_grad;
    mbfx_dim, mbfx_dim_grad(a1, a2) => crate::math::dim, crate::math::dim_grad;
    mbfx_max, mbfx_max_grad(a1, a2) => crate::math::max, crate::math::max_grad;
    mbfx_min, mbfx_min_grad(a1, a2) => crate::math::min, crate::math::min_grad;
    mbfx_pow, mbfx_pow_grad(a, b) => crate::math::pow, crate::math::pow_grad;
    mbfx_pow_libm, mbfx_pow_libm_grad(a, b) => crate::math::pow_libm, crate::math::pow_grad;
    mbfx_step, mbfx_step_grad(x, x0, h0, x1, h1) => crate::steps::step, crate::steps::step_grad;
    mbfx_step5, mbfx_step5_grad(x, x0, h0, x1, h1) => crate::steps::step5, crate::steps::step5_grad;
    mbfx_havsin, mbfx_havsin_grad(x, x0, h0, x1, h1) =>
        crate::steps::havsin, crate::steps::havsin_grad;
    mbfx_impact, mbfx_impact_grad(x, xd, x1, k, e, cmax, d) =>
        crate::contact::impact, crate::contact::impact_grad;
    mbfx_bistop, mbfx_bistop_grad(x, xd, x1, x2, k, e, cmax, d) =>
        crate::contact::bistop, crate::contact::bistop_grad;
    mbfx_shf, mbfx_shf_grad(x, x0, a, w, phi, b) => crate::series::shf, crate::series::shf_grad;
    mbfx_sweep, mbfx_sweep_grad(x, a, x0, f0, x1, f1, dx) =>
        crate::series::sweep, crate::series::sweep_grad;
}

plain_wrappers! {
    mbfx_step_d2(x, x0, h0, x1, h1) => crate::steps::step_d2;
    mbfx_step5_d2(x, x0, h0, x1, h1) => crate::steps::step5_d2;
    mbfx_havsin_d2(x, x0, h0, x1, h1) => crate::steps::havsin_d2;
}

/// (value, ∂x, ∂x0) of POLY/CHEBY gradients as (value, scalar partials).
#[inline]
fn split3((v, dx, dx0): (f64, f64, f64)) -> (f64, [f64; 2]) {
    (v, [dx, dx0])
}

/// (value, ∂x, ∂x0, ∂ω) of FORCOS/FORSIN gradients as (value, scalar partials).
#[inline]
fn split4((v, dx, dx0, dw): (f64, f64, f64, f64)) -> (f64, [f64; 3]) {
    (v, [dx, dx0, dw])
}

/// Defines the C ABI wrappers of a variadic series `f(x, x0, [w,] coeffs)` and of its
/// gradient, whose `$k` scalar partials come first in `out`, then the n partials ∂/∂a_j.
macro_rules! series_wrappers {
    ($name:ident, $grad:ident ($($s:ident),*) => $f:path, $g:path, $split:ident, $k:literal) => {
        #[doc = concat!(
            "C ABI wrapper of [`", stringify!($f), "`] with the coefficients at `coeffs[..n]`.",
            "\n\nReturns NaN when `coeffs` is null, `n == 0` or `n > 31`.\n\n",
            "# Safety\n\n`coeffs` must be null or valid and aligned for reading `n` `f64`."
        )]
        pub unsafe extern "C" fn $name(
            x: f64,
            x0: f64,
            $($s: f64,)*
            coeffs: *const f64,
            n: usize,
        ) -> f64 {
            // SAFETY: the caller guarantees `coeffs` is null or valid for `n` reads.
            match unsafe { coeff_slice(coeffs, n) } {
                Some(a) => $f(x, x0, $($s,)* a),
                None => f64::NAN,
            }
        }

        #[doc = concat!(
            "C ABI wrapper of [`", stringify!($g), "`]: returns the value and writes the ",
            stringify!($k), " scalar partials (x, x0", $(", ", stringify!($s),)*
            ") then the `n` partials ∂/∂a_j to `out`.\n\n",
            "Returns NaN and writes nothing when a pointer is null, `n == 0` or `n > 31`.",
            "\n\n# Safety\n\n`coeffs` must be null or valid for reading `n` `f64`; `out` ",
            "must be null or valid for writing ", stringify!($k), " + n `f64`."
        )]
        pub unsafe extern "C" fn $grad(
            x: f64,
            x0: f64,
            $($s: f64,)*
            coeffs: *const f64,
            n: usize,
            out: *mut f64,
        ) -> f64 {
            // SAFETY: the caller guarantees `coeffs` is null or valid for `n` reads.
            let Some(a) = (unsafe { coeff_slice(coeffs, n) }) else {
                return f64::NAN;
            };
            if out.is_null() {
                return f64::NAN;
            }
            let mut partials = [0.0; $k + MAX_COEFFS];
            let (head, tail) = partials.split_at_mut($k);
            let (value, scalars) = $split($g(x, x0, $($s,)* a, tail));
            head.copy_from_slice(&scalars);
            // SAFETY: `out` is non-null and the caller guarantees room for $k + n writes
            // (n ≤ 31, so the local array holds them); the regions cannot overlap.
            unsafe { ptr::copy_nonoverlapping(partials.as_ptr(), out, $k + n) };
            value
        }
    };
}

series_wrappers!(mbfx_poly, mbfx_poly_grad() =>
    crate::series::poly, crate::series::poly_grad, split3, 2);
series_wrappers!(mbfx_cheby, mbfx_cheby_grad() =>
    crate::series::cheby, crate::series::cheby_grad, split3, 2);
series_wrappers!(mbfx_forcos, mbfx_forcos_grad(w) =>
    crate::series::forcos, crate::series::forcos_grad, split4, 3);
series_wrappers!(mbfx_forsin, mbfx_forsin_grad(w) =>
    crate::series::forsin, crate::series::forsin_grad, split4, 3);

/// Defines the C ABI wrappers of a spline interpolation and of its gradient.
macro_rules! spline_wrappers {
    ($name:ident, $grad:ident => $f:path, $g:path) => {
        #[doc = concat!(
            "C ABI wrapper of [`", stringify!($f), "`]; NaN when `spline` is null.\n\n",
            "# Safety\n\n`spline` must be null or point to a live [`Spline`]."
        )]
        pub unsafe extern "C" fn $name(x: f64, z: f64, spline: *const Spline, iord: i32) -> f64 {
            // SAFETY: the caller guarantees `spline` is null or points to a live Spline.
            match unsafe { spline.as_ref() } {
                Some(s) => $f(x, z, s, iord),
                None => f64::NAN,
            }
        }

        #[doc = concat!(
            "C ABI wrapper of [`", stringify!($g), "`]: returns the value and writes ",
            "∂/∂x, ∂/∂z to `out`; NaN and nothing written when a pointer is null.\n\n",
            "# Safety\n\n`spline` must be null or point to a live [`Spline`]; `out` must be ",
            "null or valid for writing 2 `f64`."
        )]
        pub unsafe extern "C" fn $grad(x: f64, z: f64, spline: *const Spline, out: *mut f64) -> f64 {
            // SAFETY: the caller guarantees `spline` is null or points to a live Spline.
            let Some(s) = (unsafe { spline.as_ref() }) else {
                return f64::NAN;
            };
            let (value, dx, dz) = $g(x, z, s);
            // SAFETY: the caller guarantees `out` is null or valid for 2 writes.
            unsafe { write_partials(out, value, &[dx, dz]) }
        }
    };
}

spline_wrappers!(mbfx_akispl, mbfx_akispl_grad => crate::spline::akispl, crate::spline::akispl_grad);
spline_wrappers!(mbfx_cubspl, mbfx_cubspl_grad => crate::spline::cubspl, crate::spline::cubspl_grad);

/// Every runtime symbol with its address and C signature, for the JIT to register by
/// name (value functions, `_grad` companions and `_d2` second derivatives).
pub fn symbols() -> Vec<Symbol> {
    use Param::{Ptr, Usize, F64, I32};
    let mut table = Vec::with_capacity(80);
    scalar_symbols(&mut table);
    plain_symbols(&mut table);
    libm::call_directly(&mut table);
    let mut push = |name, addr: *const u8, params: &'static [Param]| {
        table.push(Symbol {
            name,
            addr,
            params,
            ret: Ret::F64,
        });
    };
    push("mbfx_poly", mbfx_poly as *const u8, &[F64, F64, Ptr, Usize]);
    push(
        "mbfx_poly_grad",
        mbfx_poly_grad as *const u8,
        &[F64, F64, Ptr, Usize, Ptr],
    );
    push(
        "mbfx_cheby",
        mbfx_cheby as *const u8,
        &[F64, F64, Ptr, Usize],
    );
    push(
        "mbfx_cheby_grad",
        mbfx_cheby_grad as *const u8,
        &[F64, F64, Ptr, Usize, Ptr],
    );
    push(
        "mbfx_forcos",
        mbfx_forcos as *const u8,
        &[F64, F64, F64, Ptr, Usize],
    );
    push(
        "mbfx_forcos_grad",
        mbfx_forcos_grad as *const u8,
        &[F64, F64, F64, Ptr, Usize, Ptr],
    );
    push(
        "mbfx_forsin",
        mbfx_forsin as *const u8,
        &[F64, F64, F64, Ptr, Usize],
    );
    push(
        "mbfx_forsin_grad",
        mbfx_forsin_grad as *const u8,
        &[F64, F64, F64, Ptr, Usize, Ptr],
    );
    push(
        "mbfx_akispl",
        mbfx_akispl as *const u8,
        &[F64, F64, Ptr, I32],
    );
    push(
        "mbfx_akispl_grad",
        mbfx_akispl_grad as *const u8,
        &[F64, F64, Ptr, Ptr],
    );
    push(
        "mbfx_cubspl",
        mbfx_cubspl as *const u8,
        &[F64, F64, Ptr, I32],
    );
    push(
        "mbfx_cubspl_grad",
        mbfx_cubspl_grad as *const u8,
        &[F64, F64, Ptr, Ptr],
    );
    table
}

#[cfg(test)]
mod tests;

/// The C library functions some wrappers are exactly: their symbols point at libm itself.
///
/// `f64::exp`, `f64::ln`, `f64::powf`, … compile to calls of libm's `exp`, `log`, `pow`, …
/// on Linux with glibc, so a wrapper such as [`mbfx_exp`] only adds a jump (and the PLT's
/// indirect jump) in front of libm. Pointing the symbol at libm gives the same bits with
/// one call instead of three jumps; the interpreter ≡ JIT differential tests check the
/// bits. Elsewhere the wrappers stay, and so do SIN, COS and ATAN2, which are mbfx's own
/// ([`crate::math::trig`]).
mod libm {
    use super::Symbol;

    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    mod c {
        // The C library's declarations (math.h); std links libm on this target.
        extern "C" {
            pub fn acos(a: f64) -> f64;
            pub fn asin(a: f64) -> f64;
            pub fn atan(a: f64) -> f64;
            pub fn tan(a: f64) -> f64;
            pub fn cosh(a: f64) -> f64;
            pub fn sinh(a: f64) -> f64;
            pub fn tanh(a: f64) -> f64;
            pub fn exp(a: f64) -> f64;
            pub fn log(a: f64) -> f64;
            pub fn log10(a: f64) -> f64;
            pub fn pow(a: f64, b: f64) -> f64;
        }
    }

    /// Each wrapper that is exactly a libm function, with that function's address.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    fn direct() -> [(&'static str, *const u8); 11] {
        [
            ("mbfx_acos", c::acos as *const u8),
            ("mbfx_asin", c::asin as *const u8),
            ("mbfx_atan", c::atan as *const u8),
            ("mbfx_tan", c::tan as *const u8),
            ("mbfx_cosh", c::cosh as *const u8),
            ("mbfx_sinh", c::sinh as *const u8),
            ("mbfx_tanh", c::tanh as *const u8),
            ("mbfx_exp", c::exp as *const u8),
            ("mbfx_log", c::log as *const u8),
            ("mbfx_log10", c::log10 as *const u8),
            ("mbfx_pow_libm", c::pow as *const u8),
        ]
    }

    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    fn direct() -> [(&'static str, *const u8); 0] {
        []
    }

    /// Points the symbols of [`direct`] at libm.
    pub(super) fn call_directly(table: &mut [Symbol]) {
        for (name, addr) in direct() {
            if let Some(s) = table.iter_mut().find(|s| s.name == name) {
                s.addr = addr;
            }
        }
    }
}
