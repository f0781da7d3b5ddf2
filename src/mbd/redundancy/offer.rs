//! Offering one element's rows to the factor: the greedy choice, or the catalogue set
//! inside the element that keeps as many rows ([`Offer`]), and which rows it kept and
//! dropped ([`Outcome`]).

use super::catalogue;
use super::factor::{Factor, Rows};
use crate::mbd::equations::EquationLabel;
use crate::vocab::elements::ElementKind;

/// Which rows of one element were kept, and the dropped ones with their residual norms.
#[derive(Debug, Default)]
pub(super) struct Outcome {
    pub(super) kept: Vec<usize>,
    pub(super) dropped: Vec<(usize, f64)>,
}

/// Offers the rows of one element to the factor.
pub(super) struct Offer<'a> {
    pub(super) rows: &'a Rows,
    pub(super) labels: &'a [EquationLabel],
    pub(super) tol: f64,
}

impl Offer<'_> {
    /// Greedy choice first; if it drops rows and what it keeps is no catalogue element,
    /// tries the catalogue sets that fit inside the element.
    pub(super) fn element(
        &self,
        factor: &mut Factor,
        kind: ElementKind,
        dim: usize,
        rows: &[usize],
    ) -> Outcome {
        let base = factor.len();
        let greedy = self.greedy(factor, rows);
        let eqs = |rs: &[usize]| {
            rs.iter()
                .map(|&r| self.labels[r].equation)
                .collect::<Vec<_>>()
        };
        let all = eqs(rows);
        let distinct = (1..all.len()).all(|i| !all[..i].contains(&all[i]));
        if greedy.dropped.is_empty()
            || greedy.kept.is_empty()
            || !catalogue::is_lowerable(kind)
            || !distinct
            || !catalogue::elements_with(dim, kind, &eqs(&greedy.kept)).is_empty()
        {
            return greedy;
        }
        for set in catalogue::candidate_sets(dim, &all, greedy.kept.len()) {
            factor.truncate(base);
            let (keep, drop): (Vec<usize>, Vec<usize>) = rows
                .iter()
                .partition(|&&r| set.contains(&self.labels[r].equation));
            if let Some(outcome) = self.exact(factor, &keep, &drop) {
                return outcome;
            }
        }
        factor.truncate(base);
        self.greedy(factor, rows)
    }

    /// Keeps each row that is independent of the rows kept before it.
    fn greedy(&self, factor: &mut Factor, rows: &[usize]) -> Outcome {
        let mut out = Outcome::default();
        for &r in rows {
            let residual = factor.reduce(self.rows.row(r));
            let norm = residual.norm();
            if norm > self.tol {
                factor.keep(residual);
                out.kept.push(r);
            } else {
                out.dropped.push((r, norm));
            }
        }
        out
    }

    /// Keeps `keep` and drops `drop`, if every kept row is independent and every dropped
    /// row then dependent.
    fn exact(&self, factor: &mut Factor, keep: &[usize], drop: &[usize]) -> Option<Outcome> {
        let mut out = Outcome::default();
        for &r in keep {
            let residual = factor.reduce(self.rows.row(r));
            if residual.norm() <= self.tol {
                return None;
            }
            factor.keep(residual);
            out.kept.push(r);
        }
        for &r in drop {
            let norm = factor.reduce(self.rows.row(r)).norm();
            if norm > self.tol {
                return None;
            }
            out.dropped.push((r, norm));
        }
        Some(out)
    }
}
