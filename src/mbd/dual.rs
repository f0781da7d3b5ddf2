//! Forward-mode dual numbers for the marker measures: a value with its exact partial
//! derivatives along a fixed set of local directions. A measure touches at most four
//! parts (markers i, j, k, l); each contributes 12 directions: the position-level
//! increment (δr, δθ, global axes) and the velocity (v, ω, global axes). The measures
//! module builds marker frames as duals and reads every derivative off the result, so
//! PSI, YAW or VR need no separate hand-derived Jacobian; the primitive constraint
//! equations, which are simple, are differentiated by hand in `primitives`.

use crate::vocab::math::Vec3;
use std::ops::{Add, Mul, Neg, Sub};

/// Parts a measure can touch.
pub const PARTS: usize = 4;
/// Directions per part: δr, δθ, v, ω.
pub const PER_PART: usize = 12;
/// All local directions.
pub const N: usize = PARTS * PER_PART;

/// A value and its derivatives along the `N` local directions.
#[derive(Clone, Copy, Debug)]
pub struct D {
    pub v: f64,
    pub g: [f64; N],
}

impl D {
    pub fn c(v: f64) -> D {
        D { v, g: [0.0; N] }
    }

    fn map(self, v: f64, dv: f64) -> D {
        let mut g = self.g;
        for x in &mut g {
            *x *= dv;
        }
        D { v, g }
    }

    pub fn sqrt(self) -> D {
        let s = self.v.sqrt();
        self.map(s, 0.5 / s)
    }

    pub fn asin(self) -> D {
        self.map(self.v.asin(), 1.0 / (1.0 - self.v * self.v).sqrt())
    }

    pub fn acos(self) -> D {
        self.map(self.v.acos(), -1.0 / (1.0 - self.v * self.v).sqrt())
    }

    /// atan2(self, x): d = (x dy − y dx)/(x² + y²).
    pub fn atan2(self, x: D) -> D {
        let r2 = self.v * self.v + x.v * x.v;
        let (a, b) = (x.v / r2, -self.v / r2);
        let mut g = [0.0; N];
        for (k, gk) in g.iter_mut().enumerate() {
            *gk = a * self.g[k] + b * x.g[k];
        }
        D {
            v: self.v.atan2(x.v),
            g,
        }
    }

    pub fn scale(self, s: f64) -> D {
        self.map(self.v * s, s)
    }
}

impl Add for D {
    type Output = D;
    fn add(mut self, o: D) -> D {
        self.v += o.v;
        for (a, b) in self.g.iter_mut().zip(o.g.iter()) {
            *a += b;
        }
        self
    }
}

impl Sub for D {
    type Output = D;
    fn sub(mut self, o: D) -> D {
        self.v -= o.v;
        for (a, b) in self.g.iter_mut().zip(o.g.iter()) {
            *a -= b;
        }
        self
    }
}

impl Neg for D {
    type Output = D;
    fn neg(self) -> D {
        self.scale(-1.0)
    }
}

impl Mul for D {
    type Output = D;
    fn mul(self, o: D) -> D {
        let mut g = [0.0; N];
        for (k, gk) in g.iter_mut().enumerate() {
            *gk = self.v * o.g[k] + o.v * self.g[k];
        }
        D { v: self.v * o.v, g }
    }
}

/// What the measure formulas need of a number: duals ([`D`], first derivatives along
/// every local direction) and jets ([`J2`], first and second time derivatives along the
/// motion) both evaluate them.
pub trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    fn c(v: f64) -> Self;
    fn val(&self) -> f64;
    fn sqrt(self) -> Self;
    fn asin(self) -> Self;
    fn acos(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn recip(self) -> Self;
}

impl Scalar for D {
    fn c(v: f64) -> D {
        D::c(v)
    }
    fn val(&self) -> f64 {
        self.v
    }
    fn sqrt(self) -> D {
        D::sqrt(self)
    }
    fn asin(self) -> D {
        D::asin(self)
    }
    fn acos(self) -> D {
        D::acos(self)
    }
    fn atan2(self, x: D) -> D {
        D::atan2(self, x)
    }
    fn recip(self) -> D {
        self.map(1.0 / self.v, -1.0 / (self.v * self.v))
    }
}

