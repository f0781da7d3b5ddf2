//! Body of the `capi_sequences` fuzz target, shared with the stable replay test
//! (`tests/fuzz_seeds.rs` includes this file with `#[path]`). Plain Rust: no libfuzzer
//! dependency.
//!
//! The input bytes are decoded into a sequence of C API calls (`mbfx_compile`,
//! `mbfx_expr_gradient`, `mbfx_expr_eval`, `mbfx_expr_eval_n`, the C entry, the
//! accessors, the frees), made through the exported `extern "C"` functions with raw
//! pointers, as a C program makes them: expressions from a list or raw bytes (not UTF-8
//! included), variable names good and bad, NULL where the header says NULL is refused,
//! wrong lengths, misaligned arrays, values that include ±0, subnormals, ±∞ and NaN. The
//! checks are the header's promises:
//! - a call that fails returns a status other than OK that has its own string, and a
//!   failed compile or gradient hands back an error with that status and a non-empty
//!   message and report (and a code for errors in the text);
//! - an evaluation that fails leaves `out` as it was;
//! - `mbfx_expr_eval_n` gives, point by point, the bits `mbfx_expr_eval` gives, and so
//!   does the JIT's C entry;
//! - a gradient has `outputs × (1 + wrt)` outputs and outlives the expression it came from;
//! - every object made is freed once at the end (LeakSanitizer checks nothing is left).

use mbfx_c::error::{
    mbfx_error_code, mbfx_error_free, mbfx_error_message, mbfx_error_position, mbfx_error_report,
    mbfx_error_status,
};
use mbfx_c::expr::{
    mbfx_compile, mbfx_expr_entry, mbfx_expr_eval, mbfx_expr_eval_n, mbfx_expr_free,
    mbfx_expr_gradient, mbfx_expr_n_outputs, mbfx_expr_n_variables, mbfx_expr_text,
    mbfx_expr_variable, mbfx_expr_warnings,
};
use mbfx_c::{mbfx_status_string, EntryFn, Error, Expr, Status};
use std::ffi::{c_char, c_int, CStr, CString};
use std::ptr::{null, null_mut};

/// Expressions the decoder picks by number (over the variables x, v, t, or none).
const TEXTS: [&str; 24] = [
    "x + v*t",
    "SIN(x)*COS(v) + t",
    "STEP(x, 0, 0, 1, 1)",
    "IF(x - 1: -x*v, 0, x + t)",
    "SQRT(x) + LOG(v)",
    "x**v",
    "TIME*MODE",
    "[x, v, t]",
    "[x, v, t] % [t, x, v]",
    "MAG([x, v, t])",
    "IMPACT(x, v, 1, 1e5, 1.5, 50, 0.1)",
    "POLY(x, 0, 1, 2, 3)",
    "ATAN2(v, x) + MOD(x, v)",
    "x / 0 + 0 / 0",
    "1E308 * x * 10",
    "MIN(x, v) + MAX(v, t) + ABS(x)",
    "DX(1, 2)",
    "AKISPL(x, 0, 1)",
    "SIN(",
    "x +* v",
    "",
    "unknown_name + 1",
    "3",
    "AINT(x) + ANINT(v) + SIGN(x, t)",
];

/// Variable names the decoder picks by number: good ones, case variants, builtins,
/// non-names, an empty string.
const NAMES: [&[u8]; 14] = [
    b"x", b"v", b"t", b"X", b"TIME", b"SIN", b"PI", b"", b"1a", b"a b", b"\xff", b"x_2", b"time",
    b"w",
];

/// Values the decoder picks by number.
const VALUES: [f64; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    2.5,
    1e308,
    -1e308,
    5e-324,
    -2.2e-308,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    std::f64::consts::PI,
    1e-300,
    -7.25,
];

/// The bits `out` is filled with before a call, to see what a failed call wrote.
const SENTINEL: u64 = 0x7ff4_dead_beef_0001;

/// Live objects at most (a slot refilled frees nothing: the old one is freed first).
const SLOTS: usize = 4;
/// Calls per input at most, and compiles (the JIT's are the dear ones).
const MAX_CALLS: usize = 48;
const MAX_COMPILES: usize = 6;

