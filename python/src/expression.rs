//! `mbfx.compile` and `Expression`: an expression over named variables, called with
//! scalars (a float back) or numpy arrays (an ndarray back, broadcast as numpy does),
//! its gradient, and the raw entry of its machine code for scipy and ctypes.
//!
//! Values go positionally in the order of `variables` or by keyword; `time=` gives TIME
//! (0 when absent). Evaluation over arrays releases the GIL.

use crate::arrays::{Inputs, Point};
use crate::errors::{check_error, guarded, plain_check_error};
use mbfx::diag::SourceFile;
use mbfx::session::expression::{dims_of, ExprError, Expression, ENTRY_SIGNATURE};
use mbfx::session::run::Engine;
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::collections::BTreeMap;

/// The engine named by `name`.
pub fn engine_of(name: &str) -> PyResult<Engine> {
    match name.to_ascii_lowercase().as_str() {
        "jit" => Ok(Engine::Jit),
        "interp" | "interpreter" => Ok(Engine::Interp),
        _ => Err(PyValueError::new_err(format!(
            "engine must be \"jit\" or \"interp\", not {name:?}"
        ))),
    }
}

/// The name of `engine`, as `compile` takes it.
pub fn engine_name(engine: Engine) -> &'static str {
    match engine {
        Engine::Jit => "jit",
        Engine::Interp => "interp",
    }
}

/// `e` as a Python exception: text errors as `CheckError` with diagnostics about the
/// expression, argument errors as `CheckError` without a place, or `ValueError`.
pub fn expr_error(py: Python<'_>, text: &str, e: ExprError) -> PyErr {
    match e {
        ExprError::Diagnostics(d) => check_error(py, &d, &SourceFile::new("expression", text)),
        ExprError::Arity { .. } | ExprError::Length { .. } => PyValueError::new_err(e.to_string()),
        ExprError::Jit(_) => crate::errors::InternalError::new_err(e.to_string()),
        other => plain_check_error(py, other.to_string()),
    }
}

/// A compiled expression. Call it with values for its variables (positionally, in the
/// order of `variables`, or by keyword) and optionally `time=`: scalars give a float,
/// arrays an ndarray broadcast as numpy broadcasts. A vector expression or a gradient
/// gives its values along a last axis.
#[pyclass(frozen, module = "mbfx", name = "Expression")]
pub struct PyExpression {
    pub inner: Expression,
    /// `threads=` of `compile`: None is every core.
    pub threads: Option<usize>,
}

