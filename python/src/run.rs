//! `Model.run`: a [`RunRequest`] built from `mbfx run`'s arguments, run by
//! `mbfx::session::request::run` on the calling thread without the GIL, so that other
//! Python threads go on. Every 50 ms (looked at every few integration steps) the run takes
//! the GIL back for a moment to move the progress bar and to let Python see Ctrl-C; a
//! signal handler's exception stops the run within a step, and on `KeyboardInterrupt` the
//! rows so far come back as `.run`. (Runs went to a pooled thread before: the two
//! handoffs cost 0.03 to 0.3 ms a run here, a tenth of a short variant.)
//! Rows cross as one flat vector; the `Run` object is the pure-Python `mbfx.Run`, which
//! keeps the animation the run recorded ([`crate::animation`]).

use crate::animation::PyRecording;
use crate::errors::{diagnostic_list, RunError};
use mbfx::session::animation::Animation;
use mbfx::session::request::{run, Formulation, RunFailed, RunRequest};
use mbfx::session::run::{Method, Summary};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyTypeError, PyValueError};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyBool, PyDict, PyInt, PyList};
use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// How often the waiting thread looks at Ctrl-C and the progress bar.
const POLL: Duration = Duration::from_millis(50);

/// The integrator named by `name`, as `mbfx run --integrator` spells it.
pub fn method_of(name: &str) -> PyResult<Method> {
    Ok(match name.to_ascii_lowercase().as_str() {
        "gstiff" => Method::Gstiff,
        "wstiff" => Method::Wstiff,
        "hht" => Method::Hht,
        "galpha" | "generalized-alpha" => Method::Galpha,
        "newmark" => Method::Newmark,
        "dopri853" => Method::Dopri853,
        _ => {
            return Err(PyValueError::new_err(format!(
                "integrator must be one of gstiff, wstiff, hht, galpha, newmark, dopri853; not {name:?}"
            )))
        }
    })
}

/// The BDF formulation named by `name` (`"i3"` or `"si2"`).
pub fn formulation_of(name: &str) -> PyResult<Formulation> {
    match name.to_ascii_lowercase().as_str() {
        "i3" => Ok(Formulation::I3),
        "si2" => Ok(Formulation::Si2),
        f => Err(PyValueError::new_err(format!(
            "formulation must be \"i3\" or \"si2\", not {f:?}"
        ))),
    }
}

/// Whether ERROR bounds each step (`"step"`, as Adams) or the whole run (`"run"`).
pub fn error_per_run(name: &str) -> PyResult<bool> {
    match name.to_ascii_lowercase().as_str() {
        "step" => Ok(false),
        "run" => Ok(true),
        e => Err(PyValueError::new_err(format!(
            "error_per must be \"step\" or \"run\", not {e:?}"
        ))),
    }
}

/// `estimate_error=`: None or False; True or "rerun" (the second run at ERROR/10); "steps" (the
/// error carried through the steps). Returns (rerun, carry).
pub fn estimate_of(value: Option<&Bound<'_, PyAny>>) -> PyResult<(bool, bool)> {
    let Some(value) = value else {
        return Ok((false, false));
    };
    if let Ok(on) = value.extract::<bool>() {
        return Ok((on, false));
    }
    match value.extract::<String>().as_deref() {
        Ok("rerun") => Ok((true, false)),
        Ok("steps") => Ok((false, true)),
        _ => Err(PyValueError::new_err(format!(
            "estimate_error={} must be True, False, \"rerun\" or \"steps\"",
            value.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))),
    }
}

