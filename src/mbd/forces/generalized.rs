//! What force evaluation writes: the generalized force Q per velocity-level column and
//! its Jacobians ∂Q/∂q, ∂Q/∂v and ∂Q/∂(solution value) as entries.

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
    /// ∂Q/∂s entries (row, solution value, value) by the solution values s the forces
    /// read ([`super::ForceSet::solution`]), where a force law has them (joint friction
    /// by its joint's reaction): the dynamics chains them with ∂s/∂λ into the Newton
    /// matrix.
    pub ds: Vec<(usize, usize, f64)>,
}

impl Generalized {
    /// A zero Q of `n` columns with no Jacobian entries.
    pub fn new(n: usize) -> Self {
        Generalized {
            q: DVec::zeros(n),
            dq: Vec::new(),
            dv: Vec::new(),
            ds: Vec::new(),
        }
    }

    /// Zeroes Q and drops the Jacobian entries, keeping the capacity.
    pub fn clear(&mut self) {
        self.q.fill(0.0);
        self.dq.clear();
        self.dv.clear();
        self.ds.clear();
    }
}
