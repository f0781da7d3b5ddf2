//! Incremental sparse row elimination: the rank-revealing kernel of the redundancy
//! analysis.
//!
//! Rows of the (equilibrated) constraint Jacobian arrive one at a time in priority order.
//! Each is reduced against the rows kept so far (Gaussian elimination on the rows, i.e. LU
//! of Φ_qᵀ with one pivot column chosen per kept row); what is left is its residual. A row
//! whose residual is small is dependent; otherwise the residual is kept, normalised so that
//! its pivot entry is 1. The residual is exactly `row − Σ cₖ·keptₖ` for some coefficients,
//! so its norm bounds the row's distance to the span of the kept rows: a dropped row is
//! within that distance of a combination of kept rows, and kept rows, triangular in their
//! pivot columns, are independent.
//!
//! Pivot choice is threshold pivoting with a Markowitz-style tie-break: among residual
//! entries at least [`PIVOT_THRESHOLD`] times the largest, take the column that the fewest
//! not-yet-processed rows touch, so later rows rarely need this kept row and fill stays
//! local (a mechanism's Jacobian is a union of 2-part blocks).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Pivots no smaller than this fraction of the residual's largest entry are acceptable:
/// multipliers stay below 1/threshold (UMFPACK's default threshold).
const PIVOT_THRESHOLD: f64 = 0.1;

const NONE: u32 = u32::MAX;

/// A sparse row: parallel column indices and values.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct SparseRow {
    pub cols: Vec<u32>,
    pub vals: Vec<f64>,
}

/// The Euclidean length of `vals` (0 for none).
pub(super) fn norm(vals: &[f64]) -> f64 {
    vals.iter().fold(0.0, |s, v| s + v * v).sqrt()
}

/// Rows stored one after another (compressed sparse rows).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Rows {
    /// Row r is `cols[start[r]..start[r + 1]]` (and the same range of `vals`).
    pub start: Vec<usize>,
    pub cols: Vec<u32>,
    pub vals: Vec<f64>,
}

impl Default for Rows {
    fn default() -> Self {
        Rows {
            start: vec![0],
            cols: Vec::new(),
            vals: Vec::new(),
        }
    }
}

impl Rows {
    pub fn row(&self, r: usize) -> (&[u32], &[f64]) {
        let range = self.start[r]..self.start[r + 1];
        (&self.cols[range.clone()], &self.vals[range])
    }
}

impl SparseRow {
    pub fn norm(&self) -> f64 {
        norm(&self.vals)
    }
}

/// A kept row after reduction, scaled so that its entry in `pivot` is 1 (that entry is
/// not stored).
struct KeptRow {
    pivot: u32,
    row: SparseRow,
}

/// The kept rows so far and the scratch space to reduce new ones against them.
pub(super) struct Factor {
    kept: Vec<KeptRow>,
    /// Column → index of the kept row pivoting on it, or `NONE`.
    pivot_of: Vec<u32>,
    /// Column → how many rows still to be processed touch it (the Markowitz count).
    pending: Vec<u32>,
    work: Vec<f64>,
    in_pattern: Vec<bool>,
    pattern: Vec<u32>,
    /// Kept-row index → the reduction that last queued it (avoids queueing twice).
    queued_in: Vec<u64>,
    reductions: u64,
}

impl Factor {
    /// An empty factor for rows of `ncols` columns; `pending[c]` counts the rows that will
    /// be offered and touch column `c`.
    pub fn new(ncols: usize, pending: Vec<u32>) -> Self {
        Factor {
            kept: Vec::new(),
            pivot_of: vec![NONE; ncols],
            pending,
            work: vec![0.0; ncols],
            in_pattern: vec![false; ncols],
            pattern: Vec::new(),
            queued_in: Vec::new(),
            reductions: 0,
        }
    }

    /// The number of kept rows: the rank found so far.
    pub fn len(&self) -> usize {
        self.kept.len()
    }