/// The input, read a byte at a time (0 once it is used up).
struct Input<'a> {
    data: &'a [u8],
    at: usize,
}

impl Input<'_> {
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }
    fn below(&mut self, n: usize) -> usize {
        self.byte() as usize % n
    }
    fn done(&self) -> bool {
        self.at >= self.data.len()
    }
    /// A value: from [`VALUES`] mostly, any 8 bytes' bits otherwise.
    fn value(&mut self) -> f64 {
        let b = self.byte();
        if b < 224 {
            VALUES[b as usize % VALUES.len()]
        } else {
            let mut bits = [0u8; 8];
            for x in &mut bits {
                *x = self.byte();
            }
            f64::from_le_bytes(bits)
        }
    }
    /// A C string: from [`TEXTS`], or raw bytes up to a NUL or a length.
    fn text(&mut self) -> CString {
        let b = self.byte();
        if b < 200 {
            return CString::new(TEXTS[b as usize % TEXTS.len()]).expect("no NUL");
        }
        let len = self.below(64);
        let start = self.at.min(self.data.len());
        let end = (start + len).min(self.data.len());
        let raw: Vec<u8> = self.data[start..end]
            .iter()
            .copied()
            .take_while(|&c| c != 0)
            .collect();
        self.at = end;
        CString::new(raw).expect("cut at the first NUL")
    }
    fn name(&mut self) -> CString {
        CString::new(NAMES[self.below(NAMES.len())]).expect("no NUL")
    }
}

/// The objects a sequence holds, freed when it ends.
struct Live {
    exprs: [*mut Expr; SLOTS],
    errors: [*mut Error; SLOTS],
}

impl Drop for Live {
    fn drop(&mut self) {
        for e in &mut self.exprs {
            // SAFETY: NULL or a live expression of this sequence, freed once.
            unsafe { mbfx_expr_free(std::mem::replace(e, null_mut())) };
        }
        for e in &mut self.errors {
            // SAFETY: NULL or a live error of this sequence, freed once.
            unsafe { mbfx_error_free(std::mem::replace(e, null_mut())) };
        }
    }
}

/// Runs the sequence the bytes decode to.
pub fn check_bytes(data: &[u8]) {
    let mut input = Input { data, at: 0 };
    let mut live = Live {
        exprs: [null_mut(); SLOTS],
        errors: [null_mut(); SLOTS],
    };
    let mut compiles = 0;
    for _ in 0..MAX_CALLS {
        if input.done() {
            break;
        }
        let slot = input.below(SLOTS);
        match input.below(10) {
            0 | 1 if compiles < MAX_COMPILES => {
                compiles += 1;
                compile(&mut input, &mut live, slot);
            }
            2 if compiles < MAX_COMPILES => {
                compiles += 1;
                gradient(&mut input, &mut live, slot);
            }
            3 | 4 => eval(&mut input, live.exprs[slot]),
            5 => eval_n(&mut input, live.exprs[slot]),
            6 => entry(&mut input, live.exprs[slot]),
            7 => accessors(&mut input, live.exprs[slot], live.errors[slot]),
            8 => {
                // Free (NULL is accepted: an emptied slot is freed again).
                let e = std::mem::replace(&mut live.exprs[slot], null_mut());
                // SAFETY: NULL or a live expression, freed once.
                unsafe { mbfx_expr_free(e) };
                let e = std::mem::replace(&mut live.errors[slot], null_mut());
                // SAFETY: NULL or a live error, freed once.
                unsafe { mbfx_error_free(e) };
            }
            _ => null_arguments(&mut input),
        }
    }
}

/// The C string at `p` (non-NULL).
fn text_at<'a>(p: *const c_char, what: &str) -> &'a CStr {
    assert!(!p.is_null(), "{what}: NULL");
    // SAFETY: the API returns NUL-terminated strings owned by live objects.
    unsafe { CStr::from_ptr(p) }
}

/// A failure's status has its own string.
fn failed_with(status: Status, what: &str) {
    assert_ne!(status, Status::Ok, "{what}");
    let s = text_at(mbfx_status_string(status as c_int), "status string");
    assert!(!s.is_empty(), "{what}: empty status string");
    assert_ne!(s.to_bytes(), b"unknown status", "{what}: {status:?}");
}