#[pymethods]
impl PyExpression {
    // `(*args, **kwargs)` and nothing else: pyo3 then hands over Python's own tuple and
    // dict (with a named `time=` it copied every other keyword into a new dict, which
    // cost a keyword call as much again as the call itself). TIME is a keyword like the
    // variables, any case.
    #[pyo3(signature = (*args, **kwargs))]
    // No `py` parameter either: pyo3 counts it among the arguments, and passes through
    // only a signature of exactly `*args, **kwargs`.
    fn __call__<'py>(
        &self,
        args: &Bound<'py, PyTuple>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = args.py();
        guarded(|| {
            let e = &self.inner;
            // The common small call: floats only, positional or by keyword.
            if let Some(point) = Point::scalars(e.variables(), args, kwargs)? {
                let value = if e.outputs() == 1 {
                    let v = e
                        .eval_scalar(point.values(), point.time)
                        .map_err(|x| expr_error(py, e.text(), x))?;
                    return Ok(v.into_pyobject(py)?.into_any());
                } else {
                    e.eval(point.values(), point.time)
                        .map_err(|x| expr_error(py, e.text(), x))?
                };
                return Ok(PyArray1::from_vec(py, value).into_any());
            }
            let (slots, time) = bind_arguments(e, args, kwargs)?;
            let inputs = Inputs::gather(py, &slots, time.as_ref())?;
            inputs.evaluate(py, e, crate::arrays::thread_count(self.threads))
        })
    }

    /// The value and its partial derivatives with respect to `wrt` (names of
    /// variables, or `"TIME"`; all variables when omitted), as a new expression whose
    /// outputs are the value, then each partial.
    #[pyo3(signature = (wrt = None))]
    fn gradient(&self, py: Python<'_>, wrt: Option<Vec<String>>) -> PyResult<PyExpression> {
        guarded(|| {
            let e = &self.inner;
            let wrt = wrt.unwrap_or_else(|| e.variables().to_vec());
            let names: Vec<&str> = wrt.iter().map(String::as_str).collect();
            let g = py
                .detach(|| e.gradient(&names))
                .map_err(|x| expr_error(py, e.text(), x))?;
            Ok(PyExpression {
                inner: g,
                threads: self.threads,
            })
        })
    }

    /// The expression's text.
    #[getter]
    fn text(&self) -> &str {
        self.inner.text()
    }

    /// The variables, in the order positional values take.
    #[getter]
    fn variables<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.inner.variables())
    }

    /// The threads a call over big arrays uses (`threads=` of `compile`; None: every
    /// core). Arrays of fewer than 131 072 points run on the calling thread.
    #[getter]
    fn threads(&self) -> Option<usize> {
        self.threads
    }

    /// `"jit"` or `"interp"`.
    #[getter]
    fn engine(&self) -> &'static str {
        engine_name(self.inner.engine())
    }

    /// Values per point: 1 for a scalar, 3 for a vector; a gradient adds each
    /// output's partials.
    #[getter]
    fn outputs(&self) -> usize {
        self.inner.outputs()
    }

    /// For a gradient, the names of its partials, in order (empty otherwise).
    #[getter]
    fn wrt<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.inner.wrt())
    }

    /// The dimension of each variable given one (`units=` of `compile`), as
    /// {name: dimension}; empty when none was given.
    #[getter]
    fn units<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, unit) in self.inner.unit_texts() {
            d.set_item(name, unit)?;
        }
        Ok(d)
    }

    /// The expression's dimension ("a velocity (length/time)") when variables were given
    /// dimensions and the units check fixed one; None when it is free or was not checked.
    #[getter]
    fn dimension(&self) -> Option<String> {
        self.inner.dim_name()
    }

    /// The checker's warnings about the text.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        let file = SourceFile::new("expression", self.inner.text());
        crate::errors::diagnostic_list(py, self.inner.warnings(), &file)
    }

    /// The address of the machine code's C entry, an int (see `signature`). It stays
    /// valid while this expression lives. The interpreter has none (ValueError).
    #[getter]
    fn address(&self) -> PyResult<usize> {
        match self.inner.entry() {
            Some(f) => Ok(f as usize),
            None => Err(PyValueError::new_err(
                "an expression compiled with engine=\"interp\" has no machine code",
            )),
        }
    }

    /// The C signature of `address`: `double (int n, double *x, void *out)`. `x` holds
    /// the variables in order, then TIME when n exceeds their count; `out` receives
    /// every output when there are several (NULL otherwise); the result is the first.
    /// It is the signature `scipy.LowLevelCallable` takes for `quad`.
    #[getter]
    fn signature(&self) -> &'static str {
        ENTRY_SIGNATURE
    }

    fn __repr__(&self) -> String {
        let e = &self.inner;
        let wrt = if e.wrt().is_empty() {
            String::new()
        } else {
            format!(", wrt={:?}", e.wrt())
        };
        format!(
            "mbfx.Expression({:?}, variables={:?}, engine={:?}{wrt})",
            e.text(),
            e.variables(),
            engine_name(e.engine())
        )
    }

    /// Pickled as its text, variables, engine and gradient names: rebuilt by compiling.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let e = &self.inner;
        let rebuild = py.import("mbfx._mbfx")?.getattr("_rebuild_expression")?;
        let args = (
            e.text(),
            PyTuple::new(py, e.variables())?,
            engine_name(e.engine()),
            PyTuple::new(py, e.wrt())?,
            self.inner.unit_texts(),
            self.threads,
        )
            .into_pyobject(py)?;
        Ok((rebuild, args))
    }
}

