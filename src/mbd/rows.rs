//! The constraint elements a [`System`](super::system::System) holds, as data: each
//! element as the user named it ([`Element`]), its equations ([`Equ`]) and how each row
//! is computed ([`Row`]), and the rows' expressions fused into one call ([`FusedRows`]).
//! Building and evaluating them is the job of [`constraints`](super::constraints) and
//! [`fused_rows`](super::fused_rows); the data sits here, below them, because the system
//! owns it.

use super::equations::Equation;
use super::expr::{ExprFn, FusedFn};
use super::handles::MarkerHandle;
use crate::vocab::elements::ElementRef;
use crate::vocab::math::Vec3;
use std::cell::{Cell, RefCell};

/// How one scalar equation is computed.
pub enum Row {
    /// (r_I − r_J)·(R_J dir) · sign.
    Along {
        /// The I marker.
        i: MarkerHandle,
        /// The J marker.
        j: MarkerHandle,
        /// The direction, J-marker axes.
        dir: Vec3,
        /// ±1.
        sign: f64,
    },
    /// (R_I a)·(R_J b).
    Dot {
        /// The I marker.
        i: MarkerHandle,
        /// The J marker.
        j: MarkerHandle,
        /// The I vector, I-marker axes.
        a: Vec3,
        /// The J vector, J-marker axes.
        b: Vec3,
    },
    /// Σ cₖ·measureₖ − g(t) (g = 0 when there is no drive).
    Measured {
        /// (cₖ, measure index) pairs.
        terms: Vec<(f64, usize)>,
        /// g(t): a MOTION's function.
        drive: Option<Box<dyn ExprFn>>,
    },
    /// f(t, measures): `map[k]` is the measure index of the k-th slot f reads.
    Gcon {
        /// The GCON's compiled expression.
        f: Box<dyn ExprFn>,
        /// Measure index of each slot f reads.
        map: Vec<usize>,
    },
}

/// One equation of an element.
pub struct Equ {
    /// How the row is computed.
    pub row: Row,
    /// Its Adams label (`X Delta`, `Zi.Xj`, ...).
    pub label: Equation,
    /// Length-valued (scaled by the model length in the scaled Jacobian).
    pub translational: bool,
    /// False when the 2D build drops it as identically satisfied out of plane.
    pub active: bool,
}

/// A constraint element as the user named it, with its equations.
pub struct Element {
    /// The element as the user named it.
    pub elref: ElementRef,
    /// Its equations, in Adams label order.
    pub eqs: Vec<Equ>,
}

impl Equ {
    /// An active equation (for elements built with
    /// [`System::add_element`](crate::mbd::System::add_element)).
    pub fn new(row: Row, label: Equation, translational: bool) -> Equ {
        Equ {
            row,
            label,
            translational,
            active: true,
        }
    }
}

/// The fused row expressions and their outputs at the last evaluation. Its fields are
/// open to `mbd` because [`fused_rows`](super::fused_rows) builds and reads them.
pub struct FusedRows {
    pub(super) values: Box<dyn FusedFn>,
    pub(super) partials: Option<Box<dyn FusedFn>>,
    /// The (slot, measure) pairs read.
    pub(super) slots: Vec<(u32, usize)>,
    /// Per element (None: not a fused GCON): its value's output and where its value and
    /// partials start.
    pub(super) at: Vec<Option<(usize, usize)>>,
    pub(super) out_values: RefCell<Vec<f64>>,
    pub(super) out_partials: RefCell<Vec<f64>>,
    /// The outputs are the current state's (Some(true): with the partials).
    pub(super) current: Cell<Option<bool>>,
}

/// What a fused row reads from the fused evaluation: f, and with the partials
/// ∂f/∂slot (into `grad`) and ∂f/∂t.
pub struct FusedRow {
    /// f.
    pub value: f64,
    /// ∂f/∂t (NaN when only values were computed).
    pub dt: f64,
}
