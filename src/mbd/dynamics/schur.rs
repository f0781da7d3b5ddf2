//! The Newton matrix solved through the multipliers' Schur complement, for systems
//! whose effective mass is block diagonal (no force element couples two parts):
//!
//! ```text
//! [A    w·Bᵀ] [x]   [r₁]        (w·B·A⁻¹·Bᵀ + ε·I)·y = B·A⁻¹·r₁ − r₂,
//! [B    −ε·I] [y] = [r₂]   ⇒    x = A⁻¹·(r₁ − w·Bᵀ·y).
//! ```
//!
//! A = w_m·M/UCF − w_k·∂Q/∂q − w_c·∂Q/∂v has one small dense block per part, inverted
//! on its own; the complement is m × m over the constraint rows and couples only rows
//! that share a part (block tridiagonal for a chain). It is the same linear system the
//! full saddle-point LU solves, several times cheaper to factor and to solve, because
//! the zero block no longer needs pivoting across the whole matrix. A part whose block
//! is singular (a point mass has no rotational inertia) sends the factorization back
//! to the full LU.

use super::blocks::{Mat3Block, Weights};
use super::jacobian::Jacobian;
use crate::mbd::forces::Generalized;
use crate::mbd::sparse::{FactorError, Pattern, SparseLlt, SparseLu};
use nalgebra::Matrix6;

/// The largest unsymmetric part of a block, relative to its largest entry, that is
/// dropped for the Cholesky of the complement (see [`Schur::factor`]).
const SKEW_MAX: f64 = 1e-3;

/// Condition number (∞-norm) above which a part's block is not inverted on its own.
const BLOCK_CONDITION_MAX: f64 = 1e12;

/// The Schur-complement solver: the static structure (which rows share a part) and the
/// numeric factors of the last [`Schur::factor`].
pub struct Schur {
    /// Columns per part, parts and rows.
    bs: usize,
    parts: usize,
    m: usize,
    /// The Jacobian slots of each part.
    part_slots: Vec<Vec<usize>>,
    /// For each part, for each ordered pair of its slots, the complement's value slot.
    pair_slot: Vec<usize>,
    diag_slot: Vec<usize>,
    /// Per Jacobian slot, A⁻¹ times the row's block.
    ainv_bt: Vec<f64>,
    /// Per part, A and then A⁻¹ (row major, bs × bs).
    a: Vec<f64>,
    ainv: Vec<f64>,
    values: Vec<f64>,
    /// The complement's pattern, and its LU, made the first time a complement is not
    /// positive definite (its column ordering costs as much as a dozen steps of a long
    /// chain, and symmetric blocks never need it).
    pattern: Pattern,
    lu: Option<SparseLu>,
    /// Cholesky of the complement, used when every block is symmetric (then the
    /// complement is symmetric positive definite); `via_llt` says it holds the factors.
    llt: Option<SparseLlt>,
    via_llt: bool,
    w_l: f64,
    /// Φ_q as it was factored: a reused factorization solves with it, not with the
    /// Jacobian of the current iterate, so each solve applies one fixed matrix (mixing
    /// the two costs Newton its contraction).
    frozen: Jacobian,
    /// Every 6 × 6 block (and so its inverse) is two 3 × 3 diagonal blocks: products
    /// with A⁻¹ skip the zero quarters.
    split: bool,
}

impl Schur {
    /// The structure for `parts` moving parts and the rows of `jac`.
    pub fn new(jac: &Jacobian, parts: usize) -> Schur {
        let (bs, m) = (jac.bs, jac.rows());
        let part_slots = jac.part_slots(parts);
        let pairs = || {
            part_slots.iter().flat_map(|slots| {
                slots.iter().flat_map(|&a| {
                    slots
                        .iter()
                        .map(move |&b| (jac.slot_row(a), jac.slot_row(b)))
                })
            })
        };
        let positions = (0..m).map(|r| (r, r)).chain(pairs()).collect();
        let pattern = Pattern::new(m, positions);
        let slot = |(r, c)| pattern.slot(r, c).expect("in the pattern");
        let pair_slot = pairs().map(slot).collect();
        let diag_slot = (0..m).map(|r| slot((r, r))).collect();
        Schur {
            bs,
            parts,
            m,
            part_slots,
            pair_slot,
            diag_slot,
            ainv_bt: vec![0.0; jac.slots() * bs],
            a: vec![0.0; parts * bs * bs],
            ainv: vec![0.0; parts * bs * bs],
            values: vec![0.0; pattern.nnz()],
            llt: SparseLlt::new(pattern.clone()).ok(),
            via_llt: false,
            pattern,
            lu: None,
            w_l: 1.0,
            frozen: jac.clone(),
            split: false,
        }
    }

