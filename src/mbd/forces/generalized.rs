//! What force evaluation writes: the generalized force Q per velocity-level column and
//! its Jacobians ∂Q/∂q, ∂Q/∂v as entries.

use crate::vocab::math::DVec;

/// Q and its Jacobians over velocity-level columns: `dq` holds ∂Q/∂q, `dv` ∂Q/∂v as
/// (row, column, value) entries (repeats add up).
#[derive(Clone, Debug, Default)]
pub struct Generalized {
    /// Q: the generalized force per velocity-level column.
    pub q: DVec,
    /// ∂Q/∂q entries (row, column, value).
    pub dq: Vec<(usize, usize, f64)>,
    /// ∂Q/∂v entries (row, column, value).
    pub dv: Vec<(usize, usize, f64)>,
}

impl Generalized {
    /// A zero Q of `n` columns with no Jacobian entries.
    pub fn new(n: usize) -> Self {
        Generalized {
            q: DVec::zeros(n),
            dq: Vec::new(),
            dv: Vec::new(),
        }
    }

    /// Zeroes Q and drops the Jacobian entries, keeping the capacity.
    pub fn clear(&mut self) {
        self.q.fill(0.0);
        self.dq.clear();
        self.dv.clear();
    }
}
