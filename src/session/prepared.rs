//! Compile once, run many: the simulation of the last run on this thread, kept for the
//! next run of the same request. A run whose dataset text and options are the same, and
//! whose settings only give design variables numbers (`VARIABLE/ID.FUNCTION=NUMBER`), runs
//! the kept simulation again ([`Simulation::rewind`]): nothing is read, checked, built
//! or compiled, and the rows are the bits a fresh build would give.
//!
//! A simulation holds JIT code and interior buffers that stay on the thread that built
//! it, so each thread keeps its own, a few at a time (the Python module runs a caller's
//! runs on one pooled thread; a study's worker process runs its variants one by one).

use super::request::{Input, RunRequest};
use super::run::Simulation;
use std::cell::RefCell;

/// How many simulations a thread keeps (the most recently run first): a few models run in
/// turn, such as a study's model and its reference, each keep theirs.
const KEEP: usize = 4;

thread_local! {
    static KEPT: RefCell<Vec<(RunRequest, Simulation)>> = const { RefCell::new(Vec::new()) };
}

/// What must match for a kept simulation to serve `request` on the dataset `text`
/// (named `name`): the request with the text as its input and no settings.
pub fn key(request: &RunRequest, name: &str, text: &str) -> RunRequest {
    RunRequest {
        input: Input::Dataset {
            name: name.to_string(),
            text: text.to_string(),
        },
        set: Vec::new(),
        // What a run records for its animation does not change the simulation.
        animation: None,
        ..request.clone()
    }
}

/// The simulation kept for `key`, taken (the next run keeps it again).
pub fn take(key: &RunRequest) -> Option<Simulation> {
    KEPT.with(|k| {
        let mut kept = k.borrow_mut();
        let at = kept.iter().position(|(held, _)| held == key)?;
        Some(kept.remove(at).1)
    })
}

/// Keeps `sim` for the next run of `key` on this thread, first, dropping the least
/// recently run one beyond the few a thread keeps.
pub fn keep(key: RunRequest, sim: Simulation) {
    KEPT.with(|k| {
        let mut kept = k.borrow_mut();
        kept.retain(|(held, _)| *held != key);
        kept.insert(0, (key, sim));
        kept.truncate(KEEP);
    });
}

/// Drops the kept simulations (their JIT code and buffers).
pub fn forget() {
    KEPT.with(|k| k.borrow_mut().clear());
}
