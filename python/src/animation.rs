//! `Run.animate()`'s native side: a [`PyRecording`] keeps the animation a run recorded
//! ([`mbfx::session::animation::Animation`], a frame at each output row) with the
//! request that ran it, writes it as a glTF binary or the self-contained page, and
//! makes another of the same run: with other glyphs from the same frames, or at a frame
//! rate by running the request again (the rows come out the same; only the frames
//! differ). The pure-Python `mbfx.Animation` wraps it.

use crate::errors::guarded;
use mbfx::session::animation::{Animation, AnimationRequest};
use mbfx::session::request::RunRequest;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

/// The animation request of `Model.run`: a frame at each output row (no second run
/// for `animate()`), meshes for EXTERNAL graphics from `geometry` ({id: path}).
pub fn request_of(geometry: Option<&Bound<'_, PyDict>>) -> PyResult<AnimationRequest> {
    Ok(AnimationRequest {
        fps: None,
        glyphs: false,
        geometry: meshes_of(geometry)?,
    })
}

/// `geometry` ({GRAPHICS id: path}) as the run's meshes for EXTERNAL graphics: the
/// contacts' geometry, and what an animation draws.
pub fn meshes_of(geometry: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(u32, PathBuf)>> {
    let mut meshes = Vec::new();
    for (id, path) in geometry.into_iter().flat_map(|g| g.iter()) {
        let id: u32 = id.extract().map_err(|_| {
            PyValueError::new_err(format!(
                "geometry maps a GRAPHICS id (an int) to a mesh file, not {id:?}"
            ))
        })?;
        let path: PathBuf = path.extract()?;
        meshes.push((id, path));
    }
    Ok(meshes)
}

/// What a run recorded for its animation, and how it was asked.
#[pyclass(frozen, module = "mbfx._mbfx", name = "Recording")]
pub struct PyRecording {
    /// The run as asked (its `animation` set), for a run at another frame rate.
    request: RunRequest,
    /// None: the run recorded nothing; `again` runs it with recording on.
    animation: Option<Animation>,
}

impl PyRecording {
    /// The recording `animation` of a run of `request`.
    pub fn new(request: &RunRequest, animation: Option<Animation>) -> PyRecording {
        PyRecording {
            request: request.clone(),
            animation,
        }
    }

    fn asked(&self) -> AnimationRequest {
        self.request.animation.clone().unwrap_or_default()
    }

    /// The animation recorded, or the error saying there is none.
    fn recorded(&self) -> PyResult<&Animation> {
        self.animation.as_ref().ok_or_else(|| {
            PyValueError::new_err("this run recorded no animation: call Run.animate()")
        })
    }
}

#[pymethods]
impl PyRecording {
    /// The glTF 2.0 binary (`.glb`).
    fn glb<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        guarded(|| {
            let animation = self.recorded()?;
            let bytes = py.detach(|| animation.glb());
            Ok(PyBytes::new(py, &bytes))
        })
    }

    /// The self-contained page, its chart over `columns` (time first) and `rows`.
    fn html(
        &self,
        py: Python<'_>,
        columns: Vec<String>,
        rows: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<String> {
        guarded(|| {
            if rows.shape()[1] != columns.len() {
                return Err(PyValueError::new_err(format!(
                    "{} columns for rows of {}",
                    columns.len(),
                    rows.shape()[1]
                )));
            }
            let table: Vec<Vec<f64>> = rows.as_array().outer_iter().map(|r| r.to_vec()).collect();
            let animation = self.recorded()?;
            Ok(py.detach(|| animation.html(&columns, &table)))
        })
    }

    /// What the user should hear once (placeholders, glyphs, a coarsened frame rate).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.animation
            .as_ref()
            .map_or_else(Vec::new, |a| a.notes().to_vec())
    }

    /// How many frames were recorded.
    #[getter]
    fn frames(&self) -> usize {
        self.animation.as_ref().map_or(0, Animation::frame_count)
    }

    /// Whether the run recorded its animation as it ran (else `again` runs it).
    #[getter]
    fn recorded_frames(&self) -> bool {
        self.animation.is_some()
    }

    /// The frame rate asked for (None: a frame at each output row).
    #[getter]
    fn fps(&self) -> Option<f64> {
        self.asked().fps
    }

    /// Whether every part has glyphs (not only those with nothing to draw).
    #[getter]
    fn glyphs(&self) -> bool {
        self.asked().glyphs
    }

    /// The same run's animation at `fps` (None: at the output rows) with `glyphs`:
    /// drawn again from these frames when the rate is the same, else recorded by a run
    /// of the same request at that rate. A run that fails raises `RunError`.
    fn again(&self, py: Python<'_>, fps: Option<f64>, glyphs: bool) -> PyResult<Py<PyRecording>> {
        guarded(|| {
            let mut request = self.request.clone();
            let mut asked = self.asked();
            let same_frames = fps == asked.fps;
            (asked.fps, asked.glyphs) = (fps, glyphs);
            request.animation = Some(asked);
            if let (true, Some(recorded)) = (same_frames, &self.animation) {
                let animation = py
                    .detach(|| recorded.with_glyphs(glyphs))
                    .map_err(PyValueError::new_err)?;
                return Py::new(
                    py,
                    PyRecording {
                        request,
                        animation: Some(animation),
                    },
                );
            }
            // Only the frames are wanted: no second run for an error estimate.
            (request.estimate_error, request.carry_error) = (false, false);
            let run = crate::run::run_model(py, &request, false, true)?;
            Ok(run.getattr(py, "_recording")?.extract(py)?)
        })
    }
}
