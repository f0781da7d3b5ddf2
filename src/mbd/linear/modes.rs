//! The modes of a linearized model (Adams' LINEAR/EIGENSOL): the eigenvalues λ of the
//! state matrix A ([`super::Linearized::state_matrix`]), found by faer's real
//! eigendecomposition (Hessenberg QR), each with its natural frequency |λ|/2π, damped
//! frequency Im λ/2π and damping ratio −Re λ/|λ|, and its mode shape: the eigenvector's
//! coordinate part z carried to every coordinate of the model by T·z, scaled so that
//! the minimal coordinate that moves most (translations over the model length; a
//! joint's own coordinate where the joints span the motion) moves by 1.
//!
//! Complex eigenvalues come in conjugate pairs; each pair is one mode (the one with
//! Im λ > 0). A real eigenvalue (an overdamped direction, a neutral one at 0, an unstable
//! one above 0) is a mode of its own. Modes are numbered by rising |λ|.

use super::Linearized;
use crate::mbd::dynamics::DynError;
use num_complex::Complex64;
use std::f64::consts::PI;

/// One mode.
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// 1, 2, … by rising |λ|.
    pub number: usize,
    /// λ (Im λ ≥ 0).
    pub eigenvalue: Complex64,
    /// |λ|/2π, Hz.
    pub natural_hz: f64,
    /// Im λ/2π, Hz.
    pub damped_hz: f64,
    /// −Re λ/|λ| (0 for λ = 0).
    pub damping_ratio: f64,
    /// The displacement of every coordinate of the model (velocity layout), the one that
    /// moves most at 1 (None: the mode shapes were not asked for).
    pub shape: Option<Vec<Complex64>>,
    /// The displacement of each minimal coordinate, in the order of
    /// [`super::Linearized::coords`], scaled as `shape` (None: not asked for).
    pub coordinates: Option<Vec<Complex64>>,
    /// The minimal coordinate that moves most (a joint's own where the joints span the
    /// motion), named; a state element's state for a mode of the states alone.
    pub dominant: String,
}

/// The modes of `lin`; `shapes` false leaves the shapes out (Adams' NOVECTOR; the
/// dominant coordinate is still named).
pub fn modes(lin: &Linearized, shapes: bool) -> Result<Vec<Mode>, DynError> {
    let f = lin.freedom();
    if f == 0 {
        return Ok(Vec::new());
    }
    let a = lin.state_matrix()?;
    // 2f, and one more per state element's state.
    let size = a.nrows();
    let fa = faer::Mat::<f64>::from_fn(size, size, |i, j| a[(i, j)]);
    let eig = fa.eigen().map_err(|_| DynError::Structure)?;
    let (values, vectors) = (eig.S().column_vector(), eig.U());
    let mut order: Vec<usize> = (0..size).filter(|&k| values[k].im >= 0.0).collect();
    order.sort_by(|&x, &y| {
        let (p, q) = (values[x], values[y]);
        p.norm().total_cmp(&q.norm()).then(p.im.total_cmp(&q.im))
    });
    let n = lin.basis.nrows();
    Ok(order
        .iter()
        .enumerate()
        .map(|(k, &e)| {
            let lambda = values[e];
            let r = lambda.norm();
            // δq = T·z: the coordinate half of the eigenvector carried to every column.
            let dq: Vec<Complex64> = (0..n)
                .map(|c| (0..f).map(|j| vectors[(j, e)] * lin.basis[(c, j)]).sum())
                .collect();
            // The minimal coordinate that moves most (scaled: translations over the
            // model length) names the mode and moves by 1; a mode without any (a state
            // element's own) is named by its largest state.
            let z: Vec<Complex64> = (0..f).map(|j| vectors[(j, e)]).collect();
            let coords = &lin.coords;
            let largest = |x: &[Complex64], scale: &dyn Fn(usize) -> f64| {
                (0..x.len())
                    .max_by(|&a, &b| (x[a].norm() / scale(a)).total_cmp(&(x[b].norm() / scale(b))))
            };
            let top = largest(&z, &|j| coords[j].scale).filter(|&j| z[j].norm() > 0.0);
            let (pivot, dominant) = match top {
                Some(j) => (z[j], coords[j].name.clone()),
                None => {
                    let x: Vec<Complex64> = (2 * f..size).map(|k| vectors[(k, e)]).collect();
                    let k = largest(&x, &|_| 1.0).unwrap_or(0);
                    let name = lin.states.names.get(k).cloned().unwrap_or_default();
                    (
                        x.get(k)
                            .copied()
                            .filter(|p| p.norm() > 0.0)
                            .unwrap_or(Complex64::ONE),
                        name,
                    )
                }
            };
            Mode {
                number: k + 1,
                eigenvalue: lambda,
                natural_hz: r / (2.0 * PI),
                damped_hz: lambda.im / (2.0 * PI),
                // (+ 0.0: an undamped mode's −0 prints as 0.)
                damping_ratio: if r > 0.0 { -lambda.re / r + 0.0 } else { 0.0 },
                shape: shapes.then(|| dq.iter().map(|x| x / pivot).collect()),
                coordinates: shapes.then(|| z.iter().map(|x| x / pivot).collect()),
                dominant,
            }
        })
        .collect())
}
