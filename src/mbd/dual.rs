//! Forward-mode dual numbers for the marker measures: a value with its exact partial
//! derivatives along a fixed set of local directions. A measure touches at most four
//! parts (markers i, j, k, l); each contributes 12 directions: the position-level
//! increment (δr, δθ, global axes) and the velocity (v, ω, global axes). The measures
//! module builds marker frames as duals and reads every derivative off the result, so
//! PSI, YAW or VR need no separate hand-derived Jacobian; the primitive constraint
//! equations, which are simple, are differentiated by hand in `primitives`.

use super::math::Vec3;
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

/// A 3-vector of duals.
#[derive(Clone, Copy, Debug)]
pub struct V(pub [D; 3]);

impl V {
    pub fn c(x: Vec3) -> V {
        V([D::c(x.x), D::c(x.y), D::c(x.z)])
    }

    pub fn value(&self) -> Vec3 {
        Vec3::new(self.0[0].v, self.0[1].v, self.0[2].v)
    }

    pub fn dot(&self, o: &V) -> D {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }

    pub fn cross(&self, o: &V) -> V {
        let (a, b) = (&self.0, &o.0);
        V([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }

    pub fn sub(&self, o: &V) -> V {
        V([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }

    pub fn norm(&self) -> D {
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
