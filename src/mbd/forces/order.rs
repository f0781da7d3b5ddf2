//! The order in which force elements are evaluated when their expressions read other
//! forces (`SFORCE(2, …)`, `FX(i, j)`): each element after the ones it reads, so one
//! pass gives every value at the same state. This is a topological sort over plain data,
//! what each element reads; forces that read each other in a circle have no such order,
//! and the error is the circle.

/// A topological order of the nodes `0..deps.len()`, each after the nodes `deps[k]` it
/// reads; a circle is an error holding its nodes in reading order.
pub fn order(deps: &[Vec<usize>]) -> Result<Vec<usize>, Vec<usize>> {
    let n = deps.len();
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
                        return Err(stack[from..].iter().map(|&(e, _)| e).collect());
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
