//! `mbfx_expr`: a compiled expression over named variables ([`Expression`]) and the C
//! functions that make, query, evaluate, differentiate and free it.

use crate::error::{c_string, hand_over};
use crate::{args, Engine, Error, Status};
use mbfx::session::expression::{Column, Expression};
use std::ffi::{c_char, c_int, c_void, CString};

/// A compiled expression (`mbfx_expr` in C): made by `mbfx_compile` or
/// `mbfx_expr_gradient`, owned by the caller, freed with `mbfx_expr_free`. It is never
/// changed after it is made, so several threads may evaluate it at once.
pub struct Expr {
    inner: Expression,
    text: CString,
    names: Vec<CString>,
    warnings: CString,
}

/// The C entry of a JIT-compiled expression: `double entry(int n, const double *x, void
/// *out)`, scipy's `LowLevelCallable` signature. `x` holds the variables in their order,
/// then TIME when `n` exceeds their count (TIME is 0 otherwise); the return value is the
/// first output; `out` receives every output (`mbfx_expr_n_outputs` doubles) when there
/// is more than one, and may be NULL otherwise. With `n` below the number of variables,
/// or a NULL `out` where outputs are written, it returns NaN and touches nothing. It is
/// valid while the `mbfx_expr` it came from lives, and may be called from any thread.
pub type EntryFn = Option<unsafe extern "C" fn(n: c_int, x: *const f64, out: *mut c_void) -> f64>;

// The entry's `int` is mbfx's `i32` (the transmute in `mbfx_expr_entry` relies on it).
const _: () = assert!(size_of::<c_int>() == size_of::<i32>());

// An `mbfx_expr` may be shared by threads (the header says so).
const _: fn() = || {
    fn shared<T: Send + Sync>() {}
    shared::<Expr>();
};

impl Expr {
    fn new(inner: Expression) -> Self {
        let warnings = match inner.warnings() {
            [] => String::new(),
            w => mbfx::diag::render(
                w,
                &mbfx::diag::SourceFile::new("expression", inner.text()),
                false,
            ),
        };
        Expr {
            text: c_string(inner.text()),
            names: inner
                .variables()
                .iter()
                .map(|v| c_string(v.as_str()))
                .collect(),
            warnings: c_string(warnings),
            inner,
        }
    }
}

/// Compiles `text` over the variables `names[0..n_names]` (values are later passed in
/// this order; names are case-insensitive and distinct; `names` may be NULL when
/// `n_names` is 0) with `engine` (`MBFX_ENGINE_JIT` or `MBFX_ENGINE_INTERP`). TIME is
/// given with each point; MODE is 4. Functions of a model (measures, splines) are errors.
///
/// Returns a new expression, to be freed with `mbfx_expr_free`, or NULL on failure.
/// When `error` is not NULL, `*error` is set to NULL on success and on failure to a new
/// error (freed with `mbfx_error_free`) holding the status (`MBFX_STATUS_COMPILE_ERROR`,
/// `_BAD_VARIABLE`, `_NULL_ARGUMENT`, `_INVALID_UTF8`, `_INVALID_ARGUMENT` for an
/// unknown engine, `_INTERNAL`), the diagnostic code and the rendered report. The
/// arguments are only read during the call: the expression keeps copies.
///
/// # Safety
/// `text` and each `names[i]` are NULL or NUL-terminated strings; `names` is NULL or
/// holds `n_names` pointers; `error` is NULL or points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_compile(
    text: *const c_char,
    names: *const *const c_char,
    n_names: usize,
    engine: c_int,
    error: *mut *mut Error,
) -> *mut Expr {
    let result = args::catch(|| {
        // SAFETY: NULL or a NUL-terminated string (the caller's word).
        let text = unsafe { args::string(text, "the text") }?;
        // SAFETY: NULL or `n_names` NULLs or strings (the caller's word).
        let names = unsafe { args::strings(names, n_names, "names") }?;
        let engine = Engine::from_c(engine).ok_or_else(|| {
            Error::new(
                Status::InvalidArgument,
                format!("unknown engine {engine}: use MBFX_ENGINE_JIT or MBFX_ENGINE_INTERP"),
            )
        })?;
        let e =
            Expression::compile(text, &names, engine).map_err(|e| Error::from_expr(&e, text))?;
        Ok(Expr::new(e))
    });
    // SAFETY: NULL or storage for a pointer (the caller's word).
    unsafe { hand_over(result, error) }
}

