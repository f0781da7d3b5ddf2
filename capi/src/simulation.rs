//! `mbfx_simulation`: a dataset stepped from C ([`mbfx::session::stepping`]): made from
//! the dataset's text with the integrator, ERROR, output step, probes and settings `mbfx
//! run` takes, advanced to a time, its outputs read and its inputs set between, its
//! state saved and restored, reset to the start. Failures are statuses with an
//! `mbfx_error` saying why (a run's failure as `MBFX_STATUS_RUN_FAILED`, with the time
//! and the element in its message and report).

use crate::error::{c_string, hand_over};
use crate::{args, Error, Status};
use mbfx::session::request::{parse_probe, RunFailed, RunRequest};
use mbfx::session::run::Method;
use mbfx::session::stepping::{Snapshot, Stepping};
use std::ffi::{c_char, CString};

/// A dataset being stepped (`mbfx_simulation` in C): made by `mbfx_simulation_new`,
/// owned by the caller, freed with `mbfx_simulation_free`. One thread uses it at a time.
pub struct Simulation {
    inner: Stepping,
    output_names: Vec<CString>,
    input_names: Vec<CString>,
}

/// A simulation's state at one time (`mbfx_simulation_state` in C): made by
/// `mbfx_simulation_state_save`, restored by `mbfx_simulation_state_restore` into the
/// simulation it came from, freed with `mbfx_simulation_state_free`.
pub struct SimulationState {
    inner: Snapshot,
}

/// The error a request or a stepping failed with.
fn run_failed(failed: &RunFailed) -> Error {
    let position = (failed.diagnostics.iter())
        .find(|d| d.is_error())
        .filter(|_| !failed.source.text.is_empty())
        .map(|d| failed.source.line_col(d.span.start));
    Error::with_code(
        Status::RunFailed,
        failed.code.as_str(),
        failed.cause.clone(),
        failed.render(false),
        position,
    )
}

/// The integrator `name` names, as `mbfx run --integrator` spells it.
fn method(name: &str) -> Result<Method, Error> {
    Ok(match name.to_ascii_lowercase().as_str() {
        "gstiff" => Method::Gstiff,
        "wstiff" => Method::Wstiff,
        "hht" => Method::Hht,
        "galpha" => Method::Galpha,
        "newmark" => Method::Newmark,
        "dopri853" => Method::Dopri853,
        _ => {
            return Err(Error::new(
                Status::InvalidArgument,
                format!(
                    "unknown integrator {name:?}: gstiff, wstiff, hht, galpha, newmark or dopri853"
                ),
            ))
        }
    })
}

/// A positive number given, or none (0 or less, or NaN: the default).
fn given(x: f64) -> Option<f64> {
    (x > 0.0).then_some(x)
}

/// Builds the dataset `dataset_text` for stepping, as `mbfx run` builds it with
/// `--integrator integrator` (NULL: the dataset's INTEGRATOR, else GSTIFF), `--error
/// error` and `--output-step output_step` (0 or less for the default: ERROR the
/// dataset's or 1e-3; HMAX and HINIT follow the output step, and without one the first
/// advance's interval), `--probe probes[i]` (`"NAME=EXPR"`) and `--set settings[i]`
/// (`"KIND/ID.FIELD=VALUE"`). Its outputs are the dataset's POUTPUT VARIABLEs, then the
/// probes; its inputs the PINPUT VARIABLEs. Advancing it to `mbfx run`'s output times
/// gives `mbfx run`'s rows bit for bit.
///
/// Returns a new simulation at t = 0 (freed with `mbfx_simulation_free`), or NULL; when
/// `error` is not NULL, `*error` is NULL on success, else a new error:
/// `MBFX_STATUS_RUN_FAILED` (the dataset or a probe has errors, or the model does not
/// build: code, message and report as `mbfx run` prints them), `_NULL_ARGUMENT`,
/// `_INVALID_UTF8`, `_INVALID_ARGUMENT` (an unknown integrator, a bad number).
///
/// # Safety
/// `dataset_text` and `integrator` are NULL or NUL-terminated strings; `probes` and
/// `settings` are NULL or hold `n_probes` and `n_settings` pointers to such strings;
/// `error` is NULL or points to writable storage for a pointer.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)] // one per option of `mbfx run` a stepping takes
pub unsafe extern "C" fn mbfx_simulation_new(
    dataset_text: *const c_char,
    integrator: *const c_char,
    error_tolerance: f64,
    output_step: f64,
    probes: *const *const c_char,
    n_probes: usize,
    settings: *const *const c_char,
    n_settings: usize,
    error: *mut *mut Error,
) -> *mut Simulation {
    let result = args::catch(|| {
        // SAFETY: NULL or a NUL-terminated string (the caller's word).
        let text = unsafe { args::string(dataset_text, "the dataset text") }?;
        // SAFETY: as above.
        let probes = unsafe { args::strings(probes, n_probes, "probes") }?;
        // SAFETY: as above.
        let settings = unsafe { args::strings(settings, n_settings, "settings") }?;
        let mut request = RunRequest::dataset("dataset", text);
        if !integrator.is_null() {
            // SAFETY: as above.
            request.method = Some(method(unsafe {
                args::string(integrator, "the integrator")
            }?)?);
        }
        request.error = given(error_tolerance);
        request.output_step = given(output_step);
        request.probes = probes.iter().map(|p| parse_probe(p)).collect();
        request.set = settings.iter().map(|s| s.to_string()).collect();
        let inner = Stepping::new(&request).map_err(|f| run_failed(&f))?;
        let names = |v: &[String]| v.iter().map(|n| c_string(n.as_str())).collect();
        Ok(Simulation {
            output_names: names(inner.output_names()),
            input_names: names(inner.input_names()),
            inner,
        })
    });
    // SAFETY: NULL or storage for a pointer (the caller's word).
    unsafe { hand_over(result, error) }
}

