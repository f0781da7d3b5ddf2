//! Damped least squares on a sparse Jacobian: factors JJᵀ + μI (or JᵀJ + μI) once and
//! solves for the minimum-norm step. Columns are reordered by reverse Cuthill–McKee over the graph of
//! columns that share a row, and the Cholesky factor is stored by envelope (skyline):
//! a chain or loop of parts keeps a narrow band, so the cost grows with the number of
//! parts times the band squared, not with its cube. Redundant rows make JJᵀ singular;
//! μ > 0 keeps the factor defined and the refinement sweeps remove its bias, converging
//! to the least-squares step of least norm (iterated Tikhonov).

/// Sparse rows of a Jacobian: (column, value) per row.
pub type Rows = [Vec<(usize, f64)>];

/// Cholesky factor of Σ rᵢrᵢᵀ + μI over sparse vectors rᵢ, envelope storage, permuted.
pub struct Factor {
    n: usize,
    /// perm[old] = new index.
    perm: Vec<usize>,
    first: Vec<usize>,
    /// Row i of L from column first[i] to i.
    l: Vec<Vec<f64>>,
}

/// Reverse Cuthill–McKee order of the column graph; returns perm[old] = new.
fn rcm(n: usize, rows: &Rows) -> Vec<usize> {
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    for r in rows {
        for &(a, _) in r {
            for &(b, _) in r {
                if a != b {
                    adj[a].push(b);
                }
            }
        }
    }
    for a in &mut adj {
        a.sort_unstable();
        a.dedup();
    }
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|&i| adj[i].len());
    for &start in &by_degree {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut head = order.len();
        order.push(start);
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = adj[v].iter().copied().filter(|&w| !seen[w]).collect();
            next.sort_by_key(|&w| adj[w].len());
            for w in next {
                seen[w] = true;
                order.push(w);
            }
        }
    }
    let mut perm = vec![0; n];
    for (new, &old) in order.iter().rev().enumerate() {
        perm[old] = new;
    }
    perm
}

impl Factor {
    /// Factors Σ rᵢrᵢᵀ + μI (JᵀJ + μI when the rᵢ are the rows of J with `n` columns).
    /// Returns None if a pivot is not positive.
    pub fn new(n: usize, rows: &Rows, mu: f64) -> Option<Factor> {
        let perm = rcm(n, rows);
        let mut first: Vec<usize> = (0..n).collect();
        for r in rows {
            let lo = r.iter().map(|&(c, _)| perm[c]).min().unwrap_or(0);
            for &(c, _) in r {
                let p = perm[c];
                first[p] = first[p].min(lo);
            }
        }
        let mut l: Vec<Vec<f64>> = (0..n).map(|i| vec![0.0; i - first[i] + 1]).collect();
        for r in rows {
            for &(a, va) in r {
                for &(b, vb) in r {
                    let (pa, pb) = (perm[a], perm[b]);
                    if pb <= pa {
                        l[pa][pb - first[pa]] += va * vb;
                    }
                }
            }
        }
        for (i, row) in l.iter_mut().enumerate() {
            row[i - first[i]] += mu;
        }
        // Envelope Cholesky: L[i][j] = (A[i][j] − Σ_k L[i][k]·L[j][k]) / L[j][j].
        for i in 0..n {
            for j in first[i]..=i {
                let k0 = first[i].max(first[j]);
                let mut s = l[i][j - first[i]];
                for k in k0..j {
                    s -= l[i][k - first[i]] * l[j][k - first[j]];
                }
                if j == i {
                    if s <= 0.0 || !s.is_finite() {
                        return None;
                    }
                    l[i][i - first[i]] = s.sqrt();
                } else {
                    l[i][j - first[i]] = s / l[j][j - first[j]];
                }
            }
        }
        Some(Factor { n, perm, first, l })
    }

