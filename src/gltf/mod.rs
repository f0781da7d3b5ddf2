//! glTF 2.0 binary (`.glb`) of a [`crate::scene::Scene`] and its [`crate::scene::Frames`]:
//! nodes per part and item, meshes, and the animation's tracks (docs/gltf.md has the
//! conventions: names, extras, units and axes, the root's turn).
//!
//! `tracks` makes the animation's keys from the frames, `document` the JSON, `buffers`
//! the binary accessors, `container` the GLB around them. Nothing here reads the core:
//! the frames come from the session's run.

mod buffers;
mod container;
mod document;
mod tracks;

use crate::scene::{Frames, Scene};

/// The `.glb` of `scene` moving through `frames` (a still scene when there are fewer
/// than two frames or nothing moves).
pub fn glb(scene: &Scene, frames: &Frames) -> Vec<u8> {
    let tracks = tracks::tracks(scene, frames);
    let mut buffers = buffers::Buffers::default();
    let mut doc = document::document(scene, &tracks, &mut buffers);
    if !buffers.bin.is_empty() {
        doc["buffers"] = serde_json::json!([{"byteLength": buffers.bin.len()}]);
        doc["bufferViews"] = serde_json::Value::Array(buffers.views);
        doc["accessors"] = serde_json::Value::Array(buffers.accessors);
    }
    // (Serialising a Value cannot fail: its keys are strings.)
    let json = serde_json::to_vec(&doc).unwrap_or_default();
    container::pack(&json, &buffers.bin)
}
