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
