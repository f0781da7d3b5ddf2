//! A sparse matrix as it is assembled: (row, column, value) triplets. Constraint
//! Jacobians are built this way (each element touches at most two parts), and the
//! redundancy analysis and solvers read them.

// `FactorError` sits with the dense factorizations (below this file); its old path stays.
pub use super::dense::FactorError;
use super::dense::{DenseLlt, DenseLu};

/// A matrix of `nrows` × `ncols` whose non-zeros are `entries`; repeated (row, column)
/// pairs add up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Triplets {
    /// Row count.
    pub nrows: usize,
    /// Column count.
    pub ncols: usize,
    /// (row, column, value) non-zeros, in push order.
    pub entries: Vec<(u32, u32, f64)>,
}

impl Triplets {
    /// An empty `nrows` × `ncols` matrix.
    pub fn new(nrows: usize, ncols: usize) -> Self {
        Triplets {
            nrows,
            ncols,
            entries: Vec::new(),
        }
    }

    /// Adds `value` at (`row`, `col`); exact zeros are not stored.
    pub fn push(&mut self, row: usize, col: usize, value: f64) {
        debug_assert!(row < self.nrows && col < self.ncols);
        if value != 0.0 {
            self.entries.push((row as u32, col as u32, value));
        }
    }
}

/// A fixed sparsity pattern in compressed-column form, built once from every position a
/// matrix may ever hold (structural zeros included), with O(log) lookup of a position's
/// slot in the value array. Integrators fill the Newton matrix on it at every refactor.
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    /// Order of the square matrix.
    pub n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Pattern {
    /// Writes the matrix holding `values` (one per slot) into the column-major `out`
    /// (zeroed first); `lower`: only the lower triangle's slots are read.
    fn scatter(&self, values: &[f64], lower: bool, out: &mut [f64]) {
        out.fill(0.0);
        let n = self.n;
        for c in 0..n {
            let span = self.col_ptr[c]..self.col_ptr[c + 1];
            for (&r, &v) in self.row_idx[span.clone()].iter().zip(&values[span]) {
                if !lower || r >= c {
                    out[c * n + r] += v;
                }
            }
        }
    }

    /// The n × n pattern holding `positions` (any order, repeats allowed).
    pub fn new(n: usize, mut positions: Vec<(usize, usize)>) -> Pattern {
        positions.sort_unstable_by_key(|&(r, c)| (c, r));
        positions.dedup();
        let mut col_ptr = vec![0; n + 1];
        for &(_, c) in &positions {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        Pattern {
            n,
            col_ptr,
            row_idx: positions.into_iter().map(|(r, _)| r).collect(),
        }
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// The value slot of (row, col), if the pattern holds it.
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[a..b].binary_search(&row).ok().map(|k| a + k)
    }
}

/// Sparse LU with partial pivoting (faer): the symbolic analysis (fill-reducing column
/// order) is done once per [`Pattern`]; each [`SparseLu::factor`] is numeric only, and
/// solves reuse their scratch memory.
pub struct SparseLu {
    pattern: Pattern,
    /// `pattern` as faer reads it, checked once (a check per factorization cost as
    /// much as a tenth of it).
    sym: faer::sparse::SymbolicSparseColMat<usize>,
    symbolic: faer::sparse::linalg::lu::SymbolicLu<usize>,
    numeric: faer::sparse::linalg::lu::NumericLu<usize, f64>,
    factor_scratch: faer::dyn_stack::MemBuffer,
    solve_scratch: faer::dyn_stack::MemBuffer,
    factored: bool,
    /// Matrices up to [`DENSE_MAX`] are factored dense ([`DenseLu`]): below that size
    /// the sparse machinery costs more than the arithmetic (a pendulum's 5 × 5 Newton
    /// matrix took 4 µs in faer's numeric LU, most of a step).
    dense: Option<DenseLu>,
}

/// The largest order [`SparseLu`] factors dense.
pub const DENSE_MAX: usize = 24;

impl SparseLu {
    /// The symbolic analysis of `pattern`.
    pub fn new(pattern: Pattern) -> Result<SparseLu, FactorError> {
        use faer::sparse::linalg::lu;
        let sym = Self::owned_symbolic(&pattern);
        let symbolic = lu::factorize_symbolic_lu(sym.as_ref(), Default::default())
            .map_err(|_| FactorError::Singular)?;
        let par = faer::Par::Seq;
        let factor_scratch = faer::dyn_stack::MemBuffer::new(
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
        );
        let solve_scratch =
            faer::dyn_stack::MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(SparseLu {
            sym,
            symbolic,
            numeric: lu::NumericLu::new(),
            factor_scratch,
            solve_scratch,
            factored: false,
            dense: (pattern.n <= DENSE_MAX).then(|| DenseLu::new(pattern.n)),
            pattern,
        })
    }

    fn owned_symbolic(p: &Pattern) -> faer::sparse::SymbolicSparseColMat<usize> {
        let (col_ptr, row_idx) = (p.col_ptr.clone(), p.row_idx.clone());
        faer::sparse::SymbolicSparseColMat::new_checked(p.n, p.n, col_ptr, None, row_idx)
    }

    /// The smallest pivot of the last dense factorization over its largest (about the
    /// inverse of its condition); `None` for a matrix factored sparse.
    pub fn pivot_ratio(&self) -> Option<f64> {
        self.dense.as_ref().map(DenseLu::pivot_ratio)
    }

    /// The sparsity pattern the symbolic analysis was done on.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Back to the state [`SparseLu::new`] leaves, keeping its symbolic analysis and
    /// scratch memory: no factors, a zeroed dense matrix.
    pub fn forget(&mut self) {
        self.factored = false;
        self.numeric = faer::sparse::linalg::lu::NumericLu::new();
        if let Some(d) = &mut self.dense {
            *d = DenseLu::new(self.pattern.n);
        }
    }

    /// Whether the matrix is factored dense (order up to [`DENSE_MAX`]).
    pub fn is_dense(&self) -> bool {
        self.dense.is_some()
    }

    /// The dense matrix to fill in place (column-major, entry (r, c) at `c·n + r`) for
    /// [`SparseLu::factor_dense`]; None for a matrix factored sparse.
    pub fn dense_mut(&mut self) -> Option<&mut [f64]> {
        self.factored = false;
        self.dense.as_mut().map(DenseLu::matrix_mut)
    }

    /// Factors the matrix filled through [`SparseLu::dense_mut`].
    pub fn factor_dense(&mut self) -> Result<(), FactorError> {
        self.factored = false;
        let lu = self.dense.as_mut().ok_or(FactorError::Singular)?;
        if lu.matrix_mut().iter().any(|x| !x.is_finite()) {
            return Err(FactorError::NotFinite);
        }
        lu.factor()?;
        self.factored = true;
        Ok(())
    }

    /// Factors the matrix whose values (one per pattern slot) are `values`.
    pub fn factor(&mut self, values: &[f64]) -> Result<(), FactorError> {
        self.factored = false;
        if let Some(lu) = &mut self.dense {
            self.pattern.scatter(values, false, lu.matrix_mut());
            return self.factor_dense();
        }
        if values.iter().any(|x| !x.is_finite()) {
            return Err(FactorError::NotFinite);
        }
        let a = faer::sparse::SparseColMatRef::new(self.sym.as_ref(), values);
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                a,
                faer::Par::Seq,
                faer::dyn_stack::MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(|_| FactorError::Singular)?;
        self.factored = true;
        Ok(())
    }

    /// Solves A·x = b in place (after a successful [`SparseLu::factor`]); a non-finite
    /// solution means A is numerically singular.
    pub fn solve(&mut self, b: &mut [f64]) -> Result<(), FactorError> {
        if !self.factored {
            return Err(FactorError::Singular);
        }
        let n = b.len();
        if let Some(lu) = &self.dense {
            lu.solve(b);
        } else {
            let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric);
            lu.solve_in_place_with_conj(
                faer::Conj::No,
                faer::MatMut::from_column_major_slice_mut(b, n, 1),
                faer::Par::Seq,
                faer::dyn_stack::MemStack::new(&mut self.solve_scratch),
            );
        }
        finite_solution(b)
    }
}