/// The number a keyword argument `name=` holds (a float, an int, numpy's scalars), or
/// None when it was not given: a str or another object is a `TypeError` naming the
/// argument (pyo3's own said "must be real number, not str" without saying which).
pub fn real(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<f64>> {
    let Some(v) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if v.is_instance_of::<PyBool>() || v.is_instance_of::<pyo3::types::PyString>() {
        return Err(number_expected(v, name));
    }
    v.extract::<f64>()
        .map(Some)
        .map_err(|_| number_expected(v, name))
}

fn number_expected(v: &Bound<'_, PyAny>, name: &str) -> PyErr {
    let kind = v
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    let shown = v.repr().map_or_else(|_| kind.clone(), |r| r.to_string());
    PyTypeError::new_err(format!(
        "{name} must be a number (a float or an int), not {kind} {shown}"
    ))
}

/// `request`'s numbers checked as `mbfx run` checks its options, the refusal worded for
/// Python: a `ValueError` naming the keyword (`end=-1 must be a positive time`), not
/// the option (`--end -1 ... (command line)`); with `end_required`, a missing `end` too.
pub fn check_arguments(request: &RunRequest, end_required: bool) -> PyResult<()> {
    if end_required && request.end.is_none() {
        return Err(PyValueError::new_err(
            "end is required: the time to run to, e.g. Model.run(end=1.0)",
        ));
    }
    match request.validate() {
        Ok(()) => Ok(()),
        Err(d) => Err(PyValueError::new_err(keyword_words(&d.message))),
    }
}

/// A command-line refusal `--some-option VALUE rest` as `some_option=VALUE rest`.
fn keyword_words(message: &str) -> String {
    let Some(rest) = message.strip_prefix("--") else {
        return message.to_string();
    };
    let (option, rest) = rest.split_once(' ').unwrap_or((rest, ""));
    // `--interpolate FPS` is the frame rate an animation records at.
    let name = match option {
        "interpolate" => "fps".to_string(),
        o => o.replace('-', "_"),
    };
    match rest.split_once(' ') {
        Some((value, tail)) if !value.starts_with(|c: char| c.is_ascii_alphabetic()) => {
            format!("{name}={value} {tail}")
        }
        _ => format!("{name} {rest}"),
    }
}

/// The probes of a dict, in its order.
pub fn probes_of(probes: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, String)>> {
    let mut out = Vec::new();
    if let Some(p) = probes {
        for (name, expr) in p.iter() {
            out.push((name.extract()?, expr.extract()?));
        }
    }
    Ok(out)
}

/// The settings of a dict `{"KIND/ID.FIELD": value}` as `--set` takes them: a number
/// written exactly (shortest round trip), a str (an expression, a word) as given.
pub fn settings_of(values: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let mut out = Vec::new();
    for (key, value) in values.into_iter().flat_map(|v| v.iter()) {
        let key: String = key.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "a setting's key is a str such as \"PART/2.MASS\", not {key:?}"
            ))
        })?;
        let written = if value.is_instance_of::<PyBool>() {
            return Err(PyTypeError::new_err(format!(
                "{key}: a value is a number or a str, not a bool"
            )));
        } else if value.is_instance_of::<PyInt>() {
            value.str()?.to_string()
        } else if let Ok(text) = value.extract::<String>() {
            text
        } else if let Ok(x) = value.extract::<f64>() {
            // Floats and numpy's scalars; Rust's `{:?}` is the shortest exact form.
            format!("{x:?}")
        } else {
            return Err(PyTypeError::new_err(format!(
                "{key}: a value is a number or a str, not {}",
                value.get_type().name()?
            )));
        };
        out.push(format!("{key}={written}"));
    }
    Ok(out)
}

/// Integration steps between two looks at the clock: a look costs some 25 ns, a step of
/// the smallest models a microsecond or two.
const STEPS_PER_CLOCK: u32 = 8;