/// The promises about a failure's error object.
fn check_error(err: *const Error, what: &str) -> Status {
    assert!(!err.is_null(), "{what}: failed without an error");
    // SAFETY: a live error.
    let (status, code, message, report) = unsafe {
        (
            mbfx_error_status(err),
            text_at(mbfx_error_code(err), "code"),
            text_at(mbfx_error_message(err), "message"),
            text_at(mbfx_error_report(err), "report"),
        )
    };
    failed_with(status, what);
    assert!(!message.is_empty(), "{what}: empty message");
    assert!(!report.is_empty(), "{what}: empty report");
    if matches!(status, Status::CompileError | Status::BadVariable) {
        let code = code.to_string_lossy();
        assert!(
            code.starts_with('E') && code.len() == 5,
            "{what}: code {code:?}"
        );
    }
    if status == Status::CompileError {
        let (mut line, mut column) = (0usize, 0usize);
        // SAFETY: a live error; writable size_t's.
        let placed = unsafe { mbfx_error_position(err, &mut line, &mut column) };
        assert!(
            !placed || (line >= 1 && column >= 1),
            "{what}: at {line}:{column}"
        );
    }
    status
}

/// Stores `err` in `slot` (freeing what was there) or frees it.
fn keep_error(live: &mut Live, slot: usize, err: *mut Error) {
    let old = std::mem::replace(&mut live.errors[slot], err);
    // SAFETY: NULL or a live error, freed once.
    unsafe { mbfx_error_free(old) };
}

fn keep_expr(live: &mut Live, slot: usize, e: *mut Expr) {
    let old = std::mem::replace(&mut live.exprs[slot], e);
    // SAFETY: NULL or a live expression, freed once.
    unsafe { mbfx_expr_free(old) };
}

/// A name array of 0 to 4 names, a NULL among them sometimes.
fn names(input: &mut Input, owned: &mut Vec<CString>) -> Vec<*const c_char> {
    let n = input.below(5);
    let mut ptrs = Vec::with_capacity(n);
    for _ in 0..n {
        if input.byte() == 255 {
            ptrs.push(null());
        } else {
            owned.push(input.name());
            ptrs.push(owned.last().expect("pushed").as_ptr());
        }
    }
    ptrs
}

/// The status a name array is refused with (a NULL array, then the first NULL or
/// non-UTF-8 name), if it is.
fn names_status(ptrs: &[*const c_char], null_array: bool) -> Option<Status> {
    if null_array {
        return Some(Status::NullArgument);
    }
    ptrs.iter().find_map(|&p| match p.is_null() {
        true => Some(Status::NullArgument),
        // SAFETY: a NUL-terminated name owned by the caller.
        false => unsafe { CStr::from_ptr(p) }
            .to_str()
            .is_err()
            .then_some(Status::InvalidUtf8),
    })
}

fn compile(input: &mut Input, live: &mut Live, slot: usize) {
    let engine = match input.byte() {
        0..=127 => 1, // the interpreter, cheap
        128..=250 => 0,
        b => b as c_int, // no such engine
    };
    let text = input.text();
    let null_text = input.byte() == 255;
    let mut owned = Vec::new();
    let names = names(input, &mut owned);
    let null_names = !names.is_empty() && input.byte() == 255;
    let with_error = input.byte() != 255;
    // A pointer the call must overwrite, as the C test does.
    let mut err: *mut Error = std::ptr::dangling_mut();
    let err_arg = if with_error {
        &mut err as *mut _
    } else {
        null_mut()
    };
    // SAFETY: a NUL-terminated text or NULL, `names.len()` pointers (or NULL), storage
    // for one pointer or NULL.
    let e = unsafe {
        mbfx_compile(
            if null_text { null() } else { text.as_ptr() },
            if null_names { null() } else { names.as_ptr() },
            names.len(),
            engine,
            err_arg,
        )
    };
    let what = format!("compile {text:?} engine {engine}");
    if !with_error {
        err = null_mut();
    }
    assert_ne!(err, std::ptr::dangling_mut(), "{what}: error not stored");
    if e.is_null() {
        if with_error {
            let status = check_error(err, &what);
            // The arguments are checked in order: the text, the names, the engine.
            let expected = if null_text {
                Some(Status::NullArgument)
            } else if text.to_str().is_err() {
                Some(Status::InvalidUtf8)
            } else {
                names_status(&names, null_names).or((engine > 1).then_some(Status::InvalidArgument))
            };
            if let Some(expected) = expected {
                assert_eq!(status, expected, "{what}");
            }
            keep_error(live, slot, err);
        }
    } else {
        assert!(err.is_null(), "{what}: an error with an expression");
        assert!(
            !null_text && names_status(&names, null_names).is_none() && engine <= 1,
            "{what}"
        );
        // SAFETY: a live expression.
        unsafe {
            assert_eq!(mbfx_expr_n_variables(e), names.len(), "{what}");
            assert!(mbfx_expr_n_outputs(e) >= 1, "{what}");
            assert_eq!(
                text_at(mbfx_expr_text(e), "text"),
                text.as_c_str(),
                "{what}"
            );
        }
        keep_expr(live, slot, e);
    }
}

