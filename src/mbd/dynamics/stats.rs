//! The counters of a run ([`Stats`]): steps, rejections, Newton iterations,
//! factorizations, evaluations and the error the steps made, one struct every integrator
//! fills so charts and summaries read one thing.

/// Counters of a run: what the work-precision charts plot against accuracy.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts.
    pub rejected: usize,
    /// Corrector (Newton) iterations, all attempts.
    pub newton_iterations: usize,
    /// Evaluations of a Newton or saddle-point matrix.
    pub jacobian_evaluations: usize,
    /// Sparse LU factorizations of the Newton matrix.
    pub factorizations: usize,
    /// Evaluations of compiled expressions (force magnitudes, GCON and MOTION
    /// functions), values and gradients alike.
    pub expression_evaluations: usize,
    /// Force-law switches (contact on or off, clamp on or off) located by the step
    /// control ([`super::events`]).
    pub events: usize,
    /// The size of the last accepted step, and the integrator's order on it (the step
    /// table of `mbfx run --verbose`).
    pub last_step: f64,
    /// The order used on the last accepted step (None for a fixed-order method).
    pub order: Option<u32>,
    /// Accepted steps at each order 1…6 of a variable-order method (index k − 1).
    pub steps_at_order: [usize; 6],
    /// The largest local error estimate of an accepted step, in units of ERROR: at most
    /// 1 under error control; with fixed steps, how far the run strayed from ERROR.
    pub worst_error: f64,
    /// When that step ended.
    pub worst_error_time: f64,
    /// The accepted steps' local error estimates added up, in units of ERROR: about
    /// what the answer's error can reach when the dynamics neither damp nor amplify
    /// errors (at most 1 when ERROR is per run).
    pub error_sum: f64,
    /// The largest estimate of the global error of an accepted state, in units of ERROR
    /// (positions, each column over its ERROR: the model length's for translations),
    /// when the integrator carried one through every step (`Integrator::global_error`).
    pub global_error: Option<f64>,
    /// When that state was reached.
    pub global_error_time: f64,
    /// Output rows made from a continuous extension inside a step (INTERPOLATE = ON).
    pub interpolated: usize,
    /// The largest scaled residual of the position constraints at those rows, before
    /// any projection: how far the extension strays from the constraints.
    pub interpolation_residual: f64,
    /// Those of them projected back onto the constraints (their residual exceeded the
    /// run's drift tolerance).
    pub projected: usize,
}
