//! The values an expression is called with: a point of plain floats (the small call,
//! no numpy involved), or numpy arrays broadcast to one shape, evaluated with the GIL
//! released and returned as one ndarray (a last axis for several outputs).

use crate::expression::expr_error;
use mbfx::session::expression::{Column, Expression};
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt, PyString, PyTuple};

/// Variables a point holds inline (more go through the array path).
const INLINE: usize = 8;

/// The values of one point, all plain numbers.
pub struct Point {
    values: [f64; INLINE],
    len: usize,
    /// TIME.
    pub time: f64,
}

impl Point {
    /// The values in variable order.
    pub fn values(&self) -> &[f64] {
        &self.values[..self.len]
    }

    /// The point `args` and `kwargs` (by name, case-insensitive; `time=`, any case,
    /// gives TIME) give when each value is a Python float or int and every one of
    /// `names` has one; None otherwise (arrays, unknown or repeated names, a wrong count: the
    /// general path handles and words those). Nothing is allocated: a keyword call costs
    /// about what a positional one does.
    pub fn scalars(
        names: &[String],
        args: &Bound<'_, PyTuple>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Option<Point>> {
        let n = names.len();
        if args.len() > n || n > INLINE {
            return Ok(None);
        }
        let mut p = Point {
            values: [0.0; INLINE],
            len: n,
            time: 0.0,
        };
        // Bit k: variable k has its value.
        let mut given = 0u32;
        for (k, (slot, a)) in p.values.iter_mut().zip(args.iter()).enumerate() {
            match plain(&a)? {
                Some(x) => *slot = x,
                None => return Ok(None),
            }
            given |= 1 << k;
        }
        let mut time_given = false;
        if let Some(kw) = kwargs {
            for (key, value) in kw.iter() {
                let Ok(key) = key.cast::<PyString>() else {
                    return Ok(None);
                };
                let key = key.to_str()?;
                let Some(x) = plain(&value)? else {
                    return Ok(None);
                };
                match names.iter().position(|n| n.eq_ignore_ascii_case(key)) {
                    Some(k) if given & (1 << k) == 0 => {
                        p.values[k] = x;
                        given |= 1 << k;
                    }
                    None if key.eq_ignore_ascii_case("time") && !time_given => {
                        p.time = x;
                        time_given = true;
                    }
                    _ => return Ok(None),
                }
            }
        }
        Ok((given.count_ones() as usize == n).then_some(p))
    }
}

/// The value of a Python float or int (numpy's float64 is a float), else None.
fn plain(a: &Bound<'_, PyAny>) -> PyResult<Option<f64>> {
    if a.is_instance_of::<PyFloat>() || a.is_instance_of::<PyInt>() {
        a.extract::<f64>().map(Some)
    } else {
        Ok(None)
    }
}

/// One argument after conversion: a number for every point, or an array of the common
/// shape, C-contiguous.
enum Arg<'py> {
    Number(f64),
    Array(PyReadonlyArrayDyn<'py, f64>),
}

/// The column `a` gives for evaluation.
fn column<'a>(a: &'a Arg<'_>) -> PyResult<Column<'a>> {
    Ok(match a {
        Arg::Number(x) => Column::Const(*x),
        Arg::Array(a) => Column::Values(
            a.as_slice()
                .map_err(|err| PyValueError::new_err(err.to_string()))?,
        ),
    })
}

/// The arguments of an array call, broadcast to `shape`.
pub struct Inputs<'py> {
    args: Vec<Arg<'py>>,
    time: Arg<'py>,
    shape: Vec<usize>,
    /// No argument was an array: the result is a float (or one 1-D array of outputs).
    all_numbers: bool,
}

