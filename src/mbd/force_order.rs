//! The order in which force elements are evaluated when their expressions read other
//! forces (`SFORCE(2, …)`, `FX(i, j)`): each element after the ones it reads, so one
//! pass gives every value at the same state. Forces that read each other in a circle
//! have no such order; the error names the circle.

use super::error::MbdError;
use super::forces::ForceSet;
use super::output_slot::OutputSlot;

/// The elements of `set` it reads the force of, for element `k` (after
/// [`ForceSet::reads`] is filled).
fn depends_on(set: &ForceSet, k: usize) -> Vec<usize> {
    let mut out = Vec::new();
    for &s in &set.reads[k] {
        match set.solution[s] {
            OutputSlot::ElementForce {
                constraint: false,
                element,
                ..
            } => out.push(element),
            OutputSlot::MarkerForce { i, j, .. } => {
                // Every force element acting between i and j, either way round
                // (as `Dynamics::marker_load` sums them).
                out.extend(set.elements.iter().enumerate().filter_map(|(e, el)| {
                    let between = (el.i == i && el.j == j) || (el.j == Some(i) && j == Some(el.i));
                    between.then_some(e)
                }));
            }
            _ => {}
        }
    }
    out
}

/// A topological order of the elements by what they read; a circle is an error naming
/// its elements in reading order.
pub fn order(set: &ForceSet) -> Result<Vec<usize>, MbdError> {
    let n = set.elements.len();
    let deps: Vec<Vec<usize>> = (0..n).map(|k| depends_on(set, k)).collect();
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    let mut mark = vec![Mark::New; n];
    let mut order = Vec::with_capacity(n);
    // Iterative depth-first search: (element, next dependency to visit).
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for root in 0..n {
        if mark[root] != Mark::New {
            continue;
        }
        mark[root] = Mark::Open;
        stack.push((root, 0));
        while let Some(&mut (k, ref mut next)) = stack.last_mut() {
            if let Some(&d) = deps[k].get(*next) {
                *next += 1;
                match mark[d] {
                    Mark::Done => {}
                    Mark::New => {
                        mark[d] = Mark::Open;
                        stack.push((d, 0));
                    }
                    Mark::Open => {
                        // The stack from d up to k reads in a circle back to d.
                        let from = stack.iter().position(|&(e, _)| e == d).unwrap_or(0);
                        let circle = stack[from..]
                            .iter()
                            .map(|&(e, _)| set.elements[e].elref.clone())
                            .collect();
                        return Err(MbdError::ForceCycle(circle));
                    }
                }
            } else {
                mark[k] = Mark::Done;
                order.push(k);
                stack.pop();
            }
        }
    }
    Ok(order)
}
