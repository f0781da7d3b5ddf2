//! What every C entry point stands on: the [`Handle`] an `fmi2Component` points to (the
//! instance with its name and the importer's logger), [`call`], which checks the handle,
//! runs the body under `catch_unwind` and turns a refusal or a panic into `fmi2Error`
//! with a logged message, and the checked views of the importer's arrays.

use crate::instance::{Instance, Phase};
use crate::types::{Component, ComponentEnvironment, Logger, Status};
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The importer's logger and the environment pointer it takes back.
#[derive(Clone, Copy)]
pub struct Sink {
    /// The logger (None: nothing is logged).
    pub logger: Option<Logger>,
    /// The importer's `componentEnvironment`.
    pub environment: ComponentEnvironment,
}

/// What an `fmi2Component` points to.
pub struct Handle {
    /// The instance name (`fmi2Instantiate`'s), for the logger.
    pub name: CString,
    /// Where messages go.
    pub sink: Sink,
    /// Debug logging (`fmi2SetDebugLogging`): the categories on; errors are always logged.
    pub debug: Option<Vec<String>>,
    /// The instance.
    pub instance: Instance,
}

impl Handle {
    /// Logs `message` under `category` with `status`, through the importer's logger.
    /// Errors and warnings always go out; other messages only with debug logging on
    /// for their category.
    pub fn log(&self, status: Status, category: &str, message: &str) {
        let wanted = match (&self.debug, status) {
            (_, Status::Error | Status::Fatal | Status::Warning) => true,
            (None, _) => false,
            (Some(on), _) => on.is_empty() || on.iter().any(|c| c == category || c == "logAll"),
        };
        if wanted {
            self.sink.log(&self.name, status, category, message);
        }
    }
}

impl Sink {
    /// Calls the logger (when there is one) with `message` as its format, each `%` in
    /// it doubled: the standard makes the message a printf format, and importers that
    /// print it as it comes (FMPy) or format it (the reference importers) both show the
    /// text. Passing `"%s"` and the text would be exact for the second kind only.
    pub fn log(&self, name: &CStr, status: Status, category: &str, message: &str) {
        let Some(logger) = self.logger else {
            return;
        };
        let category = text(category);
        let message = text(&message.replace('%', "%%"));
        // SAFETY: the importer gave `logger` as an fmi2CallbackLogger, with the
        // environment it takes back; every string is a NUL-terminated CString alive for
        // the call, and the format has no conversion (every `%` doubled), so it reads no
        // variadic argument.
        unsafe {
            logger(
                self.environment,
                name.as_ptr(),
                status,
                category.as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

/// `s` as a C string, a NUL inside it made a space.
pub fn text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

/// Runs `body` on the instance `c` points to, as the entry point `call`: `fmi2OK`, or
/// `fmi2Error` with the reason logged. A NULL `c` is `fmi2Error` (no logger to tell);
/// a panic puts the instance in error.
///
/// # Safety
/// A non-NULL `c` is a pointer `fmi2Instantiate` returned and `fmi2FreeInstance` has not
/// freed, used by one thread at a time (the standard's rule).
pub unsafe fn call(
    c: Component,
    call: &str,
    body: impl FnOnce(&mut Handle) -> Result<Status, String>,
) -> Status {
    if c.is_null() {
        return Status::Error;
    }
    // SAFETY: a live Handle from fmi2Instantiate, used by this thread alone (the caller's
    // word, above).
    let handle = unsafe { &mut *c.cast::<Handle>() };
    let outcome = catch_unwind(AssertUnwindSafe(|| body(&mut *handle)));
    match outcome {
        Ok(Ok(status)) => {
            handle.log(Status::Ok, "logAll", &format!("{call}: done"));
            status
        }
        Ok(Err(message)) => {
            handle.log(
                Status::Error,
                "logStatusError",
                &format!("{call}: {message}"),
            );
            Status::Error
        }
        Err(payload) => {
            handle.instance.phase = Phase::Error;
            let what = panic_text(&*payload);
            handle.log(
                Status::Error,
                "logStatusError",
                &format!("{call}: internal error in mbfx (please report it): {what}"),
            );
            Status::Error
        }
    }
}

/// The message of a panic's payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(ToString::to_string)
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}

/// `ptr[..n]`, or an error naming `what` when `ptr` is NULL with `n` > 0.
///
/// # Safety
/// A non-NULL `ptr` points to `n` initialised values nothing writes during the call.
pub unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(format!("{what} is NULL or misaligned"));
    }
    if n > isize::MAX as usize / size_of::<T>().max(1) {
        return Err(format!("{what} has length {n}, too long for memory"));
    }
    // SAFETY: non-NULL, aligned, a length that fits (checked); n values (the caller's word).
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// `ptr[..n]` to write, or an error naming `what` when `ptr` is NULL with `n` > 0.
///
/// # Safety
/// A non-NULL `ptr` points to `n` writable values nothing else uses during the call.
pub unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(format!("{what} is NULL or misaligned"));
    }
    if n > isize::MAX as usize / size_of::<T>().max(1) {
        return Err(format!("{what} has length {n}, too long for memory"));
    }
    // SAFETY: non-NULL, aligned, a length that fits (checked); n writable values used by
    // nothing else (the caller's word).
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// The text of a C string argument, or an error naming `what` when it is NULL or not
/// UTF-8.
///
/// # Safety
/// A non-NULL `s` points to a NUL-terminated string alive for `'a`.
pub unsafe fn string<'a>(s: *const c_char, what: &str) -> Result<&'a str, String> {
    if s.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated (the caller's word).
    let s = unsafe { CStr::from_ptr(s) };
    s.to_str().map_err(|_| format!("{what} is not UTF-8"))
}