/// Plain values: the measure formulas without derivatives, bit for bit the values of
/// the jets and duals (the same operations on the same numbers).
impl Scalar for f64 {
    fn c(v: f64) -> f64 {
        v
    }
    fn val(&self) -> f64 {
        *self
    }
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    fn asin(self) -> f64 {
        f64::asin(self)
    }
    fn acos(self) -> f64 {
        f64::acos(self)
    }
    fn atan2(self, x: f64) -> f64 {
        f64::atan2(self, x)
    }
    fn recip(self) -> f64 {
        1.0 / self
    }
}

/// A value with its first and second derivatives along one path: v, v̇, v̈.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct J2 {
    pub v: f64,
    pub d: f64,
    pub dd: f64,
}

impl J2 {
    /// f(self) from f, f′ and f″ at the value: (f∘x)″ = f″·ẋ² + f′·ẍ.
    fn chain(self, f: f64, f1: f64, f2: f64) -> J2 {
        J2 {
            v: f,
            d: f1 * self.d,
            dd: f2 * self.d * self.d + f1 * self.dd,
        }
    }
}

impl Add for J2 {
    type Output = J2;
    fn add(self, o: J2) -> J2 {
        J2 {
            v: self.v + o.v,
            d: self.d + o.d,
            dd: self.dd + o.dd,
        }
    }
}

impl Sub for J2 {
    type Output = J2;
    fn sub(self, o: J2) -> J2 {
        J2 {
            v: self.v - o.v,
            d: self.d - o.d,
            dd: self.dd - o.dd,
        }
    }
}

impl Neg for J2 {
    type Output = J2;
    fn neg(self) -> J2 {
        J2 {
            v: -self.v,
            d: -self.d,
            dd: -self.dd,
        }
    }
}

impl Mul for J2 {
    type Output = J2;
    fn mul(self, o: J2) -> J2 {
        J2 {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
            dd: self.dd * o.v + 2.0 * self.d * o.d + self.v * o.dd,
        }
    }
}

impl Scalar for J2 {
    fn c(v: f64) -> J2 {
        J2 { v, d: 0.0, dd: 0.0 }
    }
    fn val(&self) -> f64 {
        self.v
    }
    fn sqrt(self) -> J2 {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    fn asin(self) -> J2 {
        let q = 1.0 - self.v * self.v;
        self.chain(self.v.asin(), 1.0 / q.sqrt(), self.v / (q * q.sqrt()))
    }
    fn acos(self) -> J2 {
        let q = 1.0 - self.v * self.v;
        self.chain(self.v.acos(), -1.0 / q.sqrt(), -self.v / (q * q.sqrt()))
    }
    fn atan2(self, x: J2) -> J2 {
        // θ = atan2(y, x): θ̇ = (x·ẏ − y·ẋ)/r², θ̈ = ((x·ÿ − y·ẍ)·r² − (x·ẏ − y·ẋ)·(r²)˙)/r⁴.
        let (y, r2) = (self, self.v * self.v + x.v * x.v);
        let num = x.v * y.d - y.v * x.d;
        let num_d = x.v * y.dd - y.v * x.dd;
        let r2_d = 2.0 * (x.v * x.d + y.v * y.d);
        J2 {
            v: y.v.atan2(x.v),
            d: num / r2,
            dd: (num_d * r2 - num * r2_d) / (r2 * r2),
        }
    }
    fn recip(self) -> J2 {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }
}

/// A 3-vector of duals (or jets).
#[derive(Clone, Copy, Debug)]
pub struct V<T = D>(pub [T; 3]);

impl<T: Scalar> V<T> {
    pub fn c(x: Vec3) -> V<T> {
        V([T::c(x.x), T::c(x.y), T::c(x.z)])
    }