/// Runs `request` on the calling thread without the GIL (see the module docs) and
/// returns an `mbfx.Run`, or raises `RunError` / `KeyboardInterrupt` carrying the rows so
/// far as `.run`.
/// `animate_later`: a run that records no animation still keeps its request, so that
/// `Run.animate()` can run it again with recording on.
pub fn run_model(
    py: Python<'_>,
    request: &RunRequest,
    progress: bool,
    animate_later: bool,
) -> PyResult<Py<PyAny>> {
    let bar: Option<Py<PyAny>> = match progress {
        true => Some(
            py.import("mbfx")?
                .getattr("_Progress")?
                .call1((request.end.unwrap_or(0.0),))?
                .unbind(),
        ),
        false => None,
    };
    // The time of the last row, for the progress bar.
    let reached = AtomicU64::new(0f64.to_bits());
    let (rows, seconds, result, stop) = py.detach(|| {
        let mut rows = Vec::new();
        let mut sink = |row: &[f64]| -> std::io::Result<()> {
            rows.extend_from_slice(row);
            reached.store(row[0].to_bits(), Ordering::Relaxed);
            Ok(())
        };
        // What stopped the run from Python: a signal handler's exception (Ctrl-C's
        // KeyboardInterrupt) or the progress bar's.
        let stop: RefCell<Option<PyErr>> = RefCell::new(None);
        let (calls, next) = (Cell::new(0u32), Cell::new(Instant::now() + POLL));
        let ask = || -> bool {
            if stop.borrow().is_some() {
                return true;
            }
            calls.set(calls.get().wrapping_add(1));
            if !calls.get().is_multiple_of(STEPS_PER_CLOCK) || Instant::now() < next.get() {
                return false;
            }
            next.set(Instant::now() + POLL);
            let t = f64::from_bits(reached.load(Ordering::Relaxed));
            let looked = Python::attach(|py| {
                if let Some(bar) = &bar {
                    bar.call_method1(py, "update", (t,))?;
                }
                py.check_signals()
            });
            let stopped = looked.is_err();
            *stop.borrow_mut() = looked.err();
            stopped
        };
        let clock = Instant::now();
        let result = run(request, &mut sink, Some(&ask));
        let seconds = clock.elapsed().as_secs_f64();
        (rows, seconds, result, stop.into_inner())
    });
    // KeyboardInterrupt comes back with the rows; any other exception as it is.
    let stopped_by_user = match stop {
        Some(e) if e.is_instance_of::<PyKeyboardInterrupt>(py) => true,
        Some(e) => return Err(e),
        None => false,
    };
    if let Some(bar) = &bar {
        let t = f64::from_bits(reached.load(Ordering::Relaxed));
        bar.call_method1(py, "update", (t,))?;
        bar.call_method0(py, "close")?;
    }
    match result {
        // Ctrl-C as the run ended: Python still hears it, with the whole run.
        Ok(done) if stopped_by_user => {
            let recording = recording_of(request, done.animation, animate_later);
            let run = run_object(
                py,
                (&done.header, &done.units),
                rows,
                Some(&done.summary),
                seconds,
                "",
                recording,
            )?;
            let e = PyKeyboardInterrupt::new_err("the run was interrupted as it ended");
            e.value(py).setattr("run", run)?;
            Err(e)
        }
        Ok(done) => run_object(
            py,
            (&done.header, &done.units),
            rows,
            Some(&done.summary),
            seconds,
            &done.dim_reason,
            recording_of(request, done.animation, animate_later),
        ),
        Err(mut failed) => {
            let header = failed.header.clone().unwrap_or_else(|| vec!["time".into()]);
            let units = failed.units.clone().unwrap_or_default();
            let recording = recording_of(request, failed.animation.take(), animate_later);
            let partial = match failed.header {
                Some(_) => Some(run_object(
                    py,
                    (&header, &units),
                    rows,
                    failed.summary.as_ref(),
                    seconds,
                    "",
                    recording,
                )?),
                None => None,
            };
            if stopped_by_user {
                let e = PyKeyboardInterrupt::new_err(format!(
                    "the run was interrupted at t = {}",
                    failed.time.unwrap_or(0.0)
                ));
                e.value(py).setattr("run", partial)?;
                return Err(e);
            }
            Err(run_error(py, &failed, partial)?)
        }
    }
}

/// `RunError` for `failed`, carrying the partial run.
pub fn run_error(
    py: Python<'_>,
    failed: &RunFailed,
    partial: Option<Py<PyAny>>,
) -> PyResult<PyErr> {
    let e = RunError::new_err(failed.render(false).trim_end().to_string());
    let v = e.value(py);
    v.setattr("time", failed.time)?;
    v.setattr("element", failed.element.clone())?;
    v.setattr("cause", failed.cause.clone())?;
    v.setattr("code", failed.code.as_str())?;
    v.setattr("probe", failed.probe.clone())?;
    v.setattr(
        "diagnostics",
        diagnostic_list(py, &failed.diagnostics, &failed.source)?,
    )?;
    v.setattr("run", partial)?;
    Ok(e)
}