    /// Factors the Newton matrix with weights (w_m, w_k, w_c, w_l) from the mass
    /// `blocks`, the force Jacobians in `gen` (which must stay within each part's own
    /// block), the constraint Jacobian `jac` and the multipliers' regularisation `eps`.
    /// `Ok(false)`: a part's block is too ill-conditioned to invert alone; the caller
    /// factors the full matrix instead.
    pub fn factor(
        &mut self,
        jac: &Jacobian,
        blocks: &[Mat3Block],
        gen: &Generalized,
        geo: &[(usize, usize, f64)],
        w: Weights,
        eps: f64,
    ) -> Result<bool, FactorError> {
        let bs = self.bs;
        self.frozen.copy_values_from(jac);
        let a = &mut self.a;
        a.fill(0.0);
        for (i, blk) in blocks.iter().enumerate() {
            let o = i * bs * bs;
            match *blk {
                Mat3Block::Three(m, j) => {
                    for c in 0..3 {
                        a[o + c * bs + c] = w.w_m * m;
                        for r in 0..3 {
                            a[o + (3 + r) * bs + 3 + c] = w.w_m * j[(r, c)];
                        }
                    }
                }
                Mat3Block::Two(m, j) => {
                    a[o] = w.w_m * m;
                    a[o + bs + 1] = w.w_m * m;
                    a[o + 2 * bs + 2] = w.w_m * j;
                }
            }
        }
        // A = M − w_k·∂Q/∂q − w_c·∂Q/∂v + w_k·(geometric stiffness).
        for (list, wt) in [(&gen.dq[..], w.w_k), (&gen.dv[..], w.w_c), (geo, -w.w_k)] {
            if wt == 0.0 {
                continue;
            }
            for &(r, c, x) in list {
                let i = r / bs;
                debug_assert_eq!(i, c / bs, "a force couples two parts");
                a[i * bs * bs + (r % bs) * bs + c % bs] -= wt * x;
            }
        }
        self.split = bs == 6 && a.chunks_exact(36).all(decoupled6);
        // Blocks whose unsymmetric part is small against the block (a slender part's
        // gyroscopic terms, h·ω·J against J) are factored by their symmetric part: the
        // Newton matrix is then approximate, by that fraction, which costs Newton a
        // contraction of about that much per iteration, and the complement has the
        // Cholesky at half the LU's price. The saddle point's blocks (mass alone) are
        // symmetric as they stand.
        let symmetric = a.chunks_exact_mut(bs * bs).all(|blk| {
            let top = blk.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let skew = (0..bs)
                .flat_map(|r| (0..r).map(move |c| (r, c)))
                .fold(0.0f64, |m, (r, c)| {
                    m.max((blk[r * bs + c] - blk[c * bs + r]).abs())
                });
            if skew > SKEW_MAX * top {
                return false;
            }
            for r in 0..bs {
                for c in 0..r {
                    let mean = 0.5 * (blk[r * bs + c] + blk[c * bs + r]);
                    (blk[r * bs + c], blk[c * bs + r]) = (mean, mean);
                }
            }
            true
        });
        for (blk, inv) in a
            .chunks_exact(bs * bs)
            .zip(self.ainv.chunks_exact_mut(bs * bs))
        {
            if !invert(blk, bs, inv) {
                return Ok(false);
            }
        }
        self.w_l = w.w_l;
        // Symmetric blocks make the complement symmetric positive definite (A positive
        // definite, ε > 0): Cholesky, which reads the lower half only, unless it finds
        // otherwise; then LU on the whole.
        self.via_llt = false;
        if symmetric && self.llt.is_some() {
            self.fill(jac, w.w_l, eps, true);
            if let Some(llt) = &mut self.llt {
                if llt.factor(&self.values).is_ok() {
                    self.via_llt = true;
                    return Ok(true);
                }
            }
        }
        self.fill(jac, w.w_l, eps, false);
        let lu = match &mut self.lu {
            Some(lu) => lu,
            None => self.lu.insert(SparseLu::new(self.pattern.clone())?),
        };
        lu.factor(&self.values)?;
        Ok(true)
    }

