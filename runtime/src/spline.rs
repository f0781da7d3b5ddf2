//! SPLINE data and its interpolation (spec §5.13): AKISPL (Akima) and CUBSPL (natural
//! cubic spline).
//!
//! The host builds a [`Spline`] once from a `SPLINE/id` statement; construction
//! validates the data and precomputes both fits, so evaluation only searches and
//! evaluates a cubic (no allocation, no panic). A spline is either one curve y(x) or a
//! surface: one curve per z value, interpolated cubically in x and linearly in z.
//!
//! Decisions (the spec leaves them open, §5.13 and §9 item 9):
//! * Extrapolation in x: linear, continuing the end knot's value and slope
//!   (y(x) = y_end + y′_end·(x − x_end)); beyond the data the first derivative is that
//!   slope and the second derivative 0. This is Adams' `LINEAR_EXTRAPOLATE` behaviour;
//!   Adams' default is unknown.
//! * Extrapolation in z: the line through the two nearest curves is continued.
//! * CUBSPL end conditions: natural (y″ = 0 at both end knots), so the linear
//!   extrapolation continues it with a continuous second derivative.
//! * Akima end rule: Akima's parabolic extension of the segment slopes (see
//!   `fit::akima_slopes`).
//! * At a knot the segment to the right is active (matters only for the second
//!   derivative, which jumps at Akima knots); at the last knot the extrapolation is
//!   active. In z, at an interior curve the pair above it is active.

mod fit;

use core::fmt;

use fit::CurveFit;

/// Why [`Spline::new`] rejected the data.
#[derive(Debug, Clone, PartialEq)]
pub enum SplineError {
    /// Fewer than 4 x values.
    TooFewPoints {
        /// Number of x values given.
        found: usize,
    },
    /// `xs[index]` is not greater than `xs[index - 1]`.
    XNotIncreasing {
        /// Index of the offending x value.
        index: usize,
    },
    /// No z value (a curve needs one, which is ignored).
    NoCurves,
    /// `zs[index]` is not greater than `zs[index - 1]`.
    ZNotIncreasing {
        /// Index of the offending z value.
        index: usize,
    },
    /// `ys` does not hold one value per (curve, x) pair.
    LengthMismatch {
        /// `xs.len() * zs.len()`.
        expected: usize,
        /// `ys.len()`.
        found: usize,
    },
    /// A data value is NaN or infinite.
    NotFinite,
    /// The data are finite but the fit overflows (e.g. x spacing beyond f64 range).
    Overflow,
}

impl fmt::Display for SplineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewPoints { found } => {
                write!(f, "a spline needs at least 4 x values, found {found}")
            }
            Self::XNotIncreasing { index } => {
                write!(
                    f,
                    "x values must increase strictly (x value {} does not)",
                    index + 1
                )
            }
            Self::NoCurves => write!(f, "a spline needs at least one curve"),
            Self::ZNotIncreasing { index } => {
                write!(
                    f,
                    "z values must increase strictly (z value {} does not)",
                    index + 1
                )
            }
            Self::LengthMismatch { expected, found } => {
                write!(
                    f,
                    "expected {expected} y values (one per x per curve), found {found}"
                )
            }
            Self::NotFinite => write!(f, "spline data must be finite numbers"),
            Self::Overflow => write!(f, "spline data are too far apart to fit in f64"),
        }
    }
}

impl std::error::Error for SplineError {}

/// Validated SPLINE data with its Akima and natural-cubic fits precomputed.
#[derive(Debug, Clone)]
pub struct Spline {
    xs: Vec<f64>,
    zs: Vec<f64>,
    ys: Vec<f64>,
    akima: Fit,
    cubic: Fit,
}

/// The fit of every curve: `segments[c * (n - 1) + i]` is segment i of curve c.
#[derive(Debug, Clone)]
struct Fit {
    segments: Vec<[f64; 4]>,
    end_slopes: Vec<f64>,
}

/// Which precomputed fit to evaluate.
#[derive(Clone, Copy)]
enum Method {
    Akima,
    Cubic,
}