/// The value and partial derivatives of `expr` with respect to `wrt[0..n_wrt]`
/// (variables of the expression, case-insensitive, or `"TIME"`): a new expression with
/// the same variables and engine whose outputs are `expr`'s, then each output's partials
/// in `wrt` order (for a scalar: the value, `d/d wrt[0]`, `d/d wrt[1]`, ...).
///
/// Returns a new expression (independent of `expr`, freed with `mbfx_expr_free`) or
/// NULL; `error` as for `mbfx_compile`, with `MBFX_STATUS_BAD_VARIABLE` for a name that
/// is not a variable and `MBFX_STATUS_NOT_DIFFERENTIABLE` for a function without the
/// derivatives needed.
///
/// # Safety
/// `expr` is NULL or a live expression; `wrt` is NULL or holds `n_wrt` pointers, each
/// NULL or a NUL-terminated string; `error` as for `mbfx_compile`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_gradient(
    expr: *const Expr,
    wrt: *const *const c_char,
    n_wrt: usize,
    error: *mut *mut Error,
) -> *mut Expr {
    let result = args::catch(|| {
        // SAFETY: NULL or a live expression (the caller's word).
        let e = unsafe { args::object(expr, "the expression") }?;
        // SAFETY: NULL or `n_wrt` NULLs or strings (the caller's word).
        let wrt = unsafe { args::strings(wrt, n_wrt, "wrt") }?;
        let g = e
            .inner
            .gradient(&wrt)
            .map_err(|err| Error::from_expr(&err, e.inner.text()))?;
        Ok(Expr::new(g))
    });
    // SAFETY: NULL or storage for a pointer (the caller's word).
    unsafe { hand_over(result, error) }
}

/// The number of variables (values per point, TIME aside); 0 for NULL.
///
/// # Safety
/// `expr` is NULL or a live expression.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_n_variables(expr: *const Expr) -> usize {
    // SAFETY: NULL or a live expression (the caller's word).
    unsafe { args::object(expr, "the expression") }.map_or(0, |e| e.inner.variables().len())
}

/// The number of outputs per point: 1 for a scalar, 3 for a vector, and for a gradient
/// the outputs then their partials; 0 for NULL.
///
/// # Safety
/// `expr` is NULL or a live expression.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_n_outputs(expr: *const Expr) -> usize {
    // SAFETY: NULL or a live expression (the caller's word).
    unsafe { args::object(expr, "the expression") }.map_or(0, |e| e.inner.outputs())
}

/// The expression's text (for a gradient, the text it was taken of); NULL for NULL.
/// Owned by `expr`, valid while it lives.
///
/// # Safety
/// `expr` is NULL or a live expression.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_text(expr: *const Expr) -> *const c_char {
    // SAFETY: NULL or a live expression (the caller's word).
    unsafe { args::object(expr, "the expression") }.map_or(std::ptr::null(), |e| e.text.as_ptr())
}

/// The name of variable `i` as it was given; NULL for NULL or `i` out of range. Owned by
/// `expr`, valid while it lives.
///
/// # Safety
/// `expr` is NULL or a live expression.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_variable(expr: *const Expr, i: usize) -> *const c_char {
    // SAFETY: NULL or a live expression (the caller's word).
    unsafe { args::object(expr, "the expression") }
        .ok()
        .and_then(|e| e.names.get(i))
        .map_or(std::ptr::null(), |n| n.as_ptr())
}

/// The checker's warnings about the text, rendered like an error's report; `""` when
/// there are none, NULL for NULL. Owned by `expr`, valid while it lives.
///
/// # Safety
/// `expr` is NULL or a live expression.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_warnings(expr: *const Expr) -> *const c_char {
    // SAFETY: NULL or a live expression (the caller's word).
    unsafe { args::object(expr, "the expression") }
        .map_or(std::ptr::null(), |e| e.warnings.as_ptr())
}

