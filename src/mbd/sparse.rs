//! A sparse matrix as it is assembled: (row, column, value) triplets. Constraint
//! Jacobians are built this way (each element touches at most two parts), and the
//! redundancy analysis and solvers read them.

/// A matrix of `nrows` × `ncols` whose non-zeros are `entries`; repeated (row, column)
/// pairs add up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Triplets {
    pub nrows: usize,
    pub ncols: usize,
    pub entries: Vec<(u32, u32, f64)>,
}

impl Triplets {
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
#[derive(Clone, Debug)]
pub struct Pattern {
    pub n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Pattern {
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

/// Why a sparse factorization failed.
#[derive(Clone, Debug, PartialEq)]
pub enum FactorError {
    /// No pivot could be found (structurally singular), or the factors are not finite.
    Singular,
    /// A value of the matrix is NaN or infinite.
    NotFinite,
}

/// Sparse LU with partial pivoting (faer): the symbolic analysis (fill-reducing column
/// order) is done once per [`Pattern`]; each [`SparseLu::factor`] is numeric only, and
/// solves reuse their scratch memory.
pub struct SparseLu {
    pattern: Pattern,
    symbolic: faer::sparse::linalg::lu::SymbolicLu<usize>,
    numeric: faer::sparse::linalg::lu::NumericLu<usize, f64>,
    factor_scratch: faer::dyn_stack::MemBuffer,
    solve_scratch: faer::dyn_stack::MemBuffer,
    factored: bool,
}

impl SparseLu {
    /// The symbolic analysis of `pattern`.
    pub fn new(pattern: Pattern) -> Result<SparseLu, FactorError> {
        use faer::sparse::linalg::lu;
        let sym = Self::symbolic_of(&pattern);
        let symbolic = lu::factorize_symbolic_lu(sym, Default::default())
            .map_err(|_| FactorError::Singular)?;
        let par = faer::Par::Seq;
        let factor_scratch = faer::dyn_stack::MemBuffer::new(
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
        );
        let solve_scratch =
            faer::dyn_stack::MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(SparseLu {
            pattern,
            symbolic,
            numeric: lu::NumericLu::new(),
            factor_scratch,
            solve_scratch,
            factored: false,
        })
    }

    fn symbolic_of(p: &Pattern) -> faer::sparse::SymbolicSparseColMatRef<'_, usize> {
        faer::sparse::SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx)
    }

    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Factors the matrix whose values (one per pattern slot) are `values`.
    pub fn factor(&mut self, values: &[f64]) -> Result<(), FactorError> {
        self.factored = false;
        if values.iter().any(|x| !x.is_finite()) {
            return Err(FactorError::NotFinite);
        }
        let sym = Self::symbolic_of(&self.pattern);
        let a = faer::sparse::SparseColMatRef::new(sym, values);
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
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let n = b.len();
        lu.solve_in_place_with_conj(
            faer::Conj::No,
            faer::MatMut::from_column_major_slice_mut(b, n, 1),
            faer::Par::Seq,
            faer::dyn_stack::MemStack::new(&mut self.solve_scratch),
        );
        if b.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(FactorError::Singular)
        }
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