    /// The complement w·Φ_q·A⁻¹·Φ_qᵀ + ε·I into `values`, its lower half only when
    /// `lower` (rows ≥ columns).
    fn fill(&mut self, jac: &Jacobian, w_l: f64, eps: f64, lower: bool) {
        match self.bs {
            3 => self.fill_complement::<3>(jac, w_l, lower),
            _ => self.fill_complement::<6>(jac, w_l, lower),
        }
        for &d in &self.diag_slot {
            self.values[d] += eps;
        }
    }

    /// A⁻¹·Bᵀ per Jacobian slot, and the complement w·Φ_q·A⁻¹·Φ_qᵀ into `values` (with
    /// the block size known to the compiler: this is most of a factorization's time).
    fn fill_complement<const BS: usize>(&mut self, jac: &Jacobian, w_l: f64, lower: bool) {
        for k in 0..jac.slots() {
            let i = jac.slot_part(k);
            let inv = &self.ainv[i * BS * BS..(i + 1) * BS * BS];
            let bk: &[f64; BS] = jac.block(k).try_into().expect("blocks of BS columns");
            self.ainv_bt[k * BS..(k + 1) * BS].copy_from_slice(&apply(inv, bk, self.split));
        }
        self.values.fill(0.0);
        let mut next = 0;
        for slots in &self.part_slots {
            for &sa in slots {
                let ba: &[f64; BS] = jac.block(sa).try_into().expect("blocks of BS columns");
                let row = jac.slot_row(sa);
                for &sb in slots {
                    if !lower || row >= jac.slot_row(sb) {
                        let y = &self.ainv_bt[sb * BS..(sb + 1) * BS];
                        self.values[self.pair_slot[next]] += w_l * dot_n::<BS>(y, ba);
                    }
                    next += 1;
                }
            }
        }
    }

    /// Solves the factored matrix in place: `rhs` = [r₁ (parts × bs); r₂ (rows)].
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), FactorError> {
        match self.bs {
            3 => self.solve_blocks::<3>(rhs),
            _ => self.solve_blocks::<6>(rhs),
        }
    }

    /// [`Schur::solve`] with the block size known to the compiler.
    fn solve_blocks<const BS: usize>(&mut self, rhs: &mut [f64]) -> Result<(), FactorError> {
        let jac = &self.frozen;
        let n = self.parts * BS;
        let (top, bottom) = rhs.split_at_mut(n);
        debug_assert_eq!(bottom.len(), self.m);
        for (x, inv) in top
            .chunks_exact_mut(BS)
            .zip(self.ainv.chunks_exact(BS * BS))
        {
            let x: &mut [f64; BS] = x.try_into().expect("blocks of BS columns");
            *x = apply(inv, x, self.split);
        }
        for t in bottom.iter_mut() {
            *t = -*t;
        }
        jac.add_times(top, bottom);
        match (&mut self.llt, self.via_llt) {
            (Some(llt), true) => llt.solve(bottom)?,
            _ => match &mut self.lu {
                Some(lu) => lu.solve(bottom)?,
                None => return Err(FactorError::Singular),
            },
        }
        // x = z − w·A⁻¹·Bᵀ·y, with A⁻¹·Bᵀ kept per slot.
        for (k, g) in self.ainv_bt.chunks_exact(BS).enumerate() {
            let y = self.w_l * bottom[jac.slot_row(k)];
            let p = jac.slot_part(k);
            // fixed-size blocks: unrolled, no bounds checks
            let x: &mut [f64; BS] = (&mut top[p * BS..(p + 1) * BS])
                .try_into()
                .expect("BS columns");
            let g: &[f64; BS] = g.try_into().expect("BS values");
            for c in 0..BS {
                x[c] -= y * g[c];
            }
        }
        Ok(())
    }
}