fn gradient(input: &mut Input, live: &mut Live, slot: usize) {
    let from = live.exprs[input.below(SLOTS)];
    let mut owned = Vec::new();
    let wrt = names(input, &mut owned);
    let null_wrt = !wrt.is_empty() && input.byte() == 255;
    let mut err: *mut Error = null_mut();
    // SAFETY: NULL or a live expression; `wrt.len()` pointers (or NULL); storage for one.
    let g = unsafe {
        mbfx_expr_gradient(
            from,
            if null_wrt { null() } else { wrt.as_ptr() },
            wrt.len(),
            &mut err,
        )
    };
    let what = format!("gradient of {from:?} in {owned:?}");
    if g.is_null() {
        let status = check_error(err, &what);
        let expected = match from.is_null() {
            true => Some(Status::NullArgument),
            false => names_status(&wrt, null_wrt),
        };
        if let Some(expected) = expected {
            assert_eq!(status, expected, "{what}");
        }
        keep_error(live, slot, err);
    } else {
        assert!(err.is_null(), "{what}");
        // SAFETY: live expressions.
        unsafe {
            assert_eq!(
                mbfx_expr_n_outputs(g),
                mbfx_expr_n_outputs(from) * (1 + wrt.len()),
                "{what}"
            );
            assert_eq!(mbfx_expr_n_variables(g), mbfx_expr_n_variables(from));
        }
        // The gradient outlives its expression when it takes the same slot.
        keep_expr(live, slot, g);
    }
}

/// Same bits, or both NaN.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// The counts a call is given: right mostly, off by one or zero sometimes.
fn count(input: &mut Input, right: usize) -> usize {
    match input.byte() {
        0..=229 => right,
        230..=239 => right + 1,
        240..=249 => right.saturating_sub(1),
        _ => 0,
    }
}

/// `expr` at one point, or the status why not (`out` unchanged then).
fn eval_point(
    expr: *const Expr,
    vars: &[f64],
    n_vars: usize,
    time: f64,
    n_out: usize,
) -> Result<Vec<f64>, Status> {
    let mut out = vec![f64::from_bits(SENTINEL); n_out.max(1)];
    let vars_ptr = if vars.is_empty() {
        null()
    } else {
        vars.as_ptr()
    };
    // SAFETY: `vars` holds at least `n_vars` values when the count is right; a count
    // one too large is given only with an array one longer (see `eval`).
    let status = unsafe { mbfx_expr_eval(expr, vars_ptr, n_vars, time, out.as_mut_ptr(), n_out) };
    if status == Status::Ok {
        out.truncate(n_out);
        Ok(out)
    } else {
        failed_with(status, "eval");
        assert!(
            out.iter().all(|x| x.to_bits() == SENTINEL),
            "eval failed and wrote out"
        );
        Err(status)
    }
}

