//! `mbfx.load` and `Model`: a dataset read, built, assembled and analysed as `mbfx check`
//! does, its `Report` and its GRAPHICS ([`crate::graphics`]), expressions evaluated at
//! the assembled configuration, runs ([`crate::run`]) and steppings
//! ([`crate::simulation`]). A model keeps its dataset text: it pickles as that text and
//! rebuilds itself in a worker process.

use crate::errors::{check_error, diagnostic_list, guarded, int_in_range, plain_check_error};
use crate::expression::engine_of;
use crate::run;
use mbfx::diag::{has_errors, Diagnostic, SourceFile};
use mbfx::session::evaluate::{EvalError, Evaluator};
use mbfx::session::files::read_dataset;
use mbfx::session::graphics::Listed;
use mbfx::session::loaded::LoadedModel;
use mbfx::session::request::{set_values, LinearRequest, RunRequest};
use mbfx::session::{self, DimRequest};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::path::PathBuf;

/// The dimension asked for: None (2D when the scene is planar), 2 or 3.
pub fn dim_request(dim: Option<u8>) -> PyResult<DimRequest> {
    match dim {
        None => Ok(DimRequest::Auto),
        Some(2) => Ok(DimRequest::Two),
        Some(3) => Ok(DimRequest::Three),
        Some(d) => Err(PyValueError::new_err(format!(
            "dim must be 2, 3 or None, not {d}"
        ))),
    }
}

/// What `Model.check()` reports: the dimension and why, the degrees of freedom, and the
/// redundant constraints in Adams' words. `str()` is the report `mbfx check` prints.
#[pyclass(frozen, module = "mbfx", name = "Report")]
pub struct PyReport {
    /// 2 or 3: the dimension the system was built in.
    #[pyo3(get)]
    dimension: u8,
    /// Why that dimension, in words.
    #[pyo3(get)]
    dimension_reason: String,
    /// Degrees of freedom (from the rank of the constraint Jacobian).
    #[pyo3(get)]
    dof: usize,
    /// The Gruebler count (coordinates minus equations, redundant ones included).
    #[pyo3(get)]
    gruebler: i64,
    /// Scalar constraint equations.
    #[pyo3(get)]
    equations: usize,
    /// One line per redundant equation, in Adams Solver's words: `deactivating
    /// constraint equation  Zi.Xj in model.JOINT_2`.
    #[pyo3(get)]
    redundant: Vec<String>,
    /// A lighter element that would avoid each redundancy, one line per element.
    #[pyo3(get)]
    advice: Vec<String>,
    /// The dataset's warnings.
    #[pyo3(get)]
    warnings: Py<PyList>,
    text: String,
}

#[pymethods]
impl PyReport {
    fn __str__(&self) -> String {
        self.text.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Report(dimension={}, dof={}, redundant={})",
            self.dimension,
            self.dof,
            self.redundant.len()
        )
    }

    /// Pickled as its fields, so a report crosses a process boundary intact.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let rebuild = py.import("mbfx._mbfx")?.getattr("_rebuild_report")?;
        let fields = (
            self.dimension,
            &self.dimension_reason,
            self.dof,
            self.gruebler,
            self.equations,
            &self.redundant,
            &self.advice,
            self.warnings.clone_ref(py),
            &self.text,
        );
        Ok((rebuild, fields.into_pyobject(py)?))
    }
}

/// Unpickles a report (see `Report.__reduce__`).
#[pyfunction]
#[allow(clippy::too_many_arguments)] // one per field of the pickled report
pub fn _rebuild_report(
    dimension: u8,
    dimension_reason: String,
    dof: usize,
    gruebler: i64,
    equations: usize,
    redundant: Vec<String>,
    advice: Vec<String>,
    warnings: Py<PyList>,
    text: String,
) -> PyReport {
    PyReport {
        dimension,
        dimension_reason,
        dof,
        gruebler,
        equations,
        redundant,
        advice,
        warnings,
        text,
    }
}