/// The argument bound to each variable: positional ones first, then keywords by name
/// (case-insensitive, as the language's names are); and TIME when a keyword spelt
/// `TIME` (any case) gave it.
#[allow(clippy::type_complexity)] // the slots and TIME, each as Python gave them
fn bind_arguments<'py>(
    e: &Expression,
    args: &Bound<'py, PyTuple>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Vec<Bound<'py, PyAny>>, Option<Bound<'py, PyAny>>)> {
    let names = e.variables();
    if args.len() > names.len() {
        return Err(PyTypeError::new_err(format!(
            "the expression takes {} values ({}), {} were given",
            names.len(),
            names.join(", "),
            args.len()
        )));
    }
    let mut slots: Vec<Option<Bound<'py, PyAny>>> = vec![None; names.len()];
    let mut time = None;
    for (slot, a) in slots.iter_mut().zip(args.iter()) {
        *slot = Some(a);
    }
    if let Some(kw) = kwargs {
        for (key, value) in kw.iter() {
            let key: String = key.extract()?;
            let found = names.iter().position(|n| n.eq_ignore_ascii_case(&key));
            if found.is_none() && key.eq_ignore_ascii_case("time") {
                if time.is_some() {
                    return Err(PyTypeError::new_err("`time` is given twice"));
                }
                // `time=None` is TIME left out (0).
                time = Some(value).filter(|v| !v.is_none());
                continue;
            }
            let k = found.ok_or_else(|| {
                PyTypeError::new_err(format!(
                    "`{key}` is not a variable of the expression (its variables: {})",
                    names.join(", ")
                ))
            })?;
            if slots[k].replace(value).is_some() {
                return Err(PyTypeError::new_err(format!(
                    "`{}` is given twice",
                    names[k]
                )));
            }
        }
    }
    let slots = slots
        .into_iter()
        .zip(names)
        .map(|(s, n)| s.ok_or_else(|| PyTypeError::new_err(format!("no value for `{n}`"))))
        .collect::<PyResult<_>>()?;
    Ok((slots, time))
}

/// `mbfx.compile(text, variables=(), engine="jit", units=None, threads=None)`.
#[pyfunction]
#[pyo3(signature = (text, variables = None, engine = "jit", units = None, threads = None))]
pub fn compile(
    py: Python<'_>,
    text: &str,
    variables: Option<Vec<String>>,
    engine: &str,
    units: Option<BTreeMap<String, String>>,
    threads: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyExpression> {
    guarded(|| {
        let threads = threads
            .filter(|t| !t.is_none())
            .map(|t| crate::errors::int_in_range::<usize>(t, "threads"))
            .transpose()?;
        if threads == Some(0) {
            return Err(PyValueError::new_err(
                "threads must be at least 1, or None for every core",
            ));
        }
        let engine = engine_of(engine)?;
        let variables = variables.unwrap_or_default();
        let names: Vec<&str> = variables.iter().map(String::as_str).collect();
        let units: Vec<(String, String)> = units.unwrap_or_default().into_iter().collect();
        let dims = dims_of(&units)
            .map_err(|(name, why)| PyValueError::new_err(format!("units[{name:?}]: {why}")))?;
        let inner = py
            .detach(|| Expression::compile_with_dims(text, &names, &dims, engine))
            .map_err(|x| expr_error(py, text, x))?;
        Ok(PyExpression { inner, threads })
    })
}

/// Unpickles an expression (see `Expression.__reduce__`).
#[pyfunction]
#[pyo3(signature = (text, variables, engine, wrt, units, threads = None))]
pub fn _rebuild_expression(
    py: Python<'_>,
    text: &str,
    variables: Vec<String>,
    engine: &str,
    wrt: Vec<String>,
    units: Vec<(String, String)>,
    threads: Option<usize>,
) -> PyResult<PyExpression> {
    let threads = threads.into_pyobject(py)?;
    let e = compile(
        py,
        text,
        Some(variables),
        engine,
        Some(units.into_iter().collect()),
        Some(&threads),
    )?;
    if wrt.is_empty() {
        return Ok(e);
    }
    e.gradient(py, Some(wrt))
}
