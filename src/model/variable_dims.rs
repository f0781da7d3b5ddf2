//! The dimension of each VARIABLE's value, for `VARVAL(id)` in the units check: inferred
//! from the VARIABLE's FUNCTION when a VARVAL first asks, wherever the VARIABLE stands in
//! the dataset (four VARVALs in ten name a VARIABLE further down the corpus's files).
//!
//! Asking parses the FUNCTION and runs the units inference on it alone (no lowering,
//! no measure slots), once per VARIABLE; a VARIABLE that reads itself through other
//! VARIABLEs is free where the loop closes, and so is a FUNCTION that does not parse or
//! calls a USER subroutine. So is a VARIABLE a PINPUT lists: a controller (Adams
//! Controls) sets its value, and its FUNCTION only stands in for runs without one.

use crate::check::units::{self, Dim};
use crate::check::Scope;
use std::cell::RefCell;
use std::collections::HashMap;

/// Where a VARIABLE's dimension stands.
#[derive(Clone, Copy)]
enum State {
    /// Being inferred: a VARVAL reached it again through a loop.
    Asked,
    /// Inferred (`None`: free).
    Known(Option<Dim>),
}

/// The FUNCTION texts of the dataset's VARIABLEs and the dimensions found so far.
#[derive(Default)]
pub struct VariableDims {
    sources: HashMap<i64, String>,
    found: RefCell<HashMap<i64, State>>,
}

impl VariableDims {
    /// Records the FUNCTION text of VARIABLE/`id`.
    pub fn add(&mut self, id: i64, function: &str) {
        self.sources.insert(id, function.to_string());
    }

    /// Makes VARIABLE/`id` free whatever its FUNCTION says (a controller's input).
    pub fn free(&mut self, id: i64) {
        self.found.get_mut().insert(id, State::Known(None));
    }

    /// The dimension of VARIABLE/`id`'s value, inferred in `scope` (the model's), or
    /// `None` when it is free or unknown.
    pub fn dim(&self, id: i64, scope: &dyn Scope) -> Option<Dim> {
        if let Some(state) = self.found.borrow().get(&id) {
            return match *state {
                State::Asked => None,
                State::Known(d) => d,
            };
        }
        let src = self.sources.get(&id)?;
        self.found.borrow_mut().insert(id, State::Asked);
        // A chain of VARIABLEs recurses once per link: grow the stack as needed.
        let d = crate::stack::guard(|| {
            units::infer_text(src, scope, scope.unit_names())
                .ok()
                .and_then(|(d, _)| d)
        });
        self.found.borrow_mut().insert(id, State::Known(d));
        d
    }
}
