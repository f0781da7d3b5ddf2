//! The constraint Jacobian Φ_q of the kept rows in row-block form: one dense block of a
//! part's columns (3 in 2D, 6 in 3D) per (row, part) pair the row reads. The pairs are
//! fixed when the dynamics is set up, so an evaluation writes values in place, and
//! Φ_qᵀ·λ, Φ_q·x and the Schur complement read contiguous blocks instead of triplets.

use crate::vocab::math::DVec;
use std::ops::Range;

/// Φ_q over fixed (row, part) blocks. A non-holonomic row holds ∂f/∂v.
#[derive(Clone, Debug)]
pub struct Jacobian {
    /// Columns per part.
    pub bs: usize,
    /// Row r's slots are `row_start[r]..row_start[r + 1]`.
    row_start: Vec<usize>,
    slot_part: Vec<usize>,
    slot_row: Vec<usize>,
    /// `bs` values per slot.
    vals: Vec<f64>,
}

impl Jacobian {
    /// Blocks of `bs` columns for rows reading the parts `row_parts[r]` (velocity-layout
    /// part indices, each listed once).
    pub fn new(bs: usize, row_parts: &[Vec<usize>]) -> Jacobian {
        let (mut row_start, mut slot_part, mut slot_row) = (vec![0], Vec::new(), Vec::new());
        for (r, ps) in row_parts.iter().enumerate() {
            for &p in ps {
                slot_part.push(p);
                slot_row.push(r);
            }
            row_start.push(slot_part.len());
        }
        let vals = vec![0.0; slot_part.len() * bs];
        Jacobian {
            bs,
            row_start,
            slot_part,
            slot_row,
            vals,
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.row_start.len() - 1
    }

    /// Number of (row, part) blocks.
    pub fn slots(&self) -> usize {
        self.slot_part.len()
    }

    /// The slots of each of `parts` parts.
    pub fn part_slots(&self, parts: usize) -> Vec<Vec<usize>> {
        let mut out = vec![Vec::new(); parts];
        for (k, &p) in self.slot_part.iter().enumerate() {
            out[p].push(k);
        }
        out
    }

    /// The slots of row `r`.
    pub fn row_slots(&self, r: usize) -> Range<usize> {
        self.row_start[r]..self.row_start[r + 1]
    }

    /// The part (velocity-layout index) of slot `k`.
    pub fn slot_part(&self, k: usize) -> usize {
        self.slot_part[k]
    }

    /// The row of slot `k`.
    pub fn slot_row(&self, k: usize) -> usize {
        self.slot_row[k]
    }

    /// Copies the values of `other`, a Jacobian of the same structure.
    pub fn copy_values_from(&mut self, other: &Jacobian) {
        self.vals.copy_from_slice(&other.vals);
    }

    /// The values of slot `k` over its part's columns.
    pub fn block(&self, k: usize) -> &[f64] {
        &self.vals[k * self.bs..(k + 1) * self.bs]
    }

    /// Zeroes row `r`.
    pub fn clear_row(&mut self, r: usize) {
        let s = self.row_slots(r);
        self.vals[s.start * self.bs..s.end * self.bs].fill(0.0);
    }

    /// The slot of row `r` over part `part`, if the row reads it.
    pub fn slot_of(&self, r: usize, part: usize) -> Option<usize> {
        self.row_slots(r).find(|&k| self.slot_part[k] == part)
    }

    /// The values of slot `k`, to write.
    pub fn block_at_mut(&mut self, k: usize) -> &mut [f64] {
        &mut self.vals[k * self.bs..(k + 1) * self.bs]
    }

    /// The six-column blocks of two distinct slots, to write (None for a slot that is
    /// None); `bs` must be 6.
    pub fn six_blocks_mut(
        &mut self,
        a: Option<usize>,
        b: Option<usize>,
    ) -> (Option<&mut [f64; 6]>, Option<&mut [f64; 6]>) {
        debug_assert!(self.bs == 6 && (a != b || a.is_none()));
        match (a, b) {
            (Some(a), Some(b)) => {
                let (lo, hi) = (a.min(b), a.max(b));
                let (head, tail) = self.vals.split_at_mut(hi * 6);
                let (l, h) = (block(&mut head[lo * 6..lo * 6 + 6]), block(&mut tail[..6]));
                if a < b {
                    (Some(l), Some(h))
                } else {
                    (Some(h), Some(l))
                }
            }
            (Some(a), None) => (Some(block(&mut self.vals[a * 6..a * 6 + 6])), None),
            (None, Some(b)) => (None, Some(block(&mut self.vals[b * 6..b * 6 + 6]))),
            (None, None) => (None, None),
        }
    }

    /// The block of row `r` over part `part`, if the row reads it.
    pub fn block_mut(&mut self, r: usize, part: usize) -> Option<&mut [f64]> {
        let k = self.slot_of(r, part)?;
        Some(self.block_at_mut(k))
    }

    /// Adds `x` at (row `r`, velocity-layout column `col`). False when the row was not
    /// set up to read that column's part.
    pub fn add(&mut self, r: usize, col: usize, x: f64) -> bool {
        let bs = self.bs;
        match self.block_mut(r, col / bs) {
            Some(b) => {
                b[col % bs] += x;
                true
            }
            None => false,
        }
    }

    /// Every stored value as (row, column, value), structural zeros included.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        let bs = self.bs;
        (0..self.slots()).flat_map(move |k| {
            let (r, c0) = (self.slot_row[k], self.slot_part[k] * bs);
            self.block(k)
                .iter()
                .enumerate()
                .map(move |(c, &x)| (r, c0 + c, x))
        })
    }

