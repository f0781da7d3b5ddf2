//! Second derivatives: the companions' partials written out as IR.
//!
//! A first derivative ([`super::gradient`]) takes a library call's partial from the
//! runtime's analytic companion, an [`crate::ir::Inst::Partial`], which has no derivative
//! of its own. For a derivative that will be differentiated again ([`super::hessian`]),
//! [`partial`] writes the partial out instead, as arithmetic, selects and library calls
//! computing it by the formula the companion documents (∂SIN = COS, ∂POLY/∂x = POLY of
//! the scaled coefficients, ∂FORCOS/∂x = a FORSIN, …), so the second pass differentiates
//! it like any other code. Kinks keep the companions' branch choices, and
//! piecewise-constant partials (ABS, SIGN, AINT, MOD's quotient, …) are selects of
//! constants, whose own derivative is zero. Every partial is NaN where the call's value
//! is NaN, as every companion's is.
//!
//! STEP, STEP5, HAVSIN, IMPACT and BISTOP are lowered to arithmetic before the first
//! derivative ([`crate::ir::lower::lower_all_contacts`]: the contacts whose parameters
//! vary too, checked by selects), so they never reach here; SWEEP in arguments other than
//! x and its amplitude has no formula: its second derivative is an error naming the
//! function.

use super::DerivError;
use crate::diag::Span;
use crate::ir::builder::{Arith, Builder};
use crate::ir::lower::Lower as Ir;
use crate::ir::{Cmp, Value};
use crate::vocab::func::Func;
use core::f64::consts::LN_10;

/// ∂func/∂(argument `wrt`) at `args` written out as IR (see the module documentation),
/// NaN where the call's value is NaN; or the function, when no formula is written.
pub(super) fn partial(
    b: &mut Builder,
    func: Func,
    wrt: u32,
    args: &[Value],
    span: Span,
) -> Result<Value, DerivError> {
    let mut e = Ir { b, span };
    let p = e
        .partial(func, wrt as usize, args)
        .ok_or(DerivError::SecondOrder(func))?;
    let value = e.call(func, args);
    let nan = e.c(f64::NAN);
    Ok(e.sel(Cmp::Uno, value, value, nan, p))
}

