//! What GCON and MOTION need from an expression: its value and its partial derivatives
//! with respect to the measure slots it reads and to time. The compiled derivative of the
//! IR plugs in here through [`ExprFn`]; [`Interpreted`] gives values through the
//! interpreter alone, and [`Closure`] takes hand-written functions (tests, library users).
//! [`Integrated`] is the displacement drive of a VELOCITY or ACCELERATION MOTION: its
//! function integrated once or twice from the initial conditions.

use crate::context::Context;
use crate::interp::Program;
use crate::ir::Function;
use crate::model::elements::Expr;

/// Why an expression of the model gives no usable value.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprError {
    /// It (or one of its derivatives) is NaN or infinite at time `time`.
    NotFinite {
        /// The value given.
        value: f64,
        /// The simulation time.
        time: f64,
    },
    /// A derivative mbfx cannot form, and why.
    NoDerivative(String),
    /// Anything else (an undefined VARIABLE, a slot that resolves to nothing), worded.
    Other(String),
}

impl std::fmt::Display for ExprError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExprError::NotFinite { value, time } => {
                write!(f, "the FUNCTION evaluates to {value} at time {time}")
            }
            ExprError::NoDerivative(why) | ExprError::Other(why) => f.write_str(why),
        }
    }
}

/// Several expressions evaluated by one call ([`crate::ir::fuse`]): every value at time
/// `t` from the model's measure slots `measures` into `out`, in the order they were
/// fused (NaN and infinity pass through; the caller checks what it reads).
pub trait FusedFn {
    /// Every value into `out`.
    fn eval_into(&self, t: f64, measures: &[f64], out: &mut [f64]);
}

/// An expression f(t, m) of time and measure slots m.
pub trait ExprFn {
    /// Measure slots read, sorted (the model's slot numbers).
    fn slots(&self) -> &[u32];
    /// f at time `t`; `measures[s]` holds slot s (only the slots read are filled).
    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, ExprError>;
    /// Writes ∂f/∂m for each slot of [`ExprFn::slots`] (same order) into `grad` and
    /// returns ∂f/∂t.
    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, ExprError>;
    /// (f, ∂f/∂t), with ∂f/∂slot written into `grad` (one evaluation where the
    /// implementation computes them together).
    fn value_gradient(
        &self,
        t: f64,
        measures: &[f64],
        grad: &mut [f64],
    ) -> Result<(f64, f64), ExprError> {
        let dt = self.gradient(t, measures, grad)?;
        Ok((self.value(t, measures)?, dt))
    }

    /// Whether the expression reads TIME (true unless the implementation knows).
    fn reads_time(&self) -> bool {
        true
    }

    /// The second derivative along the direction `dir` (one entry per slot, in the
    /// order of [`ExprFn::slots`]) with time advancing at rate 1: dᵀ·H·d with
    /// d = (dir, 1) and H the Hessian in (slots, t).
    fn second(&self, _t: f64, _measures: &[f64], _dir: &[f64]) -> Result<f64, ExprError> {
        Err(ExprError::NoDerivative(
            "the second derivative of its FUNCTION is not available".into(),
        ))
    }

    /// Forgets what earlier evaluations left behind, as a run from t = 0 again needs
    /// (nothing unless the implementation keeps a history).
    fn rewind(&self) {}
}

/// Values through the interpreter; derivatives are not available until the IR
/// derivative is plugged in.
pub struct Interpreted {
    program: Program,
    slots: Vec<u32>,
    reads_time: bool,
}

impl Interpreted {
    /// The interpreter's program for `function`, with the slots it reads.
    pub fn new(function: Function) -> Self {
        let slots = function.uses.measures.clone();
        let reads_time = function.uses.time;
        Interpreted {
            program: Program::new(function),
            slots,
            reads_time,
        }
    }
}

