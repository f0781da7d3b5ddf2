//! A linear analysis' results as plain numbers, for the shells (Python's
//! `Linearization`): matrices row-major, complex numbers as (re, im) pairs, names as
//! text. [`super::linear`] computes them.

use super::linear::LinearReport;
use crate::vocab::math::DMat;

/// A matrix, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix {
    /// Its rows.
    pub rows: usize,
    /// Its columns.
    pub cols: usize,
    /// `rows · cols` numbers, row after row.
    pub data: Vec<f64>,
}

impl From<&DMat> for Matrix {
    fn from(m: &DMat) -> Matrix {
        let (rows, cols) = m.shape();
        let data = (0..rows)
            .flat_map(|i| (0..cols).map(move |j| m[(i, j)]))
            .collect();
        Matrix { rows, cols, data }
    }
}

/// One linear analysis: the operating point, the modes and the reduced matrices.
#[derive(Clone, Debug)]
pub struct Linearization {
    /// Simulation time of the operating point.
    pub time: f64,
    /// The minimal coordinates' names, in order.
    pub coordinates: Vec<String>,
    /// Each mode's eigenvalue (re, im), by rising frequency.
    pub eigenvalues: Vec<(f64, f64)>,
    /// Each mode's natural frequency, Hz.
    pub natural_hz: Vec<f64>,
    /// Each mode's damped frequency, Hz.
    pub damped_hz: Vec<f64>,
    /// Each mode's damping ratio.
    pub damping_ratio: Vec<f64>,
    /// Mode shapes (re, im): one row per column of the model's velocity layout, one
    /// column per mode, row-major; NaN where a mode has no shape.
    pub shapes: Vec<(f64, f64)>,
    /// The names of the model's velocity columns (the shapes' rows).
    pub columns: Vec<String>,
    /// The state matrix, or why it could not be formed.
    pub state_matrix: Result<Matrix, String>,
    /// The states' names (each minimal coordinate, then each one's rate).
    pub states: Vec<String>,
    /// The reduced mass matrix M̃.
    pub mass: Matrix,
    /// The reduced damping matrix C̃.
    pub damping: Matrix,
    /// The reduced stiffness matrix K̃.
    pub stiffness: Matrix,
    /// The operating point moves (the inertial partials are left out).
    pub moving: bool,
    /// The table `mbfx run --linear` prints.
    pub text: String,
}

impl From<&LinearReport> for Linearization {
    fn from(r: &LinearReport) -> Linearization {
        let lin = &r.linearized;
        let modes = &r.modes;
        let column = |f: fn(&crate::mbd::linear::modes::Mode) -> f64| modes.iter().map(f).collect();
        let n = lin.columns.len();
        let shapes = (0..n)
            .flat_map(|c| {
                modes.iter().map(move |m| {
                    m.shape
                        .as_ref()
                        .map_or((f64::NAN, 0.0), |s| (s[c].re, s[c].im))
                })
            })
            .collect();
        Linearization {
            time: lin.time,
            coordinates: lin.coords.iter().map(|c| c.name.clone()).collect(),
            eigenvalues: modes
                .iter()
                .map(|m| (m.eigenvalue.re, m.eigenvalue.im))
                .collect(),
            natural_hz: column(|m| m.natural_hz),
            damped_hz: column(|m| m.damped_hz),
            damping_ratio: column(|m| m.damping_ratio),
            shapes,
            columns: lin.columns.clone(),
            state_matrix: lin
                .state_matrix()
                .map(|a| Matrix::from(&a))
                .map_err(|e| e.to_string()),
            states: lin.state_names(),
            mass: Matrix::from(&lin.mass),
            damping: Matrix::from(&lin.damping),
            stiffness: Matrix::from(&lin.stiffness),
            moving: lin.moving,
            text: r.text(),
        }
    }
}