/// Sparse Cholesky LLᵀ (faer) of a symmetric positive definite matrix stored on a
/// [`Pattern`] holding both triangles (only the lower one is read): the symbolic
/// analysis (minimum-degree order) is done once; each [`SparseLlt::factor`] is numeric.
/// Half the work of [`SparseLu`] and no pivoting, where the matrix allows it.
pub struct SparseLlt {
    pattern: Pattern,
    symbolic: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    factor_scratch: faer::dyn_stack::MemBuffer,
    solve_scratch: faer::dyn_stack::MemBuffer,
    factored: bool,
    /// Matrices up to [`DENSE_MAX`] are factored dense ([`DenseLlt`]), as [`SparseLu`]
    /// does.
    dense: Option<DenseLlt>,
    /// As [`SparseLu`]'s.
    sym: faer::sparse::SymbolicSparseColMat<usize>,
}

impl SparseLlt {
    /// The symbolic analysis of `pattern`.
    pub fn new(pattern: Pattern) -> Result<SparseLlt, FactorError> {
        use faer::sparse::linalg::cholesky;
        let sym = SparseLu::owned_symbolic(&pattern);
        let symbolic = cholesky::factorize_symbolic_cholesky(
            sym.as_ref(),
            faer::Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(|_| FactorError::Singular)?;
        let par = faer::Par::Seq;
        let factor_scratch = faer::dyn_stack::MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        );
        let solve_scratch =
            faer::dyn_stack::MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(SparseLlt {
            l_values: vec![0.0; symbolic.len_val()],
            symbolic,
            factor_scratch,
            solve_scratch,
            factored: false,
            dense: (pattern.n <= DENSE_MAX).then(|| DenseLlt::new(pattern.n)),
            sym,
            pattern,
        })
    }