impl ExprFn for Interpreted {
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn reads_time(&self) -> bool {
        self.reads_time
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, ExprError> {
        let x = self
            .program
            .eval(&Context::new(t, &[]).with_measures(measures));
        if x.is_finite() {
            Ok(x)
        } else {
            Err(ExprError::NotFinite { value: x, time: t })
        }
    }

    fn gradient(&self, _: f64, _: &[f64], _: &mut [f64]) -> Result<f64, ExprError> {
        Err(ExprError::NoDerivative(
            "the derivative of its FUNCTION is not available: it needs the compiled IR \
             derivative, which this build does not plug in yet"
                .into(),
        ))
    }
}

/// Turns an expression of the model into an [`ExprFn`].
pub trait ExprCompiler {
    /// The evaluator of `e`.
    fn compile(&self, e: &Expr) -> Box<dyn ExprFn>;
    /// One evaluator of every value of `functions` ([`FusedFn`]), when
    /// the compiler fuses (None: each expression is evaluated on its own).
    fn fuse(&self, _functions: &[&crate::ir::Function]) -> Option<Box<dyn FusedFn>> {
        None
    }
}

/// One evaluator of the values and partials of `functions` (for each, f, ∂f/∂slot in the
/// slots it reads, ∂f/∂t), with where each one's outputs start and their total count;
/// None when one has no derivative or `exprs` does not fuse.
pub fn fuse_partials(
    exprs: &dyn ExprCompiler,
    functions: &[&crate::ir::Function],
) -> Option<(Box<dyn FusedFn>, Vec<usize>, usize)> {
    use crate::ir::deriv::{gradient, Input};
    let derivatives = functions
        .iter()
        .map(|ir| {
            let wrt: Vec<Input> = ir
                .uses
                .measures
                .iter()
                .map(|&s| Input::Measure(s))
                .chain([Input::Time])
                .collect();
            gradient(ir, &wrt).ok()
        })
        .collect::<Option<Vec<_>>>()?;
    let (mut offsets, mut width) = (Vec::new(), 0);
    for d in &derivatives {
        offsets.push(width);
        width += d.outputs.len();
    }
    let fused = exprs.fuse(&derivatives.iter().collect::<Vec<_>>())?;
    Some((fused, offsets, width))
}

/// Values through the interpreter, no derivatives.
pub struct InterpretOnly;

impl ExprCompiler for InterpretOnly {
    fn compile(&self, e: &Expr) -> Box<dyn ExprFn> {
        Box::new(Interpreted::new(e.function.clone()))
    }
}

/// Hand-written value and gradient: `f(t, m)` and `g(t, m, grad) -> ∂f/∂t`, where `m`
/// holds the slots' values in the order of `slots`.
pub struct Closure<F, G> {
    /// The measure slots the closures read, in the order of their `m`.
    pub slots: Vec<u32>,
    /// The value f(t, m).
    pub f: F,
    /// Fills ∂f/∂m into `grad` and returns ∂f/∂t.
    pub g: G,
}

impl<F, G> ExprFn for Closure<F, G>
where
    F: Fn(f64, &[f64]) -> f64,
    G: Fn(f64, &[f64], &mut [f64]) -> f64,
{
    fn slots(&self) -> &[u32] {
        &self.slots
    }

    fn value(&self, t: f64, measures: &[f64]) -> Result<f64, ExprError> {
        let m: Vec<f64> = self.slots.iter().map(|&s| measures[s as usize]).collect();
        Ok((self.f)(t, &m))
    }

    fn gradient(&self, t: f64, measures: &[f64], grad: &mut [f64]) -> Result<f64, ExprError> {
        let m: Vec<f64> = self.slots.iter().map(|&s| measures[s as usize]).collect();
        Ok((self.g)(t, &m, grad))
    }
}

/// How often a MOTION's FUNCTION is integrated to give its displacement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integration {
    /// VELOCITY: g(t) = ICDISP + ∫₀ᵗ f.
    Once,
    /// ACCELERATION: g(t) = ICDISP + ICVEL·t + ∫₀ᵗ (t − s)·f(s) ds (Cauchy's formula for
    /// the double integral).
    Twice,
}

