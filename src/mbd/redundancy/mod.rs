//! Redundancy analysis of the constraint Jacobian at the assembled configuration
//! (multibody spec §5): which scalar equations depend on the others, the true degrees of
//! freedom, Adams-shaped "deactivating constraint equation" messages, the lighter JOINT or
//! JPRIM that would not over-constrain, and conflicts (a dropped equation that is violated).
//!
//! How rows are chosen. Rows are offered one element at a time: MOTION elements first, then
//! GCON, then joints and primitives, each group in element order; within an element in
//! Adams' equation order (X Delta, Y Delta, Z Delta, Zi.Xj, Zi.Yj, Xi.Yj, …). A row is
//! *redundant* when it lies in the span of the rows kept before it, so MOTION and GCON
//! equations are kept whenever possible and the loop-closing joint (the latest) loses its
//! equations. When an element has redundant rows and the rows kept by that rule do not
//! form a catalogue element, the other valid choices inside the element that do are tried
//! (each must keep as many rows, all others still dependent), so the advice can name one
//! element: a REVOLUTE closing a planar loop keeps X Delta and Y Delta, a JPRIM INLINE.
//!
//! Tolerance. Columns are first equilibrated (each divided by its largest magnitude) and
//! rows normalised to unit length, so the decisions do not change when rows or columns are
//! scaled (mm vs m models, or any length the caller divided translational rows by). A row
//! is dependent when its residual after elimination is at most [`Options::tolerance`]
//! (default 1e-8): its distance to the span of the kept rows is then at most that, relative
//! to its own length. See the `factor` module for the elimination.

mod catalogue;
mod factor;
/// Reference mechanisms for the tests (test data shared with the bench, kept out of the
/// library).
#[cfg(test)]
#[path = "../../../tests/common/redundancy_fixtures.rs"]
mod fixtures;
mod offer;
mod problem;
mod report;
#[cfg(test)]
mod tests;

pub use catalogue::{element_name, element_title, older_phrase};
pub use problem::{Options, Problem};
pub use report::{Advice, AnalysisError, Conflict, Lighter, Redundant, Report};

use crate::mbd::sparse::Triplets;
use crate::vocab::elements::ElementKind;
use factor::{Factor, Rows};
use offer::Offer;

/// Finds the rank of the constraint Jacobian, the redundant equations and the advice; an
/// error when the input is inconsistent or a redundant equation is violated (conflicting,
/// not redundant).
pub fn analyze(problem: &Problem, options: &Options) -> Result<Report, AnalysisError> {
    validate(problem)?;
    let rows = scaled_rows(problem.jacobian)?;
    let ncols = problem.jacobian.ncols;
    let mut pending = vec![0u32; ncols];
    for &c in &rows.cols {
        pending[c as usize] += 1;
    }
    let mut factor = Factor::new(ncols, pending);
    let offer = Offer {
        rows: &rows,
        labels: problem.labels,
        tol: options.tolerance,
    };
    let mut outcomes = Vec::new();
    for (element, element_rows) in element_groups(problem) {
        let kind = problem.elements[element].kind;
        let outcome = offer.element(&mut factor, kind, problem.dim, &element_rows);
        for &r in &element_rows {
            factor.retire(rows.row(r).0);
        }
        outcomes.push((element, outcome));
    }
    let report = Report::build(
        problem,
        options,
        factor.len(),
        factor.stored_entries(),
        outcomes,
    );
    let mut conflicts = match problem.residuals {
        Some(residuals) => report.conflicts(residuals, options.conflict_tolerance),
        None => Vec::new(),
    };
    if let Some(velocities) = problem.velocity_residuals {
        for c in report.conflicts(velocities, options.conflict_tolerance) {
            if conflicts.iter().all(|k| k.row != c.row) {
                conflicts.push(Conflict {
                    velocity: true,
                    ..c
                });
            }
        }
    }
    match conflicts {
        conflicts if conflicts.is_empty() => Ok(report),
        conflicts => Err(AnalysisError::Conflicting {
            report: Box::new(report),
            conflicts,
        }),
    }
}