    /// Factors the matrix whose values (one per pattern slot) are `values`; an error when
    /// it is not numerically positive definite.
    pub fn factor(&mut self, values: &[f64]) -> Result<(), FactorError> {
        self.factored = false;
        if values.iter().any(|x| !x.is_finite()) {
            return Err(FactorError::NotFinite);
        }
        if let Some(llt) = &mut self.dense {
            // The lower triangle (the upper one is not read, as faer's).
            self.pattern.scatter(values, true, llt.matrix_mut());
            llt.factor()?;
            self.factored = true;
            return Ok(());
        }
        let a = faer::sparse::SparseColMatRef::new(self.sym.as_ref(), values);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                faer::Side::Lower,
                Default::default(),
                faer::Par::Seq,
                faer::dyn_stack::MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(|_| FactorError::Singular)?;
        self.factored = true;
        Ok(())
    }

    /// Solves A·x = b in place (after a successful [`SparseLlt::factor`]).
    pub fn solve(&mut self, b: &mut [f64]) -> Result<(), FactorError> {
        if !self.factored {
            return Err(FactorError::Singular);
        }
        let n = b.len();
        if let Some(llt) = &self.dense {
            llt.solve(b);
            return finite_solution(b);
        }
        let llt = faer::sparse::linalg::cholesky::LltRef::new(&self.symbolic, &self.l_values);
        llt.solve_in_place_with_conj(
            faer::Conj::No,
            faer::MatMut::from_column_major_slice_mut(b, n, 1),
            faer::Par::Seq,
            faer::dyn_stack::MemStack::new(&mut self.solve_scratch),
        );
        Ok(())
    }
}

