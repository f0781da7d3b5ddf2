//! glTF 2.0 binary (`.glb`) of a [`crate::scene::Scene`] and its [`crate::scene::Frames`]:
//! nodes per part and item, meshes, and the animation's tracks.