fn eval(input: &mut Input, expr: *const Expr) {
    // SAFETY: NULL or a live expression.
    let (nv, no) = unsafe { (mbfx_expr_n_variables(expr), mbfx_expr_n_outputs(expr)) };
    let n_vars = count(input, nv);
    let n_out = count(input, no);
    // One spare value, so that a count one too large still reads owned memory.
    let vars: Vec<f64> = (0..=nv).map(|_| input.value()).collect();
    let time = input.value();
    let got = eval_point(expr, &vars, n_vars, time, n_out);
    if expr.is_null() {
        assert_eq!(got, Err(Status::NullArgument));
    } else if n_vars != nv || n_out != no {
        assert_eq!(
            got,
            Err(Status::BadLength),
            "n_vars {n_vars} of {nv}, n_out {n_out} of {no}"
        );
    } else {
        assert!(got.is_ok(), "eval at {vars:?}: {got:?}");
        // Outputs written over the inputs (the header allows overlap).
        if n_vars > 0 && n_vars >= n_out {
            let mut both = vars.clone();
            // SAFETY: `both` holds n_vars ≥ n_out values, read then written.
            let status = unsafe {
                mbfx_expr_eval(expr, both.as_ptr(), n_vars, time, both.as_mut_ptr(), n_out)
            };
            assert_eq!(status, Status::Ok);
            let got = got.expect("checked");
            assert!(
                got.iter().zip(&both).all(|(a, b)| same(*a, *b)),
                "overlapping eval differs"
            );
        }
    }
}

fn eval_n(input: &mut Input, expr: *const Expr) {
    // SAFETY: NULL or a live expression.
    let (nv, no) = unsafe { (mbfx_expr_n_variables(expr), mbfx_expr_n_outputs(expr)) };
    // Across 32 points, where the JIT's lane evaluator takes over.
    let n = input.below(40);
    let strides: Vec<usize> = (0..nv).map(|_| input.below(4)).collect();
    let with_strides = input.byte() < 200 || strides.iter().any(|&s| s != 1);
    let columns: Vec<Vec<f64>> = strides
        .iter()
        .map(|&s| {
            let len = n.saturating_sub(1) * s + 1;
            let seed: Vec<f64> = (0..4).map(|_| input.value()).collect();
            (0..len).map(|i| seed[i % 4] * (1.0 + i as f64)).collect()
        })
        .collect();
    let with_times = input.byte() < 128;
    let times: Vec<f64> = (0..n).map(|i| i as f64 * 0.125).collect();
    let time = input.value();
    let n_columns = count(input, nv);
    let n_out = count(input, n * no);
    let null_columns = input.byte() == 255;
    let col_ptrs: Vec<*const f64> = columns.iter().map(|c| c.as_ptr()).collect();
    let mut out = vec![f64::from_bits(SENTINEL); n * no + 1];
    // SAFETY: each column holds `(n-1)·stride + 1` values; `times` n; `out` n·no + 1;
    // a count one too large is refused before anything is read (n_columns ≠ nv).
    let status = unsafe {
        mbfx_expr_eval_n(
            expr,
            n,
            if null_columns || col_ptrs.is_empty() {
                null()
            } else {
                col_ptrs.as_ptr()
            },
            if with_strides {
                strides.as_ptr()
            } else {
                null()
            },
            n_columns,
            if with_times { times.as_ptr() } else { null() },
            time,
            out.as_mut_ptr(),
            n_out,
        )
    };
    let right = !expr.is_null() && n_columns == nv && n_out == n * no;
    if !right || (null_columns && nv > 0) {
        failed_with(status, "eval_n");
        assert!(
            out.iter().all(|x| x.to_bits() == SENTINEL),
            "eval_n failed and wrote out"
        );
        return;
    }
    assert_eq!(status, Status::Ok, "eval_n of {n} points");
    assert_eq!(out[n * no].to_bits(), SENTINEL, "eval_n wrote past n_out");
    // Point by point, the same bits.
    for i in 0..n {
        let vars: Vec<f64> = columns
            .iter()
            .zip(&strides)
            .map(|(c, &s)| c[i * if with_strides { s } else { 1 }])
            .collect();
        let t = if with_times { times[i] } else { time };
        let one = eval_point(expr, &vars, nv, t, no).expect("the same point alone");
        let many = &out[i * no..(i + 1) * no];
        assert!(
            one.iter().zip(many).all(|(a, b)| same(*a, *b)),
            "point {i} of {n}: eval {one:?}, eval_n {many:?}"
        );
    }
}