    /// Solves (Σ rᵢrᵢᵀ + μI) x = b.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut y = vec![0.0; n];
        for (old, &new) in self.perm.iter().enumerate() {
            y[new] = b[old];
        }
        for i in 0..n {
            let (f, row) = (self.first[i], &self.l[i]);
            let s: f64 = row[..i - f].iter().zip(&y[f..i]).map(|(l, y)| l * y).sum();
            y[i] = (y[i] - s) / row[i - f];
        }
        for i in (0..n).rev() {
            let (f, row) = (self.first[i], &self.l[i]);
            y[i] /= row[i - f];
            let yi = y[i];
            for (yk, l) in y[f..i].iter_mut().zip(&row[..i - f]) {
                *yk -= l * yi;
            }
        }
        let mut x = vec![0.0; n];
        for (old, &new) in self.perm.iter().enumerate() {
            x[old] = y[new];
        }
        x
    }
}

/// The least-squares step of least norm for J x = b, in the dual form x = Jᵀy with
/// (JJᵀ + μI) y = b and `sweeps` refinement rounds (iterated Tikhonov). The dual form
/// keeps x in the row space of J exactly, so rounding never leaks into the directions J
/// leaves free (the mechanism's degrees of freedom stay where the user put them).
/// None when the factorisation fails (μ too small for the rounding at hand).
pub fn min_norm(n: usize, rows: &Rows, b: &[f64], mu: f64, sweeps: usize) -> Option<Vec<f64>> {
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for (r, row) in rows.iter().enumerate() {
        for &(c, v) in row {
            cols[c].push((r, v));
        }
    }
    // Σ_c J[:, c]·J[:, c]ᵀ = JJᵀ.
    let f = Factor::new(rows.len(), &cols, mu)?;
    let mut x = vec![0.0; n];
    for _ in 0..sweeps.max(1) {
        let res: Vec<f64> = rows
            .iter()
            .zip(b)
            .map(|(row, &bi)| bi - row.iter().map(|&(c, v)| v * x[c]).sum::<f64>())
            .collect();
        let dy = f.solve(&res);
        for (row, d) in rows.iter().zip(dy) {
            for &(c, v) in row {
                x[c] += v * d;
            }
        }
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vocab::math::{DMat, DVec};

    #[test]
    fn envelope_cholesky_matches_dense() {
        // A random-ish sparse 7×9 Jacobian with a repeated (redundant) row.
        let rows: Vec<Vec<(usize, f64)>> = vec![
            vec![(0, 1.0), (4, 2.0)],
            vec![(1, -1.0), (2, 0.5), (8, 1.5)],
            vec![(3, 2.0), (5, 1.0)],
            vec![(6, 1.0), (7, -2.0), (0, 0.3)],
            vec![(3, 2.0), (5, 1.0)],
            vec![(2, 1.0), (6, 1.0)],
            vec![(8, 1.0), (4, -1.0)],
        ];
        let n = 9;
        let mut j = DMat::zeros(rows.len(), n);
        for (i, r) in rows.iter().enumerate() {
            for &(c, v) in r {
                j[(i, c)] += v;
            }
        }
        let mu = 1e-3;
        let a = j.transpose() * &j + DMat::identity(n, n) * mu;
        let b = DVec::from_fn(n, |i, _| (i as f64 * 0.7).sin());
        let want = a.clone().cholesky().unwrap().solve(&b);
        let f = Factor::new(n, &rows, mu).unwrap();
        let got = f.solve(b.as_slice());
        for i in 0..n {
            assert!(
                (got[i] - want[i]).abs() < 1e-10,
                "{i}: {} vs {}",
                got[i],
                want[i]
            );
        }
        // Minimum-norm least squares: compare with the pseudo-inverse.
        let rhs = DVec::from_fn(rows.len(), |i, _| 1.0 + i as f64);
        let x = min_norm(n, &rows, rhs.as_slice(), 1e-9, 3).unwrap();
        let pinv = j.clone().pseudo_inverse(1e-12).unwrap() * &rhs;
        for i in 0..n {
            assert!(
                (x[i] - pinv[i]).abs() < 1e-6,
                "{i}: {} vs {}",
                x[i],
                pinv[i]
            );
        }
    }
}