    /// w·Φ_qᵀ·λ added to `out`.
    pub fn add_transpose_times(&self, lambda: &[f64], w: f64, out: &mut DVec) {
        match self.bs {
            3 => self.transpose_times::<3>(lambda, w, out.as_mut_slice()),
            _ => self.transpose_times::<6>(lambda, w, out.as_mut_slice()),
        }
    }

    fn transpose_times<const BS: usize>(&self, lambda: &[f64], w: f64, out: &mut [f64]) {
        for ((g, &r), &p) in self
            .vals
            .chunks_exact(BS)
            .zip(&self.slot_row)
            .zip(&self.slot_part)
        {
            let y = w * lambda[r];
            // fixed-size blocks: the compiler unrolls the product without bounds checks
            let o: &mut [f64; BS] = (&mut out[p * BS..(p + 1) * BS])
                .try_into()
                .expect("BS columns");
            let g: &[f64; BS] = g.try_into().expect("BS values");
            for k in 0..BS {
                o[k] += y * g[k];
            }
        }
    }

    /// Φ_q·x (x in the velocity layout) added to `out` (one value per row).
    pub fn add_times(&self, x: &[f64], out: &mut [f64]) {
        match self.bs {
            3 => self.times::<3>(x, out),
            _ => self.times::<6>(x, out),
        }
    }

    fn times<const BS: usize>(&self, x: &[f64], out: &mut [f64]) {
        for ((g, &r), &p) in self
            .vals
            .chunks_exact(BS)
            .zip(&self.slot_row)
            .zip(&self.slot_part)
        {
            let z: &[f64; BS] = x[p * BS..(p + 1) * BS].try_into().expect("BS columns");
            let g: &[f64; BS] = g.try_into().expect("BS values");
            // summed from −0.0 in order, as `Iterator::sum` does
            let mut dot = -0.0;
            for k in 0..BS {
                dot += g[k] * z[k];
            }
            out[r] += dot;
        }
    }

    /// The largest magnitude of all entries.
    pub fn amax(&self) -> f64 {
        self.vals.iter().fold(0.0f64, |m, x| m.max(x.abs()))
    }

    /// Whether some entry of row `r` exceeds `floor` in magnitude (NaN does not): the
    /// vanished-row check, which stops at the first entry of a live row.
    pub fn row_exceeds(&self, r: usize, floor: f64) -> bool {
        let s = self.row_slots(r);
        self.vals[s.start * self.bs..s.end * self.bs]
            .iter()
            .any(|x| x.abs() > floor)
    }
}

/// A slot's six values as an array.
fn block(v: &mut [f64]) -> &mut [f64; 6] {
    v.try_into().expect("six columns")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_hold_what_was_added_and_products_read_them() {
        // Two rows over 2 parts of 3 columns: row 0 reads parts 0 and 1, row 1 part 1.
        let mut j = Jacobian::new(3, &[vec![0, 1], vec![1]]);
        assert!(j.add(0, 1, 2.0) && j.add(0, 5, -1.0) && j.add(1, 3, 4.0));
        assert!(!j.add(1, 0, 1.0), "row 1 does not read part 0");
        let x = [1.0, 10.0, 100.0, 1000.0, 1e4, 1e5];
        // Φ_q·x by hand: row 0 = 2·10 − 1·1e5, row 1 = 4·1000.
        let mut jx = [0.0, 0.0];
        j.add_times(&x, &mut jx);
        assert_eq!(jx, [20.0 - 1e5, 4000.0]);
        let mut out = DVec::zeros(6);
        j.add_transpose_times(&[1.0, 0.5], 2.0, &mut out);
        assert_eq!(out.as_slice(), &[0.0, 4.0, 0.0, 4.0, 0.0, -2.0]);
        let nz: Vec<_> = j.entries().filter(|e| e.2 != 0.0).collect();
        assert_eq!(nz, vec![(0, 1, 2.0), (0, 5, -1.0), (1, 3, 4.0)]);
        j.clear_row(0);
        assert_eq!(j.amax(), 4.0);
        assert!(!j.row_exceeds(0, 0.0) && j.row_exceeds(1, 3.9) && !j.row_exceeds(1, 4.0));
    }
}