fn entry(input: &mut Input, expr: *const Expr) {
    let mut f: EntryFn = None;
    // SAFETY: NULL or a live expression; storage for a function pointer.
    let status = unsafe { mbfx_expr_entry(expr, &mut f) };
    if status != Status::Ok {
        failed_with(status, "entry");
        assert!(f.is_none());
        return;
    }
    let f = f.expect("an entry with OK");
    // SAFETY: a live expression.
    let (nv, no) = unsafe { (mbfx_expr_n_variables(expr), mbfx_expr_n_outputs(expr)) };
    let mut x: Vec<f64> = (0..=nv).map(|_| input.value()).collect();
    let with_time = input.byte() < 128;
    if !with_time {
        x[nv] = 0.0; // TIME is 0 when n leaves it out
    }
    let n = nv + usize::from(with_time);
    let mut out = vec![f64::from_bits(SENTINEL); no];
    let want =
        eval_point(expr, &x[..nv], nv, x[nv], no).expect("an expression with an entry evaluates");
    // SAFETY: `x` holds n values, `out` no writable values.
    let first = unsafe { f(n as c_int, x.as_ptr(), out.as_mut_ptr().cast()) };
    assert!(same(first, want[0]), "entry {first} vs eval {}", want[0]);
    if no > 1 {
        assert!(
            out.iter().zip(&want).all(|(a, b)| same(*a, *b)),
            "entry outputs"
        );
    }
    if nv > 0 {
        // Too few values: NaN, nothing touched.
        let mut out = vec![f64::from_bits(SENTINEL); no];
        // SAFETY: as above, a smaller n.
        let r = unsafe { f(nv as c_int - 1, x.as_ptr(), out.as_mut_ptr().cast()) };
        assert!(r.is_nan(), "entry with too few values: {r}");
        assert!(
            out.iter().all(|x| x.to_bits() == SENTINEL),
            "entry with too few values wrote"
        );
    }
}

fn accessors(input: &mut Input, expr: *const Expr, err: *const Error) {
    // SAFETY: NULL or live objects; NULL is refused with NULL or 0.
    unsafe {
        let nv = mbfx_expr_n_variables(expr);
        if expr.is_null() {
            assert!(mbfx_expr_text(expr).is_null() && mbfx_expr_warnings(expr).is_null());
            assert_eq!(mbfx_expr_n_outputs(expr), 0);
        } else {
            text_at(mbfx_expr_text(expr), "text");
            text_at(mbfx_expr_warnings(expr), "warnings");
            for i in 0..nv {
                text_at(mbfx_expr_variable(expr, i), "variable");
            }
        }
        let beyond = nv + input.below(3);
        assert!(
            mbfx_expr_variable(expr, beyond).is_null(),
            "variable {beyond} of {nv}"
        );
        if !err.is_null() {
            check_error(err, "kept error");
        }
    }
}

/// The NULLs the header says are refused, with their statuses.
fn null_arguments(input: &mut Input) {
    // SAFETY: NULL objects and arguments, as the header allows.
    unsafe {
        let null_err: *const Error = null();
        assert_eq!(mbfx_error_status(null_err), Status::NullArgument);
        assert!(mbfx_error_code(null_err).is_null());
        assert!(mbfx_error_message(null_err).is_null());
        assert!(mbfx_error_report(null_err).is_null());
        assert!(!mbfx_error_position(null_err, null_mut(), null_mut()));
        mbfx_error_free(null_mut());
        mbfx_expr_free(null_mut());
        assert_eq!(mbfx_expr_entry(null(), null_mut()), Status::NullArgument);
        let mut f: EntryFn = None;
        assert_eq!(mbfx_expr_entry(null(), &mut f), Status::NullArgument);
        let mut out = [0.0f64; 2];
        assert_eq!(
            mbfx_expr_eval(null(), null(), 0, 0.0, out.as_mut_ptr(), 1),
            Status::NullArgument
        );
        let status = input.byte() as c_int - 128;
        text_at(mbfx_status_string(status), "status string");
    }
}
