//! `mbfx_error`: why a compilation or a gradient failed, as C reads it: a status, the
//! stable diagnostic code (`E0201`), a one-line message and the rendered report (line,
//! column, caret), all owned by the error and freed with it.

use crate::{args, Status};
use mbfx::diag::{render, SourceFile};
use mbfx::session::expression::ExprError;
use std::ffi::{c_char, CString};

/// Why a call failed (`mbfx_error` in C): made by `mbfx_compile` and `mbfx_expr_gradient`,
/// owned by the caller, freed with `mbfx_error_free`. Read it with the `mbfx_error_*`
/// accessors; the strings they return belong to the error and live as long as it does.
pub struct Error {
    status: Status,
    code: CString,
    message: CString,
    report: CString,
    position: Option<(usize, usize)>,
}

/// `s` as a C string (a NUL inside, which C could not show, becomes `?`).
pub(crate) fn c_string(s: impl Into<String>) -> CString {
    let s = s.into().replace('\0', "?");
    CString::new(s).unwrap_or_default()
}

impl Error {
    /// An error the C API itself found (a NULL, a length): it has no diagnostic code.
    pub(crate) fn new(status: Status, message: impl Into<String>) -> Self {
        let message = message.into();
        Error {
            status,
            code: CString::default(),
            report: c_string(format!("Error: {message}\n")),
            message: c_string(message),
            position: None,
        }
    }

    /// An error with a diagnostic code: `message` in one line, `report` as rendered,
    /// `position` the first error's line and column in the text it is about.
    pub(crate) fn with_code(
        status: Status,
        code: &str,
        message: impl Into<String>,
        report: impl Into<String>,
        position: Option<(usize, usize)>,
    ) -> Self {
        Error {
            status,
            code: c_string(code),
            message: c_string(message),
            report: c_string(report),
            position,
        }
    }

    /// The error mbfx reported about `text`.
    pub(crate) fn from_expr(e: &ExprError, text: &str) -> Self {
        let status = match e {
            ExprError::Diagnostics(_) => Status::CompileError,
            ExprError::BadVariable { .. } | ExprError::UnknownVariable(_) => Status::BadVariable,
            ExprError::Deriv(_) => Status::NotDifferentiable,
            ExprError::Arity { .. } | ExprError::Length { .. } => Status::BadLength,
            ExprError::Jit(_) => Status::Internal,
        };
        let code = e.code().as_str();
        let message = e.to_string();
        let diags = e.diagnostics();
        let (report, position) = if diags.is_empty() {
            (format!("[{code}] Error: {message}\n"), None)
        } else {
            let file = SourceFile::new("expression", text);
            let first = diags.iter().find(|d| d.is_error()).unwrap_or(&diags[0]);
            (
                render(diags, &file, false),
                Some(file.line_col(first.span.start)),
            )
        };
        Error::with_code(status, code, message, report, position)
    }

    /// What kind of failure it is.
    pub(crate) fn status(&self) -> Status {
        self.status
    }
}

/// Stores `result` for C: returns the object (NULL on failure) and, when `error` is not
/// NULL, stores NULL (success) or a new error there.
///
/// # Safety
/// `error` is NULL or points to writable storage for one pointer.
pub(crate) unsafe fn hand_over<T>(result: Result<T, Error>, error: *mut *mut Error) -> *mut T {
    let (object, err) = match result {
        Ok(object) => (Box::into_raw(Box::new(object)), std::ptr::null_mut()),
        Err(e) => (std::ptr::null_mut(), Box::into_raw(Box::new(e))),
    };
    if error.is_null() {
        if !err.is_null() {
            // SAFETY: `err` came from Box::into_raw just above and was handed to no one.
            drop(unsafe { Box::from_raw(err) });
        }
    } else {
        // SAFETY: writable storage for one pointer (the caller's word).
        unsafe { error.write_unaligned(err) };
    }
    object
}

/// The status of `error` (`MBFX_STATUS_NULL_ARGUMENT` for a NULL error).
///
/// # Safety
/// `error` is NULL or an error from this library that has not been freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_error_status(error: *const Error) -> Status {
    // SAFETY: the caller's word, as this function's.
    match unsafe { args::object(error, "the error") } {
        Ok(e) => e.status,
        Err(e) => e.status(),
    }
}

/// The stable diagnostic code, e.g. `"E0201"` for an unexpected token; `""` when the
/// failure is not one mbfx reports with a code (a NULL argument, text that is not UTF-8,
/// an internal error). NULL for a NULL error. Owned by the error.
///
/// # Safety
/// `error` is NULL or an error from this library that has not been freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_error_code(error: *const Error) -> *const c_char {
    // SAFETY: the caller's word, as this function's.
    unsafe { args::object(error, "the error") }.map_or(std::ptr::null(), |e| e.code.as_ptr())
}

/// One line saying what is wrong (the first error's message, lower case, no code). NULL
/// for a NULL error. Owned by the error.
///
/// # Safety
/// `error` is NULL or an error from this library that has not been freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_error_message(error: *const Error) -> *const c_char {
    // SAFETY: the caller's word, as this function's.
    unsafe { args::object(error, "the error") }.map_or(std::ptr::null(), |e| e.message.as_ptr())
}

/// The full report, as the mbfx command prints it: for errors in the text, every
/// diagnostic as `[E0201] Error: message`, then `expression:LINE:COLUMN` and the line
/// with a caret under the place; otherwise one `Error: message` line. Ends with a line
/// break. NULL for a NULL error. Owned by the error.
///
/// # Safety
/// `error` is NULL or an error from this library that has not been freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_error_report(error: *const Error) -> *const c_char {
    // SAFETY: the caller's word, as this function's.
    unsafe { args::object(error, "the error") }.map_or(std::ptr::null(), |e| e.report.as_ptr())
}

/// Where the first error in the text is: stores its 1-based line and column (in bytes)
/// in `line` and `column` (either may be NULL) and returns true; returns false (storing
/// nothing) for an error that is not about a place in the text, or a NULL error.
///
/// # Safety
/// `error` is NULL or an error from this library that has not been freed; `line` and
/// `column` are NULL or point to writable `size_t`s.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_error_position(
    error: *const Error,
    line: *mut usize,
    column: *mut usize,
) -> bool {
    // SAFETY: the caller's word, as this function's.
    let Some((l, c)) = unsafe { args::object(error, "the error") }
        .ok()
        .and_then(|e| e.position)
    else {
        return false;
    };
    if !line.is_null() {
        // SAFETY: writable (the caller's word), non-NULL (checked).
        unsafe { line.write_unaligned(l) };
    }
    if !column.is_null() {
        // SAFETY: as for `line`.
        unsafe { column.write_unaligned(c) };
    }
    true
}

/// Frees an error from `mbfx_compile` or `mbfx_expr_gradient`; NULL is accepted (nothing
/// happens). The strings read from it die with it.
///
/// # Safety
/// `error` is NULL or an error from this library that has not been freed; it is not used
/// after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_error_free(error: *mut Error) {
    if error.is_null() {
        return;
    }
    // SAFETY: an error from Box::into_raw in `hand_over`, freed once (the caller's word).
    let error = unsafe { Box::from_raw(error) };
    let _ = args::catch(move || {
        drop(error);
        Ok(())
    });
}