/// Stores the failure of `result` in `*error` (NULL on success; nothing when `error` is
/// NULL) and returns its status.
///
/// # Safety
/// `error` is NULL or points to writable storage for a pointer.
unsafe fn with_error(result: Result<(), Error>, error: *mut *mut Error) -> Status {
    let status = result.as_ref().err().map_or(Status::Ok, Error::status);
    // SAFETY: the caller's word, as this function's. (A boxed `()` allocates nothing.)
    unsafe { hand_over(result, error) };
    status
}

/// Integrates `sim` to time `t` (its own steps between, switches located), the inputs
/// held; `t` equal to the current time does nothing. Returns `MBFX_STATUS_OK`, or:
/// `_RUN_FAILED` (the integration failed: the error's message and report give the time
/// and the element; every later advance fails the same until a restore or reset),
/// `_INVALID_ARGUMENT` (`t` behind the current time, or not finite), `_NULL_ARGUMENT`.
/// `error` as for `mbfx_simulation_new` (NULL: no error object).
///
/// # Safety
/// `sim` is NULL or a live simulation that no other thread uses; `error` is NULL or
/// points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_advance(
    sim: *mut Simulation,
    t: f64,
    error: *mut *mut Error,
) -> Status {
    let result = args::catch(|| {
        // SAFETY: NULL or a live simulation used by this thread alone (the caller's word).
        let sim = unsafe { args::object_mut(sim, "the simulation") }?;
        let now = sim.inner.time();
        if !(t.is_finite() && t >= now) {
            return Err(Error::new(
                Status::InvalidArgument,
                format!("t = {t} must be a finite time at or after the simulation's time {now}"),
            ));
        }
        sim.inner
            .advance(t)
            .map_err(|e| run_failed(&sim.inner.failure(e)))
    });
    // SAFETY: the caller's word, as this function's.
    unsafe { with_error(result, error) }
}

/// The simulation time of `sim`; NaN for NULL.
///
/// # Safety
/// `sim` is NULL or a live simulation.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_time(sim: *const Simulation) -> f64 {
    // SAFETY: the caller's word, as this function's.
    unsafe { args::object(sim, "the simulation") }.map_or(f64::NAN, |s| s.inner.time())
}

/// How many outputs `sim` has: its POUTPUT VARIABLEs, then its probes. 0 for NULL.
///
/// # Safety
/// `sim` is NULL or a live simulation.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_output_count(sim: *const Simulation) -> usize {
    // SAFETY: the caller's word, as this function's.
    unsafe { args::object(sim, "the simulation") }.map_or(0, |s| s.output_names.len())
}

/// The name of output `k` (a POUTPUT VARIABLE's `adams_view_name`, else `VARIABLE/id`;
/// a probe's name); NULL for NULL or `k` out of range. Owned by the simulation.
///
/// # Safety
/// `sim` is NULL or a live simulation.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_output_name(
    sim: *const Simulation,
    k: usize,
) -> *const c_char {
    // SAFETY: the caller's word, as this function's.
    let sim = unsafe { args::object(sim, "the simulation") };
    (sim.ok().and_then(|s| s.output_names.get(k))).map_or(std::ptr::null(), |n| n.as_ptr())
}

/// Copies the outputs at the current time into `out[0..n]`; `n` must be
/// `mbfx_simulation_output_count(sim)` (`MBFX_STATUS_BAD_LENGTH` otherwise).
///
/// # Safety
/// `sim` is NULL or a live simulation; `out` is NULL or points to `n` writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_outputs(
    sim: *const Simulation,
    out: *mut f64,
    n: usize,
) -> Status {
    args::status(args::catch(|| {
        // SAFETY: the caller's word, as this function's.
        let sim = unsafe { args::object(sim, "the simulation") }?;
        let values = sim.inner.outputs();
        if n != values.len() {
            return Err(Error::new(
                Status::BadLength,
                format!(
                    "out has {n} values; the simulation has {} outputs",
                    values.len()
                ),
            ));
        }
        // SAFETY: NULL (refused unless n is 0) or n writable doubles (the caller's word).
        let out = unsafe { args::slice_mut(out, n, "out") }?;
        out.copy_from_slice(values);
        Ok(())
    }))
}