impl<'py> Inputs<'py> {
    /// Converts each value (float, int, array-like) to float64 and broadcasts the
    /// arrays together as numpy does.
    pub fn gather(
        py: Python<'py>,
        values: &[Bound<'py, PyAny>],
        time: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Inputs<'py>> {
        let np = py.import("numpy")?;
        let float64 = np.getattr("float64")?;
        let mut raw = Vec::with_capacity(values.len() + 1);
        for v in values.iter().map(Some).chain(std::iter::once(time)) {
            let converted = match v {
                None => Err(0.0),
                Some(v) => match plain(v)? {
                    Some(x) => Err(x),
                    None => Ok(np.call_method1("asarray", (v, &float64))?),
                },
            };
            raw.push(converted);
        }
        let shapes: Vec<Bound<'py, PyAny>> = raw
            .iter()
            .filter_map(|r| r.as_ref().ok())
            .map(|a| a.getattr("shape"))
            .collect::<PyResult<_>>()?;
        let all_numbers = shapes.is_empty();
        let shape: Vec<usize> = np
            .call_method1("broadcast_shapes", PyTuple::new(py, shapes)?)
            .map_err(|e| {
                PyValueError::new_err(format!("the arguments do not broadcast together: {e}"))
            })?
            .extract()?;
        let target = PyTuple::new(py, &shape)?;
        let mut args = Vec::with_capacity(raw.len());
        for r in raw {
            args.push(match r {
                Err(x) => Arg::Number(x),
                Ok(a) => {
                    let a = a.cast_into::<PyArrayDyn<f64>>()?;
                    // Copied only when it must be: another shape, or not C-contiguous.
                    let a = if a.shape() == shape.as_slice() && a.is_c_contiguous() {
                        a
                    } else {
                        let a = np.call_method1("broadcast_to", (a, &target))?;
                        np.call_method1("ascontiguousarray", (a,))?
                            .cast_into::<PyArrayDyn<f64>>()?
                    };
                    Arg::Array(a.readonly())
                }
            });
        }
        let time = args.pop().unwrap_or(Arg::Number(0.0));
        Ok(Inputs {
            args,
            time,
            shape,
            all_numbers,
        })
    }

    /// Evaluates `e` at every point on up to `threads` threads, the GIL released, and
    /// shapes the result.
    pub fn evaluate(
        &self,
        py: Python<'py>,
        e: &Expression,
        threads: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        let columns: Vec<Column> = self.args.iter().map(column).collect::<PyResult<_>>()?;
        let time = column(&self.time)?;
        let points: usize = self.shape.iter().product();
        let k = e.outputs();
        // numpy's own allocation, not a Rust Vec handed over: numpy asks the kernel for
        // huge pages on large arrays, where a fresh Vec of 10⁶ points took a page fault
        // every 4 KiB, which cost as much as evaluating `arith` (benches/python).
        let flat = PyArray1::<f64>::zeros(py, points * k, false);
        if points > 0 {
            let mut guard = flat.readwrite();
            let out = guard.as_slice_mut()?;
            py.detach(|| eval_split(e, &columns, time, out, points, threads))
                .map_err(|x| expr_error(py, e.text(), x))?;
        }
        if self.all_numbers && k == 1 {
            let value = flat.readonly().as_slice()?[0];
            return Ok(value.into_pyobject(py)?.into_any());
        }
        let mut shape = self.shape.clone();
        if k > 1 {
            shape.push(k);
        }
        Ok(flat.reshape(shape)?.into_any())
    }
}

/// The fewest points a thread of a split evaluation takes: below some 64 000 points the
/// cost of starting a thread (tens of microseconds) is a large part of the work.
pub const POINTS_PER_THREAD: usize = 1 << 16;

/// The number of threads `threads=` asks for: None is every core the process may use
/// (as numexpr's default), a number at least 1.
pub fn thread_count(threads: Option<usize>) -> usize {
    threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1)
}

/// `e.eval_columns` over `points` points cut into contiguous chunks of at least
/// [`POINTS_PER_THREAD`], one per thread (at most `threads`): each chunk reads its slice
/// of every column and writes its slice of `out`, so the bits are those of one thread.
fn eval_split(
    e: &Expression,
    columns: &[Column],
    time: Column,
    out: &mut [f64],
    points: usize,
    threads: usize,
) -> Result<usize, mbfx::session::expression::ExprError> {
    let chunks = threads.min(points / POINTS_PER_THREAD).max(1);
    if chunks == 1 {
        return e.eval_columns(columns, time, out);
    }
    let k = e.outputs();
    let per = points.div_ceil(chunks);
    std::thread::scope(|scope| {
        let work: Vec<_> = out
            .chunks_mut(per * k)
            .enumerate()
            .map(|(i, part)| {
                let (from, to) = (i * per, (i * per + part.len() / k).min(points));
                let cols: Vec<Column> = columns.iter().map(|c| slice(c, from, to)).collect();
                let t = slice(&time, from, to);
                scope.spawn(move || e.eval_columns(&cols, t, part))
            })
            .collect();
        let mut done = 0;
        for w in work {
            done += w.join().unwrap_or_else(|p| std::panic::resume_unwind(p))?;
        }
        Ok(done)
    })
}

/// Points `from..to` of `c`.
fn slice<'a>(c: &Column<'a>, from: usize, to: usize) -> Column<'a> {
    match c {
        Column::Const(x) => Column::Const(*x),
        Column::Values(v) => Column::Values(&v[from..to]),
    }
}
