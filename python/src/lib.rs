//! The native part of the Python module `mbfx` (`mbfx._mbfx`): expressions compiled
//! over named variables (`expression`) and evaluated over numpy arrays (`arrays`),
//! datasets loaded and checked (`model`, their GRAPHICS listed by `graphics`) and run
//! (`run`, their animation kept by `animation`) or stepped (`simulation`), and the exceptions (`errors`). It is a thin layer over `mbfx::session`:
//! every decision is the library's, so Python gives the command line's results bit for
//! bit. The pure-Python part (`python/mbfx/`) adds the `Run` object, pandas and plotting.

mod animation;
mod arrays;
mod errors;
mod expression;
mod graphics;
mod linear;
mod model;
mod run;
mod simulation;

use pyo3::prelude::*;

/// The module `mbfx._mbfx`.
#[pymodule]
fn _mbfx(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MbfxError", py.get_type::<errors::MbfxError>())?;
    m.add("CheckError", py.get_type::<errors::CheckError>())?;
    m.add("RunError", py.get_type::<errors::RunError>())?;
    m.add("InternalError", py.get_type::<errors::InternalError>())?;
    m.add_class::<errors::PyDiagnostic>()?;
    m.add_class::<expression::PyExpression>()?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<model::PyReport>()?;
    m.add_class::<animation::PyRecording>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<simulation::PySimulationInputs>()?;
    m.add_class::<simulation::PySimulationState>()?;
    m.add_function(wrap_pyfunction!(expression::compile, m)?)?;
    m.add_function(wrap_pyfunction!(expression::_rebuild_expression, m)?)?;
    m.add_function(wrap_pyfunction!(model::load, m)?)?;
    m.add_function(wrap_pyfunction!(model::_load_text, m)?)?;
    m.add_function(wrap_pyfunction!(model::_panic_for_tests, m)?)?;
    m.add_function(wrap_pyfunction!(errors::_rebuild_diagnostic, m)?)?;
    m.add_function(wrap_pyfunction!(model::_rebuild_report, m)?)?;
    Ok(())
}