fn validate(p: &Problem) -> Result<(), AnalysisError> {
    let shape = |what: String| Err(AnalysisError::Shape(what));
    let per_part = match p.dim {
        2 => 3,
        3 => 6,
        d => return shape(format!("dimension {d} is neither 2 nor 3")),
    };
    let j = p.jacobian;
    if j.ncols != per_part * p.moving_parts {
        return shape(format!(
            "{} columns for {} moving parts in {}D (expected {})",
            j.ncols,
            p.moving_parts,
            p.dim,
            per_part * p.moving_parts
        ));
    }
    if p.labels.len() != j.nrows {
        return shape(format!("{} labels for {} rows", p.labels.len(), j.nrows));
    }
    if let Some(l) = p.labels.iter().find(|l| l.element >= p.elements.len()) {
        return shape(format!(
            "a label names element {} of {}",
            l.element,
            p.elements.len()
        ));
    }
    if let Some(&(r, c, v)) = j
        .entries
        .iter()
        .find(|&&(r, c, v)| r as usize >= j.nrows || c as usize >= j.ncols || !v.is_finite())
    {
        return shape(format!(
            "entry ({r}, {c}) = {v} is out of range or not finite"
        ));
    }
    for res in [p.residuals, p.velocity_residuals].into_iter().flatten() {
        if res.len() != j.nrows {
            return shape(format!("{} residuals for {} rows", res.len(), j.nrows));
        }
        if let Some(i) = res.iter().position(|v| !v.is_finite()) {
            return shape(format!("residual {i} is not finite"));
        }
    }
    Ok(())
}

/// The rows of the Jacobian with duplicates summed, columns divided by their largest
/// magnitude and each row by its length (zero rows stay empty); an error if summing
/// duplicates overflows.
fn scaled_rows(j: &Triplets) -> Result<Rows, AnalysisError> {
    // Counting sort by row, then each (short) row by column.
    let mut start = vec![0usize; j.nrows + 1];
    for &(r, _, _) in &j.entries {
        start[r as usize + 1] += 1;
    }
    for r in 0..j.nrows {
        start[r + 1] += start[r];
    }
    let mut next = start.clone();
    let mut by_row = vec![(0u32, 0.0); j.entries.len()];
    for &(r, c, v) in &j.entries {
        by_row[next[r as usize]] = (c, v);
        next[r as usize] += 1;
    }
    let mut rows = Rows::default();
    let mut col_max = vec![0.0_f64; j.ncols];
    for r in 0..j.nrows {
        let row = &mut by_row[start[r]..start[r + 1]];
        row.sort_unstable_by_key(|&(c, _)| c);
        let first = rows.cols.len();
        for &(c, v) in row.iter() {
            if rows.cols.len() > first && rows.cols.last() == Some(&c) {
                *rows
                    .vals
                    .last_mut()
                    .expect("cols and vals have equal length") += v;
            } else {
                rows.cols.push(c);
                rows.vals.push(v);
            }
        }
        rows.start.push(rows.cols.len());
    }
    if rows.vals.iter().any(|v| !v.is_finite()) {
        return Err(AnalysisError::Shape(
            "repeated entries sum to an infinity".into(),
        ));
    }
    for (&c, &v) in rows.cols.iter().zip(&rows.vals) {
        col_max[c as usize] = col_max[c as usize].max(v.abs());
    }
    for (&c, v) in rows.cols.iter().zip(&mut rows.vals) {
        if *v != 0.0 {
            *v /= col_max[c as usize];
        }
    }
    for r in 0..j.nrows {
        let vals = &mut rows.vals[rows.start[r]..rows.start[r + 1]];
        let norm = factor::norm(vals);
        if norm > 0.0 {
            vals.iter_mut().for_each(|v| *v /= norm);
        }
    }
    Ok(rows)
}

/// Elements in the order their rows are offered (MOTION, GCON, then the rest, each by
/// element index), each with its rows in Adams' equation order.
fn element_groups(p: &Problem) -> Vec<(usize, Vec<usize>)> {
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut slot = vec![usize::MAX; p.elements.len()];
    for (row, label) in p.labels.iter().enumerate() {
        if slot[label.element] == usize::MAX {
            slot[label.element] = groups.len();
            groups.push((label.element, Vec::new()));
        }
        groups[slot[label.element]].1.push(row);
    }
    let class = |e: usize| match p.elements[e].kind {
        ElementKind::Motion => 0,
        ElementKind::Gcon => 1,
        _ => 2,
    };
    groups.sort_by_key(|&(e, _)| (class(e), e));
    for (_, rows) in &mut groups {
        rows.sort_by_key(|&r| (catalogue::equation_order(p.labels[r].equation), r));
    }
    groups
}
