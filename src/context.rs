//! The evaluation context: everything a compiled expression may read at run time.
//!
//! One `#[repr(C)]` struct serves the interpreter and machine code alike: the time, the
//! analysis mode, and borrowed arrays of user variables, measure values (filled by the
//! multibody core) and SPLINE data. A compiled expression reads only the slots its
//! [`crate::ir::Uses`] lists.

use mbfx_runtime::Spline;
use std::marker::PhantomData;

/// Inputs of one evaluation. Built from slices, so the pointers inside are valid for `'a`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Context<'a> {
    /// `TIME`: the simulation time.
    pub time: f64,
    /// `MODE`: the analysis mode (4 for dynamics).
    pub mode: f64,
    vars: *const f64,
    n_vars: usize,
    measures: *const f64,
    n_measures: usize,
    splines: *const Spline,
    n_splines: usize,
    _borrow: PhantomData<&'a [f64]>,
}

const EMPTY: &[f64] = &[];

impl<'a> Context<'a> {
    /// A context at `time` with user variables `vars` (slot order), mode 4 (dynamics).
    pub const fn new(time: f64, vars: &'a [f64]) -> Self {
        Context {
            time,
            mode: 4.0,
            vars: vars.as_ptr(),
            n_vars: vars.len(),
            measures: EMPTY.as_ptr(),
            n_measures: 0,
            splines: std::ptr::NonNull::<Spline>::dangling().as_ptr(),
            n_splines: 0,
            _borrow: PhantomData,
        }
    }

    /// The same context with `MODE` set to `mode`.
    pub fn with_mode(mut self, mode: f64) -> Self {
        self.mode = mode;
        self
    }

    /// The same context reading measure slots from `measures`.
    pub fn with_measures(mut self, measures: &'a [f64]) -> Self {
        self.measures = measures.as_ptr();
        self.n_measures = measures.len();
        self
    }

    /// The same context reading SPLINE data from `splines`.
    pub fn with_splines(mut self, splines: &'a [Spline]) -> Self {
        self.splines = splines.as_ptr();
        self.n_splines = splines.len();
        self
    }

    /// True when the variable, measure and spline arrays hold at least `needs[0..3]`
    /// entries (what a compiled expression reads, from [`crate::ir::Uses`]).
    pub fn covers(&self, needs: [usize; 3]) -> bool {
        self.n_vars >= needs[0] && self.n_measures >= needs[1] && self.n_splines >= needs[2]
    }

    /// The variable and measure arrays' addresses, which compiled code takes as arguments.
    pub(crate) fn arrays(&self) -> (*const f64, *const f64) {
        (self.vars, self.measures)
    }

    /// The user variables, in slot order.
    pub fn vars(&self) -> &'a [f64] {
        // SAFETY: `vars`/`n_vars` come from a `&'a [f64]` given to `new`.
        unsafe { std::slice::from_raw_parts(self.vars, self.n_vars) }
    }

    /// The measure values, in slot order.
    pub fn measures(&self) -> &'a [f64] {
        // SAFETY: `measures`/`n_measures` come from a `&'a [f64]` (or the empty slice).
        unsafe { std::slice::from_raw_parts(self.measures, self.n_measures) }
    }

    /// The SPLINE data, in spline-index order.
    pub fn splines(&self) -> &'a [Spline] {
        // SAFETY: `splines`/`n_splines` come from a `&'a [Spline]`, or are a dangling,
        // well-aligned pointer with length 0, which `from_raw_parts` permits.
        unsafe { std::slice::from_raw_parts(self.splines, self.n_splines) }
    }
}

/// Byte offsets of the fields machine code reads (the struct is `#[repr(C)]`).
pub(crate) mod layout {
    use super::Context;
    use std::mem::offset_of;

    pub const MODE: i32 = offset_of!(Context<'static>, mode) as i32;
    pub const SPLINES: i32 = offset_of!(Context<'static>, splines) as i32;
}
