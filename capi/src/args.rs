//! Turning C arguments into Rust values, with every check C cannot make (NULL, alignment,
//! lengths, UTF-8) reported as an [`Error`], and the panic guard every exported body runs
//! in. The rest of the crate touches raw pointers only through these functions.

use crate::{Error, Status};
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `f`, turning a panic into an internal error: no unwind crosses into C.
pub fn catch<T>(f: impl FnOnce() -> Result<T, Error>) -> Result<T, Error> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(ToString::to_string)
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".into());
        Err(Error::new(
            Status::Internal,
            format!("internal error in mbfx (please report it): {what}"),
        ))
    })
}

/// The status of `result` (what the evaluation functions return).
pub fn status(result: Result<(), Error>) -> Status {
    match result {
        Ok(()) => Status::Ok,
        Err(e) => e.status(),
    }
}

/// Checks that `ptr` is non-NULL and aligned for `T`.
fn check_ptr<T>(ptr: *const T, what: &str) -> Result<(), Error> {
    if ptr.is_null() {
        Err(Error::new(Status::NullArgument, format!("{what} is NULL")))
    } else if !ptr.is_aligned() {
        Err(Error::new(
            Status::InvalidArgument,
            format!("{what} is not aligned for its type"),
        ))
    } else {
        Ok(())
    }
}

/// Checks that `len` values of `T` fit in one allocation (Rust's limit on slices).
fn check_len<T>(len: usize, what: &str) -> Result<(), Error> {
    if len > isize::MAX as usize / size_of::<T>().max(1) {
        Err(Error::new(
            Status::BadLength,
            format!("{what} has length {len}, too long for memory"),
        ))
    } else {
        Ok(())
    }
}

/// The object `ptr` points to.
///
/// # Safety
/// A non-NULL `ptr` points to a live `T` that nothing writes for `'a`.
pub unsafe fn object<'a, T>(ptr: *const T, what: &str) -> Result<&'a T, Error> {
    check_ptr(ptr, what)?;
    // SAFETY: non-NULL and aligned (checked); live and unwritten (the caller's word).
    Ok(unsafe { &*ptr })
}

/// The object `ptr` points to, to change.
///
/// # Safety
/// A non-NULL `ptr` points to a live `T` that nothing else reads or writes for `'a`.
pub unsafe fn object_mut<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Error> {
    check_ptr(ptr, what)?;
    // SAFETY: non-NULL and aligned (checked); live and not shared (the caller's word).
    Ok(unsafe { &mut *ptr })
}

/// `ptr[..len]` as a slice; NULL is accepted for an empty slice only.
///
/// # Safety
/// A non-NULL `ptr` points to `len` initialised values that nothing writes for `'a`.
pub unsafe fn slice<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], Error> {
    if len == 0 {
        return Ok(&[]);
    }
    check_ptr(ptr, what)?;
    check_len::<T>(len, what)?;
    // SAFETY: non-NULL, aligned, a length that fits (checked); `len` values that nothing
    // writes meanwhile (the caller's word).
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// `ptr[..len]` as a mutable slice; NULL is accepted for an empty slice only.
///
/// # Safety
/// A non-NULL `ptr` points to `len` values that nothing else reads or writes for `'a`.
pub unsafe fn slice_mut<'a, T>(ptr: *mut T, len: usize, what: &str) -> Result<&'a mut [T], Error> {
    if len == 0 {
        return Ok(&mut []);
    }
    check_ptr(ptr, what)?;
    check_len::<T>(len, what)?;
    // SAFETY: non-NULL, aligned, a length that fits (checked); `len` values nobody else
    // touches meanwhile (the caller's word).
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, len) })
}

/// The NUL-terminated UTF-8 string at `ptr`.
///
/// # Safety
/// A non-NULL `ptr` points to a NUL-terminated string that nothing writes for `'a`.
pub unsafe fn string<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, Error> {
    if ptr.is_null() {
        return Err(Error::new(Status::NullArgument, format!("{what} is NULL")));
    }
    // SAFETY: non-NULL (checked) and NUL-terminated (the caller's word).
    let bytes = unsafe { CStr::from_ptr(ptr) };
    bytes.to_str().map_err(|e| {
        Error::new(
            Status::InvalidUtf8,
            format!("{what} is not valid UTF-8 (at byte {})", e.valid_up_to()),
        )
    })
}

/// The `n` strings of the array `ptr` (NULL when `n` is 0), named `what[i]` in errors.
///
/// # Safety
/// A non-NULL `ptr` holds `n` pointers, each NULL or to a NUL-terminated string, that
/// nothing writes for `'a`.
pub unsafe fn strings<'a>(
    ptr: *const *const c_char,
    n: usize,
    what: &str,
) -> Result<Vec<&'a str>, Error> {
    // SAFETY: the caller's word, as this function's.
    let ptrs = unsafe { slice(ptr, n, what) }?;
    ptrs.iter()
        .enumerate()
        // SAFETY: each pointer is NULL (checked) or a NUL-terminated string (the caller's word).
        .map(|(i, &p)| unsafe { string(p, &format!("{what}[{i}]")) })
        .collect()
}

/// Whether the byte ranges of `a[..a_len]` and `b[..b_len]` (values of `T`) meet.
pub fn overlap<T>(a: *const T, a_len: usize, b: *const T, b_len: usize) -> bool {
    let (a, b) = (a as usize, b as usize);
    let a_end = a.saturating_add(a_len.saturating_mul(size_of::<T>()));
    let b_end = b.saturating_add(b_len.saturating_mul(size_of::<T>()));
    a_len > 0 && b_len > 0 && a < b_end && b < a_end
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_internal_error() {
        let r: Result<(), Error> = catch(|| panic!("boom {}", 42));
        let e = r.unwrap_err();
        assert_eq!(e.status(), Status::Internal);
        let r: Result<(), Error> = catch(|| std::panic::panic_any(7_u8));
        assert_eq!(status(r), Status::Internal);
    }

    #[test]
    fn overlap_is_of_byte_ranges() {
        let buf = [0.0f64; 4];
        let p = buf.as_ptr();
        // SAFETY: offsets within `buf`.
        let (p1, p2) = unsafe { (p.add(1), p.add(2)) };
        assert!(overlap(p, 2, p1, 1));
        assert!(!overlap(p, 2, p2, 2));
        assert!(!overlap(p, 0, p, 4));
    }
}
