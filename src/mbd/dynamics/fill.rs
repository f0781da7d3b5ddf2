//! Where the entries of the Newton matrix
//! [[w_m·M/UCF − w_k·∂Q/∂q − w_c·∂Q/∂v, w_l·(Φ_qᵀ − ∂Q/∂λ)], [Φ_q, −ε·I]] go, found once when the
//! dynamics is set up: the value slots of the sparse pattern or, for a matrix small
//! enough to be factored dense, the places in its column-major array, written there
//! directly. Searching the pattern for every entry at every factorization cost as much as
//! factoring a pendulum's 5 × 5 matrix.

use super::blocks::{Mat3Block, Weights};
use super::jacobian::Jacobian;
use super::workspace::Factors;
use crate::mbd::forces::Generalized;
use crate::mbd::sparse::{FactorError, SparseLu};
use crate::mbd::system::{Dimension, System};

/// A position outside the pattern.
const NONE: usize = usize::MAX;

/// The places of the entries whose positions never change: the mass blocks, the
/// Jacobian (each entry twice: Φ_q and w_l·Φ_qᵀ) and the multipliers' diagonal, in the
/// order [`Fill::factor`] writes them.
#[derive(Default)]
pub struct Fill {
    /// In the sparse value array ([`NONE`]: not in the pattern).
    slots: Vec<usize>,
    /// In the dense array, with the matrix's order, when it is factored dense.
    dense: Option<(usize, Vec<usize>)>,
}

impl Fill {
    /// The places for the matrix `lu` factors, of the system `sys` with Jacobian `jac`.
    pub fn new(lu: &SparseLu, sys: &System, jac: &Jacobian) -> Fill {
        let bs = sys.dim.cols();
        let n = sys.moving_parts() * bs;
        let mut positions = Vec::new();
        for i in 0..sys.moving_parts() {
            let b = i * bs;
            match sys.dim {
                Dimension::Three => {
                    for c in 0..3 {
                        positions.push((b + c, b + c));
                        for r in 0..3 {
                            positions.push((b + 3 + r, b + 3 + c));
                        }
                    }
                }
                Dimension::Two => positions.extend((0..3).map(|c| (b + c, b + c))),
            }
        }
        for (r, c, _) in jac.entries() {
            positions.push((n + r, c));
            positions.push((c, n + r));
        }
        positions.extend((0..jac.rows()).map(|r| (n + r, n + r)));
        let pat = lu.pattern();
        let order = pat.n;
        Fill {
            slots: positions
                .iter()
                .map(|&(r, c)| pat.slot(r, c).unwrap_or(NONE))
                .collect(),
            dense: lu.is_dense().then(|| {
                (
                    order,
                    positions.iter().map(|&(r, c)| c * order + r).collect(),
                )
            }),
        }
    }

    /// Fills the matrix with mass blocks `blocks`, Jacobian `jac`, force Jacobians `gen`
    /// and ∂Q/∂λ `reactions` (entries at their place in the matrix, the multipliers'
    /// columns), geometric stiffness `geo`, weights `w` and regularisation `eps`, and
    /// factors it.
    #[allow(clippy::too_many_arguments)]
    pub fn factor(
        &self,
        f: &mut Factors,
        blocks: &[Mat3Block],
        jac: &Jacobian,
        (gen, reactions): (&Generalized, &[(usize, usize, f64)]),
        geo: &[(usize, usize, f64)],
        w: Weights,
        eps: f64,
    ) -> Result<(), FactorError> {
        let terms = Terms {
            blocks,
            jac,
            gen,
            reactions,
            geo,
            w,
            eps,
        };
        match &self.dense {
            Some((order, places)) => {
                let order = *order;
                let buf = f.lu.dense_mut().expect("a dense factorization");
                buf.fill(0.0);
                terms.write(buf, places, |r, c| Some(c * order + r));
                f.lu.factor_dense()
            }
            None => {
                f.values.fill(0.0);
                let pat = f.lu.pattern();
                terms.write(&mut f.values, &self.slots, |r, c| pat.slot(r, c));
                f.lu.factor(&f.values)
            }
        }
    }
}

/// What goes into the matrix.
struct Terms<'a> {
    blocks: &'a [Mat3Block],
    jac: &'a Jacobian,
    gen: &'a Generalized,
    reactions: &'a [(usize, usize, f64)],
    geo: &'a [(usize, usize, f64)],
    w: Weights,
    eps: f64,
}

impl Terms<'_> {
    /// Adds every entry into `buf` (zeroed): the fixed ones at `places`, the force
    /// Jacobians' and the geometric stiffness's (whose positions vary) where `at` says.
    fn write(&self, buf: &mut [f64], places: &[usize], at: impl Fn(usize, usize) -> Option<usize>) {
        let w = self.w;
        let mut places = places.iter();
        let mut put = |buf: &mut [f64], x: f64| {
            let s = *places.next().expect("one place per entry");
            if s != NONE {
                buf[s] += x;
            }
        };
        for block in self.blocks {
            match *block {
                Mat3Block::Three(m, j) => {
                    for c in 0..3 {
                        put(buf, w.w_m * m);
                        for r in 0..3 {
                            put(buf, w.w_m * j[(r, c)]);
                        }
                    }
                }
                Mat3Block::Two(m, j) => {
                    put(buf, w.w_m * m);
                    put(buf, w.w_m * m);
                    put(buf, w.w_m * j);
                }
            }
        }
        for (_, _, x) in self.jac.entries() {
            put(buf, x);
            put(buf, w.w_l * x);
        }
        for _ in 0..self.jac.rows() {
            put(buf, -self.eps);
        }
        // (The Jacobian's and the diagonal's places hold nothing else, so each place
        // sums the mass's share first, then the force Jacobians'.)
        let mut add = |r: usize, c: usize, x: f64| {
            if let Some(s) = at(r, c) {
                buf[s] += x;
            }
        };
        if w.w_k != 0.0 {
            for &(r, c, x) in &self.gen.dq {
                add(r, c, -w.w_k * x);
            }
            for &(r, c, x) in self.geo {
                add(r, c, w.w_k * x);
            }
        }
        if w.w_c != 0.0 {
            for &(r, c, x) in &self.gen.dv {
                add(r, c, -w.w_c * x);
            }
        }
        // (A force reading its joint's reaction loads the parts the joint's rows read:
        // its ∂Q/∂λ falls on Φ_qᵀ's places.)
        for &(r, c, x) in self.reactions {
            add(r, c, -w.w_l * x);
        }
    }
}
