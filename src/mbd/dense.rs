//! Small dense factorizations in place on buffers allocated once: the LU with partial
//! pivoting and the Cholesky LLᵀ that [`super::sparse`] uses for matrices up to
//! [`super::sparse::DENSE_MAX`]. At these orders (a pendulum's Newton matrix is 5 × 5)
//! an allocation per factorization or solve costs as much as the arithmetic, so nothing
//! here allocates after construction.

/// Why a factorization (dense or sparse) failed.
#[derive(Clone, Debug, PartialEq)]
pub enum FactorError {
    /// No pivot could be found (structurally singular), or the factors are not finite.
    Singular,
    /// A value of the matrix is NaN or infinite.
    NotFinite,
}

/// LU = P·A with partial pivoting, column-major, factored in place.
#[derive(Clone, Debug)]
pub struct DenseLu {
    n: usize,
    /// A before [`DenseLu::factor`]; L (unit diagonal, below) and U (on and above) after.
    a: Vec<f64>,
    /// Row exchanged with row k at step k.
    piv: Vec<usize>,
}

impl DenseLu {
    /// Buffers for an `n` × `n` matrix.
    pub fn new(n: usize) -> DenseLu {
        DenseLu {
            n,
            a: vec![0.0; n * n],
            piv: vec![0; n],
        }
    }

    /// The matrix to factor, column-major (entry (r, c) at `c·n + r`), to be filled.
    pub fn matrix_mut(&mut self) -> &mut [f64] {
        &mut self.a
    }

    /// Factors the matrix in place; singular when a column has no non-zero pivot left.
    pub fn factor(&mut self) -> Result<(), FactorError> {
        let n = self.n;
        for k in 0..n {
            let (mut p, mut big) = (k, 0.0f64);
            for (i, x) in self.a[k * n..(k + 1) * n].iter().enumerate().skip(k) {
                if x.abs() > big {
                    (p, big) = (i, x.abs());
                }
            }
            if big == 0.0 || !big.is_finite() {
                return Err(FactorError::Singular);
            }
            self.piv[k] = p;
            if p != k {
                for col in self.a.chunks_exact_mut(n) {
                    col.swap(k, p);
                }
            }
            let (left, right) = self.a.split_at_mut((k + 1) * n);
            let pivot_col = &mut left[k * n..];
            let inv = 1.0 / pivot_col[k];
            let below = &mut pivot_col[k + 1..];
            for x in below.iter_mut() {
                *x *= inv;
            }
            let below = &*below;
            for col in right.chunks_exact_mut(n) {
                let akj = col[k];
                if akj != 0.0 {
                    for (x, l) in col[k + 1..].iter_mut().zip(below) {
                        *x -= l * akj;
                    }
                }
            }
        }
        Ok(())
    }

    /// The smallest pivot over the largest, in magnitude: how near singular the factored
    /// matrix is (about 1/condition for a well-scaled one).
    pub fn pivot_ratio(&self) -> f64 {
        let n = self.n;
        let (lo, hi) = (0..n)
            .map(|k| self.a[k * n + k].abs())
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
        if hi > 0.0 {
            lo / hi
        } else {
            0.0
        }
    }

    /// Solves A·x = b in place with the factors.
    pub fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        if n == 0 {
            // Nothing to solve (a system without constraint rows).
            return;
        }
        for (k, &p) in self.piv.iter().enumerate() {
            b.swap(k, p);
        }
        for (k, col) in self.a.chunks_exact(n).enumerate() {
            let bk = b[k];
            if bk != 0.0 {
                for (x, l) in b[k + 1..].iter_mut().zip(&col[k + 1..]) {
                    *x -= l * bk;
                }
            }
        }
        for (k, col) in self.a.chunks_exact(n).enumerate().rev() {
            b[k] /= col[k];
            let bk = b[k];
            for (x, u) in b[..k].iter_mut().zip(&col[..k]) {
                *x -= u * bk;
            }
        }
    }
}