/// A dataset (`.adm`), read and analysed. Build it with `mbfx.load`.
#[pyclass(frozen, module = "mbfx", name = "Model")]
pub struct PyModel {
    /// The dataset text.
    pub text: String,
    /// The name diagnostics show (the file, or `dataset`).
    pub name: String,
    /// The dimension asked for at load.
    pub dim: Option<u8>,
    title: String,
    parts: Vec<u32>,
    markers: Vec<(u32, u32)>,
    graphics: Vec<Listed>,
    report: Py<PyReport>,
}

/// Loads `source`: a path (str without a newline, or os.PathLike) or a dataset's text.
#[pyfunction]
#[pyo3(signature = (source, dim = None))]
pub fn load(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    dim: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyModel> {
    guarded(|| {
        let dim = dim.map(|d| int_in_range::<u8>(d, "dim")).transpose()?;
        let os = py.import("os")?;
        let is_path = source.is_instance(&os.getattr("PathLike")?)?;
        let text: Option<String> = if is_path {
            None
        } else {
            Some(source.extract::<String>().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(
                    "load takes a path (str or os.PathLike) or the dataset's text",
                )
            })?)
        };
        match text {
            Some(t) if t.contains('\n') => build(py, t, "dataset".into(), Vec::new(), dim),
            _ => {
                let path: PathBuf = match text {
                    Some(t) => PathBuf::from(t),
                    None => os.call_method1("fspath", (source,))?.extract()?,
                };
                let (text, early) = read_dataset(&path)
                    .map_err(|u| check_error(py, std::slice::from_ref(&u.diagnostic), &u.source))?;
                build(py, text, path.display().to_string(), early, dim)
            }
        }
    })
}

/// Rebuilds a pickled model from its text, name and dimension.
#[pyfunction]
#[pyo3(signature = (text, name, dim = None))]
pub fn _load_text(
    py: Python<'_>,
    text: String,
    name: String,
    dim: Option<u8>,
) -> PyResult<PyModel> {
    guarded(|| build(py, text, name, Vec::new(), dim))
}

/// Panics inside Rust, so the tests can see it become `InternalError`.
#[pyfunction]
pub fn _panic_for_tests() -> PyResult<()> {
    guarded(|| panic!("a deliberate panic"))
}

/// Reads and analyses `text` (as `mbfx check` does): its errors are a `CheckError`.
fn build(
    py: Python<'_>,
    text: String,
    name: String,
    early: Vec<Diagnostic>,
    dim: Option<u8>,
) -> PyResult<PyModel> {
    let asked = dim_request(dim)?;
    let file = SourceFile::new(name.clone(), text.clone());
    // The analysis holds compiled code that stays on its thread: only its figures and
    // words leave the GIL-free section.
    let checked = py.detach(|| session::check::check(&name, &text, asked));
    let mut diags = early;
    diags.extend(checked.diagnostics);
    let a = match checked.analysis {
        None => return Err(check_error(py, &diags, &file)),
        Some(Ok(figures)) => figures,
        Some(Err(refused)) => {
            let mut all = diags.clone();
            all.extend(refused.diagnostics);
            return Err(if has_errors(&all) {
                check_error(py, &all, &file)
            } else {
                plain_check_error(py, format!("{name}: {}", refused.why))
            });
        }
    };
    let report = PyReport {
        dimension: a.dimension,
        dimension_reason: a.dimension_reason,
        dof: a.dof,
        gruebler: a.gruebler,
        equations: a.equations,
        redundant: a.redundant,
        advice: a.advice,
        warnings: diagnostic_list(py, &diags, &file)?.unbind(),
        text: checked.report,
    };
    Ok(PyModel {
        title: checked.title,
        parts: checked.parts,
        markers: checked.markers,
        graphics: checked.graphics,
        report: Py::new(py, report)?,
        text,
        name,
        dim,
    })
}

