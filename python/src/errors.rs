//! The module's exceptions and what they carry: `CheckError` with its diagnostics,
//! `RunError` with the failure and the run up to it, `InternalError` for a Rust panic
//! (never a crash of the interpreter), and the `Diagnostic` object each list holds.

use mbfx::diag::{render, Diagnostic as Diag, Severity, SourceFile};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyOverflowError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use std::panic::{catch_unwind, AssertUnwindSafe};

create_exception!(
    mbfx,
    MbfxError,
    PyException,
    "Base class of every error mbfx raises."
);
create_exception!(
    mbfx,
    CheckError,
    MbfxError,
    "An expression or dataset has errors: `.diagnostics` lists them (code, message, span, line, column); `str()` is the rendered text with carets."
);
create_exception!(
    mbfx,
    RunError,
    MbfxError,
    "A run failed: `.time`, `.element` and `.cause` say where and why, `.code` is the diagnostic code, and `.run` holds the rows computed before the failure."
);
create_exception!(
    mbfx,
    InternalError,
    MbfxError,
    "A bug in mbfx (a panic inside Rust), reported instead of crashing the interpreter."
);

/// One diagnostic: a stable code, a message and where it points.
#[pyclass(frozen, module = "mbfx", name = "Diagnostic")]
pub struct PyDiagnostic {
    /// The stable code, e.g. `E0201`.
    #[pyo3(get)]
    code: String,
    /// `"error"` or `"warning"`.
    #[pyo3(get)]
    severity: &'static str,
    /// What is wrong.
    #[pyo3(get)]
    message: String,
    /// The byte range `(start, end)` of the text it points at.
    #[pyo3(get)]
    span: (usize, usize),
    /// 1-based line of the span's start.
    #[pyo3(get)]
    line: usize,
    /// 1-based column (in bytes) of the span's start.
    #[pyo3(get)]
    column: usize,
    /// The name of the text it points into (`expression`, a file, `probe NAME`).
    #[pyo3(get)]
    source: String,
    /// What to do about it, when known.
    #[pyo3(get)]
    help: Option<String>,
    /// The rendered text: `file:line:column`, the line and a caret under the span.
    #[pyo3(get)]
    text: String,
}

#[pymethods]
impl PyDiagnostic {
    fn __str__(&self) -> String {
        self.text.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Diagnostic({} {} at {}:{}: {})",
            self.severity, self.code, self.line, self.column, self.message
        )
    }

    /// Pickled as its fields: a diagnostic (and the `CheckError` holding it) crosses a
    /// process boundary intact.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let rebuild = py.import("mbfx._mbfx")?.getattr("_rebuild_diagnostic")?;
        let fields = (
            &self.code,
            self.severity,
            &self.message,
            self.span,
            self.line,
            self.column,
            &self.source,
            &self.help,
            &self.text,
        );
        Ok((rebuild, fields.into_pyobject(py)?))
    }
}

/// Unpickles a diagnostic (see `Diagnostic.__reduce__`).
#[pyfunction]
#[allow(clippy::too_many_arguments)] // one per field of the pickled diagnostic
pub fn _rebuild_diagnostic(
    code: String,
    severity: &str,
    message: String,
    span: (usize, usize),
    line: usize,
    column: usize,
    source: String,
    help: Option<String>,
    text: String,
) -> PyDiagnostic {
    PyDiagnostic {
        code,
        severity: if severity == "error" {
            "error"
        } else {
            "warning"
        },
        message,
        span,
        line,
        column,
        source,
        help,
        text,
    }
}

impl PyDiagnostic {
    /// The Python view of `d`, a diagnostic about `file`.
    pub fn new(d: &Diag, file: &SourceFile) -> PyDiagnostic {
        let (line, column) = file.line_col(d.span.start);
        PyDiagnostic {
            code: d.code.as_str().to_string(),
            severity: match d.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
            },
            message: d.message.clone(),
            span: (d.span.start, d.span.end),
            line,
            column,
            source: file.name.clone(),
            help: d.help.clone(),
            text: render(std::slice::from_ref(d), file, false),
        }
    }
}

/// A list of Python diagnostics about `file`.
pub fn diagnostic_list<'py>(
    py: Python<'py>,
    diags: &[Diag],
    file: &SourceFile,
) -> PyResult<Bound<'py, PyList>> {
    let items = diags
        .iter()
        .map(|d| Py::new(py, PyDiagnostic::new(d, file)))
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, items)
}

/// A `CheckError` for `diags` about `file`: its message is the rendered text.
pub fn check_error(py: Python<'_>, diags: &[Diag], file: &SourceFile) -> PyErr {
    let text = render(diags, file, false);
    let err = CheckError::new_err(text.trim_end().to_string());
    let attached = diagnostic_list(py, diags, file)
        .and_then(|list| err.value(py).setattr("diagnostics", list));
    match attached {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// A `CheckError` with one message and no place in a text (a bad argument that is
/// about the call, not about the expression).
pub fn plain_check_error(py: Python<'_>, message: String) -> PyErr {
    let err = CheckError::new_err(message);
    match err.value(py).setattr("diagnostics", PyList::empty(py)) {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// The Python integer `value` (an int, or anything with `__index__`) as a `T`; one out
/// of `T`'s range (negative, or past it) is a `ValueError` naming the argument `what`,
/// not the `OverflowError` a narrow Rust parameter type raises (found by
/// tests/python/test_fuzz_models.py).
pub fn int_in_range<T: TryFrom<i64>>(value: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    let out_of_range = || PyValueError::new_err(format!("{what} = {value} is out of range"));
    match value.extract::<i64>() {
        Ok(v) => T::try_from(v).map_err(|_| out_of_range()),
        Err(e) if e.is_instance_of::<PyOverflowError>(value.py()) => Err(out_of_range()),
        Err(e) => Err(e),
    }
}

/// Runs `f`, turning a Rust panic into `InternalError`.
pub fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let why = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Err(InternalError::new_err(format!(
                "internal error in mbfx (please report it): {why}"
            )))
        }
    }
}
