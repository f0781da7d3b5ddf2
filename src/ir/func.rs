//! The runtime functions an IR `Call` can name, and how to evaluate each one through the
//! `mbfx-runtime` crate. The constant folder and the interpreter both evaluate through
//! [`Func::eval`], so folding gives exactly the bits that evaluation would.

use mbfx_runtime as rt;

/// A library function of `mbfx-runtime` with a fixed argument list, or a variadic series.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Atan,
    Atan2,
    Cos,
    Sin,
    Tan,
    Cosh,
    Sinh,
    Tanh,
    Exp,
    Log,
    Log10,
    Sqrt,
    Aint,
    Anint,
    Mod,
    Sign,
    Dim,
    Max,
    Min,
    /// `a ** b` with a non-integer or non-literal exponent.
    Pow,
    Step,
    Step5,
    Havsin,
    Impact,
    Bistop,
    Shf,
    Sweep,
    /// Variadic: `x, x0, a0, a1, ...`.
    Poly,
    /// Variadic: `x, x0, a0, a1, ...`.
    Cheby,
    /// Variadic: `x, x0, w, a0, a1, ...`.
    Forcos,
    /// Variadic: `x, x0, w, a0, a1, ...`.
    Forsin,
}

impl Func {
    /// Fixed arguments (before the coefficient list of a series).
    pub fn fixed_args(self) -> usize {
        use Func::*;
        match self {
            Abs | Acos | Asin | Atan | Cos | Sin | Tan | Cosh | Sinh | Tanh | Exp | Log | Log10
            | Sqrt | Aint | Anint => 1,
            Atan2 | Mod | Sign | Dim | Max | Min | Pow => 2,
            Step | Step5 | Havsin => 5,
            Impact => 7,
            Bistop => 8,
            Shf => 6,
            Sweep => 7,
            Poly | Cheby => 2,
            Forcos | Forsin => 3,
        }
    }

    /// True for the series whose trailing arguments are 1 to 31 coefficients.
    pub fn is_variadic(self) -> bool {
        matches!(self, Func::Poly | Func::Cheby | Func::Forcos | Func::Forsin)
    }

    /// Name of the `extern "C"` symbol in `mbfx-runtime` the JIT calls.
    pub fn symbol(self) -> &'static str {
        use Func::*;
        match self {
            Abs => "mbfx_abs",
            Acos => "mbfx_acos",
            Asin => "mbfx_asin",
            Atan => "mbfx_atan",
            Atan2 => "mbfx_atan2",
            Cos => "mbfx_cos",
            Sin => "mbfx_sin",
            Tan => "mbfx_tan",
            Cosh => "mbfx_cosh",
            Sinh => "mbfx_sinh",
            Tanh => "mbfx_tanh",
            Exp => "mbfx_exp",
            Log => "mbfx_log",
            Log10 => "mbfx_log10",
            Sqrt => "mbfx_sqrt",
            Aint => "mbfx_aint",
            Anint => "mbfx_anint",
            Mod => "mbfx_mod",
            Sign => "mbfx_sign",
            Dim => "mbfx_dim",
            Max => "mbfx_max",
            Min => "mbfx_min",
            Pow => "mbfx_pow",
            Step => "mbfx_step",
            Step5 => "mbfx_step5",
            Havsin => "mbfx_havsin",
            Impact => "mbfx_impact",
            Bistop => "mbfx_bistop",
            Shf => "mbfx_shf",
            Sweep => "mbfx_sweep",
            Poly => "mbfx_poly",
            Cheby => "mbfx_cheby",
            Forcos => "mbfx_forcos",
            Forsin => "mbfx_forsin",
        }
    }

    /// Evaluates the function on `args` (fixed arguments, then any coefficients).
    /// A wrong argument count gives NaN (the checker never builds one).
    pub fn eval(self, a: &[f64]) -> f64 {
        use Func::*;
        let n = self.fixed_args();
        if a.len() < n || (!self.is_variadic() && a.len() != n) {
            return f64::NAN;
        }
        match self {
            Abs => rt::abs(a[0]),
            Acos => rt::acos(a[0]),
            Asin => rt::asin(a[0]),
            Atan => rt::atan(a[0]),
            Atan2 => rt::atan2(a[0], a[1]),
            Cos => rt::cos(a[0]),
            Sin => rt::sin(a[0]),
            Tan => rt::tan(a[0]),
            Cosh => rt::cosh(a[0]),
            Sinh => rt::sinh(a[0]),
            Tanh => rt::tanh(a[0]),
            Exp => rt::exp(a[0]),
            Log => rt::log(a[0]),
            Log10 => rt::log10(a[0]),
            Sqrt => rt::sqrt(a[0]),
            Aint => rt::aint(a[0]),
            Anint => rt::anint(a[0]),
            Mod => rt::amod(a[0], a[1]),
            Sign => rt::sign(a[0], a[1]),
            Dim => rt::dim(a[0], a[1]),
            Max => rt::max(a[0], a[1]),
            Min => rt::min(a[0], a[1]),
            Pow => rt::pow(a[0], a[1]),
            Step => rt::step(a[0], a[1], a[2], a[3], a[4]),
            Step5 => rt::step5(a[0], a[1], a[2], a[3], a[4]),
            Havsin => rt::havsin(a[0], a[1], a[2], a[3], a[4]),
            Impact => rt::impact(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
            Bistop => rt::bistop(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]),
            Shf => rt::shf(a[0], a[1], a[2], a[3], a[4], a[5]),
            Sweep => rt::sweep(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
            Poly => rt::poly(a[0], a[1], &a[2..]),
            Cheby => rt::cheby(a[0], a[1], &a[2..]),
            Forcos => rt::forcos(a[0], a[1], a[2], &a[3..]),
            Forsin => rt::forsin(a[0], a[1], a[2], &a[3..]),
        }
    }
}