/// Evaluates `expr` at one point: `vars[0..n_vars]` in the variables' order (NULL when
/// there are none), TIME = `time`; writes the `n_out` outputs to `out`. `n_vars` must be
/// `mbfx_expr_n_variables` and `n_out` `mbfx_expr_n_outputs` (else
/// `MBFX_STATUS_BAD_LENGTH`). `out` may overlap `vars`. Returns `MBFX_STATUS_OK` or why
/// not; on failure `out` is left as it was.
///
/// # Safety
/// `expr` is NULL or a live expression; `vars` is NULL or holds `n_vars` doubles; `out`
/// is NULL or holds `n_out` writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_eval(
    expr: *const Expr,
    vars: *const f64,
    n_vars: usize,
    time: f64,
    out: *mut f64,
    n_out: usize,
) -> Status {
    args::status(args::catch(|| {
        // SAFETY: NULL or a live expression (the caller's word).
        let e = unsafe { args::object(expr, "the expression") }?;
        let copy;
        let vars = if args::overlap(vars, n_vars, out, n_out) {
            // SAFETY: NULL or `n_vars` doubles (the caller's word); dropped before `out`
            // is borrowed.
            copy = unsafe { args::slice(vars, n_vars, "vars") }?.to_vec();
            &copy[..]
        } else {
            // SAFETY: as above; apart from `out` (checked), so nothing writes it meanwhile.
            unsafe { args::slice(vars, n_vars, "vars") }?
        };
        // SAFETY: NULL or `n_out` writable doubles (the caller's word), apart from `vars`.
        let out = unsafe { args::slice_mut(out, n_out, "out") }?;
        e.inner
            .eval_into(vars, time, out)
            .map_err(|err| Error::from_expr(&err, e.inner.text()))
    }))
}

/// Evaluates `expr` at `n` points. Variable `k` at point `i` is
/// `columns[k][i * strides[k]]`: a stride of 1 reads a contiguous array, a stride of 0
/// gives every point the value `columns[k][0]` (a constant), a larger stride reads every
/// stride-th double (a column of a row-major table); `strides` NULL means every stride
/// is 1. TIME at point `i` is `times[i]`, or `time` when `times` is NULL. The outputs go
/// to `out`, point after point: output `j` of point `i` is `out[i * n_outputs + j]`.
///
/// `n_columns` must be `mbfx_expr_n_variables` and `n_out` must be `n *
/// mbfx_expr_n_outputs` (else `MBFX_STATUS_BAD_LENGTH`); `columns` may be NULL when
/// there are no variables, but no column may be NULL. Each point gives exactly the bits
/// `mbfx_expr_eval` gives. `out` must not overlap the inputs. Returns `MBFX_STATUS_OK`
/// or why not; on a failure found before the first point (every check above) `out` is
/// left as it was.
///
/// # Safety
/// `expr` is NULL or a live expression; `columns` is NULL or holds `n_columns`
/// pointers, each NULL or to at least `(n - 1) * stride + 1` doubles (1 for stride 0);
/// `strides` is NULL or holds `n_columns` values; `times` is NULL or holds `n` doubles;
/// `out` is NULL or holds `n_out` writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_eval_n(
    expr: *const Expr,
    n: usize,
    columns: *const *const f64,
    strides: *const usize,
    n_columns: usize,
    times: *const f64,
    time: f64,
    out: *mut f64,
    n_out: usize,
) -> Status {
    args::status(args::catch(|| {
        // SAFETY: NULL or a live expression (the caller's word).
        let e = unsafe { args::object(expr, "the expression") }?;
        let expr = &e.inner;
        let bad_length = |what: &str, expected: usize, got: usize| {
            Error::new(
                Status::BadLength,
                format!("{what} is {got}, expected {expected}"),
            )
        };
        if n_columns != expr.variables().len() {
            return Err(bad_length("n_columns", expr.variables().len(), n_columns));
        }
        let k = expr.outputs();
        let want = n
            .checked_mul(k)
            .ok_or_else(|| Error::new(Status::BadLength, format!("n = {n} is too large")))?;
        if n_out != want {
            return Err(bad_length("n_out", want, n_out));
        }
        // SAFETY: NULL or `n_columns` pointers (the caller's word).
        let cols = unsafe { args::slice(columns, n_columns, "columns") }?;
        let ones;
        let strides = if strides.is_null() {
            ones = vec![1; n_columns];
            &ones[..]
        } else {
            // SAFETY: `n_columns` values (the caller's word).
            unsafe { args::slice(strides, n_columns, "strides") }?
        };
        // The span each column is read over, checked before any point is read.
        let last = n.saturating_sub(1);
        for (c, (&col, &stride)) in cols.iter().zip(strides).enumerate() {
            let reach = last.checked_mul(stride).and_then(|r| r.checked_add(1));
            match reach {
                Some(reach) => {
                    // SAFETY: `reach` doubles from `col` (the caller's word); only checked.
                    let _ = unsafe { args::slice(col, reach, &format!("columns[{c}]")) }?;
                }
                None => {
                    return Err(Error::new(
                        Status::BadLength,
                        format!("columns[{c}]: stride {stride} times n = {n} overflows"),
                    ))
                }
            }
        }
        if !times.is_null() {
            // SAFETY: `n` doubles (the caller's word); only checked here.
            let _ = unsafe { args::slice(times, n, "times") }?;
        }
        if want == 0 {
            return Ok(());
        }
        let varying = strides.contains(&1) || !times.is_null();
        if varying && strides.iter().all(|&s| s <= 1) {
            // Every column contiguous or constant, one at least of `n` values: the whole
            // batch in one call (the lane evaluator from 32 points on), same bits as
            // point by point.
            let columns: Vec<Column> = cols
                .iter()
                .zip(strides)
                .map(|(&col, &stride)| match stride {
                    // SAFETY: checked above to hold at least 1 double.
                    0 => Column::Const(unsafe { col.read() }),
                    // SAFETY: stride 1, checked above to hold `n` doubles; not written.
                    _ => Column::Values(unsafe { std::slice::from_raw_parts(col, n) }),
                })
                .collect();
            let time = match times.is_null() {
                true => Column::Const(time),
                // SAFETY: checked above to hold `n` doubles.
                false => Column::Values(unsafe { std::slice::from_raw_parts(times, n) }),
            };
            // SAFETY: `n_out` writable doubles that overlap no input (the caller's word).
            let out = unsafe { args::slice_mut(out, n_out, "out") }?;
            return expr
                .eval_columns(&columns, time, out)
                .map(|_| ())
                .map_err(|err| Error::from_expr(&err, expr.text()));
        }
        // SAFETY: `n_out` writable doubles (the caller's word); checked, not kept.
        let _ = unsafe { args::slice_mut(out, n_out, "out") }?;
        let mut vars = vec![0.0; n_columns];
        for i in 0..n {
            for (v, (&col, &stride)) in vars.iter_mut().zip(cols.iter().zip(strides)) {
                // SAFETY: column checked above to hold `(n-1)·stride + 1` doubles, and
                // i·stride is below that.
                *v = unsafe { col.add(i * stride).read() };
            }
            let t = if times.is_null() {
                time
            } else {
                // SAFETY: `times` checked above to hold `n` doubles.
                unsafe { times.add(i).read() }
            };
            // SAFETY: `out` checked above to hold n·k doubles; this point's k are borrowed
            // only for this call, after its inputs were read.
            let o = unsafe { std::slice::from_raw_parts_mut(out.add(i * k), k) };
            expr.eval_into(&vars, t, o)
                .map_err(|err| Error::from_expr(&err, expr.text()))?;
        }
        Ok(())
    }))
}