/// A solve's answer: a non-finite entry means the matrix is numerically singular.
fn finite_solution(x: &[f64]) -> Result<(), FactorError> {
    match x.iter().all(|v| v.is_finite()) {
        true => Ok(()),
        false => Err(FactorError::Singular),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solves_an_indefinite_saddle_point_system() {
        // [[2, 0, 1], [0, 3, 1], [1, 1, 0]]·x = [1, 2, 3]: a mass block with one
        // constraint row, zero on the diagonal (needs pivoting). By hand: 2a + l = 1,
        // 3b + l = 2, a + b = 3 give a = 8/5, b = 7/5, l = −11/5.
        let entries = [
            (0, 0, 2.0),
            (1, 1, 3.0),
            (0, 2, 1.0),
            (2, 0, 1.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
        ];
        let mut positions: Vec<(usize, usize)> = entries.iter().map(|e| (e.0, e.1)).collect();
        positions.push((2, 2)); // a structural zero
        let p = Pattern::new(3, positions);
        let mut vals = vec![0.0; p.nnz()];
        for &(r, c, x) in &entries {
            vals[p.slot(r, c).unwrap()] += x;
        }
        let mut lu = SparseLu::new(p).unwrap();
        lu.factor(&vals).unwrap();
        let mut b = [1.0, 2.0, 3.0];
        lu.solve(&mut b).unwrap();
        for (x, want) in b.iter().zip([8.0 / 5.0, 7.0 / 5.0, -11.0 / 5.0]) {
            assert!((x - want).abs() < 1e-14, "{b:?}");
        }
    }

    #[test]
    fn cholesky_solves_a_positive_definite_system_and_refuses_an_indefinite_one() {
        // [[4, 2, 0], [2, 5, 1], [0, 1, 3]]·x = [2, 1, 7]: by hand (Cramer, det = 44),
        // x = (36/44, −28/44, 112/44).
        let full = [
            (0, 0, 4.0),
            (0, 1, 2.0),
            (1, 0, 2.0),
            (1, 1, 5.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
            (2, 2, 3.0),
        ];
        let p = Pattern::new(3, full.iter().map(|e| (e.0, e.1)).collect());
        let mut vals = vec![0.0; p.nnz()];
        for &(r, c, x) in &full {
            vals[p.slot(r, c).unwrap()] = x;
        }
        let mut llt = SparseLlt::new(p).unwrap();
        llt.factor(&vals).unwrap();
        let mut b = [2.0, 1.0, 7.0];
        llt.solve(&mut b).unwrap();
        for (x, want) in b.iter().zip([36.0 / 44.0, -28.0 / 44.0, 112.0 / 44.0]) {
            assert!((x - want).abs() < 1e-14, "{b:?}");
        }
        vals.iter_mut().for_each(|v| *v = -*v);
        assert_eq!(llt.factor(&vals), Err(FactorError::Singular));
    }

    #[test]
    fn sparse_cholesky_recovers_a_known_solution() {
        // n = 90 (past the dense size): a chain of 3×3 blocks coupled to their
        // neighbours, plus long-range couplings that a fill-reducing order permutes,
        // diagonally dominant so positive definite. b = A·x for a chosen x; the solve
        // must give x back.
        let n = 90;
        let mut full: Vec<(usize, usize, f64)> = Vec::new();
        for i in 0..n {
            full.push((i, i, 20.0 + (i % 7) as f64));
            for (j, v) in [(i + 1, 1.5), (i + 3, -2.0), ((i * 37 + 11) % n, 0.75)] {
                if j < n && j != i && !full.iter().any(|e| (e.0, e.1) == (i, j)) {
                    full.push((i, j, v));
                    full.push((j, i, v));
                }
            }
        }
        let p = Pattern::new(n, full.iter().map(|e| (e.0, e.1)).collect());
        let mut vals = vec![0.0; p.nnz()];
        for &(r, c, v) in &full {
            vals[p.slot(r, c).unwrap()] += v;
        }
        let x: Vec<f64> = (0..n).map(|i| ((i * 13 % 17) as f64 - 8.0) / 3.0).collect();
        let mut b = vec![0.0; n];
        for &(r, c, v) in &full {
            b[r] += v * x[c];
        }
        let mut llt = SparseLlt::new(p).unwrap();
        assert!(llt.dense.is_none() && llt.symbolic.perm().is_some());
        llt.factor(&vals).unwrap();
        llt.solve(&mut b).unwrap();
        for (got, want) in b.iter().zip(&x) {
            assert!((got - want).abs() < 1e-13, "{got} vs {want}");
        }
    }

    #[test]
    fn singular_and_non_finite_matrices_are_errors() {
        let p = Pattern::new(2, vec![(0, 0), (1, 0), (0, 1), (1, 1)]);
        let mut lu = SparseLu::new(p).unwrap();
        let singular = lu
            .factor(&[1.0, 2.0, 2.0, 4.0])
            .and_then(|_| lu.solve(&mut [1.0, 1.0]));
        assert_eq!(singular, Err(FactorError::Singular));
        assert_eq!(
            lu.factor(&[f64::NAN, 0.0, 0.0, 1.0]),
            Err(FactorError::NotFinite)
        );
    }
}