    /// Total stored entries of the kept rows (fill included).
    pub fn stored_entries(&self) -> usize {
        self.kept.iter().map(|k| k.row.cols.len()).sum()
    }

    /// `row` minus the combination of kept rows that zeroes it in every pivot column.
    pub fn reduce(&mut self, (cols, vals): (&[u32], &[f64])) -> SparseRow {
        self.reductions += 1;
        let stamp = self.reductions;
        self.queued_in.resize(self.kept.len(), 0);
        let mut queue = BinaryHeap::new();
        for (&c, &v) in cols.iter().zip(vals) {
            self.touch(c, &mut queue, stamp);
            self.work[c as usize] += v;
        }
        // Kept row i is zero in the pivot columns of rows before it, so eliminating in
        // increasing kept order only ever queues later rows.
        while let Some(Reverse(i)) = queue.pop() {
            let kept = &self.kept[i as usize];
            let factor = self.work[kept.pivot as usize];
            self.work[kept.pivot as usize] = 0.0;
            if factor == 0.0 {
                continue;
            }
            for k in 0..self.kept[i as usize].row.cols.len() {
                let (c, v) = {
                    let r = &self.kept[i as usize].row;
                    (r.cols[k], r.vals[k])
                };
                self.touch(c, &mut queue, stamp);
                self.work[c as usize] -= factor * v;
            }
        }
        let mut residual = SparseRow::default();
        for &c in &self.pattern {
            let v = std::mem::take(&mut self.work[c as usize]);
            self.in_pattern[c as usize] = false;
            if v != 0.0 && self.pivot_of[c as usize] == NONE {
                residual.cols.push(c);
                residual.vals.push(v);
            }
        }
        self.pattern.clear();
        residual
    }

    /// Adds column `c` to the scratch pattern, queueing the kept row that pivots on it.
    fn touch(&mut self, c: u32, queue: &mut BinaryHeap<Reverse<u32>>, stamp: u64) {
        if !self.in_pattern[c as usize] {
            self.in_pattern[c as usize] = true;
            self.pattern.push(c);
            let k = self.pivot_of[c as usize];
            if k != NONE && self.queued_in[k as usize] != stamp {
                self.queued_in[k as usize] = stamp;
                queue.push(Reverse(k));
            }
        }
    }

    /// Keeps a non-zero residual (from [`Factor::reduce`] against the current kept rows).
    pub fn keep(&mut self, mut residual: SparseRow) {
        let largest = residual.vals.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        debug_assert!(largest > 0.0, "only non-zero residuals are kept");
        let pick = (0..residual.cols.len())
            .filter(|&k| residual.vals[k].abs() >= PIVOT_THRESHOLD * largest)
            .min_by(|&a, &b| {
                let (ca, cb) = (residual.cols[a], residual.cols[b]);
                (self.pending[ca as usize].cmp(&self.pending[cb as usize]))
                    .then(residual.vals[b].abs().total_cmp(&residual.vals[a].abs()))
                    .then(ca.cmp(&cb))
            })
            .expect("a non-zero residual has an entry above the threshold");
        let pivot = residual.cols.swap_remove(pick);
        let pivot_value = residual.vals.swap_remove(pick);
        for v in &mut residual.vals {
            *v /= pivot_value;
        }
        self.pivot_of[pivot as usize] = self.kept.len() as u32;
        self.kept.push(KeptRow {
            pivot,
            row: residual,
        });
    }

    /// Forgets the rows kept after the first `len` (to try another choice).
    pub fn truncate(&mut self, len: usize) {
        for k in self.kept.drain(len..) {
            self.pivot_of[k.pivot as usize] = NONE;
        }
    }

    /// Marks a row as processed for the Markowitz counts.
    pub fn retire(&mut self, cols: &[u32]) {
        for &c in cols {
            self.pending[c as usize] = self.pending[c as usize].saturating_sub(1);
        }
    }
}
