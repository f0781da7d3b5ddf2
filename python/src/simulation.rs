//! `Model.simulation()`: a model stepped from Python ([`mbfx::session::stepping`]):
//! `advance(t)`, `time`, `outputs` (a dict), `inputs` (a mapping whose items are set),
//! `state()` / `restore()` and `reset()`. An advance runs on the calling thread with
//! the GIL held (the stepped model is not shared with other threads); Ctrl-C is looked
//! at every few steps and stops it at the last accepted step with `KeyboardInterrupt`.
//! A failure raises `RunError` with the time and the element, worded as `run` words it.

use crate::errors::guarded;
use crate::run::run_error;
use mbfx::mbd::dynamics::DynError;
use mbfx::session::stepping::{Snapshot, Stepping};
use mbfx::session::stopped::Stopped;
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::cell::Cell;

/// Integration steps between two looks at Python's signals (a look is a call into the
/// interpreter; a step of the smallest models a microsecond or two).
const STEPS_PER_SIGNAL_CHECK: u32 = 64;

/// A model being stepped. Build it with `Model.simulation(...)`.
#[pyclass(unsendable, module = "mbfx", name = "Simulation")]
pub struct PySimulation {
    stepping: Stepping,
}

impl PySimulation {
    /// The stepping of a request `Model.simulation` made.
    pub fn new(stepping: Stepping) -> PySimulation {
        PySimulation { stepping }
    }
}

#[pymethods]
impl PySimulation {
    /// The simulation time.
    #[getter]
    fn time(&self) -> f64 {
        self.stepping.time()
    }

    /// Integrates to `t` (its own steps between, switches located), the inputs held.
    /// A time behind `time` is a `ValueError`; `t == time` does nothing.
    fn advance(&mut self, py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<()> {
        guarded(|| {
            let t = crate::run::real(Some(t), "t")?.unwrap_or(f64::NAN);
            let now = self.stepping.time();
            if !t.is_finite() || t < now {
                return Err(PyValueError::new_err(format!(
                    "t={t} must be a finite time at or after the simulation's time {now}"
                )));
            }
            let calls = Cell::new(0u32);
            let signal: Cell<Option<PyErr>> = Cell::new(None);
            let ask = || -> bool {
                calls.set(calls.get().wrapping_add(1));
                if !calls.get().is_multiple_of(STEPS_PER_SIGNAL_CHECK) {
                    return false;
                }
                match py.check_signals() {
                    Ok(()) => false,
                    Err(e) => {
                        signal.set(Some(e));
                        true
                    }
                }
            };
            let result = self.stepping.advance_interruptible(t, Some(&ask));
            match result {
                Ok(()) => Ok(()),
                Err(Stopped::Dynamics(DynError::Interrupted { .. })) => {
                    Err(signal.take().unwrap_or_else(|| {
                        pyo3::exceptions::PyKeyboardInterrupt::new_err(
                            "the advance was interrupted",
                        )
                    }))
                }
                Err(e) => {
                    let failed = self.stepping.failure(e);
                    Err(run_error(py, &failed, None)?)
                }
            }
        })
    }

    /// The outputs at `time`: the POUTPUT VARIABLEs, then the probes ({name: value}).
    #[getter]
    fn outputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in self
            .stepping
            .output_names()
            .iter()
            .zip(self.stepping.outputs())
        {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// The outputs' names, in order.
    #[getter]
    fn output_names<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, self.stepping.output_names())
    }

    /// The inputs: a mapping of the PINPUT VARIABLEs (`sim.inputs["u"] = 1.5` holds
    /// from `time`); any design variable may be set through it too.
    #[getter]
    fn inputs(slf: Py<PySimulation>) -> PySimulationInputs {
        PySimulationInputs { sim: slf }
    }

    /// The state now, to come back to with `restore`.
    fn state(&self) -> PySimulationState {
        PySimulationState {
            snapshot: self.stepping.state(),
        }
    }

    /// Back to `state` (from this simulation's `state()`): its time, state, inputs and
    /// outputs; the integrator starts afresh there.
    fn restore(&mut self, state: &PySimulationState) {
        self.stepping.restore(&state.snapshot);
    }

    /// Back to the start: t = 0, the inputs at the dataset's values.
    fn reset(&mut self) {
        self.stepping.reset();
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation(time={}, inputs={:?}, outputs={:?})",
            self.stepping.time(),
            self.stepping.input_names(),
            self.stepping.output_names()
        )
    }
}

/// The inputs of a `Simulation`: the PINPUT VARIABLEs by name (iteration, `len`,
/// `keys`, `items`); any design variable may be read or set by its name or as
/// `VARIABLE/id`.
#[pyclass(unsendable, module = "mbfx", name = "SimulationInputs")]
pub struct PySimulationInputs {
    sim: Py<PySimulation>,
}

#[pymethods]
impl PySimulationInputs {
    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<f64> {
        let sim = self.sim.borrow(py);
        sim.stepping.input(name).map_err(PyKeyError::new_err)
    }

    fn __setitem__(&self, py: Python<'_>, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let value = crate::run::real(Some(value), name)?
            .ok_or_else(|| PyTypeError::new_err(format!("{name} must be a number, not None")))?;
        let mut sim = self.sim.borrow_mut(py);
        sim.stepping
            .set_input(name, value)
            .map_err(|why| match why.starts_with("no input") {
                true => PyKeyError::new_err(why),
                false => PyValueError::new_err(why),
            })
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.sim.borrow(py).stepping.input_names().len()
    }

    fn __contains__(&self, py: Python<'_>, name: &str) -> bool {
        self.sim.borrow(py).stepping.input(name).is_ok()
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.keys(py)?.try_iter().map(Bound::into_any)
    }

    /// The PINPUT VARIABLEs' names.
    fn keys<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, self.sim.borrow(py).stepping.input_names())
    }

    /// (name, value) of each PINPUT VARIABLE.
    fn items<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let sim = self.sim.borrow(py);
        let s = &sim.stepping;
        let items: Vec<(String, f64)> = (s.input_names().iter())
            .map(|n| (n.clone(), s.input(n).unwrap_or(f64::NAN)))
            .collect();
        PyList::new(py, items)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let sim = self.sim.borrow(py);
        let s = &sim.stepping;
        let items: Vec<String> = (s.input_names().iter())
            .map(|n| format!("{n:?}: {}", s.input(n).unwrap_or(f64::NAN)))
            .collect();
        format!("{{{}}}", items.join(", "))
    }
}

/// A `Simulation`'s state at one time (`Simulation.state()`), for `restore`. It does
/// not pickle: it holds the built system's state.
#[pyclass(unsendable, frozen, module = "mbfx", name = "SimulationState")]
pub struct PySimulationState {
    snapshot: Snapshot,
}

#[pymethods]
impl PySimulationState {
    /// Its time.
    #[getter]
    fn time(&self) -> f64 {
        self.snapshot.time()
    }

    fn __repr__(&self) -> String {
        format!("SimulationState(time={})", self.snapshot.time())
    }
}