/// Stores the C entry of `expr`'s machine code in `*entry` (see `mbfx_entry_fn` for how
/// to call it) and returns `MBFX_STATUS_OK`; for an interpreter expression stores NULL
/// and returns `MBFX_STATUS_NO_ENTRY`. The pointer is valid while `expr` lives: free the
/// expression only after the last call.
///
/// # Safety
/// `expr` is NULL or a live expression; `entry` is NULL or points to writable storage for
/// a function pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_entry(expr: *const Expr, entry: *mut EntryFn) -> Status {
    if entry.is_null() {
        return Status::NullArgument;
    }
    // SAFETY: writable storage for a function pointer (the caller's word), non-NULL.
    unsafe { entry.write_unaligned(None) };
    let found = args::catch(|| {
        // SAFETY: NULL or a live expression (the caller's word).
        let e = unsafe { args::object(expr, "the expression") }?;
        e.inner
            .entry()
            .ok_or_else(|| Error::new(Status::NoEntry, "an interpreter expression has no entry"))
    });
    match found {
        Ok(f) => {
            // SAFETY: the same C signature: `c_int` is `i32` (asserted above) and a
            // `void *` is passed as a `double *` is.
            let f = unsafe {
                std::mem::transmute::<
                    mbfx::session::expression::EntryFn,
                    unsafe extern "C" fn(c_int, *const f64, *mut c_void) -> f64,
                >(f)
            };
            // SAFETY: as above.
            unsafe { entry.write_unaligned(Some(f)) };
            Status::Ok
        }
        Err(e) => e.status(),
    }
}

/// Frees an expression; NULL is accepted (nothing happens). Its strings and its entry
/// die with it; expressions made from it (gradients) live on.
///
/// # Safety
/// `expr` is NULL or an expression from this library that has not been freed; it is
/// not used after this call (no thread is evaluating it).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_expr_free(expr: *mut Expr) {
    if expr.is_null() {
        return;
    }
    // SAFETY: an expression from Box::into_raw in `hand_over`, freed once (the caller's
    // word).
    let expr = unsafe { Box::from_raw(expr) };
    let _ = args::catch(move || {
        drop(expr);
        Ok(())
    });
}