impl Spline {
    /// Builds a spline from knots `xs`, curve values `zs` and data `ys`.
    ///
    /// One curve when `zs` has one element (its value is ignored), otherwise a surface
    /// with one curve per z; `ys` is row-major by curve (`ys[c * xs.len() + i]` is y at
    /// `xs[i]` on curve c). Requires at least 4 strictly increasing x values, strictly
    /// increasing z values, `ys.len() == xs.len() * zs.len()`, and finite data.
    pub fn new(xs: Vec<f64>, zs: Vec<f64>, ys: Vec<f64>) -> Result<Spline, SplineError> {
        let n = xs.len();
        if n < 4 {
            return Err(SplineError::TooFewPoints { found: n });
        }
        if zs.is_empty() {
            return Err(SplineError::NoCurves);
        }
        let expected = n.saturating_mul(zs.len());
        if ys.len() != expected {
            return Err(SplineError::LengthMismatch {
                expected,
                found: ys.len(),
            });
        }
        if !xs.iter().chain(&zs).chain(&ys).all(|v| v.is_finite()) {
            return Err(SplineError::NotFinite);
        }
        if let Some(i) = (1..n).find(|&i| xs[i] <= xs[i - 1]) {
            return Err(SplineError::XNotIncreasing { index: i });
        }
        if zs.len() > 1 {
            if let Some(i) = (1..zs.len()).find(|&i| zs[i] <= zs[i - 1]) {
                return Err(SplineError::ZNotIncreasing { index: i });
            }
        }
        let fit_all = |f: fn(&[f64], &[f64]) -> CurveFit| {
            let mut fit = Fit {
                segments: Vec::new(),
                end_slopes: Vec::new(),
            };
            for curve in ys.chunks_exact(n) {
                let CurveFit {
                    segments,
                    end_slope,
                } = f(&xs, curve);
                fit.segments.extend(segments);
                fit.end_slopes.push(end_slope);
            }
            fit
        };
        let akima = fit_all(fit::akima);
        let cubic = fit_all(fit::natural_cubic);
        let finite = |fit: &Fit| {
            fit.segments
                .iter()
                .flatten()
                .chain(&fit.end_slopes)
                .all(|v| v.is_finite())
        };
        let gaps_finite = xs.windows(2).all(|w| (w[1] - w[0]).is_finite());
        if !gaps_finite || !finite(&akima) || !finite(&cubic) {
            return Err(SplineError::Overflow);
        }
        Ok(Spline {
            xs,
            zs,
            ys,
            akima,
            cubic,
        })
    }

    /// The x knots.
    pub fn xs(&self) -> &[f64] {
        &self.xs
    }

    /// The z value of each curve (one element for a plain curve).
    pub fn zs(&self) -> &[f64] {
        &self.zs
    }

    /// True when the spline has more than one curve (z is then interpolated).
    pub fn is_surface(&self) -> bool {
        self.zs.len() > 1
    }

    fn fit(&self, method: Method) -> &Fit {
        match method {
            Method::Akima => &self.akima,
            Method::Cubic => &self.cubic,
        }
    }

    /// Value and first two x-derivatives of curve `c` at x (x not NaN).
    ///
    /// Inside segment i, h = x − x_i: value `y + h * (b + h * (c + h * d))`, first
    /// derivative `b + h * (2.0 * c + 3.0 * d * h)`, second `2.0 * c + 6.0 * d * h`.
    /// Outside, `y_end + s * (x - x_end)`, s, 0.
    fn curve(&self, method: Method, c: usize, x: f64) -> [f64; 3] {
        let fit = self.fit(method);
        let n = self.xs.len();
        let (Some(segs), Some(&end_slope), Some(ys)) = (
            fit.segments.get(c * (n - 1)..(c + 1) * (n - 1)),
            fit.end_slopes.get(c),
            self.ys.get(c * n..(c + 1) * n),
        ) else {
            return [f64::NAN; 3];
        };
        let (Some(&x_first), Some(&x_last), Some(&y_last)) =
            (self.xs.first(), self.xs.last(), ys.last())
        else {
            return [f64::NAN; 3];
        };
        if x < x_first {
            let Some(&[y, b, _, _]) = segs.first() else {
                return [f64::NAN; 3];
            };
            return [y + b * (x - x_first), b, 0.0];
        }
        if x >= x_last {
            return [y_last + end_slope * (x - x_last), end_slope, 0.0];
        }
        let i = self.xs.partition_point(|&k| k <= x).saturating_sub(1);
        let (Some(&[y, b, c2, d]), Some(&xi)) = (segs.get(i), self.xs.get(i)) else {
            return [f64::NAN; 3];
        };
        let h = x - xi;
        [
            y + h * (b + h * (c2 + h * d)),
            b + h * (2.0 * c2 + 3.0 * d * h),
            2.0 * c2 + 6.0 * d * h,
        ]
    }