/// The displacement drive of a VELOCITY or ACCELERATION MOTION (spec §4.5: Adams
/// integrates f numerically, the initial conditions giving the constants).
///
/// Why a position-level drive: the MOTION then stays an ordinary holonomic row
/// m(q) − g(t) = 0 of the index-3 system, with exact ġ (f, or ICVEL + ∫f) for the
/// velocity solve and exact g̈ (ḟ from the IR derivative, or f) for γ, so the integrator
/// and the reconciliation need nothing new. A velocity-level row would leave the
/// displacement to the integrator's error control and an ACCELERATION motion would have no
/// row at all. f depends on time only, so its integral is computed here, to rounding:
/// adaptive Gauss–Kronrod (7–15) from the last checkpoint at or below t, the checkpoints
/// (t, ∫₀ᵗ f, ∫₀ᵗ (t − s) f) kept as time advances, so an integrator stepping forward pays
/// one 15-point panel per new time.
pub struct Integrated {
    f: Box<dyn ExprFn>,
    times: Integration,
    icdisp: f64,
    icvel: f64,
    /// (t, I, J) with I = ∫₀ᵗ f, J = ∫₀ᵗ (t − s)·f(s) ds; increasing t, from (0, 0, 0).
    marks: std::cell::RefCell<Vec<(f64, f64, f64)>>,
}

impl Integrated {
    /// The drive of `f` integrated `times`; an absent ICDISP or ICVEL counts as 0, as
    /// the formula reads (decision).
    pub fn new(f: Box<dyn ExprFn>, times: Integration, icdisp: f64, icvel: f64) -> Self {
        Integrated {
            f,
            times,
            icdisp,
            icvel,
            marks: std::cell::RefCell::new(vec![(0.0, 0.0, 0.0)]),
        }
    }

    /// (∫₀ᵗ f, ∫₀ᵗ (t − s)·f(s) ds).
    fn integrals(&self, t: f64) -> Result<(f64, f64), ExprError> {
        if !t.is_finite() {
            return Err(ExprError::NotFinite { value: t, time: t });
        }
        let mut marks = self.marks.borrow_mut();
        // The last checkpoint at or below t (the first, at 0, for t < 0).
        let k = marks.partition_point(|m| m.0 <= t).max(1) - 1;
        let (tc, ic, jc) = marks[k];
        if tc == t {
            return Ok((ic, jc));
        }
        let f = |s: f64| self.f.value(s, &[]);
        let (di, dj) = gauss_kronrod(&f, tc, t, t, 0)?;
        // ∫₀ᵗ (t − s) f = ∫₀^tc (tc − s) f + (t − tc)·∫₀^tc f + ∫_tc^t (t − s) f.
        let (i, j) = (ic + di, jc + (t - tc) * ic + dj);
        if k + 1 == marks.len() && t > tc {
            marks.push((t, i, j));
        }
        Ok((i, j))
    }
}

/// Gauss–Kronrod 15-point nodes on [−1, 1] (the positive half, QUADPACK's `xgk`), the
/// Kronrod weights, and the 7-point Gauss weights of the odd-indexed nodes.
const GK_X: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const GK_W: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
const G7_W: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// (∫ₐᵇ f, ∫ₐᵇ (t − s)·f(s) ds) by adaptive Gauss–Kronrod: a panel is accepted when its
/// 15- and 7-point results agree to 1e-14 of ∫|f| over it (or after 40 halvings, where
/// only a jump of f is left), else halved.
fn gauss_kronrod(
    f: &dyn Fn(f64) -> Result<f64, ExprError>,
    a: f64,
    b: f64,
    t: f64,
    depth: u32,
) -> Result<(f64, f64), ExprError> {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let (mut k, mut kt, mut g, mut gt, mut abs) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (n, (&x, &w)) in GK_X.iter().zip(&GK_W).enumerate() {
        let points: &[f64] = if x == 0.0 {
            &[mid]
        } else {
            &[mid - half * x, mid + half * x]
        };
        for &s in points {
            let v = f(s)?;
            k += w * v;
            kt += w * (t - s) * v;
            abs += w * v.abs();
            if n % 2 == 1 {
                g += G7_W[n / 2] * v;
                gt += G7_W[n / 2] * (t - s) * v;
            }
        }
    }
    let (k, kt, g, gt, abs) = (k * half, kt * half, g * half, gt * half, abs * half.abs());
    let scale = abs * (1.0 + (t - a).abs().max((t - b).abs()));
    let err = (k - g).abs().max((kt - gt).abs());
    if err <= 1e-14 * scale || depth >= 40 {
        return Ok((k, kt));
    }
    let (i1, j1) = gauss_kronrod(f, a, mid, t, depth + 1)?;
    let (i2, j2) = gauss_kronrod(f, mid, b, t, depth + 1)?;
    Ok((i1 + i2, j1 + j2))
}