/// How many inputs `sim` has: its PINPUT VARIABLEs. 0 for NULL.
///
/// # Safety
/// `sim` is NULL or a live simulation.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_input_count(sim: *const Simulation) -> usize {
    // SAFETY: the caller's word, as this function's.
    unsafe { args::object(sim, "the simulation") }.map_or(0, |s| s.input_names.len())
}

/// The name of input `k` (a PINPUT VARIABLE's `adams_view_name`, else `VARIABLE/id`);
/// NULL for NULL or `k` out of range. Owned by the simulation.
///
/// # Safety
/// `sim` is NULL or a live simulation.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_input_name(
    sim: *const Simulation,
    k: usize,
) -> *const c_char {
    // SAFETY: the caller's word, as this function's.
    let sim = unsafe { args::object(sim, "the simulation") };
    (sim.ok().and_then(|s| s.input_names.get(k))).map_or(std::ptr::null(), |n| n.as_ptr())
}

/// Gives input `name` (a PINPUT VARIABLE's name, any case; or any design variable by its
/// `adams_view_name` or as `VARIABLE/id`) the value `value` from the current time on; a
/// changed value restarts the integrator at the next advance. Returns `MBFX_STATUS_OK`,
/// `_INVALID_ARGUMENT` (no such input, one that cannot be set, a value not finite: the
/// error says why), `_NULL_ARGUMENT`, `_INVALID_UTF8`.
///
/// # Safety
/// `sim` is NULL or a live simulation that no other thread uses; `name` is NULL or a
/// NUL-terminated string; `error` is NULL or points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_set_input(
    sim: *mut Simulation,
    name: *const c_char,
    value: f64,
    error: *mut *mut Error,
) -> Status {
    let result = args::catch(|| {
        // SAFETY: the caller's word, as this function's.
        let sim = unsafe { args::object_mut(sim, "the simulation") }?;
        // SAFETY: as above.
        let name = unsafe { args::string(name, "the input's name") }?;
        (sim.inner.set_input(name, value)).map_err(|why| Error::new(Status::InvalidArgument, why))
    });
    // SAFETY: the caller's word, as this function's.
    unsafe { with_error(result, error) }
}

/// The state of `sim` now (time, positions, velocities, inputs, state elements), to
/// restore with `mbfx_simulation_state_restore`; NULL for a NULL simulation. Freed with
/// `mbfx_simulation_state_free`.
///
/// # Safety
/// `sim` is NULL or a live simulation.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_state_save(
    sim: *const Simulation,
) -> *mut SimulationState {
    let result = args::catch(|| {
        // SAFETY: the caller's word, as this function's.
        let sim = unsafe { args::object(sim, "the simulation") }?;
        Ok(SimulationState {
            inner: sim.inner.state(),
        })
    });
    // SAFETY: a NULL error pointer is accepted.
    unsafe { hand_over(result, std::ptr::null_mut()) }
}

/// Puts `sim` back to `state` (saved from `sim`): its time, state and inputs; the
/// integrator starts afresh there (so advancing from one state gives the same bits each
/// time). A failure to start there is given by the next advance.
///
/// # Safety
/// `sim` is NULL or a live simulation that no other thread uses; `state` is NULL or a
/// live state saved from `sim`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_state_restore(
    sim: *mut Simulation,
    state: *const SimulationState,
) -> Status {
    args::status(args::catch(|| {
        // SAFETY: the caller's word, as this function's.
        let sim = unsafe { args::object_mut(sim, "the simulation") }?;
        // SAFETY: as above.
        let state = unsafe { args::object(state, "the state") }?;
        sim.inner.restore(&state.inner);
        Ok(())
    }))
}

/// Frees a state; NULL is accepted.
///
/// # Safety
/// `state` is NULL or a state from `mbfx_simulation_state_save` that has not been freed;
/// it is not used after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_state_free(state: *mut SimulationState) {
    if state.is_null() {
        return;
    }
    // SAFETY: from Box::into_raw in `hand_over`, freed once (the caller's word).
    let state = unsafe { Box::from_raw(state) };
    let _ = args::catch(move || {
        drop(state);
        Ok(())
    });
}

/// Puts `sim` back to its start: t = 0, the inputs at the dataset's values; advancing it
/// then gives the bits a new simulation gives.
///
/// # Safety
/// `sim` is NULL or a live simulation that no other thread uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_reset(sim: *mut Simulation) -> Status {
    args::status(args::catch(|| {
        // SAFETY: the caller's word, as this function's.
        let sim = unsafe { args::object_mut(sim, "the simulation") }?;
        sim.inner.reset();
        Ok(())
    }))
}

/// Frees a simulation; NULL is accepted. The names read from it die with it.
///
/// # Safety
/// `sim` is NULL or a simulation from `mbfx_simulation_new` that has not been freed; it
/// is not used after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn mbfx_simulation_free(sim: *mut Simulation) {
    if sim.is_null() {
        return;
    }
    // SAFETY: from Box::into_raw in `hand_over`, freed once (the caller's word).
    let sim = unsafe { Box::from_raw(sim) };
    let _ = args::catch(move || {
        drop(sim);
        Ok(())
    });
}