/// `inv`·`x` for one part's N × N row-major inverse; with `split` (N = 6) the inverse is
/// two 3 × 3 diagonal blocks and only those are read.
fn apply<const N: usize>(inv: &[f64], x: &[f64; N], split: bool) -> [f64; N] {
    std::array::from_fn(|r| {
        let row = &inv[r * N..(r + 1) * N];
        if split {
            let o = if r < 3 { 0 } else { 3 };
            (o..o + 3).map(|k| row[k] * x[k]).sum()
        } else {
            dot_n::<N>(row, x)
        }
    })
}

/// A dot product of `N` entries (`a` holds at least N).
fn dot_n<const N: usize>(a: &[f64], b: &[f64; N]) -> f64 {
    let a: &[f64; N] = a[..N].try_into().expect("N entries");
    (0..N).map(|k| a[k] * b[k]).sum()
}

/// Writes into `out` the inverse of the 3 × 3 or 6 × 6 row-major block `a`; false
/// when it is singular or too ill-conditioned to be inverted alone.
fn invert(a: &[f64], bs: usize, out: &mut [f64]) -> bool {
    let norm = |x: &[f64]| {
        x.chunks_exact(bs)
            .map(|row| row.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let ok = match bs {
        3 => invert3(a, out),
        6 if decoupled6(a) => invert_diagonal_blocks6(a, out),
        6 => match Matrix6::from_row_slice(a).try_inverse() {
            Some(inv) => {
                for (r, row) in out.chunks_exact_mut(6).enumerate() {
                    for (c, o) in row.iter_mut().enumerate() {
                        *o = inv[(r, c)];
                    }
                }
                true
            }
            None => false,
        },
        _ => false,
    };
    let cond = norm(a) * norm(out);
    ok && cond.is_finite() && cond <= BLOCK_CONDITION_MAX
}

/// True when a 6 × 6 block has no translation–rotation coupling (the mass matrix alone,
/// or forces that keep the two apart): it inverts as two 3 × 3 blocks.
fn decoupled6(a: &[f64]) -> bool {
    (0..3).all(|r| (3..6).all(|c| a[r * 6 + c] == 0.0 && a[c * 6 + r] == 0.0))
}

/// The inverse of a decoupled 6 × 6 block from its two 3 × 3 diagonal blocks.
fn invert_diagonal_blocks6(a: &[f64], out: &mut [f64]) -> bool {
    out.fill(0.0);
    for o in [0, 3] {
        let (mut blk, mut inv) = ([0.0; 9], [0.0; 9]);
        for r in 0..3 {
            blk[r * 3..r * 3 + 3].copy_from_slice(&a[(o + r) * 6 + o..(o + r) * 6 + o + 3]);
        }
        if !invert3(&blk, &mut inv) {
            return false;
        }
        for r in 0..3 {
            out[(o + r) * 6 + o..(o + r) * 6 + o + 3].copy_from_slice(&inv[r * 3..r * 3 + 3]);
        }
    }
    true
}

/// 3 × 3 inverse by cofactors (the 2D blocks: one per part at every refactor).
fn invert3(a: &[f64], out: &mut [f64]) -> bool {
    let c = [
        a[4] * a[8] - a[5] * a[7],
        a[5] * a[6] - a[3] * a[8],
        a[3] * a[7] - a[4] * a[6],
    ];
    let det = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
    if det == 0.0 || !det.is_finite() {
        return false;
    }
    let inv = [
        c[0],
        a[2] * a[7] - a[1] * a[8],
        a[1] * a[5] - a[2] * a[4],
        c[1],
        a[0] * a[8] - a[2] * a[6],
        a[2] * a[3] - a[0] * a[5],
        c[2],
        a[1] * a[6] - a[0] * a[7],
        a[0] * a[4] - a[1] * a[3],
    ];
    for (o, x) in out.iter_mut().zip(inv) {
        *o = x / det;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mbd::dynamics::Weights;
    use crate::vocab::math::{DMat, DVec};

    #[test]
    fn cofactor_inverse_times_the_block_is_the_identity() {
        let a = [4.0, 1.0, -2.0, 0.5, 3.0, 1.0, -1.0, 2.0, 5.0];
        let mut inv = [0.0; 9];
        assert!(invert3(&a, &mut inv));
        for r in 0..3 {
            for c in 0..3 {
                let x: f64 = (0..3).map(|k| a[r * 3 + k] * inv[k * 3 + c]).sum();
                assert!(
                    (x - f64::from(u8::from(r == c))).abs() < 1e-15,
                    "{r} {c}: {x}"
                );
            }
        }
        assert!(!invert3(
            &[1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 0.0, 1.0],
            &mut inv
        ));
    }

    #[test]
    fn a_decoupled_six_block_inverts_as_two_threes() {
        let mut a = [0.0; 36];
        for (k, x) in [2.0, 2.0, 2.0].iter().enumerate() {
            a[k * 6 + k] = *x;
        }
        let j = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 5.0];
        for r in 0..3 {
            a[(3 + r) * 6 + 3..(3 + r) * 6 + 6].copy_from_slice(&j[r * 3..r * 3 + 3]);
        }
        assert!(decoupled6(&a));
        let mut inv = [0.0; 36];
        assert!(invert(&a, 6, &mut inv));
        let want = Matrix6::from_row_slice(&a).try_inverse().unwrap();
        for r in 0..6 {
            for c in 0..6 {
                assert!((inv[r * 6 + c] - want[(r, c)]).abs() < 1e-15, "{r} {c}");
            }
        }
    }

    #[test]
    fn the_complement_solves_the_same_system_as_a_dense_lu() {
        // Symmetric blocks go through Cholesky on the complement's lower half, an
        // unsymmetric one through LU on the whole.
        for damped in [false, true] {
            complement_matches_dense_lu(damped);
        }
    }

    fn complement_matches_dense_lu(damped: bool) {
        // Two planar parts, three rows: row 0 reads part 0, rows 1 and 2 both parts.
        let jac_rows = [vec![0], vec![0, 1], vec![1, 0]];
        let mut jac = Jacobian::new(3, &jac_rows);
        let entries = [
            (0, 0, 1.0),
            (0, 2, 0.3),
            (1, 1, 1.0),
            (1, 2, -0.7),
            (1, 4, -1.0),
            (2, 3, 0.4),
            (2, 5, 1.0),
            (2, 0, 0.2),
        ];
        for &(r, c, x) in &entries {
            assert!(jac.add(r, c, x));
        }
        let blocks = [Mat3Block::Two(2.0, 0.5), Mat3Block::Two(3.0, 0.25)];
        // A force Jacobian within part 1's block (unsymmetric, as damping may be).
        let mut gen = Generalized::new(6);
        let damping = if damped {
            vec![(3, 4, 0.6), (5, 3, -0.2)]
        } else {
            vec![]
        };
        gen.dv.extend(damping.iter().copied());
        let w = Weights {
            w_m: 1.0,
            w_k: 0.0,
            w_c: 0.5,
            w_l: 0.8,
        };
        let eps = 1e-3;
        let mut schur = Schur::new(&jac, 2);
        assert!(schur.factor(&jac, &blocks, &gen, &[], w, eps).unwrap());
        assert_eq!(schur.via_llt, !damped);
        let b = [1.0, -2.0, 0.5, 3.0, 0.25, -1.0, 0.1, 0.2, -0.3];
        let mut x = b;
        schur.solve(&mut x).unwrap();
        // The same matrix, dense: [[A, w_l·Bᵀ], [B, −ε·I]].
        let mut k = DMat::zeros(9, 9);
        for (i, m, j) in [(0, 2.0, 0.5), (1, 3.0, 0.25)] {
            k[(3 * i, 3 * i)] = m;
            k[(3 * i + 1, 3 * i + 1)] = m;
            k[(3 * i + 2, 3 * i + 2)] = j;
        }
        for &(r, c, v) in &damping {
            k[(r, c)] -= 0.5 * v;
        }
        for &(r, c, v) in &entries {
            k[(6 + r, c)] = v;
            k[(c, 6 + r)] = 0.8 * v;
        }
        for r in 0..3 {
            k[(6 + r, 6 + r)] = -eps;
        }
        let want = k.lu().solve(&DVec::from_column_slice(&b)).unwrap();
        for (got, want) in x.iter().zip(want.iter()) {
            assert!(
                (got - want).abs() < 1e-12,
                "damped {damped}: {x:?} vs {want}"
            );
        }
    }
}
