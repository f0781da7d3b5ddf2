//! `Model.linearize()`: the model linearized where a run leaves it (at its static
//! equilibrium by default), as `mbfx run --linear` does, returned as an
//! `mbfx.Linearization` with its modes, mode shapes, reduced matrices and state matrix as
//! numpy arrays.

use crate::run::run_error;
use mbfx::session::linear::LinearReport;
use mbfx::session::request::{run, RunRequest};
use mbfx::vocab::math::DMat;
use numpy::{Complex64, PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Runs `request` (which asks for a linear analysis at its end) and returns its
/// `mbfx.Linearization`; a failed run raises `RunError`.
pub fn linearize(py: Python<'_>, request: &RunRequest) -> PyResult<Py<PyAny>> {
    let result = py.detach(|| {
        let mut sink = |_: &[f64]| -> std::io::Result<()> { Ok(()) };
        run(request, &mut sink, None)
    });
    let mut done = match result {
        Ok(done) => done,
        Err(failed) => return Err(run_error(py, &failed, None)?),
    };
    let report = done
        .summary
        .linear
        .pop()
        .expect("the request asks for a linear analysis");
    object(py, &report)
}

/// An r × c matrix as a 2-D numpy array.
fn matrix<'py>(py: Python<'py>, m: &DMat) -> PyResult<Bound<'py, PyAny>> {
    let (r, c) = m.shape();
    let rows: Vec<f64> = (0..r)
        .flat_map(|i| (0..c).map(move |j| m[(i, j)]))
        .collect();
    Ok(PyArray1::from_vec(py, rows).reshape([r, c])?.into_any())
}

fn object(py: Python<'_>, r: &LinearReport) -> PyResult<Py<PyAny>> {
    let lin = &r.linearized;
    let kw = PyDict::new(py);
    kw.set_item("time", lin.time)?;
    kw.set_item(
        "coordinates",
        lin.coords
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>(),
    )?;
    let modes = &r.modes;
    let values: Vec<Complex64> = modes.iter().map(|m| m.eigenvalue).collect();
    kw.set_item("eigenvalues", PyArray1::from_vec(py, values))?;
    let column = |f: fn(&mbfx::mbd::linear::modes::Mode) -> f64| {
        PyArray1::from_vec(py, modes.iter().map(f).collect())
    };
    kw.set_item("natural_hz", column(|m| m.natural_hz))?;
    kw.set_item("damped_hz", column(|m| m.damped_hz))?;
    kw.set_item("damping_ratio", column(|m| m.damping_ratio))?;
    // Mode shapes: one column per mode over every coordinate of the model.
    let n = lin.columns.len();
    let shapes: Vec<Complex64> = (0..n)
        .flat_map(|c| {
            modes.iter().map(move |m| {
                m.shape
                    .as_ref()
                    .map_or(Complex64::new(f64::NAN, 0.0), |s| s[c])
            })
        })
        .collect();
    kw.set_item(
        "shapes",
        PyArray1::from_vec(py, shapes).reshape([n, modes.len()])?,
    )?;
    kw.set_item("columns", lin.columns.clone())?;
    let a = lin
        .state_matrix()
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    kw.set_item("A", matrix(py, &a)?)?;
    kw.set_item("states", lin.state_names())?;
    kw.set_item("M", matrix(py, &lin.mass)?)?;
    kw.set_item("C", matrix(py, &lin.damping)?)?;
    kw.set_item("K", matrix(py, &lin.stiffness)?)?;
    kw.set_item("moving", lin.moving)?;
    kw.set_item("text", r.text())?;
    Ok(py
        .import("mbfx")?
        .getattr("Linearization")?
        .call((), Some(&kw))?
        .unbind())
}