/// Cholesky A = L·Lᵀ of a symmetric positive definite matrix, column-major, in place
/// (only the lower triangle is read and written).
#[derive(Clone, Debug)]
pub struct DenseLlt {
    n: usize,
    a: Vec<f64>,
}

impl DenseLlt {
    /// Buffers for an `n` × `n` matrix.
    pub fn new(n: usize) -> DenseLlt {
        DenseLlt {
            n,
            a: vec![0.0; n * n],
        }
    }

    /// The matrix to factor, column-major; its lower triangle is what is read.
    pub fn matrix_mut(&mut self) -> &mut [f64] {
        &mut self.a
    }

    /// Factors in place; an error when the matrix is not numerically positive definite.
    pub fn factor(&mut self) -> Result<(), FactorError> {
        let n = self.n;
        let a = &mut self.a;
        for j in 0..n {
            let mut d = a[j * n + j];
            for k in 0..j {
                d -= a[k * n + j] * a[k * n + j];
            }
            if d.is_nan() || d <= 0.0 {
                return Err(FactorError::Singular);
            }
            let ljj = d.sqrt();
            a[j * n + j] = ljj;
            for i in j + 1..n {
                let mut s = a[j * n + i];
                for k in 0..j {
                    s -= a[k * n + i] * a[k * n + j];
                }
                a[j * n + i] = s / ljj;
            }
        }
        Ok(())
    }

    /// Solves A·x = b in place with the factors.
    pub fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        let a = &self.a;
        for k in 0..n {
            b[k] /= a[k * n + k];
            let bk = b[k];
            for i in k + 1..n {
                b[i] -= a[k * n + i] * bk;
            }
        }
        for k in (0..n).rev() {
            let mut s = b[k];
            for i in k + 1..n {
                s -= a[k * n + i] * b[i];
            }
            b[k] = s / a[k * n + k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn residual(a: &[f64], n: usize, x: &[f64], b: &[f64]) -> f64 {
        (0..n)
            .map(|r| ((0..n).map(|c| a[c * n + r] * x[c]).sum::<f64>() - b[r]).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn lu_solves_a_system_that_needs_pivoting() {
        // A saddle point matrix: its (1, 1) block starts with zeros on the diagonal.
        let n = 4;
        #[rustfmt::skip]
        let a = [
            0.0, 1.0, 0.0, 2.0,
            1.0, 0.0, 3.0, 0.0,
            0.0, 3.0, 4.0, 1.0,
            2.0, 0.0, 1.0, 0.0,
        ];
        let mut lu = DenseLu::new(n);
        lu.matrix_mut().copy_from_slice(&a);
        lu.factor().unwrap();
        let b = [1.0, -2.0, 0.5, 3.0];
        let mut x = b;
        lu.solve(&mut x);
        assert!(residual(&a, n, &x, &b) < 1e-14, "{x:?}");
        assert!(lu.pivot_ratio() > 0.0);
    }

    #[test]
    fn lu_refuses_a_singular_matrix_and_non_finite_pivots() {
        let mut lu = DenseLu::new(2);
        lu.matrix_mut().copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
        assert_eq!(lu.factor(), Err(FactorError::Singular));
        lu.matrix_mut().copy_from_slice(&[f64::NAN, 0.0, 0.0, 1.0]);
        assert_eq!(lu.factor(), Err(FactorError::Singular));
    }

    #[test]
    fn cholesky_solves_and_refuses_an_indefinite_matrix() {
        let n = 3;
        #[rustfmt::skip]
        let a = [
            4.0, 1.0, 0.5,
            1.0, 3.0, 0.2,
            0.5, 0.2, 2.0,
        ];
        let mut llt = DenseLlt::new(n);
        llt.matrix_mut().copy_from_slice(&a);
        llt.factor().unwrap();
        let b = [1.0, 2.0, 3.0];
        let mut x = b;
        llt.solve(&mut x);
        assert!(residual(&a, n, &x, &b) < 1e-14, "{x:?}");
        llt.matrix_mut()
            .copy_from_slice(&[1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        assert_eq!(llt.factor(), Err(FactorError::Singular));
    }
}