    pub fn value(&self) -> Vec3 {
        Vec3::new(self.0[0].val(), self.0[1].val(), self.0[2].val())
    }

    pub fn dot(&self, o: &V<T>) -> T {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }

    pub fn cross(&self, o: &V<T>) -> V<T> {
        let (a, b) = (&self.0, &o.0);
        V([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }

    pub fn sub(&self, o: &V<T>) -> V<T> {
        V([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }

    pub fn norm(&self) -> T {
        self.dot(self).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var(v: f64, k: usize) -> D {
        let mut d = D::c(v);
        d.g[k] = 1.0;
        d
    }

    #[test]
    fn jet_rules_match_calculus() {
        // x(t) = 0.3 + 0.5t + 0.1t², y(t) = −0.7 + 0.2t − 0.4t² at t = 0.
        let x = J2 {
            v: 0.3,
            d: 0.5,
            dd: 0.2,
        };
        let y = J2 {
            v: -0.7,
            d: 0.2,
            dd: -0.8,
        };
        // d²/dt² of x·y = ẍy + 2ẋẏ + xÿ.
        let p = x * y;
        assert!((p.dd - (0.2 * -0.7 + 2.0 * 0.5 * 0.2 + 0.3 * -0.8)).abs() < 1e-15);
        // atan2 along a circle of radius 2 at unit angular rate: θ̇ = 1, θ̈ = 0.
        let (c, s) = (0.4f64.cos(), 0.4f64.sin());
        let cx = J2 {
            v: 2.0 * c,
            d: -2.0 * s,
            dd: -2.0 * c,
        };
        let cy = J2 {
            v: 2.0 * s,
            d: 2.0 * c,
            dd: -2.0 * s,
        };
        let th = cy.atan2(cx);
        assert!((th.v - 0.4).abs() < 1e-15 && (th.d - 1.0).abs() < 1e-15 && th.dd.abs() < 1e-15);
        // √(t² + 1) at t = 1: d = t/√(t²+1), dd = 1/(t²+1)^{3/2}.
        let u = J2 {
            v: 2.0,
            d: 2.0,
            dd: 2.0,
        }
        .sqrt();
        assert!((u.d - 1.0 / 2f64.sqrt()).abs() < 1e-15);
        assert!((u.dd - 1.0 / 2f64.powf(1.5)).abs() < 1e-15);
        // acos(cos t) = t: first derivative 1 and second 0 away from 0 and π.
        let t = 0.9f64;
        let cj = J2 {
            v: t.cos(),
            d: -t.sin(),
            dd: -t.cos(),
        }
        .acos();
        assert!((cj.d - 1.0).abs() < 1e-14 && cj.dd.abs() < 1e-14);
        let sj = J2 {
            v: t.sin(),
            d: t.cos(),
            dd: -t.sin(),
        }
        .asin();
        assert!((sj.d - 1.0).abs() < 1e-14 && sj.dd.abs() < 1e-14);
        let r = J2 {
            v: 2.0,
            d: 1.0,
            dd: 0.0,
        }
        .recip();
        assert!((r.d + 0.25).abs() < 1e-15 && (r.dd - 0.25).abs() < 1e-15);
    }

    #[test]
    fn dual_rules_match_calculus() {
        let (x, y) = (var(0.3, 0), var(-0.7, 1));
        let a = y.atan2(x);
        // ∂atan2(y,x)/∂x = −y/(x²+y²), ∂/∂y = x/(x²+y²).
        let r2 = 0.3f64 * 0.3 + 0.7 * 0.7;
        assert!((a.g[0] - 0.7 / r2).abs() < 1e-15);
        assert!((a.g[1] - 0.3 / r2).abs() < 1e-15);
        let s = (x * x + y * y).sqrt();
        assert!((s.g[0] - 0.3 / r2.sqrt()).abs() < 1e-15);
        let c = x.acos();
        assert!((c.g[0] + 1.0 / (1.0 - 0.09f64).sqrt()).abs() < 1e-15);
    }
}