/// The recording of a run of `request`: the animation it recorded, or none but the
/// request to record one by running it again (`animate_later`), or nothing.
fn recording_of(
    request: &RunRequest,
    animation: Option<Animation>,
    animate_later: bool,
) -> Option<PyRecording> {
    (animation.is_some() || animate_later).then(|| PyRecording::new(request, animation))
}

/// An `mbfx.Run` of `rows` (flat, `header.len()` a row), with the animation it recorded;
/// `units` holds each column's unit.
fn run_object(
    py: Python<'_>,
    (header, units): (&[String], &[String]),
    rows: Vec<f64>,
    summary: Option<&Summary>,
    session_seconds: f64,
    dim_reason: &str,
    recording: Option<PyRecording>,
) -> PyResult<Py<PyAny>> {
    let width = header.len().max(1);
    let n = rows.len() / width;
    let data = PyArray1::from_vec(py, rows).reshape([n, width])?;
    let stats = PyDict::new(py);
    // The whole session call (reading, building, compiling, integrating, outputs):
    // what Python adds is the wall time of `Model.run` less this.
    stats.set_item(intern!(py, "session_seconds"), session_seconds)?;
    let (mut warnings, mut notes, mut text, mut integrator) =
        (Vec::new(), Vec::new(), String::new(), "");
    if let Some(s) = summary {
        let st = &s.stats;
        stats.set_item(intern!(py, "steps"), st.steps)?;
        stats.set_item(intern!(py, "rejected"), st.rejected)?;
        stats.set_item(intern!(py, "newton_iterations"), st.newton_iterations)?;
        stats.set_item(intern!(py, "jacobian_evaluations"), st.jacobian_evaluations)?;
        stats.set_item(intern!(py, "factorizations"), st.factorizations)?;
        stats.set_item(
            intern!(py, "expression_evaluations"),
            st.expression_evaluations,
        )?;
        stats.set_item(intern!(py, "events"), st.events)?;
        stats.set_item(intern!(py, "cpu_seconds"), s.cpu_seconds)?;
        stats.set_item(intern!(py, "max_residual"), s.max_residual)?;
        // The simulation of the last run on this thread ran again (design values only).
        stats.set_item(intern!(py, "reused"), s.reused)?;
        if let Some(e) = &s.estimate {
            stats.set_item(intern!(py, "error_estimate"), e.error)?;
            stats.set_item(intern!(py, "estimate_cpu_seconds"), e.cpu_seconds)?;
        } else if let Some(k) = st.global_error {
            // Carried through the steps: the largest along the run, and where.
            stats.set_item(intern!(py, "error_estimate"), k)?;
            stats.set_item(intern!(py, "error_estimate_time"), st.global_error_time)?;
        }
        (warnings, notes) = (s.warnings.clone(), s.notes.clone());
        text = s.text();
        integrator = s.integrator;
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item(intern!(py, "warnings"), PyList::new(py, warnings)?)?;
    kwargs.set_item(intern!(py, "notes"), PyList::new(py, notes)?)?;
    kwargs.set_item(intern!(py, "summary"), text)?;
    kwargs.set_item(intern!(py, "integrator"), integrator)?;
    kwargs.set_item(intern!(py, "dimension"), dim_reason)?;
    kwargs.set_item(intern!(py, "units"), PyList::new(py, units)?)?;
    if let Some(r) = recording {
        kwargs.set_item(intern!(py, "_recording"), Py::new(py, r)?)?;
    }
    // Looked up once: a run's Python share is a few microseconds, and a lookup by name
    // is one of them.
    static RUN: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let class = RUN.get_or_try_init(py, || py.import("mbfx")?.getattr("Run").map(Bound::unbind))?;
    let run = class
        .bind(py)
        .call((header.to_vec(), data, stats), Some(&kwargs))?;
    Ok(run.unbind())
}
