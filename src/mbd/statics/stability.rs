//! Whether a static equilibrium holds: the stiffness K = −∂Q/∂q + ∂(Φ_qᵀλ)/∂q reduced
//! to the directions the constraints leave free, Nᵀ·K·N with N an orthonormal basis of
//! the Jacobian's null space (scaled coordinates: translations over the model length),
//! must be positive definite. Its symmetric part's lowest eigenvalue decides: below
//! −[`TOL`] of the scale, the equilibrium is unstable along its eigenvector; within
//! [`TOL`], neutral (a mechanism no spring or force holds there). The scale is the
//! largest eigenvalue, or the applied and constraint forces times the model length when
//! that is larger, and never below [`FLOOR`] times the largest mass entry (so a model
//! with no stiffness at all is neutral whatever rounding leaves in it). The direction
//! is named by [`crate::mbd::freedom`].

use super::tangent;
use crate::mbd::dynamics::{DynError, Dynamics, Mat3Block};
use crate::mbd::freedom::{column_scale, describe, null_space, Freedom};
use crate::vocab::math::{DMat, DVec};

/// Eigenvalues within this fraction of the scale count as zero.
pub const TOL: f64 = 1e-10;

/// Eigenvalues below this many times the largest mass entry (per s²) count as zero.
pub const FLOOR: f64 = 1e-9;

/// A direction along which the equilibrium does not hold.
#[derive(Clone, Debug)]
pub struct Mode {
    /// No stiffness (rather than negative stiffness).
    pub neutral: bool,
    /// The direction, named.
    pub freedom: Freedom,
}

/// The verdict on an equilibrium.
#[derive(Clone, Debug)]
pub enum Verdict {
    /// Positive definite reduced stiffness (or nothing free).
    Stable,
    /// A neutral or unstable direction.
    Fails(Mode),
}

/// The verdict and how soft the softest free direction is.
#[derive(Clone, Debug)]
pub struct Check {
    /// Stable, or the direction that is not.
    pub verdict: Verdict,
    /// The lowest eigenvalue of the reduced stiffness over the largest in magnitude
    /// (None: nothing is free).
    pub softest: Option<f64>,
}

/// The verdict at the state of the last evaluations of `d` (constraints and forces with
/// their Jacobians, multipliers in `d.lambda`).
pub fn check(d: &Dynamics) -> Result<Check, DynError> {
    let n = d.n;
    let basis = null_space(d);
    if basis.ncols() == 0 {
        return Ok(Check {
            verdict: Verdict::Stable,
            softest: None,
        });
    }
    let mut k = DMat::zeros(n, n);
    for &(r, c, x) in &d.gen.dq {
        k[(r, c)] -= x;
    }
    tangent::add_constraint_tangent(d, d.lambda.as_slice(), &mut k);
    let scale: Vec<f64> = (0..n).map(|c| column_scale(d, c)).collect();
    for r in 0..n {
        for c in 0..n {
            k[(r, c)] *= scale[r] * scale[c];
        }
    }
    let reduced = basis.transpose() * &k * &basis;
    let sym = (&reduced + reduced.transpose()) * 0.5;
    let eig = sym.symmetric_eigen();
    let (low, at) =
        eig.eigenvalues
            .iter()
            .enumerate()
            .fold(
                (f64::INFINITY, 0),
                |(m, i), (j, &x)| if x < m { (x, j) } else { (m, i) },
            );
    let top = eig.eigenvalues.amax();
    let mut constraint = DVec::zeros(n);
    d.jac
        .add_transpose_times(d.lambda.as_slice(), 1.0, &mut constraint);
    let forces = d.gen.q.amax().max(constraint.amax()) * d.sys.length;
    // Below a stiffness of 1e-9 mass units per s² (a frequency under 5e-6 Hz) a
    // direction counts as held by nothing, whatever rounding left in it.
    let floor = FLOOR * mass_scale(d);
    let zero = (TOL * top.max(forces)).max(floor);
    let fails = low <= zero;
    let softest = Some(if top > 0.0 { low / top } else { 0.0 });
    if !fails {
        return Ok(Check {
            verdict: Verdict::Stable,
            softest,
        });
    }
    let direction: DVec = &basis * eig.eigenvectors.column(at);
    Ok(Check {
        verdict: Verdict::Fails(Mode {
            neutral: low.abs() <= zero,
            freedom: describe(d, &direction),
        }),
        softest,
    })
}

/// The largest mass-matrix entry in scaled coordinates (m·L², J), model units.
fn mass_scale(d: &Dynamics) -> f64 {
    let l2 = d.sys.length * d.sys.length;
    d.mass_blocks()
        .iter()
        .map(|b| match *b {
            Mat3Block::Three(m, j) => (m * l2).max(j.amax()),
            Mat3Block::Two(m, j) => (m * l2).max(j),
        })
        .fold(0.0, f64::max)
}

/// The neutral or unstable direction at the current state of `d`, if any (constraints
/// and forces evaluated afresh).
pub fn softest(d: &mut Dynamics) -> Result<Option<Mode>, DynError> {
    d.eval_constraints(true)?;
    d.eval_forces(true)?;
    Ok(match check(d)?.verdict {
        Verdict::Stable => None,
        Verdict::Fails(mode) => Some(mode),
    })
}
