//! The runtime functions a builtin can stand for and an IR `Call` can name, and how to
//! evaluate each one through the `mbfx-runtime` crate (its only import). The constant
//! folder and the interpreter both evaluate through [`Func::eval`], so folding gives
//! exactly the bits that evaluation would; the JIT calls [`Func::symbol`].

use mbfx_runtime as rt;

/// A library function of `mbfx-runtime` with a fixed argument list, or a variadic series.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    /// `ABS(a)`: |a|.
    Abs,
    /// `ACOS(a)`: arc cosine.
    Acos,
    /// `ASIN(a)`: arc sine.
    Asin,
    /// `ATAN(a)`: arc tangent.
    Atan,
    /// `ATAN2(y, x)`: angle of the point (x, y) in (−π, π].
    Atan2,
    /// `COS(a)`.
    Cos,
    /// `SIN(a)`.
    Sin,
    /// `TAN(a)`.
    Tan,
    /// `COSH(a)`.
    Cosh,
    /// `SINH(a)`.
    Sinh,
    /// `TANH(a)`.
    Tanh,
    /// `EXP(a)`.
    Exp,
    /// `LOG(a)`: natural logarithm.
    Log,
    /// `LOG10(a)`.
    Log10,
    /// `SQRT(a)`.
    Sqrt,
    /// `AINT(a)`: a truncated toward zero.
    Aint,
    /// `ANINT(a)`: nearest whole number, halves away from zero.
    Anint,
    /// `MOD(a1, a2)`: remainder with the sign of a1.
    Mod,
    /// `SIGN(a1, a2)`: |a1| with the sign of a2.
    Sign,
    /// `DIM(a1, a2)`: a1 − a2 if positive, else 0.
    Dim,
    /// `MAX(a1, a2)`.
    Max,
    /// `MIN(a1, a2)`.
    Min,
    /// `a ** b` with a non-integer or non-literal exponent.
    Pow,
    /// libm `pow` without `**`'s NaN-first test, for arguments known not to be NaN: only
    /// the lowering of IMPACT and BISTOP emits it, in the contact arm.
    PowLibm,
    /// `STEP(x, x0, h0, x1, h1)`: cubic step.
    Step,
    /// `STEP5(x, x0, h0, x1, h1)`: quintic step.
    Step5,
    /// `HAVSIN(x, x0, h0, x1, h1)`: haversine step.
    Havsin,
    /// `IMPACT(x, dx, x1, k, e, cmax, d)`: one-sided contact force.
    Impact,
    /// `BISTOP(x, dx, x1, x2, k, e, cmax, d)`: two-sided contact force.
    Bistop,
    /// `SHF(x, x0, a, w, phi, b)`: simple harmonic function.
    Shf,
    /// `SWEEP(x, a, x0, f0, x1, f1, dx)`: sine of swept frequency.
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
    /// Every function, in declaration order.
    pub const ALL: [Func; 35] = {
        use Func::*;
        [
            Abs, Acos, Asin, Atan, Atan2, Cos, Sin, Tan, Cosh, Sinh, Tanh, Exp, Log, Log10, Sqrt,
            Aint, Anint, Mod, Sign, Dim, Max, Min, Pow, PowLibm, Step, Step5, Havsin, Impact,
            Bistop, Shf, Sweep, Poly, Cheby, Forcos, Forsin,
        ]
    };

    /// Fixed arguments (before the coefficient list of a series).
    pub fn fixed_args(self) -> usize {
        use Func::*;
        match self {
            Abs | Acos | Asin | Atan | Cos | Sin | Tan | Cosh | Sinh | Tanh | Exp | Log | Log10
            | Sqrt | Aint | Anint => 1,
            Atan2 | Mod | Sign | Dim | Max | Min | Pow | PowLibm => 2,
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
            PowLibm => "mbfx_pow_libm",
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

    /// The runtime function this names, typed by its argument list: the one mapping from
    /// `Func` to `mbfx-runtime` that constant folding and every back end share.
    pub fn callee(self) -> Callee {
        use Func::*;
        match self {
            Abs => Callee::F1(rt::abs),
            Acos => Callee::F1(rt::acos),
            Asin => Callee::F1(rt::asin),
            Atan => Callee::F1(rt::atan),
            Cos => Callee::F1(rt::cos),
            Sin => Callee::F1(rt::sin),
            Tan => Callee::F1(rt::tan),
            Cosh => Callee::F1(rt::cosh),
            Sinh => Callee::F1(rt::sinh),
            Tanh => Callee::F1(rt::tanh),
            Exp => Callee::F1(rt::exp),
            Log => Callee::F1(rt::log),
            Log10 => Callee::F1(rt::log10),
            Sqrt => Callee::F1(rt::sqrt),
            Aint => Callee::F1(rt::aint),
            Anint => Callee::F1(rt::anint),
            Atan2 => Callee::F2(rt::atan2),
            Mod => Callee::F2(rt::amod),
            Sign => Callee::F2(rt::sign),
            Dim => Callee::F2(rt::dim),
            Max => Callee::F2(rt::max),
            Min => Callee::F2(rt::min),
            Pow => Callee::F2(rt::pow),
            PowLibm => Callee::F2(rt::pow_libm),
            Step => Callee::F5(rt::step),
            Step5 => Callee::F5(rt::step5),
            Havsin => Callee::F5(rt::havsin),
            Shf => Callee::F6(rt::shf),
            Impact => Callee::F7(rt::impact),
            Sweep => Callee::F7(rt::sweep),
            Bistop => Callee::F8(rt::bistop),
            Poly => Callee::Series2(rt::poly),
            Cheby => Callee::Series2(rt::cheby),
            Forcos => Callee::Series3(rt::forcos),
            Forsin => Callee::Series3(rt::forsin),
        }
    }

    /// Evaluates the function on `args` (fixed arguments, then any coefficients).
    /// A wrong argument count gives NaN (the checker never builds one).
    pub fn eval(self, a: &[f64]) -> f64 {
        let n = self.fixed_args();
        if a.len() < n || (!self.is_variadic() && a.len() != n) {
            return f64::NAN;
        }
        match self.callee() {
            Callee::F1(f) => f(a[0]),
            Callee::F2(f) => f(a[0], a[1]),
            Callee::F5(f) => f(a[0], a[1], a[2], a[3], a[4]),
            Callee::F6(f) => f(a[0], a[1], a[2], a[3], a[4], a[5]),
            Callee::F7(f) => f(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
            Callee::F8(f) => f(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]),
            Callee::Series2(f) => f(a[0], a[1], &a[2..]),
            Callee::Series3(f) => f(a[0], a[1], a[2], &a[3..]),
        }
    }
}

/// Signatures of the runtime functions with five to eight arguments.
pub type Fn5 = fn(f64, f64, f64, f64, f64) -> f64;
/// Signature of a runtime function with six arguments.
pub type Fn6 = fn(f64, f64, f64, f64, f64, f64) -> f64;
/// Signature of a runtime function with seven arguments.
pub type Fn7 = fn(f64, f64, f64, f64, f64, f64, f64) -> f64;
/// Signature of a runtime function with eight arguments.
pub type Fn8 = fn(f64, f64, f64, f64, f64, f64, f64, f64) -> f64;

/// A runtime function with its Rust signature: fixed arity 1, 2, 5, 6, 7 or 8, or a series
/// taking `x, x0` (and `w`) before its coefficient slice.
#[derive(Clone, Copy, Debug)]
pub enum Callee {
    /// One argument.
    F1(fn(f64) -> f64),
    /// Two arguments.
    F2(fn(f64, f64) -> f64),
    /// Five arguments.
    F5(Fn5),
    /// Six arguments.
    F6(Fn6),
    /// Seven arguments.
    F7(Fn7),
    /// Eight arguments.
    F8(Fn8),
    /// A series `f(x, x0, coefficients)` (POLY, CHEBY).
    Series2(fn(f64, f64, &[f64]) -> f64),
    /// A series `f(x, x0, w, coefficients)` (FORCOS, FORSIN).
    Series3(fn(f64, f64, f64, &[f64]) -> f64),
}

/// Copies the partials of a fixed-arity gradient companion into `out` and returns the value.
fn spread<const N: usize>((v, g): (f64, [f64; N]), out: &mut [f64]) -> f64 {
    for (o, p) in out.iter_mut().zip(g) {
        *o = p;
    }
    v
}

impl Func {
    /// Evaluates the function and its partials with respect to every argument, in
    /// argument order, through the runtime's analytic derivative companions (the
    /// `mbfx_<name>_grad` functions the JIT calls). `out` must hold `a.len()` values;
    /// a wrong argument count gives NaN everywhere.
    pub fn grad(self, a: &[f64], out: &mut [f64]) -> f64 {
        use Func::*;
        let n = self.fixed_args();
        if a.len() < n || (!self.is_variadic() && a.len() != n) || out.len() < a.len() {
            out.fill(f64::NAN);
            return f64::NAN;
        }
        match self {
            Abs => spread(rt::abs_grad(a[0]), out),
            Acos => spread(rt::acos_grad(a[0]), out),
            Asin => spread(rt::asin_grad(a[0]), out),
            Atan => spread(rt::atan_grad(a[0]), out),
            Cos => spread(rt::cos_grad(a[0]), out),
            Sin => spread(rt::sin_grad(a[0]), out),
            Tan => spread(rt::tan_grad(a[0]), out),
            Cosh => spread(rt::cosh_grad(a[0]), out),
            Sinh => spread(rt::sinh_grad(a[0]), out),
            Tanh => spread(rt::tanh_grad(a[0]), out),
            Exp => spread(rt::exp_grad(a[0]), out),
            Log => spread(rt::log_grad(a[0]), out),
            Log10 => spread(rt::log10_grad(a[0]), out),
            Sqrt => spread(rt::sqrt_grad(a[0]), out),
            Aint => spread(rt::aint_grad(a[0]), out),
            Anint => spread(rt::anint_grad(a[0]), out),
            Atan2 => spread(rt::atan2_grad(a[0], a[1]), out),
            Mod => spread(rt::amod_grad(a[0], a[1]), out),
            Sign => spread(rt::sign_grad(a[0], a[1]), out),
            Dim => spread(rt::dim_grad(a[0], a[1]), out),
            Max => spread(rt::max_grad(a[0], a[1]), out),
            Min => spread(rt::min_grad(a[0], a[1]), out),
            Pow | PowLibm => spread(rt::pow_grad(a[0], a[1]), out),
            Step => spread(rt::step_grad(a[0], a[1], a[2], a[3], a[4]), out),
            Step5 => spread(rt::step5_grad(a[0], a[1], a[2], a[3], a[4]), out),
            Havsin => spread(rt::havsin_grad(a[0], a[1], a[2], a[3], a[4]), out),
            Shf => spread(rt::shf_grad(a[0], a[1], a[2], a[3], a[4], a[5]), out),
            Impact => spread(
                rt::impact_grad(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
                out,
            ),
            Sweep => spread(
                rt::sweep_grad(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
                out,
            ),
            Bistop => spread(
                rt::bistop_grad(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]),
                out,
            ),
            Poly | Cheby => {
                let g = if self == Poly {
                    rt::poly_grad
                } else {
                    rt::cheby_grad
                };
                let (head, tail) = out.split_at_mut(2);
                let (v, dx, dx0) = g(a[0], a[1], &a[2..], &mut tail[..a.len() - 2]);
                head.copy_from_slice(&[dx, dx0]);
                v
            }
            Forcos | Forsin => {
                let g = if self == Forcos {
                    rt::forcos_grad
                } else {
                    rt::forsin_grad
                };
                let (head, tail) = out.split_at_mut(3);
                let (v, dx, dx0, dw) = g(a[0], a[1], a[2], &a[3..], &mut tail[..a.len() - 3]);
                head.copy_from_slice(&[dx, dx0, dw]);
                v
            }
        }
    }

    /// The partial derivative with respect to argument `wrt` (see [`Func::grad`]).
    pub fn partial(self, wrt: usize, a: &[f64]) -> f64 {
        let mut out = [0.0; 40];
        let Some(out) = out.get_mut(..a.len()) else {
            return f64::NAN;
        };
        self.grad(a, out);
        out.get(wrt).copied().unwrap_or(f64::NAN)
    }
}
