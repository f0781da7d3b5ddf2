//! Polynomial and harmonic series of spec §5.6–5.10: POLY, CHEBY, FORCOS, FORSIN
//! (variadic, 1 to 31 coefficients), SHF and SWEEP.
//!
//! The variadic functions take their coefficients as a slice; an empty slice or more
//! than [`MAX_COEFFS`] coefficients gives NaN. Their derivative companions write
//! ∂/∂a_j into a caller-provided slice (no allocation) and return the value and the
//! partials with respect to the scalar arguments.

pub mod harmonic;
pub mod polynomial;

pub use harmonic::*;
pub use polynomial::*;

/// Largest number of coefficients of POLY, CHEBY, FORCOS and FORSIN (a0 … a30).
pub const MAX_COEFFS: usize = 31;

/// True when `coeffs` has 1 ..= [`MAX_COEFFS`] elements.
#[inline]
fn count_valid(coeffs: &[f64]) -> bool {
    !coeffs.is_empty() && coeffs.len() <= MAX_COEFFS
}

/// Validates a gradient call: the coefficient count, room in `d_coeffs`, and the scalar
/// arguments that every term uses. On failure fills `d_coeffs` with NaN and returns
/// false.
#[inline]
fn grad_args_valid(coeffs: &[f64], d_coeffs: &mut [f64], scalars_nan: bool) -> bool {
    if count_valid(coeffs) && d_coeffs.len() >= coeffs.len() && !scalars_nan {
        true
    } else {
        d_coeffs.fill(f64::NAN);
        false
    }
}