impl ExprFn for Integrated {
    fn slots(&self) -> &[u32] {
        &[]
    }

    // The marks are where later integrals start: a rerun must start from t = 0 alone,
    // or its values would round differently from the first run's.
    fn rewind(&self) {
        *self.marks.borrow_mut() = vec![(0.0, 0.0, 0.0)];
    }

    fn value(&self, t: f64, _: &[f64]) -> Result<f64, ExprError> {
        let (i, j) = self.integrals(t)?;
        Ok(match self.times {
            Integration::Once => self.icdisp + i,
            Integration::Twice => self.icdisp + self.icvel * t + j,
        })
    }

    fn gradient(&self, t: f64, _: &[f64], grad: &mut [f64]) -> Result<f64, ExprError> {
        grad.fill(0.0);
        match self.times {
            Integration::Once => self.f.value(t, &[]),
            Integration::Twice => Ok(self.icvel + self.integrals(t)?.0),
        }
    }

    fn second(&self, t: f64, _: &[f64], _: &[f64]) -> Result<f64, ExprError> {
        match self.times {
            Integration::Once => self.f.gradient(t, &[], &mut []),
            Integration::Twice => self.f.value(t, &[]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn closure(f: fn(f64) -> f64) -> Box<dyn ExprFn> {
        Box::new(Closure {
            slots: Vec::new(),
            f: move |t: f64, _: &[f64]| f(t),
            g: |_: f64, _: &[f64], _: &mut [f64]| f64::NAN,
        })
    }

    /// g(t) against closed forms, at times visited forward, backward and repeated (the
    /// checkpoints must not change the answer).
    #[test]
    fn integrals_match_closed_forms() {
        let times = [0.0, 0.013, 0.4, 1.7, 0.9, 3.2, 3.2, 2.5, 6.0];
        // f = cos 3t: ∫ = sin 3t / 3; ∫∫ = (1 − cos 3t)/9.
        let once = Integrated::new(closure(|t| (3.0 * t).cos()), Integration::Once, 0.2, 0.0);
        let twice = Integrated::new(closure(|t| (3.0 * t).cos()), Integration::Twice, 0.2, -1.0);
        for t in times {
            let g1 = once.value(t, &[]).unwrap();
            assert!(
                (g1 - (0.2 + (3.0 * t).sin() / 3.0)).abs() < 1e-15,
                "once at {t}"
            );
            let g2 = twice.value(t, &[]).unwrap();
            let want = 0.2 - t + (1.0 - (3.0 * t).cos()) / 9.0;
            assert!((g2 - want).abs() < 1e-14, "twice at {t}: {g2} vs {want}");
            let v2 = twice.gradient(t, &[], &mut []).unwrap();
            assert!(
                (v2 - (-1.0 + (3.0 * t).sin() / 3.0)).abs() < 1e-15,
                "ġ at {t}"
            );
        }
    }

    #[test]
    fn a_jump_in_the_function_is_integrated_to_rounding() {
        // f = 1 from t = 0.3 on: ∫₀ᵗ f = t − 0.3, ∫₀ᵗ (t − s) f = (t − 0.3)²/2.
        let jump = |t: f64| if t < 0.3 { 0.0 } else { 1.0 };
        let once = Integrated::new(closure(jump), Integration::Once, 0.0, 0.0);
        let twice = Integrated::new(closure(jump), Integration::Twice, 0.0, 0.0);
        for t in [0.1, 0.5, 1.25] {
            let d = (t - 0.3f64).max(0.0);
            assert!(
                (once.value(t, &[]).unwrap() - d).abs() < 1e-12,
                "once at {t}"
            );
            assert!(
                (twice.value(t, &[]).unwrap() - d * d / 2.0).abs() < 1e-12,
                "twice at {t}"
            );
        }
    }
}
