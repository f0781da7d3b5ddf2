//! The animation's tracks from a scene's [`Frames`]: each moving part's pose per kept
//! frame, and each stretching item's and arrow's translation, rotation and scale, made
//! from the part poses, the anchors and the forces. Quaternions are sign-continuous
//! along each track (LINEAR interpolation then takes the short way), and a stretch's
//! turn is carried from frame to frame by the least rotation between its directions,
//! which stays continuous where a shortest arc from +z would flip (a direction through
//! −z).

use crate::scene::{Anchor, Frames, Motion, Pose, Scene};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// A node's translation, rotation and scale at each kept frame.
#[derive(Clone, Debug, Default)]
pub(super) struct Track {
    pub(super) translation: Vec<[f32; 3]>,
    pub(super) rotation: Vec<[f32; 4]>,
    /// Empty for a part (never scaled).
    pub(super) scale: Vec<[f32; 3]>,
}

/// Every track of a run.
pub(super) struct Tracks {
    /// The kept frames' times (float32 seconds, strictly increasing).
    pub(super) times: Vec<f32>,
    /// Per part (index into [`Scene::parts`]): its track, or None when it never moves.
    pub(super) parts: Vec<Option<Track>>,
    /// Per part: its pose at the first kept frame (None without frames), where a part
    /// that never moves stays (assembled, it may stand elsewhere than its input pose).
    pub(super) first: Vec<Option<Pose>>,
    /// Per item: the track of a stretching item or an arrow, None for a rigid one.
    pub(super) items: Vec<Option<Track>>,
}

/// The z scale standing for a zero length, as a fraction of the scene's extent: a node
/// scaled by zero has a singular matrix, which viewers cannot invert.
const TINY: f64 = 1e-6;

/// The tracks of `scene` over `frames`: frames whose float32 time would not increase
/// are left out, since animation inputs must increase strictly, and so are frames with
/// a pose that is not finite (a run that blew up), which glTF cannot hold.
pub(super) fn tracks(scene: &Scene, frames: &Frames) -> Tracks {
    let mut times = Vec::new();
    let mut kept = Vec::new();
    for (k, &t) in frames.times.iter().enumerate() {
        let t = t as f32;
        let finite = (frames.poses.get(k)).is_some_and(|ps| {
            (ps.iter()).all(|p| {
                p.translation
                    .iter()
                    .chain(&p.rotation)
                    .all(|x| x.is_finite())
            })
        });
        if times.last().is_none_or(|&last| t > last) && finite {
            times.push(t);
            kept.push(k);
        }
    }
    let pose = |k: usize, p: usize| -> Pose {
        frames.poses[k]
            .get(p)
            .copied()
            .unwrap_or(scene.parts[p].input)
    };
    let parts = (0..scene.parts.len())
        .map(|p| {
            let poses: Vec<Pose> = kept.iter().map(|&k| pose(k, p)).collect();
            let moves = poses.windows(2).any(|w| w[0] != w[1]);
            (!scene.parts[p].ground && moves).then(|| part_track(&poses))
        })
        .collect();
    let first = (0..scene.parts.len())
        .map(|p| kept.first().map(|&k| pose(k, p)))
        .collect();
    let scale = arrow_scale(scene, frames, &kept);
    let tiny = TINY * scene.extent.max(f64::MIN_POSITIVE);
    let items = (scene.items.iter())
        .map(|item| {
            let spans: Vec<(Vector3<f64>, Vector3<f64>)> = match &item.motion {
                Motion::Rigid => return None,
                Motion::Stretch { from, to } => (kept.iter())
                    .map(|&k| {
                        let a = world(&pose(k, from.part), from);
                        (a, world(&pose(k, to.part), to) - a)
                    })
                    .collect(),
                // A force never known (no force function): no track, a still arrow.
                Motion::Arrow { arrow, .. } if !known(frames, &kept, *arrow) => return None,
                Motion::Arrow { at, arrow } => (kept.iter())
                    .map(|&k| {
                        let f = (frames.arrows.get(k).and_then(|a| a.get(*arrow)))
                            .filter(|f| f.iter().all(|x| x.is_finite()))
                            .map_or(Vector3::zeros(), |f| Vector3::from(*f));
                        (world(&pose(k, at.part), at), f * scale)
                    })
                    .collect(),
            };
            Some(span_track(&spans, tiny))
        })
        .collect();
    Tracks {
        times,
        parts,
        first,
        items,
    }
}

/// Whether arrow `a` has a finite force at some kept frame.
fn known(frames: &Frames, kept: &[usize], a: usize) -> bool {
    (kept.iter())
        .filter_map(|&k| frames.arrows.get(k).and_then(|f| f.get(a)))
        .any(|f| f.iter().all(|x| x.is_finite()))
}