/// The lowering's emitter (constants, arithmetic, calls and selects at one span), with
/// the partials' formulas added here.
impl Ir<'_> {
    /// `1 / √(1 − a²)`, the derivative of ASIN (and of ACOS negated).
    fn inv_sqrt_one_minus_square(&mut self, a: Value) -> Value {
        let (one, a2) = (self.c(1.0), self.mul(a, a));
        let s = self.sub(one, a2);
        let r = self.b.sqrt(s, self.span.clone());
        self.div(one, r)
    }

    /// `1 ± t·t` with t = func(a): the derivative of TAN (+) and TANH (−).
    fn one_and_square(&mut self, func: Func, a: Value, op: Arith) -> Value {
        let t = self.call(func, &[a]);
        let (one, t2) = (self.c(1.0), self.mul(t, t));
        self.op(op, one, t2)
    }

    /// +1 where `a ≥ 0`, −1 below (a NaN takes −1; the guard makes it NaN).
    fn sign_of(&mut self, a: Value) -> Value {
        let (zero, one, minus) = (self.c(0.0), self.c(1.0), self.c(-1.0));
        self.sel(Cmp::Ge, a, zero, one, minus)
    }

    /// ∂func/∂(argument `wrt`) at `a`, or None where no formula is written.
    fn partial(&mut self, func: Func, wrt: usize, a: &[Value]) -> Option<Value> {
        use Func::*;
        let x = *a.first()?;
        let zero = self.c(0.0);
        let one = self.c(1.0);
        Some(match (func, wrt) {
            (Sin, 0) => self.call(Cos, &[x]),
            (Cos, 0) => {
                let s = self.call(Sin, &[x]);
                self.neg(s)
            }
            (Tan, 0) => self.one_and_square(Tan, x, Arith::Add),
            (Tanh, 0) => self.one_and_square(Tanh, x, Arith::Sub),
            (Cosh, 0) => self.call(Sinh, &[x]),
            (Sinh, 0) => self.call(Cosh, &[x]),
            (Exp, 0) => self.call(Exp, &[x]),
            (Log, 0) => self.div(one, x),
            (Log10, 0) => {
                let ln10 = self.c(LN_10);
                let d = self.mul(x, ln10);
                self.div(one, d)
            }
            (Sqrt, 0) => {
                let (half, r) = (self.c(0.5), self.call(Sqrt, &[x]));
                self.div(half, r)
            }
            (Asin, 0) => self.inv_sqrt_one_minus_square(x),
            (Acos, 0) => {
                let d = self.inv_sqrt_one_minus_square(x);
                self.neg(d)
            }
            (Atan, 0) => {
                let x2 = self.mul(x, x);
                let d = self.add(one, x2);
                self.div(one, d)
            }
            (Atan2, _) => {
                let (y, x) = (a[0], *a.get(1)?);
                let (y2, x2) = (self.mul(y, y), self.mul(x, x));
                let r2 = self.add(y2, x2);
                if wrt == 0 {
                    self.div(x, r2)
                } else {
                    let d = self.div(y, r2);
                    self.neg(d)
                }
            }
            (Abs, 0) => {
                let (minus, nan) = (self.c(-1.0), self.c(f64::NAN));
                let below = self.sel(Cmp::Lt, x, zero, minus, nan);
                self.sel(Cmp::Ge, x, zero, one, below)
            }
            (Aint | Anint, 0) => zero,
            (Mod, 0) => one,
            (Mod, 1) => {
                // −q, q = ANINT((a1 − r) / a2): the quotient the companion recovers.
                let r = self.call(Mod, a);
                let n = self.sub(x, r);
                let q = self.div(n, a[1]);
                let q = self.call(Anint, &[q]);
                self.neg(q)
            }
            (Sign, 0) => {
                let (s1, s2) = (self.sign_of(x), self.sign_of(a[1]));
                self.mul(s1, s2)
            }
            (Sign, 1) => zero,
            (Dim, _) => {
                let hit = self.c(if wrt == 0 { 1.0 } else { -1.0 });
                self.sel(Cmp::Gt, x, a[1], hit, zero)
            }
            (Max | Min, _) => {
                // Ties pick a1 (the companions' choice).
                let cmp = if func == Max { Cmp::Ge } else { Cmp::Le };
                let (first, second) = if wrt == 0 { (one, zero) } else { (zero, one) };
                self.sel(cmp, x, a[1], first, second)
            }
            (Pow | PowLibm, 0) => {
                // b·a^(b−1), exactly 0 when b = 0.
                let e = a[1];
                let e1 = self.sub(e, one);
                let p = self.call(func, &[x, e1]);
                let d = self.mul(e, p);
                self.sel(Cmp::Eq, e, zero, zero, d)
            }
            (Pow | PowLibm, 1) => {
                // v·ln a for a > 0, 0·v otherwise (the companion's decision).
                let v = self.call(func, a);
                let ln = self.call(Log, &[x]);
                let (pos, other) = (self.mul(v, ln), self.mul(zero, v));
                self.sel(Cmp::Gt, x, zero, pos, other)
            }
            (Shf, _) => self.shf(wrt, a)?,
            (Poly, _) => self.poly(wrt, a)?,
            (Cheby, _) => self.cheby(wrt, a)?,
            (Forcos | Forsin, _) => self.fourier(func == Forcos, wrt, a)?,
            (Sweep, 0 | 1) => self.sweep(wrt, a)?,
            _ => return None,
        })
    }

    /// SHF(x, x0, a, ω, φ, b): with t = x − x0, θ = ω·t − φ, ac = a·cos θ: (ac·ω, −ac·ω,
    /// sin θ, ac·t, −ac, 1).
    fn shf(&mut self, wrt: usize, a: &[Value]) -> Option<Value> {
        let [x, x0, amp, w, phi, _] = *a else {
            return None;
        };
        let t = self.sub(x, x0);
        let wt = self.mul(w, t);
        let theta = self.sub(wt, phi);
        let cos = self.call(Func::Cos, &[theta]);
        let ac = self.mul(amp, cos);
        Some(match wrt {
            0 => self.mul(ac, w),
            1 => {
                let d = self.mul(ac, w);
                self.neg(d)
            }
            2 => self.call(Func::Sin, &[theta]),
            3 => self.mul(ac, t),
            4 => self.neg(ac),
            _ => self.c(1.0),
        })
    }

    /// SWEEP(x, a, x0, f0, x1, f1, dx) in x and a (the runtime's formulas): with the phase
    /// φ (f0·x below x0; f0·u + (f1 − f0)/(2l)·u² + f0·x0 between, u = x − x0,
    /// l = x1 − x0; f1·x − (f1 − f0)/2·(x1 + x0) above), the fade F = STEP5(x, x0, 0,
    /// x0 + dx, 1), S = sin 2πφ: ∂a = F·S, ∂x = a·F_x·S + a·F·2π·cos 2πφ·φ_x, with
    /// F_x = 30·Δ²(1 − Δ)²/dx inside the fade (Δ = u/dx), 0 outside. The other arguments
    /// have no formula here.
    fn sweep(&mut self, wrt: usize, a: &[Value]) -> Option<Value> {
        let [x, amp, x0, f0, x1, f1, dx] = *a else {
            return None;
        };
        let (zero, one, half, two) = (self.c(0.0), self.c(1.0), self.c(0.5), self.c(2.0));
        let (u, l, df) = (self.sub(x, x0), self.sub(x1, x0), self.sub(f1, f0));
        // The phase and its slope on each piece: c = (f1 − f0)/(2l).
        let below = self.mul(f0, x);
        let (f1x, mid) = (self.mul(f1, x), self.add(x1, x0));
        let shift = self.prod(&[df, half, mid]);
        let above = self.sub(f1x, shift);
        let two_l = self.mul(two, l);
        let c = self.div(df, two_l);
        let (f0u, cuu, f0x0) = (self.mul(f0, u), self.prod(&[c, u, u]), self.mul(f0, x0));
        let inside = self.add(f0u, cuu);
        let inside = self.add(inside, f0x0);
        let two_cu = self.prod(&[two, c, u]);
        let slope_inside = self.add(f0, two_cu);
        let phase = self.sel(Cmp::Ge, x, x1, above, inside);
        let phase = self.sel(Cmp::Le, x, x0, below, phase);
        let slope = self.sel(Cmp::Ge, x, x1, f1, slope_inside);
        let slope = self.sel(Cmp::Le, x, x0, f0, slope);
        let tau = self.c(core::f64::consts::TAU);
        let angle = self.mul(tau, phase);
        let sin = self.call(Func::Sin, &[angle]);
        let end = self.add(x0, dx);
        let fade = self.call(Func::Step5, &[x, x0, zero, end, one]);
        if wrt == 1 {
            return Some(self.mul(fade, sin));
        }
        // F_x = 30·Δ²(1 − Δ)²/dx inside the fade.
        let d = self.div(u, dx);
        let e = self.sub(one, d);
        let thirty = self.c(30.0);
        let ramp = self.prod(&[thirty, d, e, d, e]);
        let ramp = self.div(ramp, dx);
        let fade_x = self.sel(Cmp::Ge, x, end, zero, ramp);
        let fade_x = self.sel(Cmp::Le, x, x0, zero, fade_x);
        let cos = self.call(Func::Cos, &[angle]);
        let t1 = self.mul(fade_x, sin);
        let t2 = self.prod(&[fade, tau, cos, slope]);
        let sum = self.add(t1, t2);
        Some(self.mul(amp, sum))
    }

    /// The product of `vs`, left to right.
    fn prod(&mut self, vs: &[Value]) -> Value {
        let mut p = vs[0];
        for &v in &vs[1..] {
            p = self.mul(p, v);
        }
        p
    }

    /// t^k by repeated multiplication (t⁰ = 1), as the series companions compute it.
    fn power(&mut self, t: Value, k: usize) -> Value {
        let mut p = self.c(1.0);
        for _ in 0..k {
            p = self.mul(p, t);
        }
        p
    }

    /// POLY(x, x0, a0…): ∂/∂x = POLY(x, x0, 1·a1, 2·a2, …), ∂/∂x0 = −∂/∂x, ∂/∂a_k = t^k.
    fn poly(&mut self, wrt: usize, a: &[Value]) -> Option<Value> {
        let (x, x0, coeffs) = (a[0], *a.get(1)?, a.get(2..)?);
        if wrt >= 2 {
            let t = self.sub(x, x0);
            return Some(self.power(t, wrt - 2));
        }
        let d = if coeffs.len() < 2 {
            self.c(0.0)
        } else {
            let mut args = vec![x, x0];
            for (k, &c) in coeffs.iter().enumerate().skip(1) {
                let kf = self.c(k as f64);
                args.push(self.mul(kf, c));
            }
            self.call(Func::Poly, &args)
        };
        Some(if wrt == 0 { d } else { self.neg(d) })
    }

    /// CHEBY(x, x0, a0…): ∂/∂x is the Chebyshev series of the derivative coefficients
    /// (b_{j−1} = b_{j+1} + 2j·a_j from the top, b0 halved), ∂/∂x0 = −∂/∂x, ∂/∂a_k =
    /// T_k(t) = CHEBY(x, x0, 0, …, 0, 1).
    fn cheby(&mut self, wrt: usize, a: &[Value]) -> Option<Value> {
        let (x, x0, coeffs) = (a[0], *a.get(1)?, a.get(2..)?);
        let (zero, one) = (self.c(0.0), self.c(1.0));
        if wrt >= 2 {
            let mut args = vec![x, x0];
            args.extend(std::iter::repeat_n(zero, wrt - 2));
            args.push(one);
            return Some(self.call(Func::Cheby, &args));
        }
        let n = coeffs.len();
        let d = if n < 2 {
            zero
        } else {
            let mut bs = vec![zero; n + 1];
            for j in (1..n).rev() {
                let two_j = self.c(2.0 * j as f64);
                let term = self.mul(two_j, coeffs[j]);
                bs[j - 1] = self.add(bs[j + 1], term);
            }
            let half = self.c(0.5);
            bs[0] = self.mul(bs[0], half);
            let mut args = vec![x, x0];
            args.extend_from_slice(&bs[..n - 1]);
            self.call(Func::Cheby, &args)
        };
        Some(if wrt == 0 { d } else { self.neg(d) })
    }

    /// FORCOS/FORSIN(x, x0, ω, a0…), t = x − x0: ∂/∂x = ∓Σ a_j·(jω)·sin|cos(jωt), the
    /// other series with coefficients (0, ∓1·ω·a1, ∓2·ω·a2, …); ∂/∂x0 = −∂/∂x; ∂/∂ω the
    /// same with jt in place of jω; ∂/∂a0 = 1, ∂/∂a_j = cos|sin(jω·t).
    fn fourier(&mut self, cos: bool, wrt: usize, a: &[Value]) -> Option<Value> {
        let (x, x0, w, coeffs) = (a[0], *a.get(1)?, *a.get(2)?, a.get(3..)?);
        let t = self.sub(x, x0);
        if wrt >= 3 {
            let j = wrt - 3;
            if j == 0 {
                return Some(self.c(1.0));
            }
            let jf = self.c(j as f64);
            let jw = self.mul(jf, w);
            let angle = self.mul(jw, t);
            return Some(self.call(if cos { Func::Cos } else { Func::Sin }, &[angle]));
        }
        if coeffs.len() < 2 {
            return Some(self.c(0.0));
        }
        let (other, sign) = if cos {
            (Func::Forsin, -1.0)
        } else {
            (Func::Forcos, 1.0)
        };
        let factor = if wrt == 2 { t } else { w };
        let mut args = vec![x, x0, w, self.c(0.0)];
        for (j, &c) in coeffs.iter().enumerate().skip(1) {
            let sj = self.c(sign * j as f64);
            let k = self.mul(sj, factor);
            args.push(self.mul(k, c));
        }
        let d = self.call(other, &args);
        Some(if wrt == 1 { self.neg(d) } else { d })
    }
}
