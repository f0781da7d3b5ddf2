//! The recorder a run feeds: at each frame time, every scene part's BCS pose from the
//! dynamics' system (parts by Adams id; ground, and a part the system does not hold,
//! at its input pose) and each arrow's force. An arrow reads its element's force
//! function as `ETYPE(eid, 1, comp, 0)` would (components FX, FY, FZ in global axes on
//! the EMARKER side, which is the element's J marker), resolved through the same
//! [`OutputSlot`] a model expression's is.

use super::{AnimationRequest, DEFAULT_FPS, MAX_FRAMES};
use crate::mbd::dynamics::Dynamics;
use crate::mbd::output_slot::OutputSlot;
use crate::model::elements::MeasureSlot;
use crate::model::Model;
use crate::scene::{Frames, Pose, Scene};

/// Records a run's frames.
pub(crate) struct Recorder {
    /// Per scene part: the index of its part in the system (None: drawn at `input`).
    parts: Vec<Option<usize>>,
    input: Vec<Pose>,
    /// Per arrow: its FX, FY, FZ slots (None: the element kind has no force function).
    arrows: Vec<Option<[OutputSlot; 3]>>,
    /// Frames at this step from the continuous extension; None: at each output row.
    pub(crate) step: Option<f64>,
    pub(crate) frames: Frames,
    pub(crate) notes: Vec<String>,
}

/// The step between frames for `request` over a run of `span` (model time), with the
/// note saying so when the rate asked for is coarsened to [`MAX_FRAMES`]; None for a
/// frame at each row.
pub(crate) fn frame_step(request: &AnimationRequest, span: f64) -> (Option<f64>, Option<String>) {
    let Some(fps) = request.fps else {
        return (None, None);
    };
    let fps = if fps > 0.0 && fps.is_finite() {
        fps
    } else {
        DEFAULT_FPS
    };
    let most = (MAX_FRAMES - 1) as f64 / span;
    if span > 0.0 && fps > most {
        let note = format!(
            "animation: {fps} frames per second over {span} s would be more than {MAX_FRAMES} frames; recorded at {most:.4} per second"
        );
        (Some(1.0 / most), Some(note))
    } else {
        (Some(1.0 / fps), None)
    }
}

impl Recorder {
    /// A recorder of `scene`'s parts and arrows in the system of `d` built from `model`
    /// (whose measure slots lend room to resolve the arrows' force functions), with
    /// frames every `step` (None: at each row).
    pub(crate) fn new(
        scene: &Scene,
        model: &mut Model,
        d: &mut Dynamics,
        step: Option<f64>,
    ) -> Recorder {
        let parts = (scene.parts.iter())
            .map(|p| {
                (!p.ground)
                    .then(|| d.sys.parts.iter().position(|s| s.id == Some(p.id)))
                    .flatten()
            })
            .collect();
        let mut notes = Vec::new();
        let arrows = (scene.arrows.iter())
            .map(|a| {
                let first = model.measures.len();
                model.measures.extend((2..=4).map(|comp| MeasureSlot {
                    name: a.etype.to_string(),
                    ids: vec![a.eid as i64, 1, comp, 0],
                    component: 0,
                }));
                let slots: Result<Vec<OutputSlot>, _> = (0..3)
                    .map(|k| OutputSlot::resolve(&mut d.sys, model, (first + k) as u32))
                    .collect();
                model.measures.truncate(first);
                match slots {
                    Ok(s) => Some([s[0], s[1], s[2]]),
                    Err(e) => {
                        notes.push(format!(
                            "GRAPHICS FORCE of {}/{}: no arrow drawn ({e})",
                            a.etype, a.eid
                        ));
                        None
                    }
                }
            })
            .collect();
        Recorder {
            parts,
            input: scene.parts.iter().map(|p| p.input).collect(),
            arrows,
            step,
            frames: Frames::default(),
            notes,
        }
    }

    /// Records the state of `d` as a frame, unless its time is not past the last one's
    /// (a segment's start repeats the last row; a run's estimate runs again from 0).
    pub(crate) fn record(&mut self, d: &mut Dynamics) {
        let t = d.sys.time;
        if self.frames.times.last().is_some_and(|&last| t <= last) {
            return;
        }
        let poses = (self.parts.iter().zip(&self.input))
            .map(|(p, input)| match p {
                Some(k) => {
                    let part = &d.sys.parts[*k];
                    let o = part.bcs_origin();
                    let q = part.rot;
                    Pose {
                        translation: [o.x, o.y, o.z],
                        rotation: [q.i, q.j, q.k, q.w],
                    }
                }
                None => *input,
            })
            .collect();
        let mut arrows = Vec::with_capacity(self.arrows.len());
        // Forces at this state: refreshed once for all arrows (a failure leaves zeros:
        // the run itself reports its own).
        let fresh = self.arrows.iter().any(Option::is_some) && d.refresh_outputs().is_ok();
        for a in &self.arrows {
            arrows.push(match a {
                Some(s) if fresh => [s[0].value(d), s[1].value(d), s[2].value(d)],
                Some(_) => [0.0; 3],
                // No force function: not a number, which the writer draws as no track.
                None => [f64::NAN; 3],
            });
        }
        self.frames.times.push(t);
        self.frames.poses.push(poses);
        self.frames.arrows.push(arrows);
    }
}