#[pymethods]
impl PyModel {
    /// The dataset's title (its first line).
    #[getter]
    fn title(&self) -> &str {
        &self.title
    }

    /// The dataset text.
    #[getter]
    fn text(&self) -> &str {
        &self.text
    }

    /// The name diagnostics show: the file, or `dataset` for a text.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// PART ids, ground included, in file order.
    #[getter]
    fn parts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, &self.parts)
    }

    /// MARKER ids and the part each is on, as a dict.
    #[getter]
    fn markers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for &(m, p) in &self.markers {
            d.set_item(m, p)?;
        }
        Ok(d)
    }

    /// The GRAPHICS statements in file order, as `mbfx.Graphic` (id, kind, view name,
    /// part, markers and the kind's arguments as written).
    #[getter]
    fn graphics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        crate::graphics::graphics(py, &self.graphics)
    }

    /// The analysis `mbfx check` prints: dimension, degrees of freedom, redundancy.
    fn check(&self, py: Python<'_>) -> Py<PyReport> {
        self.report.clone_ref(py)
    }

    /// The value of `expr` at the assembled configuration (TIME 0): a float, or an
    /// array of 3 for a vector.
    #[pyo3(signature = (expr, engine = "jit"))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        expr: &str,
        engine: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        guarded(|| {
            let engine = engine_of(engine)?;
            let asked = dim_request(self.dim)?;
            let result = py.detach(|| {
                let loaded =
                    LoadedModel::load(&self.text, asked).map_err(|f| Err(f.1.to_string()))?;
                let mut ev = Evaluator::new(engine);
                ev.set_model(Some(loaded));
                ev.evaluate_any(expr).map_err(Ok)
            });
            let file = SourceFile::new("expression", expr);
            match result {
                Ok(v) if v.values.len() == 1 => Ok(v.values[0].into_pyobject(py)?.into_any()),
                Ok(v) => Ok(PyArray1::from_vec(py, v.values).into_any()),
                Err(Err(why)) => Err(plain_check_error(py, why)),
                Err(Ok(EvalError::Diagnostics(d))) => Err(check_error(py, &d, &file)),
                Err(Ok(e)) => Err(plain_check_error(
                    py,
                    e.failure()
                        .unwrap_or_else(|| "the expression has no value".into()),
                )),
            }
        })
    }

    /// Simulates the model to `end`, as `mbfx run` does with the same arguments and
    /// defaults, and returns an `mbfx.Run`. `probes` maps output column names to
    /// expressions; `set` maps `"KIND/ID.FIELD"` to a value for this run only (as
    /// `--set`). `estimate_error` runs the model again at ERROR/10 to estimate the
    /// answer's error (`stats["error_estimate"]`, in ERRORs), as `--estimate-error`.
    /// `Run.animate()` runs the model again to record its frames; `animation=True`
    /// records a frame at each output row as it runs (no second run; a small model's
    /// run costs a third more), `animation=False` keeps nothing to animate. `geometry`
    /// maps EXTERNAL GRAPHICS ids to mesh files (STL, OBJ, glTF), as `--geometry`: a
    /// CONTACT naming the graphic collides with the mesh, and the animation draws it
    /// (recorded as it runs unless `animation=False`).
    /// A failure raises `RunError` with the rows so far as `.run`; Ctrl-C raises
    /// `KeyboardInterrupt` with them.
    #[pyo3(signature = (
        end = None, output_step = None, integrator = None, error = None, probes = None,
        progress = false, *, hmax = None, hinit = None, hmin = None, fixed_step = None,
        alpha = None, rho_inf = None, kmax = None, formulation = None, error_per = "step",
        cartesian = false, interpolate = false, engine = "jit", set = None,
        estimate_error = false, animation = None, geometry = None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        py: Python<'_>,
        end: Option<&Bound<'_, PyAny>>,
        output_step: Option<&Bound<'_, PyAny>>,
        integrator: Option<&str>,
        error: Option<&Bound<'_, PyAny>>,
        probes: Option<&Bound<'_, PyDict>>,
        progress: bool,
        hmax: Option<&Bound<'_, PyAny>>,
        hinit: Option<&Bound<'_, PyAny>>,
        hmin: Option<&Bound<'_, PyAny>>,
        fixed_step: Option<&Bound<'_, PyAny>>,
        alpha: Option<&Bound<'_, PyAny>>,
        rho_inf: Option<&Bound<'_, PyAny>>,
        kmax: Option<&Bound<'_, PyAny>>,
        formulation: Option<&str>,
        error_per: &str,
        cartesian: bool,
        interpolate: bool,
        engine: &str,
        set: Option<&Bound<'_, PyDict>>,
        estimate_error: bool,
        animation: Option<bool>,
        geometry: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<PyAny>> {
        guarded(|| {
            let mut r = RunRequest::dataset(self.name.clone(), self.text.clone());
            // Recording costs a small model's run a third (the scene is drawn before it
            // starts): by default a run records nothing and `Run.animate()` runs it
            // again; `animation=True` (or meshes given) records as it runs, `False`
            // keeps nothing to animate.
            if animation == Some(true) || (geometry.is_some() && animation.is_none()) {
                r.animation = Some(crate::animation::request_of(geometry)?);
            }
            r.geometry = crate::animation::meshes_of(geometry)?;
            r.end = run::real(end, "end")?;
            r.output_step = run::real(output_step, "output_step")?;
            r.error = run::real(error, "error")?;
            r.estimate_error = estimate_error;
            r.method = integrator.map(run::method_of).transpose()?;
            r.hmax = run::real(hmax, "hmax")?;
            r.hinit = run::real(hinit, "hinit")?;
            r.hmin = run::real(hmin, "hmin")?;
            r.fixed_step = run::real(fixed_step, "fixed_step")?;
            let kmax = kmax.map(|k| int_in_range::<u32>(k, "kmax")).transpose()?;
            r.alpha = run::real(alpha, "alpha")?;
            r.rho_inf = run::real(rho_inf, "rho_inf")?;
            r.kmax = kmax;
            r.formulation = formulation.map(run::formulation_of).transpose()?;
            r.error_per_run = run::error_per_run(error_per)?;
            r.cartesian = cartesian;
            r.interpolate = interpolate;
            r.engine = engine_of(engine)?;
            r.dim = dim_request(self.dim)?;
            r.probes = run::probes_of(probes)?;
            r.set = run::settings_of(set)?;
            run::check_arguments(&r, true)?;
            run::run_model(py, &r, progress, animation != Some(false))
        })
    }

    /// The model to step from Python ([`crate::simulation`]): `sim.advance(t)`,
    /// `sim.outputs`, `sim.inputs["u"] = 1.5`, `state()`/`restore()`, `reset()`. The
    /// arguments are `run`'s; HMAX and HINIT follow `output_step` (END/100 when only
    /// `end` is given; with neither, the first advance's interval). Advancing to `run`'s
    /// output times with the inputs held gives `run`'s rows bit for bit.
    #[pyo3(signature = (
        integrator = None, error = None, set = None, probes = None, *, output_step = None,
        end = None, hmax = None, hinit = None, hmin = None, fixed_step = None, kmax = None,
        formulation = None, engine = "jit"
    ))]
    #[allow(clippy::too_many_arguments)]
    fn simulation(
        &self,
        py: Python<'_>,
        integrator: Option<&str>,
        error: Option<&Bound<'_, PyAny>>,
        set: Option<&Bound<'_, PyDict>>,
        probes: Option<&Bound<'_, PyDict>>,
        output_step: Option<&Bound<'_, PyAny>>,
        end: Option<&Bound<'_, PyAny>>,
        hmax: Option<&Bound<'_, PyAny>>,
        hinit: Option<&Bound<'_, PyAny>>,
        hmin: Option<&Bound<'_, PyAny>>,
        fixed_step: Option<&Bound<'_, PyAny>>,
        kmax: Option<&Bound<'_, PyAny>>,
        formulation: Option<&str>,
        engine: &str,
    ) -> PyResult<crate::simulation::PySimulation> {
        guarded(|| {
            let mut r = RunRequest::dataset(self.name.clone(), self.text.clone());
            r.end = run::real(end, "end")?;
            r.output_step = run::real(output_step, "output_step")?;
            r.error = run::real(error, "error")?;
            r.method = integrator.map(run::method_of).transpose()?;
            r.hmax = run::real(hmax, "hmax")?;
            r.hinit = run::real(hinit, "hinit")?;
            r.hmin = run::real(hmin, "hmin")?;
            r.fixed_step = run::real(fixed_step, "fixed_step")?;
            r.kmax = kmax.map(|k| int_in_range::<u32>(k, "kmax")).transpose()?;
            r.formulation = formulation.map(run::formulation_of).transpose()?;
            r.engine = engine_of(engine)?;
            r.dim = dim_request(self.dim)?;
            r.probes = run::probes_of(probes)?;
            r.set = run::settings_of(set)?;
            run::check_arguments(&r, false)?;
            match session::stepping::Stepping::new(&r) {
                Ok(s) => Ok(crate::simulation::PySimulation::new(s)),
                Err(failed) => Err(run::run_error(py, &failed, None)?),
            }
        })
    }

    /// The model linearized (as `mbfx run --linear`): at its static equilibrium when
    /// `statics` (the default), after a run to `end` when given (the dynamics start from
    /// the equilibrium when both are), else at the assembled start. `damping=False`
    /// leaves the damping out (NODAMPIN); `set` is as in `run`. Returns an
    /// `mbfx.Linearization`; a failure (no equilibrium, a run that fails) raises
    /// `RunError`.
    #[pyo3(signature = (statics = true, end = None, damping = true, *, engine = "jit", set = None))]
    fn linearize(
        &self,
        py: Python<'_>,
        statics: bool,
        end: Option<&Bound<'_, PyAny>>,
        damping: bool,
        engine: &str,
        set: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<PyAny>> {
        guarded(|| {
            let mut r = RunRequest::dataset(self.name.clone(), self.text.clone());
            (r.statics, r.end) = (statics, run::real(end, "end")?);
            r.engine = engine_of(engine)?;
            r.dim = dim_request(self.dim)?;
            r.set = run::settings_of(set)?;
            r.linear = Some(LinearRequest {
                file: None,
                damping,
            });
            run::check_arguments(&r, false)?;
            crate::linear::linearize(py, &r)
        })
    }

    /// A new model with `values` set in the dataset: a dict of `"KIND/ID.FIELD"`
    /// (`"PART/2.MASS"`, `"SFORCE/1.FUNCTION"`) to a number or a str. A statement the
    /// dataset lacks, a field it does not take or a value it refuses raises `CheckError`.
    fn with_values(&self, py: Python<'_>, values: &Bound<'_, PyDict>) -> PyResult<PyModel> {
        guarded(|| {
            let written = run::settings_of(Some(values))?;
            let text = set_values(&written, &self.text)
                .map_err(|(text, d)| check_error(py, &d, &SourceFile::new("values", text)))?;
            build(py, text, self.name.clone(), Vec::new(), self.dim)
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "mbfx.Model({:?}, {} parts, {} markers)",
            self.name,
            self.parts.len(),
            self.markers.len()
        )
    }

    /// Pickled as its text: a worker process rebuilds it.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let rebuild = py.import("mbfx._mbfx")?.getattr("_load_text")?;
        let args = PyTuple::new(
            py,
            [
                self.text.clone().into_pyobject(py)?.into_any(),
                self.name.clone().into_pyobject(py)?.into_any(),
                self.dim.into_pyobject(py)?.into_any(),
            ],
        )?;
        Ok((rebuild, args))
    }
}