    /// Curve pair and weight for z: (j, w) with value (1 − w)·v_j + w·v_{j+1}; (0, 0) for
    /// a plain curve.
    fn z_cell(&self, z: f64) -> (usize, f64) {
        let m = self.zs.len();
        if m < 2 {
            return (0, 0.0);
        }
        let j = self
            .zs
            .partition_point(|&k| k <= z)
            .saturating_sub(1)
            .min(m - 2);
        match (self.zs.get(j), self.zs.get(j + 1)) {
            (Some(&z0), Some(&z1)) => (j, (z - z0) / (z1 - z0)),
            _ => (0, f64::NAN),
        }
    }

    /// Shared evaluation: derivative order `iord` in x, NaN rules of [`akispl`].
    fn eval(&self, method: Method, x: f64, z: f64, iord: i32) -> f64 {
        let k = match iord {
            0 => 0,
            1 => 1,
            2 => 2,
            _ => return f64::NAN,
        };
        if x.is_nan() || z.is_nan() || (k != 0 && self.is_surface()) {
            return f64::NAN;
        }
        let (j, w) = self.z_cell(z);
        let v0 = self.curve(method, j, x)[k];
        if !self.is_surface() {
            return v0;
        }
        let v1 = self.curve(method, j + 1, x)[k];
        (1.0 - w) * v0 + w * v1
    }

    /// Shared gradient: (value, ∂/∂x, ∂/∂z).
    fn eval_grad(&self, method: Method, x: f64, z: f64) -> (f64, f64, f64) {
        if x.is_nan() || z.is_nan() {
            return (f64::NAN, f64::NAN, f64::NAN);
        }
        let (j, w) = self.z_cell(z);
        let [v0, d0, _] = self.curve(method, j, x);
        if !self.is_surface() {
            return (v0, d0, 0.0);
        }
        let [v1, d1, _] = self.curve(method, j + 1, x);
        let (Some(&z0), Some(&z1)) = (self.zs.get(j), self.zs.get(j + 1)) else {
            return (f64::NAN, f64::NAN, f64::NAN);
        };
        (
            (1.0 - w) * v0 + w * v1,
            (1.0 - w) * d0 + w * d1,
            (v1 - v0) / (z1 - z0),
        )
    }
}

/// `AKISPL(x, z, id, iord)`: Akima interpolation of `spline` at x (and z on a surface).
///
/// `iord` = 0, 1, 2 gives the value or the first or second derivative in x; other values
/// give NaN, and so does `iord ≠ 0` on a surface (spec F25). On a plain curve z is
/// ignored (but a NaN z still gives NaN). On a surface, with the curves j, j + 1
/// bracketing z and w = (z − z_j)/(z_{j+1} − z_j), the value is
/// `(1.0 - w) * v_j + w * v_{j+1}` (exact at both curves). Extrapolation and knot
/// conventions: see the module documentation.
#[doc(alias = "AKISPL")]
pub fn akispl(x: f64, z: f64, spline: &Spline, iord: i32) -> f64 {
    spline.eval(Method::Akima, x, z, iord)
}

/// [`akispl`] with its partials: (value, ∂/∂x, ∂/∂z). ∂/∂z is 0 on a plain curve and
/// (v_{j+1} − v_j)/(z_{j+1} − z_j) on a surface (at an interior curve, the pair above it).
pub fn akispl_grad(x: f64, z: f64, spline: &Spline) -> (f64, f64, f64) {
    spline.eval_grad(Method::Akima, x, z)
}

/// `CUBSPL(x, z, id, iord)`: natural cubic spline interpolation of `spline`; arguments,
/// NaN rules and z interpolation as [`akispl`].
#[doc(alias = "CUBSPL")]
pub fn cubspl(x: f64, z: f64, spline: &Spline, iord: i32) -> f64 {
    spline.eval(Method::Cubic, x, z, iord)
}

/// [`cubspl`] with its partials: (value, ∂/∂x, ∂/∂z), as [`akispl_grad`].
pub fn cubspl_grad(x: f64, z: f64, spline: &Spline) -> (f64, f64, f64) {
    spline.eval_grad(Method::Cubic, x, z)
}

#[cfg(test)]
mod tests;
