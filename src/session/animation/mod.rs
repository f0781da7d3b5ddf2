//! A run's animation, the session side: what a run is asked to draw
//! ([`AnimationRequest`]: the frame rate, glyphs, meshes for EXTERNAL graphics), and what
//! it hands back ([`Animation`]: the scene, the frames it recorded, the notes), which
//! writes itself as a `.glb` ([`crate::gltf`]) or a self-contained HTML page
//! ([`crate::viewer`]). `record` holds the recorder the run loop feeds at each output
//! row or frame time.

mod record;

use crate::diag::{Code, Diagnostic};
use crate::model::Model;
use crate::scene::{self, Frames, Scene};
use crate::session::run::Simulation;
use std::path::PathBuf;
use std::sync::Arc;

pub(crate) use record::Recorder;

/// What a run's animation should hold (`mbfx run --animate`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AnimationRequest {
    /// `--interpolate[=FPS]`: frames at this many per second of model time from the
    /// integrator's continuous extension, whatever the output step (at most
    /// [`MAX_FRAMES`], coarsened with a note); None: a frame at each output row.
    pub fps: Option<f64>,
    /// `--glyphs`: glyphs for every part, not only for those with nothing to draw.
    pub glyphs: bool,
    /// `--geometry GRAPHICS/ID=FILE`: a mesh file (STL, OBJ, glTF) per EXTERNAL id.
    pub geometry: Vec<(u32, PathBuf)>,
}

/// The most frames `--interpolate` records: a finer rate is coarsened to fit.
pub const MAX_FRAMES: usize = 10_000;

/// The frame rate `--interpolate` takes without a value (frames per second of model time).
pub const DEFAULT_FPS: f64 = 60.0;

/// A run's animation: the scene drawn and the frames recorded. Cheap to clone (the
/// model is shared).
#[derive(Clone, Debug)]
pub struct Animation {
    model: Arc<Model>,
    options: scene::Options,
    scene: Scene,
    frames: Frames,
    /// The recording's notes (after the scene's).
    recorded: Vec<String>,
    notes: Vec<String>,
}

impl Animation {
    /// The animation of `scene` (built from `model` with `options`) through `frames`,
    /// with the recording's notes.
    pub(crate) fn new(
        model: Arc<Model>,
        options: scene::Options,
        scene: Scene,
        frames: Frames,
        recorded: Vec<String>,
    ) -> Animation {
        let notes = scene.notes.iter().chain(&recorded).cloned().collect();
        Animation {
            model,
            options,
            scene,
            frames,
            recorded,
            notes,
        }
    }

    /// The glTF binary.
    pub fn glb(&self) -> Vec<u8> {
        crate::gltf::glb(&self.scene, &self.frames)
    }

    /// The self-contained HTML page: the viewer with the .glb and the run's columns
    /// (`header`, time first, and `rows`) for its chart.
    pub fn html(&self, header: &[String], rows: &[Vec<f64>]) -> String {
        let chart = crate::viewer::Chart {
            names: header.to_vec(),
            rows: rows.to_vec(),
        };
        crate::viewer::page(&self.glb(), &chart, &self.scene.title, &self.notes)
    }

    /// What the user should hear once: the scene's notes (placeholders, glyphs) and the
    /// recording's (a coarsened frame rate, a force no arrow can show).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// How many frames the run recorded.
    pub fn frame_count(&self) -> usize {
        self.frames.times.len()
    }

    /// The scene drawn.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The frames recorded.
    pub fn frames(&self) -> &Frames {
        &self.frames
    }

    /// The same run drawn with glyphs for every part (`glyphs`) or only where a part has
    /// nothing to draw: a new scene from the same model and frames.
    pub fn with_glyphs(&self, glyphs: bool) -> Result<Animation, String> {
        let options = scene::Options {
            glyphs,
            ..self.options.clone()
        };
        let scene = scene::build(&self.model, &options).map_err(|e| e.to_string())?;
        Ok(Animation::new(
            self.model.clone(),
            options,
            scene,
            self.frames.clone(),
            self.recorded.clone(),
        ))
    }
}

/// The scene `request` asks for, drawn from `model`, with the options it was drawn
/// with; a mesh file that cannot be read is E0501, naming it.
pub(crate) fn scene_of(
    request: &AnimationRequest,
    model: &Model,
) -> Result<(scene::Options, Scene), Diagnostic> {
    // Each mesh file is opened first, so that one that cannot be read is named here
    // whatever the scene makes of it.
    for (id, path) in &request.geometry {
        if let Err(e) = std::fs::File::open(path) {
            let msg = format!(
                "--geometry GRAPHICS/{id}={}: cannot read it: {e}",
                path.display()
            );
            return Err(Diagnostic::error(Code::Io, 0..0, msg));
        }
    }
    let options = scene::Options {
        glyphs: request.glyphs,
        geometry: request.geometry.clone(),
    };
    match scene::build(model, &options) {
        Ok(s) => Ok((options, s)),
        Err(e) => Err(Diagnostic::error(
            Code::Io,
            0..0,
            format!("--geometry: {e}"),
        )),
    }
}

/// The recorder of `scene` for `sim`, a run of `span` (model time) asked `request`.
pub(crate) fn recorder(
    request: &AnimationRequest,
    scene: &Scene,
    sim: &mut Simulation,
    span: f64,
) -> Recorder {
    let (step, note) = record::frame_step(request, span);
    let mut r = Recorder::new(scene, &mut sim.read.model, &mut sim.dynamics, step);
    r.notes.extend(note);
    r
}

/// The animation `recorder` made of `scene` (drawn from `model` with `options`).
pub(crate) fn finish(
    recorder: Recorder,
    options: scene::Options,
    scene: Scene,
    model: &Model,
) -> Animation {
    Animation::new(
        Arc::new(model.clone()),
        options,
        scene,
        recorder.frames,
        recorder.notes,
    )
}

#[cfg(test)]
mod tests;