/// The world point of `anchor` with its part at `pose`.
fn world(pose: &Pose, anchor: &Anchor) -> Vector3<f64> {
    quaternion(pose.rotation) * Vector3::from(anchor.point) + Vector3::from(pose.translation)
}

/// The unit quaternion of `[x, y, z, w]`.
pub(super) fn quaternion(q: [f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]))
}

/// `[x, y, z, w]` in float32, its sign the one nearer `prev` (sign continuity).
fn xyzw(q: &UnitQuaternion<f64>, prev: Option<&[f32; 4]>) -> [f32; 4] {
    let c = [q.i, q.j, q.k, q.w];
    let dot = prev.map_or(1.0, |p| (0..4).map(|i| p[i] as f64 * c[i]).sum::<f64>());
    let s = if dot < 0.0 { -1.0 } else { 1.0 };
    c.map(|x| (s * x) as f32)
}

/// A part's track: its BCS poses.
fn part_track(poses: &[Pose]) -> Track {
    let mut track = Track::default();
    for p in poses {
        track.translation.push(p.translation.map(|x| x as f32));
        let q = xyzw(&quaternion(p.rotation), track.rotation.last());
        track.rotation.push(q);
    }
    track
}

/// The track of a node placed at each span's start, its +z turned along the span and
/// scaled to its length (`tiny` for none, the turn then kept).
fn span_track(spans: &[(Vector3<f64>, Vector3<f64>)], tiny: f64) -> Track {
    let mut track = Track::default();
    let mut turn: Option<UnitQuaternion<f64>> = None;
    for (at, d) in spans {
        let len = d.norm();
        if len > 0.0 {
            let now = match turn {
                Some(q) => {
                    let was = q * Vector3::z();
                    rotation_between(&was, d) * q
                }
                None => rotation_between(&Vector3::z(), d),
            };
            turn = Some(now);
        }
        let q = turn.unwrap_or_else(UnitQuaternion::identity);
        track
            .translation
            .push([at.x as f32, at.y as f32, at.z as f32]);
        let q = xyzw(&q, track.rotation.last());
        track.rotation.push(q);
        track.scale.push([1.0, 1.0, len.max(tiny) as f32]);
    }
    track
}

/// The least rotation taking direction `a` to direction `b`; a half turn about an axis
/// normal to `a` when they are opposite.
pub(super) fn rotation_between(a: &Vector3<f64>, b: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(a, b).unwrap_or_else(|| {
        // Opposite: any axis normal to a; the one from a's smallest component.
        let a = a.normalize();
        let helper = if a.x.abs() <= a.y.abs() && a.x.abs() <= a.z.abs() {
            Vector3::x()
        } else if a.y.abs() <= a.z.abs() {
            Vector3::y()
        } else {
            Vector3::z()
        };
        let axis = nalgebra::Unit::new_normalize(a.cross(&helper));
        UnitQuaternion::from_axis_angle(&axis, std::f64::consts::PI)
    })
}

/// The factor taking a force to an arrow length: the run's largest |F| drawn a quarter
/// of the scene's extent (1 when every force is zero).
fn arrow_scale(scene: &Scene, frames: &Frames, kept: &[usize]) -> f64 {
    let largest = (kept.iter())
        .filter_map(|&k| frames.arrows.get(k))
        .flatten()
        .map(|f| Vector3::from(*f).norm())
        .filter(|f| f.is_finite())
        .fold(0.0, f64::max);
    if largest > 0.0 {
        0.25 * scene.extent / largest
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opposite_directions_turn_by_half_a_turn() {
        let q = rotation_between(&Vector3::z(), &-Vector3::z());
        assert!((q * Vector3::z() + Vector3::z()).norm() < 1e-12);
        let q = rotation_between(&Vector3::y(), &Vector3::new(0.0, -2.0, 0.0));
        assert!((q * Vector3::y() + Vector3::y()).norm() < 1e-12);
    }

    #[test]
    fn a_span_through_minus_z_turns_continuously() {
        // A direction sweeping a full circle in the xz plane passes −z: the carried turn
        // changes little from key to key, unlike a fresh shortest arc (which flips).
        let spans: Vec<_> = (0..=64)
            .map(|k| {
                let a = k as f64 / 64.0 * std::f64::consts::TAU;
                (Vector3::zeros(), Vector3::new(a.sin(), 0.0, a.cos()) * 2.0)
            })
            .collect();
        let track = span_track(&spans, 1e-9);
        for (w, (_, d)) in track.rotation.windows(2).zip(&spans[1..]) {
            let dot: f32 = (0..4).map(|i| w[0][i] * w[1][i]).sum();
            assert!(dot > 0.99, "a jump between keys: {w:?}");
            let q = quaternion(w[1].map(|x| x as f64));
            assert!((q * Vector3::z() - d.normalize()).norm() < 1e-6);
        }
        assert!(track.scale.iter().all(|s| (s[2] - 2.0).abs() < 1e-6));
    }
}
