//! Construction-time fitting of one curve: Akima knot slopes and natural cubic spline
//! coefficients, turned into per-segment cubic coefficients. Runs once in
//! [`Spline::new`](super::Spline::new); this is the only code of the crate that
//! allocates.

/// One curve's fit: per segment i the coefficients [y_i, b_i, c_i, d_i] of
/// y(x) = y_i + b·h + c·h² + d·h³ with h = x − x_i, and the slope at the last knot.
pub(super) struct CurveFit {
    pub segments: Vec<[f64; 4]>,
    pub end_slope: f64,
}

/// Akima (1970) knot slopes.
///
/// With segment slopes m_i = (y_{i+1} − y_i)/(x_{i+1} − x_i), i = 0 … n−2, extended past
/// the ends by Akima's parabolic rule m_{−1} = 2m_0 − m_1, m_{−2} = 2m_{−1} − m_0,
/// m_{n−1} = 2m_{n−2} − m_{n−3}, m_n = 2m_{n−1} − m_{n−2} (decision: the spec does not say
/// which end rule Adams uses), the slope at knot i is
/// t_i = (|m_{i+1} − m_i|·m_{i−1} + |m_{i−1} − m_{i−2}|·m_i) / (|m_{i+1} − m_i| + |m_{i−1} − m_{i−2}|),
/// and (m_{i−1} + m_i)/2 when both weights are 0.
fn akima_slopes(xs: &[f64], ys: &[f64]) -> Vec<f64> {
    let n = xs.len();
    // ext[k] = m_{k-2}, k = 0 ..= n + 2.
    let mut ext = vec![0.0; n + 3];
    for i in 0..n - 1 {
        ext[i + 2] = (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]);
    }
    ext[1] = 2.0 * ext[2] - ext[3];
    ext[0] = 2.0 * ext[1] - ext[2];
    ext[n + 1] = 2.0 * ext[n] - ext[n - 1];
    ext[n + 2] = 2.0 * ext[n + 1] - ext[n];
    (0..n)
        .map(|i| {
            let (m2, m1, m0, p1) = (ext[i], ext[i + 1], ext[i + 2], ext[i + 3]);
            let w1 = (p1 - m0).abs();
            let w2 = (m1 - m2).abs();
            if w1 + w2 > 0.0 {
                (w1 * m1 + w2 * m0) / (w1 + w2)
            } else {
                (m1 + m0) / 2.0
            }
        })
        .collect()
}

/// Akima fit: Hermite cubics through the data with the [`akima_slopes`]:
/// b = t_i, c = (3δ − 2t_i − t_{i+1})/h, d = (t_i + t_{i+1} − 2δ)/h², δ = segment slope.
pub(super) fn akima(xs: &[f64], ys: &[f64]) -> CurveFit {
    let t = akima_slopes(xs, ys);
    let segments = (0..xs.len() - 1)
        .map(|i| {
            let h = xs[i + 1] - xs[i];
            let delta = (ys[i + 1] - ys[i]) / h;
            [
                ys[i],
                t[i],
                (3.0 * delta - 2.0 * t[i] - t[i + 1]) / h,
                (t[i] + t[i + 1] - 2.0 * delta) / (h * h),
            ]
        })
        .collect();
    CurveFit {
        segments,
        end_slope: t[xs.len() - 1],
    }
}

/// Natural cubic spline (decision: end conditions y″ = 0 at both ends; Adams' are
/// unknown). Solves the tridiagonal system for the knot second derivatives M_i,
/// h_{i−1}·M_{i−1} + 2(h_{i−1} + h_i)·M_i + h_i·M_{i+1} = 6(δ_i − δ_{i−1}), M_0 = M_{n−1} = 0,
/// by the Thomas algorithm (diagonally dominant, no pivoting needed), then
/// b = δ_i − h_i(2M_i + M_{i+1})/6, c = M_i/2, d = (M_{i+1} − M_i)/(6h_i); the last knot's
/// slope is δ_{n−2} + h_{n−2}(M_{n−2} + 2M_{n−1})/6.
pub(super) fn natural_cubic(xs: &[f64], ys: &[f64]) -> CurveFit {
    let n = xs.len();
    let h: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
    let delta: Vec<f64> = (0..n - 1).map(|i| (ys[i + 1] - ys[i]) / h[i]).collect();
    // Forward sweep over the interior unknowns M_1 … M_{n-2}.
    let mut diag = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    for i in 1..n - 1 {
        diag[i] = 2.0 * (h[i - 1] + h[i]);
        rhs[i] = 6.0 * (delta[i] - delta[i - 1]);
        if i > 1 {
            let w = h[i - 1] / diag[i - 1];
            diag[i] -= w * h[i - 1];
            rhs[i] -= w * rhs[i - 1];
        }
    }
    // Back substitution; m[0] = m[n-1] = 0.
    let mut m = vec![0.0; n];
    for i in (1..n - 1).rev() {
        m[i] = (rhs[i] - h[i] * m[i + 1]) / diag[i];
    }
    let segments = (0..n - 1)
        .map(|i| {
            [
                ys[i],
                delta[i] - h[i] * (2.0 * m[i] + m[i + 1]) / 6.0,
                m[i] / 2.0,
                (m[i + 1] - m[i]) / (6.0 * h[i]),
            ]
        })
        .collect();
    let end_slope = delta[n - 2] + h[n - 2] * (m[n - 2] + 2.0 * m[n - 1]) / 6.0;
    CurveFit {
        segments,
        end_slope,
    }
}
