//! `Model.linearize()`: the model linearized where a run leaves it (at its static
//! equilibrium by default), as `mbfx run --linear` does, returned as an
//! `mbfx.Linearization` with its modes, mode shapes, reduced matrices and state matrix as
//! numpy arrays.

use crate::run::run_error;
use mbfx::session::linearization::{Linearization, Matrix};
use mbfx::session::request::{run, RunRequest};
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
    object(py, Linearization::from(&report))
}

/// A row-major matrix as a 2-D numpy array.
fn matrix(py: Python<'_>, m: Matrix) -> PyResult<Bound<'_, PyAny>> {
    Ok(PyArray1::from_vec(py, m.data)
        .reshape([m.rows, m.cols])?
        .into_any())
}

/// (re, im) pairs as complex numbers.
fn complex(pairs: &[(f64, f64)]) -> Vec<Complex64> {
    pairs
        .iter()
        .map(|&(re, im)| Complex64::new(re, im))
        .collect()
}

fn object(py: Python<'_>, lin: Linearization) -> PyResult<Py<PyAny>> {
    let kw = PyDict::new(py);
    kw.set_item("time", lin.time)?;
    kw.set_item("coordinates", lin.coordinates)?;
    let modes = lin.eigenvalues.len();
    kw.set_item(
        "eigenvalues",
        PyArray1::from_vec(py, complex(&lin.eigenvalues)),
    )?;
    kw.set_item("natural_hz", PyArray1::from_vec(py, lin.natural_hz))?;
    kw.set_item("damped_hz", PyArray1::from_vec(py, lin.damped_hz))?;
    kw.set_item("damping_ratio", PyArray1::from_vec(py, lin.damping_ratio))?;
    // Mode shapes: one column per mode over every coordinate of the model.
    let n = lin.columns.len();
    kw.set_item(
        "shapes",
        PyArray1::from_vec(py, complex(&lin.shapes)).reshape([n, modes])?,
    )?;
    kw.set_item("columns", lin.columns)?;
    let a = lin
        .state_matrix
        .map_err(pyo3::exceptions::PyValueError::new_err)?;
    kw.set_item("A", matrix(py, a)?)?;
    kw.set_item("states", lin.states)?;
    kw.set_item("M", matrix(py, lin.mass)?)?;
    kw.set_item("C", matrix(py, lin.damping)?)?;
    kw.set_item("K", matrix(py, lin.stiffness)?)?;
    kw.set_item("moving", lin.moving)?;
    kw.set_item("text", lin.text)?;
    Ok(py
        .import("mbfx")?
        .getattr("Linearization")?
        .call((), Some(&kw))?
        .unbind())
}
